/* libFuzzer target for the import helper's reply as the parent reads it
 * (import_reply_decode): a helper that went wrong, or was replaced, cannot make the caller
 * crash or allocate beyond the reply. The input is decoded as a whole reply, then again as
 * the payload of a well-formed "ok" reply (so the .sinew seeds reach the model decoder the
 * way a reply does); a model that decodes is exercised.
 *   build/fuzz_reply_replay FILES   the same on given files (part of `make test`) */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "exercise.h"
#include "import/internal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void decode(const uint8_t *bytes, size_t size)
{
    sinew_model *model = NULL;
    sinew_error error = {0};
    if (import_reply_decode(bytes, size, "fuzz", NULL, &model, &error) == SINEW_OK) {
        fuzz_exercise(model);
        sinew_model_free(model);
    } else if (model || error.message[0] == '\0') {
        abort(); /* a refusal leaves no model and says why */
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    decode(data, size);
    uint8_t *wrapped = malloc(sizeof(reply_header) + size + 1);
    if (!wrapped)
        return 0;
    reply_header h = {.magic = REPLY_MAGIC, .kind = SINEW_OK, .size = size};
    memcpy(wrapped, &h, sizeof h);
    memcpy(wrapped + sizeof h, data, size);
    decode(wrapped, sizeof h + size);
    free(wrapped);
    return 0;
}
