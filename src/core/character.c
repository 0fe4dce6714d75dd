/* The character (sinew/character.h): layers of clips with weights, masks, fades and additive
 * motion, IK chains and root motion, composed in one call.
 *
 * Memory, from the caller's block (each part 32-byte aligned): the character, its layers and
 * chains, structure-of-arrays poses (the blend, and the rest pose with several layers), the morph scratch, the
 * local poses when the description has IK, additive layers or root motion (the composed one,
 * one a layer, one reference a layer for additive layers), then one player a layer.
 * The clock: after a seek the layers' times and weights are a function of the clock (the
 * description's weights and scheduled fade), so advance is a seek to clock + dt. A play starts
 * fades that run on from now, as the mixer of three.js does: each layer's weight is a
 * smoothstep from the weight it had to 0 or 1, and layers in step share one phase that
 * advances at 1 / the weighted mean of their clips' durations.
 */
#include "sinew/character.h"

#include <math.h>
#include <string.h>

#include "internal.h"
#include "sinew/blend.h"
#include "sinew/morph.h"

typedef struct layer_state {
    sinew_player *player;
    const float *mask;
    float duration; /* the clip's; 0 for the rest pose */
    float time;     /* seconds into the clip, unwrapped */
    float weight, base;
    float fade_from, fade_to, fade_elapsed, fade_duration;
    bool additive, fading, synced;
} layer_state;

typedef struct chain_state {
    uint32_t start, middle, end;
    float target[3], pole[3], weight;
    bool pole_given;
} chain_state;

struct sinew_character {
    const sinew_model *model;
    uint32_t layer_count, ik_count, root_layer;
    sinew_character_fade fade;
    bool has_fade, root_motion, clamp, scheduled, has_rest;
    float threshold;
    double clock, phase;
    sinew_root_motion motion;
    float motion_translation[3], motion_yaw;
    layer_state *layers;
    chain_state *chains;
    sinew_soa_pose out, rest;
    sinew_transform *locals, *layer_locals, *reference;
    float *scratch;           /* layer_count times the morph channels: each layer's weights */
    float *reference_weights; /* with additive layers: each one's weights at its first frame */
};

#define ALIGN32(n) (((n) + 31u) & ~(size_t)31u)

static const sinew_clip *layer_clip(const sinew_character_layer *l)
{
    return sinew_layout_clip(l->layout);
}

/* Whether the description can be made; the error says what is wrong when it cannot. */
static sinew_result check_desc(const sinew_character_desc *d, sinew_error *error)
{
    if (!d || !d->model)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_character: no description or no model");
    const sinew_model *m = d->model;
    if (d->layer_count > SINEW_CHARACTER_MAX_LAYERS || (d->layer_count && !d->layers))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_character: give 0 to %u layers",
                          SINEW_CHARACTER_MAX_LAYERS);
    for (uint32_t i = 0; i < d->layer_count; i++) {
        const sinew_character_layer *l = &d->layers[i];
        if (!l->layout || sinew_layout_model(l->layout) != m)
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "sinew_character: layer %u has no clip layout, or one of another model", i);
        if (!isfinite(l->weight) || (!l->additive && l->weight < 0.0f))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "sinew_character: layer %u's weight %g is not finite or is negative", i,
                              (double)l->weight);
    }
    const sinew_character_fade *f = &d->fade;
    if (f->from != f->to) {
        if (f->from >= d->layer_count || f->to >= d->layer_count || d->layers[f->from].additive ||
            d->layers[f->to].additive)
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "sinew_character: the fade goes from layer %u to %u: both must be blended layers of the "
                              "%u given",
                              f->from, f->to, d->layer_count);
        if (!isfinite(f->start) || !isfinite(f->duration) || f->duration < 0.0f)
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "sinew_character: the fade's start %g s or duration %g s is not finite or negative",
                              (double)f->start, (double)f->duration);
    }
    if (d->ik_count > SINEW_CHARACTER_MAX_IK || (d->ik_count && !d->ik))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_character: give 0 to %u IK chains",
                          SINEW_CHARACTER_MAX_IK);
    for (uint32_t i = 0; i < d->ik_count; i++) {
        const sinew_character_ik *k = &d->ik[i];
        int32_t mid = k->end < m->node_count ? m->node_parents[k->end] : -1;
        if (mid < 0 || m->node_parents[mid] < 0)
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "%s: IK chain %u: node %u needs a parent and a grandparent to bend", m->source, i,
                              k->end);
        if (!isfinite(k->target[0] + k->target[1] + k->target[2]) || !(k->weight >= 0.0f && k->weight <= 1.0f) ||
            (k->pole_given && !isfinite(k->pole[0] + k->pole[1] + k->pole[2])))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "sinew_character: IK chain %u: a target or pole that is not finite, or a weight "
                              "outside 0..1",
                              i);
    }
    if (d->root_motion && (d->root_motion_layer >= d->layer_count || d->layers[d->root_motion_layer].additive ||
                           !layer_clip(&d->layers[d->root_motion_layer])))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "%s: root motion needs a blended layer that plays a clip (layer %u of %u)", m->source,
                          d->root_motion_layer, d->layer_count);
    if (!isfinite(d->threshold) || d->threshold < 0.0f)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_character: threshold %g is not finite or negative", (double)d->threshold);
    return SINEW_OK;
}

