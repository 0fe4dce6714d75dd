/* Imports a model through the helper, poses it at 0.5 s and prints what it found. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sinew/sinew.h>

int main(int argc, char **argv)
{
    if (argc != 2)
        return 64;
    if (strcmp(sinew_version(), SINEW_VERSION_STRING) != 0) {
        fprintf(stderr, "headers %s, library %s\n", SINEW_VERSION_STRING, sinew_version());
        return 1;
    }
    sinew_import_desc desc = {.path = argv[1]};
#ifdef HELPER
    desc.helper = HELPER;
#endif
    sinew_model *model = NULL;
    sinew_error error = {0};
    if (sinew_import(&desc, &model, &error) != SINEW_OK) {
        fprintf(stderr, "%s\n", error.message);
        return 2;
    }
    printf("sinew %s: %u nodes, %u clips\n", sinew_version(), model->node_count, model->clip_count);
    sinew_model_free(model);
    return 0;
}
