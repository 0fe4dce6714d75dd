/* The builder: raw model -> validated, repaired runtime blob.
 *
 * Index:
 *   raw model helpers ...... raw_model_free, raw_model_warn, raw_strdup
 *   validation/repair ...... check_nodes, fix_mesh (normals, influences), fix_clip (keys)
 *   blob writer ............ writer_put, writer_string, write_* tables, raw_model_build
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/internal.h"
#include "internal.h"
#include "sinew/muscle_file.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

/* Morph weights beyond this (either way) are kept and warned about. */
#define WEIGHT_WARN_LIMIT 10.0f

/* ---- raw model helpers ---------------------------------------------------------------- */

char *raw_strdup(const char *text)
{
    size_t n = strlen(text) + 1;
    char *copy = malloc(n);
    if (copy)
        memcpy(copy, text, n);
    return copy;
}

raw_clip *raw_model_add_rotation_clip(raw_model *m, const char *name, float duration, uint32_t track_count,
                                      uint32_t keys)
{
    m->clips = calloc(1, sizeof *m->clips);
    if (!m->clips)
        return NULL;
    m->clip_count = 1;
    raw_clip *clip = &m->clips[0];
    clip->name = raw_strdup(name);
    clip->duration = duration;
    clip->tracks = calloc(track_count, sizeof *clip->tracks);
    if (!clip->name || !clip->tracks)
        return NULL;
    clip->track_count = track_count;
    for (uint32_t t = 0; t < track_count; t++)
        if (!raw_channel_even(&clip->tracks[t].channels[SINEW_CHANNEL_ROTATION], SINEW_CHANNEL_ROTATION, duration,
                              keys))
            return NULL;
    return clip;
}

bool raw_channel_even(raw_channel *c, int kind, float duration, uint32_t keys)
{
    c->interp = SINEW_INTERP_LINEAR;
    c->times = malloc(keys * sizeof(float));
    c->values = malloc((size_t)keys * sinew_channel_width(kind) * sizeof(float));
    if (!c->times || !c->values)
        return false;
    c->count = keys;
    for (uint32_t k = 0; k < keys; k++)
        c->times[k] = duration * (float)k / (float)(keys - 1);
    return true;
}

bool raw_model_warn(raw_model *model, const char *format, ...)
{
    char text[512];
    va_list args;
    va_start(args, format);
    vsnprintf(text, sizeof text, format, args);
    va_end(args);
    char **grown = realloc(model->warnings, (model->warning_count + 1) * sizeof(char *));
    if (!grown) {
        model->warning_lost = true;
        return false;
    }
    model->warnings = grown;
    if (!(grown[model->warning_count] = raw_strdup(text))) {
        model->warning_lost = true;
        return false;
    }
    model->warning_count++;
    return true;
}

void raw_clip_free(raw_clip *clip)
{
    for (uint32_t t = 0; t < clip->track_count; t++)
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++) {
            free(clip->tracks[t].channels[k].times);
            free(clip->tracks[t].channels[k].values);
        }
    free(clip->tracks);
    for (uint32_t t = 0; t < clip->weight_track_count; t++) {
        free(clip->weight_tracks[t].keys.times);
        free(clip->weight_tracks[t].keys.values);
    }
    free(clip->weight_tracks);
    free(clip->name);
}

void raw_colors_from_srgb(const float *in, uint32_t stride, uint32_t n, float *out)
{
    float last_in[3] = {0, 0, 0}, last_out[3] = {0, 0, 0}; /* painted meshes repeat colours: powf once a run */
    for (uint32_t v = 0; v < n; v++) {
        const float *c = &in[(size_t)v * stride];
        float *o = &out[(size_t)v * 4];
        if (memcmp(c, last_in, sizeof last_in) != 0) {
            for (int k = 0; k < 3; k++)
                last_out[k] = sinew_srgb_to_linear(c[k]);
            memcpy(last_in, c, sizeof last_in);
        }
        memcpy(o, last_out, sizeof last_out);
        o[3] = stride > 3 ? c[3] : 1.0f;
    }
}

void raw_mesh_free(raw_mesh *mesh)
{
    free(mesh->name);
    free(mesh->positions);
    free(mesh->normals);
    free(mesh->uvs);
    free(mesh->tangents);
    free(mesh->colors);
    free(mesh->indices);
    free(mesh->joints);
    free(mesh->weights);
    free(mesh->dq_weights);
    for (uint32_t t = 0; t < mesh->target_count; t++) {
        free(mesh->targets[t].name);
        free(mesh->targets[t].vertices);
        free(mesh->targets[t].positions);
        free(mesh->targets[t].normals);
        free(mesh->targets[t].tangents);
    }
    free(mesh->targets);
    if (mesh->cache) {
        free(mesh->cache->times);
        free(mesh->cache->positions);
        free(mesh->cache);
    }
}

bool raw_model_moved_nodes(const raw_model *m, const bool *excluded, bool *out)
{
    /* moved[n]: a clip animates n; below[n]: n or a node below it is moved */
    size_t n_nodes = m->node_count ? m->node_count : 1;
    bool *moved = calloc(2 * n_nodes, sizeof *moved), *below = moved ? moved + n_nodes : NULL;
    if (!moved)
        return false;
    for (uint32_t c = 0; c < m->clip_count; c++)
        for (uint32_t t = 0; t < m->clips[c].track_count; t++) {
            const raw_track *track = &m->clips[c].tracks[t];
            for (int k = 0; k < SINEW_CHANNEL_COUNT && track->node < m->node_count; k++)
                moved[track->node] |= track->channels[k].count > 0;
        }
    /* A node is kept when it or a node below it moves, or its parent moves (end sites);
     * parents come before children, so one backward pass gathers the subtrees. */
    for (uint32_t n = m->node_count; n-- > 0;) {
        below[n] |= moved[n];
        if (m->node_parents[n] >= 0)
            below[m->node_parents[n]] |= below[n];
    }
    for (uint32_t n = 0; n < m->node_count; n++) {
        int32_t parent = m->node_parents[n];
        out[n] = !excluded[n] && (below[n] || (parent >= 0 && moved[parent]));
    }
    free(moved);
    return true;
}

bool raw_model_grow_nodes(raw_model *m, uint32_t capacity)
{
    char **names = realloc(m->node_names, capacity * sizeof *names);
    if (names)
        m->node_names = names;
    int32_t *parents = realloc(m->node_parents, capacity * sizeof *parents);
    if (parents)
        m->node_parents = parents;
    sinew_transform *rest = realloc(m->node_rest, capacity * sizeof *rest);
    if (rest)
        m->node_rest = rest;
    return names && parents && rest;
}

bool raw_model_joints_from(raw_model *m, uint32_t first)
{
    bool *joint = calloc(m->node_count ? m->node_count : 1, sizeof *joint);
    uint32_t added = 0;
    if (!joint)
        return false;
    for (uint32_t i = first; i < m->node_count; i++)
        joint[i] = true;
    bool ok = raw_model_add_skeleton(m, joint, &added);
    free(joint);
    return ok;
}

