/* Structure-of-arrays poses and what works on them: conversions both ways, world matrices
 * (equal to sinew_local_to_world()), sinew_blend_soa() (the AVX2 path against the scalar
 * reference, both against sinew_blend(), over random weights, masks and additive layers, on
 * the demo humanoid and CMU's 01_01.bvh). The character that composes them: test_character.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "sinew/blend.h"

typedef struct soa_buffer {
    void *memory;
    sinew_soa_pose pose;
} soa_buffer;

static void soa_open(soa_buffer *b, uint32_t node_count)
{
    size_t size = sinew_soa_pose_size(node_count);
    b->memory = malloc(size);
    assert_non_null(b->memory);
    assert_int_equal(sinew_soa_pose_init(b->memory, size, node_count, &b->pose, NULL), SINEW_OK);
}

static void test_pose_conversions_and_worlds(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    uint32_t n = m->node_count;
    soa_buffer b;
    soa_open(&b, n);
    assert_int_equal(b.pose.stride % 8, 0);
    assert_true(b.pose.stride >= n && ((uintptr_t)b.pose.data & 31) == 0);
    sinew_transform *locals = pose_locals(m, &m->clips[0], 0.37f, SINEW_WRAP_LOOP), *back = malloc(n * sizeof *back);
    assert_int_equal(sinew_soa_pose_from_locals(locals, n, &b.pose, NULL), SINEW_OK);
    assert_int_equal(sinew_soa_pose_to_locals(&b.pose, back, n, NULL), SINEW_OK);
    double round_trip = pose_difference(locals, back, n);
    sinew_mat4 *ref = malloc(n * sizeof *ref), *worlds = malloc(n * sizeof *worlds);
    sinew_mat4 root = {{0, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0, 0, 2, 0.5f, -1, 1}};
    assert_int_equal(sinew_local_to_world(m, locals, n, &root, ref, n, NULL), SINEW_OK);
    assert_int_equal(sinew_soa_pose_worlds(m, &b.pose, &root, worlds, n, NULL), SINEW_OK);
    double world = worlds_difference(ref, worlds, n);
    print_message("SoA pose: round trip %.1e, world matrices vs sinew_local_to_world %.1e\n", round_trip, world);
    assert_true(round_trip < 1e-7 && world < 1e-5);
    sinew_error error = {0};
    assert_int_equal(sinew_soa_pose_worlds(m, &b.pose, NULL, worlds, n - 1, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(sinew_soa_pose_init(b.memory, 16, n, &b.pose, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "sinew_soa_pose_size"));
    free(ref);
    free(worlds);
    free(locals);
    free(back);
    free(b.memory);
    sinew_model_free(m);
}

static float random01(uint32_t *seed)
{
    *seed = *seed * 1664525u + 1013904223u;
    return (float)(*seed >> 8) / 16777216.0f;
}

/* The blend three ways (AVX2 where there is one, scalar, sinew_blend on local transforms)
 * over random weights, masks and additive layers of poses of `clips` at random times. */
static void compare_blends(const sinew_model *m, uint32_t rounds, double *simd_vs_scalar, double *soa_vs_aos)
{
    const uint32_t n = m->node_count, L = 4, A = 2;
    soa_buffer poses[4 + 2], out, out_scalar, rest;
    for (uint32_t i = 0; i < L + A; i++)
        soa_open(&poses[i], n);
    soa_open(&out, n);
    soa_open(&out_scalar, n);
    soa_open(&rest, n);
    assert_int_equal(sinew_soa_pose_from_locals(m->node_rest, n, &rest.pose, NULL), SINEW_OK);
    sinew_transform *locals[4 + 2], *aos = malloc(n * sizeof *aos), *a = malloc(n * sizeof *a),
                                    *b = malloc(n * sizeof *b);
    float *masks[4 + 2];
    uint32_t seed = 12345;
    *simd_vs_scalar = *soa_vs_aos = 0.0;
    for (uint32_t round = 0; round < rounds; round++) {
        sinew_blend_layer aos_layers[4 + 2];
        sinew_blend_soa_layer soa_layers[4 + 2];
        for (uint32_t i = 0; i < L + A; i++) {
            const sinew_clip *clip = &m->clips[(i + round) % m->clip_count];
            locals[i] = pose_locals(m, clip, random01(&seed) * clip->duration, SINEW_WRAP_LOOP);
            if (i >= L) { /* an additive layer: the clip at one time minus itself at another */
                sinew_transform *ref = pose_locals(m, clip, random01(&seed) * clip->duration, SINEW_WRAP_LOOP);
                assert_int_equal(sinew_additive_delta(ref, locals[i], locals[i], n, NULL), SINEW_OK);
                free(ref);
            }
            assert_int_equal(sinew_soa_pose_from_locals(locals[i], n, &poses[i].pose, NULL), SINEW_OK);
            masks[i] = NULL;
            if (round % 3 != 0) {
                masks[i] = malloc(n * sizeof(float));
                for (uint32_t j = 0; j < n; j++) /* some outside [0, 1] (clamped) and a NaN (0) */
                    masks[i][j] = j == 3 ? NAN : random01(&seed) * 1.4f - 0.2f;
            }
            /* some weights 0, some small enough that the rest pose fills in */
            float w = round % 4 == 1 ? random01(&seed) * 0.03f : random01(&seed) < 0.2f ? 0.0f : random01(&seed);
            aos_layers[i] = (sinew_blend_layer){locals[i], w, masks[i]};
            soa_layers[i] = (sinew_blend_soa_layer){&poses[i].pose, w, masks[i]};
        }
        sinew_blend_desc d = {.model = m,
                              .layers = aos_layers,
                              .layer_count = L,
                              .additive = aos_layers + L,
                              .additive_count = A,
                              .out = aos,
                              .out_count = n};
        sinew_blend_soa_desc s = {.model = m,
                                  .rest = round % 2 ? &rest.pose : NULL,
                                  .layers = soa_layers,
                                  .layer_count = L,
                                  .additive = soa_layers + L,
                                  .additive_count = A,
                                  .out = &out.pose};
        assert_int_equal(sinew_blend(&d, NULL), SINEW_OK);
        assert_int_equal(sinew_blend_soa(&s, NULL), SINEW_OK);
        s.out = &out_scalar.pose;
        assert_int_equal(sinew_blend_soa_scalar(&s, NULL), SINEW_OK);
        assert_int_equal(sinew_soa_pose_to_locals(&out.pose, a, n, NULL), SINEW_OK);
        assert_int_equal(sinew_soa_pose_to_locals(&out_scalar.pose, b, n, NULL), SINEW_OK);
        *simd_vs_scalar = fmax(*simd_vs_scalar, pose_difference(a, b, n));
        *soa_vs_aos = fmax(*soa_vs_aos, pose_difference(b, aos, n));
        for (uint32_t i = 0; i < L + A; i++) {
            free(locals[i]);
            free(masks[i]);
        }
    }
    for (uint32_t i = 0; i < L + A; i++)
        free(poses[i].memory);
    free(out.memory);
    free(out_scalar.memory);
    free(rest.memory);
    free(aos);
    free(a);
    free(b);
}

