/* Structure-of-arrays poses (sinew/anim.h): conversions, world matrices, and the blend of
 * sinew/blend.h on them (sinew_blend_soa).
 *
 * World matrices: local rotation*scale matrices are built 8 nodes at a time into a block on
 * the stack, then each node's world is its parent's times its local one (parents come
 * before children, so a parent's world is ready, in an earlier block or earlier in this
 * one). The player (player.c) computes its worlds with the same code.
 *
 * The blend works on blocks of 8 nodes: each layer's weight (times its mask) multiplies its
 * translation, scale and unit rotation, the rotation taken in the hemisphere of what is
 * summed so far; the rest pose fills weight below the threshold; the sums are divided by
 * the total and the rotation normalised; then each additive layer is applied. The scalar
 * functions are the reference: the AVX2+FMA ones do the same operations in the same order
 * (tests/core/test_blend.c compares them, and both with sinew_blend()).
 */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "sinew/blend.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define SOA_X86 1
#endif

enum { M_00, M_01, M_02, M_10, M_11, M_12, M_20, M_21, M_22, M_COUNT }; /* M_cr: column c, row r */

typedef float local_block[M_COUNT][8];

static uint32_t soa_stride(uint32_t node_count)
{
    return (node_count + 7u) & ~7u;
}

bool sinew_soa_simd_supported(void)
{
#ifdef SOA_X86
    return sinew_cpu_has(SINEW_CPU_AVX2_FMA);
#else
    return false;
#endif
}

/* ---- the pose itself ------------------------------------------------------------------------ */

size_t sinew_soa_pose_size(uint32_t node_count)
{
    return 31 + (size_t)SINEW_SOA_ROWS * soa_stride(node_count) * sizeof(float);
}

void sinew_soa_identity(float *P, uint32_t stride, uint32_t first)
{
    for (uint32_t r = 0; r < SINEW_SOA_ROWS; r++) {
        float v = r == SINEW_SOA_QW || r >= SINEW_SOA_SX ? 1.0f : 0.0f;
        for (uint32_t i = first; i < stride; i++)
            P[r * stride + i] = v;
    }
}

sinew_result sinew_soa_pose_init(void *memory, size_t size, uint32_t node_count, sinew_soa_pose *out,
                                 sinew_error *error)
{
    if (!memory || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_soa_pose_init: NULL memory or output");
    if (size < sinew_soa_pose_size(node_count))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_soa_pose_init: %zu bytes given, %u nodes need %zu (sinew_soa_pose_size())", size,
                          node_count, sinew_soa_pose_size(node_count));
    float *data = (float *)(((uintptr_t)memory + 31) & ~(uintptr_t)31);
    *out = (sinew_soa_pose){data, node_count, soa_stride(node_count)};
    sinew_soa_identity(data, out->stride, 0);
    return SINEW_OK;
}

static sinew_result check_pose(const sinew_soa_pose *pose, const char *what, sinew_error *error)
{
    if (!pose || !pose->data)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s: NULL pose", what);
    if (pose->stride != soa_stride(pose->node_count) || ((uintptr_t)pose->data & 31u))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "%s: a pose of %u nodes with stride %u, or not 32-byte aligned (use sinew_soa_pose_init())",
                          what, pose->node_count, pose->stride);
    return SINEW_OK;
}

/* The checks of a conversion between a pose and `count` local transforms. */
static sinew_result check_locals(const sinew_soa_pose *pose, const sinew_transform *locals, uint32_t count,
                                 const char *what, sinew_error *error)
{
    sinew_result r = check_pose(pose, what, error);
    if (r == SINEW_OK && (count < pose->node_count || (count && !locals)))
        r = sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s: %u transforms for %u nodes", what, locals ? count : 0,
                       pose->node_count);
    return r;
}

