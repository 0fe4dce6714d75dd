/* The fast paths against their references: sinew_player (AVX2 and scalar) against
 * sinew_sample + sinew_local_to_world, forward and seeking, on generated characters and real
 * files; SIMD skinning against the scalar reference. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "helpers.h"

/* Largest difference of matrix elements, relative to the element where it is over 1 (files
 * in centimetres have translations in the hundreds). */
static double matrix_difference(const sinew_mat4 *a, const sinew_mat4 *b, uint32_t n)
{
    double worst = 0.0;
    for (uint32_t i = 0; i < n; i++)
        for (int e = 0; e < 16; e++)
            worst = fmax(worst, fabs(a[i].m[e] - b[i].m[e]) / fmax(1.0, fabs(b[i].m[e])));
    return worst;
}

/* Plays every clip forward at 60 Hz (looping past the end) and then at scattered times;
 * returns the largest difference from the reference, SIMD and scalar players both. */
static double check_player(const sinew_model *m, double tolerance)
{
    uint32_t n = m->node_count;
    sinew_mat4 *fast = malloc((n + 1) * sizeof *fast), *slow = malloc((n + 1) * sizeof *slow);
    double worst = 0.0, simd_vs_scalar = 0.0;
    for (uint32_t c = 0; c <= m->clip_count; c++) {
        const sinew_clip *clip = c < m->clip_count ? &m->clips[c] : NULL;
        sinew_error error = {0};
        test_player tp;
        void *simd_memory, *scalar_memory;
        sinew_player *first = test_player_open(&tp, m, clip);
        assert_int_equal(sinew_player_update(first, 0.3f, SINEW_WRAP_LOOP, NULL, fast, n, &error), SINEW_OK);
        /* players of one layout share its keys and keep their own pose and cursors */
        sinew_player *simd = test_player_another(&tp, &simd_memory);
        sinew_player *scalar = test_player_another(&tp, &scalar_memory);
        sinew_player_set_simd(scalar, false);
        float duration = clip ? clip->duration : 1.0f;
        for (int i = 0; i < 160; i++) {
            /* forward frames first, then jumps back and forth */
            float t = i < 100 ? (float)i / 60.0f : duration * (float)((i * 7919) % 101) / 100.0f;
            assert_int_equal(sinew_player_update(simd, t, SINEW_WRAP_LOOP, NULL, fast, n, &error), SINEW_OK);
            sinew_transform *locals = malloc((n + 1) * sizeof *locals);
            sinew_sample_desc d = {
                .model = m, .clip = clip, .time = t, .wrap = SINEW_WRAP_LOOP, .locals = locals, .local_count = n};
            assert_int_equal(sinew_sample(&d, &error), SINEW_OK);
            assert_int_equal(sinew_local_to_world(m, locals, n, NULL, slow, n, &error), SINEW_OK);
            free(locals);
            worst = fmax(worst, matrix_difference(fast, slow, n));
            assert_int_equal(sinew_player_update(scalar, t, SINEW_WRAP_LOOP, NULL, slow, n, &error), SINEW_OK);
            simd_vs_scalar = fmax(simd_vs_scalar, matrix_difference(fast, slow, n));
        }
        free(simd_memory);
        free(scalar_memory);
        test_player_close(&tp);
    }
    print_message("%s: player vs reference %.2e, SIMD vs scalar player %.2e\n", m->source, worst, simd_vs_scalar);
    assert_true(worst <= tolerance);
    assert_true(simd_vs_scalar <= 1e-5);
    free(fast);
    free(slow);
    return worst;
}

static void test_player_generated(void **state)
{
    (void)state;
    sinew_synthetic_desc d = {.joints = 64, .vertices = 500, .influences = 4, .keyed_trs = true};
    sinew_model *m = NULL;
    assert_int_equal(sinew_synthetic_model(&d, &m, NULL), SINEW_OK);
    check_player(m, 1e-5);
    sinew_model_free(m);
    d.joints = 13; /* not a multiple of 8 */
    assert_int_equal(sinew_synthetic_model(&d, &m, NULL), SINEW_OK);
    check_player(m, 1e-5);
    sinew_model_free(m);
    assert_int_equal(sinew_demo_humanoid(&m, NULL), SINEW_OK);
    check_player(m, 1e-5);
    sinew_model_free(m);
}

