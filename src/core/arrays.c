/* A clip as arrays (sinew/arrays.h): the player run over many times, each frame's locals,
 * worlds, weights and deformed vertices written where the caller asks. */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "sinew/arrays.h"
#include "sinew/morph.h"

uint32_t sinew_model_vertex_total(const sinew_model *model)
{
    uint64_t total = 0;
    for (uint32_t i = 0; model && i < model->instance_count; i++)
        total += model->meshes[model->instances[i].mesh].vertex_count;
    return total > UINT32_MAX ? UINT32_MAX : (uint32_t)total;
}

typedef struct arrays_scratch {
    sinew_allocator allocator;
    sinew_clip_layout *layout;
    void *player_memory;
    sinew_player *player;
    sinew_transform *locals;
    sinew_mat4 *worlds;
    void *deform;
    size_t deform_size;
    float *positions; /* one mesh's positions when only normals are asked for */
    float *weights;   /* a frame's morph weights when the caller keeps none but deforms */
} arrays_scratch;

static void scratch_free(arrays_scratch *s)
{
    if (s->player_memory)
        s->allocator.free(s->player_memory, s->allocator.user);
    if (s->locals)
        s->allocator.free(s->locals, s->allocator.user);
    if (s->worlds)
        s->allocator.free(s->worlds, s->allocator.user);
    if (s->deform)
        s->allocator.free(s->deform, s->allocator.user);
    if (s->positions)
        s->allocator.free(s->positions, s->allocator.user);
    if (s->weights)
        s->allocator.free(s->weights, s->allocator.user);
    sinew_clip_layout_free(s->layout);
}

static sinew_result scratch_init(arrays_scratch *s, const sinew_clip_arrays_desc *d, sinew_error *error)
{
    const sinew_model *m = d->model;
    s->allocator = sinew_allocator_or_default(d->allocator);
    sinew_result r = sinew_clip_layout_create(
        &(sinew_clip_layout_desc){.model = m, .clip = d->clip, .allocator = d->allocator}, &s->layout, error);
    if (r != SINEW_OK)
        return r;
    size_t player_size = sinew_player_size(s->layout);
    size_t nodes = m->node_count ? m->node_count : 1;
    s->player_memory = s->allocator.alloc(player_size, s->allocator.user);
    s->locals = s->allocator.alloc(nodes * sizeof *s->locals, s->allocator.user);
    s->worlds = s->allocator.alloc(nodes * sizeof *s->worlds, s->allocator.user);
    if (d->vertices || d->normals) {
        s->deform_size = sinew_deform_scratch_size(m);
        s->deform = s->allocator.alloc(s->deform_size, s->allocator.user);
    }
    if (d->normals && !d->vertices) {
        size_t largest = 1;
        for (uint32_t i = 0; i < m->mesh_count; i++)
            largest = m->meshes[i].vertex_count > largest ? m->meshes[i].vertex_count : largest;
        s->positions = s->allocator.alloc(largest * 3 * sizeof(float), s->allocator.user);
    }
    bool own_weights = m->morph_channel_count && !d->weights && (d->vertices || d->normals);
    if (own_weights)
        s->weights = s->allocator.alloc(m->morph_channel_count * sizeof(float), s->allocator.user);
    if (!s->player_memory || !s->locals || !s->worlds || ((d->vertices || d->normals) && !s->deform) ||
        (d->normals && !d->vertices && !s->positions) || (own_weights && !s->weights))
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for the arrays' scratch",
                          m->source ? m->source : "model");
    return sinew_player_init(s->player_memory, player_size, s->layout, &s->player, error);
}

static bool clip_of(const sinew_model *m, const sinew_clip *clip)
{
    return !clip || (m->clip_count > 0 && clip >= m->clips && clip < m->clips + m->clip_count);
}