sinew_result sinew_soa_pose_from_locals(const sinew_transform *locals, uint32_t count, sinew_soa_pose *pose,
                                        sinew_error *error)
{
    sinew_result r = check_locals(pose, locals, count, "sinew_soa_pose_from_locals", error);
    if (r != SINEW_OK)
        return r;
    const uint32_t S = pose->stride;
    float *P = pose->data;
    for (uint32_t i = 0; i < pose->node_count; i++)
        for (uint32_t k = 0; k < 4; k++) {
            if (k < 3) {
                P[(SINEW_SOA_TX + k) * S + i] = locals[i].translation[k];
                P[(SINEW_SOA_SX + k) * S + i] = locals[i].scale[k];
            }
            P[(SINEW_SOA_QX + k) * S + i] = locals[i].rotation[k];
        }
    sinew_soa_identity(P, S, pose->node_count);
    return SINEW_OK;
}

void sinew_soa_to_locals(const float *P, uint32_t S, uint32_t node_count, sinew_transform *locals)
{
    for (uint32_t i = 0; i < node_count; i++) {
        sinew_transform *o = &locals[i];
        for (int k = 0; k < 3; k++) {
            o->translation[k] = P[(SINEW_SOA_TX + k) * S + i];
            o->scale[k] = P[(SINEW_SOA_SX + k) * S + i];
        }
        float q[4], n = 0.0f;
        for (int k = 0; k < 4; k++)
            q[k] = P[(SINEW_SOA_QX + k) * S + i], n += q[k] * q[k];
        float inv = n > 0.0f ? 1.0f / sqrtf(n) : 0.0f;
        for (int k = 0; k < 4; k++)
            o->rotation[k] = n > 0.0f ? q[k] * inv : (k == 3 ? 1.0f : 0.0f);
    }
}

sinew_result sinew_soa_pose_to_locals(const sinew_soa_pose *pose, sinew_transform *locals, uint32_t count,
                                      sinew_error *error)
{
    sinew_result r = check_locals(pose, locals, count, "sinew_soa_pose_to_locals", error);
    if (r != SINEW_OK)
        return r;
    sinew_soa_to_locals(pose->data, pose->stride, pose->node_count, locals);
    return SINEW_OK;
}

/* ---- world matrices -------------------------------------------------------------------------- */

static void locals_scalar(const float *P, uint32_t S, uint32_t i0, local_block M)
{
    for (uint32_t j = 0; j < 8; j++) {
        uint32_t i = i0 + j;
        float x = P[SINEW_SOA_QX * S + i], y = P[SINEW_SOA_QY * S + i], z = P[SINEW_SOA_QZ * S + i];
        float w = P[SINEW_SOA_QW * S + i];
        float n = x * x + y * y + z * z + w * w;
        float s = n > 0.0f ? 2.0f / n : 0.0f;
        float xx = s * x * x, yy = s * y * y, zz = s * z * z;
        float xy = s * x * y, xz = s * x * z, yz = s * y * z;
        float wx = s * w * x, wy = s * w * y, wz = s * w * z;
        float sx = P[SINEW_SOA_SX * S + i], sy = P[SINEW_SOA_SY * S + i], sz = P[SINEW_SOA_SZ * S + i];
        M[M_00][j] = (1.0f - yy - zz) * sx;
        M[M_01][j] = (xy + wz) * sx;
        M[M_02][j] = (xz - wy) * sx;
        M[M_10][j] = (xy - wz) * sy;
        M[M_11][j] = (1.0f - xx - zz) * sy;
        M[M_12][j] = (yz + wx) * sy;
        M[M_20][j] = (xz + wy) * sz;
        M[M_21][j] = (yz - wx) * sz;
        M[M_22][j] = (1.0f - xx - yy) * sz;
    }
}

static void world_scalar(const float *b, const float l[16], float *o)
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            o[c * 4 + r] =
                b[r] * l[c * 4] + b[4 + r] * l[c * 4 + 1] + b[8 + r] * l[c * 4 + 2] + b[12 + r] * l[c * 4 + 3];
}