bool raw_model_add_skeleton(raw_model *m, const bool *joint, uint32_t *added)
{
    *added = 0;
    uint32_t count = 0;
    for (uint32_t n = 0; n < m->node_count; n++)
        count += joint[n];
    if (count == 0)
        return true;
    raw_skin *skins = realloc(m->skins, (m->skin_count + 1) * sizeof *skins);
    if (!skins)
        return false;
    m->skins = skins;
    raw_skin *skin = &m->skins[m->skin_count];
    skin->joints = malloc(count * sizeof *skin->joints);
    skin->inverse_bind = malloc(count * sizeof *skin->inverse_bind);
    if (!skin->joints || !skin->inverse_bind) {
        free(skin->joints);
        free(skin->inverse_bind);
        return false;
    }
    skin->joint_count = 0;
    for (uint32_t n = 0; n < m->node_count; n++) {
        if (!joint[n])
            continue;
        skin->joints[skin->joint_count] = n;
        skin->inverse_bind[skin->joint_count++] = (sinew_mat4){{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
    }
    m->skin_count++;
    *added = count;
    return true;
}

void raw_model_free(raw_model *m)
{
    if (!m)
        return;
    for (uint32_t i = 0; i < m->node_count && m->node_names; i++)
        free(m->node_names[i]);
    free(m->node_names);
    free(m->node_parents);
    free(m->node_rest);
    free(m->node_inherit);
    for (uint32_t i = 0; i < m->skin_count; i++) {
        free(m->skins[i].joints);
        free(m->skins[i].inverse_bind);
    }
    free(m->skins);
    for (uint32_t i = 0; i < m->mesh_count; i++)
        raw_mesh_free(&m->meshes[i]);
    free(m->meshes);
    free(m->instances);
    for (uint32_t i = 0; i < m->material_count; i++) {
        free(m->materials[i].name);
        for (int k = 0; k < SINEW_MAP_COUNT; k++) {
            free(m->materials[i].maps[k].path);
            free(m->materials[i].maps[k].image);
        }
    }
    free(m->materials);
    for (uint32_t c = 0; c < m->clip_count; c++)
        raw_clip_free(&m->clips[c]);
    free(m->clips);
    for (uint32_t i = 0; i < m->morph_channel_count; i++)
        free(m->morph_channels[i].name);
    free(m->morph_channels);
    for (uint32_t i = 0; i < m->pool_count; i++) {
        free(m->pools[i].times);
        free(m->pools[i].values);
    }
    free(m->pools);
    for (uint32_t i = 0; i < m->warning_count; i++)
        free(m->warnings[i]);
    free(m->warnings);
    free(m->source);
    free(m->format);
    memset(m, 0, sizeof *m);
}

/* ---- validation and repair -------------------------------------------------------------- */

static sinew_result oom(const raw_model *m, sinew_error *error)
{
    return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory while building the model", m->source);
}

static sinew_result check_nodes(const raw_model *m, sinew_error *error)
{
    for (uint32_t i = 0; i < m->node_count; i++) {
        if (m->node_parents[i] < -1 || m->node_parents[i] >= (int32_t)i)
            return sinew_fail(error, SINEW_ERROR_DATA, "%s: node \"%s\" comes before its parent", m->source,
                              m->node_names[i]);
        if (!sinew_floats_finite(&m->node_rest[i].translation[0], 10))
            return sinew_fail(error, SINEW_ERROR_DATA,
                              "%s: node \"%s\" has a transform that is not finite (NaN or Inf)", m->source,
                              m->node_names[i]);
    }
    for (uint32_t s = 0; s < m->skin_count; s++) {
        const raw_skin *skin = &m->skins[s];
        if (skin->joint_count > SINEW_MAX_JOINTS)
            return sinew_fail(error, SINEW_ERROR_LIMIT, "%s: a skin has %u joints; sinew handles at most %d", m->source,
                              skin->joint_count, SINEW_MAX_JOINTS);
        for (uint32_t j = 0; j < skin->joint_count; j++) {
            if (skin->joints[j] >= m->node_count)
                return sinew_fail(error, SINEW_ERROR_DATA, "%s: skin joint %u is not a node", m->source, j);
            if (!sinew_floats_finite(skin->inverse_bind[j].m, 16))
                return sinew_fail(error, SINEW_ERROR_DATA,
                                  "%s: the inverse bind matrix of joint \"%s\" is not finite (NaN or Inf)", m->source,
                                  m->node_names[skin->joints[j]]);
        }
    }
    for (uint32_t i = 0; i < m->instance_count; i++)
        if (m->instances[i].mesh >= m->mesh_count || m->instances[i].node >= m->node_count)
            return sinew_fail(error, SINEW_ERROR_DATA, "%s: a mesh instance names a missing mesh or node", m->source);
    return SINEW_OK;
}

/* Area-weighted smooth normals, for meshes that came without any; summed in double, so that
 * positions near float's range (1e30 and more: their areas overflow a float) still give unit
 * normals. False when out of memory. */
static bool compute_normals(raw_mesh *mesh)
{
    double *sum = calloc((size_t)mesh->vertex_count * 3 + 1, sizeof *sum);
    if (!sum)
        return false;
    for (uint32_t t = 0; t + 2 < mesh->index_count; t += 3) {
        const uint32_t *tri = &mesh->indices[t];
        const float *a = &mesh->positions[tri[0] * 3], *b = &mesh->positions[tri[1] * 3],
                    *c = &mesh->positions[tri[2] * 3];
        double e1[3] = {(double)b[0] - a[0], (double)b[1] - a[1], (double)b[2] - a[2]};
        double e2[3] = {(double)c[0] - a[0], (double)c[1] - a[1], (double)c[2] - a[2]};
        double f[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++)
                sum[tri[k] * 3 + i] += f[i];
    }
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        const double *p = &sum[v * 3];
        double len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        float *n = &mesh->normals[v * 3];
        if (len > 0.0 && isfinite(len)) {
            double inv = 1.0 / len; /* one division, not three (the same floats on every shared model) */
            n[0] = (float)(p[0] * inv), n[1] = (float)(p[1] * inv), n[2] = (float)(p[2] * inv);
        } else {
            n[0] = 0.0f, n[1] = 1.0f, n[2] = 0.0f;
        }
    }
    free(sum);
    return true;
}

typedef struct influence {
    uint32_t joint;
    float weight;
} influence;

static int by_weight_desc(const void *a, const void *b)
{
    const influence *x = a, *y = b;
    if (x->weight != y->weight)
        return x->weight > y->weight ? -1 : 1;
    return x->joint < y->joint ? -1 : (x->joint > y->joint);
}

/* Index of the joint that unweighted vertices of `mesh` follow: the node the mesh is
 * instanced at, added to its skin with an identity inverse bind when missing. */
static int32_t fallback_joint(raw_model *m, uint32_t mesh_index)
{
    raw_mesh *mesh = &m->meshes[mesh_index];
    raw_skin *skin = &m->skins[mesh->skin];
    uint32_t node = 0;
    for (uint32_t i = 0; i < m->instance_count; i++)
        if (m->instances[i].mesh == mesh_index) {
            node = m->instances[i].node;
            break;
        }
    static const sinew_mat4 identity = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
    for (uint32_t j = 0; j < skin->joint_count; j++)
        if (skin->joints[j] == node && memcmp(&skin->inverse_bind[j], &identity, sizeof identity) == 0)
            return (int32_t)j;
    if (skin->joint_count >= SINEW_MAX_JOINTS)
        return -1;
    uint32_t *joints = realloc(skin->joints, (skin->joint_count + 1) * sizeof *joints);
    if (!joints)
        return -1;
    skin->joints = joints;
    sinew_mat4 *ibm = realloc(skin->inverse_bind, (skin->joint_count + 1) * sizeof *ibm);
    if (!ibm)
        return -1;
    skin->inverse_bind = ibm;
    joints[skin->joint_count] = node;
    ibm[skin->joint_count] = identity;
    return (int32_t)skin->joint_count++;
}

/* Sorts each vertex's influences by weight, keeps the largest SINEW_MAX_INFLUENCES,
 * normalises them, and narrows the slot count to what the mesh needs. */
static sinew_result fix_influences(raw_model *m, uint32_t mesh_index, sinew_error *error)
{
    raw_mesh *mesh = &m->meshes[mesh_index];
    const uint32_t k = mesh->influence_count;
    const uint32_t joint_count = m->skins[mesh->skin].joint_count;
    influence *scratch = malloc((k ? k : 1) * sizeof *scratch);
    if (!scratch)
        return oom(m, error);
    uint32_t used = 1, truncated = 0, unweighted = 0, renormalised = 0;
    int32_t fallback = -1;
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        uint32_t *joints = &mesh->joints[(size_t)v * k];
        float *weights = &mesh->weights[(size_t)v * k];
        uint32_t n = 0, listed = 0;
        float sum = 0.0f;
        for (uint32_t i = 0; i < k; i++) {
            if (joints[i] == UINT32_MAX)
                continue;
            listed++;
            if (!isfinite(weights[i]) || weights[i] < 0.0f) {
                free(scratch);
                return sinew_fail(error, SINEW_ERROR_DATA, "%s: mesh \"%s\": vertex %u has an invalid skin weight (%g)",
                                  m->source, mesh->name, v, (double)weights[i]);
            }
            if (joints[i] >= joint_count) {
                free(scratch);
                return sinew_fail(error, SINEW_ERROR_DATA, "%s: mesh \"%s\": vertex %u names joint %u of %u", m->source,
                                  mesh->name, v, joints[i], joint_count);
            }
            if (weights[i] > 0.0f)
                scratch[n++] = (influence){joints[i], weights[i]};
        }
        if (n <= 16) /* the usual four to eight: in place, without qsort's calls (the same order) */
            for (uint32_t i = 1; i < n; i++) {
                influence x = scratch[i];
                uint32_t j = i;
                for (; j > 0 && by_weight_desc(&x, &scratch[j - 1]) < 0; j--)
                    scratch[j] = scratch[j - 1];
                scratch[j] = x;
            }
        else
            qsort(scratch, n, sizeof *scratch, by_weight_desc);
        if (n > SINEW_MAX_INFLUENCES) {
            n = SINEW_MAX_INFLUENCES;
            truncated++;
        }
        for (uint32_t i = 0; i < n; i++)
            sum += scratch[i].weight;
        if (listed > 0 && !(sum > 0.0f)) {
            free(scratch);
            return sinew_fail(error, SINEW_ERROR_DATA, "%s: mesh \"%s\": the skin weights of vertex %u sum to zero",
                              m->source, mesh->name, v);
        }
        if (n == 0) {
            if (fallback < 0 && (fallback = fallback_joint(m, mesh_index)) < 0) {
                free(scratch);
                return oom(m, error);
            }
            scratch[n++] = (influence){(uint32_t)fallback, 1.0f};
            sum = 1.0f;
            unweighted++;
        }
        if (fabsf(sum - 1.0f) > 1e-3f)
            renormalised++;
        for (uint32_t i = 0; i < k; i++) {
            joints[i] = i < n ? scratch[i].joint : 0;
            weights[i] = i < n ? scratch[i].weight / sum : 0.0f;
        }
        if (n > used)
            used = n;
    }
    free(scratch);
    if (truncated)
        raw_model_warn(
            m, "mesh \"%s\": %u vertices had more than %d influences; the %d largest were kept and renormalised",
            mesh->name, truncated, SINEW_MAX_INFLUENCES, SINEW_MAX_INFLUENCES);
    if (renormalised)
        raw_model_warn(m, "mesh \"%s\": the skin weights of %u vertices did not sum to 1 and were renormalised",
                       mesh->name, renormalised);
    if (unweighted)
        raw_model_warn(m, "mesh \"%s\": %u vertices have no skin weights; they follow the mesh's node \"%s\"",
                       mesh->name, unweighted, m->node_names[m->skins[mesh->skin].joints[fallback]]);
    /* Narrow the slots from k to `used`, in place. */
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        for (uint32_t i = 0; i < used; i++) {
            mesh->joints[(size_t)v * used + i] = mesh->joints[(size_t)v * k + i];
            mesh->weights[(size_t)v * used + i] = mesh->weights[(size_t)v * k + i];
        }
    mesh->influence_count = used;
    return SINEW_OK;
}

