/* sinew/arrays.h: sinew_clip_arrays() equals the calls it stands for (the player's worlds and
 * locals, sinew_player_weights(), sinew_deform_instance() per instance) frame by frame, bit for
 * bit; the rest pose without a clip; loop and clamp; normals alone; bad arguments; every
 * scratch allocation failing in turn gives OUT_OF_MEMORY and leaks nothing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "sinew/arrays.h"
#include "sinew/morph.h"

static sinew_model *tube(void)
{
    sinew_model *m = NULL;
    sinew_error error = {0};
    sinew_synthetic_desc d = {.joints = 12, .vertices = 600, .morph_targets = 4, .morph_animated = 2};
    assert_int_equal(sinew_synthetic_model(&d, &m, &error), SINEW_OK);
    return m;
}

static void test_arrays_equal_the_player(void **state)
{
    (void)state;
    sinew_model *m = tube();
    const sinew_clip *clip = &m->clips[0];
    const float times[] = {0.0f, 0.37f, 1.1f, 2.5f};
    const uint32_t T = 4, N = m->node_count, C = m->morph_channel_count, V = sinew_model_vertex_total(m);
    assert_true(C == 4 && V > 0);
    float *tr = malloc(sizeof(float) * T * N * 3), *ro = malloc(sizeof(float) * T * N * 4);
    float *sc = malloc(sizeof(float) * T * N * 3), *wo = malloc(sizeof(float) * T * N * 16);
    float *we = malloc(sizeof(float) * T * C), *ve = malloc(sizeof(float) * T * V * 3);
    float *no = malloc(sizeof(float) * T * V * 3), *no_only = malloc(sizeof(float) * T * V * 3);
    sinew_error error = {0};
    sinew_clip_arrays_desc d = {.model = m,
                                .clip = clip,
                                .times = times,
                                .time_count = T,
                                .wrap = SINEW_WRAP_LOOP,
                                .translations = tr,
                                .rotations = ro,
                                .scales = sc,
                                .worlds = wo,
                                .weights = we,
                                .vertices = ve,
                                .normals = no};
    assert_int_equal(sinew_clip_arrays(&d, &error), SINEW_OK);
    sinew_clip_arrays_desc only = {
        .model = m, .clip = clip, .times = times, .time_count = T, .wrap = SINEW_WRAP_LOOP, .normals = no_only};
    assert_int_equal(sinew_clip_arrays(&only, &error), SINEW_OK);
    assert_memory_equal(no, no_only, sizeof(float) * T * V * 3);

    /* the same through the calls themselves */
    sinew_clip_layout *layout = NULL;
    assert_int_equal(sinew_clip_layout_create(&(sinew_clip_layout_desc){.model = m, .clip = clip}, &layout, &error),
                     SINEW_OK);
    size_t size = sinew_player_size(layout);
    void *memory = malloc(size);
    sinew_player *player = NULL;
    assert_int_equal(sinew_player_init(memory, size, layout, &player, &error), SINEW_OK);
    sinew_mat4 *worlds = malloc(sizeof *worlds * N);
    sinew_transform *locals = malloc(sizeof *locals * N);
    float *weights = malloc(sizeof(float) * C), *pos = malloc(sizeof(float) * V * 3),
          *nrm = malloc(sizeof(float) * V * 3);
    size_t scratch_size = sinew_deform_scratch_size(m);
    void *scratch = aligned_alloc(16, (scratch_size + 15) / 16 * 16);
    for (uint32_t t = 0; t < T; t++) {
        assert_int_equal(sinew_player_update(player, times[t], SINEW_WRAP_LOOP, NULL, worlds, N, &error), SINEW_OK);
        assert_memory_equal(wo + (size_t)t * N * 16, worlds, sizeof *worlds * N);
        assert_int_equal(sinew_player_sample(player, times[t], SINEW_WRAP_LOOP, locals, N, &error), SINEW_OK);
        for (uint32_t i = 0; i < N; i++) {
            assert_memory_equal(tr + ((size_t)t * N + i) * 3, locals[i].translation, 12);
            assert_memory_equal(ro + ((size_t)t * N + i) * 4, locals[i].rotation, 16);
            assert_memory_equal(sc + ((size_t)t * N + i) * 3, locals[i].scale, 12);
        }
        assert_int_equal(sinew_player_weights(player, times[t], SINEW_WRAP_LOOP, weights, C, &error), SINEW_OK);
        assert_memory_equal(we + (size_t)t * C, weights, sizeof(float) * C);
        size_t at = 0;
        for (uint32_t i = 0; i < m->instance_count; i++) {
            const sinew_mesh *mesh = &m->meshes[m->instances[i].mesh];
            sinew_deform_desc dd = {.model = m,
                                    .instance = i,
                                    .worlds = worlds,
                                    .world_count = N,
                                    .weights = weights,
                                    .weight_count = C,
                                    .cache_time = clip->timeline + sinew_clip_time(clip, times[t], SINEW_WRAP_LOOP),
                                    .scratch = scratch,
                                    .scratch_size = scratch_size,
                                    .out_positions = pos,
                                    .out_normals = nrm};
            assert_int_equal(sinew_deform_instance(&dd, &error), SINEW_OK);
            assert_memory_equal(ve + ((size_t)t * V + at) * 3, pos, sizeof(float) * mesh->vertex_count * 3);
            assert_memory_equal(no + ((size_t)t * V + at) * 3, nrm, sizeof(float) * mesh->vertex_count * 3);
            at += mesh->vertex_count;
        }
    }
    /* loop wraps, clamp holds the end */
    float *a = malloc(sizeof(float) * N * 16), *b = malloc(sizeof(float) * N * 16);
    float t1 = 0.5f, t2 = 0.5f + clip->duration, t3 = clip->duration + 3.0f, t4 = clip->duration;
    sinew_clip_arrays_desc one = {.model = m, .clip = clip, .time_count = 1, .wrap = SINEW_WRAP_LOOP, .worlds = a};
    one.times = &t1;
    assert_int_equal(sinew_clip_arrays(&one, &error), SINEW_OK);
    one.times = &t2;
    one.worlds = b;
    assert_int_equal(sinew_clip_arrays(&one, &error), SINEW_OK);
    for (uint32_t k = 0; k < N * 16; k++)
        assert_float_equal(a[k], b[k], 1e-4);
    one.wrap = SINEW_WRAP_CLAMP;
    one.times = &t3;
    one.worlds = a;
    assert_int_equal(sinew_clip_arrays(&one, &error), SINEW_OK);
    one.times = &t4;
    one.worlds = b;
    assert_int_equal(sinew_clip_arrays(&one, &error), SINEW_OK);
    assert_memory_equal(a, b, sizeof(float) * N * 16);
    free(b);
    free(a);

    free(scratch);
    free(nrm);
    free(pos);
    free(weights);
    free(locals);
    free(worlds);
    free(memory);
    sinew_clip_layout_free(layout);
    free(no_only);
    free(no);
    free(ve);
    free(we);
    free(wo);
    free(sc);
    free(ro);
    free(tr);
    sinew_model_free(m);
}

