/* The AVX2 + FMA skinning kernel (sinew_skin_avx2), chosen by skin.c on processors without
 * AVX-512 (most desktops and laptops, AMD before Zen 4): the steps of skin_x86.c's AVX-512
 * kernel on 8 vertices at a time in 256-bit registers, linear blend and dual quaternions,
 * positions, normals and tangents:
 *   1. blend: a block whose 8 vertices name the same k <= 4 joints (most blocks of real
 *      meshes) goes straight into structure-of-arrays registers, each of the 16 record
 *      elements as sum_i W_i * record_i[element] with W_i the 8 vertices' weights of
 *      influence i; any other block a vertex at a time (a joint record is two registers: two
 *      loads and two FMAs an influence), then two 8x8 transposes;
 *   2. the math of skin_soa.h (rsqrt plus a Newton step where the reference divides by a
 *      square root);
 *   3. packed xyz triples (stride 12) read and written as three registers with blends and
 *      lane inserts; interleaved outputs and tangents through 4x8 transposes, a vertex at a time.
 * A block of fewer than 8 vertices (a range's end) runs the same code on a padded copy of its
 * inputs and writes only its own vertices. Both blends sum a lane's influences in one chain,
 * in the same order, so a vertex gets the same bits whichever path its block takes.
 * tests/core/test_runtime.c holds it within 2e-6 of the scalar reference (skin.c). */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "skin_dispatch.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#define AVX2 __attribute__((target("avx2,fma"))) static inline __attribute__((always_inline))
#define AVX2_FN __attribute__((target("avx2,fma")))

/* The SoA math (skin_soa.h) on 8 lanes; rsqrt's 12-bit estimate is what its Newton step refines
 * (a second step moved no result of test_runtime's by more than rounding). */
#define SOA_VEC __m256
#define SOA_FN AVX2
#define SOA_NAME(x) x##_8
#define SOA_ADD _mm256_add_ps
#define SOA_MUL _mm256_mul_ps
#define SOA_XOR _mm256_xor_ps
#define SOA_AND _mm256_and_ps
#define SOA_FMADD _mm256_fmadd_ps
#define SOA_FMSUB _mm256_fmsub_ps
#define SOA_FNMADD _mm256_fnmadd_ps
#define SOA_SET1 _mm256_set1_ps
#define SOA_ZERO _mm256_setzero_ps
#define SOA_RSQRT _mm256_rsqrt_ps
#define SOA_KEEP_POSITIVE(x, r) _mm256_and_ps((r), _mm256_cmp_ps((x), _mm256_setzero_ps(), _CMP_GT_OQ))
#include "skin_soa.h"

#define BLOCK 8

/* A block's inputs: the mesh's arrays at its first vertex, or a padded copy of a range's end. */
typedef struct block_in {
    const uint16_t *joints;
    const float *weights, *positions, *normals, *tangents; /* normals, tangents NULL when not wanted */
} block_in;

/* Two 128-bit loads into the halves of one register. */
AVX2 __m256 load_halves(const float *lo, const float *hi)
{
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(lo)), _mm_loadu_ps(hi), 1);
}

/* 8 packed xyz triples (24 floats at p) into x, y, z. Each 128-bit half takes 4 vertices:
 * [x0 y0 z0 x1] [y1 z1 x2 y2] [z2 x3 y3 z3], blended into [x0 x3 x2 x1], [y1 y0 y3 y2],
 * [z2 z1 z0 z3] and put in order by an in-lane permute. */
AVX2 void load3(const float *p, __m256 out[3])
{
    __m256 r0 = load_halves(p, p + 12), r1 = load_halves(p + 4, p + 16), r2 = load_halves(p + 8, p + 20);
    out[0] = _mm256_permute_ps(_mm256_blend_ps(_mm256_blend_ps(r0, r1, 0x44), r2, 0x22), _MM_SHUFFLE(1, 2, 3, 0));
    out[1] = _mm256_permute_ps(_mm256_blend_ps(_mm256_blend_ps(r0, r1, 0x99), r2, 0x44), _MM_SHUFFLE(2, 3, 0, 1));
    out[2] = _mm256_permute_ps(_mm256_blend_ps(_mm256_blend_ps(r0, r1, 0x22), r2, 0x99), _MM_SHUFFLE(3, 0, 1, 2));
}

