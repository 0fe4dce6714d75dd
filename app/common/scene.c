/* The scene both apps show: loading, clip, muscles, posing, framing (scene.h). */
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scene.h"

/* ---- a player with its own layout ------------------------------------------------------------ */

sinew_result app_player_open(app_player *p, const sinew_model *model, const sinew_clip *clip, sinew_error *error)
{
    memset(p, 0, sizeof *p);
    sinew_clip_layout_desc desc = {.model = model, .clip = clip};
    sinew_result result = sinew_clip_layout_create(&desc, &p->layout, error);
    if (result != SINEW_OK)
        return result;
    size_t size = sinew_player_size(p->layout);
    p->memory = malloc(size);
    if (!p->memory)
        result = sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for a player", model->source);
    else
        result = sinew_player_init(p->memory, size, p->layout, &p->player, error);
    if (result != SINEW_OK)
        app_player_close(p);
    return result;
}

void app_player_close(app_player *p)
{
    free(p->memory);
    sinew_clip_layout_free(p->layout);
    memset(p, 0, sizeof *p);
}

/* ---- what a model holds ---------------------------------------------------------------------- */

uint32_t app_tree_order(const sinew_model *model, uint32_t *order, uint32_t *depth)
{
    uint32_t n = model->node_count, count = 0;
    int32_t *first = malloc(sizeof(int32_t) * (n ? n : 1)), *next = malloc(sizeof(int32_t) * (n ? n : 1));
    uint32_t *stack = malloc(sizeof(uint32_t) * (n ? n : 1));
    if (!first || !next || !stack) {
        free(first), free(next), free(stack);
        for (uint32_t i = 0; i < n; i++)
            order[i] = i, depth[i] = 0;
        return n;
    }
    for (uint32_t i = 0; i < n; i++)
        first[i] = next[i] = -1;
    /* each node's children, last index first: pushed in that order, they come off the stack first first */
    for (uint32_t i = 0; i < n; i++) {
        int32_t p = model->node_parents[i];
        if (p >= 0 && (uint32_t)p < n) {
            next[i] = first[p];
            first[p] = (int32_t)i;
        }
    }
    for (uint32_t root = 0; root < n; root++) {
        int32_t p = model->node_parents[root];
        if (p >= 0 && (uint32_t)p < n)
            continue;
        uint32_t top = 0;
        stack[top++] = root;
        depth[root] = 0;
        while (top) {
            uint32_t node = stack[--top];
            order[count++] = node;
            for (int32_t c = first[node]; c >= 0; c = next[c]) {
                stack[top++] = (uint32_t)c;
                depth[c] = depth[node] + 1;
            }
        }
    }
    free(first), free(next), free(stack);
    return count;
}

uint32_t app_vertex_count(const sinew_model *model)
{
    uint32_t n = 0;
    for (uint32_t i = 0; model && i < model->instance_count; i++)
        n += model->meshes[model->instances[i].mesh].vertex_count;
    return n;
}

uint32_t app_joint_count(const sinew_model *model)
{
    uint32_t n = 0;
    for (uint32_t i = 0; model && i < model->node_count; i++)
        n += sinew_model_node_is_joint(model, i);
    return n;
}

/* Whether `part` appears in `text`, case ignored. */
static bool contains_nocase(const char *text, const char *part)
{
    size_t n = strlen(part);
    for (; *text; text++)
        if (strncasecmp(text, part, n) == 0)
            return true;
    return n == 0;
}

int app_edit_distance(const char *a, const char *b)
{
    size_t n = strlen(b);
    if (n > 63 || strlen(a) > 63)
        return 99;
    int row[64];
    for (size_t j = 0; j <= n; j++)
        row[j] = (int)j;
    for (size_t i = 1; a[i - 1]; i++) {
        int diagonal = row[0];
        row[0] = (int)i;
        for (size_t j = 1; j <= n; j++) {
            int above = row[j];
            int change = diagonal + (tolower((unsigned char)a[i - 1]) != tolower((unsigned char)b[j - 1]));
            row[j] = change < above + 1 ? change : above + 1;
            row[j] = row[j] < row[j - 1] + 1 ? row[j] : row[j - 1] + 1;
            diagonal = above;
        }
    }
    return row[n];
}

int32_t app_pick_clip(const sinew_model *model, const char *text, sinew_error *error)
{
    if (strcmp(text, "none") == 0 && sinew_model_find_clip(model, text) < 0)
        return APP_CLIP_NONE;
    int32_t clip = sinew_model_pick_clip(model, text);
    if (clip >= 0)
        return clip;
    /* the clips' names, up to 8, and the nearest to a misspelt name */
    char names[512] = "";
    size_t used = 0;
    const char *nearest = NULL;
    bool tied = false;
    int len = (int)strlen(text), best = (len / 2 > 2 ? len / 2 : 2) + 1; /* a near name: half the text at most */
    for (uint32_t i = 0; i < model->clip_count; i++) {
        const char *name = model->clips[i].name ? model->clips[i].name : "";
        int d =
            len >= 3 && contains_nocase(name, text) ? 1 : app_edit_distance(text, name); /* "walk" in "Robot_Walking" */
        if (d < best)
            best = d, nearest = name, tied = false;
        else if (d == best)
            tied = true; /* two as near: suggest neither */
        if (i < 8 && used < sizeof names)
            used += (size_t)snprintf(names + used, sizeof names - used, "%s%u \"%s\"", i ? ", " : "", i, name);
    }
    if (model->clip_count > 8 && used < sizeof names)
        snprintf(names + used, sizeof names - used, ", ... (%u in all; `sinew info` lists them)", model->clip_count);
    char *end = NULL;
    long index = strtol(text, &end, 10);
    if (model->clip_count == 0)
        sinew_fail(error, SINEW_ERROR_DATA, "%s: no clip \"%s\": the file has no clips (--clip none: the rest pose)",
                   model->source, text);
    else if (end != text && *end == '\0')
        sinew_fail(error, SINEW_ERROR_DATA, "%s: no clip %ld: the file's clips are 0..%u: %s", model->source, index,
                   model->clip_count - 1, names);
    else if (nearest && !tied)
        sinew_fail(error, SINEW_ERROR_DATA, "%s: no clip \"%s\"; did you mean \"%s\"? The clips: %s", model->source,
                   text, nearest, names);
    else
        sinew_fail(error, SINEW_ERROR_DATA, "%s: no clip \"%s\"; the clips: %s", model->source, text, names);
    return APP_CLIP_ERROR;
}

