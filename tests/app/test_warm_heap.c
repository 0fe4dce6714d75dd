/* app_warm_heap(): the CLI's heap made ready before an import. Paths that are missing, folders,
 * small files and formats read by Assimp are left alone; a warmed import gives the same model. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "helpers.h"
#include "scene.h"

/* With glibc's heap set as the CLI sets it, what is allocated after the warming starts at a 2 MB
 * boundary: the filled-in 2 MB pages, not the 4 KiB pages before them. (First, while the heap
 * has no freed blocks that could serve the request instead.) */
static void test_heap_top_on_a_huge_page(void **state)
{
    (void)state;
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
    char path[1024];
    if (!testdata_path("gltf-samples/Fox.glb", path, sizeof path))
        skip();
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
    app_warm_heap(path);
    unsigned char *p = malloc(64 << 10);
    assert_non_null(p);
    assert_int_equal((uintptr_t)p & (((uintptr_t)2 << 20) - 1), 0);
    free(p);
#else
    skip();
#endif
}

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
        cmocka_unit_test(test_heap_top_on_a_huge_page),
        cmocka_unit_test(test_nothing_to_warm),
        cmocka_unit_test(test_same_model_warmed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
