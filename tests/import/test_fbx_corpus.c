/* Every FBX file of the shared test data against ufbx (../shared/testdata/reference/ufbx):
 * each file is imported as a user's `sinew pose` imports it, posed by its first clip at the
 * reference's ten times, and its node world positions and skinned vertices compared with
 * ufbx's, relative to the bounding diagonal. A file agrees when its joints are within 1e-3
 * and its vertices within 2e-3 (the bar); the count within 1e-5 ("the same pose")
 * is reported beside it. The same scene saved in several FBX versions (NAME_6100_ascii,
 * NAME_7500_binary, ...) must also pose the same, to 1e-6 of the diagonal beyond what their
 * references differ by (a 6.x ASCII file may write its numbers with fewer digits).
 *
 * The authoring tools' own exports of some frames (ufbx/NAME_FRAME.obj: the scene's vertices
 * at that frame, in the file's axes and units) are the last word: every version of the scene
 * posed at that frame, taken back to the file's space, must match them within 1e-3 of their
 * diagonal (they keep six digits).
 *
 * The output is a table per class of file (FBX version, what ufbx/CORPUS.tsv says the file
 * carries), so a change that helps one class and hurts another shows. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "reference.h"

#define JOINT_LIMIT 1e-3
#define VERTEX_LIMIT 2e-3
#define VERSION_LIMIT 1e-6
#define OBJ_LIMIT 1e-3
#define MAX_FILES 512

enum {
    C_ALL,
    C_FBX5,
    C_FBX6,
    C_FBX7,
    C_ASCII,
    C_BINARY,
    C_TANGENTS,
    C_STEPPED,
    C_EXTRAPOLATION,
    C_LAYERS,
    C_STACKS,
    C_PIVOTS,
    C_SKINNED,
    C_BLEND_SHAPES,
    C_CACHES,
    C_DUAL_QUATERNION,
    C_COUNT
};

static const char *const class_names[C_COUNT] = {
    "all files",     "FBX 5.x",      "FBX 6.x",        "FBX 7.x",
    "ASCII",         "binary",       "cubic tangents", "stepped keys",
    "extrapolation", "layers",       "stacks",         "pivots, pre/post rotation",
    "skinned",       "blend shapes", "caches",         "dual-quaternion skins",
};

typedef struct corpus_file {
    char rel[512];   /* under testdata */
    char scene[512]; /* the name without its version and encoding: versions of a scene share it */
    int version;     /* 5000, 6100, 7500 ... (0: unknown) */
    bool classes[C_COUNT];
    bool loaded, agrees, same_pose;
    outcome o;
    char error[600];
} corpus_file;

/* The number after "KEY=" in a CORPUS.tsv feature list, or 0. */
static double feature(const char *features, const char *key)
{
    char pattern[64];
    snprintf(pattern, sizeof pattern, " %s=", key);
    const char *at = strstr(features, pattern);
    if (!at && strncmp(features, pattern + 1, strlen(pattern + 1)) == 0)
        at = features - 1;
    return at ? atof(at + strlen(pattern)) : 0;
}

/* "interp=cpA,cnB,linC,cubD": how many keys of each kind. */
static void interpolation(const char *features, double *stepped, double *cubic)
{
    const char *at = strstr(features, "interp=");
    double cp = 0, cn = 0, lin = 0, cub = 0;
    if (at)
        sscanf(at, "interp=cp%lf,cn%lf,lin%lf,cub%lf", &cp, &cn, &lin, &cub);
    *stepped = cp + cn;
    *cubic = cub;
}

