/* sinew's poses against three.js (../shared/testdata/reference): every COLLADA, glTF and BVH
 * file with a reference, node world positions at ten times and skinned vertices (as point sets) at
 * three, relative to the bounding diagonal of the reference's nodes. The FBX files are
 * test_fbx_corpus's. */
#define _GNU_SOURCE /* memmem */
#include <dirent.h>
#include <sys/stat.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "import/internal.h"
#include "reference.h"

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

/* Files whose limit is not 1e-5 of the diagonal ("the same pose"), and why. */
static const struct {
    const char *file;
    double limit;
} exceptions[] = {
    /* three.js skins with the file's unnormalised key quaternions (0.707, 0.707: |q|^2 =
     * 0.9997) as they are; sinew normalises them */
    {"assimp/glTF2/simple_skin/simple_skin.gltf", 5e-4},
    /* five influences a vertex; three.js's COLLADA loader keeps the largest four */
    {"collada-cts/skin_long_tube.dae", 4e-5},
};

/* Whether three.js made up a node of this name, one the file does not have: a name the file
 * does not hold at all ("mesh_0", "ENDSITE#2", a node for each primitive of a glTF mesh), or
 * a glTF scene's (three.js makes the scene a node). */
static bool made_up(const char *name, const unsigned char *bytes, size_t size, const cJSON *scenes)
{
    const cJSON *scene;
    cJSON_ArrayForEach(scene, scenes)
    {
        const cJSON *n = cJSON_GetObjectItemCaseSensitive(scene, "name");
        if (cJSON_IsString(n) && strcmp(n->valuestring, name) == 0)
            return true;
    }
    return !*name || !memmem(bytes, size, name, strlen(name));
}

/* The node positions of the reference that are of nodes three.js made up (all frames). */
static uint32_t made_up_positions(const sinew_model *m, const char *path, const cJSON *ref, const sid_names *sids)
{
    size_t size;
    unsigned char *bytes = read_file(path, &size);
    assert_non_null(bytes);
    /* a glTF's JSON (a .glb's first chunk) for its scenes' names */
    cJSON *json = NULL;
    if (size > 20 && memcmp(bytes, "glTF", 4) == 0) {
        uint32_t n =
            (uint32_t)bytes[12] | (uint32_t)bytes[13] << 8 | (uint32_t)bytes[14] << 16 | (uint32_t)bytes[15] << 24;
        json = n <= size - 20 ? cJSON_ParseWithLength((const char *)bytes + 20, n) : NULL;
    } else if (strstr(path, ".gltf")) {
        json = cJSON_ParseWithLength((const char *)bytes, size);
    }
    const cJSON *scenes = cJSON_GetObjectItemCaseSensitive(json, "scenes"), *frame, *node;
    uint32_t count = 0;
    cJSON_ArrayForEach(frame, cJSON_GetObjectItem(ref, "frames"))
        cJSON_ArrayForEach(node, cJSON_GetObjectItem(frame, "nodes")) count +=
        sinew_model_find_node(m, sid_to_name(sids, node->string)) < 0 && made_up(node->string, bytes, size, scenes);
    cJSON_Delete(json);
    free(bytes);
    return count;
}

typedef struct found {
    char (*rel)[512];
    uint32_t count, capacity;
} found;

/* Every COLLADA, glTF and BVH file under testdata/`dir` that has a three.js reference. */
static void find_models(const char *root, const char *dir, found *out)
{
    char path[1280];
    snprintf(path, sizeof path, "%s/%s", root, dir);
    DIR *d = opendir(path);
    for (struct dirent *e; d && (e = readdir(d));) {
        if (e->d_name[0] == '.' || (!*dir && strcmp(e->d_name, "reference") == 0))
            continue;
        char rel[512], ref[512], ref_path[1024];
        snprintf(rel, sizeof rel, "%s%s%s", dir, *dir ? "/" : "", e->d_name);
        size_t n = strlen(rel);
        bool model = n > 5 && (strcasecmp(rel + n - 4, ".dae") == 0 || strcasecmp(rel + n - 4, ".glb") == 0 ||
                               strcasecmp(rel + n - 5, ".gltf") == 0 || strcasecmp(rel + n - 4, ".bvh") == 0);
        if (e->d_type == DT_DIR) {
            find_models(root, rel, out);
        } else if (model) {
            reference_name("threejs", rel, ref, sizeof ref);
            struct stat st;
            snprintf(ref_path, sizeof ref_path, "%s/%s", root, ref);
            if (stat(ref_path, &st) != 0)
                continue; /* no reference (or one kept back) */
            if (out->count == out->capacity) {
                out->capacity = out->capacity ? out->capacity * 2 : 32;
                out->rel = realloc(out->rel, out->capacity * sizeof *out->rel);
                assert_non_null(out->rel);
            }
            snprintf(out->rel[out->count++], sizeof out->rel[0], "%s", rel);
        }
    }
    if (d)
        closedir(d);
}

static int compare_rel(const void *a, const void *b)
{
    return strcmp(a, b);
}

/* Every COLLADA, glTF and BVH file with a three.js reference (found by walking the test
 * data, so that a file added to it is compared too): nodes and vertices within the file's
 * limit of the diagonal. */
static void test_against_threejs(void **state)
{
    (void)state;
    char root[1024], path[1024], rel[512];
    if (!testdata_path("reference/threejs", root, sizeof root) || !testdata_path("", root, sizeof root))
        skip();
    found files = {0};
    find_models(root, "", &files);
    qsort(files.rel, files.count, sizeof *files.rel, compare_rel);
    assert_true(files.count > 0);
    bool failed = false;
    for (uint32_t i = 0; i < files.count; i++) {
        const char *file = files.rel[i];
        double limit = SAME_POSE;
        for (size_t k = 0; k < sizeof exceptions / sizeof exceptions[0]; k++)
            if (strcmp(exceptions[k].file, file) == 0)
                limit = exceptions[k].limit;
        testdata_path(file, path, sizeof path);
        reference_name("threejs", file, rel, sizeof rel);
        char ref_path[1024];
        testdata_path(rel, ref_path, sizeof ref_path);
        cJSON *ref = read_gzip_json(ref_path);
        size_t len = strlen(path);
        sinew_model *m = strcasecmp(path + len - 4, ".dae") == 0 ? load_collada_native(path) : load_or_fail(path);
        sid_names sids = read_sids(path);
        outcome o = compare_with_reference(m, ref, &sids);
        uint32_t made = made_up_positions(m, path, ref, &sids);
        sid_names_free(&sids);
        bool ok = o.nodes <= limit && o.verts <= limit && o.missing <= made;
        print_message("%-50s nodes %.2e verts %.2e of the diagonal (%u node positions, %u missing)%s\n", file, o.nodes,
                      o.verts, o.compared, o.missing, ok ? "" : "  <-- over the limit");
        failed |= !ok;
        sinew_model_free(m);
        cJSON_Delete(ref);
    }
    free(files.rel);
    if (failed)
        fail_msg("some files do not pose as three.js does (see above)");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_against_threejs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
