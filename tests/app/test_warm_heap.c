/* app_warm_heap(): the CLI's heap made ready before an import. Paths that are missing, folders,
 * small files and formats read by Assimp are left alone; a warmed import gives the same model. */
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "scene.h"

static void test_nothing_to_warm(void **state)
{
    (void)state;
    app_warm_heap("/nonexistent/model.fbx");
    app_warm_heap("/tmp");
    app_warm_heap("/tmp/");
    app_warm_heap("no-extension");
    char path[1024];
    if (testdata_path("assimp/BVH/01_01.bvh", path, sizeof path)) /* Assimp's: imported elsewhere */
        app_warm_heap(path);
    void *p = malloc(1 << 20); /* the heap is fine */
    assert_non_null(p);
    memset(p, 1, 1 << 20);
    free(p);
}

static void test_same_model_warmed(void **state)
{
    (void)state;
    const char *names[] = {"raylib/robot.glb", "gltf-samples/Fox.glb", "ozz/pab/arnaud.fbx", "blender/robot_walk.dae"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char path[1024];
        if (!testdata_path(names[i], path, sizeof path))
            continue;
        sinew_model *cold = NULL, *warm = NULL;
        sinew_error error = {0};
        app_scene_desc desc = {.path = path};
        assert_int_equal(app_load_model(&desc, &cold, &error), SINEW_OK);
        desc.import.warm_heap = true;
        assert_int_equal(app_load_model(&desc, &warm, &error), SINEW_OK);
        const void *a, *b;
        size_t na, nb;
        sinew_model_blob(cold, &a, &na);
        sinew_model_blob(warm, &b, &nb);
        assert_int_equal(na, nb);
        assert_memory_equal(a, b, na);
        sinew_model_free(cold);
        sinew_model_free(warm);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nothing_to_warm),
        cmocka_unit_test(test_same_model_warmed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