#ifdef SOA_X86
__attribute__((target("avx2,fma"))) static void locals_avx2(const float *P, uint32_t S, uint32_t i, local_block M)
{
    const __m256 one = _mm256_set1_ps(1.0f), two = _mm256_set1_ps(2.0f), zero = _mm256_setzero_ps();
    __m256 x = _mm256_load_ps(P + SINEW_SOA_QX * S + i), y = _mm256_load_ps(P + SINEW_SOA_QY * S + i);
    __m256 z = _mm256_load_ps(P + SINEW_SOA_QZ * S + i), w = _mm256_load_ps(P + SINEW_SOA_QW * S + i);
    __m256 n = _mm256_fmadd_ps(x, x, _mm256_fmadd_ps(y, y, _mm256_fmadd_ps(z, z, _mm256_mul_ps(w, w))));
    __m256 s = _mm256_and_ps(_mm256_div_ps(two, n), _mm256_cmp_ps(n, zero, _CMP_GT_OQ));
    __m256 xs = _mm256_mul_ps(x, s), ys = _mm256_mul_ps(y, s), zs = _mm256_mul_ps(z, s);
    __m256 xx = _mm256_mul_ps(xs, x), yy = _mm256_mul_ps(ys, y), zz = _mm256_mul_ps(zs, z);
    __m256 xy = _mm256_mul_ps(xs, y), xz = _mm256_mul_ps(xs, z), yz = _mm256_mul_ps(ys, z);
    __m256 wx = _mm256_mul_ps(xs, w), wy = _mm256_mul_ps(ys, w), wz = _mm256_mul_ps(zs, w);
    __m256 sx = _mm256_load_ps(P + SINEW_SOA_SX * S + i), sy = _mm256_load_ps(P + SINEW_SOA_SY * S + i);
    __m256 sz = _mm256_load_ps(P + SINEW_SOA_SZ * S + i);
    _mm256_storeu_ps(M[M_00], _mm256_mul_ps(_mm256_sub_ps(_mm256_sub_ps(one, yy), zz), sx));
    _mm256_storeu_ps(M[M_01], _mm256_mul_ps(_mm256_add_ps(xy, wz), sx));
    _mm256_storeu_ps(M[M_02], _mm256_mul_ps(_mm256_sub_ps(xz, wy), sx));
    _mm256_storeu_ps(M[M_10], _mm256_mul_ps(_mm256_sub_ps(xy, wz), sy));
    _mm256_storeu_ps(M[M_11], _mm256_mul_ps(_mm256_sub_ps(_mm256_sub_ps(one, xx), zz), sy));
    _mm256_storeu_ps(M[M_12], _mm256_mul_ps(_mm256_add_ps(yz, wx), sy));
    _mm256_storeu_ps(M[M_20], _mm256_mul_ps(_mm256_add_ps(xz, wy), sz));
    _mm256_storeu_ps(M[M_21], _mm256_mul_ps(_mm256_sub_ps(yz, wx), sz));
    _mm256_storeu_ps(M[M_22], _mm256_mul_ps(_mm256_sub_ps(_mm256_sub_ps(one, xx), yy), sz));
}

__attribute__((target("avx2,fma"))) static void world_avx2(const float *b, const float l[16], float *o)
{
    __m128 b0 = _mm_loadu_ps(b), b1 = _mm_loadu_ps(b + 4), b2 = _mm_loadu_ps(b + 8), b3 = _mm_loadu_ps(b + 12);
    for (int c = 0; c < 3; c++)
        _mm_storeu_ps(o + 4 * c, _mm_fmadd_ps(b2, _mm_broadcast_ss(l + 4 * c + 2),
                                              _mm_fmadd_ps(b1, _mm_broadcast_ss(l + 4 * c + 1),
                                                           _mm_mul_ps(b0, _mm_broadcast_ss(l + 4 * c)))));
    _mm_storeu_ps(o + 12, _mm_fmadd_ps(b2, _mm_broadcast_ss(l + 14),
                                       _mm_fmadd_ps(b1, _mm_broadcast_ss(l + 13),
                                                    _mm_fmadd_ps(b0, _mm_broadcast_ss(l + 12), b3))));
}
#endif