static void test_rest_pose_without_clip(void **state)
{
    (void)state;
    sinew_model *m = tube();
    float t = 1.0f;
    float *tr = malloc(sizeof(float) * m->node_count * 3), *ro = malloc(sizeof(float) * m->node_count * 4);
    sinew_error error = {0};
    sinew_clip_arrays_desc d = {.model = m, .times = &t, .time_count = 1, .translations = tr, .rotations = ro};
    assert_int_equal(sinew_clip_arrays(&d, &error), SINEW_OK);
    for (uint32_t i = 0; i < m->node_count; i++) {
        for (int k = 0; k < 3; k++)
            assert_float_equal(tr[i * 3 + k], m->node_rest[i].translation[k], 1e-6);
        float dot = 0;
        for (int k = 0; k < 4; k++)
            dot += ro[i * 4 + k] * m->node_rest[i].rotation[k];
        assert_float_equal(fabsf(dot), 1.0f, 1e-5);
    }
    free(ro);
    free(tr);
    sinew_model_free(m);
}

static void test_bad_arguments(void **state)
{
    (void)state;
    sinew_model *m = tube(), *other = tube();
    sinew_error error = {0};
    float nan = NAN, t = 0, out[16 * 64];
    assert_int_equal(sinew_clip_arrays(NULL, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(sinew_clip_arrays(
                         &(sinew_clip_arrays_desc){
                             .model = m, .clip = &other->clips[0], .times = &t, .time_count = 1, .worlds = out},
                         &error),
                     SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "not one of"));
    assert_int_equal(sinew_clip_arrays(&(sinew_clip_arrays_desc){.model = m, .time_count = 2, .worlds = out}, &error),
                     SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(
        sinew_clip_arrays(&(sinew_clip_arrays_desc){.model = m, .times = &nan, .time_count = 1, .worlds = out}, &error),
        SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "not finite"));
    assert_int_equal(sinew_clip_arrays(&(sinew_clip_arrays_desc){.model = m}, &error), SINEW_OK);
    sinew_model_free(other);
    sinew_model_free(m);
}

typedef struct failing {
    int countdown; /* allocations left before one fails */
    int live;
} failing;

static void *failing_alloc(size_t size, void *user)
{
    failing *f = user;
    if (f->countdown-- == 0)
        return NULL;
    f->live++;
    return aligned_alloc(16, (size + 15) / 16 * 16);
}

static void failing_free(void *p, void *user)
{
    failing *f = user;
    f->live--;
    free(p);
}

static void test_allocation_failures(void **state)
{
    (void)state;
    sinew_model *m = tube();
    float t[2] = {0.1f, 0.2f};
    uint32_t V = sinew_model_vertex_total(m);
    float *ve = malloc(sizeof(float) * 2 * V * 3), *no = malloc(sizeof(float) * 2 * V * 3);
    bool succeeded = false;
    for (int k = 0; k < 64 && !succeeded; k++) {
        failing f = {.countdown = k};
        sinew_allocator a = {.alloc = failing_alloc, .free = failing_free, .user = &f};
        sinew_error error = {0};
        sinew_result r = sinew_clip_arrays(
            &(sinew_clip_arrays_desc){
                .model = m, .clip = &m->clips[0], .times = t, .time_count = 2, .allocator = &a, .normals = no},
            &error);
        assert_true(r == SINEW_OK || r == SINEW_ERROR_OUT_OF_MEMORY);
        assert_int_equal(f.live, 0);
        succeeded = r == SINEW_OK;
        (void)ve;
    }
    assert_true(succeeded);
    free(no);
    free(ve);
    sinew_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_arrays_equal_the_player),
        cmocka_unit_test(test_rest_pose_without_clip),
        cmocka_unit_test(test_bad_arguments),
        cmocka_unit_test(test_allocation_failures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
