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

/* the pose's rows: the player's pose is a sinew_soa_pose */
enum {
    C_TX = SINEW_SOA_TX,
    C_TY = SINEW_SOA_TY,
    C_TZ = SINEW_SOA_TZ,
    C_QX = SINEW_SOA_QX,
    C_QY = SINEW_SOA_QY,
    C_QZ = SINEW_SOA_QZ,
    C_QW = SINEW_SOA_QW,
    C_SX = SINEW_SOA_SX,
    C_SY = SINEW_SOA_SY,
    C_SZ = SINEW_SOA_SZ,
    C_COUNT = SINEW_SOA_ROWS
};

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
    const float *times; /* the clip's, key_count */
    float *rows;        /* key_count * row_floats */
    run *runs;
    slerp_fix *fixes;
} group;

/* The asset: built once per model and clip, read by every player of it. */
struct sinew_clip_layout {
    const sinew_model *model;
    const sinew_clip *clip;
    uint32_t node_count, stride; /* stride: node_count rounded up to 8 */
    uint32_t group_count;
    group *groups;
    float *start_pose; /* C_COUNT * stride: the rest pose with one-key channels written in */
    sinew_allocator allocator;
};

/* One character's state, in memory the caller owns. */
struct sinew_player {
    const sinew_clip_layout *layout;
    bool simd;
    float *pose;       /* C_COUNT * stride, 32-byte aligned: a structure-of-arrays pose */
    uint32_t *cursors; /* group_count key cursors */
};

#define ALIGN32(n) (((n) + 31u) & ~(size_t)31u)

/* ---- building the layout ------------------------------------------------------------------ */

typedef struct lane_src {
    uint32_t dst;
    uint32_t channel; /* index into the channel list */
    uint32_t component;
} lane_src;

typedef struct channel_ref {
    const sinew_channel *channel;
    uint32_t node, kind, group;
} channel_ref;

/* What the layout holds, counted before anything is laid out. */
typedef struct layout_plan {
    channel_ref *refs;     /* channels with two keys or more */
    uint32_t *group_first; /* each group's first channel in refs */
    lane_src *lanes;       /* scratch: one group's lanes */
    uint32_t ref_count, group_count;
    size_t lane_total, float_total;
} layout_plan;

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

/* Channels with two keys or more, grouped by equal times; one-key channels are constants,
 * written into the start pose. */
static void plan_groups(const sinew_clip *clip, layout_plan *plan)
{
    uint32_t track_count = clip ? clip->track_count : 0;
    for (uint32_t t = 0; t < track_count; t++)
        for (uint32_t k = 0; k < SINEW_CHANNEL_COUNT; k++) {
            const sinew_channel *ch = &clip->tracks[t].channels[k];
            if (ch->key_count < 2)
                continue;
            uint32_t g = 0;
            while (g < plan->group_count && !same_times(clip, plan->refs[plan->group_first[g]].channel, ch))
                g++;
            if (g == plan->group_count)
                plan->group_first[plan->group_count++] = plan->ref_count;
            plan->refs[plan->ref_count++] = (channel_ref){ch, clip->tracks[t].node, k, g};
            uint32_t width = sinew_channel_width((int)k);
            plan->lane_total += width;
            plan->float_total += (size_t)width * ch->key_count * sinew_interp_floats(ch->interp);
        }
}

static void write_start_pose(sinew_clip_layout *l)
{
    const sinew_model *m = l->model;
    const uint32_t S = l->stride;
    float *pose = l->start_pose;
    for (uint32_t c = 0; c < C_COUNT; c++)
        for (uint32_t i = 0; i < S; i++)
            pose[c * S + i] = c == C_QW || c >= C_SX ? 1.0f : 0.0f;
    for (uint32_t i = 0; i < m->node_count; i++) {
        const sinew_transform *r = &m->node_rest[i];
        for (uint32_t k = 0; k < 3; k++) {
            pose[(C_TX + k) * S + i] = r->translation[k];
            pose[(C_SX + k) * S + i] = r->scale[k];
        }
        for (uint32_t k = 0; k < 4; k++)
            pose[(C_QX + k) * S + i] = r->rotation[k];
    }
    const sinew_clip *clip = l->clip;
    for (uint32_t t = 0; clip && t < clip->track_count; t++)
        for (uint32_t k = 0; k < SINEW_CHANNEL_COUNT; k++) {
            const sinew_channel *ch = &clip->tracks[t].channels[k];
            if (ch->key_count != 1)
                continue;
            const float *v =
                clip->values + ch->first_value + (ch->interp == SINEW_INTERP_CUBIC ? sinew_channel_width((int)k) : 0);
            for (uint32_t i = 0; i < sinew_channel_width((int)k); i++)
                pose[pose_component(k, i) * S + clip->tracks[t].node] = v[i];
        }
}