/* load3 backwards: x, y, z as 8 packed triples at p. */
AVX2 void store3(float *p, const __m256 v[3])
{
    __m256 x = _mm256_permute_ps(v[0], _MM_SHUFFLE(1, 2, 3, 0));
    __m256 y = _mm256_permute_ps(v[1], _MM_SHUFFLE(2, 3, 0, 1));
    __m256 z = _mm256_permute_ps(v[2], _MM_SHUFFLE(3, 0, 1, 2));
    __m256 r0 = _mm256_blend_ps(_mm256_blend_ps(x, y, 0x22), z, 0x44);
    __m256 r1 = _mm256_blend_ps(_mm256_blend_ps(y, z, 0x22), x, 0x44);
    __m256 r2 = _mm256_blend_ps(_mm256_blend_ps(z, x, 0x22), y, 0x44);
    _mm256_storeu_ps(p, _mm256_permute2f128_ps(r0, r1, 0x20));
    _mm256_storeu_ps(p + 8, _mm256_permute2f128_ps(r2, r0, 0x30));
    _mm256_storeu_ps(p + 16, _mm256_permute2f128_ps(r1, r2, 0x31));
}

/* 8 vertices of 4 floats (32 floats at p: tangents, or 4 weights a vertex) into 4 registers
 * of one component each. */
AVX2 void load4(const float *p, __m256 out[4])
{
    __m256 a0 = load_halves(p, p + 16), a1 = load_halves(p + 4, p + 20);
    __m256 a2 = load_halves(p + 8, p + 24), a3 = load_halves(p + 12, p + 28);
    __m256 t0 = _mm256_unpacklo_ps(a0, a1), t1 = _mm256_unpacklo_ps(a2, a3);
    __m256 t2 = _mm256_unpackhi_ps(a0, a1), t3 = _mm256_unpackhi_ps(a2, a3);
    out[0] = _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(1, 0, 1, 0));
    out[1] = _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(3, 2, 3, 2));
    out[2] = _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(1, 0, 1, 0));
    out[3] = _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(3, 2, 3, 2));
}

/* n <= 8 vertices' x, y, z (and w when given) at `base`, `stride` bytes apart: a 4x8
 * transpose, then a vertex at a time. */
AVX2 void store_strided(float *base, size_t stride, uint32_t n, const __m256 v[3], const __m256 *w)
{
    __m256 ww = w ? *w : _mm256_setzero_ps();
    __m256 t0 = _mm256_unpacklo_ps(v[0], v[1]), t1 = _mm256_unpackhi_ps(v[0], v[1]);
    __m256 t2 = _mm256_unpacklo_ps(v[2], ww), t3 = _mm256_unpackhi_ps(v[2], ww);
    /* a[i]: vertex i in the low half, vertex i + 4 in the high */
    __m256 a[4] = {
        _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0)), _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2)),
        _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0)), _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2))};
#pragma GCC unroll 8
    for (uint32_t i = 0; i < BLOCK; i++) {
        if (i >= n)
            break;
        __m128 x = i < 4 ? _mm256_castps256_ps128(a[i]) : _mm256_extractf128_ps(a[i - 4], 1);
        float *o = (float *)((char *)base + i * stride);
        if (w) {
            _mm_storeu_ps(o, x);
        } else {
            _mm_storel_pi((__m64 *)o, x);
            _mm_store_ss(o + 2, _mm_movehl_ps(x, x));
        }
    }
}

/* DQS's hemisphere test: the sign of the dot of two joints' real parts (the records' first 4
 * floats) in every lane, to xor into the weight of the records' first half. The sum in the
 * order of the AVX-512 kernel's. */
