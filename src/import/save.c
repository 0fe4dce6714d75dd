/* Writing a runtime model back out as a .sinew file: the model's tables are copied into a
 * raw model (already valid: nothing is repaired) and written with the blob writer, so a
 * model saved without new muscles gives back the bytes it was loaded from. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../core/internal.h"
#include "internal.h"
#include "sinew/import.h"
#include "sinew/muscle_file.h"

static void *copy_array(const void *src, size_t count, size_t elem, bool *ok)
{
    if (!src || count == 0)
        return NULL;
    void *p = malloc(count * elem);
    if (!p) {
        *ok = false;
        return NULL;
    }
    return memcpy(p, src, count * elem);
}

static char *copy_string(const char *text, bool *ok)
{
    if (!text)
        return NULL;
    char *p = raw_strdup(text);
    if (!p)
        *ok = false;
    return p;
}

static char **copy_strings(const char *const *texts, uint32_t count, bool *ok)
{
    char **out = count ? calloc(count, sizeof *out) : NULL;
    if (count && !out)
        *ok = false;
    for (uint32_t i = 0; out && i < count; i++)
        out[i] = copy_string(texts[i], ok);
    return out;
}

static void copy_mesh(const sinew_mesh *src, raw_mesh *dst, bool *ok)
{
    size_t v = src->vertex_count, k = (size_t)v * src->influence_count;
    *dst = (raw_mesh){
        .name = copy_string(src->name, ok),
        .vertex_count = src->vertex_count,
        .index_count = src->index_count,
        .positions = copy_array(src->positions, v * 3, sizeof(float), ok),
        .normals = copy_array(src->normals, v * 3, sizeof(float), ok),
        .uvs = copy_array(src->uvs, v * 2, sizeof(float), ok),
        .tangents = copy_array(src->tangents, v * 4, sizeof(float), ok),
        .indices = copy_array(src->indices, src->index_count, sizeof(uint32_t), ok),
        .skin = src->skin,
        .material = src->material,
        .influence_count = src->influence_count,
        .weights = copy_array(src->weights, k, sizeof(float), ok),
        .dq_weights = copy_array(src->dq_weights, v, sizeof(float), ok),
        .flat_normals = src->flat_normals,
        .colors = copy_array(src->colors, v * 4, sizeof(float), ok),
    };
    if (src->target_count) {
        dst->targets = calloc(src->target_count, sizeof *dst->targets);
        if (!dst->targets)
            *ok = false;
        else
            dst->target_count = src->target_count;
    }
    for (uint32_t t = 0; t < dst->target_count; t++) {
        const sinew_morph_target *st = &src->targets[t];
        dst->targets[t] = (raw_morph_target){
            .name = copy_string(st->name, ok),
            .channel = st->channel,
            .full_weight = st->full_weight,
            .delta_count = st->delta_count,
            .vertices = copy_array(st->vertices, st->delta_count, sizeof(uint32_t), ok),
            .positions = copy_array(st->positions, (size_t)st->delta_count * 3, sizeof(float), ok),
            .normals = copy_array(st->normals, (size_t)st->delta_count * 3, sizeof(float), ok),
            .tangents = copy_array(st->tangents, (size_t)st->delta_count * 3, sizeof(float), ok),
        };
    }
    if (src->cache) {
        dst->cache = calloc(1, sizeof *dst->cache);
        if (!dst->cache) {
            *ok = false;
        } else {
            dst->cache->frame_count = src->cache->frame_count;
            dst->cache->times = copy_array(src->cache->times, src->cache->frame_count, sizeof(float), ok);
            dst->cache->positions =
                copy_array(src->cache->positions, (size_t)src->cache->frame_count * v * 3, sizeof(float), ok);
        }
    }
    if (k) {
        dst->joints = malloc(k * sizeof *dst->joints);
        if (!dst->joints)
            *ok = false;
        for (size_t i = 0; dst->joints && i < k; i++)
            dst->joints[i] = src->joints[i];
    }
}

/* A clip's keys become a pool of the raw model, one for every clip that shares them (the
 * same times and values: windows cut from one animation), so they are written once again. */
