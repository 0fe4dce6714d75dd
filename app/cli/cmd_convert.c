/* `sinew convert IN OUT.sinew`: a model file (FBX, any format Assimp reads, or a .sinew) written
 * as the .sinew runtime format, with its muscles. */
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"

static const char convert_usage[] =
    "usage: sinew convert IN OUT.sinew [--muscles [M.json] | --no-muscles]\n"
    "\n"
    "Writes IN (COLLADA, glTF, FBX, BVH, ... or a .sinew) as a .sinew file: sinew's runtime format, one\n"
    "tagged, versioned, checksummed block that loads with one read and a validation pass, no parsing.\n"
    "It holds everything sinew needs to pose, skin and draw the model (nodes, skins, meshes, materials,\n"
    "clips, import warnings) and its muscle definitions. Every command that takes a model takes it.\n"
    "\n"
    "  --muscles [M.json]  store these muscles (default: IN's own, or IN.muscles.json beside IN when\n"
    "                      there is one); with no file, IN.muscles.json must exist\n"
    "  --no-muscles        store none\n"
    "\n"
    "Textures stay files: their paths are stored as the importer resolved them.\n";

static bool ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcmp(s + n - k, suffix) == 0;
}

int cmd_convert(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *muscles = NULL;
    bool no_muscles = false;
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            fputs(convert_usage, stdout);
            return EXIT_OK;
        } else if (strcmp(argv[i], "--muscles") == 0) {
            muscles = cli_muscles_arg(argc, argv, &i);
        } else if (strcmp(argv[i], "--no-muscles") == 0) {
            no_muscles = true;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            cli_error("convert: unknown option %s (see `sinew convert --help`)", argv[i]);
            return EXIT_USAGE;
        } else if (!in) {
            in = argv[i];
        } else if (!out) {
            out = argv[i];
        } else {
            cli_error("convert: one input and one output file (see `sinew convert --help`)");
            return EXIT_USAGE;
        }
    }
    if (!in || !out) {
        fputs(convert_usage, stderr);
        return EXIT_USAGE;
    }
    if (muscles && no_muscles) {
        cli_error("convert: --muscles and --no-muscles together");
        return EXIT_USAGE;
    }
    if (!ends_with(out, ".sinew")) {
        cli_error("%s: the output must be a .sinew file", out);
        return EXIT_USAGE;
    }
    const char *inputs[2] = {in, muscles};
    sinew_error error = {0};
    if (app_output_check(out, inputs, 2, &error) != SINEW_OK) {
        cli_error("convert: %s", error.message);
        return EXIT_OUTPUT;
    }
    /* Muscles: named, the model's own, or the file beside it when there is one (which must
     * then fit the model). */
    app_scene_desc desc = {.path = in, .muscles = APP_MUSCLES_IF_PRESENT};
    if (muscles)
        cli_scene_muscles(muscles, &desc);
    if (no_muscles)
        desc.muscles = APP_MUSCLES_NONE;
    app_scene scene;
    if (cli_scene_load(&scene, &desc) != SINEW_OK)
        return EXIT_BAD_INPUT; /* a muscle that names no joint of IN, too */
    const sinew_model *model = scene.model;
    const sinew_muscle_set *set = scene.muscle_set;
    int status = EXIT_OK;
    /* An empty set stores none, so --no-muscles drops a .sinew's own. */
    static const sinew_muscle_set none = {.source = "", .muscle_count = 0, .muscles = NULL};
    if (sinew_model_save(model, set ? set : &none, out, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        status = error.kind == SINEW_ERROR_IO ? EXIT_OUTPUT : EXIT_BAD_INPUT;
    }
    struct stat st;
    if (status == EXIT_OK) {
        stat(out, &st);
        printf("%s: %lld bytes, %u nodes, %u meshes, %u clips, %u muscles%s%s\n", out, (long long)st.st_size,
               model->node_count, model->mesh_count, model->clip_count, set ? set->muscle_count : 0,
               set && set != model->muscles ? " from " : "", set && set != model->muscles ? set->source : "");
    }
    app_scene_close(&scene);
    return status;
}
