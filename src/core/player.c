/* sinew_player: one clip played on one character, fast.
 *
 * At creation the clip's channels are grouped by their key times: channels whose time
 * arrays are equal (and that interpolate alike) form one group, and a group's keys are
 * stored key-major, one row of floats a key holding every component of every channel
 * of the group (a "lane" each). Forward playback then finds one segment a group (a cursor
 * that steps ahead), and interpolates two neighbouring rows lane by lane, straight into
 * the pose, which is kept as a structure of arrays (translation x of every node, then
 * y, ...). Rotations are interpolated component-wise (nlerp) and normalised when the
 * local matrices are built, 8 nodes at a time; then each node's world matrix is its
 * parent's times its local one. Channels with one key and nodes with no channel are
 * written into the pose once, at creation. Nothing is allocated after creation.
 *
 * nlerp is within 5e-7 rad of slerp when neighbouring keys are less than 0.03 rad apart on
 * the quaternion sphere (any clip keyed 30 times a second that turns less than 100 degrees
 * a second); a rotation channel with a wider segment anywhere is slerped after the blend,
 * so sparse keys (two keys a quarter turn apart) come out exact too.
 *
 * SIMD: AVX2+FMA paths where the processor has them, chosen once; the scalar functions
 * beside them are the reference (tests/core/test_player.c compares the two, and the
 * player with sinew_sample() + sinew_local_to_world()).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "sinew/anim.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PLAYER_X86 1
#endif

enum { C_TX, C_TY, C_TZ, C_QX, C_QY, C_QZ, C_QW, C_SX, C_SY, C_SZ, C_COUNT };
enum { M_00, M_01, M_02, M_10, M_11, M_12, M_20, M_21, M_22, M_COUNT }; /* M_cr: column c, row r */

typedef struct run {
    uint32_t dst;  /* index into the pose */
    uint32_t lane; /* first lane of the row */
    uint32_t length;
} run;

/* A rotation channel slerped after the blend: its lanes in the row, its places in the pose. */
typedef struct slerp_fix {
    uint32_t lane[4];
    uint32_t dst[4];
} slerp_fix;

typedef struct group {
    uint32_t key_count;
    uint32_t interp;
    uint32_t lane_count;
    uint32_t row_floats; /* lane_count, or 3 * lane_count for cubic (value, in, out) */
    uint32_t run_count;
    uint32_t fix_count;
    uint32_t cursor;
    const float *times; /* the clip's, key_count */
    float *rows;        /* key_count * row_floats */
    run *runs;
    slerp_fix *fixes;
} group;

struct sinew_player {
    const sinew_model *model;
    const sinew_clip *clip;
    uint32_t node_count, stride; /* stride: node_count rounded up to 8 */
    bool simd;
    float *pose;   /* C_COUNT * stride */
    float *locals; /* M_COUNT * stride: rotation * scale */
    uint32_t group_count;
    group *groups;
    void *block; /* everything above, one allocation */
};

/* ---- building -------------------------------------------------------------------------- */

typedef struct lane_src {
    uint32_t dst;
    uint32_t channel; /* index into the channel list */
    uint32_t component;
} lane_src;

typedef struct channel_ref {
    const sinew_channel *channel;
    uint32_t node, kind, group;
} channel_ref;

static int compare_lanes(const void *a, const void *b)
{
    const lane_src *x = a, *y = b;
    return x->dst < y->dst ? -1 : x->dst > y->dst;
}

static uint32_t pose_component(uint32_t kind, uint32_t i)
{
    return kind == SINEW_CHANNEL_TRANSLATION ? C_TX + i : kind == SINEW_CHANNEL_ROTATION ? C_QX + i : C_SX + i;
}

static bool same_times(const sinew_clip *clip, const sinew_channel *a, const sinew_channel *b)
{
    return a->key_count == b->key_count && a->interp == b->interp &&
           memcmp(clip->times + a->first_key, clip->times + b->first_key, a->key_count * sizeof(float)) == 0;
}

/* True when neighbouring keys of a rotation channel are far enough apart on the quaternion
 * sphere (over 0.03 rad) that nlerp would stray from slerp by more than 5e-7 rad. */
