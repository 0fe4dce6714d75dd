/* A generated skinned, animated character (a swaying tube on a joint chain) built through
 * the same raw model and builder as imported files. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/internal.h"
#include "internal.h"
#include "sinew/import.h"

#define HEIGHT 1.8f
#define RADIUS 0.12f
#define AROUND 32u

static sinew_result make_nodes(raw_model *m, uint32_t joints)
{
    m->node_count = joints;
    m->node_names = calloc(joints, sizeof *m->node_names);
    m->node_parents = calloc(joints, sizeof *m->node_parents);
    m->node_rest = calloc(joints, sizeof *m->node_rest);
    m->skin_count = 1;
    m->skins = calloc(1, sizeof *m->skins);
    if (!m->node_names || !m->node_parents || !m->node_rest || !m->skins)
        return SINEW_ERROR_OUT_OF_MEMORY;
    raw_skin *skin = &m->skins[0];
    skin->joint_count = joints;
    skin->joints = calloc(joints, sizeof *skin->joints);
    skin->inverse_bind = calloc(joints, sizeof *skin->inverse_bind);
    if (!skin->joints || !skin->inverse_bind)
        return SINEW_ERROR_OUT_OF_MEMORY;
    float step = HEIGHT / (float)joints;
    for (uint32_t j = 0; j < joints; j++) {
        char name[32];
        snprintf(name, sizeof name, "joint%03u", j);
        m->node_names[j] = raw_strdup(name);
        if (!m->node_names[j])
            return SINEW_ERROR_OUT_OF_MEMORY;
        m->node_parents[j] = (int32_t)j - 1;
        m->node_rest[j] = (sinew_transform){{0.0f, j ? step : 0.0f, 0.0f}, {0, 0, 0, 1}, {1, 1, 1}};
        skin->joints[j] = j;
        /* Joint j sits at height j * step at rest: its inverse bind moves it back down. */
        sinew_mat4 *ib = &skin->inverse_bind[j];
        memset(ib, 0, sizeof *ib);
        ib->m[0] = ib->m[5] = ib->m[10] = ib->m[15] = 1.0f;
        ib->m[13] = -step * (float)j;
    }
    return SINEW_OK;
}

/* Weights of the `influences` joints nearest to height y, falling off with distance. */
static void ring_weights(float y, uint32_t joints, uint32_t influences, uint32_t *out_joints, float *out_weights)
{
    float step = HEIGHT / (float)joints;
    float at = y / step; /* in joint units */
    int32_t first = (int32_t)floorf(at - (float)(influences - 1) * 0.5f);
    if (first < 0)
        first = 0;
    if (first + (int32_t)influences > (int32_t)joints)
        first = (int32_t)joints - (int32_t)influences;
    if (first < 0)
        first = 0;
    float sum = 0.0f;
    for (uint32_t k = 0; k < influences; k++) {
        uint32_t j = (uint32_t)first + k;
        float d = fabsf(at - (float)j - 0.5f);
        float w = j < joints ? 1.0f / (1.0f + d * d * 2.0f) : 0.0f;
        out_joints[k] = j < joints ? j : 0;
        out_weights[k] = w;
        sum += w;
    }
    for (uint32_t k = 0; k < influences; k++)
        out_weights[k] /= sum;
}

static sinew_result make_mesh(raw_model *m, uint32_t joints, uint32_t vertices, uint32_t influences)
{
    uint32_t rings = (vertices + AROUND - 1) / AROUND;
    if (rings < 2)
        rings = 2;
    m->mesh_count = m->instance_count = m->material_count = 1;
    m->meshes = calloc(1, sizeof *m->meshes);
    m->instances = calloc(1, sizeof *m->instances);
    m->materials = calloc(1, sizeof *m->materials);
    if (!m->meshes || !m->instances || !m->materials)
        return SINEW_ERROR_OUT_OF_MEMORY;
    m->materials[0] = (raw_material){.name = raw_strdup("skin"), .base_color = {0.8f, 0.45f, 0.35f, 1.0f}};
    raw_mesh *mesh = &m->meshes[0];
    mesh->name = raw_strdup("tube");
    mesh->vertex_count = rings * AROUND;
    mesh->index_count = (rings - 1) * AROUND * 6;
    mesh->influence_count = influences;
    mesh->positions = malloc((size_t)mesh->vertex_count * 3 * sizeof(float));
    mesh->indices = malloc((size_t)mesh->index_count * sizeof(uint32_t));
    mesh->joints = malloc((size_t)mesh->vertex_count * influences * sizeof(uint32_t));
    mesh->weights = malloc((size_t)mesh->vertex_count * influences * sizeof(float));
    if (!m->materials[0].name || !mesh->name || !mesh->positions || !mesh->indices || !mesh->joints || !mesh->weights)
        return SINEW_ERROR_OUT_OF_MEMORY;
    for (uint32_t r = 0; r < rings; r++) {
        float y = HEIGHT * (float)r / (float)(rings - 1);
        /* A little waist and head so the silhouette is not a plain cylinder. */
        float radius = RADIUS * (0.8f + 0.3f * sinf(y / HEIGHT * 3.14159265f * 3.0f));
        for (uint32_t a = 0; a < AROUND; a++) {
            uint32_t v = r * AROUND + a;
            float angle = 6.28318531f * (float)a / (float)AROUND;
            mesh->positions[v * 3 + 0] = radius * cosf(angle);
            mesh->positions[v * 3 + 1] = y;
            mesh->positions[v * 3 + 2] = -radius * sinf(angle);
            ring_weights(y, joints, influences, &mesh->joints[(size_t)v * influences],
                         &mesh->weights[(size_t)v * influences]);
        }
    }
    uint32_t *idx = mesh->indices;
    for (uint32_t r = 0; r + 1 < rings; r++)
        for (uint32_t a = 0; a < AROUND; a++) {
            uint32_t v0 = r * AROUND + a, v1 = r * AROUND + (a + 1) % AROUND;
            uint32_t v2 = v0 + AROUND, v3 = v1 + AROUND;
            *idx++ = v0, *idx++ = v1, *idx++ = v3;
            *idx++ = v0, *idx++ = v3, *idx++ = v2;
        }
    mesh->skin = 0;
    mesh->material = 0;
    m->instances[0] = (sinew_instance){0, 0, 0};
    return SINEW_OK;
}