static sinew_result fix_mesh(raw_model *m, uint32_t index, sinew_error *error)
{
    raw_mesh *mesh = &m->meshes[index];
    size_t v = mesh->vertex_count;
    if (!sinew_floats_finite(mesh->positions, v * 3))
        return sinew_fail(error, SINEW_ERROR_DATA,
                          "%s: mesh \"%s\" has vertex positions that are not finite (NaN or Inf)", m->source,
                          mesh->name);
    if (mesh->uvs && !sinew_floats_finite(mesh->uvs, v * 2))
        return sinew_fail(error, SINEW_ERROR_DATA, "%s: mesh \"%s\" has texture coordinates that are not finite",
                          m->source, mesh->name);
    if (mesh->tangents && !sinew_floats_finite(mesh->tangents, v * 4))
        return sinew_fail(error, SINEW_ERROR_DATA, "%s: mesh \"%s\" has tangents that are not finite", m->source,
                          mesh->name);
    if (mesh->colors && !sinew_floats_finite(mesh->colors, v * 4))
        return sinew_fail(error, SINEW_ERROR_DATA, "%s: mesh \"%s\" has vertex colours that are not finite", m->source,
                          mesh->name);
    if (mesh->index_count % 3 != 0)
        return sinew_fail(error, SINEW_ERROR_DATA, "%s: mesh \"%s\" has %u indices, not whole triangles", m->source,
                          mesh->name, mesh->index_count);
    for (uint32_t i = 0; i < mesh->index_count; i++)
        if (mesh->indices[i] >= mesh->vertex_count)
            return sinew_fail(error, SINEW_ERROR_DATA, "%s: mesh \"%s\": index %u names vertex %u of %u", m->source,
                              mesh->name, i, mesh->indices[i], mesh->vertex_count);
    if (mesh->material < -1 || mesh->material >= (int32_t)m->material_count)
        return sinew_fail(error, SINEW_ERROR_DATA, "%s: mesh \"%s\" names a missing material", m->source, mesh->name);
    if (mesh->skin < -1 || mesh->skin >= (int32_t)m->skin_count)
        return sinew_fail(error, SINEW_ERROR_DATA, "%s: mesh \"%s\" names a missing skin", m->source, mesh->name);
    bool recompute = !mesh->normals || !sinew_floats_finite(mesh->normals, v * 3);
    if (!mesh->normals && !(mesh->normals = malloc((v ? v : 1) * 3 * sizeof(float))))
        return oom(m, error);
    if (recompute && !compute_normals(mesh))
        return oom(m, error);
    if (mesh->skin >= 0 && (mesh->influence_count == 0 || !mesh->joints || !mesh->weights))
        return sinew_fail(error, SINEW_ERROR_DATA, "%s: mesh \"%s\" has a skin but no influences", m->source,
                          mesh->name);
    if (mesh->skin < 0)
        mesh->influence_count = 0;
    return mesh->skin >= 0 ? fix_influences(m, index, error) : SINEW_OK;
}

typedef struct key_order {
    float time;
    uint32_t index;
} key_order;

static int by_time(const void *a, const void *b)
{
    const key_order *x = a, *y = b;
    if (x->time != y->time)
        return x->time < y->time ? -1 : 1;
    return x->index < y->index ? -1 : (x->index > y->index); /* stable */
}

/* Puts keys that are out of time order in order, stably. */
static bool sort_keys(raw_channel *ch, uint32_t stride)
{
    key_order *order = malloc(ch->count * sizeof *order);
    float *values = malloc((size_t)ch->count * stride * sizeof(float));
    if (!order || !values) {
        free(order);
        free(values);
        return false;
    }
    for (uint32_t k = 0; k < ch->count; k++)
        order[k] = (key_order){ch->times[k], k};
    qsort(order, ch->count, sizeof *order, by_time);
    for (uint32_t k = 0; k < ch->count; k++) {
        ch->times[k] = order[k].time;
        memcpy(&values[(size_t)k * stride], &ch->values[(size_t)order[k].index * stride], stride * sizeof(float));
    }
    free(ch->values);
    ch->values = values;
    free(order);
    return true;
}

/* Unit-length rotations, each on the same side as the one before (so linear keys take the
 * short way even in readers that do not check). Cubic keys keep their sign: their tangents
 * were made for it. */
static bool fix_rotations(raw_channel *ch)
{
    uint32_t stride = sinew_channel_stride(SINEW_CHANNEL_ROTATION, ch->interp);
    uint32_t at = ch->interp == SINEW_INTERP_CUBIC ? 4 : 0;
    for (uint32_t k = 0; k < ch->count; k++) {
        float *q = &ch->values[(size_t)k * stride + at];
        float len = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (!(len > 1e-6f))
            return false;
        for (int i = 0; i < 4; i++)
            q[i] /= len;
        if (k > 0 && ch->interp != SINEW_INTERP_CUBIC) {
            const float *p = q - stride;
            if (p[0] * q[0] + p[1] * q[1] + p[2] * q[2] + p[3] * q[3] < 0.0f)
                for (int i = 0; i < 4; i++)
                    q[i] = -q[i];
        }
    }
    return true;
}

static const char *const channel_names[SINEW_CHANNEL_COUNT] = {"translation", "rotation", "scale"};

/* A pooled channel: every key inside its pool, the clip's one pool, keys in time order. */
static bool pooled_channel_ok(const raw_model *m, const raw_channel *ch, int kind, uint32_t *clip_pool)
{
    if (ch->pool == 0 || ch->pool > m->pool_count || (*clip_pool && ch->pool != *clip_pool) ||
        ch->interp > SINEW_INTERP_BEZIER || (ch->interp == SINEW_INTERP_BEZIER && kind == SINEW_CHANNEL_ROTATION))
        return false;
    *clip_pool = ch->pool;
    const raw_key_pool *pool = &m->pools[ch->pool - 1];
    if ((uint64_t)ch->first_key + ch->count > pool->time_count ||
        (uint64_t)ch->first_value + (uint64_t)ch->count * sinew_channel_stride(kind, ch->interp) > pool->value_count)
        return false;
    const float *times = pool->times + ch->first_key;
    for (uint32_t k = 1; k < ch->count; k++)
        if (!(times[k] >= times[k - 1]))
            return false;
    return true;
}

static sinew_result fix_clip(raw_model *m, raw_clip *clip, sinew_error *error)
{
    if (!isfinite(clip->duration) || clip->duration < 0.0f || !isfinite(clip->start))
        return sinew_fail(error, SINEW_ERROR_DATA, "%s: clip \"%s\" has an invalid duration (%g) or start (%g)",
                          m->source, clip->name, (double)clip->duration, (double)clip->start);
    uint32_t unsorted = 0, pool = 0;
    bool owned = false;
    for (uint32_t t = 0; t < clip->track_count; t++) {
        raw_track *track = &clip->tracks[t];
        if (track->node >= m->node_count)
            return sinew_fail(error, SINEW_ERROR_DATA, "%s: clip \"%s\" animates a missing node", m->source,
                              clip->name);
        for (int kind = 0; kind < SINEW_CHANNEL_COUNT; kind++) {
            raw_channel *ch = &track->channels[kind];
            if (ch->count == 0)
                continue;
            if (ch->pool || pool) {
                /* made by raw_model_pool_clip() (or a .sinew file's shared keys): repaired already */
                if (owned || !pooled_channel_ok(m, ch, kind, &pool))
                    return sinew_fail(error, SINEW_ERROR_DATA,
                                      "%s: clip \"%s\": the %s keys of node \"%s\" "
                                      "are outside the keys the clip shares",
                                      m->source, clip->name, channel_names[kind], m->node_names[track->node]);
                continue;
            }
            owned = true;
            uint32_t stride = sinew_channel_stride(kind, ch->interp);
            if (ch->interp > SINEW_INTERP_BEZIER ||
                (!ch->finite && (!sinew_floats_finite(ch->times, ch->count) ||
                                 !sinew_floats_finite(ch->values, (size_t)ch->count * stride))))
                return sinew_fail(error, SINEW_ERROR_DATA,
                                  "%s: clip \"%s\": the %s keys of node \"%s\" are not finite (NaN or Inf)", m->source,
                                  clip->name, channel_names[kind], m->node_names[track->node]);
            bool was_sorted = sinew_times_ascending(ch->times, ch->count);
            if (!was_sorted && !sort_keys(ch, stride))
                return oom(m, error);
            unsorted += !was_sorted;
            if (ch->interp == SINEW_INTERP_BEZIER &&
                (kind == SINEW_CHANNEL_ROTATION ||
                 !sinew_bezier_times_ok(ch->times, ch->values, ch->count, sinew_channel_width(kind))))
                return sinew_fail(error, SINEW_ERROR_DATA,
                                  "%s: clip \"%s\": the %s keys of node \"%s\" are Bezier keys %s", m->source,
                                  clip->name, channel_names[kind], m->node_names[track->node],
                                  kind == SINEW_CHANNEL_ROTATION ? "on a rotation (only translation and scale)"
                                                                 : "whose control points leave their segments");
            if (kind == SINEW_CHANNEL_ROTATION && !fix_rotations(ch))
                return sinew_fail(error, SINEW_ERROR_DATA,
                                  "%s: clip \"%s\": node \"%s\" has a zero-length rotation key", m->source, clip->name,
                                  m->node_names[track->node]);
        }
    }
    for (uint32_t t = 0; t < clip->weight_track_count; t++) {
        raw_weight_track *wt = &clip->weight_tracks[t];
        raw_channel *ch = &wt->keys;
        if (ch->pool) { /* a .sinew file's shared keys: checked when it was read */
            if (wt->channel >= m->morph_channel_count || owned)
                return sinew_fail(error, SINEW_ERROR_DATA, "%s: clip \"%s\": a weight track names a missing channel",
                                  m->source, clip->name);
            continue;
        }
        if (wt->channel >= m->morph_channel_count || pool ||
            (t > 0 && wt->channel <= clip->weight_tracks[t - 1].channel))
            return sinew_fail(error, SINEW_ERROR_DATA,
                              "%s: clip \"%s\": a weight track names a missing morph channel, comes twice or out of "
                              "order, or is in a clip that shares its keys",
                              m->source, clip->name);
        uint32_t stride = sinew_channel_stride(SINEW_CHANNEL_WEIGHT, ch->interp);
        if (ch->interp > SINEW_INTERP_CUBIC ||
            (!ch->finite && (!sinew_floats_finite(ch->times, ch->count) ||
                             !sinew_floats_finite(ch->values, (size_t)ch->count * stride))))
            return sinew_fail(error, SINEW_ERROR_DATA,
                              "%s: clip \"%s\": the weight keys of morph channel \"%s\" are not finite or of an "
                              "unknown interpolation",
                              m->source, clip->name, m->morph_channels[wt->channel].name);
        bool was_sorted = sinew_times_ascending(ch->times, ch->count);
        if (!was_sorted && !sort_keys(ch, stride))
            return oom(m, error);
        unsorted += !was_sorted;
        /* weights far outside 0..1 are kept, and said: a file scaled in percent, or a broken rig */
        uint32_t at = ch->interp == SINEW_INTERP_CUBIC ? 1 : 0;
        float worst = 0.0f;
        for (uint32_t k = 0; k < ch->count; k++)
            if (fabsf(ch->values[(size_t)k * stride + at]) > fabsf(worst))
                worst = ch->values[(size_t)k * stride + at];
        if (fabsf(worst) > WEIGHT_WARN_LIMIT &&
            !raw_model_warn(m, "%s: clip \"%s\": morph channel \"%s\" reaches weight %g, outside -%g..%g; kept",
                            m->source, clip->name, m->morph_channels[wt->channel].name, (double)worst,
                            WEIGHT_WARN_LIMIT, WEIGHT_WARN_LIMIT))
            return oom(m, error);
    }
    if (!isfinite(clip->timeline))
        clip->timeline = 0.0f;
    if (!(clip->frame_rate > 0.0f) || !isfinite(clip->frame_rate))
        clip->frame_rate = 0.0f;
    if (unsorted)
        raw_model_warn(m, "clip \"%s\": %u channels had keys out of time order; they were sorted", clip->name,
                       unsorted);
    return SINEW_OK;
}