/* Whether the description can take the local-transform path (IK, additive layers, root motion):
 * only then are its buffers (the composed pose, a pose a layer, additive references) made. A
 * crowd of plain players pays for none of them. */
static bool has_additive(const sinew_character_desc *d)
{
    for (uint32_t i = 0; i < d->layer_count; i++)
        if (d->layers[i].additive)
            return true;
    return false;
}

static bool needs_locals(const sinew_character_desc *d)
{
    return d->ik_count > 0 || d->root_motion || has_additive(d);
}

/* The bytes of a valid description's instance, part by part as init takes them. */
static size_t size_of(const sinew_character_desc *d)
{
    const sinew_model *m = d->model;
    size_t n = m->node_count ? m->node_count : 1, layers = d->layer_count ? d->layer_count : 1,
           channels = m->morph_channel_count ? m->morph_channel_count : 1;
    size_t size = 31 + ALIGN32(sizeof(sinew_character)) + ALIGN32(layers * sizeof(layer_state)) +
                  ALIGN32((d->ik_count ? d->ik_count : 1) * sizeof(chain_state)) +
                  (d->layer_count > 1 ? 2 : 1) * ALIGN32(sinew_soa_pose_size(m->node_count)) +
                  ALIGN32(layers * channels * sizeof(float));
    if (needs_locals(d))
        size += ALIGN32(n * sizeof(sinew_transform)) + 2 * ALIGN32(layers * n * sizeof(sinew_transform));
    if (has_additive(d) && m->morph_channel_count)
        size += ALIGN32(layers * channels * sizeof(float));
    for (uint32_t i = 0; i < d->layer_count; i++)
        size += ALIGN32(sinew_player_size(d->layers[i].layout));
    return size;
}

size_t sinew_character_size(const sinew_character_desc *d)
{
    return check_desc(d, NULL) == SINEW_OK ? size_of(d) : 0;
}

/* Takes `bytes` (32-aligned) from *at. */
static void *take(unsigned char **at, size_t bytes)
{
    void *p = *at;
    *at += ALIGN32(bytes);
    return p;
}