int app_import_option_parse(app_import_options *o, int argc, char *const *argv, int i, sinew_error *error)
{
    bool timeout = strcmp(argv[i], "--import-timeout") == 0, memory = strcmp(argv[i], "--import-memory") == 0;
    if (!timeout && !memory)
        return 0;
    double value = 0.0;
    if (i + 1 >= argc || !app_parse_number(argv[i + 1], 0.0, timeout ? APP_MAX_SECONDS : 1e9, &value)) {
        sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "bad %s \"%s\": expected %s", argv[i],
                   i + 1 < argc ? argv[i + 1] : "", timeout ? "seconds (0: no deadline)" : "MiB (0: no limit)");
        return -1;
    }
    if (timeout)
        o->timeout = value > 0.0 ? value : -1.0; /* the desc's "no deadline" */
    else
        o->memory_limit = value > 0.0 ? (uint64_t)(value * 1048576.0) : UINT64_MAX;
    return 2;
}

/* ---- built-in models -------------------------------------------------------------------------- */

const char *app_data_path(const char *name, char *buf, size_t size)
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

sinew_result app_arm_model(const app_arm_spec *spec, sinew_model **out, sinew_error *error)
{
    char path[4096];
    app_data_path("arm.muscles.json", path, sizeof path);
    sinew_arm_desc desc = {0};
    sinew_muscle_set *biceps = NULL;
    sinew_result result = sinew_arm_read(path, &desc, error);
    if (result == SINEW_OK)
        result = sinew_muscle_set_read(path, &biceps, error);
    double angle = spec->angle;
    if (result == SINEW_OK && spec->length > 0.0)
        result = sinew_arm_angle(desc.origin_to_elbow, desc.elbow_to_insertion, spec->length, &angle, error);
    if (result == SINEW_OK) {
        desc.elbow_angle = angle;
        desc.flex_from = spec->flex_from;
        desc.flex_to = spec->flex_to;
        desc.place = spec->place;
        desc.muscles = biceps;
        result = sinew_arm_model(&desc, out, error);
    }
    sinew_muscle_set_free(biceps);
    return result;
}

#define WARM_HUGE ((uintptr_t)2 << 20)

/* x rounded up to a 2 MB boundary. */
static uintptr_t huge_up(uintptr_t x)
{
    return (x + WARM_HUGE - 1) & ~(WARM_HUGE - 1);
}

/* Fills in [from, to) of the heap, asking for huge pages on it first. */
static void warm_range(uintptr_t from, uintptr_t to)
{
    if (to <= from)
        return;
    madvise((void *)from, to - from, MADV_HUGEPAGE); /* where there are none: no harm */
#ifdef MADV_POPULATE_WRITE
    madvise((void *)from, to - from, MADV_POPULATE_WRITE);
#endif
}

