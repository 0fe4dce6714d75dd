#include "read.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "exercise.h"
#include "sinew/import.h"

static bool no_files(const char *path, void **bytes, size_t *size, void *user)
{
    (void)path, (void)bytes, (void)size, (void)user;
    return false;
}

int fuzz_read(const char *format, const char *name, const uint8_t *data, size_t size)
{
    sinew_model *model = NULL;
    sinew_error error = {0};
    sinew_import_desc desc = {.path = name, .read_file = no_files};
    sinew_result result = sinew_import_memory(data, size, format, &desc, &model, &error);
    if (result != SINEW_OK) {
        if (result == SINEW_ERROR_INTERNAL || !strstr(error.message, name) || strcmp(error.file, name) != 0)
            abort(); /* every refusal names the file; nothing is sinew's own bug */
        return 0;
    }
    fuzz_exercise(model);
    sinew_model_free(model);
    return 0;
}
