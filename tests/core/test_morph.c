/* Morph targets, in-between shapes, vertex caches and mixed skinning in the runtime
 * (sinew/morph.h, sinew/anim.h): the SIMD morph against its scalar reference on a big mesh,
 * the in-between rule at hand-computed weights, caches between and beyond their frames,
 * mixed linear/DQ skinning against the two methods it mixes, and bad spans refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"

/* A deterministic number in [-1, 1). */
static float noise(uint32_t *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (float)(*state >> 8) / (float)(1u << 23) - 1.0f;
}

typedef struct big_mesh {
    sinew_mesh mesh;
    sinew_morph_target *targets;
    float *positions, *normals, *tangents;
    uint32_t *vertices;
    float *offsets;
} big_mesh;

/* n vertices, t targets: even targets dense (every vertex), odd ones sparse (every third vertex,
 * with runs and gaps), all with normal offsets, one in three with tangent offsets. */
static big_mesh make_big_mesh(uint32_t n, uint32_t t)
{
    big_mesh b = {0};
    uint32_t seed = 7;
    b.positions = malloc((size_t)n * 3 * sizeof(float));
    b.normals = malloc((size_t)n * 3 * sizeof(float));
    b.tangents = malloc((size_t)n * 4 * sizeof(float));
    b.targets = calloc(t, sizeof *b.targets);
    b.vertices = malloc((size_t)n * t * sizeof *b.vertices);
    b.offsets = malloc((size_t)n * t * 9 * sizeof *b.offsets);
    assert_non_null(b.positions && b.normals && b.tangents && b.targets && b.vertices && b.offsets);
    for (uint32_t v = 0; v < n; v++) {
        for (int c = 0; c < 3; c++)
            b.positions[v * 3 + c] = noise(&seed);
        float nn[3] = {noise(&seed), noise(&seed), 1.0f}, len = sqrtf(nn[0] * nn[0] + nn[1] * nn[1] + 1.0f);
        for (int c = 0; c < 3; c++)
            b.normals[v * 3 + c] = nn[c] / len;
        b.tangents[v * 4] = 1.0f, b.tangents[v * 4 + 1] = 0.0f, b.tangents[v * 4 + 2] = 0.0f;
        b.tangents[v * 4 + 3] = v % 2 ? 1.0f : -1.0f;
    }
    for (uint32_t k = 0; k < t; k++) {
        sinew_morph_target *tg = &b.targets[k];
        uint32_t *vs = b.vertices + (size_t)k * n;
        float *o = b.offsets + (size_t)k * n * 9;
        uint32_t count = 0;
        for (uint32_t v = 0; v < n; v++)
            if (k % 2 == 0 || v % 3 != 1)
                vs[count++] = v;
        for (uint32_t i = 0; i < count * 9; i++)
            o[i] = 0.1f * noise(&seed);
        *tg = (sinew_morph_target){.name = "t",
                                   .channel = k,
                                   .full_weight = 1.0f,
                                   .delta_count = count,
                                   .vertices = vs,
                                   .positions = o,
                                   .normals = o + (size_t)count * 3,
                                   .tangents = k % 3 == 0 ? o + (size_t)count * 6 : NULL};
    }
    b.mesh = (sinew_mesh){.name = "big",
                          .vertex_count = n,
                          .positions = b.positions,
                          .normals = b.normals,
                          .tangents = b.tangents,
                          .skin = -1,
                          .material = -1,
                          .target_count = t,
                          .targets = b.targets,
                          .morph_channel_count = t};
    return b;
}

static void free_big_mesh(big_mesh *b)
{
    free(b->positions);
    free(b->normals);
    free(b->tangents);
    free(b->targets);
    free(b->vertices);
    free(b->offsets);
}

/* 50,000 vertices, 50 targets, 5 of them with weight: the SIMD path within 1e-6 of the scalar
 * reference, positions, normals and tangents; two ranges give what the whole does; the scalar
 * reference equals a plain sum. */