AVX2 __m256 hemisphere_sign(__m256 first, __m256 record)
{
    __m128 d = _mm_mul_ps(_mm256_castps256_ps128(first), _mm256_castps256_ps128(record));
    d = _mm_add_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(2, 3, 0, 1)));
    d = _mm_add_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(1, 0, 3, 2)));
    d = _mm_and_ps(d, _mm_set1_ps(-0.0f));
    return _mm256_set_m128(d, d);
}

/* Record blend of one vertex: out[0] elements 0..7, out[1] 8..15 of sum w_i * record[j_i],
 * one FMA chain a half in the reference's order (two chains cost an add a half and gained
 * nothing: 8 vertices' chains are independent already; one is 7% faster). The joint indices
 * are loaded one by one (unpacking 4 from one 64-bit load was 2-11% slower here). */
AVX2 void blend_vertex(const float *records, const uint16_t *joints, const float *weights, uint32_t k, bool dqs,
                       __m256 out[2])
{
    const float *r = records + (size_t)joints[0] * 16;
    __m256 first = _mm256_loadu_ps(r), w = _mm256_broadcast_ss(&weights[0]);
    __m256 lo_acc = _mm256_mul_ps(w, first), hi_acc = _mm256_mul_ps(w, _mm256_loadu_ps(r + 8));
#pragma GCC unroll 8
    for (uint32_t i = 1; i < k; i++) {
        r = records + (size_t)joints[i] * 16;
        __m256 lo = _mm256_loadu_ps(r), hi = _mm256_loadu_ps(r + 8);
        w = _mm256_broadcast_ss(&weights[i]);
        __m256 wq = dqs ? _mm256_xor_ps(w, hemisphere_sign(first, lo)) : w;
        lo_acc = _mm256_fmadd_ps(wq, lo, lo_acc);
        hi_acc = _mm256_fmadd_ps(w, hi, hi_acc);
    }
    out[0] = lo_acc, out[1] = hi_acc;
}

/* 8 registers of 8 floats transposed: e[i] holds element i of r[0 .. 7]. */
AVX2 void transpose8(const __m256 r[8], __m256 e[8])
{
    __m256 t[8], u[8];
#pragma GCC unroll 8
    for (int i = 0; i < 8; i += 2) {
        t[i] = _mm256_unpacklo_ps(r[i], r[i + 1]);
        t[i + 1] = _mm256_unpackhi_ps(r[i], r[i + 1]);
    }
    /* u[4g + j]: element j (low half) and j + 4 (high half) of r[4g .. 4g + 3] */
#pragma GCC unroll 8
    for (int g = 0; g < 2; g++) {
        u[4 * g + 0] = _mm256_shuffle_ps(t[4 * g], t[4 * g + 2], _MM_SHUFFLE(1, 0, 1, 0));
        u[4 * g + 1] = _mm256_shuffle_ps(t[4 * g], t[4 * g + 2], _MM_SHUFFLE(3, 2, 3, 2));
        u[4 * g + 2] = _mm256_shuffle_ps(t[4 * g + 1], t[4 * g + 3], _MM_SHUFFLE(1, 0, 1, 0));
        u[4 * g + 3] = _mm256_shuffle_ps(t[4 * g + 1], t[4 * g + 3], _MM_SHUFFLE(3, 2, 3, 2));
    }
#pragma GCC unroll 8
    for (int j = 0; j < 4; j++) {
        e[j] = _mm256_permute2f128_ps(u[j], u[4 + j], 0x20);
        e[4 + j] = _mm256_permute2f128_ps(u[j], u[4 + j], 0x31);
    }
}

