/* Local -> world, palettes and skinning against hand-computed values. */
#include <math.h>
#include <string.h>

#include "helpers.h"

#define S45 0.70710678f

static void assert_point(const float *p, float x, float y, float z, double tol, const char *what)
{
    assert_near(p[0], x, tol, what);
    assert_near(p[1], y, tol, what);
    assert_near(p[2], z, tol, what);
}

/* A 3-joint chain: a at (1,0,0); b 1 up from a, turned 90 degrees about Z; c 1 along b's x,
 * scaled 2. In world: a (1,0,0); b (1,1,0); c: b's x axis is world +y, so (1,2,0). */
static void test_chain(void **state)
{
    (void)state;
    const char *names[] = {"a", "b", "c"};
    const int32_t parents[] = {-1, 0, 1};
    const sinew_transform rest[] = {
        {{1, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}},
        {{0, 1, 0}, {0, 0, S45, S45}, {1, 1, 1}},
        {{1, 0, 0}, {0, 0, 0, 1}, {2, 2, 2}},
    };
    sinew_model m = {.node_count = 3, .node_names = names, .node_parents = parents, .node_rest = rest};
    sinew_mat4 worlds[3];
    assert_int_equal(sinew_local_to_world(&m, rest, 3, NULL, worlds, 3, NULL), SINEW_OK);
    assert_point(&worlds[0].m[12], 1, 0, 0, 1e-6, "a");
    assert_point(&worlds[1].m[12], 1, 1, 0, 1e-6, "b");
    assert_point(&worlds[2].m[12], 1, 2, 0, 1e-6, "c");
    /* c's x axis: rotated to +y and scaled 2 */
    assert_point(&worlds[2].m[0], 0, 2, 0, 1e-6, "c x axis");
    sinew_transform t;
    sinew_mat4_decompose(&worlds[2], &t);
    assert_point(t.scale, 2, 2, 2, 1e-6, "c scale");
    assert_near(fabsf(t.rotation[2]), S45, 1e-6, "c rotation z");

    /* a root matrix moves everything */
    sinew_mat4 root = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1}};
    assert_int_equal(sinew_local_to_world(&m, rest, 3, &root, worlds, 3, NULL), SINEW_OK);
    assert_point(&worlds[2].m[12], 1, 2, 5, 1e-6, "c under root");

    sinew_error error = {0};
    assert_int_equal(sinew_local_to_world(&m, rest, 3, NULL, worlds, 2, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "3 nodes"));
}

/* root -> {left, right}; right -> tip. */
static void test_branching_tree(void **state)
{
    (void)state;
    const char *names[] = {"root", "left", "right", "tip"};
    const int32_t parents[] = {-1, 0, 0, 2};
    const sinew_transform rest[] = {
        {{0, 1, 0}, {0, 0, 0, 1}, {1, 1, 1}},
        {{-1, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}},
        {{1, 0, 0}, {0, S45, 0, S45}, {1, 1, 1}}, /* 90 degrees about Y: x -> -z */
        {{2, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}},
    };
    sinew_model m = {.node_count = 4, .node_names = names, .node_parents = parents, .node_rest = rest};
    sinew_mat4 worlds[4];
    assert_int_equal(sinew_local_to_world(&m, rest, 4, NULL, worlds, 4, NULL), SINEW_OK);
    assert_point(&worlds[1].m[12], -1, 1, 0, 1e-6, "left");
    assert_point(&worlds[2].m[12], 1, 1, 0, 1e-6, "right");
    assert_point(&worlds[3].m[12], 1, 1, -2, 1e-6, "tip");
}

static void test_decompose_mirrored(void **state)
{
    (void)state;
    sinew_transform in = {{1, 2, 3}, {0, 0, S45, S45}, {-2, 3, 4}}, out;
    sinew_mat4 m, back;
    sinew_transform_to_mat4(&in, &m);
    sinew_mat4_decompose(&m, &out);
    sinew_transform_to_mat4(&out, &back);
    for (int i = 0; i < 16; i++)
        assert_near(back.m[i], m.m[i], 1e-5, "mirrored matrix round trip");
    assert_true(out.scale[0] < 0);
}

/* A cylinder along +Y, 2 long: joint 0 at the origin, joint 1 at (0,1,0). Vertices at
 * y = 2 follow joint 1 alone, at y = 1 half each, at y = 0 joint 0. Joint 1 turns 90
 * degrees about Z. By hand: (r,2,0) -> (-1,1+r,0); (r,1,0) -> (r/2, 1+r/2, 0); (r,0,0) stays. */