void app_warm_heap(const char *path)
{
    /* Not .sinew files: one of 1 MiB or more is read into 2 MB pages by sinew_model_load(), a
     * smaller one into a malloc'd buffer whose pages it fills in with one call (sinew_prefault),
     * and the model beside it touches a few pages more. A 2 MB page warmed for them cost more
     * than it saved where faults are cheap (Fox.glb.sinew 0.72-0.85 of the time without,
     * arnaud.fbx.sinew 0.88-0.95, walk.fbx.sinew 0.96). */
    static const char *const in_process[] = {".fbx", ".gltf", ".glb", ".dae", ".iqm", ".bvh"};
    const char *dot = strrchr(path, '.');
    bool native = false;
    for (size_t i = 0; dot && i < sizeof in_process / sizeof *in_process; i++)
        native = native || strcasecmp(dot, in_process[i]) == 0;
    struct stat st;
    if (!native || stat(path, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size < (64 << 10))
        return;
    /* twice the file in whole 2 MB pages, rounded down, at least one and at most 24 MiB: the
     * readers' heap grows by 1.4 (robot.glb) to 3.9 times (Fox.glb) the file, beside their
     * arena, and a page zeroed for nothing costs more than the faults of what spills past
     * the warmed pages where faults are cheap (robot.glb 0.91 of the time with one page
     * against four times the file's four pages; walk.fbx 0.98, robot_walk.dae the same) */
    size_t bytes = (size_t)st.st_size * 2;
    bytes = bytes > ((size_t)24 << 20) ? (size_t)24 << 20 : bytes & ~(WARM_HUGE - 1);
    bytes = bytes < WARM_HUGE ? WARM_HUGE : bytes;
    /* Only whole 2 MB pages are filled in: a 4 KiB page costs about as much to fault in as a
     * 2 MB one here. The heap's top is first moved to a 2 MB boundary by a block that is kept
     * and never touched (its pages stay unmapped), so that what the import allocates next
     * starts inside the first filled 2 MB page. */
    unsigned char *probe = malloc(bytes + WARM_HUGE);
    if (!probe)
        return;
    uintptr_t head = huge_up((uintptr_t)probe) - (uintptr_t)probe;
    free(probe);
    static void *volatile kept[4]; /* the pads, for the life of the process (volatile: kept by the compiler too) */
    static size_t pads;
    if (head >= 64 && pads < sizeof kept / sizeof *kept)
        kept[pads++] = malloc(head - 2 * sizeof(size_t)); /* a chunk's size is its request and 8, in 16s */
    unsigned char *block = malloc(bytes);
    if (!block)
        return;
    warm_range(huge_up((uintptr_t)block), ((uintptr_t)block + bytes) & ~(WARM_HUGE - 1));
    free(block);
}

sinew_result app_load_model(const app_scene_desc *d, sinew_model **out, sinew_error *error)
{
    const char *path = d->path ? d->path : APP_BUILTIN_DEMO;
    if (strcmp(path, APP_BUILTIN_DEMO) == 0)
        return sinew_demo_humanoid(out, error);
    if (strcmp(path, APP_BUILTIN_MORPH) == 0)
        return sinew_synthetic_model(&(sinew_synthetic_desc){.morph_targets = 50, .morph_animated = 5}, out, error);
    if (strcmp(path, APP_BUILTIN_ARM) == 0) {
        /* The seed's arm at 150 degrees, with a clip that flexes it to 40 degrees and back. */
        app_arm_spec arm = {.angle = 150.0 * M_PI / 180.0,
                            .flex_from = 150.0 * M_PI / 180.0,
                            .flex_to = 40.0 * M_PI / 180.0,
                            .place = {.translation = {0.0f, 0.15f, 0.0f}}};
        return app_arm_model(&arm, out, error);
    }
    /* SINEW_IMPORTER=assimp: read even FBX through Assimp, to compare (README). */
    const char *importer = getenv("SINEW_IMPORTER");
    sinew_import_desc desc = {.path = path,
                              .isolate = d->isolate || getenv("SINEW_IMPORT_ISOLATE") != NULL,
                              .assimp = d->assimp || (importer && strcmp(importer, "assimp") == 0),
                              .timeout = d->import.timeout,
                              .memory_limit = d->import.memory_limit,
                              .stderr_fd = d->stderr_fd,
                              .progress = d->progress,
                              .progress_user = d->progress_user};
    if (d->import.warm_heap && !desc.isolate && !desc.assimp)
        app_warm_heap(path);
    sinew_result result = sinew_import(&desc, out, error);
    /* in the apps' words: the option that sets the limit the import hit */
    int limit = result == SINEW_ERROR_LIMIT_TIME ? 0 : result == SINEW_ERROR_LIMIT_MEMORY ? 1 : -1;
    if (limit >= 0 && error)
        for (int i = limit; i == limit; i++) {
            static const char *const library[2] = {"sinew_import_desc.timeout", "sinew_import_desc.memory_limit"};
            static const char *const option[2] = {"--import-timeout", "--import-memory"};
            char *at = strstr(error->message, library[i]);
            if (at) {
                char rest[SINEW_ERROR_MESSAGE_SIZE];
                snprintf(rest, sizeof rest, "%s", at + strlen(library[i]));
                snprintf(at, sizeof error->message - (size_t)(at - error->message), "%s%s", option[i], rest);
            }
        }
    return result;
}

/* ---- muscles ----------------------------------------------------------------------------------- */

static void note(app_scene *s, const char *format, ...) __attribute__((format(printf, 2, 3)));
static void note(app_scene *s, const char *format, ...)
{
    if (s->note_count >= APP_SCENE_NOTES)
        return;
    va_list args;
    va_start(args, format);
    vsnprintf(s->notes[s->note_count++], sizeof s->notes[0], format, args);
    va_end(args);
}

/* The set the desc asks for: *set NULL with SINEW_OK when there is none to attach. */
static sinew_result find_muscles(app_scene *s, const app_scene_desc *d, const sinew_muscle_set **set,
                                 sinew_error *error)
{
    *set = NULL;
    const sinew_model *m = s->model;
    bool required = d->muscles == APP_MUSCLES_REQUIRED; /* else none is fine */
    if (!(required && d->muscle_path && d->muscle_path[0]) && m->muscles) {
        *set = m->muscles;
        return SINEW_OK;
    }
    char beside[4096];
    const char *path = d->muscle_path;
    if (!required || !path || !path[0]) {
        sinew_muscle_path_for(m->source, beside, sizeof beside);
        path = beside;
        struct stat st;
        if (!required && stat(beside, &st) != 0)
            return SINEW_OK; /* nothing beside the model: none */
    }
    sinew_result result = sinew_muscle_set_read(path, &s->owned_muscles, error);
    if (result == SINEW_ERROR_IO && path == beside)
        return sinew_fail(error, result, "%s: no muscle file beside the model (%s); give one with --muscles FILE.json",
                          m->source, beside);
    *set = s->owned_muscles;
    return result;
}

static sinew_result attach_muscles(app_scene *s, const app_scene_desc *d, sinew_error *error)
{
    const sinew_muscle_set *set = NULL;
    sinew_error why = {0};
    sinew_result result = find_muscles(s, d, &set, &why);
    if (result == SINEW_OK && set)
        result = sinew_muscle_rig_create(s->model, set, &s->muscle_rig, &why);
    if (result == SINEW_OK && set) {
        s->muscle_count = sinew_muscle_rig_count(s->muscle_rig);
        s->muscle_poses = calloc(s->muscle_count + 1, sizeof *s->muscle_poses);
        if (!s->muscle_poses)
            result = sinew_fail(&why, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for muscles", s->model->source);
    }
    if (result == SINEW_OK) {
        s->muscle_set = set;
        if (set) {
            sinew_muscle_rig_set_scale(s->muscle_rig, d->muscle_scale > 0.0 ? d->muscle_scale : 1.0);
            note(s, "%s: %u muscles attached", s->model->source, s->muscle_count);
        }
        return SINEW_OK;
    }
    sinew_muscle_rig_free(s->muscle_rig);
    sinew_muscle_set_free(s->owned_muscles);
    free(s->muscle_poses);
    s->muscle_rig = NULL;
    s->owned_muscles = NULL;
    s->muscle_poses = NULL;
    s->muscle_count = 0;
    if (d->muscles != APP_MUSCLES_IF_ANY) {
        if (error)
            *error = why;
        return result;
    }
    note(s, "muscles not attached: %s", why.message);
    return SINEW_OK;
}

/* ---- the scene ---------------------------------------------------------------------------------- */

sinew_result app_scene_open(app_scene *s, const app_scene_desc *d, sinew_error *error)
{
    memset(s, 0, sizeof *s);
    s->posed_at = NAN;
    s->clip_index = -1;
    s->model = d->model;
    sinew_result result = s->model ? SINEW_OK : app_load_model(d, &s->model, error);
    if (result != SINEW_OK)
        return result;
    if (d->anim) { /* the other file's clips on this model's skeleton */
        app_scene_desc other = *d;
        other.path = d->anim, other.model = NULL;
        sinew_model *source = NULL, *combined = NULL;
        result = app_load_model(&other, &source, error);
        if (result == SINEW_OK) {
            sinew_retarget_desc rd = {.target = s->model, .source = source, .name_map = d->name_map};
            result = sinew_retarget(&rd, &combined, error);
            sinew_model_free(source);
        }
        if (result != SINEW_OK) {
            sinew_model_free(s->model);
            s->model = NULL;
            return result;
        }
        sinew_model_free(s->model);
        s->model = combined;
    }
    int32_t clip = d->clip ? app_pick_clip(s->model, d->clip, error) : (s->model->clip_count ? 0 : APP_CLIP_NONE);
    s->worlds = malloc(((size_t)s->model->node_count + 1) * sizeof *s->worlds);
    size_t channels = (size_t)s->model->morph_channel_count + 1;
    s->weights = malloc(channels * sizeof *s->weights);
    s->overrides = malloc(channels * sizeof *s->overrides);
    s->layouts = calloc((size_t)s->model->clip_count + 1, sizeof *s->layouts);
    s->masks = malloc(((size_t)s->model->node_count + 1) * SINEW_CHARACTER_MAX_LAYERS * sizeof *s->masks);
    s->ops.fade_to = -1;
    for (size_t i = 0; s->overrides && i < channels; i++)
        s->overrides[i] = NAN;
    if (clip == APP_CLIP_ERROR)
        result = SINEW_ERROR_DATA;
    else if (!s->worlds || !s->weights || !s->overrides || !s->layouts || !s->masks)
        result = sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", s->model->source);
    if (result == SINEW_OK)
        result = app_scene_use_clip(s, clip, error);
    if (result == SINEW_OK && d->muscles != APP_MUSCLES_NONE)
        result = attach_muscles(s, d, error);
    if (result == SINEW_OK && d->up && !app_scene_set_up_axis(s, d->up))
        result = sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "--up \"%s\": expected [+|-]x, y or z", d->up);
    if (result == SINEW_OK && d->pose)
        result = app_scene_set_pose_ops(s, d->pose, error);
    if (result != SINEW_OK)
        app_scene_close(s);
    return result;
}

bool app_up_axis(const char *axis, sinew_mat4 *root)
{
    /* the rotation taking each axis to +Y (column-major): +X, +Y, +Z, then their negatives */
    static const struct {
        char axis;
        sinew_mat4 root;
    } TURNS[] = {
        {'x', {{0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}},
        {'y', {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}},
        {'z', {{1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1}}},
        {'X', {{0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}},
        {'Y', {{1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1}}},
        {'Z', {{1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1}}},
    };
    if (!axis)
        return false;
    bool negative = axis[0] == '-';
    const char *name = axis[0] == '-' || axis[0] == '+' ? axis + 1 : axis;
    if (strlen(name) != 1)
        return false;
    char c = (char)tolower((unsigned char)name[0]);
    for (size_t i = 0; i < 3; i++) {
        if (TURNS[i].axis != c)
            continue;
        if (root)
            *root = TURNS[negative ? i + 3 : i].root;
        return true;
    }
    return false;
}

bool app_scene_set_up_axis(app_scene *s, const char *axis)
{
    sinew_mat4 root;
    if (!app_up_axis(axis, &root))
        return false;
    s->root = root;
    s->z_up = memcmp(&root, &(sinew_mat4){{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}, sizeof root) != 0;
    s->posed_at = NAN;
    return true;
}

/* ---- posing: one sinew_character (sinew/character.h) ---------------------------------------- */

/* The layout of clip `index` (-1: the rest pose), made once and kept while the scene is open. */
static sinew_result clip_layout(app_scene *s, int32_t index, const sinew_clip_layout **out, sinew_error *error)
{
    sinew_clip_layout **slot = &s->layouts[index + 1];
    if (!*slot) {
        sinew_clip_layout_desc d = {.model = s->model, .clip = index >= 0 ? &s->model->clips[index] : NULL};
        sinew_result r = sinew_clip_layout_create(&d, slot, error);
        if (r != SINEW_OK)
            return r;
    }
    *out = *slot;
    return SINEW_OK;
}

/* A layer of the character: clip `index` at `weight`, masked to a joint's subtree (mask_joint >= 0). */
static sinew_result add_layer(app_scene *s, sinew_character_desc *d, sinew_character_layer *layers, int32_t index,
                              float weight, int32_t mask_joint, bool additive, sinew_error *error)
{
    sinew_character_layer *l = &layers[d->layer_count];
    *l = (sinew_character_layer){.weight = weight, .additive = additive};
    sinew_result r = clip_layout(s, index, &l->layout, error);
    if (r == SINEW_OK && mask_joint >= 0) {
        float *mask = s->masks + (size_t)d->layer_count * s->model->node_count;
        r = sinew_character_subtree_mask(s->model, (uint32_t)mask_joint, mask, s->model->node_count, error);
        l->mask = mask;
    }
    if (r == SINEW_OK)
        d->layer_count++;
    return r;
}

/* The character of the scene's clip and pose operations, made again (the old one stays on failure). */
static sinew_result build_character(app_scene *s, sinew_error *error)
{
    const app_pose_ops *ops = &s->ops;
    sinew_character_layer layers[SINEW_CHARACTER_MAX_LAYERS];
    sinew_character_ik chains[APP_MAX_IK];
    sinew_character_desc d = {.model = s->model, .layers = layers, .ik = chains, .root_motion = ops->root_motion};
    sinew_result r = SINEW_OK;
    if (ops->blend_count) {
        for (uint32_t i = 0; r == SINEW_OK && i < ops->blend_count; i++)
            r = add_layer(s, &d, layers, ops->blend[i].clip, ops->blend[i].weight, ops->blend[i].mask_joint, false,
                          error);
    } else {
        r = add_layer(s, &d, layers, s->clip_index, 1.0f, -1, false, error);
        if (r == SINEW_OK && ops->fade_to >= 0 && s->clip) { /* from the clip to another, from time 0 */
            d.fade = (sinew_character_fade){.from = 0, .to = 1, .duration = ops->fade_seconds, .sync = true};
            r = add_layer(s, &d, layers, ops->fade_to, 0.0f, -1, false, error);
        }
    }
    for (uint32_t i = 0; r == SINEW_OK && i < ops->additive_count; i++)
        r = add_layer(s, &d, layers, ops->additive[i].clip, ops->additive[i].weight, ops->additive[i].mask_joint, true,
                      error);
    for (uint32_t i = 0; i < ops->ik_count; i++) {
        chains[i] = (sinew_character_ik){.end = ops->ik_end[i], .weight = 1.0f};
        memcpy(chains[i].target, ops->ik_target[i], sizeof chains[i].target);
    }
    d.ik_count = ops->ik_count;
    if (r == SINEW_OK && ops->root_motion && (ops->blend_count ? ops->blend[0].clip < 0 : !s->clip))
        r = sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s: --root-motion needs a clip", s->model->source);
    size_t size = r == SINEW_OK ? sinew_character_size(&d) : 0;
    void *memory = size ? malloc(size) : NULL;
    sinew_character *c = NULL;
    if (r == SINEW_OK)
        r = !size     ? sinew_character_init(&(char){0}, 0, &d, &c, error) /* says what is wrong */
            : !memory ? sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for posing", s->model->source)
                      : sinew_character_init(memory, size, &d, &c, error);
    if (r != SINEW_OK) {
        free(memory);
        return r;
    }
    free(s->character_memory);
    s->character_memory = memory;
    s->character = c;
    s->posed_at = NAN;
    return SINEW_OK;
}

sinew_result app_scene_use_clip(app_scene *s, int32_t index, sinew_error *error)
{
    if (index >= (int32_t)s->model->clip_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s: no clip %d", s->model->source, index);
    int32_t was = s->clip_index;
    s->clip_index = index;
    s->clip = index >= 0 ? &s->model->clips[index] : NULL;
    s->posed_at = NAN;
    sinew_result r = build_character(s, error);
    if (r != SINEW_OK && was != index) { /* the clip stays */
        s->clip_index = was;
        s->clip = was >= 0 ? &s->model->clips[was] : NULL;
        build_character(s, NULL);
    }
    return r;
}

/* The morph weights of the pose (the character's blend of its clips' weights), then the
 * overrides; and where the clip is on the file's timeline, for vertex caches. */
static void pose_weights(app_scene *s, double time, sinew_wrap wrap)
{
    const sinew_model *m = s->model;
    s->cache_time = s->clip ? s->clip->timeline + sinew_clip_time(s->clip, (float)time, wrap) : 0.0f;
    for (uint32_t c = 0; c < m->morph_channel_count; c++)
        if (!isnan(s->overrides[c]))
            s->weights[c] = s->overrides[c];
}

bool app_scene_override_weight(app_scene *s, uint32_t channel, float weight)
{
    if (channel >= s->model->morph_channel_count)
        return false;
    s->overrides[channel] = weight;
    s->posed_at = NAN;
    return true;
}

sinew_result app_scene_pose(app_scene *s, double time, sinew_wrap wrap, sinew_error *error)
{
    if (time == s->posed_at && wrap == s->posed_wrap)
        return SINEW_OK;
    const sinew_model *m = s->model;
    if (!isfinite(time) || fabs(time) > APP_MAX_SECONDS)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "time %g s is out of range (at most %g s either way)",
                          time, APP_MAX_SECONDS);
    sinew_character_set_clamp(s->character, wrap == SINEW_WRAP_CLAMP);
    sinew_result result = sinew_character_seek(s->character, time, error);
    sinew_character_output out = {.root = s->z_up ? &s->root : NULL,
                                  .worlds = s->worlds,
                                  .world_count = m->node_count,
                                  .weights = m->morph_channel_count ? s->weights : NULL,
                                  .weight_count = m->morph_channel_count,
                                  .muscle_rig = s->muscle_rig,
                                  .muscles = s->muscle_poses,
                                  .muscle_count = s->muscle_count};
    if (result == SINEW_OK)
        result = sinew_character_evaluate(s->character, &out, error);
    if (result == SINEW_OK)
        pose_weights(s, time, wrap);
    s->posed_at = result == SINEW_OK ? time : NAN;
    s->posed_wrap = wrap;
    return result;
}

const sinew_root_motion *app_scene_root_motion(const app_scene *s, float translation[3], float *yaw)
{
    return sinew_character_root_motion(s->character, translation, yaw);
}

sinew_frame app_scene_frame(const app_scene *s, const sinew_camera *camera, const sinew_render_options *options,
                            int width, int height)
{
    return (sinew_frame){.worlds = s->worlds,
                         .world_count = s->model->node_count,
                         .camera = camera,
                         .width = width,
                         .height = height,
                         .options = options,
                         .muscles = s->muscle_poses, /* NULL and 0 without muscles */
                         .muscle_count = s->muscle_count,
                         .weights = s->model->morph_channel_count ? s->weights : NULL,
                         .weight_count = s->model->morph_channel_count,
                         .cache_time = s->cache_time};
}

bool app_scene_bounds(app_scene *s, sinew_renderer *renderer, double from, double to, int samples, sinew_wrap wrap,
                      float lo[3], float hi[3])
{
    for (int k = 0; k < 3; k++)
        lo[k] = INFINITY, hi[k] = -INFINITY;
    if (!(to > from) || samples < 2)
        samples = 1;
    for (int i = 0; i < samples; i++) {
        double t = samples > 1 ? from + (to - from) * i / (samples - 1) : to;
        float a[3], b[3];
        if (app_scene_pose(s, t, wrap, NULL) != SINEW_OK)
            continue;
        sinew_render_options o = sinew_render_options_default();
        sinew_frame frame = app_scene_frame(s, NULL, &o, 1, 1);
        if (!sinew_renderer_frame_bounds(renderer, &frame, a, b))
            continue;
        for (int k = 0; k < 3; k++)
            lo[k] = fminf(lo[k], a[k]), hi[k] = fmaxf(hi[k], b[k]);
    }
    if (lo[0] <= hi[0])
        return true;
    for (int k = 0; k < 3; k++)
        lo[k] = -1.0f, hi[k] = 1.0f;
    return false;
}

void app_scene_follow(app_scene *s, double time, sinew_wrap wrap, app_follow *follow, sinew_camera *camera)
{
    if (!camera || !follow->noted || follow->clip != s->clip) { /* (again) from here */
        sinew_root_motion root;
        follow->noted = false;
        follow->clip = s->clip;
        follow->node = s->model && s->clip && sinew_root_motion_init(s->model, s->clip, -1, &root, NULL) == SINEW_OK &&
                               root.node < s->model->node_count
                           ? (int32_t)root.node
                           : -1;
        camera = NULL;
    }
    if (follow->node < 0 || app_scene_pose(s, time, wrap, NULL) != SINEW_OK)
        return;
    const float *at = &s->worlds[follow->node].m[12];
    float *moved = !camera ? NULL : camera->mode == SINEW_CAMERA_ORBIT ? camera->target : camera->position;
    for (int k = 0; moved && k < 3; k += 2) /* over the ground: x and z */
        moved[k] += at[k] - follow->at[k];
    memcpy(follow->at, at, sizeof follow->at);
    follow->noted = true;
}

float app_scene_ground(app_scene *s, sinew_renderer *renderer, int samples)
{
    float lo[3], hi[3];
    double end = s->clip ? s->clip->duration : 0.0;
    return app_scene_bounds(s, renderer, 0.0, end, samples, SINEW_WRAP_CLAMP, lo, hi) ? lo[1] : 0.0f;
}

/* ---- pose operations: blending, cross-fade, additive, root motion, IK ---------------------- */

int app_pose_option_parse(app_pose_spec *spec, int argc, char *const *argv, int i)
{
    const char *o = argv[i];
    if (strcmp(o, "--root-motion") == 0) {
        spec->root_motion = true;
        return 1;
    }
    if (i + 1 >= argc)
        return 0;
    if (strcmp(o, "--blend") == 0)
        spec->blend = argv[i + 1];
    else if (strcmp(o, "--additive") == 0)
        spec->additive = argv[i + 1];
    else if (strcmp(o, "--crossfade") == 0)
        spec->crossfade = argv[i + 1];
    else if (strcmp(o, "--ik") == 0 && spec->ik_count < APP_MAX_IK)
        spec->ik[spec->ik_count++] = argv[i + 1];
    else if (strcmp(o, "--morph") == 0 && spec->morph_count < APP_MAX_MORPHS)
        spec->morph[spec->morph_count++] = argv[i + 1];
    else
        return 0;
    return 2;
}

/* "CLIP[:W][@JOINT],..." into layers (a clip by name or index; W a weight >= 0, 1 when not
 * given; JOINT: only that joint and the nodes below it move with the clip). */
static sinew_result parse_layers(const app_scene *s, const char *option, const char *text, app_layer *out,
                                 uint32_t *count, sinew_error *error)
{
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", text);
    *count = 0;
    for (char *save = NULL, *item = strtok_r(buf, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
        char *at = strrchr(item, '@');
        int32_t joint = -1;
        if (at) {
            *at = 0;
            if ((joint = sinew_model_find_joint(s->model, at + 1)) < 0)
                return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                                  "%s: %s \"%s\": no node \"%s\" to mask the clip to (see `sinew info`)",
                                  s->model->source, option, text, at + 1);
        }
        char *colon = strrchr(item, ':');
        double w = 1.0;
        if (colon) {
            *colon = 0;
            if (!app_parse_number(colon + 1, 0.0, 1000.0, &w))
                return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                                  "%s \"%s\": the weight \"%s\" is not a number in 0..1000", option, text, colon + 1);
        }
        if (*count >= APP_MAX_LAYERS)
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s: at most %d clips", option, APP_MAX_LAYERS);
        int32_t clip = app_pick_clip(s->model, item, error);
        if (clip < 0)
            return clip == APP_CLIP_NONE
                       ? sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s: \"none\" is not a clip to blend", option)
                       : SINEW_ERROR_INVALID_ARGUMENT;
        out[(*count)++] = (app_layer){.clip = clip, .weight = (float)w, .mask_joint = joint};
    }
    if (*count == 0)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s \"%s\": expected CLIP:WEIGHT,...", option, text);
    return SINEW_OK;
}

/* "JOINT:X,Y,Z": a joint with a parent and a grandparent, and a world target. */
static sinew_result parse_ik(const app_scene *s, const char *text, uint32_t *end, float target[3], sinew_error *error)
{
    char name[512];
    const char *colon = strrchr(text, ':');
    double v[3];
    if (!colon || colon == text || sscanf(colon + 1, "%lf,%lf,%lf", &v[0], &v[1], &v[2]) != 3 || !isfinite(v[0]) ||
        !isfinite(v[1]) || !isfinite(v[2]))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "--ik \"%s\": expected JOINT:X,Y,Z (world space)", text);
    snprintf(name, sizeof name, "%.*s", (int)(colon - text), text);
    int32_t node = sinew_model_find_joint(s->model, name);
    if (node < 0)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "%s: --ik \"%s\": no node of that name (see `sinew info`)", s->model->source, name);
    int32_t mid = s->model->node_parents[node], start = mid >= 0 ? s->model->node_parents[mid] : -1;
    if (start < 0)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "%s: --ik \"%s\": the joint needs a parent and a grandparent to bend", s->model->source,
                          name);
    *end = (uint32_t)node;
    for (int k = 0; k < 3; k++)
        target[k] = (float)v[k];
    return SINEW_OK;
}