/* Group g's key rows (for each key the lanes' values, then in- and out-tangents), its runs
 * of lanes that land next to each other in the pose, and its slerp fixes, laid out from
 * `at`; returns the end. */
static unsigned char *lay_out_group(sinew_clip_layout *l, const layout_plan *plan, uint32_t g, unsigned char *at)
{
    const sinew_clip *clip = l->clip;
    const uint32_t S = l->stride;
    group *gr = &l->groups[g];
    const channel_ref *refs = plan->refs, *first = &refs[plan->group_first[g]];
    lane_src *lanes = plan->lanes;
    uint32_t lane_count = 0;
    for (uint32_t r = 0; r < plan->ref_count; r++)
        if (refs[r].group == g)
            for (uint32_t i = 0; i < sinew_channel_width((int)refs[r].kind); i++)
                lanes[lane_count++] = (lane_src){pose_component(refs[r].kind, i) * S + refs[r].node, r, i};
    qsort(lanes, lane_count, sizeof *lanes, compare_lanes);
    bool cubic = first->channel->interp == SINEW_INTERP_CUBIC;
    *gr = (group){.key_count = first->channel->key_count,
                  .interp = first->channel->interp,
                  .lane_count = lane_count,
                  .row_floats = lane_count * sinew_interp_floats(first->channel->interp),
                  .times = clip->times + first->channel->first_key};
    gr->rows = (float *)at;
    at += ALIGN32((size_t)gr->row_floats * gr->key_count * 4);
    gr->runs = (run *)at;
    for (uint32_t ln = 0; ln < lane_count; ln++) {
        const channel_ref *ref = &refs[lanes[ln].channel];
        uint32_t width = sinew_channel_width((int)ref->kind);
        uint32_t key_stride = sinew_channel_stride((int)ref->kind, ref->channel->interp);
        const float *src = clip->values + ref->channel->first_value + lanes[ln].component;
        for (uint32_t key = 0; key < gr->key_count; key++) {
            float *row = gr->rows + (size_t)key * gr->row_floats;
            const float *kv = src + (size_t)key * key_stride;
            if (cubic) {
                row[ln] = kv[width];                      /* value */
                row[lane_count + ln] = kv[0];             /* in-tangent */
                row[2 * lane_count + ln] = kv[2 * width]; /* out-tangent */
            } else if (gr->interp == SINEW_INTERP_BEZIER) {
                for (uint32_t j = 0; j < 5; j++) /* value, in time, in value, out time, out value */
                    row[j * lane_count + ln] = kv[j * width];
            } else {
                row[ln] = kv[0];
            }
        }
        run *last = gr->run_count ? &gr->runs[gr->run_count - 1] : NULL;
        if (last && last->dst + last->length == lanes[ln].dst)
            last->length++;
        else
            gr->runs[gr->run_count++] = (run){lanes[ln].dst, ln, 1};
    }
    at += ALIGN32((size_t)gr->run_count * sizeof(run));
    gr->fixes = (slerp_fix *)at;
    for (uint32_t r = 0; r < plan->ref_count; r++) {
        if (refs[r].group != g || refs[r].kind != SINEW_CHANNEL_ROTATION ||
            refs[r].channel->interp != SINEW_INTERP_LINEAR || !wide_segment(clip, refs[r].channel))
            continue;
        slerp_fix *fix = &gr->fixes[gr->fix_count++];
        for (uint32_t ln = 0; ln < lane_count; ln++)
            if (lanes[ln].channel == r) {
                fix->lane[lanes[ln].component] = ln;
                fix->dst[lanes[ln].component] = lanes[ln].dst;
            }
    }
    return at + ALIGN32((size_t)gr->fix_count * sizeof(slerp_fix));
}