sinew_result sinew_character_init(void *memory, size_t size, const sinew_character_desc *d, sinew_character **out,
                                  sinew_error *error)
{
    if (!memory || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_character_init: NULL memory or output");
    *out = NULL;
    sinew_result r = check_desc(d, error);
    if (r != SINEW_OK)
        return r;
    size_t need = size_of(d);
    if (size < need)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_character_init: %zu bytes given, the character needs %zu (sinew_character_size())",
                          size, need);
    const sinew_model *m = d->model;
    size_t n = m->node_count ? m->node_count : 1, layers = d->layer_count ? d->layer_count : 1;
    unsigned char *at = (unsigned char *)(((uintptr_t)memory + 31) & ~(uintptr_t)31);
    sinew_character *c = take(&at, sizeof *c);
    *c = (sinew_character){.model = m,
                           .layer_count = d->layer_count,
                           .ik_count = d->ik_count,
                           .root_layer = d->root_motion_layer,
                           .fade = d->fade,
                           .has_fade = d->fade.from != d->fade.to,
                           .root_motion = d->root_motion,
                           .clamp = d->clamp,
                           .threshold = d->threshold > 0.0f ? d->threshold : 0.1f};
    c->layers = take(&at, layers * sizeof *c->layers);
    c->chains = take(&at, (d->ik_count ? d->ik_count : 1) * sizeof *c->chains);
    size_t pose_size = sinew_soa_pose_size(m->node_count);
    r = sinew_soa_pose_init(take(&at, pose_size), pose_size, m->node_count, &c->out, error);
    /* the rest pose as a structure of arrays, for blends of several layers; one layer blends (when
     * its weight is under the threshold or it is masked) reading the rest pose from the model */
    c->has_rest = d->layer_count > 1;
    if (r == SINEW_OK && c->has_rest)
        r = sinew_soa_pose_init(take(&at, pose_size), pose_size, m->node_count, &c->rest, error);
    if (r == SINEW_OK && c->has_rest)
        r = sinew_soa_pose_from_locals(m->node_rest, m->node_count, &c->rest, error);
    if (needs_locals(d)) {
        c->locals = take(&at, n * sizeof *c->locals);
        c->layer_locals = take(&at, layers * n * sizeof *c->layer_locals);
        c->reference = take(&at, layers * n * sizeof *c->reference);
    }
    size_t channels = m->morph_channel_count ? m->morph_channel_count : 1;
    c->scratch = take(&at, layers * channels * sizeof(float));
    if (has_additive(d) && m->morph_channel_count)
        c->reference_weights = take(&at, layers * channels * sizeof(float));
    for (uint32_t i = 0; r == SINEW_OK && i < d->layer_count; i++) {
        const sinew_character_layer *l = &d->layers[i];
        layer_state *s = &c->layers[i];
        const sinew_clip *clip = layer_clip(l);
        *s = (layer_state){.mask = l->mask,
                           .duration = clip ? clip->duration : 0.0f,
                           .weight = l->weight,
                           .base = l->weight,
                           .additive = l->additive};
        size_t player_size = sinew_player_size(l->layout);
        r = sinew_player_init(take(&at, player_size), player_size, l->layout, &s->player, error);
        if (r == SINEW_OK && l->additive) /* what the layer adds is its motion from its first frame */
            r = sinew_player_sample(s->player, 0.0f, SINEW_WRAP_CLAMP, c->reference + i * n, m->node_count, error);
        if (r == SINEW_OK && l->additive && c->reference_weights) /* and its morph weights' */
            r = sinew_player_weights(s->player, 0.0f, SINEW_WRAP_CLAMP, c->reference_weights + i * channels,
                                     m->morph_channel_count, error);
    }
    for (uint32_t i = 0; i < d->ik_count; i++) {
        const sinew_character_ik *k = &d->ik[i];
        chain_state *s = &c->chains[i];
        *s = (chain_state){.end = k->end, .weight = k->weight > 0.0f ? k->weight : 1.0f, .pole_given = k->pole_given};
        s->middle = (uint32_t)m->node_parents[k->end];
        s->start = (uint32_t)m->node_parents[s->middle];
        memcpy(s->target, k->target, sizeof s->target);
        memcpy(s->pole, k->pole, sizeof s->pole);
    }
    if (r == SINEW_OK && d->root_motion)
        r = sinew_root_motion_init(m, layer_clip(&d->layers[d->root_motion_layer]), -1, &c->motion, error);
    if (r == SINEW_OK)
        r = sinew_character_seek(c, 0.0, error);
    if (r == SINEW_OK)
        *out = c;
    return r;
}

sinew_result sinew_character_seek(sinew_character *c, double time, sinew_error *error)
{
    if (!c)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_character_seek: NULL character");
    if (!isfinite(time))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_character_seek: time is not finite");
    c->clock = time;
    c->phase = 0.0;
    c->scheduled = true;
    for (uint32_t i = 0; i < c->layer_count; i++) {
        layer_state *s = &c->layers[i];
        s->time = (float)time;
        s->weight = s->base;
        s->fading = s->synced = false;
    }
    if (c->has_fade) {
        layer_state *a = &c->layers[c->fade.from], *b = &c->layers[c->fade.to];
        sinew_crossfade f = {.from = sinew_layout_clip(sinew_player_layout(a->player)),
                             .to = sinew_layout_clip(sinew_player_layout(b->player)),
                             .from_time = c->fade.start,
                             .start = c->fade.start,
                             .duration = c->fade.duration,
                             .sync = c->fade.sync && !c->clamp};
        float w;
        sinew_crossfade_at(&f, (float)time, &a->time, &b->time, &w);
        a->weight = 1.0f - w;
        b->weight = w;
    }
    return SINEW_OK;
}

