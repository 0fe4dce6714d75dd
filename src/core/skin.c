/* CPU skinning: checks, the scalar reference, dual-quaternion joints, and the choice of path.
 *
 * The reference is skin_range_scalar(): for linear blend (LBS) the weighted sum of the
 * joints' matrices applied to the vertex, normals through the blended matrix's cofactor; for
 * dual quaternions (DQS) the blended scale/shear S, then the blended unit dual quaternion.
 * The SIMD kernels live in skin_x86.c and compute the same arithmetic on the same 16-float
 * joint records (a column-major matrix for LBS, a sinew_dq_joint for DQS); tests hold them
 * within 2e-6 of this code. */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "sinew/anim.h"

/* ---- vector helpers shared by the reference paths ---- */

static void normalize3(float *v)
{
    float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    float inv = len > 0.0f ? 1.0f / len : 0.0f;
    v[0] *= inv, v[1] *= inv, v[2] *= inv;
}

static void cross3(const float *a, const float *b, float *out)
{
    float x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2], z = a[0] * b[1] - a[1] * b[0];
    out[0] = x, out[1] = y, out[2] = z;
}

/* Normal transform for a 3x3 part given as columns c0, c1, c2: the cofactor matrix,
 * which is det * inverse-transpose; its sign is fixed by det so mirrored matrices keep
 * normals outward. Returns det (its sign flips tangent handedness). */
static float transform_normal(const float *m, const float *n, float *out)
{
    const float *c0 = &m[0], *c1 = &m[4], *c2 = &m[8];
    float k0[3], k1[3], k2[3];
    cross3(c1, c2, k0);
    cross3(c2, c0, k1);
    cross3(c0, c1, k2);
    float det = c0[0] * k0[0] + c0[1] * k0[1] + c0[2] * k0[2];
    float sign = det < 0.0f ? -1.0f : 1.0f;
    if (out) {
        out[0] = sign * (k0[0] * n[0] + k1[0] * n[1] + k2[0] * n[2]);
        out[1] = sign * (k0[1] * n[0] + k1[1] * n[1] + k2[1] * n[2]);
        out[2] = sign * (k0[2] * n[0] + k1[2] * n[1] + k2[2] * n[2]);
        normalize3(out);
    }
    return det;
}

static void transform_direction(const float *m, const float *d, float *out)
{
    out[0] = m[0] * d[0] + m[4] * d[1] + m[8] * d[2];
    out[1] = m[1] * d[0] + m[5] * d[1] + m[9] * d[2];
    out[2] = m[2] * d[0] + m[6] * d[1] + m[10] * d[2];
}

static void transform_point(const float *m, const float *p, float *out)
{
    transform_direction(m, p, out);
    out[0] += m[12], out[1] += m[13], out[2] += m[14];
}

/* A tangent (xyz, handedness) through the 3x3 part `m` whose determinant is `det`. */
static void transform_tangent(const float *m, float det, const float *t, float *out)
{
    transform_direction(m, t, out);
    normalize3(out);
    out[3] = det < 0.0f ? -t[3] : t[3];
}

/* ---- checks ---- */

/* The largest of n joint indices, 32 lanes at a time: a loop the compiler vectorises, built
 * for AVX-512BW, AVX2 and the baseline and chosen at run time (not through target_clones:
 * an ifunc resolver runs before a sanitizer's runtime is up). It reads 8 bytes a vertex of
 * 4 influences, a tenth of what skinning reads. */
#define LARGEST_INDEX_BODY                                                                                             \
    {                                                                                                                  \
        uint16_t lanes[32] = {0};                                                                                      \
        size_t i = 0;                                                                                                  \
        for (; i + 32 <= n; i += 32)                                                                                   \
            for (int l = 0; l < 32; l++)                                                                               \
                lanes[l] = joints[i + l] > lanes[l] ? joints[i + l] : lanes[l];                                        \
        uint16_t largest = 0;                                                                                          \
        for (int l = 0; l < 32; l++)                                                                                   \
            largest = lanes[l] > largest ? lanes[l] : largest;                                                         \
        for (; i < n; i++)                                                                                             \
            largest = joints[i] > largest ? joints[i] : largest;                                                       \
        return largest;                                                                                                \
    }

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target("avx512bw"), optimize("tree-vectorize"))) static uint16_t
largest_index_avx512(const uint16_t *joints, size_t n) LARGEST_INDEX_BODY
    __attribute__((target("avx2"), optimize("tree-vectorize"))) static uint16_t
    largest_index_avx2(const uint16_t *joints, size_t n) LARGEST_INDEX_BODY
