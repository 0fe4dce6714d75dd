/* The x86 SIMD skinning kernels, chosen at run time by skin.c.
 *
 * AVX-512 (sinew_skin_avx512), 16 vertices at a time:
 *   1. blend: each vertex's joint records (16 floats: a column-major matrix, or a
 *      sinew_dq_joint) are summed with its weights in one zmm register, one load and one FMA
 *      an influence; the influence count is a compile-time constant for 1 to 8 (no branch);
 *   2. transpose: the 16 blended records become 16 registers of one element for 16
 *      vertices (structure of arrays: unpacks and 128-bit shuffles);
 *   3. math in SoA registers (skin_soa.h, shared with the AVX2 kernel): positions, the
 *      cofactor normal transform (exact, no approximation: it costs fewer instructions than
 *      blending a second palette), tangents, or the dual-quaternion rotation and
 *      translation after the scale/shear; rsqrt14 plus a Newton step where the reference
 *      divides by a square root;
 *   4. positions and normals are read and written as xyz triples by two-register permutes
 *      when the output stride is 12, by scatters otherwise (interleaved vertex buffers).
 * AVX2+FMA (skin_avx2.c): the same steps 8 vertices at a time, for processors without AVX-512.
 * tests/core/test_runtime.c holds both within 2e-6 of skin.c's reference. */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "skin_dispatch.h"

#if defined(__x86_64__) && defined(__GNUC__)
#ifdef SINEW_SKIN_AVX512_EMULATED
/* tests/core/test_skin_avx512.c builds this file against SIMDe's portable AVX-512, so that the
 * kernel is tested on processors without it */
#include "avx512_emulated.h"
#define AVX512_TARGET
#else
#include <immintrin.h>
#define AVX512_TARGET __attribute__((target("avx512f,avx512dq")))
#endif

#define AVX512 AVX512_TARGET static inline __attribute__((always_inline))
#define AVX512_FN AVX512_TARGET

/* ---- AVX-512 ---- */

/* DQS's hemisphere test: the sign of the dot of two joints' real parts (the records' first 4
 * floats), on the first 8 lanes (the dual quaternion), 0 elsewhere: xor it into a weight. */
AVX512 __m512 hemisphere_sign(__m512 first, __m512 record)
{
    __m128 d = _mm_mul_ps(_mm512_castps512_ps128(first), _mm512_castps512_ps128(record)); /* all lanes */
    d = _mm_add_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(2, 3, 0, 1)));
    d = _mm_add_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm512_maskz_broadcast_f32x4(0x00ff, _mm_and_ps(d, _mm_set1_ps(-0.0f)));
}

/* Record blend of one vertex: sum of w_i * record[j_i] over k influences. DQS takes each
 * joint's quaternion (the first 8 floats) in the first joint's hemisphere. */
AVX512 __m512 blend_vertex(const float *records, const uint16_t *joints, const float *weights, uint32_t k, bool dqs)
{
    /* up to 4 joint indices in one load, and their weights in another (each weight broadcast
     * from the register: a shuffle instead of a load, where loads are what the path waits on;
     * positions alone skin 10% faster, with normals the same) */
    uint64_t packed = 0;
    __m512 w4 = _mm512_setzero_ps();
    if (k >= 4) {
        memcpy(&packed, joints, 8);
        w4 = _mm512_castps128_ps512(_mm_loadu_ps(weights));
    }
#define JOINT(i) ((k >= 4 && (i) < 4) ? (size_t)((packed >> (16 * (i))) & 0xffff) : (size_t)joints[i])
#define WEIGHT(i)                                                                                                      \
    ((k >= 4 && (i) < 4) ? _mm512_permutexvar_ps(_mm512_set1_epi32((int)(i)), w4) : _mm512_set1_ps(weights[i]))
    __m512 first = _mm512_loadu_ps(records + JOINT(0) * 16);
    __m512 acc[2] = {_mm512_mul_ps(WEIGHT(0), first), _mm512_setzero_ps()};
#pragma GCC unroll 8
    for (uint32_t i = 1; i < k; i++) {
        __m512 r = _mm512_loadu_ps(records + JOINT(i) * 16);
        __m512 w = WEIGHT(i);
        if (dqs)
            w = _mm512_xor_ps(w, hemisphere_sign(first, r));
        acc[i & 1] = _mm512_fmadd_ps(w, r, acc[i & 1]); /* two chains: half the FMA latency a vertex */
    }
    return k > 1 ? _mm512_add_ps(acc[0], acc[1]) : acc[0];
#undef JOINT
#undef WEIGHT
}