/* The spec's operations resolved against the scene's model; --crossfade also plays its first clip. */
static sinew_result parse_ops(app_scene *s, const app_pose_spec *spec, app_pose_ops *ops, sinew_error *error)
{
    sinew_result r = SINEW_OK;
    if (spec->blend)
        r = parse_layers(s, "--blend", spec->blend, ops->blend, &ops->blend_count, error);
    if (r == SINEW_OK && spec->additive)
        r = parse_layers(s, "--additive", spec->additive, ops->additive, &ops->additive_count, error);
    if (r == SINEW_OK && spec->crossfade) {
        char buf[512], *comma1, *comma2;
        snprintf(buf, sizeof buf, "%s", spec->crossfade);
        comma2 = strrchr(buf, ',');
        double seconds = 0.0;
        if (!comma2 || !app_parse_number(comma2 + 1, 0.0, APP_MAX_SECONDS, &seconds) ||
            !(comma1 = (*comma2 = 0, strrchr(buf, ',')))) {
            r = sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "--crossfade \"%s\": expected FROM,TO,SECONDS",
                           spec->crossfade);
        } else {
            *comma1 = 0;
            int32_t from = app_pick_clip(s->model, buf, error),
                    to = from >= 0 ? app_pick_clip(s->model, comma1 + 1, error) : APP_CLIP_ERROR;
            if (from < 0 || to < 0) {
                r = SINEW_ERROR_INVALID_ARGUMENT;
            } else {
                s->clip_index = from;
                s->clip = &s->model->clips[from];
                ops->fade_to = to;
                ops->fade_seconds = (float)seconds;
            }
        }
    }
    for (int i = 0; r == SINEW_OK && i < spec->ik_count; i++)
        if ((r = parse_ik(s, spec->ik[i], &ops->ik_end[i], ops->ik_target[i], error)) == SINEW_OK)
            ops->ik_count++;
    ops->root_motion = spec->root_motion;
    return r;
}