/* The classes of a file from its name and its CORPUS.tsv row (NULL when it has none). */
static void classify(corpus_file *f, const char *features)
{
    const char *base = strrchr(f->rel, '/') ? strrchr(f->rel, '/') + 1 : f->rel;
    snprintf(f->scene, sizeof f->scene, "%s", base);
    char *dot = strrchr(f->scene, '.');
    if (dot)
        *dot = 0;
    bool ascii = strstr(base, "_ascii.") != NULL, binary = strstr(base, "_binary.") != NULL;
    char *enc = strstr(f->scene, ascii ? "_ascii" : "_binary");
    if ((ascii || binary) && enc) {
        *enc = 0;
        char *v = strrchr(f->scene, '_');
        if (v && strlen(v + 1) == 4 && strspn(v + 1, "0123456789") == 4) {
            f->version = atoi(v + 1);
            *v = 0;
        }
    }
    f->classes[C_ALL] = true;
    f->classes[C_FBX5] = f->version >= 5000 && f->version < 6000;
    f->classes[C_FBX6] = f->version >= 6000 && f->version < 7000;
    f->classes[C_FBX7] = f->version >= 7000 || f->version == 0;
    f->classes[C_ASCII] = ascii;
    f->classes[C_BINARY] = binary || !ascii;
    if (!features)
        return;
    double stepped, cubic;
    interpolation(features, &stepped, &cubic);
    f->classes[C_TANGENTS] = cubic > 0;
    f->classes[C_STEPPED] = stepped > 0;
    f->classes[C_EXTRAPOLATION] = feature(features, "extrap_curves") > 0;
    f->classes[C_LAYERS] = feature(features, "layers") > 1;
    f->classes[C_STACKS] = feature(features, "stacks") > 1;
    f->classes[C_PIVOTS] = feature(features, "pivots") > 0 || feature(features, "prepost_rot") > 0;
    f->classes[C_SKINNED] = strstr(features, "skin_method=") != NULL;
    f->classes[C_BLEND_SHAPES] = feature(features, "blend_channels") > 0;
    f->classes[C_CACHES] = feature(features, "caches") > 0;
    f->classes[C_DUAL_QUATERNION] = strstr(features, "skin_method=dual") || strstr(features, "skin_method=blended");
}

/* The CORPUS.tsv row's feature column for a file name, or NULL; the text's lines were cut
 * into strings (cut_lines). */
static const char *corpus_features(const char *tsv, size_t size, const char *name)
{
    size_t n = strlen(name);
    for (const char *line = tsv; line < tsv + size; line += strlen(line) + 1) {
        if (strncmp(line, name, n) == 0 && line[n] == '\t') {
            const char *col = strchr(line + n + 1, '\t'); /* after the exporter */
            return col ? col + 1 : NULL;
        }
    }
    return NULL;
}

static void cut_lines(char *text, size_t size)
{
    for (size_t i = 0; i < size; i++)
        if (text[i] == '\n')
            text[i] = 0;
}

static bool has_reference(const char *rel)
{
    char name[512], path[1024];
    reference_name("ufbx", rel, name, sizeof name);
    return testdata_path(name, path, sizeof path) != NULL;
}

static void add_file(corpus_file *files, uint32_t *count, const char *rel)
{
    if (*count == MAX_FILES || !has_reference(rel))
        return;
    corpus_file *f = &files[(*count)++];
    memset(f, 0, sizeof *f);
    snprintf(f->rel, sizeof f->rel, "%s", rel);
}

static int compare_rel(const void *a, const void *b)
{
    return strcmp(((const corpus_file *)a)->rel, ((const corpus_file *)b)->rel);
}

/* Every .fbx of the folders under testdata that hold FBX files and has a ufbx reference. */
static uint32_t find_files(corpus_file *files)
{
    static const char *const folders[] = {"ufbx", "assimp/FBX", "ozz/pab"};
    uint32_t count = 0;
    char path[1024], rel[512];
    for (size_t i = 0; i < sizeof folders / sizeof folders[0]; i++) {
        if (!testdata_path(folders[i], path, sizeof path))
            continue;
        DIR *d = opendir(path);
        if (!d)
            continue;
        for (struct dirent *e; (e = readdir(d));) {
            size_t n = strlen(e->d_name);
            if (n > 4 && strcasecmp(e->d_name + n - 4, ".fbx") == 0) {
                snprintf(rel, sizeof rel, "%s/%s", folders[i], e->d_name);
                add_file(files, &count, rel);
            }
        }
        closedir(d);
    }
    qsort(files, count, sizeof *files, compare_rel);
    return count;
}