sinew_result sinew_clip_layout_create(const sinew_clip_layout_desc *desc, sinew_clip_layout **out, sinew_error *error)
{
    if (!desc || !desc->model || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_clip_layout_create: NULL desc, model or output");
    *out = NULL;
    const sinew_allocator *a = desc->allocator;
    if (a && (!a->alloc || !a->free))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_clip_layout_create: allocator without alloc or free");
    sinew_allocator alloc = sinew_allocator_or_default(a);
    const sinew_model *model = desc->model;
    const sinew_clip *clip = desc->clip;
    for (uint32_t t = 0; clip && t < clip->track_count; t++)
        if (clip->tracks[t].node >= model->node_count)
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "%s: clip \"%s\" animates node %u, the model has %u nodes", model->source,
                              clip->name ? clip->name : "", clip->tracks[t].node, model->node_count);

    /* Scratch for the plan: a channel reference and a group start per channel (three a
     * track at most), a lane per component (ten a track at most). */
    size_t channels = (size_t)(clip ? clip->track_count : 0) * SINEW_CHANNEL_COUNT + 1;
    size_t scratch_bytes =
        channels * (sizeof(channel_ref) + sizeof(uint32_t)) + (channels * 10 / 3 + 1) * sizeof(lane_src) + 16;
    unsigned char *scratch = alloc.alloc(scratch_bytes, alloc.user);
    if (!scratch)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for a clip layout", model->source);
    layout_plan plan = {.refs = (channel_ref *)scratch};
    plan.lanes = (lane_src *)(scratch + channels * sizeof(channel_ref));
    plan.group_first =
        (uint32_t *)(scratch + channels * sizeof(channel_ref) + (channels * 10 / 3 + 1) * sizeof(lane_src));
    plan_groups(clip, &plan);

    /* One allocation: the layout, the start pose, the groups, then each group's rows, runs
     * and fixes (each part 32-byte aligned from the start of the block). */
    uint32_t stride = (model->node_count + 7u) & ~7u;
    if (stride == 0)
        stride = 8;
    size_t bytes = ALIGN32(sizeof(sinew_clip_layout)) + ALIGN32((size_t)C_COUNT * stride * 4) +
                   ALIGN32(plan.group_count * sizeof(group)) + plan.float_total * 4 + plan.lane_total * sizeof(run) +
                   plan.ref_count * sizeof(slerp_fix) + (size_t)plan.group_count * 3 * 32;
    unsigned char *block = alloc.alloc(bytes, alloc.user);
    if (!block) {
        alloc.free(scratch, alloc.user);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for a clip layout", model->source);
    }
    sinew_clip_layout *l = (sinew_clip_layout *)block;
    *l = (sinew_clip_layout){.model = model,
                             .clip = clip,
                             .node_count = model->node_count,
                             .stride = stride,
                             .group_count = plan.group_count,
                             .allocator = alloc};
    unsigned char *at = block + ALIGN32(sizeof *l);
    l->start_pose = (float *)at;
    at += ALIGN32((size_t)C_COUNT * stride * 4);
    l->groups = (group *)at;
    at += ALIGN32(plan.group_count * sizeof(group));
    write_start_pose(l);
    for (uint32_t g = 0; g < plan.group_count; g++)
        at = lay_out_group(l, &plan, g, at);
    alloc.free(scratch, alloc.user);
    *out = l;
    return SINEW_OK;
}

void sinew_clip_layout_free(sinew_clip_layout *layout)
{
    if (layout)
        layout->allocator.free(layout, layout->allocator.user);
}

/* ---- one character's state ------------------------------------------------------------------ */

const sinew_model *sinew_layout_model(const sinew_clip_layout *layout)
{
    return layout->model;
}

const sinew_clip_layout *sinew_player_layout(const sinew_player *player)
{
    return player->layout;
}

const sinew_clip *sinew_layout_clip(const sinew_clip_layout *layout)
{
    return layout->clip;
}

size_t sinew_player_size(const sinew_clip_layout *layout)
{
    if (!layout)
        return 0;
    /* 31 bytes of slack: the memory may start anywhere, the pose starts on 32 bytes. */
    return 31 + ALIGN32(sizeof(sinew_player)) + (size_t)C_COUNT * layout->stride * 4 +
           (size_t)layout->group_count * sizeof(uint32_t);
}

