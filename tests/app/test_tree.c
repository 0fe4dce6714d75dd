/* app_tree_order(): the hierarchy panel's order. Every node once, each after its parent, each
 * subtree contiguous, depths one below the parent's; the demo's Staff (added last, under
 * Hand.R) comes inside Hand.R's subtree, not after the legs. */
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "scene.h"

static void check_order(const sinew_model *m)
{
    uint32_t n = m->node_count;
    uint32_t *order = malloc(sizeof(uint32_t) * n), *depth = malloc(sizeof(uint32_t) * n);
    uint32_t *at = malloc(sizeof(uint32_t) * n);
    assert_int_equal(app_tree_order(m, order, depth), n);
    for (uint32_t i = 0; i < n; i++)
        at[i] = UINT32_MAX;
    for (uint32_t k = 0; k < n; k++) {
        assert_true(order[k] < n);
        assert_int_equal(at[order[k]], UINT32_MAX); /* once */
        at[order[k]] = k;
    }
    for (uint32_t k = 0; k < n; k++) {
        uint32_t node = order[k];
        int32_t p = m->node_parents[node];
        if (p < 0) {
            assert_int_equal(depth[node], 0);
            continue;
        }
        assert_true(at[p] < k);
        assert_int_equal(depth[node], depth[p] + 1);
        /* the row before is the parent or inside the parent's subtree */
        int32_t prev = (int32_t)order[k - 1];
        while (prev >= 0 && prev != p)
            prev = m->node_parents[prev];
        assert_int_equal(prev, p);
    }
    free(at);
    free(depth);
    free(order);
}

static void test_demo_staff_under_its_hand(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    check_order(m);
    int32_t staff = sinew_model_find_node(m, "Staff"), toes = sinew_model_find_node(m, "RightToes");
    assert_true(staff >= 0 && toes >= 0);
    assert_true(staff > toes); /* last in the file's order */
    uint32_t *order = malloc(sizeof(uint32_t) * m->node_count), *depth = malloc(sizeof(uint32_t) * m->node_count);
    app_tree_order(m, order, depth);
    uint32_t k_staff = 0, k_toes = 0;
    for (uint32_t k = 0; k < m->node_count; k++) {
        if (order[k] == (uint32_t)staff)
            k_staff = k;
        if (order[k] == (uint32_t)toes)
            k_toes = k;
    }
    assert_true(k_staff < k_toes); /* the arm's subtree comes before the legs' in the tree */
    free(depth);
    free(order);
    sinew_model_free(m);
}

static void test_shared_models(void **state)
{
    (void)state;
    const char *names[] = {"gltf-samples/RecursiveSkeletons.glb", "raylib/robot.glb", "assimp/BVH/01_01.bvh"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char path[1024];
        if (!testdata_path(names[i], path, sizeof path))
            continue;
        sinew_model *m = NULL;
        sinew_error error = {0};
        assert_int_equal(sinew_import(&(sinew_import_desc){.path = path}, &m, &error), SINEW_OK);
        check_order(m);
        sinew_model_free(m);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_demo_staff_under_its_hand),
        cmocka_unit_test(test_shared_models),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
