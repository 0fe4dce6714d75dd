/* Structure-of-arrays poses and what works on them: conversions both ways, world matrices
 * (equal to sinew_local_to_world()), sinew_blend_soa() (the AVX2 path against the scalar
 * reference, both against sinew_blend(), over random weights, masks and additive layers, on
 * the demo humanoid and CMU's 01_01.bvh), and the mixer (a clip alone is the player, a
 * cross-fade is the blend of the two clips at the mixer's times and weights, weights are
 * smooth and continuous when a fade interrupts another, phase sync keeps normalised times
 * equal, bad calls are refused). */
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

/* ---- the mixer ------------------------------------------------------------------------------- */

typedef struct test_mixer {
    sinew_clip_layout *layouts[3];
    uint32_t count;
    void *memory;
    sinew_mixer *mixer;
} test_mixer;

static sinew_mixer *mixer_open(test_mixer *t, const sinew_model *m, uint32_t count)
{
    memset(t, 0, sizeof *t);
    t->count = count;
    for (uint32_t i = 0; i < count; i++) {
        sinew_clip_layout_desc ld = {.model = m, .clip = i < m->clip_count ? &m->clips[i] : NULL};
        assert_int_equal(sinew_clip_layout_create(&ld, &t->layouts[i], NULL), SINEW_OK);
    }
    sinew_mixer_desc d = {.layouts = (const sinew_clip_layout *const *)t->layouts, .layout_count = count};
    size_t size = sinew_mixer_size(&d);
    assert_true(size > 0);
    t->memory = malloc(size);
    assert_int_equal(sinew_mixer_init(t->memory, size, &d, &t->mixer, NULL), SINEW_OK);
    return t->mixer;
}

static void mixer_close(test_mixer *t)
{
    free(t->memory);
    for (uint32_t i = 0; i < t->count; i++)
        sinew_clip_layout_free(t->layouts[i]);
}

/* World matrices of the AoS blend of the clips at the mixer's times and weights. */
static void expected_worlds(const sinew_model *m, const sinew_mixer *mx, uint32_t count, sinew_mat4 *worlds)
{
    sinew_blend_layer layers[3];
    sinew_transform *locals[3], *out = malloc(m->node_count * sizeof *out);
    uint32_t used = 0;
    for (uint32_t i = 0; i < count; i++) {
        locals[i] = pose_locals(m, &m->clips[i], sinew_mixer_time(mx, i), SINEW_WRAP_LOOP);
        if (sinew_mixer_weight(mx, i) > 0.0f)
            layers[used++] = (sinew_blend_layer){locals[i], sinew_mixer_weight(mx, i), NULL};
    }
    sinew_blend_desc d = {
        .model = m, .layers = layers, .layer_count = used, .threshold = 1e-6f, .out = out, .out_count = m->node_count};
    assert_int_equal(sinew_blend(&d, NULL), SINEW_OK);
    assert_int_equal(sinew_local_to_world(m, out, m->node_count, NULL, worlds, m->node_count, NULL), SINEW_OK);
    for (uint32_t i = 0; i < count; i++)
        free(locals[i]);
    free(out);
}

static void test_mixer_plays_and_fades(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid();
    const uint32_t n = m->node_count;
    test_mixer t;
    sinew_mixer *mx = mixer_open(&t, m, 2);
    sinew_mat4 *worlds = malloc(n * sizeof *worlds), *expect = malloc(n * sizeof *expect);
    /* nothing playing: the rest pose */
    assert_int_equal(sinew_mixer_update(mx, 0.1f, NULL, worlds, n, NULL), SINEW_OK);
    sinew_mat4 *rest = pose_worlds(m, NULL, 0.0f);
    double at_rest = worlds_difference(worlds, rest, n);
    free(rest);
    /* the walk alone is the walk's player */
    assert_int_equal(sinew_mixer_play(mx, 0, 0.0f, false, NULL), SINEW_OK);
    double alone = 0.0, clock = 0.0;
    for (int f = 0; f < 40; f++) {
        float dt = f == 0 ? 0.0f : 1.0f / 30.0f;
        clock += dt;
        assert_int_equal(sinew_mixer_update(mx, dt, NULL, worlds, n, NULL), SINEW_OK);
        sinew_mat4 *ref = pose_worlds(m, &m->clips[0], (float)fmod(clock, m->clips[0].duration));
        alone = fmax(alone, worlds_difference(worlds, ref, n));
        free(ref);
    }
    /* into the wave over 0.5 s: each frame the blend of both at the mixer's times and weights */
    assert_int_equal(sinew_mixer_play(mx, 1, 0.5f, false, NULL), SINEW_OK);
    assert_float_equal(sinew_mixer_time(mx, 1), 0.0f, 0.0f);
    double fading = 0.0, sum = 0.0, step = 0.0;
    float last = 0.0f;
    for (int f = 0; f < 24; f++) {
        assert_int_equal(sinew_mixer_update(mx, 1.0f / 30.0f, NULL, worlds, n, NULL), SINEW_OK);
        expected_worlds(m, mx, 2, expect);
        fading = fmax(fading, worlds_difference(worlds, expect, n));
        float w = sinew_mixer_weight(mx, 1);
        sum = fmax(sum, fabs(w + sinew_mixer_weight(mx, 0) - 1.0));
        step = fmax(step, fabs(w - last));
        assert_true(w >= last);
        last = w;
    }
    assert_float_equal(sinew_mixer_weight(mx, 0), 0.0f, 0.0f);
    assert_float_equal(sinew_mixer_weight(mx, 1), 1.0f, 0.0f);
    /* back to the walk, interrupted half-way by the wave again: no jump in the weights */
    assert_int_equal(sinew_mixer_play(mx, 0, 0.4f, false, NULL), SINEW_OK);
    for (int f = 0; f < 6; f++)
        assert_int_equal(sinew_mixer_update(mx, 1.0f / 30.0f, NULL, worlds, n, NULL), SINEW_OK);
    float before = sinew_mixer_weight(mx, 1);
    assert_int_equal(sinew_mixer_play(mx, 1, 0.4f, false, NULL), SINEW_OK);
    float after = sinew_mixer_weight(mx, 1);
    assert_int_equal(sinew_mixer_update(mx, 1.0f / 30.0f, NULL, worlds, n, NULL), SINEW_OK);
    expected_worlds(m, mx, 2, expect);
    double interrupted = worlds_difference(worlds, expect, n);
    print_message("mixer: nothing playing vs rest %.1e; the walk alone vs its player %.1e; fading into the wave vs "
                  "the blend at its times and weights %.1e (weights sum to 1 within %.1e, largest step a frame "
                  "%.3f); interrupted fade: the wave's weight %.4f before, %.4f after, pose %.1e\n",
                  at_rest, alone, fading, sum, step, before, after, interrupted);
    assert_true(at_rest < 1e-6 && alone < 1e-5 && fading < 1e-5 && interrupted < 1e-5);
    assert_true(sum < 1e-6 && step < 0.11);
    assert_float_equal(before, after, 0.0f);
    free(worlds);
    free(expect);
    mixer_close(&t);
    sinew_model_free(m);
}