/* Blends the n <= 16 vertices from `v` and transposes them: e[i] holds element i of the 16
 * vertices' blended records (lanes past n are 0). Pairs of vertices are unpacked as they are
 * blended, so that no more than 16 registers are live between the stages. */
/* Permute indices that turn 16 xyz triples (3 registers) into x, y, z registers and back. */
typedef struct triples {
    __m512i split_a[3], split_b[3]; /* component c: permutex2var(P0, a, P1), then with P2 */
    __m512i join_a[3], join_b[3];   /* output register o: permutex2var(x, a, y), then with z */
} triples;

AVX512 triples make_triples(void)
{
    int32_t sa[3][16], sb[3][16], ja[3][16], jb[3][16];
#pragma GCC unroll 16
    for (int c = 0; c < 3; c++)
#pragma GCC unroll 16
        for (int v = 0; v < 16; v++) {
            int f = 3 * v + c;
            sa[c][v] = f < 32 ? f : 0;
            sb[c][v] = f < 32 ? v : 16 + (f - 32);
        }
#pragma GCC unroll 16
    for (int o = 0; o < 3; o++)
#pragma GCC unroll 16
        for (int i = 0; i < 16; i++) {
            int f = 16 * o + i, v = f / 3, c = f % 3;
            ja[o][i] = c == 0 ? v : c == 1 ? 16 + v : 0;
            jb[o][i] = c == 2 ? 16 + v : i;
        }
    triples t;
#pragma GCC unroll 16
    for (int c = 0; c < 3; c++) {
        t.split_a[c] = _mm512_loadu_si512(sa[c]);
        t.split_b[c] = _mm512_loadu_si512(sb[c]);
        t.join_a[c] = _mm512_loadu_si512(ja[c]);
        t.join_b[c] = _mm512_loadu_si512(jb[c]);
    }
    return t;
}

/* Loads n <= 16 xyz triples from p into x, y, z (lanes past n are 0). */
AVX512 void load3(const triples *t, const float *p, uint32_t n, __m512 out[3])
{
    __m512 r[3];
#pragma GCC unroll 16
    for (int i = 0; i < 3; i++) {
        int valid = (int)(3 * n) - 16 * i;
        __mmask16 m = valid >= 16 ? 0xffff : valid <= 0 ? 0 : (__mmask16)((1u << valid) - 1);
        r[i] = _mm512_maskz_loadu_ps(m, p + 16 * i);
    }
#pragma GCC unroll 16
    for (int c = 0; c < 3; c++)
        out[c] = _mm512_permutex2var_ps(_mm512_permutex2var_ps(r[0], t->split_a[c], r[1]), t->split_b[c], r[2]);
}

/* Whether all 16 vertices of a block name the same joints (in the same order). */
AVX512 bool same_joints(const uint16_t *joints, uint32_t k)
{
    if (k == 4) { /* 16 vertices' joints: two registers of 8 64-bit sets, against the first */
        uint64_t first;
        memcpy(&first, joints, 8);
        __m512i f = _mm512_set1_epi64((long long)first);
        __mmask8 a = _mm512_cmpeq_epi64_mask(_mm512_loadu_si512(joints), f);
        __mmask8 b = _mm512_cmpeq_epi64_mask(_mm512_loadu_si512(joints + 32), f);
        return (a & b) == 0xff;
    }
    for (uint32_t i = 1; i < 16; i++)
        if (memcmp(joints + i * k, joints, k * sizeof *joints) != 0)
            return false;
    return true;
}

/* Record blend of one vertex of a block whose vertices share their joints: the k records
 * (their DQS signs already applied to the weights' sign masks) loaded once for the block. */
AVX512 __m512 blend_shared(const __m512 *records, const __m512 *signs, const float *weights, uint32_t k)
{
    __m512 acc[2] = {_mm512_mul_ps(_mm512_set1_ps(weights[0]), records[0]), _mm512_setzero_ps()};
#pragma GCC unroll 8
    for (uint32_t i = 1; i < k; i++)
        acc[i & 1] = _mm512_fmadd_ps(_mm512_xor_ps(_mm512_set1_ps(weights[i]), signs[i]), records[i], acc[i & 1]);
    return k > 1 ? _mm512_add_ps(acc[0], acc[1]) : acc[0];
}