static int by_weight_track(const void *a, const void *b)
{
    const raw_weight_track *x = a, *y = b;
    return x->channel < y->channel ? -1 : (x->channel > y->channel);
}

/* A delta: its vertex, and where it is in the target's arrays. */
typedef struct delta_order {
    uint32_t vertex, index;
} delta_order;

static int by_vertex(const void *a, const void *b)
{
    const delta_order *x = a, *y = b;
    return x->vertex < y->vertex ? -1 : x->vertex > y->vertex ? 1 : (x->index > y->index) - (x->index < y->index);
}

static int by_channel_weight(const void *a, const void *b)
{
    const raw_morph_target *x = a, *y = b;
    if (x->channel != y->channel)
        return x->channel < y->channel ? -1 : 1;
    return x->full_weight < y->full_weight ? -1 : (x->full_weight > y->full_weight);
}

/* A target's deltas sorted by vertex, each vertex once (a vertex given twice adds up), zero
 * offsets dropped. */
static sinew_result fix_target(raw_model *m, const raw_mesh *mesh, raw_morph_target *t, sinew_error *error)
{
    float **attributes[3] = {&t->positions, &t->normals, &t->tangents};
    bool finite = isfinite(t->full_weight) && t->full_weight != 0.0f && t->positions;
    for (int a = 0; a < 3; a++)
        finite = finite && (!*attributes[a] || sinew_floats_finite(*attributes[a], (size_t)t->delta_count * 3));
    if (!finite)
        return sinew_fail(error, SINEW_ERROR_DATA,
                          "%s: mesh \"%s\": morph target \"%s\" has offsets that are not finite or a full weight of 0",
                          m->source, mesh->name, t->name);
    size_t room = t->delta_count ? t->delta_count : 1;
    delta_order *order = malloc(room * sizeof *order);
    if (!order)
        return oom(m, error);
    for (uint32_t k = 0; k < t->delta_count; k++) {
        if (t->vertices[k] >= mesh->vertex_count) {
            uint32_t v = t->vertices[k];
            free(order);
            return sinew_fail(error, SINEW_ERROR_DATA,
                              "%s: mesh \"%s\": morph target \"%s\" moves vertex %u of a mesh of %u vertices",
                              m->source, mesh->name, t->name, v, mesh->vertex_count);
        }
        order[k] = (delta_order){t->vertices[k], k};
    }
    qsort(order, t->delta_count, sizeof *order, by_vertex);
    uint32_t *vertices = malloc(room * sizeof *vertices);
    float *out[3] = {NULL, NULL, NULL};
    bool ok = vertices != NULL;
    for (int a = 0; a < 3; a++)
        if (*attributes[a])
            ok = ok && (out[a] = malloc(room * 3 * sizeof(float))) != NULL;
    if (!ok) {
        free(order);
        free(vertices);
        for (int a = 0; a < 3; a++)
            free(out[a]);
        return oom(m, error);
    }
    uint32_t n = 0;
    for (uint32_t k = 0; k < t->delta_count; k++) {
        bool again = n > 0 && vertices[n - 1] == order[k].vertex;
        if (!again)
            vertices[n++] = order[k].vertex;
        for (int a = 0; a < 3; a++) {
            if (!out[a])
                continue;
            const float *p = &(*attributes[a])[order[k].index * 3];
            float *q = &out[a][(n - 1) * 3];
            for (int c = 0; c < 3; c++)
                q[c] = again ? q[c] + p[c] : p[c];
        }
    }
    /* offsets that move nothing go */
    uint32_t kept = 0;
    for (uint32_t k = 0; k < n; k++) {
        bool zero = true;
        for (int a = 0; a < 3; a++)
            for (int c = 0; out[a] && c < 3; c++)
                zero = zero && out[a][k * 3 + c] == 0;
        if (zero)
            continue;
        vertices[kept] = vertices[k];
        for (int a = 0; a < 3; a++)
            if (out[a])
                memmove(&out[a][kept * 3], &out[a][k * 3], 3 * sizeof(float));
        kept++;
    }
    /* normal or tangent offsets that are all zero (as exporters write them) are none */
    for (int a = 1; a < 3; a++) {
        bool none = true;
        for (size_t i = 0; out[a] && none && i < (size_t)kept * 3; i++)
            none = out[a][i] == 0.0f;
        if (out[a] && none) {
            free(out[a]);
            out[a] = NULL;
        }
    }
    free(order);
    free(t->vertices);
    t->vertices = vertices;
    for (int a = 0; a < 3; a++) {
        free(*attributes[a]);
        *attributes[a] = out[a];
    }
    t->delta_count = kept;
    return SINEW_OK;
}

/* A mesh's morph targets (sorted by channel and full weight, each with its deltas in order),
 * its vertex cache and its dual-quaternion weights. */
static sinew_result fix_deformers(raw_model *m, uint32_t index, sinew_error *error)
{
    raw_mesh *mesh = &m->meshes[index];
    sinew_result result;
    for (uint32_t t = 0; t < mesh->target_count; t++)
        if ((result = fix_target(m, mesh, &mesh->targets[t], error)))
            return result;
    if (mesh->target_count)
        qsort(mesh->targets, mesh->target_count, sizeof *mesh->targets, by_channel_weight);
    uint32_t channels = 0;
    for (uint32_t t = 0; t < mesh->target_count; t++) {
        if (t > 0 && mesh->targets[t].channel == mesh->targets[t - 1].channel &&
            mesh->targets[t].full_weight == mesh->targets[t - 1].full_weight)
            return sinew_fail(error, SINEW_ERROR_DATA,
                              "%s: mesh \"%s\": morph targets \"%s\" and \"%s\" are whole at the same weight of "
                              "one channel",
                              m->source, mesh->name, mesh->targets[t - 1].name, mesh->targets[t].name);
        if (mesh->targets[t].channel + 1 > channels)
            channels = mesh->targets[t].channel + 1;
    }
    for (uint32_t i = 0; channels && i < m->instance_count; i++)
        if (m->instances[i].mesh == index && (uint64_t)m->instances[i].morph_first + channels > m->morph_channel_count)
            return sinew_fail(error, SINEW_ERROR_DATA,
                              "%s: mesh \"%s\": its morph targets name channels the model does not have", m->source,
                              mesh->name);
    raw_vertex_cache *c = mesh->cache;
    if (c) {
        bool ok = c->frame_count > 0 && sinew_floats_finite(c->times, c->frame_count) &&
                  sinew_floats_finite(c->positions, (size_t)c->frame_count * mesh->vertex_count * 3);
        for (uint32_t k = 1; ok && k < c->frame_count; k++)
            ok = c->times[k] > c->times[k - 1];
        if (!ok)
            return sinew_fail(error, SINEW_ERROR_DATA,
                              "%s: mesh \"%s\": its vertex cache has no frames, frames out of order or positions "
                              "that are not finite",
                              m->source, mesh->name);
    }
    for (uint32_t v = 0; mesh->dq_weights && v < mesh->vertex_count; v++)
        mesh->dq_weights[v] = isfinite(mesh->dq_weights[v]) ? fminf(fmaxf(mesh->dq_weights[v], 0.0f), 1.0f) : 0.0f;
    return SINEW_OK;
}

static int by_node(const void *a, const void *b)
{
    const raw_track *x = a, *y = b;
    return x->node < y->node ? -1 : (x->node > y->node);
}

/* Tracks sorted by node, one per node: later duplicates give only the channels the first
 * lacks, and the rest are dropped with a warning. */
static void merge_tracks(raw_model *m, raw_clip *clip)
{
    if (clip->track_count > 1) /* a clip of no tracks may have no array (qsort wants one) */
        qsort(clip->tracks, clip->track_count, sizeof *clip->tracks, by_node);
    uint32_t out = 0, dropped = 0;
    for (uint32_t t = 0; t < clip->track_count; t++) {
        raw_track *track = &clip->tracks[t];
        if (out > 0 && clip->tracks[out - 1].node == track->node) {
            raw_track *keep = &clip->tracks[out - 1];
            for (int k = 0; k < SINEW_CHANNEL_COUNT; k++) {
                if (keep->channels[k].count == 0 && track->channels[k].count) {
                    keep->channels[k] = track->channels[k];
                } else {
                    dropped += track->channels[k].count > 0;
                    free(track->channels[k].times);
                    free(track->channels[k].values);
                }
                track->channels[k] = (raw_channel){0};
            }
            continue;
        }
        clip->tracks[out++] = *track;
    }
    clip->track_count = out;
    if (dropped)
        raw_model_warn(
            m, "clip \"%s\": %u channels animated a node that another channel already animates; the first was kept",
            clip->name, dropped);
}

