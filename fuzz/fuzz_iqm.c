/* libFuzzer target for sinew's IQM reader (fuzz/read.h says what is checked).
 *
 *   make fuzz                     every target; this one seeded from the IQM fixtures in tests/fixtures
 *   build/fuzz_iqm_replay FILES  the same checks on given files (part of `make test`)
 */
#include "read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_read("iqm", "fuzz.iqm", data, size);
}