/* A block of 16 vertices with the same k <= 4 joints, straight into structure-of-arrays
 * registers: the weights transposed (influence i's weight of each vertex in one register: a
 * load for 1 influence, a permute each for 2, load3's split for 3, three permutes each for 4),
 * then each element of the blended records as sum_i W_i * record_i[element] (the records'
 * elements broadcast), so neither the per-vertex weight broadcasts nor the 16x16 transpose are
 * needed. Each lane gets the operations blend_vertex() does, in its order. */
AVX512 void blend_shared_soa(const skin_call *c, const triples *tr, const uint16_t *joints, const float *weights,
                             uint32_t k, bool dqs, __m512 e[16])
{
    static const int32_t pick4[4][16] = {{0, 4, 8, 12, 16, 20, 24, 28},
                                         {1, 5, 9, 13, 17, 21, 25, 29},
                                         {2, 6, 10, 14, 18, 22, 26, 30},
                                         {3, 7, 11, 15, 19, 23, 27, 31}};
    static const int32_t pick2[2][16] = {{0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30},
                                         {1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31}};
    __m512 w[4] = {_mm512_setzero_ps(), _mm512_setzero_ps(), _mm512_setzero_ps(), _mm512_setzero_ps()};
    if (k == 1) {
        w[0] = _mm512_loadu_ps(weights);
    } else if (k == 2) {
        __m512 l0 = _mm512_loadu_ps(weights), l1 = _mm512_loadu_ps(weights + 16);
#pragma GCC unroll 2
        for (int i = 0; i < 2; i++)
            w[i] = _mm512_permutex2var_ps(l0, _mm512_loadu_si512(pick2[i]), l1);
    } else if (k == 3) {
        load3(tr, weights, 16, w);
    } else {
        __m512 l[4];
#pragma GCC unroll 4
        for (int m = 0; m < 4; m++)
            l[m] = _mm512_loadu_ps(weights + 16 * m);
#pragma GCC unroll 4
        for (int i = 0; i < 4; i++) {
            __m512i idx = _mm512_loadu_si512(pick4[i]);
            w[i] = _mm512_shuffle_f32x4(_mm512_permutex2var_ps(l[0], idx, l[1]),
                                        _mm512_permutex2var_ps(l[2], idx, l[3]), _MM_SHUFFLE(1, 0, 1, 0));
        }
    }
    const float *r[4] = {NULL, NULL, NULL, NULL};
    bool flip[4] = {false, false, false, false};
#pragma GCC unroll 4
    for (uint32_t i = 0; i < k; i++) {
        r[i] = c->records + (size_t)joints[i] * 16;
        if (dqs && i > 0) { /* blend_vertex's hemisphere test, in its order of additions */
            float d = (r[0][0] * r[i][0] + r[0][1] * r[i][1]) + (r[0][2] * r[i][2] + r[0][3] * r[i][3]);
            flip[i] = signbit(d);
        }
    }
#pragma GCC unroll 16
    for (int el = 0; el < 16; el++) {
        __m512 acc[2] = {_mm512_mul_ps(w[0], _mm512_set1_ps(r[0][el])), _mm512_setzero_ps()};
#pragma GCC unroll 4
        for (uint32_t i = 1; i < k; i++) {
            float x = flip[i] && el < 8 ? -r[i][el] : r[i][el];
            acc[i & 1] = _mm512_fmadd_ps(w[i], _mm512_set1_ps(x), acc[i & 1]);
        }
        e[el] = k > 1 ? _mm512_add_ps(acc[0], acc[1]) : acc[0];
    }
}

