/* libFuzzer target for sinew's FBX reader: any bytes either read (and then build into a
 * runtime model that is exercised like a player would) or are refused with a message that
 * names the data; never a crash, a hang or a sanitizer report.
 *
 *   make fuzz                    both targets, clang + libFuzzer + ASan/UBSan; this one seeded
 *                                from tests/fixtures/two_bone_*.fbx (ASCII, binary 7.4 and 7.5)
 *   build/fuzz_fbx_replay FILES  the same checks on given files (part of `make test`)
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "exercise.h"
#include "import/internal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    raw_model raw;
    sinew_error error = {0};
    sinew_result result = raw_model_from_fbx("fuzz.fbx", data, size, &raw, &error);
    if (result != SINEW_OK) {
        if (!strstr(error.message, "fuzz.fbx"))
            abort(); /* every refusal names the file */
        return 0;
    }
    void *blob = NULL;
    size_t blob_size = 0;
    result = raw_model_build(&raw, &blob, &blob_size, &error);
    raw_model_free(&raw);
    if (result != SINEW_OK) {
        if (!strstr(error.message, "fuzz.fbx"))
            abort();
        return 0;
    }
    sinew_model *model = NULL;
    if (sinew_model_from_blob(blob, blob_size, "fuzz.fbx", NULL, &model, &error) != SINEW_OK)
        abort(); /* the builder wrote a blob the reader refuses */
    fuzz_exercise(model);
    sinew_model_free(model);
    free(blob);
    return 0;
}