static void copy_clip(const sinew_model *m, uint32_t index, raw_model *raw, bool *ok)
{
    const sinew_clip *src = &m->clips[index];
    raw_clip *dst = &raw->clips[index];
    dst->name = copy_string(src->name, ok);
    dst->duration = src->duration;
    dst->start = src->start;
    dst->timeline = src->timeline;
    dst->frame_rate = src->frame_rate;
    uint32_t pool = 0;
    for (uint32_t c = 0; c < index && !pool; c++)
        if (m->clips[c].times == src->times && m->clips[c].values == src->values &&
            m->clips[c].time_count == src->time_count && m->clips[c].value_count == src->value_count)
            pool = raw->clips[c].track_count ? raw->clips[c].tracks[0].channels[0].pool : 0;
    if (!pool) {
        raw_key_pool *pools = realloc(raw->pools, (raw->pool_count + 1) * sizeof *pools);
        if (!pools) {
            *ok = false;
            return;
        }
        raw->pools = pools;
        raw_key_pool *p = &raw->pools[raw->pool_count];
        *p = (raw_key_pool){src->time_count, src->value_count,
                            copy_array(src->times, src->time_count ? src->time_count : 1, sizeof(float), ok),
                            copy_array(src->values, src->value_count ? src->value_count : 1, sizeof(float), ok)};
        pool = ++raw->pool_count;
    }
    dst->track_count = src->track_count;
    dst->tracks = src->track_count ? calloc(src->track_count, sizeof *dst->tracks) : NULL;
    if (src->track_count && !dst->tracks) {
        *ok = false;
        dst->track_count = 0;
    }
    for (uint32_t t = 0; t < dst->track_count; t++) {
        const sinew_track *track = &src->tracks[t];
        dst->tracks[t].node = track->node;
        for (int kind = 0; kind < SINEW_CHANNEL_COUNT; kind++) {
            const sinew_channel *ch = &track->channels[kind];
            dst->tracks[t].channels[kind] = (raw_channel){.interp = ch->interp,
                                                          .count = ch->key_count,
                                                          .pool = pool,
                                                          .first_key = ch->first_key,
                                                          .first_value = ch->first_value};
        }
    }
    dst->weight_tracks = src->weight_track_count ? calloc(src->weight_track_count, sizeof *dst->weight_tracks) : NULL;
    if (src->weight_track_count && !dst->weight_tracks)
        *ok = false;
    for (uint32_t t = 0; dst->weight_tracks && t < src->weight_track_count; t++) {
        const sinew_weight_track *wt = &src->weight_tracks[t];
        dst->weight_tracks[t] = (raw_weight_track){wt->channel,
                                                   {.interp = wt->keys.interp,
                                                    .count = wt->keys.key_count,
                                                    .pool = pool,
                                                    .first_key = wt->keys.first_key,
                                                    .first_value = wt->keys.first_value}};
        dst->weight_track_count++;
    }
}