AVX512 void blend_transposed(const skin_call *c, const triples *tr, uint32_t v, uint32_t n, uint32_t k, bool dqs,
                             __m512 e[16])
{
    const uint16_t *joints = &c->mesh->joints[(size_t)v * k];
    const float *weights = &c->mesh->weights[(size_t)v * k];
    if (k <= 4 && n == 16 && same_joints(joints, k)) {
        blend_shared_soa(c, tr, joints, weights, k, dqs, e);
        return;
    }
    __m512 t[16], u[16];
    /* Meshes come in runs of vertices bound to the same joints (the demo humanoid: 93% of its
     * vertices share their predecessor's): such a block loads each joint record once, not
     * once a vertex, and the same sums come out. */
    if (n == 16 && same_joints(joints, k)) {
        __m512 records[8], signs[8];
#pragma GCC unroll 8
        for (uint32_t i = 0; i < 8; i++)
            records[i] = signs[i] = _mm512_setzero_ps();
#pragma GCC unroll 8
        for (uint32_t i = 0; i < k; i++) {
            records[i] = _mm512_loadu_ps(c->records + (size_t)joints[i] * 16);
            signs[i] = _mm512_setzero_ps();
            if (dqs && i > 0)
                signs[i] = hemisphere_sign(records[0], records[i]);
        }
#pragma GCC unroll 16
        for (uint32_t i = 0; i < 16; i += 2) {
            __m512 a = blend_shared(records, signs, weights + i * k, k);
            __m512 b = blend_shared(records, signs, weights + (i + 1) * k, k);
            t[i] = _mm512_unpacklo_ps(a, b);
            t[i + 1] = _mm512_unpackhi_ps(a, b);
        }
    } else {
#pragma GCC unroll 16
        for (uint32_t i = 0; i < 16; i += 2) {
            __m512 a = i < n ? blend_vertex(c->records, joints + i * k, weights + i * k, k, dqs) : _mm512_setzero_ps();
            __m512 b = i + 1 < n ? blend_vertex(c->records, joints + (i + 1) * k, weights + (i + 1) * k, k, dqs)
                                 : _mm512_setzero_ps();
            t[i] = _mm512_unpacklo_ps(a, b);
            t[i + 1] = _mm512_unpackhi_ps(a, b);
        }
    }
#pragma GCC unroll 16
    for (int g = 0; g < 4; g++) {
        __m512d lo0 = _mm512_castps_pd(t[4 * g]), lo1 = _mm512_castps_pd(t[4 * g + 2]);
        __m512d hi0 = _mm512_castps_pd(t[4 * g + 1]), hi1 = _mm512_castps_pd(t[4 * g + 3]);
        u[4 * g + 0] = _mm512_castpd_ps(_mm512_unpacklo_pd(lo0, lo1));
        u[4 * g + 1] = _mm512_castpd_ps(_mm512_unpackhi_pd(lo0, lo1));
        u[4 * g + 2] = _mm512_castpd_ps(_mm512_unpacklo_pd(hi0, hi1));
        u[4 * g + 3] = _mm512_castpd_ps(_mm512_unpackhi_pd(hi0, hi1));
    }
    /* u[4g + j]: in 128-bit lane L, element 4L + j of vertices 4g .. 4g + 3 */
#pragma GCC unroll 16
    for (int j = 0; j < 4; j++) {
        __m512 v0 = _mm512_shuffle_f32x4(u[j], u[4 + j], _MM_SHUFFLE(1, 0, 1, 0));
        __m512 v1 = _mm512_shuffle_f32x4(u[j], u[4 + j], _MM_SHUFFLE(3, 2, 3, 2));
        __m512 v2 = _mm512_shuffle_f32x4(u[8 + j], u[12 + j], _MM_SHUFFLE(1, 0, 1, 0));
        __m512 v3 = _mm512_shuffle_f32x4(u[8 + j], u[12 + j], _MM_SHUFFLE(3, 2, 3, 2));
        e[0 + j] = _mm512_shuffle_f32x4(v0, v2, _MM_SHUFFLE(2, 0, 2, 0));
        e[4 + j] = _mm512_shuffle_f32x4(v0, v2, _MM_SHUFFLE(3, 1, 3, 1));
        e[8 + j] = _mm512_shuffle_f32x4(v1, v3, _MM_SHUFFLE(2, 0, 2, 0));
        e[12 + j] = _mm512_shuffle_f32x4(v1, v3, _MM_SHUFFLE(3, 1, 3, 1));
    }
}

/* Stores n <= 16 vertices' x, y, z (and w when given) at `base`, `stride` bytes apart. */
AVX512 void store_vertices(const triples *t, float *base, size_t stride, uint32_t n, const __m512 v[3], const __m512 *w)
{
    if (stride == 12 && !w && n == 16) {
#pragma GCC unroll 16
        for (int o = 0; o < 3; o++)
            _mm512_storeu_ps(base + 16 * o, _mm512_permutex2var_ps(_mm512_permutex2var_ps(v[0], t->join_a[o], v[1]),
                                                                   t->join_b[o], v[2]));
        return;
    }
    __mmask16 m = n >= 16 ? 0xffff : (__mmask16)((1u << n) - 1);
    __m512i at = _mm512_mullo_epi32(_mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0),
                                    _mm512_set1_epi32((int)stride));