#endif

    static uint16_t largest_index_plain(const uint16_t *joints, size_t n) LARGEST_INDEX_BODY

    static uint16_t largest_index(const uint16_t *joints, size_t n)
{
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
    if (sinew_cpu_has(SINEW_CPU_AVX512BW))
        return largest_index_avx512(joints, n);
    if (sinew_cpu_has(SINEW_CPU_AVX2))
        return largest_index_avx2(joints, n);
#endif
    return largest_index_plain(joints, n);
}

/* Checks a skinning request and turns it into the kernels' form. */
static sinew_result check_skin(const sinew_skin_desc *desc, skin_call *call, sinew_error *error)
{
    if (!desc || !desc->mesh || !desc->out_positions)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: NULL mesh or output");
    /* the mesh as the kernels see it: the desc's input arrays in place of the mesh's */
    call->view = *desc->mesh;
    if (desc->positions)
        call->view.positions = desc->positions;
    if (desc->normals)
        call->view.normals = desc->normals;
    if (desc->tangents)
        call->view.tangents = desc->tangents;
    const sinew_mesh *mesh = &call->view;
    bool dqs = desc->method == SINEW_SKIN_DUAL_QUATERNION, mixed = desc->method == SINEW_SKIN_MIXED;
    if (desc->method != SINEW_SKIN_LINEAR && !dqs && !mixed)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: unknown method %d",
                          (int)desc->method);
    if ((dqs || mixed) && !desc->dq_palette)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_skin_vertices: NULL dq_palette (dual-quaternion skinning)");
    if (!dqs && !desc->palette)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: NULL palette");
    if (mesh->influence_count == 0 || (mesh->vertex_count && (!mesh->joints || !mesh->weights)))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: mesh \"%s\" is not skinned",
                          mesh->name);
    if (desc->out_tangents && !mesh->tangents && mesh->vertex_count) /* a mesh of no vertices has no arrays */
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: mesh \"%s\" has no tangents",
                          mesh->name);
    if (desc->out_normals && !mesh->normals && mesh->vertex_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: mesh \"%s\" has no normals",
                          mesh->name);
    if (desc->first > mesh->vertex_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_skin_vertices: first vertex %u past the %u vertices", desc->first, mesh->vertex_count);
    uint32_t count = desc->count ? desc->count : mesh->vertex_count - desc->first;
    if (count > mesh->vertex_count - desc->first)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: range %u+%u past the %u vertices",
                          desc->first, count, mesh->vertex_count);
    size_t least = desc->out_tangents ? 4 * sizeof(float) : 3 * sizeof(float);
    size_t stride = desc->out_stride ? desc->out_stride : least;
    if (stride < least || stride > ((size_t)1 << 26))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_skin_vertices: stride %zu outside %zu..2^26 bytes", stride, least);
    /* Every joint index the range uses must be in the palette (the SIMD loops do not
     * check): one pass for the largest, another to name the vertex only when one is out. */
    const uint32_t k = mesh->influence_count;
    const uint16_t *joints = count ? mesh->joints + (size_t)desc->first * k : NULL;
    if (count && largest_index(joints, (size_t)count * k) >= desc->palette_count)
        for (size_t i = 0; i < (size_t)count * k; i++)
            if (joints[i] >= desc->palette_count)
                return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                                  "sinew_skin_vertices: vertex %zu uses joint %u, the palette has %u",
                                  desc->first + i / k, joints[i], desc->palette_count);
    call->mesh = mesh;
    call->records = dqs ? desc->dq_palette[0].real : desc->palette[0].m;
    call->record_count = desc->palette_count;
    call->dqs = dqs;
    call->dq_records = mixed ? desc->dq_palette[0].real : NULL;
    call->mix = mixed ? mesh->dq_weights : NULL;
    call->first = desc->first;
    call->count = count;
    call->out_p = desc->out_positions;
    call->out_n = desc->out_normals;
    call->out_t = desc->out_tangents;
    call->stride = stride;
    return SINEW_OK;
}