/* A raw copy of a runtime model; false when out of memory (the copy stays freeable). */
bool raw_model_from_model(const sinew_model *m, raw_model *raw)
{
    bool ok = true;
    memset(raw, 0, sizeof *raw);
    raw->source = copy_string(m->source, &ok);
    raw->format = copy_string(m->format, &ok);
    raw->node_count = m->node_count;
    raw->node_names = copy_strings(m->node_names, m->node_count, &ok);
    raw->node_parents = copy_array(m->node_parents, m->node_count, sizeof(int32_t), &ok);
    raw->node_rest = copy_array(m->node_rest, m->node_count, sizeof(sinew_transform), &ok);
    raw->node_inherit = copy_array(m->node_inherit, m->node_count, sizeof(uint8_t), &ok);
    raw->skins = m->skin_count ? calloc(m->skin_count, sizeof *raw->skins) : NULL;
    raw->skin_count = raw->skins ? m->skin_count : 0;
    for (uint32_t i = 0; i < raw->skin_count; i++) {
        const sinew_skin *s = &m->skins[i];
        raw->skins[i].joint_count = s->joint_count;
        raw->skins[i].joints = copy_array(s->joints, s->joint_count, sizeof(uint32_t), &ok);
        raw->skins[i].inverse_bind = copy_array(s->inverse_bind, s->joint_count, sizeof(sinew_mat4), &ok);
        raw->skins[i].blend = s->blend;
    }
    raw->meshes = m->mesh_count ? calloc(m->mesh_count, sizeof *raw->meshes) : NULL;
    raw->mesh_count = raw->meshes ? m->mesh_count : 0;
    for (uint32_t i = 0; i < raw->mesh_count; i++)
        copy_mesh(&m->meshes[i], &raw->meshes[i], &ok);
    raw->instance_count = m->instance_count;
    raw->instances = copy_array(m->instances, m->instance_count, sizeof(sinew_instance), &ok);
    raw->materials = m->material_count ? calloc(m->material_count, sizeof *raw->materials) : NULL;
    raw->material_count = raw->materials ? m->material_count : 0;
    for (uint32_t i = 0; i < raw->material_count; i++) {
        const sinew_material *src = &m->materials[i];
        raw_material *dst = &raw->materials[i];
        dst->name = copy_string(src->name, &ok);
        memcpy(dst->base_color, src->base_color, sizeof dst->base_color);
        dst->metallic = src->metallic;
        dst->roughness = src->roughness;
        memcpy(dst->emissive, src->emissive, sizeof dst->emissive);
        dst->normal_scale = src->normal_scale;
        dst->occlusion_strength = src->occlusion_strength;
        dst->metallic_roughness = src->metallic_roughness;
        dst->alpha_mode = src->alpha_mode;
        dst->alpha_cutoff = src->alpha_cutoff;
        for (int k = 0; k < SINEW_MAP_COUNT; k++) {
            dst->maps[k].path = copy_string(src->maps[k].path, &ok);
            dst->maps[k].image = copy_array(src->maps[k].image, src->maps[k].image_size, 1, &ok);
            dst->maps[k].image_size = dst->maps[k].image ? src->maps[k].image_size : 0;
        }
    }
    raw->clips = m->clip_count ? calloc(m->clip_count, sizeof *raw->clips) : NULL;
    raw->clip_count = raw->clips ? m->clip_count : 0;
    for (uint32_t i = 0; i < raw->clip_count; i++)
        copy_clip(m, i, raw, &ok);
    raw->morph_channels = m->morph_channel_count ? calloc(m->morph_channel_count, sizeof *raw->morph_channels) : NULL;
    raw->morph_channel_count = raw->morph_channels ? m->morph_channel_count : 0;
    for (uint32_t i = 0; i < raw->morph_channel_count; i++)
        raw->morph_channels[i] =
            (raw_morph_channel){copy_string(m->morph_channels[i].name, &ok), m->morph_channels[i].default_weight};
    /* the reader's own note about an older format is not the model's */
    uint32_t warnings = m->warning_count;
    if (warnings && m->warnings[warnings - 1] == sinew_blob_old_version_warning)
        warnings--;
    raw->warning_count = warnings;
    raw->warnings = copy_strings(m->warnings, warnings, &ok);
    if (!raw->warnings)
        raw->warning_count = 0;
    ok = ok && raw->skin_count == m->skin_count && raw->mesh_count == m->mesh_count &&
         raw->material_count == m->material_count && raw->clip_count == m->clip_count &&
         raw->morph_channel_count == m->morph_channel_count;
    return ok;
}

sinew_result sinew_model_write_blob(const sinew_model *model, const sinew_muscle_set *muscles, void **bytes,
                                    size_t *size, sinew_error *error)
{
    if (!model || !bytes || !size)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_model_write_blob: NULL argument");
    raw_model raw;
    bool ok = raw_model_from_model(model, &raw);
    raw.muscles = muscles ? muscles : model->muscles;
    if (model->converted_from) { /* a .sinew file saved again keeps naming the original */
        free(raw.source);
        raw.source = raw_strdup(model->converted_from);
        ok = ok && raw.source;
    }
    sinew_result result = ok ? raw_model_write(&raw, bytes, size, error)
                             : sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", model->source);
    raw_model_free(&raw);
    return result;
}

sinew_result sinew_model_save(const sinew_model *model, const sinew_muscle_set *muscles, const char *path,
                              sinew_error *error)
{
    if (!path)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_model_save: NULL path");
    void *bytes = NULL;
    size_t size = 0;
    sinew_result result = sinew_model_write_blob(model, muscles, &bytes, &size, error);
    if (result)
        return result;
    result = import_write_file(path, bytes, size, error);
    free(bytes);
    return result;
}
