/* CPU linear-blend skinning and rigid transforms of vertices.
 *
 * skin_range_scalar() is the reference; skin_range_avx2() does the same arithmetic a vertex
 * at a time in SIMD registers (the blended matrix's four columns in two 8-float registers,
 * the cofactor normal transform with shuffles, rsqrt plus a Newton step for the length),
 * chosen when the processor has AVX2 and FMA. tests/core/test_skin_simd.c holds the two
 * within 2e-6 of each other. */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "sinew/anim.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define SKIN_X86 1
#endif

/* Normal transform for a 3x3 part given as columns c0, c1, c2: the cofactor matrix,
 * which is det * inverse-transpose; its sign is fixed by det so mirrored matrices keep
 * normals outward. The caller renormalises. */
static void transform_normal(const float *m, const float *n, float *out)
{
    const float *c0 = &m[0], *c1 = &m[4], *c2 = &m[8];
    float k0[3] = {c1[1] * c2[2] - c1[2] * c2[1], c1[2] * c2[0] - c1[0] * c2[2], c1[0] * c2[1] - c1[1] * c2[0]};
    float k1[3] = {c2[1] * c0[2] - c2[2] * c0[1], c2[2] * c0[0] - c2[0] * c0[2], c2[0] * c0[1] - c2[1] * c0[0]};
    float k2[3] = {c0[1] * c1[2] - c0[2] * c1[1], c0[2] * c1[0] - c0[0] * c1[2], c0[0] * c1[1] - c0[1] * c1[0]};
    float det = c0[0] * k0[0] + c0[1] * k0[1] + c0[2] * k0[2];
    float sign = det < 0.0f ? -1.0f : 1.0f;
    float x = sign * (k0[0] * n[0] + k1[0] * n[1] + k2[0] * n[2]);
    float y = sign * (k0[1] * n[0] + k1[1] * n[1] + k2[1] * n[2]);
    float z = sign * (k0[2] * n[0] + k1[2] * n[1] + k2[2] * n[2]);
    float len = sqrtf(x * x + y * y + z * z);
    float inv = len > 0.0f ? 1.0f / len : 0.0f;
    out[0] = x * inv;
    out[1] = y * inv;
    out[2] = z * inv;
}

static void transform_point(const float *m, const float *p, float *out)
{
    out[0] = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
    out[1] = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
    out[2] = m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14];
}

/* The largest of n joint indices, 8 lanes at a time (a loop the compiler vectorises). */
static uint16_t largest_index(const uint16_t *joints, size_t n)
{
    uint16_t lanes[8] = {0};
    size_t i = 0;
    for (; i + 8 <= n; i += 8)
        for (int l = 0; l < 8; l++)
            lanes[l] = joints[i + l] > lanes[l] ? joints[i + l] : lanes[l];
    uint16_t largest = 0;
    for (int l = 0; l < 8; l++)
        largest = lanes[l] > largest ? lanes[l] : largest;
    for (; i < n; i++)
        largest = joints[i] > largest ? joints[i] : largest;
    return largest;
}

/* Checks a skinning request; fills the vertex range and output stride. */
static sinew_result check_skin(const sinew_skin_desc *desc, uint32_t *count_out, size_t *stride_out, sinew_error *error)
{
    if (!desc || !desc->mesh || !desc->palette || !desc->out_positions)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: NULL mesh, palette or output");
    const sinew_mesh *mesh = desc->mesh;
    if (mesh->influence_count == 0 || (mesh->vertex_count && (!mesh->joints || !mesh->weights)))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: mesh \"%s\" is not skinned",
                          mesh->name);
    if (desc->first > mesh->vertex_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_skin_vertices: first vertex %u past the %u vertices", desc->first, mesh->vertex_count);
    uint32_t count = desc->count ? desc->count : mesh->vertex_count - desc->first;
    if (count > mesh->vertex_count - desc->first)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: range %u+%u past the %u vertices",
                          desc->first, count, mesh->vertex_count);
    size_t stride = desc->out_stride ? desc->out_stride : 3 * sizeof(float);
    if (stride < 3 * sizeof(float))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: stride %zu below 12 bytes",
                          stride);
    /* Every joint index the range uses must be in the palette (the SIMD loop does not
     * check): one pass for the largest, another to name the vertex only when one is out. */
    const uint32_t k = mesh->influence_count;
    const uint16_t *joints = count ? mesh->joints + (size_t)desc->first * k : NULL;
    if (count && largest_index(joints, (size_t)count * k) >= desc->palette_count)
        for (size_t i = 0; i < (size_t)count * k; i++)
            if (joints[i] >= desc->palette_count)
                return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                                  "sinew_skin_vertices: vertex %zu uses joint %u, the palette has %u",
                                  desc->first + i / k, joints[i], desc->palette_count);
    *count_out = count;
    *stride_out = stride;
    return SINEW_OK;
}