/* ---- the scalar reference ---- */

/* Blends a vertex's joint records: weights sorted descending, so the first zero ends it.
 * For DQS the dual quaternion of each joint is taken in the first joint's hemisphere
 * (the scale part is blended as it is). */
static void blend_records(const skin_call *c, const float *records, bool dqs, uint32_t v, float out[16])
{
    const uint32_t k = c->mesh->influence_count;
    const uint16_t *joints = &c->mesh->joints[(size_t)v * k];
    const float *weights = &c->mesh->weights[(size_t)v * k];
    const float *first = records + (size_t)joints[0] * 16;
    memset(out, 0, 16 * sizeof(float));
    for (uint32_t i = 0; i < k && weights[i] != 0.0f; i++) {
        const float *r = records + (size_t)joints[i] * 16;
        float w = weights[i];
        float wq = w;
        if (dqs && r[0] * first[0] + r[1] * first[1] + r[2] * first[2] + r[3] * first[3] < 0.0f)
            wq = -w;
        for (int e = 0; e < 16; e++)
            out[e] += (e < 8 ? wq : w) * r[e];
    }
}

/* v + 2 q.xyz x (q.xyz x v + q.w v) for a unit quaternion q. */
static void rotate(const float *q, const float *v, float *out)
{
    float t[3], u[3];
    cross3(q, v, t);
    t[0] += q[3] * v[0], t[1] += q[3] * v[1], t[2] += q[3] * v[2];
    cross3(q, t, u);
    out[0] = v[0] + 2.0f * u[0], out[1] = v[1] + 2.0f * u[1], out[2] = v[2] + 2.0f * u[2];
}

/* A blended DQS record's scale/shear S as a column-major 4x4 (no translation). */
static void dq_scale_matrix(const float *b, float m[16])
{
    const float *s = b + 8; /* xx yy zz xy xz yz */
    float cols[16] = {s[0], s[3], s[4], 0, s[3], s[1], s[5], 0, s[4], s[5], s[2], 0, 0, 0, 0, 1};
    memcpy(m, cols, sizeof cols);
}

static void skin_vertex_dqs(const skin_call *c, uint32_t v, const float b[16], float *out_p, float *out_n, float *out_t)
{
    const sinew_mesh *mesh = c->mesh;
    float len = sqrtf(b[0] * b[0] + b[1] * b[1] + b[2] * b[2] + b[3] * b[3]);
    float inv = len > 0.0f ? 1.0f / len : 0.0f;
    float q[4] = {b[0] * inv, b[1] * inv, b[2] * inv, b[3] * inv};
    float d[4] = {b[4] * inv, b[5] * inv, b[6] * inv, b[7] * inv};
    float s[16], scaled[4], qd[3];
    dq_scale_matrix(b, s);
    /* translation 2 (q.w d.xyz - d.w q.xyz + q.xyz x d.xyz) */
    cross3(q, d, qd);
    float t[3];
    for (int e = 0; e < 3; e++)
        t[e] = 2.0f * (q[3] * d[e] - d[3] * q[e] + qd[e]);
    transform_direction(s, &mesh->positions[(size_t)v * 3], scaled);
    rotate(q, scaled, out_p);
    out_p[0] += t[0], out_p[1] += t[1], out_p[2] += t[2];
    float det = transform_normal(s, mesh->normals ? &mesh->normals[(size_t)v * 3] : NULL, out_n ? scaled : NULL);
    if (out_n)
        rotate(q, scaled, out_n);
    if (out_t) {
        transform_tangent(s, det, &mesh->tangents[(size_t)v * 4], scaled);
        rotate(q, scaled, out_t);
        out_t[3] = det < 0.0f ? -mesh->tangents[(size_t)v * 4 + 3] : mesh->tangents[(size_t)v * 4 + 3];
    }
}

/* One vertex by one method: the joints' records blended, then applied. */
static void skin_vertex_scalar(const skin_call *c, const float *records, bool dqs, uint32_t v, float *out_p,
                               float *out_n, float *out_t)
{
    const sinew_mesh *mesh = c->mesh;
    float b[16];
    blend_records(c, records, dqs, v, b);
    if (dqs) {
        skin_vertex_dqs(c, v, b, out_p, out_n, out_t);
        return;
    }
    transform_point(b, &mesh->positions[(size_t)v * 3], out_p);
    if (out_n || out_t) {
        float det = transform_normal(b, out_n ? &mesh->normals[(size_t)v * 3] : NULL, out_n);
        if (out_t)
            transform_tangent(b, det, &mesh->tangents[(size_t)v * 4], out_t);
    }
}