#pragma GCC unroll 16
    for (int c = 0; c < 3; c++)
        _mm512_mask_i32scatter_ps(base + c, m, at, v[c], 1);
    if (w)
        _mm512_mask_i32scatter_ps(base + 3, m, at, *w, 1);
}

/* The SoA math (skin_soa.h) on 16 lanes; rsqrt14 is the estimate its Newton step refines. */
#define SOA_VEC __m512
#define SOA_FN AVX512
#define SOA_NAME(x) x##_16
#define SOA_ADD _mm512_add_ps
#define SOA_MUL _mm512_mul_ps
#define SOA_XOR _mm512_xor_ps
#define SOA_AND _mm512_and_ps
#define SOA_FMADD _mm512_fmadd_ps
#define SOA_FMSUB _mm512_fmsub_ps
#define SOA_FNMADD _mm512_fnmadd_ps
#define SOA_SET1 _mm512_set1_ps
#define SOA_ZERO _mm512_setzero_ps
#define SOA_RSQRT _mm512_rsqrt14_ps
#define SOA_KEEP_POSITIVE(x, r) _mm512_maskz_mov_ps(_mm512_cmp_ps_mask((x), _mm512_setzero_ps(), _CMP_GT_OQ), (r))
#include "skin_soa.h"

/* Tangent w components of n vertices (stride 4 floats), gathered. */
AVX512 __m512 load_tangents(const float *t, uint32_t n, __m512 xyz[3])
{
    __mmask16 m = n >= 16 ? 0xffff : (__mmask16)((1u << n) - 1);
    __m512i at = _mm512_mullo_epi32(_mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0),
                                    _mm512_set1_epi32(4));
#pragma GCC unroll 16
    for (int c = 0; c < 3; c++)
        xyz[c] = _mm512_mask_i32gather_ps(_mm512_setzero_ps(), m, at, t + c, 4);
    return _mm512_mask_i32gather_ps(_mm512_setzero_ps(), m, at, t + 3, 4);
}

/* The vertices [v, v + n) of one block, n <= 16. */
AVX512 void skin_block(const skin_call *c, const triples *tr, uint32_t v, uint32_t n, uint32_t k, bool dqs)
{
    const sinew_mesh *mesh = c->mesh;
    __m512 e[16];
    blend_transposed(c, tr, v, n, k, dqs, e);
    __m512 p[3], t_w = _mm512_setzero_ps();
    __m512 n_in[3] = {_mm512_setzero_ps(), _mm512_setzero_ps(), _mm512_setzero_ps()};
    __m512 t_in[3] = {_mm512_setzero_ps(), _mm512_setzero_ps(), _mm512_setzero_ps()};
    load3(tr, &mesh->positions[(size_t)v * 3], n, p);
    if (c->out_n)
        load3(tr, &mesh->normals[(size_t)v * 3], n, n_in);
    if (c->out_t)
        t_w = load_tangents(&mesh->tangents[(size_t)v * 4], n, t_in);
    size_t at = (size_t)v * c->stride;
    __m512 out_p[3], out_n[3] = {_mm512_setzero_ps(), _mm512_setzero_ps(), _mm512_setzero_ps()},
                     out_t[3] = {_mm512_setzero_ps(), _mm512_setzero_ps(), _mm512_setzero_ps()},
                     out_w = _mm512_setzero_ps();
    skin_math_16(e, dqs, p, c->out_n ? n_in : NULL, c->out_t ? t_in : NULL, t_w, out_p, out_n, out_t, &out_w);
    store_vertices(tr, (float *)((char *)c->out_p + at), c->stride, n, out_p, NULL);
    if (c->out_n)
        store_vertices(tr, (float *)((char *)c->out_n + at), c->stride, n, out_n, NULL);
    if (c->out_t)
        store_vertices(tr, (float *)((char *)c->out_t + at), c->stride, n, out_t, &out_w);
}

/* Every block of the range, with the influence count k and the method known at compile
 * time (an instance a pair). */
AVX512 void skin_blocks(const skin_call *c, uint32_t k, bool dqs)
{
    triples tr = make_triples();
    uint32_t v = c->first, end = c->first + c->count;
    for (; v + 16 <= end; v += 16)
        skin_block(c, &tr, v, 16, k, dqs);
    if (v < end)
        skin_block(c, &tr, v, end - v, k, dqs);
}

/* The entry point (skin_dispatch.h); skin.c copies records that are not 64-byte aligned to
 * the stack first, where that pays. */
SKIN_KERNEL(AVX512_FN, sinew_skin_avx512)

#endif