/* Every instance at one frame, one after another into positions (and normals). */
static sinew_result deform_frame(const sinew_clip_arrays_desc *d, arrays_scratch *s, const float *weights,
                                 float cache_time, float *positions, float *normals, sinew_error *error)
{
    const sinew_model *m = d->model;
    size_t at = 0;
    for (uint32_t i = 0; i < m->instance_count; i++) {
        const sinew_mesh *mesh = &m->meshes[m->instances[i].mesh];
        sinew_result r = sinew_deform_instance(
            &(sinew_deform_desc){.model = m,
                                 .instance = i,
                                 .worlds = s->worlds,
                                 .world_count = m->node_count,
                                 .weights = weights,
                                 .weight_count = m->morph_channel_count,
                                 .cache_time = cache_time,
                                 .scratch = s->deform,
                                 .scratch_size = s->deform_size,
                                 .out_positions = positions ? positions + at * 3 : s->positions,
                                 .out_normals = normals && mesh->normals ? normals + at * 3 : NULL},
            error);
        if (r != SINEW_OK)
            return r;
        if (normals && !mesh->normals)
            memset(normals + at * 3, 0, (size_t)mesh->vertex_count * 3 * sizeof(float));
        at += mesh->vertex_count;
    }
    return SINEW_OK;
}

sinew_result sinew_clip_arrays(const sinew_clip_arrays_desc *d, sinew_error *error)
{
    if (!d || !d->model)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_clip_arrays: no model");
    const sinew_model *m = d->model;
    if (!clip_of(m, d->clip))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_clip_arrays: the clip is not one of %s's",
                          m->source ? m->source : "the model");
    if (d->time_count > 0 && !d->times)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_clip_arrays: %u times but no array",
                          d->time_count);
    for (uint32_t t = 0; t < d->time_count; t++)
        if (!isfinite(d->times[t]))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_clip_arrays: time %u is not finite", t);
    if (d->time_count == 0)
        return SINEW_OK;
    arrays_scratch s = {0};
    sinew_result r = scratch_init(&s, d, error);
    const size_t nodes = m->node_count, channels = m->morph_channel_count;
    const size_t verts = sinew_model_vertex_total(m);
    for (uint32_t t = 0; r == SINEW_OK && t < d->time_count; t++) {
        float time = d->times[t];
        r = sinew_player_update(s.player, time, d->wrap, NULL, s.worlds, m->node_count, error);
        if (r == SINEW_OK && (d->translations || d->rotations || d->scales)) {
            r = sinew_player_sample(s.player, time, d->wrap, s.locals, m->node_count, error);
            for (size_t i = 0; r == SINEW_OK && i < nodes; i++) {
                if (d->translations)
                    memcpy(d->translations + (t * nodes + i) * 3, s.locals[i].translation, 3 * sizeof(float));
                if (d->rotations)
                    memcpy(d->rotations + (t * nodes + i) * 4, s.locals[i].rotation, 4 * sizeof(float));
                if (d->scales)
                    memcpy(d->scales + (t * nodes + i) * 3, s.locals[i].scale, 3 * sizeof(float));
            }
        }
        if (r == SINEW_OK && d->worlds)
            memcpy(d->worlds + t * nodes * 16, s.worlds, nodes * sizeof(sinew_mat4));
        float *weights = !channels ? NULL : d->weights ? d->weights + t * channels : s.weights;
        if (r == SINEW_OK && weights)
            r = sinew_player_weights(s.player, time, d->wrap, weights, m->morph_channel_count, error);
        if (r == SINEW_OK && (d->vertices || d->normals)) {
            float cache_time = d->clip ? d->clip->timeline + sinew_clip_time(d->clip, time, d->wrap) : 0.0f;
            r = deform_frame(d, &s, weights, cache_time, d->vertices ? d->vertices + t * verts * 3 : NULL,
                             d->normals ? d->normals + t * verts * 3 : NULL, error);
        }
    }
    scratch_free(&s);
    return r;
}
