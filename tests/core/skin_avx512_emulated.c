/* src/core/skin_x86.c against SIMDe's portable AVX-512 (avx512_emulated.h), its entry point
 * renamed so that it links beside the library's: what test_skin_avx512 runs. */
#define SINEW_SKIN_AVX512_EMULATED
#define sinew_skin_avx512 sinew_skin_avx512_emulated
#include "core/skin_x86.c"