sinew_result app_scene_set_pose_ops(app_scene *s, const app_pose_spec *spec, sinew_error *error)
{
    app_pose_ops ops = {.fade_to = -1};
    int32_t clip = s->clip_index;
    sinew_result r = spec ? parse_ops(s, spec, &ops, error) : SINEW_OK;
    for (uint32_t c = 0; r == SINEW_OK && c < s->model->morph_channel_count; c++)
        s->overrides[c] = NAN;
    for (int i = 0; r == SINEW_OK && spec && i < spec->morph_count; i++)
        r = app_scene_parse_morph(s, spec->morph[i], error);
    if (r == SINEW_OK) {
        s->ops = ops;
        r = build_character(s, error);
    }
    if (r != SINEW_OK) { /* back to plain play of the clip */
        s->ops = (app_pose_ops){.fade_to = -1};
        s->clip_index = clip;
        s->clip = clip >= 0 ? &s->model->clips[clip] : NULL;
        build_character(s, NULL);
    }
    s->posed_at = NAN;
    return r;
}

bool app_scene_set_ik_target(app_scene *s, uint32_t chain, const float target[3])
{
    if (chain >= s->ops.ik_count || sinew_character_set_target(s->character, chain, target, 1.0f, NULL) != SINEW_OK)
        return false;
    memcpy(s->ops.ik_target[chain], target, sizeof s->ops.ik_target[chain]);
    s->posed_at = NAN;
    return true;
}