static void skin_range_scalar(const sinew_skin_desc *desc, uint32_t count, size_t stride)
{
    const sinew_mesh *mesh = desc->mesh;
    const uint32_t k = mesh->influence_count;
    for (uint32_t v = desc->first; v < desc->first + count; v++) {
        const uint16_t *joints = &mesh->joints[(size_t)v * k];
        const float *weights = &mesh->weights[(size_t)v * k];
        float blended[16] = {0};
        for (uint32_t i = 0; i < k; i++) {
            float w = weights[i];
            if (w == 0.0f)
                break; /* weights are sorted: the rest are zero too */
            const float *m = desc->palette[joints[i]].m;
            for (int e = 0; e < 16; e++)
                blended[e] += w * m[e];
        }
        float *out_p = (float *)((char *)desc->out_positions + (size_t)v * stride);
        transform_point(blended, &mesh->positions[(size_t)v * 3], out_p);
        if (desc->out_normals) {
            float *out_n = (float *)((char *)desc->out_normals + (size_t)v * stride);
            transform_normal(blended, &mesh->normals[(size_t)v * 3], out_n);
        }
    }
}

#ifdef SKIN_X86
#define YZX(v) _mm_shuffle_ps((v), (v), _MM_SHUFFLE(3, 0, 2, 1))

/* a x b given a, b and their yzx rotations. */
__attribute__((target("avx2,fma"))) static inline __m128 cross(__m128 a, __m128 a_yzx, __m128 b, __m128 b_yzx)
{
    __m128 t = _mm_fmsub_ps(a, b_yzx, _mm_mul_ps(a_yzx, b));
    return YZX(t);
}

