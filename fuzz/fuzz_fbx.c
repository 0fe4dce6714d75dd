/* libFuzzer target for sinew's FBX reader (fuzz/read.h says what is checked).
 *
 *   make fuzz                    every target, clang + libFuzzer + ASan/UBSan; this one seeded
 *                                from the FBX fixtures in tests/fixtures (ASCII, binary 7.4 and 7.5)
 *   build/fuzz_fbx_replay FILES  the same checks on given files (part of `make test`)
 */
#include "read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_read("fbx", "fuzz.fbx", data, size);
}