/* ---- shared keys -------------------------------------------------------------------------- */

sinew_result raw_model_pool_clip(raw_model *m, raw_clip *clip, sinew_error *error)
{
    merge_tracks(m, clip);
    sinew_result result = fix_clip(m, clip, error);
    if (result)
        return result;
    uint64_t time_count = 0, value_count = 0;
    for (uint32_t t = 0; t < clip->track_count; t++)
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++) {
            const raw_channel *ch = &clip->tracks[t].channels[k];
            if (ch->pool)
                return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s: clip \"%s\" shares its keys already",
                                  m->source, clip->name);
            time_count += ch->count;
            value_count += (uint64_t)ch->count * sinew_channel_stride(k, ch->interp);
        }
    if (time_count > UINT32_MAX / 4 || value_count > UINT32_MAX / 4)
        return sinew_fail(error, SINEW_ERROR_LIMIT, "%s: clip \"%s\" has more keys than a model holds", m->source,
                          clip->name);
    raw_key_pool *pools = realloc(m->pools, (m->pool_count + 1) * sizeof *pools);
    if (!pools)
        return oom(m, error);
    m->pools = pools;
    raw_key_pool pool = {(uint32_t)time_count, (uint32_t)value_count,
                         malloc((time_count ? time_count : 1) * sizeof(float)),
                         malloc((value_count ? value_count : 1) * sizeof(float))};
    if (!pool.times || !pool.values) {
        free(pool.times);
        free(pool.values);
        return oom(m, error);
    }
    uint32_t at_time = 0, at_value = 0;
    for (uint32_t t = 0; t < clip->track_count; t++)
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++) {
            raw_channel *ch = &clip->tracks[t].channels[k];
            uint32_t n_values = ch->count * sinew_channel_stride(k, ch->interp);
            if (ch->count) {
                memcpy(pool.times + at_time, ch->times, ch->count * sizeof(float));
                memcpy(pool.values + at_value, ch->values, n_values * sizeof(float));
            }
            free(ch->times);
            free(ch->values);
            *ch = (raw_channel){.interp = ch->interp,
                                .count = ch->count,
                                .pool = ch->count ? m->pool_count + 1 : 0,
                                .first_key = at_time,
                                .first_value = at_value};
            at_time += ch->count;
            at_value += n_values;
        }
    m->pools[m->pool_count++] = pool;
    return SINEW_OK;
}

/* How many of the sorted times are below t (or at it, with `at`). */
static uint32_t count_below(const float *times, uint32_t n, float t, bool at)
{
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (times[mid] < t || (at && times[mid] == t))
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* The keys of a pooled channel that a window [from, to] reaches: the last at or before
 * `from` to the first at or after `to`, and one more each side where there is one (so that
 * rounding in start + time never falls off an end). */
static raw_channel window_channel(const raw_model *m, const raw_channel *ch, int kind, float from, float to)
{
    if (ch->count == 0)
        return *ch;
    const float *times = m->pools[ch->pool - 1].times + ch->first_key;
    uint32_t n = ch->count;
    uint32_t lo = count_below(times, n, from, true); /* keys <= from */
    uint32_t hi = count_below(times, n, to, false);  /* keys < to: the first >= to is next */
    lo = lo > 1 ? lo - 2 : 0;
    hi = hi + 1 < n ? hi + 1 : n - 1;
    raw_channel out = *ch;
    out.count = hi - lo + 1;
    out.first_key += lo;
    out.first_value += lo * sinew_channel_stride(kind, ch->interp);
    return out;
}

bool raw_model_add_window(raw_model *m, const raw_clip *pooled, const char *name, float start, float duration,
                          const bool *keep)
{
    raw_clip clip = {.name = raw_strdup(name), .duration = duration, .start = pooled->start + start};
    clip.tracks = calloc(pooled->track_count ? pooled->track_count : 1, sizeof *clip.tracks);
    raw_clip *clips = clip.name && clip.tracks ? realloc(m->clips, (m->clip_count + 1) * sizeof *clips) : NULL;
    if (!clips) {
        raw_clip_free(&clip);
        return false;
    }
    m->clips = clips;
    for (uint32_t t = 0; t < pooled->track_count; t++) {
        const raw_track *track = &pooled->tracks[t];
        if (keep && (track->node >= m->node_count || !keep[track->node]))
            continue;
        raw_track *out = &clip.tracks[clip.track_count++];
        out->node = track->node;
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++)
            out->channels[k] = window_channel(m, &track->channels[k], k, clip.start, clip.start + duration);
    }
    m->clips[m->clip_count++] = clip;
    return true;
}

/* ---- blob writer ------------------------------------------------------------------------ */

typedef struct writer {
    unsigned char *bytes;
    size_t size, capacity;
    char *pool;
    size_t pool_size, pool_capacity;
    bool failed;
    bool too_big; /* failed for the blob's 4 GiB, not for memory */
    bool measure; /* only count: the first of raw_model_write's two passes */
} writer;

static bool writer_reserve(unsigned char **buf, size_t *capacity, size_t need)
{
    if (need <= *capacity)
        return true;
    size_t cap = *capacity ? *capacity : 4096;
    while (cap < need)
        cap *= 2;
    unsigned char *grown = realloc(*buf, cap);
    if (!grown)
        return false;
    *buf = grown;
    *capacity = cap;
    return true;
}

/* Room for `bytes` at the next 16-byte boundary, written by the caller through writer_at()
 * (or by writer_put); BLOB_NONE for nothing. */
static uint32_t writer_space(writer *w, size_t bytes)
{
    if (w->failed || bytes == 0)
        return BLOB_NONE;
    size_t at = (w->size + BLOB_ALIGN - 1) & ~(size_t)(BLOB_ALIGN - 1);
    w->too_big = w->too_big || at + bytes > UINT32_MAX;
    if (w->measure && !w->too_big) {
        w->size = at + bytes;
        return (uint32_t)at;
    }
    if (at + bytes > UINT32_MAX || !writer_reserve(&w->bytes, &w->capacity, at + bytes)) {
        w->failed = true;
        return BLOB_NONE;
    }
    memset(w->bytes + w->size, 0, at - w->size);
    w->size = at + bytes;
    return (uint32_t)at;
}

/* Where writer_space's room is, until the next put; NULL while measuring or for nothing. */
static void *writer_at(const writer *w, uint32_t offset)
{
    return w->measure || w->failed || offset == BLOB_NONE ? NULL : w->bytes + offset;
}

/* Appends bytes at the next 16-byte boundary; returns their offset (BLOB_NONE for nothing). */
static uint32_t writer_put(writer *w, const void *data, size_t bytes)
{
    if (!data)
        return BLOB_NONE;
    uint32_t at = writer_space(w, bytes);
    void *room = writer_at(w, at);
    if (room)
        memcpy(room, data, bytes);
    return at;
}

static uint32_t writer_string(writer *w, const char *text)
{
    if (!text || w->failed)
        return BLOB_NONE;
    size_t n = strlen(text) + 1;
    w->too_big = w->too_big || w->pool_size + n > UINT32_MAX - 1;
    if (w->pool_size + n > UINT32_MAX - 1 ||
        !writer_reserve((unsigned char **)&w->pool, &w->pool_capacity, w->pool_size + n)) {
        w->failed = true;
        return BLOB_NONE;
    }
    memcpy(w->pool + w->pool_size, text, n);
    uint32_t at = (uint32_t)w->pool_size;
    w->pool_size += n;
    return at;
}

static blob_span writer_strings(writer *w, char *const *texts, uint32_t count)
{
    uint32_t *offsets = malloc((count ? count : 1) * sizeof *offsets);
    if (!offsets) {
        w->failed = true;
        return (blob_span){BLOB_NONE, 0};
    }
    for (uint32_t i = 0; i < count; i++)
        offsets[i] = writer_string(w, texts[i]);
    blob_span span = {writer_put(w, offsets, count * sizeof *offsets), count};
    free(offsets);
    return span;
}

static uint32_t write_mesh_joints(writer *w, const raw_mesh *mesh)
{
    size_t n = (size_t)mesh->vertex_count * mesh->influence_count;
    uint16_t *joints = malloc((n ? n : 1) * sizeof *joints);
    if (!joints) {
        w->failed = true;
        return BLOB_NONE;
    }
    for (size_t i = 0; i < n; i++)
        joints[i] = (uint16_t)mesh->joints[i];
    uint32_t at = writer_put(w, joints, n * sizeof *joints);
    free(joints);
    return at;
}

static blob_span write_meshes(writer *w, const raw_model *m)
{
    blob_mesh *table = calloc(m->mesh_count ? m->mesh_count : 1, sizeof *table);
    if (!table) {
        w->failed = true;
        return (blob_span){BLOB_NONE, 0};
    }
    for (uint32_t i = 0; i < m->mesh_count; i++) {
        const raw_mesh *mesh = &m->meshes[i];
        size_t v = mesh->vertex_count, k = mesh->influence_count;
        table[i] = (blob_mesh){
            .name = writer_string(w, mesh->name),
            .vertex_count = mesh->vertex_count,
            .index_count = mesh->index_count,
            .influence_count = mesh->influence_count,
            .skin = mesh->skin,
            .material = mesh->material,
            .positions = writer_put(w, mesh->positions, v * 12),
            .normals = writer_put(w, mesh->normals, v * 12),
            .uvs = writer_put(w, mesh->uvs, v * 8),
            .indices = writer_put(w, mesh->indices, (size_t)mesh->index_count * 4),
            .joints = k ? write_mesh_joints(w, mesh) : BLOB_NONE,
            .weights = k ? writer_put(w, mesh->weights, v * k * 4) : BLOB_NONE,
        };
    }
    blob_span span = {writer_put(w, table, m->mesh_count * sizeof *table), m->mesh_count};
    free(table);
    return span;
}

/* MTAN and MCOL: a table of an offset a mesh for the optional array of 4 floats a vertex at
 * `field` of raw_mesh (tangents, colours), BLOB_NONE where a mesh has none; no section when no
 * mesh has one. */
