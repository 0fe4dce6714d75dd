/* libFuzzer target for sinew's BVH reader (fuzz/read.h says what is checked).
 *
 *   make fuzz                     every target; this one seeded from the BVH fixtures in tests/fixtures
 *   build/fuzz_bvh_replay FILES  the same checks on given files (part of `make test`)
 */
#include "read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_read("bvh", "fuzz.bvh", data, size);
}