/* SINEW_SKIN_MIXED's share of dual-quaternion skinning for vertex v. */
static float mix_at(const skin_call *c, uint32_t v)
{
    return c->mix ? c->mix[v] : 0.0f;
}

static void skin_range_scalar(const skin_call *c)
{
    for (uint32_t v = c->first; v < c->first + c->count; v++) {
        size_t at = (size_t)v * c->stride;
        float *out_p = (float *)((char *)c->out_p + at);
        float *out_n = c->out_n ? (float *)((char *)c->out_n + at) : NULL;
        float *out_t = c->out_t ? (float *)((char *)c->out_t + at) : NULL;
        float a = c->dq_records ? mix_at(c, v) : 0.0f;
        if (!c->dq_records || a <= 0.0f) {
            skin_vertex_scalar(c, c->records, c->dqs, v, out_p, out_n, out_t);
            continue;
        }
        if (a >= 1.0f) {
            skin_vertex_scalar(c, c->dq_records, true, v, out_p, out_n, out_t);
            continue;
        }
        /* (1 - a) * linear + a * dual quaternion */
        float p[3], n[3], t[4];
        skin_vertex_scalar(c, c->records, false, v, out_p, out_n, out_t);
        skin_vertex_scalar(c, c->dq_records, true, v, p, out_n ? n : NULL, out_t ? t : NULL);
        for (int e = 0; e < 3; e++) {
            out_p[e] += a * (p[e] - out_p[e]);
            if (out_n)
                out_n[e] += a * (n[e] - out_n[e]);
            if (out_t)
                out_t[e] += a * (t[e] - out_t[e]);
        }
        if (out_n)
            normalize3(out_n);
        if (out_t)
            normalize3(out_t);
    }
}

/* ---- the choice of path ---- */

static sinew_isa isa_limit = SINEW_ISA_AVX512;

sinew_isa sinew_skin_isa(const skin_call *c)
{
    sinew_isa best = SINEW_ISA_SCALAR;
#if defined(__x86_64__) && defined(__GNUC__)
    if (sinew_cpu_has(SINEW_CPU_AVX512))
        best = SINEW_ISA_AVX512;
    else if (sinew_cpu_has(SINEW_CPU_AVX2_FMA))
        best = SINEW_ISA_AVX2;
#endif
    if (best > isa_limit)
        best = isa_limit;
    /* the AVX2 kernel pads a range's end for at most SINEW_MAX_INFLUENCES influences (a
     * model's meshes have no more; one built by hand might) */
    if (best == SINEW_ISA_AVX2 && c && c->mesh->influence_count > SINEW_MAX_INFLUENCES)
        best = SINEW_ISA_SCALAR;
    return best;
}

sinew_isa sinew_skin_set_isa_limit(sinew_isa limit)
{
    sinew_isa previous = isa_limit;
    isa_limit = limit;
    return previous;
}

const char *sinew_simd_name(void)
{
    static const char *names[] = {"scalar", "avx2+fma", "avx512"};
    return names[sinew_skin_isa(NULL)];
}

sinew_result sinew_skin_vertices_scalar(const sinew_skin_desc *desc, sinew_error *error)
{
    skin_call call;
    sinew_result result = check_skin(desc, &call, error);
    if (result == SINEW_OK)
        skin_range_scalar(&call);
    return result;
}

/* Records copied to 64-byte alignment for a SIMD kernel when the caller's are not and the copy
 * pays: a vertex whose joints differ from its neighbours' loads a joint's 64-byte record
 * (AVX-512: one load, AVX2: two), and a load that crosses a cache line costs two (out-of-order
 * influences skin 15% faster aligned on AVX-512, 5-10% on AVX2 from malloc's 16-byte
 * alignment). On the stack, so at most ALIGNED_RECORDS of them. */
#define ALIGNED_RECORDS 256