sinew_result sinew_player_init(void *memory, size_t size, const sinew_clip_layout *layout, sinew_player **out,
                               sinew_error *error)
{
    if (!memory || !layout || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_player_init: NULL memory, layout or output");
    *out = NULL;
    if (size < sinew_player_size(layout))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_player_init: %zu bytes given, the clip's player needs %zu (sinew_player_size())", size,
                          sinew_player_size(layout));
    unsigned char *at = (unsigned char *)(((uintptr_t)memory + 31) & ~(uintptr_t)31);
    sinew_player *p = (sinew_player *)at;
    at += ALIGN32(sizeof *p);
    size_t pose_bytes = (size_t)C_COUNT * layout->stride * 4;
    *p = (sinew_player){.layout = layout, .pose = (float *)at};
    p->cursors = (uint32_t *)(at + pose_bytes);
    memcpy(p->pose, layout->start_pose, pose_bytes);
    memset(p->cursors, 0, layout->group_count * sizeof *p->cursors);
    sinew_player_set_simd(p, true);
    *out = p;
    return SINEW_OK;
}

void sinew_player_set_simd(sinew_player *player, bool simd)
{
#ifdef PLAYER_X86
    player->simd = simd && sinew_soa_simd_supported();
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

static segment find(const group *g, uint32_t *cursor, float t)
{
    const float *times = g->times;
    uint32_t n = g->key_count;
    if (t <= times[0])
        return (segment){0, true, 0, 0, t};
    if (t >= times[n - 1])
        return (segment){n - 1, true, 0, 0, t};
    uint32_t k = sinew_find_segment(times, n, t, cursor);
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

#endif

/* Every group's keys at t into the pose, blended by `blend` (the SIMD or the scalar one). */
static void sample_groups(sinew_player *p, float t, void (*blend)(float *, const group *, const segment *))
{
    const sinew_clip_layout *l = p->layout;
    for (uint32_t g = 0; g < l->group_count; g++) {
        segment seg = find(&l->groups[g], &p->cursors[g], t);
        blend(p->pose, &l->groups[g], &seg);
        slerp_fixes(p->pose, &l->groups[g], &seg);
    }
}

/* The pose at clip time t, through the SIMD or the scalar blend. */
static void sample_at(sinew_player *p, float t)
{
#ifdef PLAYER_X86
    sample_groups(p, t, p->simd ? blend_avx2 : blend_scalar);
#else
    sample_groups(p, t, blend_scalar);
#endif
}

/* The checks the entry points make; the clip time to sample, or a failure. */
static sinew_result player_time(const sinew_player *p, const void *out, uint32_t count, float time, sinew_wrap wrap,
                                const char *what, float *t, sinew_error *error)
{
    if (!p || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s: NULL player or output", what);
    const sinew_clip_layout *l = p->layout;
    if (count < l->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s: %u outputs given, the model has %u nodes", what,
                          count, l->node_count);
    if (!isfinite(time))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s: time is not finite", what);
    *t = sinew_clip_time(l->clip, time, wrap) + (l->clip ? l->clip->start : 0.0f);
    return SINEW_OK;
}

sinew_result sinew_player_sample(sinew_player *p, float time, sinew_wrap wrap, sinew_transform *locals,
                                 uint32_t local_count, sinew_error *error)
{
    float t = 0.0f; /* set by player_time when it succeeds (GCC cannot see that a failure is non-zero) */
    sinew_result r = player_time(p, locals, local_count, time, wrap, "sinew_player_sample", &t, error);
    if (r != SINEW_OK)
        return r;
    const sinew_clip_layout *l = p->layout;
    sample_at(p, t);
    sinew_soa_to_locals(p->pose, l->stride, l->node_count, locals);
    return SINEW_OK;
}

sinew_result sinew_player_update(sinew_player *p, float time, sinew_wrap wrap, const sinew_mat4 *root,
                                 sinew_mat4 *worlds, uint32_t world_count, sinew_error *error)
{
    float t = 0.0f; /* set by player_time when it succeeds (GCC cannot see that a failure is non-zero) */
    sinew_result r = player_time(p, worlds, world_count, time, wrap, "sinew_player_update", &t, error);
    if (r != SINEW_OK)
        return r;
    sample_at(p, t);
    sinew_soa_worlds(p->layout->model, p->pose, p->layout->stride, root, worlds, p->simd);
    return SINEW_OK;
}

sinew_result sinew_player_advance(sinew_player *p, float time, sinew_wrap wrap, sinew_soa_pose *pose,
                                  sinew_error *error)
{
    float t = 0.0f; /* set by player_time when it succeeds (GCC cannot see that a failure is non-zero) */
    sinew_result r = player_time(p, pose, p ? p->layout->node_count : 0, time, wrap, "sinew_player_advance", &t, error);
    if (r != SINEW_OK)
        return r;
    sample_at(p, t);
    *pose = (sinew_soa_pose){p->pose, p->layout->node_count, p->layout->stride};
    return SINEW_OK;
}