static void test_simd_equals_scalar(void **state)
{
    (void)state;
    const uint32_t n = 50000, t = 50;
    big_mesh b = make_big_mesh(n, t);
    float weights[50] = {0};
    weights[0] = 0.7f, weights[3] = -0.4f, weights[10] = 1.3f, weights[27] = 0.05f, weights[49] = 0.5f;
    float *p[3], *nrm[3], *tan[3];
    for (int i = 0; i < 3; i++) {
        p[i] = malloc((size_t)n * 3 * sizeof(float));
        nrm[i] = malloc((size_t)n * 3 * sizeof(float));
        tan[i] = malloc((size_t)n * 4 * sizeof(float));
    }
    sinew_morph_desc d = {.mesh = &b.mesh, .target_weights = weights};
    d.out_positions = p[0], d.out_normals = nrm[0], d.out_tangents = tan[0];
    assert_int_equal(sinew_morph_vertices_scalar(&d, NULL), SINEW_OK);
    d.out_positions = p[1], d.out_normals = nrm[1], d.out_tangents = tan[1];
    assert_int_equal(sinew_morph_vertices(&d, NULL), SINEW_OK);
    /* in two ranges, as two threads would */
    d.out_positions = p[2], d.out_normals = nrm[2], d.out_tangents = tan[2];
    d.first = 0, d.count = 20011;
    assert_int_equal(sinew_morph_vertices(&d, NULL), SINEW_OK);
    d.first = 20011, d.count = 0;
    assert_int_equal(sinew_morph_vertices(&d, NULL), SINEW_OK);
    assert_true(floats_difference(p[0], p[1], (size_t)n * 3) < 1e-6);
    assert_true(floats_difference(nrm[0], nrm[1], (size_t)n * 3) < 1e-6);
    assert_true(floats_difference(tan[0], tan[1], (size_t)n * 4) < 1e-6);
    assert_true(floats_difference(p[1], p[2], (size_t)n * 3) == 0.0);
    /* the reference is the plain weighted sum */
    double worst = 0.0;
    for (uint32_t v = 0; v < n; v += 997) {
        double sum[3] = {b.positions[v * 3], b.positions[v * 3 + 1], b.positions[v * 3 + 2]};
        for (uint32_t k = 0; k < t; k++)
            for (uint32_t i = 0; i < b.targets[k].delta_count; i++)
                if (b.targets[k].vertices[i] == v)
                    for (int c = 0; c < 3; c++)
                        sum[c] += weights[k] * b.targets[k].positions[i * 3 + c];
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs(sum[c] - p[0][v * 3 + c]));
    }
    assert_true(worst < 1e-5);
    /* normals come out unit, tangents keep their handedness */
    for (uint32_t v = 0; v < n; v += 101) {
        const float *q = &nrm[1][v * 3];
        assert_true(fabs(sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) - 1.0) < 1e-5);
        assert_true(tan[1][v * 4 + 3] == b.tangents[v * 4 + 3]);
    }
    /* no weights: the base shape */
    d = (sinew_morph_desc){.mesh = &b.mesh, .out_positions = p[1]};
    assert_int_equal(sinew_morph_vertices(&d, NULL), SINEW_OK);
    assert_memory_equal(p[1], b.positions, (size_t)n * 3 * sizeof(float));
    for (int i = 0; i < 3; i++) {
        free(p[i]);
        free(nrm[i]);
        free(tan[i]);
    }
    free_big_mesh(&b);
}

/* One channel with in-between shapes whole at -0.5, 0.5 and 1 (and a second channel of one
 * target): each target's weight as Maya and ufbx give it, from the base shape at 0, between
 * neighbours and beyond the ends. */