static blob_span write_mesh_optional(writer *w, const raw_model *m, size_t field)
{
    bool any = false;
    for (uint32_t i = 0; i < m->mesh_count; i++)
        any |= *(float *const *)((const char *)&m->meshes[i] + field) != NULL;
    if (!any)
        return (blob_span){0, 0};
    uint32_t *offsets = malloc(m->mesh_count * sizeof *offsets);
    if (!offsets) {
        w->failed = true;
        return (blob_span){BLOB_NONE, 0};
    }
    for (uint32_t i = 0; i < m->mesh_count; i++)
        offsets[i] = writer_put(w, *(float *const *)((const char *)&m->meshes[i] + field),
                                (size_t)m->meshes[i].vertex_count * 16);
    blob_span span = {writer_put(w, offsets, m->mesh_count * sizeof *offsets), m->mesh_count};
    free(offsets);
    return span;
}

/* MFLT: a byte a mesh, 1 where it is drawn with flat normals; no section when none is. */
static blob_span write_mesh_flat(writer *w, const raw_model *m)
{
    bool any = false;
    for (uint32_t i = 0; i < m->mesh_count; i++)
        any |= m->meshes[i].flat_normals;
    if (!any)
        return (blob_span){0, 0};
    uint32_t at = writer_space(w, m->mesh_count);
    uint8_t *flat = writer_at(w, at);
    for (uint32_t i = 0; flat && i < m->mesh_count; i++)
        flat[i] = m->meshes[i].flat_normals;
    return (blob_span){at, m->mesh_count};
}

static blob_span write_skins(writer *w, const raw_model *m)
{
    blob_skin *table = calloc(m->skin_count ? m->skin_count : 1, sizeof *table);
    if (!table) {
        w->failed = true;
        return (blob_span){BLOB_NONE, 0};
    }
    for (uint32_t i = 0; i < m->skin_count; i++) {
        const raw_skin *skin = &m->skins[i];
        table[i].joints = (blob_span){writer_put(w, skin->joints, skin->joint_count * 4u), skin->joint_count};
        table[i].inverse_bind =
            (blob_span){writer_put(w, skin->inverse_bind, skin->joint_count * sizeof(sinew_mat4)), skin->joint_count};
    }
    blob_span span = {writer_put(w, table, m->skin_count * sizeof *table), m->skin_count};
    free(table);
    return span;
}

/* Embedded images already written (maps of one or several materials often share one). */
typedef struct written_images {
    const raw_texture **textures;
    uint32_t *offsets;
    uint32_t count;
} written_images;

static blob_texture write_texture(writer *w, const raw_texture *t, written_images *done)
{
    blob_texture out = {writer_string(w, t->path), {BLOB_NONE, 0}};
    if (!t->image)
        return out;
    for (uint32_t i = 0; i < done->count; i++)
        if (done->textures[i]->image_size == t->image_size &&
            memcmp(done->textures[i]->image, t->image, t->image_size) == 0)
            return (blob_texture){out.path, {done->offsets[i], t->image_size}};
    out.image = (blob_span){writer_put(w, t->image, t->image_size), t->image_size};
    done->textures[done->count] = t;
    done->offsets[done->count++] = out.image.offset;
    return out;
}

/* MATL (name, colour, base colour map) and MPBR (the rest of each material). */
static blob_span write_materials(writer *w, const raw_model *m, blob_span *pbr_span)
{
    size_t n = m->material_count ? m->material_count : 1;
    blob_material *table = calloc(n, sizeof *table);
    blob_pbr *pbr = calloc(n, sizeof *pbr);
    written_images done = {calloc(n * SINEW_MAP_COUNT, sizeof *done.textures),
                           calloc(n * SINEW_MAP_COUNT, sizeof *done.offsets), 0};
    blob_span span = {BLOB_NONE, 0};
    *pbr_span = (blob_span){0, 0};
    if (!table || !pbr || !done.textures || !done.offsets) {
        w->failed = true;
        goto out;
    }
    for (uint32_t i = 0; i < m->material_count; i++) {
        const raw_material *rm = &m->materials[i];
        table[i].name = writer_string(w, rm->name);
        memcpy(table[i].base_color, rm->base_color, sizeof table[i].base_color);
        table[i].base_color_map = write_texture(w, &rm->maps[SINEW_MAP_BASE_COLOR], &done);
        blob_pbr *p = &pbr[i];
        p->metallic = rm->metallic;
        p->roughness = rm->roughness;
        memcpy(p->emissive, rm->emissive, sizeof p->emissive);
        p->normal_scale = rm->normal_scale;
        p->occlusion_strength = rm->occlusion_strength;
        p->flags = rm->metallic_roughness ? 1u : 0u;
        for (int k = 1; k < SINEW_MAP_COUNT; k++)
            p->maps[k - 1] = write_texture(w, &rm->maps[k], &done);
    }
    span = (blob_span){writer_put(w, table, m->material_count * sizeof *table), m->material_count};
    if (m->material_count)
        *pbr_span = (blob_span){writer_put(w, pbr, m->material_count * sizeof *pbr), m->material_count};
out:
    free(table);
    free(pbr);
    free(done.textures);
    free(done.offsets);
    return span;
}

/* MALP: a material's alpha mode and cutoff; no section when every material is opaque. */
static blob_span write_material_alpha(writer *w, const raw_model *m)
{
    bool any = false;
    for (uint32_t i = 0; i < m->material_count; i++)
        any |= m->materials[i].alpha_mode != SINEW_ALPHA_OPAQUE;
    if (!any)
        return (blob_span){0, 0};
    uint32_t at = writer_space(w, (size_t)m->material_count * sizeof(blob_alpha));
    blob_alpha *alpha = writer_at(w, at);
    for (uint32_t i = 0; alpha && i < m->material_count; i++)
        alpha[i] = (blob_alpha){(uint32_t)m->materials[i].alpha_mode, m->materials[i].alpha_cutoff};
    return (blob_span){at, m->material_count};
}

/* Weight tracks of all clips, gathered as the clips are written (WTRK). */
typedef struct weight_table {
    blob_weight_track *tracks;
    uint32_t count, capacity;
} weight_table;

static bool weight_table_push(weight_table *t, const blob_weight_track *track)
{
    if (t->count == t->capacity) {
        uint32_t cap = t->capacity ? t->capacity * 2 : 16;
        blob_weight_track *grown = realloc(t->tracks, cap * sizeof *grown);
        if (!grown)
            return false;
        t->tracks = grown;
        t->capacity = cap;
    }
    t->tracks[t->count++] = *track;
    return true;
}

static uint32_t clip_pool(const raw_clip *clip)
{
    for (uint32_t t = 0; t < clip->track_count; t++)
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++)
            if (clip->tracks[t].channels[k].count)
                return clip->tracks[t].channels[k].pool;
    for (uint32_t t = 0; t < clip->weight_track_count; t++)
        if (clip->weight_tracks[t].keys.count)
            return clip->weight_tracks[t].keys.pool;
    return 0;
}

/* A clip whose channels play a pool's keys: its tracks point into the pool's spans. */
static bool write_pooled_clip(writer *w, const raw_clip *clip, uint32_t index, const blob_span *pool_spans,
                              blob_clip *out, weight_table *weights)
{
    sinew_track *tracks = calloc(clip->track_count ? clip->track_count : 1, sizeof *tracks);
    if (!tracks)
        return false;
    uint32_t pool = clip_pool(clip); /* > 0: the caller found one (a weight track's, when no node track has keys) */
    for (uint32_t t = 0; t < clip->track_count; t++) {
        tracks[t].node = clip->tracks[t].node;
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++) {
            const raw_channel *ch = &clip->tracks[t].channels[k];
            tracks[t].channels[k] = (sinew_channel){ch->count, ch->count ? ch->interp : SINEW_INTERP_LINEAR,
                                                    ch->count ? ch->first_key : 0, ch->count ? ch->first_value : 0};
        }
    }
    *out = (blob_clip){
        .name = writer_string(w, clip->name),
        .duration = clip->duration,
        .start = clip->start,
        .tracks = {writer_put(w, tracks, clip->track_count * sizeof *tracks), clip->track_count},
        .times = pool_spans[2 * (pool - 1)],
        .values = pool_spans[2 * (pool - 1) + 1],
    };
    free(tracks);
    bool ok = true;
    for (uint32_t t = 0; ok && t < clip->weight_track_count; t++) {
        const raw_channel *ch = &clip->weight_tracks[t].keys;
        blob_weight_track bt = {
            index, clip->weight_tracks[t].channel, {ch->count, ch->interp, ch->first_key, ch->first_value}};
        ok = ch->count == 0 || weight_table_push(weights, &bt);
    }
    return ok;
}

/* A channel's keys into the blob's times and values (NULL while measuring) at its offsets; its
 * times only when `times_too` (not when they are another channel's, which it shares). */
static void copy_keys(float *times, float *values, const raw_channel *ch, int kind, const sinew_channel *at,
                      bool times_too)
{
    if (!times || !values || !ch->count)
        return;
    if (times_too)
        memcpy(times + at->first_key, ch->times, ch->count * sizeof(float));
    memcpy(values + at->first_value, ch->values,
           (size_t)ch->count * sinew_channel_stride(kind, ch->interp) * sizeof(float));
}

/* The times of the channels written last, for channels with the same times to share them. */
#define SHARED_TIMES 4
typedef struct recent_times {
    const float *times;
    uint32_t count, first_key;
} recent_times;

/* Where a channel's times start in the clip's array: a recent channel's, when they are the same
 * times (glTF samplers share an input: robot.glb's 1,806 channels have 8 inputs; a baked FBX node's
 * channels share their key times), else `*time_count`, which then grows. */
static uint32_t place_times(recent_times *recent, uint32_t *next, const float *times, uint32_t count,
                            size_t *time_count)
{
    for (int i = 0; i < SHARED_TIMES; i++)
        if (recent[i].times && recent[i].count == count &&
            (recent[i].times == times || memcmp(recent[i].times, times, count * sizeof *times) == 0))
            return recent[i].first_key;
    recent[*next % SHARED_TIMES] = (recent_times){times, count, (uint32_t)*time_count};
    (*next)++;
    uint32_t at = (uint32_t)*time_count;
    *time_count += count;
    return at;
}