/* A range by one method on the best path this processor has. */
static void skin_range(const skin_call *call)
{
    sinew_isa isa = sinew_skin_isa(call);
    if (isa == SINEW_ISA_SCALAR) {
        skin_range_scalar(call);
        return;
    }
#if defined(__x86_64__) && defined(__GNUC__)
    void (*kernel)(const skin_call *) = isa == SINEW_ISA_AVX512 ? sinew_skin_avx512 : sinew_skin_avx2;
    if (((uintptr_t)call->records & 63) != 0 && call->record_count <= ALIGNED_RECORDS && call->count >= 64 &&
        call->count >= call->record_count) {
        _Alignas(64) float aligned[ALIGNED_RECORDS * 16];
        memcpy(aligned, call->records, (size_t)call->record_count * 16 * sizeof(float));
        skin_call copy = *call;
        copy.records = aligned;
        kernel(&copy);
        return;
    }
    kernel(call);
#endif
}

/* SINEW_SKIN_MIXED: runs of vertices all linear or all dual quaternion go to the SIMD paths
 * as they are; vertices in between mix the two in the reference code. */
static void skin_range_mixed(const skin_call *call)
{
    uint32_t end = call->first + call->count;
    for (uint32_t v = call->first; v < end;) {
        float a = mix_at(call, v);
        int kind = a <= 0.0f ? 0 : a >= 1.0f ? 2 : 1;
        uint32_t run = v + 1;
        while (run < end) {
            float b = mix_at(call, run);
            if ((b <= 0.0f ? 0 : b >= 1.0f ? 2 : 1) != kind)
                break;
            run++;
        }
        skin_call part = *call;
        part.first = v;
        part.count = run - v;
        if (kind == 1) {
            skin_range_scalar(&part);
        } else {
            if (kind == 2)
                part.records = call->dq_records, part.dqs = true;
            part.dq_records = NULL;
            skin_range(&part);
        }
        v = run;
    }
}

sinew_result sinew_skin_vertices(const sinew_skin_desc *desc, sinew_error *error)
{
    skin_call call;
    sinew_result result = check_skin(desc, &call, error);
    if (result != SINEW_OK || call.count == 0)
        return result;
    if (call.dq_records)
        skin_range_mixed(&call);
    else
        skin_range(&call);
    return SINEW_OK;
}

/* ---- dual-quaternion joints ---- */

typedef double dmat3[3][3]; /* [column][row] */

static double det3(dmat3 a)
{
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[1][0] * (a[0][1] * a[2][2] - a[0][2] * a[2][1]) +
           a[2][0] * (a[0][1] * a[1][2] - a[0][2] * a[1][1]);
}

/* out = a^-T (a non-singular). */
static void inverse_transpose3(dmat3 a, double det, dmat3 out)
{
    /* the cofactor matrix over det is the inverse transpose */
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++) {
            int c1 = (c + 1) % 3, c2 = (c + 2) % 3, r1 = (r + 1) % 3, r2 = (r + 2) % 3;
            out[c][r] = (a[c1][r1] * a[c2][r2] - a[c1][r2] * a[c2][r1]) / det;
        }
}

static double norm3(dmat3 a)
{
    double s = 0.0;
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            s += a[c][r] * a[c][r];
    return sqrt(s);
}

/* The rotation of the polar decomposition of `a` (det > 0) by Higham's scaled Newton
 * iteration X <- (g X + X^-T / g) / 2; false when it does not settle. */
static bool polar_rotation(dmat3 a, dmat3 out)
{
    dmat3 x;
    memcpy(x, a, sizeof x);
    for (int it = 0; it < 40; it++) {
        double det = det3(x);
        if (!(fabs(det) > 1e-300))
            return false;
        dmat3 it_x;
        inverse_transpose3(x, det, it_x);
        double g = sqrt(norm3(it_x) / norm3(x));
        double change = 0.0;
        for (int c = 0; c < 3; c++)
            for (int r = 0; r < 3; r++) {
                double next = 0.5 * (g * x[c][r] + it_x[c][r] / g);
                change = fmax(change, fabs(next - x[c][r]));
                x[c][r] = next;
            }
        if (change < 1e-13)
            break;
    }
    memcpy(out, x, sizeof x);
    return fabs(det3(out) - 1.0) < 1e-6;
}