/* Whether all 8 vertices of a block name the same joints (in the same order). */
AVX2 bool same_joints(const uint16_t *joints, uint32_t k)
{
    if (k == 4) { /* 8 vertices' joints: two registers of 4 64-bit sets, against the first */
        uint64_t first;
        memcpy(&first, joints, 8);
        __m256i f = _mm256_set1_epi64x((long long)first);
        __m256i a = _mm256_cmpeq_epi64(_mm256_loadu_si256((const __m256i *)joints), f);
        __m256i b = _mm256_cmpeq_epi64(_mm256_loadu_si256((const __m256i *)(joints + 16)), f);
        return _mm256_movemask_epi8(_mm256_and_si256(a, b)) == -1;
    }
    for (uint32_t i = 1; i < BLOCK; i++)
        if (memcmp(joints + i * k, joints, k * sizeof *joints) != 0)
            return false;
    return true;
}

/* A block of 8 vertices with the same k <= 4 joints, straight into SoA registers: the
 * weights transposed (W_i: influence i's weight of each vertex), then each element as
 * sum_i W_i * record_i[element], the element broadcast from memory. DQS's hemisphere signs
 * are tested once for the block and flip W_i for the first 8 elements. */
AVX2 void blend_shared_soa(const float *records, const uint16_t *joints, const float *weights, uint32_t k, bool dqs,
                           __m256 e[16])
{
    __m256 w[4] = {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()};
    if (k == 1) {
        w[0] = _mm256_loadu_ps(weights);
    } else if (k == 2) { /* evens and odds, then the 64-bit pairs in vertex order */
        __m256 a = _mm256_loadu_ps(weights), b = _mm256_loadu_ps(weights + 8);
        w[0] = _mm256_castpd_ps(_mm256_permute4x64_pd(
            _mm256_castps_pd(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0))), _MM_SHUFFLE(3, 1, 2, 0)));
        w[1] = _mm256_castpd_ps(_mm256_permute4x64_pd(
            _mm256_castps_pd(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1))), _MM_SHUFFLE(3, 1, 2, 0)));
    } else if (k == 3) {
        _Alignas(32) float t[3][BLOCK];
        for (uint32_t v = 0; v < BLOCK; v++)
            for (uint32_t i = 0; i < 3; i++)
                t[i][v] = weights[v * 3 + i];
        for (uint32_t i = 0; i < 3; i++)
            w[i] = _mm256_load_ps(t[i]);
    } else {
        load4(weights, w);
    }
    const float *r[4] = {NULL, NULL, NULL, NULL};
    __m256 wq[4] = {w[0], w[1], w[2], w[3]}; /* the weights of the first 8 elements */
#pragma GCC unroll 4
    for (uint32_t i = 0; i < k; i++) {
        r[i] = records + (size_t)joints[i] * 16;
        if (dqs && i > 0) { /* blend_vertex's hemisphere test, in its order of additions */
            float d = (r[0][0] * r[i][0] + r[0][1] * r[i][1]) + (r[0][2] * r[i][2] + r[0][3] * r[i][3]);
            if (signbit(d))
                wq[i] = _mm256_xor_ps(w[i], _mm256_set1_ps(-0.0f));
        }
    }
#pragma GCC unroll 16
    for (int el = 0; el < 16; el++) {
        const __m256 *ws = el < 8 ? wq : w;
        __m256 acc = _mm256_mul_ps(ws[0], _mm256_broadcast_ss(&r[0][el]));
#pragma GCC unroll 4
        for (uint32_t i = 1; i < k; i++)
            acc = _mm256_fmadd_ps(ws[i], _mm256_broadcast_ss(&r[i][el]), acc);
        e[el] = acc;
    }
}

/* The blended records of a block's 8 vertices in SoA registers. */
AVX2 void blend_block(const float *records, const block_in *in, uint32_t k, bool dqs, __m256 e[16])
{
    if (k <= 4 && same_joints(in->joints, k)) {
        blend_shared_soa(records, in->joints, in->weights, k, dqs, e);
        return;
    }
    __m256 lo[BLOCK], hi[BLOCK];
#pragma GCC unroll 8
    for (uint32_t v = 0; v < BLOCK; v++) {
        __m256 b[2];
        blend_vertex(records, in->joints + v * k, in->weights + v * k, k, dqs, b);
        lo[v] = b[0], hi[v] = b[1];
    }
    transpose8(lo, e);
    transpose8(hi, e + 8);
}

