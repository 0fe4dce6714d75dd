/* Loading, clip selection and posing shared by the subcommands. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "cli.h"

void cli_error(const char *format, ...)
{
    va_list args;
    va_start(args, format);
    fputs("sinew: ", stderr);
    vfprintf(stderr, format, args);
    fputc('\n', stderr);
    va_end(args);
}

double cli_json_float(float value)
{
    if (fabsf(value) < 1e-12f)
        return 0.0;
    char text[32];
    for (int digits = 6; digits < 9; digits++) {
        snprintf(text, sizeof text, "%.*g", digits, (double)value);
        if ((float)strtod(text, NULL) == value)
            return strtod(text, NULL);
    }
    snprintf(text, sizeof text, "%.9g", (double)value);
    return strtod(text, NULL);
}

bool cli_is_help(const char *arg)
{
    return strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0;
}

const char *cli_data_path(const char *name, char *buf, size_t size)
{
    const char *dir = getenv("SINEW_DATA");
    if (dir && dir[0]) {
        snprintf(buf, size, "%s/%s", dir, name);
        return buf;
    }
    /* data/ beside the program (a build tree), else share/sinew relative to it (installed). */
    char exe[4096];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    exe[n > 0 ? n : 0] = '\0';
    char *slash = strrchr(exe, '/');
    if (slash)
        *slash = '\0';
    snprintf(buf, size, "%s/data/%s", exe, name);
    if (access(buf, R_OK) != 0)
        snprintf(buf, size, "%s/" SINEW_BIN_TO_DATA "/%s", exe, name);
    return buf;
}