static float fade_weight(const layer_state *s)
{
    if (!(s->fade_duration > 0.0f) || s->fade_elapsed >= s->fade_duration)
        return s->fade_to;
    float t = fmaxf(s->fade_elapsed / s->fade_duration, 0.0f);
    t = t * t * (3.0f - 2.0f * t);
    return s->fade_from + (s->fade_to - s->fade_from) * t;
}

sinew_result sinew_character_advance(sinew_character *c, float dt, sinew_error *error)
{
    if (!c)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_character_advance: NULL character");
    if (!isfinite(dt) || dt < 0.0f)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_character_advance: dt %g s is negative or not finite", (double)dt);
    if (c->scheduled)
        return sinew_character_seek(c, c->clock + dt, error);
    c->clock += dt;
    double cycle = 0.0, total = 0.0;
    for (uint32_t i = 0; i < c->layer_count; i++) {
        layer_state *s = &c->layers[i];
        if (s->fading) {
            s->fade_elapsed += dt;
            s->weight = fade_weight(s);
            if (s->weight <= 0.0f && s->fade_to <= 0.0f)
                s->synced = false;
        }
        if (s->synced)
            cycle += (double)s->weight * s->duration, total += s->weight;
    }
    if (total > 0.0)
        c->phase += dt / (cycle / total);
    for (uint32_t i = 0; i < c->layer_count; i++) {
        layer_state *s = &c->layers[i];
        s->time = s->synced ? (float)(c->phase * s->duration) : s->time + dt;
    }
    return SINEW_OK;
}

/* The blended layer with the most weight other than `except`, or -1. */
static int32_t heaviest(const sinew_character *c, uint32_t except)
{
    int32_t best = -1;
    for (uint32_t i = 0; i < c->layer_count; i++) {
        const layer_state *s = &c->layers[i];
        if (i != except && !s->additive && s->weight > 0.0f && (best < 0 || s->weight > c->layers[best].weight))
            best = (int32_t)i;
    }
    return best;
}

sinew_result sinew_character_play(sinew_character *c, uint32_t layer, float fade, bool sync, sinew_error *error)
{
    if (!c)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_character_play: NULL character");
    if (layer >= c->layer_count || c->layers[layer].additive)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_character_play: layer %u of %u is not a blended layer", layer, c->layer_count);
    if (!isfinite(fade) || fade < 0.0f)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_character_play: fade %g s is negative or not finite", (double)fade);
    c->scheduled = false;
    layer_state *s = &c->layers[layer];
    int32_t lead = heaviest(c, layer);
    if (sync && lead >= 0 && s->duration > 0.0f && c->layers[lead].duration > 0.0f) {
        layer_state *l = &c->layers[lead];
        if (!l->synced) { /* the phase starts where the leading layer is */
            double phase = (double)l->time / l->duration;
            c->phase = phase - floor(phase);
            for (uint32_t i = 0; i < c->layer_count; i++)
                c->layers[i].synced = false;
            l->synced = true;
            l->time = (float)(c->phase * l->duration);
        }
        s->synced = true;
        s->time = (float)(c->phase * s->duration);
    } else if (s->weight <= 0.0f) {
        s->synced = false;
        s->time = 0.0f;
    }
    for (uint32_t i = 0; i < c->layer_count; i++) {
        layer_state *t = &c->layers[i];
        if (t->additive)
            continue;
        t->fade_from = t->weight;
        t->fade_to = i == layer ? 1.0f : 0.0f;
        t->fade_elapsed = 0.0f;
        t->fade_duration = fade;
        t->fading = true;
        t->weight = fade_weight(t);
    }
    return SINEW_OK;
}