/* One clip: every channel's times and values concatenated (its weight tracks' after its
 * node tracks'; channels with the same times share them), tracks pointing into them; the keys
 * are copied straight into the blob. */
static bool write_clip(writer *w, const raw_clip *clip, uint32_t index, blob_clip *out, weight_table *weights)
{
    sinew_track *tracks = calloc(clip->track_count ? clip->track_count : 1, sizeof *tracks);
    if (!tracks)
        return false;
    size_t time_count = 0, value_count = 0;
    recent_times recent[SHARED_TIMES] = {{0}};
    uint32_t next = 0;
    for (uint32_t t = 0; t < clip->track_count; t++) {
        tracks[t].node = clip->tracks[t].node;
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++) {
            const raw_channel *ch = &clip->tracks[t].channels[k];
            uint32_t first_key =
                ch->count ? place_times(recent, &next, ch->times, ch->count, &time_count) : (uint32_t)time_count;
            tracks[t].channels[k] = (sinew_channel){ch->count, ch->count ? ch->interp : SINEW_INTERP_LINEAR, first_key,
                                                    (uint32_t)value_count};
            value_count += (size_t)ch->count * sinew_channel_stride(k, ch->interp);
        }
    }
    size_t node_times = time_count, node_values = value_count; /* where the weight tracks' keys start */
    for (uint32_t t = 0; t < clip->weight_track_count; t++) {
        const raw_channel *ch = &clip->weight_tracks[t].keys;
        time_count += ch->count;
        value_count += (size_t)ch->count * sinew_channel_stride(SINEW_CHANNEL_WEIGHT, ch->interp);
    }
    if (time_count > UINT32_MAX / 4 || value_count > UINT32_MAX / 4) {
        free(tracks);
        return false;
    }
    *out = (blob_clip){
        .name = writer_string(w, clip->name),
        .duration = clip->duration,
        .start = clip->start,
        .tracks = {writer_put(w, tracks, clip->track_count * sizeof *tracks), clip->track_count},
        .times = {writer_space(w, time_count * sizeof(float)), (uint32_t)time_count},
        .values = {writer_space(w, value_count * sizeof(float)), (uint32_t)value_count},
    };
    float *times = writer_at(w, out->times.offset), *values = writer_at(w, out->values.offset);
    /* place_times put each new run of times at the end of those placed before, in this order: a
     * channel whose run starts at the end of the times written so far is the one that placed it */
    size_t written = 0;
    for (uint32_t t = 0; t < clip->track_count; t++)
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++) {
            const raw_channel *ch = &clip->tracks[t].channels[k];
            bool placed = ch->count && tracks[t].channels[k].first_key == written;
            written += placed ? ch->count : 0;
            copy_keys(times, values, ch, k, &tracks[t].channels[k], placed);
        }
    free(tracks);
    bool ok = true;
    for (uint32_t t = 0; ok && t < clip->weight_track_count; t++) { /* after the node tracks' keys */
        const raw_channel *ch = &clip->weight_tracks[t].keys;
        blob_weight_track bt = {
            index,
            clip->weight_tracks[t].channel,
            {ch->count, ch->count ? ch->interp : SINEW_INTERP_LINEAR, (uint32_t)node_times, (uint32_t)node_values}};
        copy_keys(times, values, ch, SINEW_CHANNEL_WEIGHT, &bt.keys, true);
        node_times += ch->count;
        node_values += (size_t)ch->count * sinew_channel_stride(SINEW_CHANNEL_WEIGHT, ch->interp);
        ok = ch->count == 0 || weight_table_push(weights, &bt);
    }
    return ok;
}

/* CLIP, and WTRK (the clips' weight tracks) and CTLN (their timelines) when any has them. */
static blob_span write_clips(writer *w, const raw_model *m, blob_span *weight_span, blob_span *timeline_span)
{
    blob_clip *table = calloc(m->clip_count ? m->clip_count : 1, sizeof *table);
    float *timeline = calloc(m->clip_count ? 2 * m->clip_count : 1, sizeof *timeline);
    weight_table weights = {0};
    *weight_span = *timeline_span = (blob_span){0, 0};
    if (!table || !timeline) {
        free(table);
        free(timeline);
        w->failed = true;
        return (blob_span){BLOB_NONE, 0};
    }
    /* each pool once, whichever clips play it */
    blob_span *pool_spans = calloc(m->pool_count ? 2 * m->pool_count : 1, sizeof *pool_spans);
    if (!pool_spans)
        w->failed = true;
    for (uint32_t i = 0; i < m->pool_count && !w->failed; i++) {
        const raw_key_pool *p = &m->pools[i];
        pool_spans[2 * i] = (blob_span){writer_put(w, p->times, p->time_count * sizeof(float)), p->time_count};
        pool_spans[2 * i + 1] = (blob_span){writer_put(w, p->values, p->value_count * sizeof(float)), p->value_count};
    }
    bool timelines = false;
    for (uint32_t i = 0; i < m->clip_count && !w->failed; i++) {
        uint32_t pool = clip_pool(&m->clips[i]);
        if (!(pool ? write_pooled_clip(w, &m->clips[i], i, pool_spans, &table[i], &weights)
                   : write_clip(w, &m->clips[i], i, &table[i], &weights)))
            w->failed = true;
        timeline[2 * i] = m->clips[i].timeline;
        timeline[2 * i + 1] = m->clips[i].frame_rate;
        timelines |= timeline[2 * i] != 0.0f || timeline[2 * i + 1] != 0.0f;
    }
    blob_span span = {writer_put(w, table, m->clip_count * sizeof *table), m->clip_count};
    if (weights.count)
        *weight_span =
            (blob_span){writer_put(w, weights.tracks, weights.count * sizeof *weights.tracks), weights.count};
    if (timelines)
        *timeline_span = (blob_span){writer_put(w, timeline, 2 * m->clip_count * sizeof *timeline), 2 * m->clip_count};
    free(weights.tracks);
    free(pool_spans);
    free(table);
    free(timeline);
    return span;
}

/* INST and IMRF (each instance's first morph channel, when any is not 0). */
static blob_span write_instances(writer *w, const raw_model *m, blob_span *morph_span)
{
    blob_instance *table = calloc(m->instance_count ? m->instance_count : 1, sizeof *table);
    uint32_t *first = calloc(m->instance_count ? m->instance_count : 1, sizeof *first);
    *morph_span = (blob_span){0, 0};
    blob_span span = {BLOB_NONE, 0};
    if (!table || !first) {
        w->failed = true;
    } else {
        bool any = false;
        for (uint32_t i = 0; i < m->instance_count; i++) {
            table[i] = (blob_instance){m->instances[i].mesh, m->instances[i].node};
            first[i] = m->instances[i].morph_first;
            any |= first[i] != 0;
        }
        span = (blob_span){writer_put(w, table, m->instance_count * sizeof *table), m->instance_count};
        if (any)
            *morph_span = (blob_span){writer_put(w, first, m->instance_count * sizeof *first), m->instance_count};
    }
    free(table);
    free(first);
    return span;
}

/* MCHN, MTGT, VCCH, SKBL and MDQW: what deforms meshes besides the skin's joints. */
static void write_deformers(writer *w, const raw_model *m, blob_header *h)
{
    uint32_t targets = 0, caches = 0;
    bool blends = false, dq = false;
    for (uint32_t i = 0; i < m->mesh_count; i++) {
        targets += m->meshes[i].target_count;
        caches += m->meshes[i].cache != NULL;
        dq |= m->meshes[i].dq_weights != NULL;
    }
    for (uint32_t i = 0; i < m->skin_count; i++)
        blends |= m->skins[i].blend != SINEW_SKIN_BLEND_LINEAR;
    blob_morph_channel *ch = calloc(m->morph_channel_count + 1u, sizeof *ch);
    blob_morph_target *tt = calloc(targets + 1u, sizeof *tt);
    blob_cache *ct = calloc(caches + 1u, sizeof *ct);
    uint32_t *bl = calloc(m->skin_count + 1u, sizeof *bl), *dqo = calloc(m->mesh_count + 1u, sizeof *dqo);
    if (!ch || !tt || !ct || !bl || !dqo) {
        w->failed = true;
        goto out;
    }
    for (uint32_t i = 0; i < m->morph_channel_count; i++)
        ch[i] = (blob_morph_channel){writer_string(w, m->morph_channels[i].name), m->morph_channels[i].default_weight};
    if (m->morph_channel_count)
        h->morph_channels = (blob_span){writer_put(w, ch, m->morph_channel_count * sizeof *ch), m->morph_channel_count};
    uint32_t nt = 0, nc = 0;
    for (uint32_t i = 0; i < m->mesh_count; i++) {
        const raw_mesh *mesh = &m->meshes[i];
        for (uint32_t k = 0; k < mesh->target_count; k++) {
            const raw_morph_target *t = &mesh->targets[k];
            tt[nt++] = (blob_morph_target){
                .mesh = i,
                .name = writer_string(w, t->name),
                .channel = t->channel,
                .full_weight = t->full_weight,
                .delta_count = t->delta_count,
                .vertices = writer_put(w, t->vertices, (size_t)t->delta_count * 4),
                .positions = writer_put(w, t->positions, (size_t)t->delta_count * 12),
                .normals = t->normals ? writer_put(w, t->normals, (size_t)t->delta_count * 12) : BLOB_NONE,
                .tangents = t->tangents ? writer_put(w, t->tangents, (size_t)t->delta_count * 12) : BLOB_NONE};
        }
        if (mesh->cache)
            ct[nc++] = (blob_cache){
                i, mesh->cache->frame_count, writer_put(w, mesh->cache->times, (size_t)mesh->cache->frame_count * 4),
                writer_put(w, mesh->cache->positions, (size_t)mesh->cache->frame_count * mesh->vertex_count * 12)};
        dqo[i] = mesh->dq_weights ? writer_put(w, mesh->dq_weights, (size_t)mesh->vertex_count * 4) : BLOB_NONE;
    }
    if (nt)
        h->morph_targets = (blob_span){writer_put(w, tt, nt * sizeof *tt), nt};
    if (nc)
        h->caches = (blob_span){writer_put(w, ct, nc * sizeof *ct), nc};
    for (uint32_t i = 0; blends && i < m->skin_count; i++)
        bl[i] = m->skins[i].blend;
    if (blends)
        h->skin_blend = (blob_span){writer_put(w, bl, m->skin_count * sizeof *bl), m->skin_count};
    if (dq)
        h->mesh_dq = (blob_span){writer_put(w, dqo, m->mesh_count * sizeof *dqo), m->mesh_count};
out:
    free(ch);
    free(tt);
    free(ct);
    free(bl);
    free(dqo);
}