static void test_skin_two_bone_cylinder(void **state)
{
    (void)state;
    const float r = 0.5f;
    const float positions[] = {r, 0, 0, r, 1, 0, r, 2, 0, -r, 2, 0};
    const float normals[] = {1, 0, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0};
    const uint16_t joints[] = {0, 1, 0, 1, 1, 0, 1, 0};
    const float weights[] = {1, 0, 0.5f, 0.5f, 1, 0, 1, 0};
    sinew_mesh mesh = {.name = "cylinder",
                       .vertex_count = 4,
                       .positions = positions,
                       .normals = normals,
                       .influence_count = 2,
                       .joints = joints,
                       .weights = weights,
                       .skin = 0};
    const char *names[] = {"j0", "j1"};
    const int32_t parents[] = {-1, 0};
    const sinew_transform bind[] = {{{0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}}, {{0, 1, 0}, {0, 0, 0, 1}, {1, 1, 1}}};
    const sinew_transform bent[] = {{{0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}}, {{0, 1, 0}, {0, 0, S45, S45}, {1, 1, 1}}};
    sinew_model m = {.node_count = 2, .node_names = names, .node_parents = parents, .node_rest = bind};

    /* inverse bind matrices: inverse of the bind worlds (pure translations here) */
    sinew_mat4 ibm[2] = {{{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}},
                         {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1}}};
    const uint32_t skin_joints[] = {0, 1};
    sinew_skin skin = {.joint_count = 2, .joints = skin_joints, .inverse_bind = ibm};

    sinew_mat4 worlds[2], palette[2];
    float out_p[12], out_n[12];
    assert_int_equal(sinew_local_to_world(&m, bent, 2, NULL, worlds, 2, NULL), SINEW_OK);
    assert_int_equal(sinew_skin_palette(&skin, worlds, 2, palette, 2, NULL), SINEW_OK);
    sinew_skin_desc desc = {
        .mesh = &mesh, .palette = palette, .palette_count = 2, .out_positions = out_p, .out_normals = out_n};
    assert_int_equal(sinew_skin_vertices(&desc, NULL), SINEW_OK);
    assert_point(&out_p[0], r, 0, 0, 1e-6, "root vertex");
    assert_point(&out_p[3], r / 2, 1 + r / 2, 0, 1e-6, "elbow vertex");
    assert_point(&out_p[6], -1, 1 + r, 0, 1e-6, "tip vertex");
    assert_point(&out_p[9], -1, 1 - r, 0, 1e-6, "tip vertex, far side");
    assert_point(&out_n[0], 1, 0, 0, 1e-6, "root normal");
    /* half of identity and half of a 90 degree turn: the normal turns 45 degrees */
    assert_point(&out_n[3], S45, S45, 0, 1e-6, "elbow normal");
    assert_point(&out_n[6], 0, 1, 0, 1e-6, "tip normal");

    /* at the bind pose, skinning gives the mesh back */
    assert_int_equal(sinew_local_to_world(&m, bind, 2, NULL, worlds, 2, NULL), SINEW_OK);
    assert_int_equal(sinew_skin_palette(&skin, worlds, 2, palette, 2, NULL), SINEW_OK);
    assert_int_equal(sinew_skin_vertices(&desc, NULL), SINEW_OK);
    for (int i = 0; i < 12; i++)
        assert_near(out_p[i], positions[i], 1e-6, "bind pose");

    /* a vertex range skins only that range */
    float marker[12];
    for (int i = 0; i < 12; i++)
        marker[i] = 42;
    desc.out_positions = marker;
    desc.out_normals = NULL;
    desc.first = 1;
    desc.count = 2;
    assert_int_equal(sinew_skin_vertices(&desc, NULL), SINEW_OK);
    assert_near(marker[0], 42, 0, "vertex before the range untouched");
    assert_near(marker[9], 42, 0, "vertex after the range untouched");
    assert_near(marker[4], 1, 1e-6, "vertex in the range skinned");

    sinew_error error = {0};
    desc.count = 4;
    assert_int_equal(sinew_skin_vertices(&desc, &error), SINEW_ERROR_INVALID_ARGUMENT);
    desc.first = 0;
    desc.palette_count = 1;
    assert_int_equal(sinew_skin_vertices(&desc, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "palette"));
}

/* Normals through non-uniform and mirrored scale follow the inverse transpose. */
static void test_skin_normals_non_uniform(void **state)
{
    (void)state;
    const float positions[] = {1, 1, 0, 1, 0, 0};
    const float normals[] = {S45, S45, 0, 1, 0, 0};
    const uint16_t joints[] = {0, 1};
    const float weights[] = {1, 1};
    sinew_mesh mesh = {.name = "m",
                       .vertex_count = 2,
                       .positions = positions,
                       .normals = normals,
                       .influence_count = 1,
                       .joints = joints,
                       .weights = weights,
                       .skin = 0};
    sinew_mat4 palette[2] = {{{2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}},
                             {{-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}};
    float p[6], n[6];
    sinew_skin_desc desc = {
        .mesh = &mesh, .palette = palette, .palette_count = 2, .out_positions = p, .out_normals = n};
    assert_int_equal(sinew_skin_vertices(&desc, NULL), SINEW_OK);
    assert_point(&p[0], 2, 1, 0, 1e-6, "stretched position");
    /* inverse transpose of diag(2,1,1) on (1,1,0): (0.5,1,0), normalised */
    assert_point(&n[0], 0.5f / sqrtf(1.25f), 1 / sqrtf(1.25f), 0, 1e-6, "stretched normal");
    /* a mirror flips the normal with the surface */
    assert_point(&n[3], -1, 0, 0, 1e-6, "mirrored normal");
    /* the rigid path does the same */
    assert_int_equal(sinew_transform_vertices(&mesh, &palette[0], p, n, 0, NULL), SINEW_OK);
    assert_point(&n[0], 0.5f / sqrtf(1.25f), 1 / sqrtf(1.25f), 0, 1e-6, "rigid stretched normal");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_chain),
        cmocka_unit_test(test_branching_tree),
        cmocka_unit_test(test_decompose_mirrored),
        cmocka_unit_test(test_skin_two_bone_cylinder),
        cmocka_unit_test(test_skin_normals_non_uniform),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