static void test_player_real_files(void **state)
{
    (void)state;
    /* glTF with step and cubic keys (sinew's own), a COLLADA with channels at different
     * times, Blender's glTF robot with 14 clips, a BVH */
    const char *fixtures[] = {"two_bone_cubic.gltf", "two_bone.dae"};
    char path[4096];
    for (size_t i = 0; i < 2; i++) {
        sinew_model *m = load_or_fail(fixture_path(fixtures[i], path, sizeof path));
        check_player(m, 1e-5);
        sinew_model_free(m);
    }
    const char *files[] = {"raylib/robot.glb", "ozz/pab/walk.dae", "assimp/BVH/01_01.bvh"};
    for (size_t i = 0; i < 3; i++) {
        if (!testdata_path(files[i], path, sizeof path))
            continue;
        FILE *f = fopen(path, "rb");
        if (!f) {
            print_message("%s is not in the shared test data; skipped\n", files[i]);
            continue;
        }
        fclose(f);
        sinew_model *m = load_or_fail(path);
        /* tolerance relative to the model's size: nlerp against slerp between keys */
        check_player(m, 1e-5);
        sinew_model_free(m);
    }
}

typedef struct counting {
    int allocations, live;
} counting;

static void *count_alloc(size_t size, void *user)
{
    counting *c = user;
    c->allocations++;
    c->live++;
    return malloc(size);
}

static void count_free(void *ptr, void *user)
{
    counting *c = user;
    c->live--;
    free(ptr);
}

static void test_player_arguments(void **state)
{
    (void)state;
    sinew_model *m = NULL;
    assert_int_equal(sinew_demo_humanoid(&m, NULL), SINEW_OK);
    sinew_clip_layout *layout = NULL;
    sinew_player *p = NULL;
    sinew_error error = {0};
    assert_int_equal(sinew_clip_layout_create(NULL, &layout, &error), SINEW_ERROR_INVALID_ARGUMENT);
    sinew_allocator half = {.alloc = count_alloc};
    sinew_clip_layout_desc desc = {.model = m, .clip = &m->clips[0], .allocator = &half};
    assert_int_equal(sinew_clip_layout_create(&desc, &layout, &error), SINEW_ERROR_INVALID_ARGUMENT);
    /* the layout and its scratch come from the allocator, and all go back to it */
    counting count = {0};
    sinew_allocator allocator = {count_alloc, count_free, &count};
    desc.allocator = &allocator;
    assert_int_equal(sinew_clip_layout_create(&desc, &layout, &error), SINEW_OK);
    assert_int_equal(count.allocations, 2);
    assert_int_equal(count.live, 1);

    /* the state: too little memory is refused; any alignment is taken */
    size_t size = sinew_player_size(layout);
    unsigned char *memory = malloc(size + 3);
    assert_int_equal(sinew_player_init(memory, size - 1, layout, &p, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "sinew_player_size"));
    assert_int_equal(sinew_player_init(memory + 3, size, layout, &p, &error), SINEW_OK);
    sinew_mat4 worlds[4];
    assert_int_equal(sinew_player_update(p, 0.0f, SINEW_WRAP_CLAMP, NULL, worlds, 4, &error),
                     SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "nodes"));
    uint32_t n = m->node_count;
    sinew_mat4 *all = malloc(n * sizeof *all), *again = malloc(n * sizeof *again);
    assert_int_equal(sinew_player_update(p, NAN, SINEW_WRAP_CLAMP, NULL, all, n, &error), SINEW_ERROR_INVALID_ARGUMENT);
    /* init again on the same memory starts over: the same worlds as a fresh player */
    assert_int_equal(sinew_player_update(p, 0.7f, SINEW_WRAP_LOOP, NULL, all, n, &error), SINEW_OK);
    assert_int_equal(sinew_player_init(memory + 3, size, layout, &p, &error), SINEW_OK);
    assert_int_equal(sinew_player_update(p, 0.7f, SINEW_WRAP_LOOP, NULL, again, n, &error), SINEW_OK);
    assert_memory_equal(all, again, n * sizeof *all);
    free(all);
    free(again);
    free(memory);
    sinew_clip_layout_free(layout);
    assert_int_equal(count.live, 0);

    /* a clip that animates a node the model lacks (another model's) is refused */
    sinew_track track = {.node = m->node_count};
    sinew_clip foreign = {.name = "foreign", .duration = 1.0f, .track_count = 1, .tracks = &track};
    desc = (sinew_clip_layout_desc){.model = m, .clip = &foreign};
    assert_int_equal(sinew_clip_layout_create(&desc, &layout, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "foreign"));
    sinew_model_free(m);
}