void app_scene_close(app_scene *s)
{
    for (uint32_t i = 0; s->layouts && s->model && i <= s->model->clip_count; i++)
        sinew_clip_layout_free(s->layouts[i]);
    free(s->layouts);
    free(s->character_memory);
    free(s->masks);
    sinew_muscle_rig_free(s->muscle_rig);
    sinew_muscle_set_free(s->owned_muscles);
    free(s->muscle_poses);
    free(s->worlds);
    free(s->weights);
    free(s->overrides);
    if (s->model)
        sinew_model_free(s->model);
    memset(s, 0, sizeof *s);
    s->posed_at = NAN;
    s->clip_index = -1;
    s->ops.fade_to = -1;
}

/* ---- --morph: a weight by hand -------------------------------------------------------------- */

/* Whether `text` names item `index` called `name`: the name, or the index written in decimal. */
static bool names(const char *text, size_t len, const char *name, uint32_t index)
{
    if (name && strlen(name) == len && strncmp(text, name, len) == 0)
        return true;
    char digits[16];
    int n = snprintf(digits, sizeof digits, "%u", index);
    return (size_t)n == len && strncmp(text, digits, len) == 0;
}

/* Overrides every channel that target `target` (of meshes `mesh`, any when NULL) drives; the
 * number overridden. */
