/* The mixer (sinew/blend.h): a character's clips, each with a player, a weight that fades
 * and a time; updates sample the clips with weight and blend them on structure-of-arrays
 * poses.
 *
 * Memory, from the caller's block: the mixer, its tracks, the blended pose, the rest pose,
 * then one player a clip. Phase sync: the clips marked in step share one phase (normalised
 * time) that advances at 1 / the weighted mean of their durations; each one's time is the
 * phase times its duration.
 */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "sinew/blend.h"
#include "sinew/morph.h"

typedef struct track {
    sinew_player *player;
    float duration; /* the clip's; 0 for the rest pose */
    float time;     /* seconds into the clip, unwrapped */
    float weight;
    float fade_from, fade_to, fade_elapsed, fade_duration;
    bool synced;
} track;

struct sinew_mixer {
    const sinew_model *model;
    sinew_wrap wrap;
    uint32_t count;
    double phase; /* of the tracks in step */
    sinew_soa_pose out, rest;
    track *tracks;
};

#define ALIGN32(n) (((n) + 31u) & ~(size_t)31u)

static bool valid_desc(const sinew_mixer_desc *d)
{
    if (!d || !d->layouts || d->layout_count == 0 || d->layout_count > SINEW_MIXER_MAX_CLIPS)
        return false;
    for (uint32_t i = 0; i < d->layout_count; i++)
        if (!d->layouts[i] || sinew_layout_model(d->layouts[i]) != sinew_layout_model(d->layouts[0]))
            return false;
    return true;
}

size_t sinew_mixer_size(const sinew_mixer_desc *d)
{
    if (!valid_desc(d))
        return 0;
    uint32_t n = sinew_layout_model(d->layouts[0])->node_count;
    size_t size = 31 + ALIGN32(sizeof(sinew_mixer)) + ALIGN32(d->layout_count * sizeof(track)) +
                  2 * ALIGN32(sinew_soa_pose_size(n));
    for (uint32_t i = 0; i < d->layout_count; i++)
        size += ALIGN32(sinew_player_size(d->layouts[i]));
    return size;
}

