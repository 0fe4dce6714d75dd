/* libFuzzer target for the .sinew reader: any bytes either load or are refused with
 * SINEW_ERROR_FORMAT; a model that loads is then used the way a player uses it (sample
 * every clip, world matrices, palettes, skin every mesh), which must stay in bounds.
 *
 *   make fuzz                       clang + libFuzzer + ASan/UBSan, seeded from fuzz/corpus
 *   build/fuzz_model_replay FILES   the same checks on given files (part of `make test`)
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "exercise.h"
#include "sinew/sinew.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sinew_model *model = NULL;
    sinew_error error = {0};
    sinew_result result = sinew_model_from_blob(data, size, "fuzz", NULL, &model, &error);
    if (result == SINEW_OK) {
        fuzz_exercise(model);
        sinew_model_free(model);
    } else if (result != SINEW_ERROR_FORMAT || strstr(error.message, "fuzz") == NULL) {
        abort(); /* every refusal is a format error naming the data */
    }
    return 0;
}