/* SIMD skinning equals the scalar reference, positions and normals, with strides and
 * ranges; a joint index past the palette is refused. */
static void test_skin_simd_matches_scalar(void **state)
{
    (void)state;
    sinew_synthetic_desc d = {.joints = 64, .vertices = 20000, .influences = 4, .keyed_trs = true};
    for (uint32_t influences = 1; influences <= 8; influences *= 2) {
        d.influences = influences;
        sinew_model *m = NULL;
        assert_int_equal(sinew_synthetic_model(&d, &m, NULL), SINEW_OK);
        const sinew_mesh *mesh = &m->meshes[0];
        const sinew_skin *skin = &m->skins[0];
        sinew_mat4 *worlds = pose_worlds(m, &m->clips[0], 0.37f);
        sinew_mat4 *palette = malloc(skin->joint_count * sizeof *palette);
        assert_int_equal(sinew_skin_palette(skin, worlds, m->node_count, palette, skin->joint_count, NULL), SINEW_OK);
        /* a mirrored joint and a squashed one: normals go through the cofactor */
        palette[3].m[0] = -palette[3].m[0], palette[3].m[1] = -palette[3].m[1], palette[3].m[2] = -palette[3].m[2];
        for (int e = 4; e < 7; e++)
            palette[5].m[e] *= 0.3f;
        size_t n = mesh->vertex_count;
        float *a = calloc(n * 8, sizeof(float)), *b = calloc(n * 8, sizeof(float));
        /* interleaved output: position, normal, 2 floats of padding (stride 32) */
        sinew_skin_desc sd = {.mesh = mesh,
                              .palette = palette,
                              .palette_count = skin->joint_count,
                              .first = 7,
                              .count = (uint32_t)n - 20,
                              .out_positions = a,
                              .out_normals = a + 3,
                              .out_stride = 32};
        assert_int_equal(sinew_skin_vertices(&sd, NULL), SINEW_OK);
        sd.out_positions = b, sd.out_normals = b + 3;
        assert_int_equal(sinew_skin_vertices_scalar(&sd, NULL), SINEW_OK);
        double worst_p = 0.0, worst_n = 0.0;
        for (size_t v = 0; v < n; v++)
            for (int e = 0; e < 3; e++) {
                worst_p = fmax(worst_p, fabs(a[v * 8 + e] - b[v * 8 + e]));
                worst_n = fmax(worst_n, fabs(a[v * 8 + 3 + e] - b[v * 8 + 3 + e]));
                assert_true(a[v * 8 + 6] == 0.0f && a[v * 8 + 7] == 0.0f); /* padding untouched */
            }
        assert_true(a[0] == 0.0f && a[(n - 1) * 8] == 0.0f); /* outside the range untouched */
        print_message("%u influences: SIMD vs scalar skinning %.2e in positions, %.2e in normals\n", influences,
                      worst_p, worst_n);
        assert_true(worst_p <= 2e-6);
        assert_true(worst_n <= 2e-6);
        sd.palette_count = 2;
        sinew_error error = {0};
        assert_int_equal(sinew_skin_vertices(&sd, &error), SINEW_ERROR_INVALID_ARGUMENT);
        assert_non_null(strstr(error.message, "the palette has 2"));
        free(a);
        free(b);
        free(worlds);
        free(palette);
        sinew_model_free(m);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_player_generated),
        cmocka_unit_test(test_player_real_files),
        cmocka_unit_test(test_player_arguments),
        cmocka_unit_test(test_skin_simd_matches_scalar),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