void sinew_soa_worlds(const sinew_model *m, const float *P, uint32_t S, const sinew_mat4 *root, sinew_mat4 *worlds,
                      bool simd)
{
    _Alignas(32) local_block M;
    for (uint32_t i0 = 0; i0 < m->node_count; i0 += 8) {
#ifdef SOA_X86
        if (simd)
            locals_avx2(P, S, i0, M);
        else
#endif
            locals_scalar(P, S, i0, M);
        uint32_t end = m->node_count - i0 < 8 ? m->node_count - i0 : 8;
        for (uint32_t j = 0; j < end; j++) {
            uint32_t i = i0 + j;
            int32_t parent = m->node_parents[i];
            if (m->node_inherit && m->node_inherit[i] != SINEW_INHERIT_NORMAL && parent >= 0) {
                float t[3] = {P[SINEW_SOA_TX * S + i], P[SINEW_SOA_TY * S + i], P[SINEW_SOA_TZ * S + i]};
                float q[4] = {P[SINEW_SOA_QX * S + i], P[SINEW_SOA_QY * S + i], P[SINEW_SOA_QZ * S + i],
                              P[SINEW_SOA_QW * S + i]};
                float s[3] = {P[SINEW_SOA_SX * S + i], P[SINEW_SOA_SY * S + i], P[SINEW_SOA_SZ * S + i]};
                sinew_pose_world_inherit(m, i, t, q, s, (pose_scales){P + SINEW_SOA_SX * S, 1, S}, worlds, &worlds[i]);
                continue;
            }
            const float l[16] = {M[M_00][j],
                                 M[M_01][j],
                                 M[M_02][j],
                                 0.0f,
                                 M[M_10][j],
                                 M[M_11][j],
                                 M[M_12][j],
                                 0.0f,
                                 M[M_20][j],
                                 M[M_21][j],
                                 M[M_22][j],
                                 0.0f,
                                 P[SINEW_SOA_TX * S + i],
                                 P[SINEW_SOA_TY * S + i],
                                 P[SINEW_SOA_TZ * S + i],
                                 1.0f};
            const float *b = parent >= 0 ? worlds[parent].m : root ? root->m : NULL;
            if (!b)
                memcpy(worlds[i].m, l, sizeof l);
#ifdef SOA_X86
            else if (simd)
                world_avx2(b, l, worlds[i].m);
#endif
            else
                world_scalar(b, l, worlds[i].m);
        }
    }
}

sinew_result sinew_soa_pose_worlds(const sinew_model *model, const sinew_soa_pose *pose, const sinew_mat4 *root,
                                   sinew_mat4 *worlds, uint32_t world_count, sinew_error *error)
{
    sinew_result r = check_pose(pose, "sinew_soa_pose_worlds", error);
    if (r != SINEW_OK)
        return r;
    if (!model || !worlds || pose->node_count != model->node_count || world_count < model->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_soa_pose_worlds: a pose of %u nodes, %u world matrices, a model of %u nodes",
                          pose->node_count, worlds ? world_count : 0, model ? model->node_count : 0);
    sinew_soa_worlds(model, pose->data, pose->stride, root, worlds, sinew_soa_simd_supported());
    return SINEW_OK;
}

/* ---- the blend ------------------------------------------------------------------------------ */

/* One layer as the kernels see it: its pose's rows and its weight in each of the block's lanes. */
typedef struct block_layer {
    const float *P;
    float w[8];
} block_layer;

static void block_weights(const sinew_blend_soa_layer *layer, uint32_t i0, uint32_t node_count, float w[8])
{
    if (!layer->node_weights && i0 + 8 <= node_count) {
        for (uint32_t j = 0; j < 8; j++)
            w[j] = layer->weight;
        return;
    }
    for (uint32_t j = 0; j < 8; j++) {
        float m = 1.0f;
        if (i0 + j >= node_count)
            m = 0.0f;
        else if (layer->node_weights)
            m = isfinite(layer->node_weights[i0 + j]) ? fminf(fmaxf(layer->node_weights[i0 + j], 0.0f), 1.0f) : 0.0f;
        w[j] = layer->weight * m;
    }
}

/* What the kernels take for one block of 8 nodes starting at i0. */
typedef struct block_job {
    const block_layer *layers;
    uint32_t layer_count;
    const block_layer *additive;
    uint32_t additive_count;
    const float *rest; /* the block's rest pose: SINEW_SOA_ROWS rows, rest_stride floats apart */
    uint32_t rest_stride;
    float threshold;
    float *out;
    uint32_t S, i0;
} block_job;