static void test_mixer_sync_and_errors(void **state)
{
    (void)state;
    sinew_model *m = demo_humanoid(); /* walk 1 s, wave 2 s */
    const uint32_t n = m->node_count;
    test_mixer t;
    sinew_mixer *mx = mixer_open(&t, m, 2);
    sinew_mat4 *worlds = malloc(n * sizeof *worlds), *expect = malloc(n * sizeof *expect);
    assert_int_equal(sinew_mixer_play(mx, 0, 0.0f, false, NULL), SINEW_OK);
    for (int f = 0; f < 10; f++)
        assert_int_equal(sinew_mixer_update(mx, 0.03f, NULL, worlds, n, NULL), SINEW_OK);
    float phase0 = sinew_mixer_time(mx, 0) / m->clips[0].duration;
    assert_int_equal(sinew_mixer_play(mx, 1, 1.0f, true, NULL), SINEW_OK);
    double apart = fabs(sinew_mixer_time(mx, 1) / m->clips[1].duration - phase0), pose = 0.0;
    float mid_rate = 0.0f;
    for (int f = 0; f < 60; f++) {
        float p0 = sinew_mixer_time(mx, 1) / m->clips[1].duration;
        assert_int_equal(sinew_mixer_update(mx, 0.025f, NULL, worlds, n, NULL), SINEW_OK);
        if (sinew_mixer_weight(mx, 0) > 0.0f) {
            double a = sinew_mixer_time(mx, 0) / m->clips[0].duration,
                   b = sinew_mixer_time(mx, 1) / m->clips[1].duration;
            apart = fmax(apart, fabs(a - b));
        }
        if (f == 20) /* mid-fade the shared cycle is between 1 s and 2 s long */
            mid_rate = (sinew_mixer_time(mx, 1) / m->clips[1].duration - p0) / 0.025f;
        expected_worlds(m, mx, 2, expect);
        pose = fmax(pose, worlds_difference(worlds, expect, n));
    }
    print_message("mixer with phase sync: normalised times apart by at most %.1e; mid-fade %.2f cycles a second "
                  "(walk 1.00, wave 0.50); pose vs the blend %.1e\n",
                  apart, mid_rate, pose);
    assert_true(apart < 1e-5 && pose < 1e-5);
    assert_true(mid_rate > 0.5f && mid_rate < 1.0f);
    sinew_error error = {0};
    assert_int_equal(sinew_mixer_play(mx, 2, 0.0f, false, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "clip 2 of 2"));
    assert_int_equal(sinew_mixer_play(mx, 0, -1.0f, false, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(sinew_mixer_update(mx, NAN, NULL, worlds, n, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(sinew_mixer_update(mx, 0.1f, NULL, worlds, n - 1, &error), SINEW_ERROR_INVALID_ARGUMENT);
    /* clips of two models do not mix */
    sinew_model *other = demo_humanoid();
    sinew_clip_layout *foreign;
    assert_int_equal(
        sinew_clip_layout_create(&(sinew_clip_layout_desc){.model = other, .clip = &other->clips[0]}, &foreign, NULL),
        SINEW_OK);
    const sinew_clip_layout *mixed[2] = {t.layouts[0], foreign};
    sinew_mixer_desc bad = {.layouts = mixed, .layout_count = 2};
    assert_int_equal(sinew_mixer_size(&bad), 0);
    sinew_mixer *no;
    assert_int_equal(sinew_mixer_init(t.memory, 1u << 20, &bad, &no, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "one model"));
    sinew_clip_layout_free(foreign);
    sinew_model_free(other);
    free(worlds);
    free(expect);
    mixer_close(&t);
    sinew_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pose_conversions_and_worlds),   cmocka_unit_test(test_blend_soa_matches),
        cmocka_unit_test(test_blend_soa_aliasing_and_errors), cmocka_unit_test(test_mixer_plays_and_fades),
        cmocka_unit_test(test_mixer_sync_and_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
