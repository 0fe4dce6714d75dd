/* The AVX-512 skinning kernel (src/core/skin_x86.c) on any x86 processor: the file is built
 * into this test against SIMDe's portable AVX-512 (avx512_emulated.h), so that the kernel is
 * checked against the scalar reference where the processor cannot run it (test_runtime checks
 * it natively where it can). Linear blend and dual quaternions, 1-5 and 8 influences, the
 * synthetic mesh's runs of shared joints and its influences dealt out of order, interleaved
 * outputs with tangents and packed positions, ranges that start and end mid-block, and a
 * palette that is not 64-byte aligned (the same bits). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "helpers.h"

void sinew_skin_avx512_emulated(const skin_call *call);

typedef struct case_mesh {
    sinew_model *model;
    sinew_mesh mesh;
    float *tangents;
    uint16_t *mixed_joints;
    float *mixed_weights;
    sinew_mat4 *palette; /* 64-byte aligned */
    sinew_dq_joint *dq;  /* 64-byte aligned */
    uint32_t joints;
} case_mesh;

/* The synthetic character with `influences`, tangents, its influences also dealt out of order
 * (influences_out_of_order), and a palette with a mirrored and a squashed joint. */
static void make_case(uint32_t influences, case_mesh *c)
{
    sinew_synthetic_desc d = {.joints = 64, .vertices = 3000, .influences = influences, .keyed_trs = true};
    assert_int_equal(sinew_synthetic_model(&d, &c->model, NULL), SINEW_OK);
    c->mesh = c->model->meshes[0];
    uint32_t n = c->mesh.vertex_count;
    c->tangents = malloc((size_t)n * 4 * sizeof(float));
    for (uint32_t v = 0; v < n; v++) {
        float a = 0.37f * (float)v;
        float t[4] = {cosf(a), sinf(a), 0.3f, (v & 1) ? -1.0f : 1.0f};
        memcpy(c->tangents + (size_t)v * 4, t, sizeof t);
    }
    influences_out_of_order(&c->mesh, &c->mixed_joints, &c->mixed_weights);
    c->mesh.tangents = c->tangents;
    const sinew_skin *skin = &c->model->skins[0];
    c->joints = skin->joint_count;
    c->palette = aligned_alloc(64, c->joints * sizeof *c->palette);
    c->dq = aligned_alloc(64, c->joints * sizeof *c->dq);
    sinew_mat4 *worlds = pose_worlds(c->model, &c->model->clips[0], 0.37f);
    assert_int_equal(sinew_skin_palette(skin, worlds, c->model->node_count, c->palette, c->joints, NULL), SINEW_OK);
    free(worlds);
    for (int e = 0; e < 3; e++)
        c->palette[3].m[e] = -c->palette[3].m[e];
    for (int e = 4; e < 7; e++)
        c->palette[5].m[e] *= 0.3f;
    assert_int_equal(sinew_skin_dq_palette(c->palette, c->joints, c->dq, NULL), SINEW_OK);
}

static void free_case(case_mesh *c)
{
    free(c->tangents);
    free(c->mixed_joints);
    free(c->mixed_weights);
    free(c->palette);
    free(c->dq);
    sinew_model_free(c->model);
}

/* One call of the emulated kernel against the reference over the same range and outputs:
 * `floats` a vertex at `stride` floats, tangents when stride is 12 (then normals at 3,
 * tangents at 6: the padding at 10 and 11 stays 0). Returns the largest difference. */