/* A linear channel with the rotation channel's times, for translation or scale. */
static bool key_vectors(raw_track *track, int kind, const float *rest, float amount, float duration)
{
    const raw_channel *r = &track->channels[SINEW_CHANNEL_ROTATION];
    raw_channel *c = &track->channels[kind];
    if (!raw_channel_even(c, kind, duration, r->count))
        return false;
    for (uint32_t k = 0; k < r->count; k++) {
        float wave = amount * sinf(6.28318531f * (float)k / (float)(r->count - 1) + (float)track->node);
        for (int i = 0; i < 3; i++)
            c->values[k * 3 + i] = rest[i] + (i == 1 ? wave : 0.5f * wave);
    }
    return true;
}

static sinew_result make_clip(raw_model *m, uint32_t joints, float duration, float keys_per_second, bool trs)
{
    uint32_t keys = (uint32_t)ceilf(duration * keys_per_second) + 1;
    raw_clip *clip = raw_model_add_rotation_clip(m, "sway", duration, joints, keys);
    if (!clip)
        return SINEW_ERROR_OUT_OF_MEMORY;
    float amplitude = 1.05f / (float)joints; /* about 60 degrees over the chain */
    for (uint32_t j = 0; j < joints; j++) {
        raw_channel *c = &clip->tracks[j].channels[SINEW_CHANNEL_ROTATION];
        clip->tracks[j].node = j;
        for (uint32_t k = 0; k < keys; k++) {
            float phase = 6.28318531f * c->times[k] / duration;
            float ax = amplitude * sinf(phase + (float)j * 0.15f), az = amplitude * 0.7f * cosf(phase);
            float ay = amplitude * 0.5f * sinf(phase * 2.0f);
            /* Small rotations: the quaternion of a rotation vector (ax, ay, az). */
            float angle = sqrtf(ax * ax + ay * ay + az * az), s = angle > 0.0f ? sinf(angle * 0.5f) / angle : 0.5f;
            float *q = &c->values[k * 4];
            q[0] = ax * s, q[1] = ay * s, q[2] = az * s, q[3] = cosf(angle * 0.5f);
        }
        static const float unit[3] = {1.0f, 1.0f, 1.0f};
        if (trs &&
            (!key_vectors(&clip->tracks[j], SINEW_CHANNEL_TRANSLATION, m->node_rest[j].translation, 0.002f, duration) ||
             !key_vectors(&clip->tracks[j], SINEW_CHANNEL_SCALE, unit, 0.01f, duration)))
            return SINEW_ERROR_OUT_OF_MEMORY;
    }
    return SINEW_OK;
}