static bool wide_segment(const sinew_clip *clip, const sinew_channel *ch)
{
    const float *q = clip->values + ch->first_value;
    for (uint32_t k = 0; k + 1 < ch->key_count; k++, q += 4) {
        float dot = fabsf(q[0] * q[4] + q[1] * q[5] + q[2] * q[6] + q[3] * q[7]);
        if (dot < 0.9995f)
            return true;
    }
    return false;
}

static void write_rest(sinew_player *p)
{
    const sinew_model *m = p->model;
    for (uint32_t c = 0; c < C_COUNT; c++)
        for (uint32_t i = 0; i < p->stride; i++)
            p->pose[c * p->stride + i] = c == C_QW || c >= C_SX ? 1.0f : 0.0f;
    for (uint32_t i = 0; i < m->node_count; i++) {
        const sinew_transform *r = &m->node_rest[i];
        for (uint32_t k = 0; k < 3; k++) {
            p->pose[(C_TX + k) * p->stride + i] = r->translation[k];
            p->pose[(C_SX + k) * p->stride + i] = r->scale[k];
        }
        for (uint32_t k = 0; k < 4; k++)
            p->pose[(C_QX + k) * p->stride + i] = r->rotation[k];
    }
}

sinew_result sinew_player_create(const sinew_model *model, const sinew_clip *clip, sinew_player **out,
                                 sinew_error *error)
{
    if (!model || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_player_create: NULL model or output");
    *out = NULL;
    uint32_t track_count = clip ? clip->track_count : 0;
    channel_ref *refs = calloc((size_t)track_count * SINEW_CHANNEL_COUNT + 1, sizeof *refs);
    uint32_t *group_first = calloc((size_t)track_count * SINEW_CHANNEL_COUNT + 1, sizeof *group_first);
    if (!refs || !group_first) {
        free(refs);
        free(group_first);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for a player", model->source);
    }
    /* Channels with two keys or more, grouped by equal times (first channel of each group
     * in group_first); one-key channels are constants, written with the rest pose. */
    uint32_t ref_count = 0, group_count = 0;
    size_t lanes_total = 0, floats_total = 0;
    for (uint32_t t = 0; t < track_count; t++)
        for (uint32_t k = 0; k < SINEW_CHANNEL_COUNT; k++) {
            const sinew_channel *ch = &clip->tracks[t].channels[k];
            if (ch->key_count < 2)
                continue;
            uint32_t g = 0;
            while (g < group_count && !same_times(clip, refs[group_first[g]].channel, ch))
                g++;
            if (g == group_count)
                group_first[group_count++] = ref_count;
            refs[ref_count++] = (channel_ref){ch, clip->tracks[t].node, k, g};
            uint32_t width = sinew_channel_width((int)k);
            lanes_total += width;
            floats_total += (size_t)width * ch->key_count * sinew_interp_floats(ch->interp);
        }

    uint32_t n = model->node_count, stride = (n + 7u) & ~7u;
    if (stride == 0)
        stride = 8;
    size_t bytes = sizeof(sinew_player) + (size_t)C_COUNT * stride * 4 + (size_t)M_COUNT * stride * 4 +
                   group_count * (sizeof(group) + 64) + floats_total * 4 + lanes_total * sizeof(run) +
                   ref_count * sizeof(slerp_fix) + 64;
    unsigned char *block = aligned_alloc(32, (bytes + 31) & ~(size_t)31);
    lane_src *lanes = malloc((lanes_total + 1) * sizeof *lanes);
    if (!block || !lanes) {
        free(block);
        free(lanes);
        free(refs);
        free(group_first);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for a player", model->source);
    }
    sinew_player *p = (sinew_player *)block;
    *p = (sinew_player){.model = model, .clip = clip, .node_count = n, .stride = stride, .block = block};
#ifdef PLAYER_X86
    p->simd = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#endif
    unsigned char *at = block + ((sizeof *p + 31) & ~(size_t)31);
    p->pose = (float *)at;
    at += (size_t)C_COUNT * stride * 4;
    p->locals = (float *)at;
    at += (size_t)M_COUNT * stride * 4;
    p->groups = (group *)at;
    p->group_count = group_count;
    at += group_count * sizeof(group);
    write_rest(p);

    /* Constants: one-key channels. */
    for (uint32_t t = 0; t < track_count; t++)
        for (uint32_t k = 0; k < SINEW_CHANNEL_COUNT; k++) {
            const sinew_channel *ch = &clip->tracks[t].channels[k];
            if (ch->key_count != 1)
                continue;
            const float *v =
                clip->values + ch->first_value + (ch->interp == SINEW_INTERP_CUBIC ? sinew_channel_width((int)k) : 0);
            for (uint32_t i = 0; i < sinew_channel_width((int)k); i++)
                p->pose[pose_component(k, i) * stride + clip->tracks[t].node] = v[i];
        }

    for (uint32_t g = 0; g < group_count; g++) {
        group *gr = &p->groups[g];
        const channel_ref *first = &refs[group_first[g]];
        uint32_t lane_count = 0;
        for (uint32_t r = 0; r < ref_count; r++) {
            if (refs[r].group != g)
                continue;
            for (uint32_t i = 0; i < sinew_channel_width((int)refs[r].kind); i++)
                lanes[lane_count++] = (lane_src){pose_component(refs[r].kind, i) * stride + refs[r].node, r, i};
        }
        qsort(lanes, lane_count, sizeof *lanes, compare_lanes);
        bool cubic = first->channel->interp == SINEW_INTERP_CUBIC;
        *gr = (group){.key_count = first->channel->key_count,
                      .interp = first->channel->interp,
                      .lane_count = lane_count,
                      .row_floats = lane_count * sinew_interp_floats(first->channel->interp),
                      .times = clip->times + first->channel->first_key};
        gr->rows = (float *)at;
        at += (size_t)gr->row_floats * gr->key_count * 4;
        gr->runs = (run *)at;
        /* Rows: for each key, the lanes' values (then in-tangents, out-tangents). */
        for (uint32_t l = 0; l < lane_count; l++) {
            const channel_ref *ref = &refs[lanes[l].channel];
            uint32_t width = sinew_channel_width((int)ref->kind);
            uint32_t key_stride = sinew_channel_stride((int)ref->kind, ref->channel->interp);
            const float *src = clip->values + ref->channel->first_value + lanes[l].component;
            for (uint32_t key = 0; key < gr->key_count; key++) {
                float *row = gr->rows + (size_t)key * gr->row_floats;
                const float *kv = src + (size_t)key * key_stride;
                if (cubic) {
                    row[l] = kv[width];                      /* value */
                    row[lane_count + l] = kv[0];             /* in-tangent */
                    row[2 * lane_count + l] = kv[2 * width]; /* out-tangent */
                } else if (gr->interp == SINEW_INTERP_BEZIER) {
                    for (uint32_t j = 0; j < 5; j++) /* value, in time, in value, out time, out value */
                        row[j * lane_count + l] = kv[j * width];
                } else {
                    row[l] = kv[0];
                }
            }
            if (gr->run_count > 0) {
                run *last = &gr->runs[gr->run_count - 1];
                if (last->dst + last->length == lanes[l].dst) {
                    last->length++;
                    continue;
                }
            }
            gr->runs[gr->run_count++] = (run){lanes[l].dst, l, 1};
        }
        at += (size_t)gr->run_count * sizeof(run);
        at = (unsigned char *)(((uintptr_t)at + 31) & ~(uintptr_t)31);
        gr->fixes = (slerp_fix *)at;
        for (uint32_t r = 0; r < ref_count; r++)
            if (refs[r].group == g && refs[r].kind == SINEW_CHANNEL_ROTATION &&
                refs[r].channel->interp == SINEW_INTERP_LINEAR && wide_segment(clip, refs[r].channel)) {
                slerp_fix *fix = &gr->fixes[gr->fix_count++];
                for (uint32_t l = 0; l < lane_count; l++)
                    if (lanes[l].channel == r) {
                        fix->lane[lanes[l].component] = l;
                        fix->dst[lanes[l].component] = lanes[l].dst;
                    }
            }
        at += (size_t)gr->fix_count * sizeof(slerp_fix);
        at = (unsigned char *)(((uintptr_t)at + 31) & ~(uintptr_t)31);
    }
    free(lanes);
    free(refs);
    free(group_first);
    *out = p;
    return SINEW_OK;
}

sinew_result sinew_player_clone(const sinew_player *source, sinew_player **out, sinew_error *error)
{
    if (!source || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_player_clone: NULL player or output");
    *out = NULL;
    /* Own: the player, the pose and local matrices, the groups (for their cursors);
     * shared: the key rows, runs and slerp lists the groups point to. */
    size_t head = (sizeof *source + 31) & ~(size_t)31;
    size_t pose = (size_t)C_COUNT * source->stride * 4, locals = (size_t)M_COUNT * source->stride * 4;
    size_t groups = source->group_count * sizeof(group);
    unsigned char *block = aligned_alloc(32, (head + pose + locals + groups + 31) & ~(size_t)31);
    if (!block)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for a player", source->model->source);
    sinew_player *p = (sinew_player *)block;
    *p = *source;
    p->block = block;
    p->pose = (float *)(block + head);
    p->locals = (float *)(block + head + pose);
    p->groups = (group *)(block + head + pose + locals);
    memcpy(p->pose, source->pose, pose);
    memcpy(p->groups, source->groups, groups);
    for (uint32_t g = 0; g < p->group_count; g++)
        p->groups[g].cursor = 0;
    *out = p;
    return SINEW_OK;
}

void sinew_player_free(sinew_player *player)
{
    if (player)
        free(player->block);
}

void sinew_player_set_simd(sinew_player *player, bool simd)
{
#ifdef PLAYER_X86
    player->simd = simd && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    (void)simd;
    player->simd = false;
#endif
}

/* ---- sampling ---------------------------------------------------------------------------- */

/* Segment k and blend weights of a group at t: out = wa * row[k] + wb * row[k + 1] for
 * linear; Hermite weights for cubic. Returns false when one row is copied (row k). */
typedef struct segment {
    uint32_t k;
    bool copy;
    float s, dt;
    float t; /* the time (Bezier segments solve for their parameter) */
} segment;

static segment find(group *g, float t)
{
    const float *times = g->times;
    uint32_t n = g->key_count;
    if (t <= times[0])
        return (segment){0, true, 0, 0, t};
    if (t >= times[n - 1])
        return (segment){n - 1, true, 0, 0, t};
    uint32_t k = sinew_find_segment(times, n, t, &g->cursor);
    float dt = times[k + 1] - times[k];
    float s = dt > 0.0f ? (t - times[k]) / dt : 0.0f;
    return (segment){k, g->interp == SINEW_INTERP_STEP, s, dt, t};
}

/* Hermite basis for a cubic segment: value a, out-tangent a, value b, in-tangent b. */
static void hermite_weights(float s, float dt, float w[4])
{
    float s2 = s * s, s3 = s2 * s;
    w[0] = 2.0f * s3 - 3.0f * s2 + 1.0f;
    w[1] = (s3 - 2.0f * s2 + s) * dt;
    w[2] = -2.0f * s3 + 3.0f * s2;
    w[3] = (s3 - s2) * dt;
}

/* The group's wide rotation channels, slerped over what the blend wrote. */
static void slerp_fixes(float *pose, const group *g, const segment *seg)
{
    if (seg->copy || g->interp != SINEW_INTERP_LINEAR)
        return;
    const float *a = g->rows + (size_t)seg->k * g->row_floats;
    const float *b = a + g->row_floats;
    for (uint32_t f = 0; f < g->fix_count; f++) {
        const slerp_fix *fix = &g->fixes[f];
        float qa[4], qb[4], q[4];
        for (int c = 0; c < 4; c++)
            qa[c] = a[fix->lane[c]], qb[c] = b[fix->lane[c]];
        sinew_slerp_shortest(qa, qb, seg->s, q);
        for (int c = 0; c < 4; c++)
            pose[fix->dst[c]] = q[c];
    }
}

static void blend_scalar(float *pose, const group *g, const segment *seg)
{
    const float *a = g->rows + (size_t)seg->k * g->row_floats;
    const float *b = a + g->row_floats;
    const uint32_t L = g->lane_count;
    float w[4] = {1.0f - seg->s, 0.0f, seg->s, 0.0f};
    if (g->interp == SINEW_INTERP_CUBIC && !seg->copy)
        hermite_weights(seg->s, seg->dt, w);
    for (uint32_t r = 0; r < g->run_count; r++) {
        const run *ru = &g->runs[r];
        float *dst = pose + ru->dst;
        const float *va = a + ru->lane;
        if (seg->copy) {
            memcpy(dst, va, ru->length * sizeof(float));
        } else if (g->interp == SINEW_INTERP_CUBIC) {
            const float *oa = va + 2 * L, *vb = b + ru->lane, *ib = vb + L;
            for (uint32_t i = 0; i < ru->length; i++)
                dst[i] = w[0] * va[i] + w[1] * oa[i] + w[2] * vb[i] + w[3] * ib[i];
        } else if (g->interp == SINEW_INTERP_BEZIER) {
            /* each lane solves its own time polynomial (its control times are its own) */
            const float *vb = b + ru->lane, t0 = g->times[seg->k], t3 = g->times[seg->k + 1];
            for (uint32_t i = 0; i < ru->length; i++)
                dst[i] =
                    sinew_bezier(t0, va[i], va[3 * L + i], va[4 * L + i], vb[L + i], vb[2 * L + i], t3, vb[i], seg->t);
        } else {
            const float *vb = b + ru->lane;
            for (uint32_t i = 0; i < ru->length; i++)
                dst[i] = va[i] + (vb[i] - va[i]) * seg->s;
        }
    }
}

/* Local rotation*scale matrices of nodes [0, stride) from the pose. */
static void locals_scalar(sinew_player *p)
{
    const uint32_t S = p->stride;
    const float *P = p->pose;
    float *M = p->locals;
    for (uint32_t i = 0; i < S; i++) {
        float x = P[C_QX * S + i], y = P[C_QY * S + i], z = P[C_QZ * S + i], w = P[C_QW * S + i];
        float n = x * x + y * y + z * z + w * w;
        float s = n > 0.0f ? 2.0f / n : 0.0f;
        float xx = s * x * x, yy = s * y * y, zz = s * z * z;
        float xy = s * x * y, xz = s * x * z, yz = s * y * z;
        float wx = s * w * x, wy = s * w * y, wz = s * w * z;
        float sx = P[C_SX * S + i], sy = P[C_SY * S + i], sz = P[C_SZ * S + i];
        M[M_00 * S + i] = (1.0f - yy - zz) * sx;
        M[M_01 * S + i] = (xy + wz) * sx;
        M[M_02 * S + i] = (xz - wy) * sx;
        M[M_10 * S + i] = (xy - wz) * sy;
        M[M_11 * S + i] = (1.0f - xx - zz) * sy;
        M[M_12 * S + i] = (yz + wx) * sy;
        M[M_20 * S + i] = (xz + wy) * sz;
        M[M_21 * S + i] = (yz - wx) * sz;
        M[M_22 * S + i] = (1.0f - xx - yy) * sz;
    }
}

/* A node whose inherit type is not NORMAL (sinew_inherit): its world from the pose's TRS. */
static bool world_inherit(const sinew_player *p, uint32_t i, sinew_mat4 *worlds)
{
    const sinew_model *m = p->model;
    if (!m->node_inherit || m->node_inherit[i] == SINEW_INHERIT_NORMAL || m->node_parents[i] < 0)
        return false;
    const uint32_t S = p->stride;
    const float *P = p->pose;
    float t[3] = {P[C_TX * S + i], P[C_TY * S + i], P[C_TZ * S + i]};
    float q[4] = {P[C_QX * S + i], P[C_QY * S + i], P[C_QZ * S + i], P[C_QW * S + i]};
    float s[3] = {P[C_SX * S + i], P[C_SY * S + i], P[C_SZ * S + i]};
    pose_world_inherit(m, i, t, q, s, (pose_scales){P + C_SX * S, 1, S}, worlds, &worlds[i]);
    return true;
}

static void world_scalar(const sinew_player *p, const sinew_mat4 *root, sinew_mat4 *worlds)
{
    const uint32_t S = p->stride;
    const float *M = p->locals, *P = p->pose;
    for (uint32_t i = 0; i < p->node_count; i++) {
        if (world_inherit(p, i, worlds))
            continue;
        float l[16] = {M[M_00 * S + i], M[M_01 * S + i], M[M_02 * S + i], 0.0f,
                       M[M_10 * S + i], M[M_11 * S + i], M[M_12 * S + i], 0.0f,
                       M[M_20 * S + i], M[M_21 * S + i], M[M_22 * S + i], 0.0f,
                       P[C_TX * S + i], P[C_TY * S + i], P[C_TZ * S + i], 1.0f};
        int32_t parent = p->model->node_parents[i];
        const float *b = parent >= 0 ? worlds[parent].m : root ? root->m : NULL;
        float *o = worlds[i].m;
        if (!b) {
            memcpy(o, l, sizeof l);
            continue;
        }
        for (int c = 0; c < 4; c++)
            for (int r = 0; r < 4; r++)
                o[c * 4 + r] =
                    b[r] * l[c * 4] + b[4 + r] * l[c * 4 + 1] + b[8 + r] * l[c * 4 + 2] + b[12 + r] * l[c * 4 + 3];
    }
}

#ifdef PLAYER_X86
__attribute__((target("avx2,fma"))) static void blend_avx2(float *pose, const group *g, const segment *seg)
{
    const float *a = g->rows + (size_t)seg->k * g->row_floats;
    const float *b = a + g->row_floats;
    if (seg->copy || g->interp != SINEW_INTERP_LINEAR) {
        blend_scalar(pose, g, seg);
        return;
    }
    const __m256 s8 = _mm256_set1_ps(seg->s);
    for (uint32_t r = 0; r < g->run_count; r++) {
        const run *ru = &g->runs[r];
        float *dst = pose + ru->dst;
        const float *va = a + ru->lane, *vb = b + ru->lane;
        uint32_t i = 0;
        for (; i + 8 <= ru->length; i += 8) {
            __m256 x = _mm256_loadu_ps(va + i), y = _mm256_loadu_ps(vb + i);
            _mm256_storeu_ps(dst + i, _mm256_fmadd_ps(_mm256_sub_ps(y, x), s8, x));
        }
        for (; i < ru->length; i++)
            dst[i] = fmaf(vb[i] - va[i], seg->s, va[i]);
    }
}

__attribute__((target("avx2,fma"))) static void locals_avx2(sinew_player *p)
{
    const uint32_t S = p->stride;
    const float *P = p->pose;
    float *M = p->locals;
    const __m256 one = _mm256_set1_ps(1.0f), two = _mm256_set1_ps(2.0f), zero = _mm256_setzero_ps();
    for (uint32_t i = 0; i < S; i += 8) {
        __m256 x = _mm256_load_ps(P + C_QX * S + i), y = _mm256_load_ps(P + C_QY * S + i);
        __m256 z = _mm256_load_ps(P + C_QZ * S + i), w = _mm256_load_ps(P + C_QW * S + i);
        __m256 n = _mm256_fmadd_ps(x, x, _mm256_fmadd_ps(y, y, _mm256_fmadd_ps(z, z, _mm256_mul_ps(w, w))));
        __m256 s = _mm256_and_ps(_mm256_div_ps(two, n), _mm256_cmp_ps(n, zero, _CMP_GT_OQ));
        __m256 xs = _mm256_mul_ps(x, s), ys = _mm256_mul_ps(y, s), zs = _mm256_mul_ps(z, s);
        __m256 xx = _mm256_mul_ps(xs, x), yy = _mm256_mul_ps(ys, y), zz = _mm256_mul_ps(zs, z);
        __m256 xy = _mm256_mul_ps(xs, y), xz = _mm256_mul_ps(xs, z), yz = _mm256_mul_ps(ys, z);
        __m256 wx = _mm256_mul_ps(xs, w), wy = _mm256_mul_ps(ys, w), wz = _mm256_mul_ps(zs, w);
        __m256 sx = _mm256_load_ps(P + C_SX * S + i), sy = _mm256_load_ps(P + C_SY * S + i);
        __m256 sz = _mm256_load_ps(P + C_SZ * S + i);
        _mm256_store_ps(M + M_00 * S + i, _mm256_mul_ps(_mm256_sub_ps(_mm256_sub_ps(one, yy), zz), sx));
        _mm256_store_ps(M + M_01 * S + i, _mm256_mul_ps(_mm256_add_ps(xy, wz), sx));
        _mm256_store_ps(M + M_02 * S + i, _mm256_mul_ps(_mm256_sub_ps(xz, wy), sx));
        _mm256_store_ps(M + M_10 * S + i, _mm256_mul_ps(_mm256_sub_ps(xy, wz), sy));
        _mm256_store_ps(M + M_11 * S + i, _mm256_mul_ps(_mm256_sub_ps(_mm256_sub_ps(one, xx), zz), sy));
        _mm256_store_ps(M + M_12 * S + i, _mm256_mul_ps(_mm256_add_ps(yz, wx), sy));
        _mm256_store_ps(M + M_20 * S + i, _mm256_mul_ps(_mm256_add_ps(xz, wy), sz));
        _mm256_store_ps(M + M_21 * S + i, _mm256_mul_ps(_mm256_sub_ps(yz, wx), sz));
        _mm256_store_ps(M + M_22 * S + i, _mm256_mul_ps(_mm256_sub_ps(_mm256_sub_ps(one, xx), yy), sz));
    }
}

__attribute__((target("avx2,fma"))) static void world_avx2(const sinew_player *p, const sinew_mat4 *root,
                                                           sinew_mat4 *worlds)
{
    const uint32_t S = p->stride;
    const float *M = p->locals, *P = p->pose;
    const int32_t *parents = p->model->node_parents;
    for (uint32_t i = 0; i < p->node_count; i++) {
        if (world_inherit(p, i, worlds))
            continue;
        int32_t parent = parents[i];
        const float *b = parent >= 0 ? worlds[parent].m : root ? root->m : NULL;
        float *o = worlds[i].m;
        if (!b) {
            const float l[16] = {M[M_00 * S + i], M[M_01 * S + i], M[M_02 * S + i], 0.0f,
                                 M[M_10 * S + i], M[M_11 * S + i], M[M_12 * S + i], 0.0f,
                                 M[M_20 * S + i], M[M_21 * S + i], M[M_22 * S + i], 0.0f,
                                 P[C_TX * S + i], P[C_TY * S + i], P[C_TZ * S + i], 1.0f};
            memcpy(o, l, sizeof l);
            continue;
        }
        __m128 b0 = _mm_loadu_ps(b), b1 = _mm_loadu_ps(b + 4), b2 = _mm_loadu_ps(b + 8), b3 = _mm_loadu_ps(b + 12);
        __m128 c0 = _mm_fmadd_ps(
            b2, _mm_broadcast_ss(M + M_02 * S + i),
            _mm_fmadd_ps(b1, _mm_broadcast_ss(M + M_01 * S + i), _mm_mul_ps(b0, _mm_broadcast_ss(M + M_00 * S + i))));
        __m128 c1 = _mm_fmadd_ps(
            b2, _mm_broadcast_ss(M + M_12 * S + i),
            _mm_fmadd_ps(b1, _mm_broadcast_ss(M + M_11 * S + i), _mm_mul_ps(b0, _mm_broadcast_ss(M + M_10 * S + i))));
        __m128 c2 = _mm_fmadd_ps(
            b2, _mm_broadcast_ss(M + M_22 * S + i),
            _mm_fmadd_ps(b1, _mm_broadcast_ss(M + M_21 * S + i), _mm_mul_ps(b0, _mm_broadcast_ss(M + M_20 * S + i))));
        __m128 c3 = _mm_fmadd_ps(b2, _mm_broadcast_ss(P + C_TZ * S + i),
                                 _mm_fmadd_ps(b1, _mm_broadcast_ss(P + C_TY * S + i),
                                              _mm_fmadd_ps(b0, _mm_broadcast_ss(P + C_TX * S + i), b3)));
        _mm_storeu_ps(o, c0);
        _mm_storeu_ps(o + 4, c1);
        _mm_storeu_ps(o + 8, c2);
        _mm_storeu_ps(o + 12, c3);
    }
}
#endif

sinew_result sinew_player_update(sinew_player *p, float time, sinew_wrap wrap, const sinew_mat4 *root,
                                 sinew_mat4 *worlds, uint32_t world_count, sinew_error *error)
{
    if (!p || !worlds)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_player_update: NULL player or output");
    if (world_count < p->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_player_update: %u world matrices given, the model has %u nodes", world_count,
                          p->node_count);
    if (!isfinite(time))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_player_update: time is not finite");
    float t = sinew_clip_time(p->clip, time, wrap) + (p->clip ? p->clip->start : 0.0f);
#ifdef PLAYER_X86
    if (p->simd) {
        for (uint32_t g = 0; g < p->group_count; g++) {
            segment seg = find(&p->groups[g], t);
            blend_avx2(p->pose, &p->groups[g], &seg);
            slerp_fixes(p->pose, &p->groups[g], &seg);
        }
        locals_avx2(p);
        world_avx2(p, root, worlds);
        return SINEW_OK;
    }
#endif
    for (uint32_t g = 0; g < p->group_count; g++) {
        segment seg = find(&p->groups[g], t);
        blend_scalar(p->pose, &p->groups[g], &seg);
        slerp_fixes(p->pose, &p->groups[g], &seg);
    }
    locals_scalar(p);
    world_scalar(p, root, worlds);
    return SINEW_OK;
}