static void test_inbetween_weights(void **state)
{
    (void)state;
    static const uint32_t vertex[1] = {0};
    static const float offset[3] = {1, 0, 0};
    sinew_morph_target targets[4] = {
        {.name = "below",
         .channel = 0,
         .full_weight = -0.5f,
         .delta_count = 1,
         .vertices = vertex,
         .positions = offset},
        {.name = "half", .channel = 0, .full_weight = 0.5f, .delta_count = 1, .vertices = vertex, .positions = offset},
        {.name = "whole", .channel = 0, .full_weight = 1.0f, .delta_count = 1, .vertices = vertex, .positions = offset},
        {.name = "other", .channel = 1, .full_weight = 1.0f, .delta_count = 1, .vertices = vertex, .positions = offset},
    };
    sinew_mesh mesh = {.name = "m", .vertex_count = 1, .target_count = 4, .targets = targets, .morph_channel_count = 2};
    static const struct {
        float channel;
        float below, half, whole;
    } cases[] = {
        {0.0f, 0, 0, 0},        /* the base shape */
        {0.25f, 0, 0.5f, 0},    /* half way to "half" */
        {0.5f, 0, 1, 0},        /* "half" whole */
        {0.75f, 0, 0.5f, 0.5f}, /* between "half" and "whole" */
        {1.0f, 0, 0, 1},        /* "whole" */
        {1.5f, 0, -1, 2},       /* beyond: the last two extrapolated */
        {-0.25f, 0.5f, 0, 0},   /* half way to "below" */
        {-1.0f, 2, 0, 0},       /* beyond "below": it and the base shape extrapolated */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        float channels[2] = {cases[i].channel, 0.3f}, w[4];
        assert_int_equal(sinew_morph_target_weights(&mesh, channels, 2, w, 4, NULL), SINEW_OK);
        assert_float_equal(w[0], cases[i].below, 1e-6);
        assert_float_equal(w[1], cases[i].half, 1e-6);
        assert_float_equal(w[2], cases[i].whole, 1e-6);
        assert_float_equal(w[3], 0.3f, 0.0);
    }
    /* without negative shapes, a negative weight extrapolates the first positive one */
    sinew_mesh positive = mesh;
    positive.targets = targets + 1, positive.target_count = 3;
    float channels[2] = {-0.25f, 0.0f}, w[3];
    assert_int_equal(sinew_morph_target_weights(&positive, channels, 2, w, 3, NULL), SINEW_OK);
    assert_float_equal(w[0], -0.5f, 1e-6);
    assert_float_equal(w[1], 0.0f, 1e-6);
    /* spans too short are refused */
    sinew_error error = {0};
    assert_int_equal(sinew_morph_target_weights(&mesh, channels, 1, w, 4, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "2 channels and 4 targets"));
}

/* A cache of three frames: linear between them, the ends outside. */
static void test_cache(void **state)
{
    (void)state;
    static const float times[3] = {1.0f, 2.0f, 4.0f};
    static const float frames[9] = {0, 0, 0, 1, 2, 3, 3, 2, 1}; /* one vertex */
    sinew_vertex_cache cache = {3, times, frames};
    sinew_mesh mesh = {.name = "c", .vertex_count = 1, .cache = &cache};
    static const struct {
        float t, p[3];
    } cases[] = {{0.0f, {0, 0, 0}}, {1.5f, {0.5f, 1, 1.5f}}, {3.0f, {2, 2, 2}}, {9.0f, {3, 2, 1}}, {NAN, {0, 0, 0}}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        float p[3];
        assert_int_equal(sinew_cache_vertices(&mesh, cases[i].t, p, NULL), SINEW_OK);
        for (int c = 0; c < 3; c++)
            assert_float_equal(p[c], cases[i].p[c], 1e-6);
    }
    sinew_error error = {0};
    mesh.cache = NULL;
    float p[3];
    assert_int_equal(sinew_cache_vertices(&mesh, 1.0f, p, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "no vertex cache"));
}

/* Mixed skinning: a vertex of DQ weight 0 skins as linear blend, 1 as dual quaternions, 0.5
 * half way between; the SIMD dispatch gives the reference's results; morphed input arrays
 * replace the mesh's. */