__attribute__((target("avx2,fma"))) static void skin_range_avx2(const sinew_skin_desc *desc, uint32_t count,
                                                                size_t stride)
{
    const sinew_mesh *mesh = desc->mesh;
    const uint32_t k = mesh->influence_count;
    const float *palette = desc->palette[0].m;
    const __m128 zero = _mm_setzero_ps();
    for (uint32_t v = desc->first; v < desc->first + count; v++) {
        const uint16_t *joints = &mesh->joints[(size_t)v * k];
        const float *weights = &mesh->weights[(size_t)v * k];
        /* columns 0|1 and 2|3 of the blended matrix */
        const float *m = palette + (size_t)joints[0] * 16;
        __m256 w = _mm256_broadcast_ss(&weights[0]);
        __m256 c01 = _mm256_mul_ps(w, _mm256_loadu_ps(m));
        __m256 c23 = _mm256_mul_ps(w, _mm256_loadu_ps(m + 8));
        for (uint32_t i = 1; i < k && weights[i] != 0.0f; i++) {
            m = palette + (size_t)joints[i] * 16;
            w = _mm256_broadcast_ss(&weights[i]);
            c01 = _mm256_fmadd_ps(w, _mm256_loadu_ps(m), c01);
            c23 = _mm256_fmadd_ps(w, _mm256_loadu_ps(m + 8), c23);
        }
        __m128 c0 = _mm256_castps256_ps128(c01), c1 = _mm256_extractf128_ps(c01, 1);
        __m128 c2 = _mm256_castps256_ps128(c23), c3 = _mm256_extractf128_ps(c23, 1);
        const float *p = &mesh->positions[(size_t)v * 3];
        __m128 pos = _mm_fmadd_ps(c2, _mm_broadcast_ss(p + 2),
                                  _mm_fmadd_ps(c1, _mm_broadcast_ss(p + 1), _mm_fmadd_ps(c0, _mm_broadcast_ss(p), c3)));
        float *out_p = (float *)((char *)desc->out_positions + (size_t)v * stride);
        _mm_storel_pi((__m64 *)out_p, pos);
        _mm_store_ss(out_p + 2, _mm_movehl_ps(pos, pos));
        if (!desc->out_normals)
            continue;
        /* cofactor columns k0 = c1 x c2, k1 = c2 x c0, k2 = c0 x c1; n' = sign(det) K n */
        __m128 c0r = YZX(c0), c1r = YZX(c1), c2r = YZX(c2);
        __m128 k0 = cross(c1, c1r, c2, c2r), k1 = cross(c2, c2r, c0, c0r), k2 = cross(c0, c0r, c1, c1r);
        const float *n = &mesh->normals[(size_t)v * 3];
        __m128 nv = _mm_fmadd_ps(k2, _mm_broadcast_ss(n + 2),
                                 _mm_fmadd_ps(k1, _mm_broadcast_ss(n + 1), _mm_mul_ps(k0, _mm_broadcast_ss(n))));
        __m128 det = _mm_dp_ps(c0, k0, 0x7f);
        __m128 len2 = _mm_dp_ps(nv, nv, 0x7f);
        __m128 r = _mm_rsqrt_ps(len2); /* one Newton step: r * (1.5 - 0.5 * len2 * r * r) */
        r = _mm_mul_ps(r, _mm_fnmadd_ps(_mm_mul_ps(_mm_mul_ps(_mm_set1_ps(0.5f), len2), r), r, _mm_set1_ps(1.5f)));
        r = _mm_and_ps(r, _mm_cmpgt_ps(len2, zero));
        r = _mm_xor_ps(r, _mm_and_ps(det, _mm_set1_ps(-0.0f))); /* the sign of det */
        nv = _mm_mul_ps(nv, r);
        float *out_n = (float *)((char *)desc->out_normals + (size_t)v * stride);
        _mm_storel_pi((__m64 *)out_n, nv);
        _mm_store_ss(out_n + 2, _mm_movehl_ps(nv, nv));
    }
}
#endif

sinew_result sinew_skin_vertices_scalar(const sinew_skin_desc *desc, sinew_error *error)
{
    uint32_t count;
    size_t stride;
    sinew_result result = check_skin(desc, &count, &stride, error);
    if (result == SINEW_OK)
        skin_range_scalar(desc, count, stride);
    return result;
}

sinew_result sinew_skin_vertices(const sinew_skin_desc *desc, sinew_error *error)
{
    uint32_t count;
    size_t stride;
    sinew_result result = check_skin(desc, &count, &stride, error);
    if (result != SINEW_OK)
        return result;
#ifdef SKIN_X86
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
        skin_range_avx2(desc, count, stride);
        return SINEW_OK;
    }
#endif
    skin_range_scalar(desc, count, stride);
    return SINEW_OK;
}

sinew_result sinew_transform_vertices(const sinew_mesh *mesh, const sinew_mat4 *matrix, float *out_positions,
                                      float *out_normals, size_t out_stride, sinew_error *error)
{
    if (!mesh || !matrix || !out_positions)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_transform_vertices: NULL argument");
    size_t stride = out_stride ? out_stride : 3 * sizeof(float);
    if (stride < 3 * sizeof(float))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_transform_vertices: stride %zu below 12 bytes",
                          stride);
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        transform_point(matrix->m, &mesh->positions[(size_t)v * 3],
                        (float *)((char *)out_positions + (size_t)v * stride));
        if (out_normals)
            transform_normal(matrix->m, &mesh->normals[(size_t)v * 3],
                             (float *)((char *)out_normals + (size_t)v * stride));
    }
    return SINEW_OK;
}
