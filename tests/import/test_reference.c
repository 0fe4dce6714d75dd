/* sinew's poses against three.js (../shared/testdata/reference): every COLLADA and glTF file
 * with a reference, node world positions at ten times and skinned vertices (as point sets) at
 * three, relative to the bounding diagonal of the reference's nodes. The FBX files are
 * test_fbx_corpus's. */
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
        sid_names_free(&sids);
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
        cmocka_unit_test(test_collada_gltf_against_threejs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