static void blend_block_scalar(const block_job *b)
{
    const uint32_t S = b->S;
    for (uint32_t j = 0; j < 8; j++) {
        const uint32_t i = b->i0 + j;
        float acc[SINEW_SOA_ROWS] = {0}, total = 0.0f;
        for (uint32_t l = 0; l <= b->layer_count; l++) {
            /* the layers, then the rest pose with what they leave below the threshold */
            const float *P = l < b->layer_count ? b->layers[l].P : b->rest;
            uint32_t stride = l < b->layer_count ? S : b->rest_stride, at = l < b->layer_count ? i : j;
            float w = l < b->layer_count ? b->layers[l].w[j] : fmaxf(b->threshold - total, 0.0f);
            float q[4], n = 0.0f;
            for (int k = 0; k < 4; k++)
                q[k] = P[(SINEW_SOA_QX + k) * stride + at], n += q[k] * q[k];
            float inv = n > 0.0f ? 1.0f / sqrtf(n) : 0.0f;
            float d = acc[SINEW_SOA_QX] * q[0] + acc[SINEW_SOA_QY] * q[1] + acc[SINEW_SOA_QZ] * q[2] +
                      acc[SINEW_SOA_QW] * q[3];
            float wq = d < 0.0f ? -w * inv : w * inv;
            for (int k = 0; k < 3; k++) {
                acc[SINEW_SOA_TX + k] += w * P[(SINEW_SOA_TX + k) * stride + at];
                acc[SINEW_SOA_SX + k] += w * P[(SINEW_SOA_SX + k) * stride + at];
            }
            for (int k = 0; k < 4; k++)
                acc[SINEW_SOA_QX + k] += wq * q[k];
            total += w;
        }
        float inv_total = 1.0f / total;
        float q[4] = {acc[SINEW_SOA_QX], acc[SINEW_SOA_QY], acc[SINEW_SOA_QZ], acc[SINEW_SOA_QW]};
        float n = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
        float inv = n > 0.0f ? 1.0f / sqrtf(n) : 0.0f;
        float t[3], s[3];
        for (int k = 0; k < 3; k++) {
            t[k] = acc[SINEW_SOA_TX + k] * inv_total;
            s[k] = acc[SINEW_SOA_SX + k] * inv_total;
        }
        for (int k = 0; k < 4; k++)
            q[k] *= inv;
        if (!(n > 0.0f))
            q[0] = q[1] = q[2] = 0.0f, q[3] = 1.0f;
        for (uint32_t a = 0; a < b->additive_count; a++) {
            /* out = out * nlerp(identity, delta, w); t += w dt; s *= 1 + w (ds - 1) */
            const float *P = b->additive[a].P, w = b->additive[a].w[j];
            float d[4], dn = 0.0f;
            for (int k = 0; k < 4; k++)
                d[k] = P[(SINEW_SOA_QX + k) * S + i], dn += d[k] * d[k];
            float dinv = dn > 0.0f ? 1.0f / sqrtf(dn) : 0.0f;
            float wd = d[3] < 0.0f ? -w * dinv : w * dinv;
            float p[4] = {wd * d[0], wd * d[1], wd * d[2], wd * d[3] + (1.0f - w)};
            float r[4] = {q[3] * p[0] + q[0] * p[3] + q[1] * p[2] - q[2] * p[1],
                          q[3] * p[1] - q[0] * p[2] + q[1] * p[3] + q[2] * p[0],
                          q[3] * p[2] + q[0] * p[1] - q[1] * p[0] + q[2] * p[3],
                          q[3] * p[3] - q[0] * p[0] - q[1] * p[1] - q[2] * p[2]};
            float rn = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3];
            float rinv = rn > 0.0f ? 1.0f / sqrtf(rn) : 0.0f;
            for (int k = 0; k < 4; k++)
                q[k] = r[k] * rinv;
            for (int k = 0; k < 3; k++) {
                t[k] += w * P[(SINEW_SOA_TX + k) * S + i];
                s[k] *= 1.0f + w * (P[(SINEW_SOA_SX + k) * S + i] - 1.0f);
            }
        }
        for (int k = 0; k < 3; k++) {
            b->out[(SINEW_SOA_TX + k) * S + i] = t[k];
            b->out[(SINEW_SOA_SX + k) * S + i] = s[k];
        }
        for (int k = 0; k < 4; k++)
            b->out[(SINEW_SOA_QX + k) * S + i] = q[k];
    }
}

