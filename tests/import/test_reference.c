/* sinew's poses against independent implementations (../shared/testdata/reference): every
 * FBX file against ufbx, node world positions at ten times and skinned vertices (as point
 * sets) at three, relative to the bounding diagonal of the reference's nodes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <cjson/cJSON.h>
#include <libxml/parser.h>
#include <libxml/tree.h>
#include <zlib.h>

#include "helpers.h"
#include "import/internal.h"

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

static int compare_x(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Distance from p to the nearest of n points sorted by x (3 doubles each). */
static double nearest(const double *sorted, uint32_t n, const double p[3])
{
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = (lo + hi) / 2;
        if (sorted[mid * 3] < p[0])
            lo = mid + 1;
        else
            hi = mid;
    }
    double best = INFINITY;
    for (uint32_t i = lo; i < n && sorted[i * 3] - p[0] < best; i++) {
        double dx = sorted[i * 3] - p[0], dy = sorted[i * 3 + 1] - p[1], dz = sorted[i * 3 + 2] - p[2];
        best = fmin(best, sqrt(dx * dx + dy * dy + dz * dz));
    }
    for (uint32_t i = lo; i-- > 0 && p[0] - sorted[i * 3] < best;) {
        double dx = sorted[i * 3] - p[0], dy = sorted[i * 3 + 1] - p[1], dz = sorted[i * 3 + 2] - p[2];
        best = fmin(best, sqrt(dx * dx + dy * dy + dz * dz));
    }
    return best;
}