static uint32_t write_numbers(writer *w, const double *values, uint32_t count)
{
    return writer_put(w, values, (size_t)count * sizeof(double));
}

static blob_span write_muscles(writer *w, const sinew_muscle_set *set)
{
    uint32_t count = set ? set->muscle_count : 0;
    blob_muscle *table = calloc(count ? count : 1, sizeof *table);
    if (!table) {
        w->failed = true;
        return (blob_span){BLOB_NONE, 0};
    }
    for (uint32_t i = 0; i < count; i++) {
        const sinew_muscle_def *d = &set->muscles[i];
        table[i] = (blob_muscle){
            .rest_length = d->rest_length,
            .name = writer_string(w, d->name),
            .origin_joint = writer_string(w, d->origin.joint),
            .insertion_joint = writer_string(w, d->insertion.joint),
            .node_count = d->node_count,
            .segments = d->segments,
            .radii = write_numbers(w, d->radii, d->node_count),
            .coefficients = write_numbers(w, d->coefficients, d->node_count),
        };
        memcpy(table[i].origin_offset, d->origin.offset, sizeof table[i].origin_offset);
        memcpy(table[i].insertion_offset, d->insertion.offset, sizeof table[i].insertion_offset);
        memcpy(table[i].color, d->color, sizeof table[i].color);
    }
    blob_span span = {writer_put(w, table, count * sizeof *table), count};
    free(table);
    return span;
}

/* Header and directory first (filled in at the end), then the tables, then the pool. */
/* Every table of the model into the writer; the header's spans. */
static void write_tables(writer *w, const raw_model *m, size_t head, blob_header *h)
{
    unsigned char *zeros = calloc(1, head);
    if (!zeros)
        w->failed = true;
    writer_put(w, zeros, head);
    free(zeros);
    *h = (blob_header){0};
    h->source = writer_string(w, m->source);
    h->format = writer_string(w, m->format ? m->format : "unknown");
    h->node_names = writer_strings(w, m->node_names, m->node_count);
    h->node_parents = (blob_span){writer_put(w, m->node_parents, m->node_count * 4u), m->node_count};
    h->node_rest = (blob_span){writer_put(w, m->node_rest, m->node_count * sizeof(sinew_transform)), m->node_count};
    bool inherits = false;
    for (uint32_t i = 0; m->node_inherit && i < m->node_count; i++)
        inherits |= m->node_inherit[i] != SINEW_INHERIT_NORMAL;
    if (inherits)
        h->node_inherit = (blob_span){writer_put(w, m->node_inherit, m->node_count), m->node_count};
    h->skins = write_skins(w, m);
    h->meshes = write_meshes(w, m);
    h->mesh_tangents = write_mesh_optional(w, m, offsetof(raw_mesh, tangents));
    h->mesh_flat = write_mesh_flat(w, m);
    h->mesh_colors = write_mesh_optional(w, m, offsetof(raw_mesh, colors));
    h->instances = write_instances(w, m, &h->instance_morph);
    write_deformers(w, m, h);
    h->materials = write_materials(w, m, &h->materials_pbr);
    h->material_alpha = write_material_alpha(w, m);
    h->clips = write_clips(w, m, &h->weight_tracks, &h->clip_timeline);
    h->warnings = writer_strings(w, m->warnings, m->warning_count);
    h->muscles = write_muscles(w, m->muscles);
    h->strings = (blob_span){writer_put(w, w->pool, w->pool_size), (uint32_t)w->pool_size};
}

sinew_result raw_model_write(const raw_model *m, void **bytes, size_t *size, sinew_error *error)
{
    const uint32_t sections = sinew_blob_section_kind_count;
    size_t head = sizeof(blob_file_header) + sections * sizeof(blob_section);
    /* Twice: first counting the bytes, then into one allocation of exactly that size (growing
     * the buffer by doubling copied the blob about twice and touched twice its pages). */
    writer w = {.measure = true};
    blob_header h;
    write_tables(&w, m, head, &h);
    free(w.pool);
    w.pool = NULL;
    if (!w.failed) {
        w = (writer){.capacity = w.size,
                     .bytes = import_large_alloc(w.size, m->blob_in_pages ? MODEL_PAGES_MIN : SIZE_MAX)};
        w.failed = !w.bytes;
    }
    if (!w.failed)
        write_tables(&w, m, head, &h);
    free(w.pool);
    if (w.failed) {
        free(w.bytes);
        return w.too_big
                   ? sinew_fail(error, SINEW_ERROR_LIMIT, "%s: the model does not fit in a 4 GiB blob", m->source)
                   : sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory writing the model", m->source);
    }
    blob_file_header f = {.version = BLOB_VERSION,
                          .header_size = sizeof f,
                          .size = w.size,
                          .section_count = sections,
                          .source = h.source,
                          .format = h.format};
    memcpy(f.magic, BLOB_MAGIC, 8);
    for (uint32_t k = 0; k < sections; k++) {
        const blob_section_kind *kind = &sinew_blob_section_kinds[k];
        const blob_span *span = (const blob_span *)((const char *)&h + kind->field);
        blob_section sec = {
            .offset = span->count ? span->offset : BLOB_NONE, .count = span->count, .elem_size = kind->elem_size};
        memcpy(sec.tag, kind->tag, 4);
        memcpy(w.bytes + sizeof f + k * sizeof sec, &sec, sizeof sec);
    }
    memcpy(w.bytes, &f, sizeof f);
    f.checksum = sinew_blob_checksum(w.bytes, w.size);
    memcpy(w.bytes, &f, sizeof f);
    *bytes = w.bytes;
    *size = w.size;
    return SINEW_OK;
}

static float clamp01(float x)
{
    return isfinite(x) ? fminf(fmaxf(x, 0.0f), 1.0f) : 0.0f;
}

/* Material values in range; readers that know no metallic-roughness parameters leave them
 * zero, which means the defaults (a dielectric of middling roughness, maps at full strength). */
static void fix_material(raw_material *mat)
{
    if (!mat->metallic_roughness) {
        if (!(mat->roughness > 0.0f))
            mat->roughness = 0.5f;
        if (mat->normal_scale == 0.0f)
            mat->normal_scale = 1.0f;
        if (mat->occlusion_strength == 0.0f)
            mat->occlusion_strength = 1.0f;
    }
    mat->metallic = clamp01(mat->metallic);
    mat->roughness = clamp01(mat->roughness);
    mat->occlusion_strength = clamp01(mat->occlusion_strength);
    if (!isfinite(mat->normal_scale))
        mat->normal_scale = 1.0f;
    for (int c = 0; c < 3; c++)
        mat->emissive[c] = isfinite(mat->emissive[c]) ? fmaxf(mat->emissive[c], 0.0f) : 0.0f;
    if (mat->alpha_mode > SINEW_ALPHA_BLEND)
        mat->alpha_mode = SINEW_ALPHA_OPAQUE;
    /* a reader that says nothing leaves 0: glTF's default */
    mat->alpha_cutoff = mat->alpha_mode == SINEW_ALPHA_MASK ? clamp01(mat->alpha_cutoff) : 0.5f;
}

sinew_result raw_model_build(raw_model *m, void **bytes, size_t *size, sinew_error *error)
{
    if (m->warning_lost)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory keeping the import's warnings",
                          m->source ? m->source : "the model");
    sinew_result result = check_nodes(m, error);
    if (result)
        return result;
    for (uint32_t i = 0; i < m->material_count; i++)
        fix_material(&m->materials[i]);
    for (uint32_t i = 0; i < m->morph_channel_count; i++) {
        float w = m->morph_channels[i].default_weight;
        if (!isfinite(w))
            m->morph_channels[i].default_weight = 0.0f;
        else if (fabsf(w) > WEIGHT_WARN_LIMIT &&
                 !raw_model_warn(m, "%s: morph channel \"%s\" has weight %g, outside -%g..%g; kept", m->source,
                                 m->morph_channels[i].name, (double)w, WEIGHT_WARN_LIMIT, WEIGHT_WARN_LIMIT))
            return oom(m, error);
    }
    for (uint32_t i = 0; i < m->mesh_count; i++)
        if ((result = fix_mesh(m, i, error)) || (result = fix_deformers(m, i, error)))
            return result;
    for (uint32_t i = 0; i < m->skin_count; i++)
        if (m->skins[i].blend > SINEW_SKIN_BLEND_MIXED)
            m->skins[i].blend = SINEW_SKIN_BLEND_LINEAR;
    for (uint32_t i = 0; i < m->clip_count; i++) {
        if (m->clips[i].weight_track_count)
            qsort(m->clips[i].weight_tracks, m->clips[i].weight_track_count, sizeof *m->clips[i].weight_tracks,
                  by_weight_track);
        merge_tracks(m, &m->clips[i]);
        if ((result = fix_clip(m, &m->clips[i], error)))
            return result;
    }
    /* fix_mesh may have added fallback joints: check the skins again. */
    if ((result = check_nodes(m, error)))
        return result;
    if (m->warning_lost) /* a repair's warning could not be kept: say so rather than hide the repair */
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory keeping the import's warnings",
                          m->source ? m->source : "the model");
    return raw_model_write(m, bytes, size, error);
}