static void test_blend_soa_matches(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    double simd, aos;
    compare_blends(m, 200, &simd, &aos);
    print_message("SoA blend on the demo (%u nodes, 4 layers + 2 additive, 200 random rounds, %s): SIMD vs scalar "
                  "%.1e, scalar vs sinew_blend %.1e\n",
                  m->node_count, sinew_simd_name(), simd, aos);
    assert_true(simd < 1e-6 && aos < 1e-6);
    sinew_model_free(m);
    char path[4096];
    if (!testdata_path("assimp/BVH/01_01.bvh", path, sizeof path))
        return;
    m = load_or_fail(path);
    compare_blends(m, 50, &simd, &aos);
    print_message("SoA blend on 01_01.bvh (%u nodes): SIMD vs scalar %.1e, scalar vs sinew_blend %.1e\n", m->node_count,
                  simd, aos);
    assert_true(simd < 1e-6 && aos < 1e-6);
    sinew_model_free(m);
}

static void test_blend_soa_aliasing_and_errors(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    uint32_t n = m->node_count;
    soa_buffer walk, other;
    soa_open(&walk, n);
    soa_open(&other, n);
    sinew_transform *locals = pose_locals(m, &m->clips[0], 0.6f, SINEW_WRAP_LOOP), *back = malloc(n * sizeof *back);
    assert_int_equal(sinew_soa_pose_from_locals(locals, n, &walk.pose, NULL), SINEW_OK);
    /* a pose with itself at 0.5 each, written over itself */
    sinew_blend_soa_layer layers[2] = {{&walk.pose, 0.5f, NULL}, {&walk.pose, 0.5f, NULL}};
    sinew_blend_soa_desc d = {.model = m, .layers = layers, .layer_count = 2, .out = &walk.pose};
    assert_int_equal(sinew_blend_soa(&d, NULL), SINEW_OK);
    assert_int_equal(sinew_soa_pose_to_locals(&walk.pose, back, n, NULL), SINEW_OK);
    double itself = pose_difference(locals, back, n);
    /* no layers: the rest pose */
    d.layer_count = 0;
    d.out = &other.pose;
    assert_int_equal(sinew_blend_soa(&d, NULL), SINEW_OK);
    assert_int_equal(sinew_soa_pose_to_locals(&other.pose, back, n, NULL), SINEW_OK);
    double rest = pose_difference(m->node_rest, back, n);
    print_message("SoA blend: a pose with itself, in place %.1e; no layer vs rest %.1e\n", itself, rest);
    assert_true(itself < 1e-6 && rest < 1e-6);
    sinew_error error = {0};
    d.layer_count = 2;
    layers[1].weight = NAN;
    assert_int_equal(sinew_blend_soa(&d, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "not finite"));
    layers[1].weight = 1.0f;
    d.layer_count = SINEW_BLEND_SOA_MAX_LAYERS + 1;
    assert_int_equal(sinew_blend_soa(&d, &error), SINEW_ERROR_INVALID_ARGUMENT);
    d.layer_count = 2;
    sinew_soa_pose small = {other.pose.data, n - 1, (n - 1 + 7) & ~7u};
    layers[1].pose = &small;
    assert_int_equal(sinew_blend_soa(&d, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "nodes"));
    free(locals);
    free(back);
    free(walk.memory);
    free(other.memory);
    sinew_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pose_conversions_and_worlds),
        cmocka_unit_test(test_blend_soa_matches),
        cmocka_unit_test(test_blend_soa_aliasing_and_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