/* Largest distance from a point of one set to the nearest of the other, both ways. */
static double point_set_distance(const float *ours, uint32_t n_ours, const double *ref, uint32_t n_ref)
{
    double *a = malloc(((size_t)n_ours + 1) * 3 * sizeof *a), *b = malloc(((size_t)n_ref + 1) * 3 * sizeof *b);
    for (size_t i = 0; i < (size_t)n_ours * 3; i++)
        a[i] = ours[i];
    memcpy(b, ref, (size_t)n_ref * 3 * sizeof *b);
    qsort(a, n_ours, 3 * sizeof *a, compare_x);
    qsort(b, n_ref, 3 * sizeof *b, compare_x);
    double worst = 0;
    for (uint32_t i = 0; i < n_ref; i++)
        worst = fmax(worst, nearest(a, n_ours, &b[i * 3]));
    for (uint32_t j = 0; j < n_ours; j++)
        worst = fmax(worst, nearest(b, n_ref, &a[j * 3]));
    free(a);
    free(b);
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

/* three.js's node name for a name (PropertyBinding.sanitizeNodeName): white space as '_',
 * and without '[', ']', '.', ':' and '/'. */
static void threejs_name(const char *name, char *out, size_t size)
{
    size_t n = 0;
    for (const char *c = name; *c && n + 1 < size; c++) {
        if (strchr("[].:/", *c))
            continue;
        out[n++] = (*c == ' ' || *c == '\t' || *c == '\n') ? '_' : *c;
    }
    out[n] = 0;
}

/* The distance from a reference node position to the node it names: its own name, else
 * three.js's sanitised form of a name. When names repeat, three.js tells them apart by a
 * suffix ("Head#2" in the COLLADA references, "FootL_1" for glTF's second "Foot.L") counted
 * in its own loading order, which is not the file's: the nearest of the nodes with that
 * name stands for it. INFINITY: no node of that name. */
static double reference_distance(const sinew_model *m, const sinew_mat4 *w, const char *ref_name, const double p[3])
{
    int32_t exact = sinew_model_find_node(m, ref_name);
    char base[256], san[256];
    snprintf(base, sizeof base, "%s", ref_name);
    char *mark = strrchr(base, '#');
    if (!mark)
        mark = strrchr(base, '_');
    if (mark && mark[1] && strspn(mark + 1, "0123456789") == strlen(mark + 1))
        *mark = 0;
    double best = INFINITY;
    uint32_t same_name = 0;
    for (uint32_t i = 0; i < m->node_count; i++)
        same_name += strcmp(m->node_names[i], ref_name) == 0;
    if (exact >= 0 && same_name == 1)
        return dist3(&w[exact].m[12], p);
    for (uint32_t i = 0; i < m->node_count; i++) {
        threejs_name(m->node_names[i], san, sizeof san);
        if (strcmp(san, base) == 0 || strcmp(san, ref_name) == 0 || strcmp(m->node_names[i], ref_name) == 0)
            best = fmin(best, dist3(&w[i].m[12], p));
    }
    return best;
}

/* three.js names a COLLADA joint by its SID ("Foot_L", "bone0"), sinew by its name ("Foot.L",
 * "joint1"): the file's own <node sid name> pairs, read here with libxml2. */
typedef struct sid_names {
    char (*sid)[128], (*name)[128];
    uint32_t count;
} sid_names;

static void collect_sids(xmlNode *n, sid_names *out)
{
    for (; n; n = n->next) {
        if (n->type != XML_ELEMENT_NODE)
            continue;
        xmlChar *sid = xmlGetProp(n, (const xmlChar *)"sid"), *name = xmlGetProp(n, (const xmlChar *)"name");
        if (!name)
            name = xmlGetProp(n, (const xmlChar *)"id");
        if (strcmp((const char *)n->name, "node") == 0 && sid && name) {
            out->sid = realloc(out->sid, (out->count + 1) * sizeof *out->sid);
            out->name = realloc(out->name, (out->count + 1) * sizeof *out->name);
            snprintf(out->sid[out->count], 128, "%s", (const char *)sid);
            snprintf(out->name[out->count], 128, "%s", (const char *)name);
            out->count++;
        }
        xmlFree(sid);
        xmlFree(name);
        collect_sids(n->children, out);
    }
}

static sid_names read_sids(const char *path)
{
    sid_names s = {0};
    size_t n = strlen(path);
    if (n < 4 || strcasecmp(path + n - 4, ".dae") != 0)
        return s;
    xmlDoc *doc = xmlReadFile(path, NULL, XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
    if (doc)
        collect_sids(xmlDocGetRootElement(doc), &s);
    xmlFreeDoc(doc);
    return s;
}

static const char *sid_to_name(const sid_names *s, const char *ref_name)
{
    for (uint32_t i = 0; i < s->count; i++)
        if (strcmp(s->sid[i], ref_name) == 0)
            return s->name[i];
    return ref_name;
}

typedef struct outcome {
    double nodes, verts; /* largest, relative to the diagonal */
    uint32_t compared, missing;
} outcome;

static outcome compare_with_reference(const sinew_model *m, const cJSON *ref, const sid_names *sids)
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
            double p[3] = {vec_at(node, 0), vec_at(node, 1), vec_at(node, 2)};
            double d = reference_distance(m, w, sid_to_name(sids, node->string), p);
            if (!isfinite(d)) {
                o.missing++;
                continue;
            }
            o.nodes = fmax(o.nodes, d / diag);
            o.compared++;
        }
        const cJSON *verts = cJSON_GetObjectItem(frame, "verts");
        int nv = cJSON_GetArraySize(verts);
        if (nv > 0) {
            double *rv = malloc((size_t)nv * 3 * sizeof *rv);
            const cJSON *v;
            int i = 0;
            cJSON_ArrayForEach(v, verts)
            {
                for (int c = 0; c < 3; c++)
                    rv[i * 3 + c] = vec_at(v, c);
                i++;
            }
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
static void reference_name(const char *source, const char *model, char *out, size_t size)
{
    size_t n = (size_t)snprintf(out, size, "reference/%s/", source);
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
        reference_name("ufbx", files[i], rel, sizeof rel);
        char ref_path[1024];
        testdata_path(rel, ref_path, sizeof ref_path);
        cJSON *ref = read_gzip_json(ref_path);
        sinew_model *m = load_or_fail(path);
        sid_names none = {0};
        outcome o = compare_with_reference(m, ref, &none);
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

/* A COLLADA file through sinew's own reader (src/import/collada.c), which sinew_import does not
 * use by default yet. */
static sinew_model *load_collada_native(const char *path)
{
    size_t size;
    unsigned char *bytes = read_file(path, &size);
    assert_non_null(bytes);
    raw_model raw;
    sinew_error error = {0};
    if (raw_model_from_collada(path, bytes, size, &raw, &error))
        fail_msg("%s", error.message);
    free(bytes);
    void *blob;
    size_t blob_size;
    if (raw_model_build(&raw, &blob, &blob_size, &error))
        fail_msg("%s", error.message);
    raw_model_free(&raw);
    sinew_model *m = NULL;
    if (sinew_model_from_blob(blob, blob_size, path, NULL, &m, &error))
        fail_msg("%s", error.message);
    free(blob);
    return m;
}

/* Every COLLADA and glTF file with a three.js reference: nodes and vertices within each
 * file's limit of the diagonal (1e-5, "the same pose", unless the file says otherwise). */
static void test_collada_gltf_against_threejs(void **state)
{
    (void)state;
    static const struct {
        const char *file;
        double limit;
        uint32_t made_up; /* node positions three.js has and the file has not */
    } files[] = {
        {"assimp/Collada/box_nested_animation.dae", SAME_POSE, 0},
        {"assimp/Collada/duck.dae", SAME_POSE, 0},
        {"assimp/Collada/regr01.dae", SAME_POSE, 0},
        {"assimp/glTF2/simple_skin/quad_skin.glb", SAME_POSE, 0},
        /* three.js skins with the file's unnormalised key quaternions (0.707, 0.707: |q|^2 =
         * 0.9997) as they are; sinew normalises them. Its node is "mesh_0" to three.js. */
        {"assimp/glTF2/simple_skin/simple_skin.gltf", 5e-4, 10},
        {"blender/robot_walk.dae", SAME_POSE, 0},
        {"collada-cts/non_identity.dae", SAME_POSE, 0},
        /* five influences a vertex; three.js's COLLADA loader keeps the largest four */
        {"collada-cts/skin_long_tube.dae", 4e-5, 0},
        {"collada-dae-parser/leg-with-control-bones.dae", SAME_POSE, 0},
        {"ozz/pab/walk.dae", SAME_POSE, 0},
        /* three.js's "Scene" and a node for each primitive of the 4 multi-primitive meshes. */
        {"raylib/robot.glb", SAME_POSE, 100},
    };
    char path[1024], rel[512];
    bool failed = false;
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        if (!testdata_path(files[i].file, path, sizeof path))
            skip();
        reference_name("threejs", files[i].file, rel, sizeof rel);
        char ref_path[1024];
        testdata_path(rel, ref_path, sizeof ref_path);
        cJSON *ref = read_gzip_json(ref_path);
        size_t len = strlen(path);
        sinew_model *m = strcasecmp(path + len - 4, ".dae") == 0 ? load_collada_native(path) : load_or_fail(path);
        sid_names sids = read_sids(path);
        outcome o = compare_with_reference(m, ref, &sids);
        free(sids.sid);
        free(sids.name);
        /* Nodes three.js makes up ("Scene", a mesh per glTF primitive) are not in the file. */
        bool ok = o.nodes <= files[i].limit && o.verts <= files[i].limit && o.missing <= files[i].made_up;
        print_message("%-50s nodes %.2e verts %.2e of the diagonal (%u node positions, %u missing)%s\n", files[i].file,
                      o.nodes, o.verts, o.compared, o.missing, ok ? "" : "  <-- over the limit");
        failed |= !ok;
        sinew_model_free(m);
        cJSON_Delete(ref);
    }
    if (failed)
        fail_msg("some COLLADA/glTF files do not pose as three.js does (see above)");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fbx_against_ufbx),
        cmocka_unit_test(test_collada_gltf_against_threejs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
