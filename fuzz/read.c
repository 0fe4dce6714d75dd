#include "read.h"

#include <stdlib.h>
#include <string.h>

#include "exercise.h"

int fuzz_read(fuzz_reader reader, const char *name, const uint8_t *data, size_t size)
{
    raw_model raw;
    sinew_error error = {0};
    sinew_result result = reader(name, data, size, &raw, &error);
    if (result != SINEW_OK) {
        if (!strstr(error.message, name))
            abort(); /* every refusal names the file */
        return 0;
    }
    void *blob = NULL;
    size_t blob_size = 0;
    result = raw_model_build(&raw, &blob, &blob_size, &error);
    raw_model_free(&raw);
    if (result != SINEW_OK) {
        if (!strstr(error.message, name))
            abort();
        return 0;
    }
    sinew_model *model = NULL;
    if (sinew_model_from_blob(blob, blob_size, name, NULL, &model, &error) != SINEW_OK)
        abort(); /* the builder wrote a blob the reader refuses */
    fuzz_exercise(model);
    sinew_model_free(model);
    free(blob);
    return 0;
}