sinew_result sinew_character_set_weight(sinew_character *c, uint32_t layer, float weight, sinew_error *error)
{
    if (!c || layer >= c->layer_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_character_set_weight: no layer %u", layer);
    layer_state *s = &c->layers[layer];
    if (!isfinite(weight) || (!s->additive && weight < 0.0f))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_character_set_weight: weight %g is not finite or is negative", (double)weight);
    s->weight = s->base = weight;
    s->fading = false;
    return SINEW_OK;
}

sinew_result sinew_character_set_target(sinew_character *c, uint32_t chain, const float target[3], float weight,
                                        sinew_error *error)
{
    if (!c || chain >= c->ik_count || !target)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_character_set_target: no IK chain %u", chain);
    if (!isfinite(target[0] + target[1] + target[2]) || !(weight >= 0.0f && weight <= 1.0f))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_character_set_target: a target that is not finite or a weight outside 0..1");
    memcpy(c->chains[chain].target, target, sizeof c->chains[chain].target);
    c->chains[chain].weight = weight;
    return SINEW_OK;
}

void sinew_character_set_clamp(sinew_character *c, bool clamp)
{
    if (c)
        c->clamp = clamp;
}

/* ---- evaluation ------------------------------------------------------------------------------ */

static sinew_result check_output(const sinew_character *c, const sinew_character_output *o, sinew_error *error)
{
    const sinew_model *m = c->model;
    if (!o || !o->worlds || o->world_count < m->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_character_evaluate: room for %u world matrices, the model has %u nodes",
                          o && o->worlds ? o->world_count : 0, m->node_count);
    if (o->locals && o->local_count < m->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_character_evaluate: room for %u locals, the model has %u nodes", o->local_count,
                          m->node_count);
    uint32_t palettes = sinew_character_palette_count(m);
    if (o->palettes && o->palette_count < palettes)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_character_evaluate: room for %u palette matrices, the skins need %u", o->palette_count,
                          palettes);
    if (o->weights && o->weight_count < m->morph_channel_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_character_evaluate: room for %u morph weights, the model has %u channels",
                          o->weight_count, m->morph_channel_count);
    if (o->muscle_count && (!o->muscle_rig || !o->muscles))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_character_evaluate: muscles without a rig");
    return SINEW_OK;
}

/* Whether a layer counts in the blend now: a blended one with weight, an additive one not at 0. */
static bool weighs(const layer_state *s)
{
    return s->additive ? s->weight != 0.0f : s->weight > 0.0f;
}

/* Blended layers on structure-of-arrays poses (no additive layer, IK or root motion). */
static sinew_result evaluate_soa(sinew_character *c, sinew_wrap wrap, const sinew_character_output *o,
                                 sinew_error *error)
{
    sinew_soa_pose poses[SINEW_CHARACTER_MAX_LAYERS];
    sinew_blend_soa_layer layers[SINEW_CHARACTER_MAX_LAYERS];
    uint32_t count = 0;
    for (uint32_t i = 0; i < c->layer_count; i++) {
        layer_state *s = &c->layers[i];
        if (s->additive || !weighs(s))
            continue;
        sinew_result r = sinew_player_advance(s->player, s->time, wrap, &poses[count], error);
        if (r != SINEW_OK)
            return r;
        layers[count] = (sinew_blend_soa_layer){.pose = &poses[count], .weight = s->weight, .node_weights = s->mask};
        count++;
    }
    sinew_result r = sinew_blend_soa(&(sinew_blend_soa_desc){.model = c->model,
                                                             .rest = c->has_rest ? &c->rest : NULL,
                                                             .layers = layers,
                                                             .layer_count = count,
                                                             .threshold = c->threshold,
                                                             .out = &c->out},
                                     error);
    return r == SINEW_OK ? sinew_soa_pose_worlds(c->model, &c->out, o->root, o->worlds, o->world_count, error) : r;
}