static uint32_t override_targets(app_scene *s, const char *mesh, size_t mesh_len, const char *target, size_t target_len,
                                 float w)
{
    const sinew_model *m = s->model;
    uint32_t count = 0;
    for (uint32_t i = 0; i < m->instance_count; i++) {
        const sinew_instance *in = &m->instances[i];
        const sinew_mesh *me = &m->meshes[in->mesh];
        if (mesh && !names(mesh, mesh_len, me->name, in->mesh))
            continue;
        for (uint32_t t = 0; t < me->target_count; t++)
            if (names(target, target_len, me->targets[t].name, t) &&
                app_scene_override_weight(s, in->morph_first + me->targets[t].channel, w))
                count++;
    }
    return count;
}

sinew_result app_scene_parse_morph(app_scene *s, const char *text, sinew_error *error)
{
    const sinew_model *m = s->model;
    const char *eq = strrchr(text, '=');
    double w = 0.0;
    if (!eq || eq == text || !app_parse_number(eq + 1, -1e6, 1e6, &w))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "--morph \"%s\": expected MESH:TARGET=WEIGHT, TARGET=WEIGHT or CHANNEL=WEIGHT", text);
    const char *colon = memchr(text, ':', (size_t)(eq - text));
    uint32_t count = 0;
    if (colon) {
        count = override_targets(s, text, (size_t)(colon - text), colon + 1, (size_t)(eq - colon - 1), (float)w);
    } else {
        size_t len = (size_t)(eq - text);
        for (uint32_t c = 0; c < m->morph_channel_count; c++)
            if (strlen(m->morph_channels[c].name) == len && strncmp(text, m->morph_channels[c].name, len) == 0)
                count += app_scene_override_weight(s, c, (float)w);
        if (!count)
            count = override_targets(s, NULL, 0, text, len, (float)w);
        for (uint32_t c = 0; !count && c < m->morph_channel_count; c++)
            if (names(text, len, NULL, c))
                count += app_scene_override_weight(s, c, (float)w);
    }
    if (count)
        return SINEW_OK;
    char list[1024] = "";
    size_t at = 0;
    for (uint32_t i = 0; i < m->mesh_count && at + 64 < sizeof list; i++)
        for (uint32_t t = 0; t < m->meshes[i].target_count && at + 64 < sizeof list; t++)
            at += (size_t)snprintf(list + at, sizeof list - at, "%s%s:%s", at ? ", " : "", m->meshes[i].name,
                                   m->meshes[i].targets[t].name);
    return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "--morph \"%s\": %s has no such morph target%s%s", text,
                      m->source, list[0] ? "; it has " : " (it has none)", list);
}