static void test_mixed_skinning(void **state)
{
    (void)state;
    const uint32_t n = 64;
    float *pos = malloc(n * 3 * sizeof(float)), *nrm = malloc(n * 3 * sizeof(float));
    uint16_t *joints = malloc(n * 2 * sizeof(uint16_t));
    float *weights = malloc(n * 2 * sizeof(float)), *dq = malloc(n * sizeof(float));
    uint32_t seed = 3;
    for (uint32_t v = 0; v < n; v++) {
        for (int c = 0; c < 3; c++)
            pos[v * 3 + c] = noise(&seed), nrm[v * 3 + c] = c == 1 ? 1.0f : 0.0f;
        joints[v * 2] = 0, joints[v * 2 + 1] = 1;
        float w = 0.5f + 0.5f * fabsf(noise(&seed));
        weights[v * 2] = w, weights[v * 2 + 1] = 1.0f - w;
        dq[v] = v < 20 ? 0.0f : v < 40 ? 1.0f : 0.5f; /* runs of each kind */
    }
    sinew_mesh mesh = {.name = "m",
                       .vertex_count = n,
                       .positions = pos,
                       .normals = nrm,
                       .influence_count = 2,
                       .joints = joints,
                       .weights = weights,
                       .skin = 0,
                       .dq_weights = dq};
    sinew_transform a = {{0.1f, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}},
                    b = {{0, 0.2f, 0}, {0, 0, 0.7071068f, 0.7071068f}, {1, 1, 1}};
    sinew_mat4 palette[2];
    sinew_transform_to_mat4(&a, &palette[0]);
    sinew_transform_to_mat4(&b, &palette[1]);
    sinew_dq_joint dqp[2];
    assert_int_equal(sinew_skin_dq_palette(palette, 2, dqp, NULL), SINEW_OK);
    float *out[5];
    for (int i = 0; i < 5; i++)
        out[i] = malloc(n * 3 * sizeof(float));
    sinew_skin_desc d = {.mesh = &mesh, .palette = palette, .palette_count = 2, .dq_palette = dqp};
    d.method = SINEW_SKIN_LINEAR, d.out_positions = out[0];
    assert_int_equal(sinew_skin_vertices_scalar(&d, NULL), SINEW_OK);
    d.method = SINEW_SKIN_DUAL_QUATERNION, d.out_positions = out[1];
    assert_int_equal(sinew_skin_vertices_scalar(&d, NULL), SINEW_OK);
    d.method = SINEW_SKIN_MIXED, d.out_positions = out[2];
    assert_int_equal(sinew_skin_vertices_scalar(&d, NULL), SINEW_OK);
    d.out_positions = out[3];
    assert_int_equal(sinew_skin_vertices(&d, NULL), SINEW_OK);
    assert_true(floats_difference(out[2], out[3], n * 3) < 2e-6);
    for (uint32_t v = 0; v < n; v++)
        for (int c = 0; c < 3; c++) {
            float want = dq[v] == 0.0f   ? out[0][v * 3 + c]
                         : dq[v] == 1.0f ? out[1][v * 3 + c]
                                         : 0.5f * (out[0][v * 3 + c] + out[1][v * 3 + c]);
            assert_float_equal(out[2][v * 3 + c], want, 2e-6);
        }
    /* the differences are not trivially zero: the two methods disagree on these vertices */
    assert_true(floats_difference(out[0], out[1], n * 3) > 1e-3);
    /* morphed input in place of the mesh's: every vertex moved by +1 in x moves the output */
    float *moved = malloc(n * 3 * sizeof(float));
    for (uint32_t i = 0; i < n * 3; i++)
        moved[i] = pos[i] + (i % 3 == 0 ? 1.0f : 0.0f);
    d.method = SINEW_SKIN_LINEAR, d.positions = moved, d.out_positions = out[4];
    assert_int_equal(sinew_skin_vertices(&d, NULL), SINEW_OK);
    assert_true(floats_difference(out[0], out[4], n * 3) > 0.5);
    /* MIXED without a DQ palette is refused */
    sinew_error error = {0};
    d.method = SINEW_SKIN_MIXED, d.dq_palette = NULL;
    assert_int_equal(sinew_skin_vertices(&d, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "dq_palette"));
    for (int i = 0; i < 5; i++)
        free(out[i]);
    free(moved);
    free(pos);
    free(nrm);
    free(joints);
    free(weights);
    free(dq);
}

/* Bad spans: NULL mesh or output, a range past the vertices, normals asked of a mesh without. */
static void test_bad_spans(void **state)
{
    (void)state;
    big_mesh b = make_big_mesh(10, 2);
    float out[30];
    sinew_error error = {0};
    assert_int_equal(sinew_morph_vertices(NULL, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(sinew_morph_vertices(&(sinew_morph_desc){.mesh = &b.mesh}, &error), SINEW_ERROR_INVALID_ARGUMENT);
    assert_int_equal(sinew_morph_vertices(
                         &(sinew_morph_desc){.mesh = &b.mesh, .first = 8, .count = 5, .out_positions = out}, &error),
                     SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "past the 10 vertices"));
    b.mesh.normals = NULL;
    assert_int_equal(
        sinew_morph_vertices(&(sinew_morph_desc){.mesh = &b.mesh, .out_positions = out, .out_normals = out}, &error),
        SINEW_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "no normals"));
    free_big_mesh(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_simd_equals_scalar),
        cmocka_unit_test(test_inbetween_weights),
        cmocka_unit_test(test_cache),
        cmocka_unit_test(test_mixed_skinning),
        cmocka_unit_test(test_bad_spans),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
