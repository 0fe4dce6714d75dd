/* libFuzzer target for sinew's COLLADA reader (fuzz/read.h says what is checked).
 *
 *   make fuzz                    every target, clang + libFuzzer + ASan/UBSan; this one seeded
 *                                from the COLLADA fixtures in tests/fixtures (two_bone.dae)
 *   build/fuzz_collada_replay FILES  the same checks on given files (part of `make test`)
 */
#include "read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_read("dae", "fuzz.dae", data, size);
}