/* Unit quaternion (x y z w) of a rotation matrix (Shepperd's method). */
static void rotation_quaternion(dmat3 m, double q[4])
{
    double tr = m[0][0] + m[1][1] + m[2][2];
    if (tr > 0.0) {
        double s = 2.0 * sqrt(tr + 1.0);
        q[3] = 0.25 * s, q[0] = (m[1][2] - m[2][1]) / s, q[1] = (m[2][0] - m[0][2]) / s, q[2] = (m[0][1] - m[1][0]) / s;
    } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
        double s = 2.0 * sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]);
        q[3] = (m[1][2] - m[2][1]) / s, q[0] = 0.25 * s, q[1] = (m[1][0] + m[0][1]) / s, q[2] = (m[2][0] + m[0][2]) / s;
    } else if (m[1][1] > m[2][2]) {
        double s = 2.0 * sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]);
        q[3] = (m[2][0] - m[0][2]) / s, q[0] = (m[1][0] + m[0][1]) / s, q[1] = 0.25 * s, q[2] = (m[2][1] + m[1][2]) / s;
    } else {
        double s = 2.0 * sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]);
        q[3] = (m[0][1] - m[1][0]) / s, q[0] = (m[2][0] + m[0][2]) / s, q[1] = (m[2][1] + m[1][2]) / s, q[2] = 0.25 * s;
    }
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int e = 0; e < 4; e++)
        q[e] /= n;
}

static void dq_joint(const sinew_mat4 *matrix, sinew_dq_joint *out)
{
    const float *m = matrix->m;
    dmat3 a, r;
    for (int c = 0; c < 3; c++)
        for (int e = 0; e < 3; e++)
            a[c][e] = m[c * 4 + e];
    double det = det3(a), scale = norm3(a);
    bool found = false;
    if (fabs(det) > 1e-9 * scale * scale * scale) {
        /* a mirror (det < 0) goes into S: the rotation of -a, S = R^T a */
        dmat3 signed_a;
        for (int c = 0; c < 3; c++)
            for (int e = 0; e < 3; e++)
                signed_a[c][e] = det < 0.0 ? -a[c][e] : a[c][e];
        found = polar_rotation(signed_a, r);
    }
    if (!found) {
        sinew_transform t;
        sinew_mat4_decompose(matrix, &t);
        double x = t.rotation[0], y = t.rotation[1], z = t.rotation[2], w = t.rotation[3];
        dmat3 from_q = {{1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w)},
                        {2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w)},
                        {2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)}};
        memcpy(r, from_q, sizeof r);
    }
    /* S = R^T a, made exactly symmetric */
    double s[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            s[i][j] = r[i][0] * a[j][0] + r[i][1] * a[j][1] + r[i][2] * a[j][2]; /* row i of R^T . column j */
    double q[4];
    rotation_quaternion(r, q);
    double t[3] = {m[12], m[13], m[14]};
    /* dual = 0.5 * (t, 0) * q */
    double dual[4] = {0.5 * (q[3] * t[0] + t[1] * q[2] - t[2] * q[1]), 0.5 * (q[3] * t[1] + t[2] * q[0] - t[0] * q[2]),
                      0.5 * (q[3] * t[2] + t[0] * q[1] - t[1] * q[0]),
                      -0.5 * (t[0] * q[0] + t[1] * q[1] + t[2] * q[2])};
    memset(out, 0, sizeof *out);
    for (int e = 0; e < 4; e++)
        out->real[e] = (float)q[e], out->dual[e] = (float)dual[e];
    /* s[i][j] = S row i, column j */
    out->scale[0] = (float)s[0][0];
    out->scale[1] = (float)s[1][1];
    out->scale[2] = (float)s[2][2];
    out->scale[3] = (float)(0.5 * (s[0][1] + s[1][0]));
    out->scale[4] = (float)(0.5 * (s[0][2] + s[2][0]));
    out->scale[5] = (float)(0.5 * (s[1][2] + s[2][1]));
}

sinew_result sinew_skin_dq_palette(const sinew_mat4 *palette, uint32_t count, sinew_dq_joint *out, sinew_error *error)
{
    if (count && (!palette || !out))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_dq_palette: NULL palette or output");
    for (uint32_t j = 0; j < count; j++)
        dq_joint(&palette[j], &out[j]);
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
