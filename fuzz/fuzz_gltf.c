/* libFuzzer target for sinew's glTF reader (fuzz/read.h says what is checked): .gltf JSON
 * with data: URI buffers and .glb alike (the reader tells them by the GLB magic).
 *
 *   make fuzz                     every target; this one seeded from the glTF fixtures in tests/fixtures
 *   build/fuzz_gltf_replay FILES  the same checks on given files (part of `make test`)
 */
#include "read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return fuzz_read("gltf", "fuzz.gltf", data, size);
}