/* Targets that swell bands of rings outwards, and weight tracks for the first `animated`. */
static sinew_result make_targets(raw_model *m, uint32_t targets, uint32_t animated, float duration,
                                 float keys_per_second)
{
    raw_mesh *mesh = &m->meshes[0];
    uint32_t rings = mesh->vertex_count / AROUND, half = rings / 8 > 2 ? rings / 8 : 2;
    mesh->targets = calloc(targets, sizeof *mesh->targets);
    m->morph_channels = calloc(targets, sizeof *m->morph_channels);
    if (!mesh->targets || !m->morph_channels)
        return SINEW_ERROR_OUT_OF_MEMORY;
    for (uint32_t t = 0; t < targets; t++) {
        char name[32];
        snprintf(name, sizeof name, "bulge %u", t);
        uint32_t centre = (uint32_t)(((uint64_t)t * 2 + 1) * rings / (2 * targets));
        uint32_t first = centre > half ? centre - half : 0, last = centre + half < rings ? centre + half : rings - 1;
        raw_morph_target *tg = &mesh->targets[mesh->target_count++];
        m->morph_channels[m->morph_channel_count++] = (raw_morph_channel){.name = raw_strdup(name)};
        tg->name = raw_strdup(name);
        tg->channel = t;
        tg->full_weight = 1.0f;
        tg->delta_count = (last - first + 1) * AROUND;
        tg->vertices = malloc((size_t)tg->delta_count * sizeof *tg->vertices);
        tg->positions = malloc((size_t)tg->delta_count * 3 * sizeof *tg->positions);
        if (!tg->name || !m->morph_channels[t].name || !tg->vertices || !tg->positions)
            return SINEW_ERROR_OUT_OF_MEMORY;
        for (uint32_t r = first, d = 0; r <= last; r++) {
            float bump = 0.5f + 0.5f * cosf(3.14159265f * ((float)r - (float)centre) / (float)(half + 1));
            for (uint32_t a = 0; a < AROUND; a++, d++) {
                uint32_t v = r * AROUND + a;
                tg->vertices[d] = v;
                tg->positions[d * 3 + 0] = 0.6f * bump * mesh->positions[v * 3 + 0];
                tg->positions[d * 3 + 1] = 0.0f;
                tg->positions[d * 3 + 2] = 0.6f * bump * mesh->positions[v * 3 + 2];
            }
        }
    }
    raw_clip *clip = &m->clips[0];
    uint32_t keys = (uint32_t)ceilf(duration * keys_per_second) + 1;
    clip->weight_tracks = calloc(animated + 1, sizeof *clip->weight_tracks);
    if (!clip->weight_tracks)
        return SINEW_ERROR_OUT_OF_MEMORY;
    for (uint32_t t = 0; t < animated; t++) {
        raw_weight_track *tr = &clip->weight_tracks[clip->weight_track_count++];
        tr->channel = t * (targets / animated); /* spread over the body */
        if (!raw_channel_even(&tr->keys, SINEW_CHANNEL_WEIGHT, duration, keys))
            return SINEW_ERROR_OUT_OF_MEMORY;
        for (uint32_t k = 0; k < keys; k++) /* a whole number of cycles: the clip loops */
            tr->keys.values[k] = 0.5f - 0.5f * cosf(6.28318531f * (float)(1 + t % 3) * tr->keys.times[k] / duration);
    }
    return SINEW_OK;
}

sinew_result sinew_synthetic_model(const sinew_synthetic_desc *desc, sinew_model **out, sinew_error *error)
{
    sinew_synthetic_desc d = desc ? *desc : (sinew_synthetic_desc){0};
    if (!out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_synthetic_model: no output");
    *out = NULL;
    d.joints = d.joints ? d.joints : 64;
    d.vertices = d.vertices ? d.vertices : 10000;
    d.influences = d.influences ? d.influences : 4;
    d.duration = d.duration > 0.0f ? d.duration : 2.0f;
    d.keys_per_second = d.keys_per_second > 0.0f ? d.keys_per_second : 30.0f;
    if (d.joints < 2 || d.joints > SINEW_MAX_JOINTS || d.influences > SINEW_MAX_INFLUENCES || d.influences > d.joints ||
        d.vertices > 16u * 1024u * 1024u || !isfinite(d.duration) || d.duration > 3600.0f ||
        d.keys_per_second > 1000.0f || d.morph_targets > 4096 || d.morph_animated > d.morph_targets)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "synthetic model: %u joints (2..%d), %u influences (1..8, at most the joints), %u vertices, "
                          "%g s, %g keys/s, %u morph targets (0..4096), %u animated (at most the targets) are out of "
                          "range",
                          d.joints, SINEW_MAX_JOINTS, d.influences, d.vertices, d.duration, d.keys_per_second,
                          d.morph_targets, d.morph_animated);
    char source[96];
    snprintf(source, sizeof source, "synthetic:%u-joints-%u-vertices%s", d.joints, d.vertices,
             d.morph_targets ? "-morph" : "");
    raw_model raw = {.source = raw_strdup(source), .format = raw_strdup("synthetic")};
    sinew_result result = raw.source && raw.format ? SINEW_OK : SINEW_ERROR_OUT_OF_MEMORY;
    if (result == SINEW_OK)
        result = make_nodes(&raw, d.joints);
    if (result == SINEW_OK)
        result = make_mesh(&raw, d.joints, d.vertices, d.influences);
    if (result == SINEW_OK)
        result = make_clip(&raw, d.joints, d.duration, d.keys_per_second, d.keyed_trs);
    if (result == SINEW_OK && d.morph_targets)
        result = make_targets(&raw, d.morph_targets, d.morph_animated, d.duration, d.keys_per_second);
    if (result != SINEW_OK) {
        raw_model_free(&raw);
        return sinew_fail(error, result, "synthetic model: out of memory");
    }
    void *bytes = NULL;
    size_t size = 0;
    result = raw_model_build(&raw, &bytes, &size, error);
    raw_model_free(&raw);
    if (result == SINEW_OK)
        result = sinew_model_from_blob(bytes, size, source, NULL, out, error);
    free(bytes);
    return result;
}