static double against_reference(const case_mesh *c, const sinew_mesh *mesh, bool dqs, const float *records,
                                uint32_t first, uint32_t count, uint32_t stride)
{
    size_t n = (size_t)mesh->vertex_count * stride;
    float *got = calloc(n, sizeof(float)), *want = calloc(n, sizeof(float));
    bool full = stride == 12;
    skin_call call = {.mesh = mesh,
                      .records = records,
                      .record_count = c->joints,
                      .dqs = dqs,
                      .first = first,
                      .count = count,
                      .out_p = got,
                      .out_n = full ? got + 3 : NULL,
                      .out_t = full ? got + 6 : NULL,
                      .stride = stride * sizeof(float)};
    sinew_skin_avx512_emulated(&call);
    sinew_skin_desc d = {.mesh = mesh,
                         .palette = c->palette,
                         .palette_count = c->joints,
                         .method = dqs ? SINEW_SKIN_DUAL_QUATERNION : SINEW_SKIN_LINEAR,
                         .dq_palette = c->dq,
                         .first = first,
                         .count = count,
                         .out_positions = want,
                         .out_normals = full ? want + 3 : NULL,
                         .out_tangents = full ? want + 6 : NULL,
                         .out_stride = stride * sizeof(float)};
    assert_int_equal(sinew_skin_vertices_scalar(&d, NULL), SINEW_OK);
    double worst = floats_difference(got, want, n);
    for (size_t v = 0; full && v < mesh->vertex_count; v++)
        assert_true(got[v * 12 + 10] == 0.0f && got[v * 12 + 11] == 0.0f); /* padding untouched */
    assert_true(got[0] == 0.0f && got[n - 1] == 0.0f);                     /* outside the range untouched */
    free(got);
    free(want);
    return worst;
}

static void test_avx512_kernel_matches_scalar(void **state)
{
    (void)state;
    static const uint32_t counts[] = {1, 2, 3, 4, 5, 8};
    for (size_t i = 0; i < sizeof counts / sizeof *counts; i++) {
        case_mesh c = {0};
        make_case(counts[i], &c);
        for (int order = 0; order < 2; order++) {
            sinew_mesh mesh = c.mesh;
            if (order)
                mesh.joints = c.mixed_joints, mesh.weights = c.mixed_weights;
            uint32_t n = mesh.vertex_count;
            for (int dqs = 0; dqs < 2; dqs++) {
                const float *records = dqs ? c.dq[0].real : c.palette[0].m;
                double all = against_reference(&c, &mesh, dqs, records, 7, n - 20, 12);
                double packed = against_reference(&c, &mesh, dqs, records, 16, n - 19, 3);
                print_message("%s, %u influences, %s: emulated AVX-512 vs scalar %.2e (all outputs), %.2e (packed)\n",
                              dqs ? "DQS" : "LBS", counts[i], order ? "mixed" : "in runs", all, packed);
                assert_true(all <= 2e-6 && packed <= 2e-6);
            }
        }
        free_case(&c);
    }
}

/* A palette one float off 64-byte alignment (which skin.c copies to aligned memory before
 * calling the kernel, but a kernel must read either way): the same results as from the aligned
 * one, bit for bit. */
static void test_unaligned_palette_same_bits(void **state)
{
    (void)state;
    case_mesh c = {0};
    make_case(4, &c);
    sinew_mesh mesh = c.mesh;
    mesh.joints = c.mixed_joints, mesh.weights = c.mixed_weights;
    uint32_t n = mesh.vertex_count;
    float *shifted = aligned_alloc(64, (c.joints * 16 + 16) * sizeof(float));
    memcpy(shifted + 1, c.palette, c.joints * sizeof *c.palette);
    float *a = calloc((size_t)n * 6, sizeof(float)), *b = calloc((size_t)n * 6, sizeof(float));
    skin_call call = {.mesh = &mesh,
                      .records = c.palette[0].m,
                      .record_count = c.joints,
                      .first = 0,
                      .count = n,
                      .out_p = a,
                      .out_n = a + 3,
                      .stride = 6 * sizeof(float)};
    sinew_skin_avx512_emulated(&call);
    call.records = shifted + 1, call.out_p = b, call.out_n = b + 3;
    sinew_skin_avx512_emulated(&call);
    assert_memory_equal(a, b, (size_t)n * 6 * sizeof(float));
    free(a);
    free(b);
    free(shifted);
    free_case(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_avx512_kernel_matches_scalar),
        cmocka_unit_test(test_unaligned_palette_same_bits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