sinew_model *cli_arm_model(const cli_arm_spec *spec)
{
    char path[4096];
    cli_data_path("arm.muscles.json", path, sizeof path);
    sinew_arm_desc desc = {0};
    sinew_error error = {0};
    sinew_model *model = NULL;
    if (sinew_arm_read(path, &desc, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return NULL;
    }
    double angle = spec->angle;
    if (spec->length > 0.0 &&
        sinew_arm_angle(desc.origin_to_elbow, desc.elbow_to_insertion, spec->length, &angle, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return NULL;
    }
    desc.elbow_angle = angle;
    desc.flex_from = spec->flex_from;
    desc.flex_to = spec->flex_to;
    desc.place = spec->place;
    if (sinew_arm_model(&desc, &model, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return NULL;
    }
    return model;
}

sinew_model *cli_load_model(const char *path)
{
    sinew_model *model = NULL;
    sinew_error error = {0};
    if (strcmp(path, CLI_BUILTIN_ARM) == 0) {
        /* The seed's arm at 150 degrees, with a clip that flexes it to 40 degrees and back. */
        cli_arm_spec arm = {.angle = 150.0 * M_PI / 180.0,
                            .flex_from = 150.0 * M_PI / 180.0,
                            .flex_to = 40.0 * M_PI / 180.0,
                            .place = {.translation = {0.0f, 0.15f, 0.0f}}};
        return cli_arm_model(&arm);
    }
    /* SINEW_IMPORTER=assimp: read even FBX through Assimp, to compare (README). */
    const char *importer = getenv("SINEW_IMPORTER");
    sinew_import_desc desc = {.path = path,
                              .in_process = getenv("SINEW_IMPORT_IN_PROCESS") != NULL,
                              .assimp = importer && strcmp(importer, "assimp") == 0,
                              .stderr_fd = STDERR_FILENO};
    if (sinew_import(&desc, &model, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return NULL;
    }
    return model;
}

bool cli_pick_clip(const sinew_model *model, const char *spec, int32_t *clip)
{
    if (!spec) {
        *clip = model->clip_count ? 0 : -1;
        return true;
    }
    if ((*clip = sinew_model_pick_clip(model, spec)) >= 0)
        return true;
    cli_error("%s: no clip \"%s\" (the file has %u clip%s%s)", model->source, spec, model->clip_count,
              model->clip_count == 1 ? "" : "s", model->clip_count ? "; see `sinew info`" : "");
    return false;
}

bool cli_pose_init(cli_pose *pose, const sinew_model *model, const sinew_clip *clip)
{
    memset(pose, 0, sizeof *pose);
    pose->model = model;
    uint32_t n = model->node_count ? model->node_count : 1;
    pose->locals = malloc(n * sizeof *pose->locals);
    pose->worlds = malloc(n * sizeof *pose->worlds);
    pose->palette = malloc(SINEW_MAX_JOINTS * sizeof *pose->palette);
    size_t context_size = sinew_sample_context_size(clip);
    pose->context_memory = malloc(context_size);
    if (!pose->locals || !pose->worlds || !pose->palette || !pose->context_memory ||
        sinew_sample_context_init(pose->context_memory, context_size, clip, &pose->context, NULL) != SINEW_OK) {
        cli_pose_free(pose);
        cli_error("out of memory");
        return false;
    }
    return true;
}

bool cli_pose_at(cli_pose *pose, const sinew_clip *clip, float time, sinew_wrap wrap)
{
    sinew_error error = {0};
    const sinew_model *m = pose->model;
    sinew_sample_desc sample = {.model = m,
                                .clip = clip,
                                .time = time,
                                .wrap = wrap,
                                .context = pose->context,
                                .locals = pose->locals,
                                .local_count = m->node_count};
    if (sinew_sample(&sample, &error) != SINEW_OK ||
        sinew_local_to_world(m, pose->locals, m->node_count, NULL, pose->worlds, m->node_count, &error) != SINEW_OK) {
        cli_error("%s: %s", m->source, error.message);
        return false;
    }
    return true;
}

void cli_pose_free(cli_pose *pose)
{
    free(pose->locals);
    free(pose->worlds);
    free(pose->palette);
    free(pose->context_memory);
    memset(pose, 0, sizeof *pose);
}

sinew_muscle_rig *cli_load_muscles(const sinew_model *model, const char *spec)
{
    sinew_muscle_set *owned = NULL;
    const sinew_muscle_set *set = NULL;
    sinew_muscle_rig *rig = cli_load_muscle_set(model, spec, &owned, &set);
    sinew_muscle_set_free(owned);
    return rig;
}

sinew_muscle_rig *cli_load_muscle_set(const sinew_model *model, const char *spec, sinew_muscle_set **owned,
                                      const sinew_muscle_set **set_out)
{
    *owned = NULL;
    *set_out = NULL;
    sinew_error error = {0};
    if ((!spec || !spec[0]) && model->muscles) {
        /* A .sinew file that carries its muscles. */
        sinew_muscle_rig *rig = NULL;
        if (sinew_muscle_rig_create(model, model->muscles, &rig, &error) != SINEW_OK)
            cli_error("%s", error.message);
        else
            *set_out = model->muscles;
        return rig;
    }
    char beside[4096];
    const char *path = spec;
    if ((!spec || !spec[0]) && strcmp(model->source, "built-in arm") == 0) {
        path = cli_data_path("arm.muscles.json", beside, sizeof beside);
    } else if (!spec || !spec[0]) {
        sinew_muscle_path_for(model->source, beside, sizeof beside);
        path = beside;
    }
    sinew_muscle_set *set = NULL;
    sinew_muscle_rig *rig = NULL;
    if (sinew_muscle_set_read(path, &set, &error) != SINEW_OK ||
        sinew_muscle_rig_create(model, set, &rig, &error) != SINEW_OK) {
        if (error.kind == SINEW_ERROR_IO && path == beside)
            cli_error("%s: no muscle file beside the model (%s); give one with --muscles FILE.json", model->source,
                      beside);
        else
            cli_error("%s", error.message);
    }
    if (!rig) {
        sinew_muscle_set_free(set);
        set = NULL;
    }
    *owned = set;
    *set_out = set;
    return rig;
}

const char *cli_muscles_arg(int argc, char **argv, int *i)
{
    if (*i + 1 < argc) {
        const char *next = argv[*i + 1];
        size_t n = strlen(next);
        if (n > 5 && strcmp(next + n - 5, ".json") == 0) {
            ++*i;
            return next;
        }
    }
    return "";
}

cJSON *cli_muscle_pose_json(const sinew_muscle_pose *p)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", p->name);
    cJSON_AddNumberToObject(o, "length", p->distance);
    cJSON_AddNumberToObject(o, "rest_length", p->state.rest_length);
    cJSON_AddNumberToObject(o, "delta", p->state.delta);
    cJSON_AddNumberToObject(o, "volume", p->state.volume);
    cJSON_AddNumberToObject(o, "rest_volume", p->state.rest_volume);
    cJSON_AddBoolToObject(o, "in_range", p->in_range);
    cJSON *ends[2] = {cJSON_AddArrayToObject(o, "origin"), cJSON_AddArrayToObject(o, "insertion")};
    for (int k = 0; k < 3; k++) {
        cJSON_AddItemToArray(ends[0], cJSON_CreateNumber(cli_json_float(p->origin[k])));
        cJSON_AddItemToArray(ends[1], cJSON_CreateNumber(cli_json_float(p->insertion[k])));
    }
    cJSON *radii = cJSON_AddArrayToObject(o, "radii");
    for (uint32_t k = 0; k < p->node_count; k++)
        cJSON_AddItemToArray(radii, cJSON_CreateNumber(p->radii[k]));
    return o;
}

bool cli_parse_count(const char *command, const char *option, const char *text, long lo, long hi, long *out)
{
    long n = 0;
    if (!app_parse_integer(text, lo, hi, &n)) {
        cli_error("%s: bad %s \"%s\": expected a whole number in %ld..%ld", command, option, text, lo, hi);
        return false;
    }
    *out = n;
    return true;
}

bool cli_parse_size(const char *command, const char *text, int *width, int *height)
{
    if (!app_parse_size(text, 1, 16384, width, height)) {
        cli_error("%s: bad --size \"%s\": expected WIDTHxHEIGHT, each 1..16384", command, text);
        return false;
    }
    return true;
}

uint32_t cli_vertex_count(const sinew_model *model)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < model->instance_count; i++)
        n += model->meshes[model->instances[i].mesh].vertex_count;
    return n;
}