#ifdef SOA_X86
/* 1 / sqrt(n) where n > 0, else 0 (exact division, as the scalar code). */
__attribute__((target("avx2,fma"))) static __m256 inv_length(__m256 n)
{
    __m256 r = _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(n));
    return _mm256_and_ps(r, _mm256_cmp_ps(n, _mm256_setzero_ps(), _CMP_GT_OQ));
}

__attribute__((target("avx2,fma"))) static __m256 dot4(const __m256 a[4], const __m256 b[4])
{
    /* the scalar code's order: ((a0 b0 + a1 b1) + a2 b2) + a3 b3, without fused steps */
    __m256 d = _mm256_add_ps(_mm256_mul_ps(a[0], b[0]), _mm256_mul_ps(a[1], b[1]));
    d = _mm256_add_ps(d, _mm256_mul_ps(a[2], b[2]));
    return _mm256_add_ps(d, _mm256_mul_ps(a[3], b[3]));
}

__attribute__((target("avx2,fma"))) static void blend_block_avx2(const block_job *b)
{
    const uint32_t S = b->S, i = b->i0;
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f), sign = _mm256_set1_ps(-0.0f);
    __m256 acc[SINEW_SOA_ROWS], total = zero;
    for (int r = 0; r < SINEW_SOA_ROWS; r++)
        acc[r] = zero;
    for (uint32_t l = 0; l <= b->layer_count; l++) {
        const float *P = l < b->layer_count ? b->layers[l].P + i : b->rest;
        uint32_t stride = l < b->layer_count ? S : b->rest_stride;
        __m256 w = l < b->layer_count ? _mm256_loadu_ps(b->layers[l].w)
                                      : _mm256_max_ps(_mm256_sub_ps(_mm256_set1_ps(b->threshold), total), zero);
        __m256 q[4];
        for (int k = 0; k < 4; k++)
            q[k] = _mm256_loadu_ps(P + (SINEW_SOA_QX + k) * stride);
        __m256 inv = inv_length(dot4(q, q));
        __m256 flip = _mm256_and_ps(_mm256_cmp_ps(dot4(acc + SINEW_SOA_QX, q), zero, _CMP_LT_OQ), sign);
        __m256 wq = _mm256_xor_ps(_mm256_mul_ps(w, inv), flip);
        for (int k = 0; k < 3; k++) {
            acc[SINEW_SOA_TX + k] = _mm256_add_ps(acc[SINEW_SOA_TX + k],
                                                  _mm256_mul_ps(w, _mm256_loadu_ps(P + (SINEW_SOA_TX + k) * stride)));
            acc[SINEW_SOA_SX + k] = _mm256_add_ps(acc[SINEW_SOA_SX + k],
                                                  _mm256_mul_ps(w, _mm256_loadu_ps(P + (SINEW_SOA_SX + k) * stride)));
        }
        for (int k = 0; k < 4; k++)
            acc[SINEW_SOA_QX + k] = _mm256_add_ps(acc[SINEW_SOA_QX + k], _mm256_mul_ps(wq, q[k]));
        total = _mm256_add_ps(total, w);
    }
    __m256 inv_total = _mm256_div_ps(one, total);
    __m256 n = dot4(acc + SINEW_SOA_QX, acc + SINEW_SOA_QX);
    __m256 inv = inv_length(n), some = _mm256_cmp_ps(n, zero, _CMP_GT_OQ);
    __m256 t[3], s[3], q[4];
    for (int k = 0; k < 3; k++) {
        t[k] = _mm256_mul_ps(acc[SINEW_SOA_TX + k], inv_total);
        s[k] = _mm256_mul_ps(acc[SINEW_SOA_SX + k], inv_total);
    }
    for (int k = 0; k < 4; k++)
        q[k] = _mm256_mul_ps(acc[SINEW_SOA_QX + k], inv);
    q[3] = _mm256_blendv_ps(one, q[3], some);
    for (uint32_t a = 0; a < b->additive_count; a++) {
        const float *P = b->additive[a].P + i;
        __m256 w = _mm256_loadu_ps(b->additive[a].w), d[4];
        for (int k = 0; k < 4; k++)
            d[k] = _mm256_loadu_ps(P + (SINEW_SOA_QX + k) * S);
        __m256 dinv = inv_length(dot4(d, d));
        __m256 flip = _mm256_and_ps(_mm256_cmp_ps(d[3], zero, _CMP_LT_OQ), sign);
        __m256 wd = _mm256_xor_ps(_mm256_mul_ps(w, dinv), flip);
        __m256 p[4] = {_mm256_mul_ps(wd, d[0]), _mm256_mul_ps(wd, d[1]), _mm256_mul_ps(wd, d[2]),
                       _mm256_add_ps(_mm256_mul_ps(wd, d[3]), _mm256_sub_ps(one, w))};
        /* r = q * p, each component in the scalar code's order */
        __m256 r[4];
        r[0] = _mm256_sub_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(q[3], p[0]), _mm256_mul_ps(q[0], p[3])),
                                           _mm256_mul_ps(q[1], p[2])),
                             _mm256_mul_ps(q[2], p[1]));
        r[1] = _mm256_add_ps(_mm256_add_ps(_mm256_sub_ps(_mm256_mul_ps(q[3], p[1]), _mm256_mul_ps(q[0], p[2])),
                                           _mm256_mul_ps(q[1], p[3])),
                             _mm256_mul_ps(q[2], p[0]));
        r[2] = _mm256_add_ps(_mm256_sub_ps(_mm256_add_ps(_mm256_mul_ps(q[3], p[2]), _mm256_mul_ps(q[0], p[1])),
                                           _mm256_mul_ps(q[1], p[0])),
                             _mm256_mul_ps(q[2], p[3]));
        r[3] = _mm256_sub_ps(_mm256_sub_ps(_mm256_sub_ps(_mm256_mul_ps(q[3], p[3]), _mm256_mul_ps(q[0], p[0])),
                                           _mm256_mul_ps(q[1], p[1])),
                             _mm256_mul_ps(q[2], p[2]));
        __m256 rinv = inv_length(dot4(r, r));
        for (int k = 0; k < 4; k++)
            q[k] = _mm256_mul_ps(r[k], rinv);
        for (int k = 0; k < 3; k++) {
            t[k] = _mm256_add_ps(t[k], _mm256_mul_ps(w, _mm256_loadu_ps(P + (SINEW_SOA_TX + k) * S)));
            __m256 ds = _mm256_sub_ps(_mm256_loadu_ps(P + (SINEW_SOA_SX + k) * S), one);
            s[k] = _mm256_mul_ps(s[k], _mm256_add_ps(one, _mm256_mul_ps(w, ds)));
        }
    }
    for (int k = 0; k < 3; k++) {
        _mm256_store_ps(b->out + (SINEW_SOA_TX + k) * S + i, t[k]);
        _mm256_store_ps(b->out + (SINEW_SOA_SX + k) * S + i, s[k]);
    }
    for (int k = 0; k < 4; k++)
        _mm256_store_ps(b->out + (SINEW_SOA_QX + k) * S + i, q[k]);
}
#endif