/* Everything on local transforms: blend, additive layers, root motion, worlds, IK. */
static sinew_result evaluate_locals(sinew_character *c, sinew_wrap wrap, const sinew_character_output *o,
                                    sinew_error *error)
{
    const sinew_model *m = c->model;
    const uint32_t n = m->node_count;
    const size_t stride = n ? n : 1;
    sinew_blend_layer layers[SINEW_CHARACTER_MAX_LAYERS], adds[SINEW_CHARACTER_MAX_LAYERS];
    uint32_t count = 0, add_count = 0;
    sinew_result r = SINEW_OK;
    for (uint32_t i = 0; r == SINEW_OK && i < c->layer_count; i++) {
        layer_state *s = &c->layers[i];
        if (!weighs(s))
            continue;
        sinew_transform *dst = c->layer_locals + i * stride;
        r = sinew_player_sample(s->player, s->time, wrap, dst, n, error);
        if (r == SINEW_OK && s->additive)
            r = sinew_additive_delta(c->reference + i * stride, dst, dst, n, error);
        sinew_blend_layer l = {dst, s->weight, s->mask};
        if (s->additive)
            adds[add_count++] = l;
        else
            layers[count++] = l;
    }
    if (r == SINEW_OK)
        r = sinew_blend(&(sinew_blend_desc){.model = m,
                                            .layers = layers,
                                            .layer_count = count,
                                            .additive = adds,
                                            .additive_count = add_count,
                                            .threshold = c->threshold,
                                            .out = c->locals,
                                            .out_count = n},
                        error);
    if (r == SINEW_OK && c->root_motion)
        sinew_root_motion_extract(&c->motion, c->locals, c->motion_translation, &c->motion_yaw);
    if (r == SINEW_OK)
        r = sinew_local_to_world(m, c->locals, n, o->root, o->worlds, o->world_count, error);
    for (uint32_t i = 0; r == SINEW_OK && i < c->ik_count; i++) {
        const chain_state *k = &c->chains[i];
        if (!(k->weight > 0.0f))
            continue;
        sinew_ik_two_bone_desc d = {.model = m,
                                    .worlds = o->worlds,
                                    .locals = c->locals,
                                    .node_count = n,
                                    .start = k->start,
                                    .middle = k->middle,
                                    .end = k->end,
                                    .weight = k->weight};
        /* the pole: where the middle joint already bends, away from the start-end line */
        const float *start = o->worlds[k->start].m + 12, *mid = o->worlds[k->middle].m + 12,
                    *end = o->worlds[k->end].m + 12;
        for (int a = 0; a < 3; a++) {
            d.pole[a] = k->pole_given ? k->pole[a] : mid[a] + 4.0f * (mid[a] - 0.5f * (start[a] + end[a]));
            d.target[a] = k->target[a];
        }
        r = sinew_ik_two_bone(&d, error);
        if (r == SINEW_OK)
            r = sinew_local_to_world(m, c->locals, n, o->root, o->worlds, o->world_count, error);
    }
    if (r == SINEW_OK && o->locals)
        memcpy(o->locals, c->locals, n * sizeof *o->locals);
    return r;
}

/* The morph channel weights, blended as the pose is: each layer's weights at its time
 * (additive layers' less those of their first frame). */
static sinew_result evaluate_weights(sinew_character *c, sinew_wrap wrap, float *out, sinew_error *error)
{
    const sinew_model *m = c->model;
    const uint32_t n = m->morph_channel_count;
    sinew_weight_layer layers[SINEW_CHARACTER_MAX_LAYERS], adds[SINEW_CHARACTER_MAX_LAYERS];
    uint32_t count = 0, add_count = 0;
    sinew_result r = SINEW_OK;
    for (uint32_t i = 0; r == SINEW_OK && i < c->layer_count; i++) {
        layer_state *s = &c->layers[i];
        if (!weighs(s))
            continue;
        float *dst = c->scratch + (size_t)i * n;
        r = sinew_player_weights(s->player, s->time, wrap, dst, n, error);
        if (r == SINEW_OK && s->additive) {
            const float *first = c->reference_weights + (size_t)i * n;
            for (uint32_t k = 0; k < n; k++)
                dst[k] -= first[k];
            adds[add_count++] = (sinew_weight_layer){dst, s->weight};
        } else {
            layers[count++] = (sinew_weight_layer){dst, s->weight};
        }
    }
    if (r == SINEW_OK)
        r = sinew_blend_weights(&(sinew_blend_weights_desc){.model = m,
                                                            .layers = layers,
                                                            .layer_count = count,
                                                            .additive = adds,
                                                            .additive_count = add_count,
                                                            .threshold = c->threshold,
                                                            .out = out,
                                                            .out_count = n},
                                error);
    return r;
}