static sinew_model *import_file(const char *path, char *error_text, size_t size)
{
    sinew_model *model = NULL;
    sinew_error error = {0};
    if (sinew_import(&(sinew_import_desc){.path = path}, &model, &error) != SINEW_OK) {
        snprintf(error_text, size, "%s", error.message);
        return NULL;
    }
    return model;
}

/* Largest distance between the same-named nodes of two models over the reference's times,
 * relative to the reference's diagonal; -1 when they share no node name. */
static double version_difference(const sinew_model *a, const sinew_model *b, const cJSON *ref)
{
    const cJSON *frames = cJSON_GetObjectItem(ref, "frames"), *frame;
    double diag = reference_diagonal(frames), worst = -1;
    cJSON_ArrayForEach(frame, frames)
    {
        float t = (float)cJSON_GetObjectItem(frame, "t")->valuedouble;
        sinew_mat4 *wa = pose_worlds(a, a->clip_count ? &a->clips[0] : NULL, t);
        sinew_mat4 *wb = pose_worlds(b, b->clip_count ? &b->clips[0] : NULL, t);
        for (uint32_t i = 0; i < a->node_count; i++) {
            int32_t j = sinew_model_find_node(b, a->node_names[i]);
            if (j < 0)
                continue;
            double d = 0;
            for (int c = 12; c < 15; c++)
                d += (wa[i].m[c] - wb[j].m[c]) * (wa[i].m[c] - wb[j].m[c]);
            worst = fmax(worst, sqrt(d) / diag);
        }
        free(wa);
        free(wb);
    }
    return worst;
}

/* The same between two references of the same times (the files of one scene in two versions
 * may not hold the same numbers: FBX 6.x ASCII writes fewer digits). */
static double reference_difference(const cJSON *a, const cJSON *b)
{
    const cJSON *fa = cJSON_GetObjectItem(a, "frames"), *fb = cJSON_GetObjectItem(b, "frames");
    double diag = reference_diagonal(fa), worst = 0;
    int n = cJSON_GetArraySize(fa);
    if (n != cJSON_GetArraySize(fb))
        return INFINITY;
    for (int f = 0; f < n; f++) {
        const cJSON *na = cJSON_GetObjectItem(cJSON_GetArrayItem(fa, f), "nodes");
        const cJSON *nb = cJSON_GetObjectItem(cJSON_GetArrayItem(fb, f), "nodes"), *node;
        cJSON_ArrayForEach(node, na)
        {
            const cJSON *other = cJSON_GetObjectItem(nb, node->string);
            if (!other)
                continue;
            double d = 0;
            for (int c = 0; c < 3; c++) {
                double x = cJSON_GetArrayItem(node, c)->valuedouble - cJSON_GetArrayItem(other, c)->valuedouble;
                d += x * x;
            }
            worst = fmax(worst, sqrt(d) / diag);
        }
    }
    return worst;
}

/* An OBJ file's vertices (malloc'd xyz), or NULL. ufbx's test suite marks the frames it does
 * not compare as they are ("# ufbx:transform_skin": Maya shows those skinned meshes moved again by
 * their nodes' animation, which neither ufbx nor the FBX SDK nor sinew applies); *marked is set
 * for them. */
static double *read_obj(const char *path, uint32_t *count, bool *marked)
{
    size_t size;
    char *text = read_file(path, &size);
    if (!text)
        return NULL;
    *marked = strstr(text, "ufbx:transform_skin") != NULL;
    uint32_t n = 0, cap = 1024;
    double *v = malloc(cap * 3 * sizeof *v);
    for (char *line = text; v && line && *line; line = strchr(line, '\n') ? strchr(line, '\n') + 1 : NULL) {
        double x, y, z;
        if (line[0] != 'v' || line[1] != ' ' || sscanf(line + 2, "%lf %lf %lf", &x, &y, &z) != 3)
            continue;
        if (n == cap)
            v = realloc(v, (cap *= 2) * 3 * sizeof *v);
        if (v)
            v[n * 3] = x, v[n * 3 + 1] = y, v[n * 3 + 2] = z, n++;
    }
    free(text);
    *count = n;
    return v;
}

