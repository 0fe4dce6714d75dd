/* sinew's poses against independent implementations (../shared/testdata/reference): every
 * FBX file against ufbx, node world positions at ten times and skinned vertices (as point
 * sets) at three, relative to the bounding diagonal of the reference's nodes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>
#include <zlib.h>

#include "helpers.h"

#define SAME_POSE 1e-5 /* of the diagonal: "the same pose" (reference/README.md) */

static cJSON *read_gzip_json(const char *path)
{
    gzFile f = gzopen(path, "rb");
    assert_non_null(f);
    size_t cap = 1 << 20, n = 0;
    char *text = malloc(cap);
    int got;
    while ((got = gzread(f, text + n, (unsigned)(cap - n - 1))) > 0) {
        n += (size_t)got;
        if (n + 1 == cap)
            text = realloc(text, cap *= 2);
    }
    gzclose(f);
    text[n] = 0;
    cJSON *root = cJSON_Parse(text);
    free(text);
    assert_non_null(root);
    return root;
}

static double dist3(const float *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* Largest distance from a point of one set to the nearest of the other, both ways. */
static double point_set_distance(const float *ours, uint32_t n_ours, const double *ref, uint32_t n_ref)
{
    double worst = 0;
    for (uint32_t i = 0; i < n_ref; i++) {
        double best = INFINITY;
        for (uint32_t j = 0; j < n_ours; j++)
            best = fmin(best, dist3(&ours[j * 3], &ref[i * 3]));
        worst = fmax(worst, best);
    }
    for (uint32_t j = 0; j < n_ours; j++) {
        double best = INFINITY;
        for (uint32_t i = 0; i < n_ref; i++)
            best = fmin(best, dist3(&ours[j * 3], &ref[i * 3]));
        worst = fmax(worst, best);
    }
    return worst;
}

static double vec_at(const cJSON *a, int i)
{
    return cJSON_GetArrayItem(a, i)->valuedouble;
}

/* The diagonal of every node position of every frame of the reference. */
static double reference_diagonal(const cJSON *frames)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const cJSON *frame, *node;
    cJSON_ArrayForEach(frame, frames)
        cJSON_ArrayForEach(node, cJSON_GetObjectItem(frame, "nodes")) for (int c = 0; c < 3; c++)
    {
        lo[c] = fmin(lo[c], vec_at(node, c));
        hi[c] = fmax(hi[c], vec_at(node, c));
    }
    double d =
        sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    return d > 0 ? d : 1.0;
}

typedef struct outcome {
    double nodes, verts; /* largest, relative to the diagonal */
    uint32_t compared, missing;
} outcome;

static outcome compare_with_reference(const sinew_model *m, const cJSON *ref)
{
    outcome o = {0};
    const cJSON *frames = cJSON_GetObjectItem(ref, "frames"), *frame;
    double diag = reference_diagonal(frames);
    const sinew_clip *clip = m->clip_count ? &m->clips[0] : NULL;
    cJSON_ArrayForEach(frame, frames)
    {
        float t = (float)cJSON_GetObjectItem(frame, "t")->valuedouble;
        sinew_mat4 *w = pose_worlds(m, clip, t);
        const cJSON *node;
        cJSON_ArrayForEach(node, cJSON_GetObjectItem(frame, "nodes"))
        {
            int32_t n = sinew_model_find_node(m, node->string);
            if (n < 0) {
                o.missing++;
                continue;
            }
            double p[3] = {vec_at(node, 0), vec_at(node, 1), vec_at(node, 2)};
            o.nodes = fmax(o.nodes, dist3(&w[n].m[12], p) / diag);
            o.compared++;
        }
        const cJSON *verts = cJSON_GetObjectItem(frame, "verts");
        int nv = cJSON_GetArraySize(verts);
        if (nv > 0) {
            double *rv = malloc((size_t)nv * 3 * sizeof *rv);
            for (int i = 0; i < nv; i++)
                for (int c = 0; c < 3; c++)
                    rv[i * 3 + c] = vec_at(cJSON_GetArrayItem(verts, i), c);
            uint32_t count;
            float *ours = posed_vertices(m, w, &count);
            o.verts = fmax(o.verts, point_set_distance(ours, count, rv, (uint32_t)nv) / diag);
            free(ours);
            free(rv);
        }
        free(w);
    }
    return o;
}

/* reference/ufbx/NAME.json.gz of a model of the test data: its path with '/' as "__" and
 * without its extension (reference/README.md). */
static void reference_name(const char *model, char *out, size_t size)
{
    size_t n = (size_t)snprintf(out, size, "reference/ufbx/");
    const char *dot = strrchr(model, '.');
    for (const char *c = model; c < dot && n + 2 < size; c++) {
        if (*c == '/')
            out[n++] = '_', out[n++] = '_';
        else
            out[n++] = *c;
    }
    snprintf(out + n, size - n, ".json.gz");
}

/* Every FBX file of the test data, against ufbx: nodes and vertices within 1e-5 of the
 * diagonal at every reference time. */
static void test_fbx_against_ufbx(void **state)
{
    (void)state;
    static const char *const files[] = {
        "assimp/FBX/animation_with_skeleton.fbx",
        "assimp/FBX/huesitos.fbx",
        "ozz/pab/arnaud.fbx",
        "ozz/pab/walk.fbx",
        "ufbx/max_transformed_skin_7500_ascii.fbx",
        "ufbx/max_transformed_skin_7500_binary.fbx",
        "ufbx/maya_transformed_skin_7700_ascii.fbx",
        "ufbx/maya_transformed_skin_7700_binary.fbx",
        "ufbx/maya_instanced_skin_7700_ascii.fbx",
        "ufbx/maya_instanced_skin_7700_binary.fbx",
        "ufbx/motionbuilder_sausage_rrss_7700_binary.fbx",
    };
    char path[1024], rel[512];
    bool failed = false;
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        if (!testdata_path(files[i], path, sizeof path))
            skip();
        reference_name(files[i], rel, sizeof rel);
        char ref_path[1024];
        testdata_path(rel, ref_path, sizeof ref_path);
        cJSON *ref = read_gzip_json(ref_path);
        sinew_model *m = load_or_fail(path);
        outcome o = compare_with_reference(m, ref);
        bool ok = o.nodes <= SAME_POSE && o.verts <= SAME_POSE && o.missing == 0 && o.compared > 0;
        print_message("%-50s nodes %.2e verts %.2e of the diagonal (%u node positions, %u missing)%s\n", files[i],
                      o.nodes, o.verts, o.compared, o.missing, ok ? "" : "  <-- over 1e-5");
        failed |= !ok;
        sinew_model_free(m);
        cJSON_Delete(ref);
    }
    if (failed)
        fail_msg("some FBX files do not pose as ufbx does (see above)");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fbx_against_ufbx),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