sinew_result sinew_mixer_init(void *memory, size_t size, const sinew_mixer_desc *d, sinew_mixer **out,
                              sinew_error *error)
{
    if (!memory || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_mixer_init: NULL memory or output");
    *out = NULL;
    if (!valid_desc(d))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_mixer_init: give 1 to %u clip layouts, all of one model", SINEW_MIXER_MAX_CLIPS);
    size_t need = sinew_mixer_size(d);
    if (size < need)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_mixer_init: %zu bytes given, the mixer needs %zu (sinew_mixer_size())", size, need);
    unsigned char *at = (unsigned char *)(((uintptr_t)memory + 31) & ~(uintptr_t)31);
    sinew_mixer *mx = (sinew_mixer *)at;
    at += ALIGN32(sizeof *mx);
    const sinew_model *m = sinew_layout_model(d->layouts[0]);
    *mx = (sinew_mixer){.model = m, .wrap = d->wrap ? d->wrap : SINEW_WRAP_LOOP, .count = d->layout_count};
    mx->tracks = (track *)at;
    at += ALIGN32(d->layout_count * sizeof(track));
    size_t pose_size = sinew_soa_pose_size(m->node_count);
    sinew_result r = sinew_soa_pose_init(at, pose_size, m->node_count, &mx->out, error);
    at += ALIGN32(pose_size);
    if (r == SINEW_OK)
        r = sinew_soa_pose_init(at, pose_size, m->node_count, &mx->rest, error);
    at += ALIGN32(pose_size);
    if (r == SINEW_OK)
        r = sinew_soa_pose_from_locals(m->node_rest, m->node_count, &mx->rest, error);
    for (uint32_t i = 0; r == SINEW_OK && i < d->layout_count; i++) {
        track *t = &mx->tracks[i];
        const sinew_clip *clip = sinew_layout_clip(d->layouts[i]);
        *t = (track){.duration = clip ? clip->duration : 0.0f};
        size_t player_size = sinew_player_size(d->layouts[i]);
        r = sinew_player_init(at, player_size, d->layouts[i], &t->player, error);
        at += ALIGN32(player_size);
    }
    if (r != SINEW_OK)
        return r;
    sinew_blend_soa(&(sinew_blend_soa_desc){.model = m, .rest = &mx->rest, .out = &mx->out}, NULL);
    *out = mx;
    return SINEW_OK;
}

static float fade_weight(const track *t)
{
    if (!(t->fade_duration > 0.0f) || t->fade_elapsed >= t->fade_duration)
        return t->fade_to;
    float s = fmaxf(t->fade_elapsed / t->fade_duration, 0.0f);
    s = s * s * (3.0f - 2.0f * s);
    return t->fade_from + (t->fade_to - t->fade_from) * s;
}

/* The playing track with the most weight other than `except`, or -1. */
static int32_t heaviest(const sinew_mixer *mx, uint32_t except)
{
    int32_t best = -1;
    for (uint32_t i = 0; i < mx->count; i++)
        if (i != except && mx->tracks[i].weight > 0.0f && (best < 0 || mx->tracks[i].weight > mx->tracks[best].weight))
            best = (int32_t)i;
    return best;
}

sinew_result sinew_mixer_play(sinew_mixer *mx, uint32_t clip, float fade, bool sync, sinew_error *error)
{
    if (!mx)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_mixer_play: NULL mixer");
    if (clip >= mx->count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_mixer_play: clip %u of %u", clip, mx->count);
    if (!isfinite(fade) || fade < 0.0f)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_mixer_play: fade %g s is negative or not finite",
                          (double)fade);
    track *c = &mx->tracks[clip];
    int32_t lead = heaviest(mx, clip);
    if (sync && lead >= 0 && c->duration > 0.0f && mx->tracks[lead].duration > 0.0f) {
        track *l = &mx->tracks[lead];
        if (!l->synced) { /* the phase starts where the leading clip is */
            double phase = (double)l->time / l->duration;
            mx->phase = phase - floor(phase);
            for (uint32_t i = 0; i < mx->count; i++)
                mx->tracks[i].synced = false;
            l->synced = true;
            l->time = (float)(mx->phase * l->duration);
        }
        c->synced = true;
        c->time = (float)(mx->phase * c->duration);
    } else if (c->weight <= 0.0f) {
        c->synced = false;
        c->time = 0.0f;
    }
    for (uint32_t i = 0; i < mx->count; i++) {
        track *t = &mx->tracks[i];
        t->fade_from = t->weight;
        t->fade_to = i == clip ? 1.0f : 0.0f;
        t->fade_elapsed = 0.0f;
        t->fade_duration = fade;
        t->weight = fade_weight(t);
    }
    return SINEW_OK;
}

/* Advances the fades and the clocks by dt. */
static void advance(sinew_mixer *mx, float dt)
{
    double cycle = 0.0, total = 0.0;
    for (uint32_t i = 0; i < mx->count; i++) {
        track *t = &mx->tracks[i];
        t->fade_elapsed += dt;
        t->weight = fade_weight(t);
        if (t->weight <= 0.0f && t->fade_to <= 0.0f)
            t->synced = false;
        if (t->synced)
            cycle += (double)t->weight * t->duration, total += t->weight;
    }
    if (total > 0.0)
        mx->phase += dt / (cycle / total);
    for (uint32_t i = 0; i < mx->count; i++) {
        track *t = &mx->tracks[i];
        t->time = t->synced ? (float)(mx->phase * t->duration) : t->time + dt;
    }
}

sinew_result sinew_mixer_update(sinew_mixer *mx, float dt, const sinew_mat4 *root, sinew_mat4 *worlds,
                                uint32_t world_count, sinew_error *error)
{
    if (!mx || !worlds)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_mixer_update: NULL mixer or output");
    if (world_count < mx->model->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_mixer_update: %u world matrices given, the model has %u nodes", world_count,
                          mx->model->node_count);
    if (!isfinite(dt) || dt < 0.0f)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_mixer_update: dt %g s is negative or not finite",
                          (double)dt);
    advance(mx, dt);
    /* the heaviest SINEW_BLEND_SOA_MAX_LAYERS tracks with weight */
    uint32_t pick[SINEW_BLEND_SOA_MAX_LAYERS], n = 0;
    for (uint32_t i = 0; i < mx->count; i++) {
        if (!(mx->tracks[i].weight > 0.0f))
            continue;
        if (n < SINEW_BLEND_SOA_MAX_LAYERS) {
            pick[n++] = i;
            continue;
        }
        uint32_t lightest = 0;
        for (uint32_t k = 1; k < n; k++)
            if (mx->tracks[pick[k]].weight < mx->tracks[pick[lightest]].weight)
                lightest = k;
        if (mx->tracks[i].weight > mx->tracks[pick[lightest]].weight)
            pick[lightest] = i;
    }
    sinew_soa_pose poses[SINEW_BLEND_SOA_MAX_LAYERS];
    sinew_blend_soa_layer layers[SINEW_BLEND_SOA_MAX_LAYERS];
    for (uint32_t k = 0; k < n; k++) {
        track *t = &mx->tracks[pick[k]];
        sinew_result r = sinew_player_advance(t->player, t->time, mx->wrap, &poses[k], error);
        if (r != SINEW_OK)
            return r;
        layers[k] = (sinew_blend_soa_layer){.pose = &poses[k], .weight = t->weight};
    }
    sinew_result r = sinew_blend_soa(
        &(sinew_blend_soa_desc){.model = mx->model,
                                .rest = &mx->rest,
                                .layers = layers,
                                .layer_count = n,
                                .threshold =
                                    1e-6f, /* the weights are normalised; the rest pose only when nothing plays */
                                .out = &mx->out},
        error);
    if (r == SINEW_OK)
        r = sinew_soa_pose_worlds(mx->model, &mx->out, root, worlds, world_count, error);
    return r;
}