/* A loaded file of the scene posed at the OBJ's frame (the clip's frame rate, 24 when it keeps
 * none), in the file's own space (node 0's conversion undone), against the OBJ: the distance
 * relative to the OBJ's diagonal. */
static double obj_frame_difference(const sinew_model *m, const double *obj, uint32_t n, int frame)
{
    const sinew_clip *clip = m->clip_count ? &m->clips[0] : NULL;
    double fps = clip && clip->frame_rate > 0 ? clip->frame_rate : 24.0;
    float t = (float)(frame / fps - (clip ? clip->timeline : 0.0));
    sinew_mat4 *w = pose_worlds(m, clip, t);
    uint32_t count;
    float *ours = posed_vertices_at(m, w, clip, t, &count);
    /* node 0's affine inverse: the cofactors of its 3x3 part over the determinant */
    const float *a = w[0].m;
    double k[9] = {a[5] * a[10] - a[6] * a[9], a[9] * a[2] - a[10] * a[1], a[1] * a[6] - a[2] * a[5],
                   a[6] * a[8] - a[4] * a[10], a[10] * a[0] - a[8] * a[2], a[2] * a[4] - a[0] * a[6],
                   a[4] * a[9] - a[5] * a[8],  a[8] * a[1] - a[9] * a[0],  a[0] * a[5] - a[1] * a[4]};
    double det = a[0] * k[0] + a[4] * k[1] + a[8] * k[2];
    for (uint32_t i = 0; i < count; i++) {
        double p[3] = {ours[i * 3] - a[12], ours[i * 3 + 1] - a[13], ours[i * 3 + 2] - a[14]};
        for (int r = 0; r < 3; r++) /* row r of the inverse is column r of the cofactors over det */
            ours[i * 3 + r] = (float)((k[r] * p[0] + k[3 + r] * p[1] + k[6 + r] * p[2]) / det);
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            lo[c] = fmin(lo[c], obj[i * 3 + c]), hi[c] = fmax(hi[c], obj[i * 3 + c]);
    double diag =
        sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    double d = point_set_distance(ours, count, obj, n) / (diag > 0 ? diag : 1);
    free(ours);
    free(w);
    return d;
}

/* Every ufbx/SCENE_FRAME.obj against the loaded versions of SCENE; false when one differs. */
static bool check_obj_frames(const corpus_file *files, sinew_model *const *models, uint32_t count, uint32_t *checked)
{
    char dir[1024], path[1280];
    *checked = 0;
    if (!testdata_path("ufbx", dir, sizeof dir))
        return true;
    DIR *d = opendir(dir);
    bool ok = true;
    for (struct dirent *e; d && (e = readdir(d));) {
        size_t len = strlen(e->d_name);
        const char *us = strrchr(e->d_name, '_');
        if (len < 5 || strcmp(e->d_name + len - 4, ".obj") || !us ||
            strspn(us + 1, "0123456789") != (size_t)(len - 4 - (size_t)(us + 1 - e->d_name)))
            continue;
        char scene[256];
        snprintf(scene, sizeof scene, "%.*s", (int)(us - e->d_name), e->d_name);
        int frame = atoi(us + 1);
        double *obj = NULL;
        uint32_t n = 0;
        bool marked = false;
        for (uint32_t i = 0; i < count; i++) {
            if (!models[i] || strcmp(files[i].scene, scene))
                continue;
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            if (!obj && !(obj = read_obj(path, &n, &marked)))
                break;
            if (marked) {
                print_message("%-62s frame %4d: not compared (Maya's own view of a skin whose node moves)\n",
                              files[i].rel, frame);
                continue;
            }
            double diff = obj_frame_difference(models[i], obj, n, frame);
            (*checked)++;
            print_message("%-62s frame %4d: %.1e of the OBJ's diagonal%s\n", files[i].rel, frame, diff,
                          diff <= OBJ_LIMIT ? "" : "  <-- differs from the tool's export");
            ok &= diff <= OBJ_LIMIT;
        }
        free(obj);
    }
    if (d)
        closedir(d);
    return ok;
}

static void print_classes(const corpus_file *files, uint32_t count)
{
    print_message("\n%-28s %6s %7s %9s %9s\n", "class", "files", "loaded", "agree", "at 1e-5");
    for (int c = 0; c < C_COUNT; c++) {
        uint32_t n = 0, loaded = 0, agree = 0, exact = 0;
        for (uint32_t i = 0; i < count; i++) {
            if (!files[i].classes[c])
                continue;
            n++;
            loaded += files[i].loaded;
            agree += files[i].agrees;
            exact += files[i].agrees && files[i].o.nodes <= SAME_POSE && files[i].o.verts <= SAME_POSE;
        }
        if (n)
            print_message("%-28s %6u %7u %9u %9u\n", class_names[c], n, loaded, agree, exact);
    }
}

static void test_corpus_against_ufbx(void **state)
{
    (void)state;
    char path[1024], tsv_path[1024];
    if (!testdata_path("ufbx/CORPUS.tsv", tsv_path, sizeof tsv_path))
        skip();
    size_t tsv_size;
    char *tsv = read_file(tsv_path, &tsv_size);
    assert_non_null(tsv);
    cut_lines(tsv, tsv_size);
    corpus_file *files = calloc(MAX_FILES, sizeof *files);
    uint32_t count = find_files(files);
    assert_true(count > 0);
    sinew_model **models = calloc(count, sizeof *models);
    cJSON **refs = calloc(count, sizeof *refs);
    bool failed = false;
    for (uint32_t i = 0; i < count; i++) {
        corpus_file *f = &files[i];
        const char *base = strrchr(f->rel, '/') + 1;
        classify(f, strncmp(f->rel, "ufbx/", 5) == 0 ? corpus_features(tsv, tsv_size, base) : NULL);
        char rel[512], ref_path[1024];
        reference_name("ufbx", f->rel, rel, sizeof rel);
        refs[i] = read_gzip_json(testdata_path(rel, ref_path, sizeof ref_path));
        models[i] = import_file(testdata_path(f->rel, path, sizeof path), f->error, sizeof f->error);
        f->loaded = models[i] != NULL;
        if (f->loaded) {
            f->o = compare_with_reference(models[i], refs[i], NULL);
            f->agrees = f->o.nodes <= JOINT_LIMIT && f->o.verts <= VERTEX_LIMIT && f->o.missing == 0;
        }
        if (f->loaded)
            print_message("%-62s nodes %.1e verts %.1e (%u, %u missing)%s\n", f->rel, f->o.nodes, f->o.verts,
                          f->o.compared, f->o.missing, f->agrees ? "" : "  <-- disagrees");
        else
            print_message("%-62s NOT LOADED: %s\n", f->rel, f->error);
        failed |= !f->agrees;
    }
    /* Versions of one scene against the first of them that loaded. */
    uint32_t pairs = 0, pairs_same = 0;
    for (uint32_t i = 0; i < count; i++) {
        if (!models[i] || !files[i].version)
            continue;
        for (uint32_t j = i + 1; j < count; j++) {
            if (!models[j] || strcmp(files[i].scene, files[j].scene) != 0)
                continue;
            double d = version_difference(models[i], models[j], refs[i]);
            double files_differ = reference_difference(refs[i], refs[j]);
            pairs++;
            bool same = d >= 0 && d <= files_differ + VERSION_LIMIT;
            pairs_same += same;
            if (!same)
                print_message("versions differ: %s and %s by %.1e of the diagonal (their references by %.1e)\n",
                              files[i].rel, files[j].rel, d, files_differ);
            failed |= !same;
        }
    }
    uint32_t obj_frames = 0;
    failed |= !check_obj_frames(files, models, count, &obj_frames);
    print_classes(files, count);
    print_message("the authoring tools' OBJ frames: %u compared\n", obj_frames);
    print_message("versions of one scene posing the same (1e-6 beyond their references): %u of %u pairs\n", pairs_same,
                  pairs);
    for (uint32_t i = 0; i < count; i++) {
        sinew_model_free(models[i]);
        cJSON_Delete(refs[i]);
    }
    free(models);
    free(refs);
    free(files);
    free(tsv);
    if (failed)
        fail_msg("some FBX files do not pose as ufbx does (see above)");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_corpus_against_ufbx),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