/* The n <= 8 vertices of one block, from `in`, written at vertex v of the outputs. */
AVX2 void skin_block(const skin_call *c, const block_in *in, uint32_t v, uint32_t n, uint32_t k, bool dqs)
{
    __m256 e[16], p[3], n_in[3],
        t_in[4] = {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()};
    blend_block(c->records, in, k, dqs, e);
    load3(in->positions, p);
    if (c->out_n)
        load3(in->normals, n_in);
    if (c->out_t)
        load4(in->tangents, t_in);
    __m256 out_p[3], out_n[3] = {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()},
                     out_t[3] = {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()},
                     out_w = _mm256_setzero_ps();
    skin_math_8(e, dqs, p, c->out_n ? n_in : NULL, c->out_t ? t_in : NULL, t_in[3], out_p, out_n, out_t, &out_w);
    size_t at = (size_t)v * c->stride;
    float *op = (float *)((char *)c->out_p + at), *on = c->out_n ? (float *)((char *)c->out_n + at) : NULL;
    if (c->stride == 12 && n == BLOCK) {
        store3(op, out_p);
        if (on)
            store3(on, out_n);
    } else {
        store_strided(op, c->stride, n, out_p, NULL);
        if (on)
            store_strided(on, c->stride, n, out_n, NULL);
    }
    if (c->out_t)
        store_strided((float *)((char *)c->out_t + at), c->stride, n, out_t, &out_w);
}

/* The last n < 8 vertices of a range from v: their inputs copied into zero-padded arrays
 * (padding binds to joint 0 with weight 0), so that the block reads no further than the range. */
AVX2 void skin_tail(const skin_call *c, uint32_t v, uint32_t n, uint32_t k, bool dqs)
{
    const sinew_mesh *m = c->mesh;
    uint16_t joints[BLOCK * SINEW_MAX_INFLUENCES] = {0};
    float weights[BLOCK * SINEW_MAX_INFLUENCES] = {0}, positions[BLOCK * 3] = {0}, normals[BLOCK * 3] = {0};
    float tangents[BLOCK * 4] = {0};
    memcpy(joints, m->joints + (size_t)v * k, (size_t)n * k * sizeof *joints);
    memcpy(weights, m->weights + (size_t)v * k, (size_t)n * k * sizeof *weights);
    memcpy(positions, m->positions + (size_t)v * 3, (size_t)n * 3 * sizeof(float));
    if (c->out_n)
        memcpy(normals, m->normals + (size_t)v * 3, (size_t)n * 3 * sizeof(float));
    if (c->out_t)
        memcpy(tangents, m->tangents + (size_t)v * 4, (size_t)n * 4 * sizeof(float));
    block_in in = {joints, weights, positions, normals, tangents};
    skin_block(c, &in, v, n, k, dqs);
}

/* Every block of the range, with the influence count k and the method known at compile
 * time (an instance a pair). */
AVX2 void skin_blocks(const skin_call *c, uint32_t k, bool dqs)
{
    const sinew_mesh *m = c->mesh;
    uint32_t v = c->first, end = c->first + c->count;
    for (; v + BLOCK <= end; v += BLOCK) {
        block_in in = {m->joints + (size_t)v * k, m->weights + (size_t)v * k, m->positions + (size_t)v * 3,
                       c->out_n ? m->normals + (size_t)v * 3 : NULL, c->out_t ? m->tangents + (size_t)v * 4 : NULL};
        skin_block(c, &in, v, BLOCK, k, dqs);
    }
    if (v < end)
        skin_tail(c, v, end - v, k, dqs);
}

/* The entry point (skin_dispatch.h): influence counts up to SINEW_MAX_INFLUENCES (skin.c sends
 * no other here; skin_tail pads for that many). */
SKIN_KERNEL(AVX2_FN, sinew_skin_avx2)
#endif