static sinew_result check_soa_layers(const sinew_blend_soa_layer *layers, uint32_t count, uint32_t node_count,
                                     const char *what, sinew_error *error)
{
    if (count && !layers)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend_soa: %u %s layers and no array", count,
                          what);
    if (count > SINEW_BLEND_SOA_MAX_LAYERS)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend_soa: %u %s layers, at most %u", count, what,
                          (unsigned)SINEW_BLEND_SOA_MAX_LAYERS);
    for (uint32_t i = 0; i < count; i++) {
        sinew_result r = check_pose(layers[i].pose, "sinew_blend_soa", error);
        if (r != SINEW_OK)
            return r;
        if (layers[i].pose->node_count != node_count)
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "sinew_blend_soa: %s layer %u has %u nodes, the model %u", what, i,
                              layers[i].pose->node_count, node_count);
        if (!isfinite(layers[i].weight) || layers[i].weight < 0.0f)
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "sinew_blend_soa: %s layer %u's weight %g is negative or not finite", what, i,
                              (double)layers[i].weight);
    }
    return SINEW_OK;
}

static sinew_result blend_soa(const sinew_blend_soa_desc *d, bool simd, sinew_error *error)
{
    if (!d || !d->model)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend_soa: missing model");
    const sinew_model *m = d->model;
    sinew_result r = check_pose(d->out, "sinew_blend_soa", error);
    if (r == SINEW_OK && d->out->node_count != m->node_count)
        r = sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend_soa: an output of %u nodes, a model of %u",
                       d->out->node_count, m->node_count);
    if (r == SINEW_OK && d->rest)
        r = check_pose(d->rest, "sinew_blend_soa", error);
    if (r == SINEW_OK && d->rest && d->rest->node_count != m->node_count)
        r = sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend_soa: a rest pose of %u nodes, a model of %u",
                       d->rest->node_count, m->node_count);
    if (r == SINEW_OK)
        r = check_soa_layers(d->layers, d->layer_count, m->node_count, "blend", error);
    if (r == SINEW_OK)
        r = check_soa_layers(d->additive, d->additive_count, m->node_count, "additive", error);
    if (r != SINEW_OK)
        return r;
    if (!(d->threshold >= 0.0f) || !isfinite(d->threshold))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_blend_soa: threshold %g is not a weight",
                          (double)d->threshold);
    block_layer layers[SINEW_BLEND_SOA_MAX_LAYERS], additive[SINEW_BLEND_SOA_MAX_LAYERS];
    for (uint32_t l = 0; l < d->layer_count; l++)
        layers[l].P = d->layers[l].pose->data;
    for (uint32_t l = 0; l < d->additive_count; l++)
        additive[l].P = d->additive[l].pose->data;
    const uint32_t S = d->out->stride;
    _Alignas(32) float rest[SINEW_SOA_ROWS * 8]; /* a block of the model's rest pose, without d->rest */
    block_job job = {layers,
                     d->layer_count,
                     additive,
                     d->additive_count,
                     rest,
                     8,
                     d->threshold > 0.0f ? d->threshold : 0.1f,
                     d->out->data,
                     S,
                     0};
    for (uint32_t i0 = 0; i0 < m->node_count; i0 += 8) {
        job.i0 = i0;
        for (uint32_t l = 0; l < d->layer_count; l++)
            block_weights(&d->layers[l], i0, m->node_count, layers[l].w);
        for (uint32_t l = 0; l < d->additive_count; l++)
            block_weights(&d->additive[l], i0, m->node_count, additive[l].w);
        if (d->rest)
            job.rest = d->rest->data + i0, job.rest_stride = S;
        for (uint32_t r8 = 0; !d->rest && r8 < SINEW_SOA_ROWS; r8++)
            for (uint32_t j = 0; j < 8; j++) {
                uint32_t i = i0 + j;
                if (i >= m->node_count)
                    rest[r8 * 8 + j] = r8 == SINEW_SOA_QW || r8 >= SINEW_SOA_SX ? 1.0f : 0.0f;
                else if (r8 < SINEW_SOA_QX)
                    rest[r8 * 8 + j] = m->node_rest[i].translation[r8 - SINEW_SOA_TX];
                else if (r8 < SINEW_SOA_SX)
                    rest[r8 * 8 + j] = m->node_rest[i].rotation[r8 - SINEW_SOA_QX];
                else
                    rest[r8 * 8 + j] = m->node_rest[i].scale[r8 - SINEW_SOA_SX];
            }
#ifdef SOA_X86
        if (simd)
            blend_block_avx2(&job);
        else
#endif
            blend_block_scalar(&job);
    }
    sinew_soa_identity(d->out->data, S, m->node_count); /* the padding stays identity */
    return SINEW_OK;
}

sinew_result sinew_blend_soa(const sinew_blend_soa_desc *desc, sinew_error *error)
{
    return blend_soa(desc, sinew_soa_simd_supported(), error);
}

sinew_result sinew_blend_soa_scalar(const sinew_blend_soa_desc *desc, sinew_error *error)
{
    return blend_soa(desc, false, error);
}