float sinew_mixer_weight(const sinew_mixer *mx, uint32_t clip)
{
    return mx && clip < mx->count ? mx->tracks[clip].weight : 0.0f;
}

float sinew_mixer_time(const sinew_mixer *mx, uint32_t clip)
{
    return mx && clip < mx->count ? mx->tracks[clip].time : 0.0f;
}

const sinew_soa_pose *sinew_mixer_pose(const sinew_mixer *mx)
{
    return mx ? &mx->out : NULL;
}

sinew_result sinew_mixer_weights(const sinew_mixer *mx, float *weights, uint32_t weight_count, sinew_error *error)
{
    if (!mx || (mx->model->morph_channel_count && !weights))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_mixer_weights: NULL mixer or output");
    const sinew_model *m = mx->model;
    if (weight_count < m->morph_channel_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_mixer_weights: room for %u weights, the model has %u channels", weight_count,
                          m->morph_channel_count);
    float total = 0.0f;
    for (uint32_t i = 0; i < mx->count; i++)
        total += mx->tracks[i].weight > 0.0f ? mx->tracks[i].weight : 0.0f;
    for (uint32_t c = 0; c < m->morph_channel_count; c++) {
        if (!(total > 0.0f)) {
            weights[c] = m->morph_channels[c].default_weight;
            continue;
        }
        float sum = 0.0f;
        for (uint32_t i = 0; i < mx->count; i++) {
            const track *t = &mx->tracks[i];
            if (t->weight > 0.0f)
                sum += t->weight *
                       sinew_clip_weight(m, sinew_layout_clip(sinew_player_layout(t->player)), c, t->time, mx->wrap);
        }
        weights[c] = sum / total;
    }
    return SINEW_OK;
}