sinew_result sinew_character_evaluate(sinew_character *c, const sinew_character_output *o, sinew_error *error)
{
    if (!c)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_character_evaluate: NULL character");
    sinew_result r = check_output(c, o, error);
    if (r != SINEW_OK)
        return r;
    const sinew_model *m = c->model;
    const sinew_wrap wrap = c->clamp ? SINEW_WRAP_CLAMP : SINEW_WRAP_LOOP;
    bool locals = c->root_motion || (o->locals != NULL && c->locals);
    uint32_t blended = 0, alone = 0;
    for (uint32_t i = 0; i < c->layer_count; i++) {
        const layer_state *s = &c->layers[i];
        if (weighs(s) && s->additive)
            locals = true;
        else if (weighs(s))
            blended++, alone = i;
    }
    for (uint32_t i = 0; i < c->ik_count; i++)
        locals = locals || c->chains[i].weight > 0.0f;
    if (locals)
        r = evaluate_locals(c, wrap, o, error);
    else if (blended == 1 && !c->layers[alone].mask && c->layers[alone].weight >= c->threshold && !o->locals)
        r = sinew_player_update(c->layers[alone].player, c->layers[alone].time, wrap, o->root, o->worlds,
                                o->world_count, error);                      /* the clip alone: the player */
    else if ((r = evaluate_soa(c, wrap, o, error)) == SINEW_OK && o->locals) /* a lean character's locals */
        r = sinew_soa_pose_to_locals(&c->out, o->locals, o->local_count, error);
    if (r == SINEW_OK && o->palettes)
        for (uint32_t s = 0, at = 0; r == SINEW_OK && s < m->skin_count; at += m->skins[s++].joint_count)
            r = sinew_skin_palette(&m->skins[s], o->worlds, o->world_count, o->palettes + at, m->skins[s].joint_count,
                                   error);
    if (r == SINEW_OK && o->weights && m->morph_channel_count)
        r = evaluate_weights(c, wrap, o->weights, error);
    if (r == SINEW_OK && o->muscle_rig)
        r = sinew_muscle_rig_update(o->muscle_rig, o->worlds, o->world_count, o->muscles, o->muscle_count, error);
    return r;
}

/* ---- what it holds --------------------------------------------------------------------------- */

double sinew_character_clock(const sinew_character *c)
{
    return c ? c->clock : 0.0;
}

float sinew_character_weight(const sinew_character *c, uint32_t layer)
{
    return c && layer < c->layer_count ? c->layers[layer].weight : 0.0f;
}

float sinew_character_time(const sinew_character *c, uint32_t layer)
{
    return c && layer < c->layer_count ? c->layers[layer].time : 0.0f;
}

const sinew_root_motion *sinew_character_root_motion(const sinew_character *c, float translation[3], float *yaw)
{
    bool on = c && c->root_motion;
    if (translation)
        for (int k = 0; k < 3; k++)
            translation[k] = on ? c->motion_translation[k] : 0.0f;
    if (yaw)
        *yaw = on ? c->motion_yaw : 0.0f;
    return on ? &c->motion : NULL;
}

uint32_t sinew_character_palette_count(const sinew_model *m)
{
    uint32_t count = 0;
    for (uint32_t s = 0; m && s < m->skin_count; s++)
        count += m->skins[s].joint_count;
    return count;
}

sinew_result sinew_character_subtree_mask(const sinew_model *m, uint32_t joint, float *mask, uint32_t count,
                                          sinew_error *error)
{
    if (!m || !mask || count < m->node_count || joint >= m->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_character_subtree_mask: node %u of %u, or room for %u of %u weights", joint,
                          m ? m->node_count : 0, count, m ? m->node_count : 0);
    for (uint32_t i = 0; i < m->node_count; i++) {
        int32_t at = (int32_t)i;
        for (uint32_t depth = 0; at >= 0 && (uint32_t)at != joint && depth <= m->node_count; depth++)
            at = m->node_parents[at];
        mask[i] = at == (int32_t)joint ? 1.0f : 0.0f;
    }
    return SINEW_OK;
}
