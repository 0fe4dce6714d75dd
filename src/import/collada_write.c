/* sinew_model_write_collada: a runtime model as COLLADA 1.4.1, through libxml2's xmlwriter.
 *
 * Ids: every node gets id = sid = its name made a valid, unique XML name (Assimp names
 * nodes by id), and name = its name as it is. Matrices are written row-major, floats with 9
 * significant digits (exact for 32-bit floats). Clips: one timeline, clip i starting 1 s
 * after clip i-1 ends; each animated node has one <animation> with a matrix channel keyed
 * at the union of its channels' key times inside each clip (plus both ends of every clip),
 * and every <animation_clip> instances all of them. Linear keys of translation, rotation
 * and scale baked this way give the same poses between keys (the decomposed matrices lerp
 * and slerp as the channels did).
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "xml.h" /* libxml2, loaded on first use */

#include "../core/internal.h"
#include "internal.h"
#include "sinew/anim.h"
#include "sinew/import.h"

#define CLIP_GAP 1.0f
#define CUBIC_RATE 60.0f

typedef struct text {
    char *data;
    size_t size, capacity;
    bool failed;
} text;

static void text_put(text *t, const char *s)
{
    size_t n = strlen(s);
    if (t->failed)
        return;
    if (t->size + n + 1 > t->capacity) {
        size_t cap = t->capacity ? t->capacity : 4096;
        while (cap < t->size + n + 1)
            cap *= 2;
        char *grown = realloc(t->data, cap);
        if (!grown) {
            t->failed = true;
            return;
        }
        t->data = grown;
        t->capacity = cap;
    }
    memcpy(t->data + t->size, s, n + 1);
    t->size += n;
}

static void text_float(text *t, float v)
{
    char buf[32];
    snprintf(buf, sizeof buf, t->size ? " %.9g" : "%.9g", (double)v);
    text_put(t, buf);
}

static void text_uint(text *t, uint32_t v)
{
    char buf[16];
    snprintf(buf, sizeof buf, t->size ? " %u" : "%u", v);
    text_put(t, buf);
}

static void text_matrix(text *t, const sinew_mat4 *m)
{
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            text_float(t, m->m[c * 4 + r]);
}

typedef struct writer {
    xmlTextWriterPtr w;
    const sinew_model *model;
    char **ids; /* node ids */
    bool failed;
} writer;

static void start(writer *wr, const char *element)
{
    if (xmlTextWriterStartElement(wr->w, BAD_CAST element) < 0)
        wr->failed = true;
}

static void end(writer *wr)
{
    if (xmlTextWriterEndElement(wr->w) < 0)
        wr->failed = true;
}

static void attr(writer *wr, const char *name, const char *value)
{
    if (xmlTextWriterWriteAttribute(wr->w, BAD_CAST name, BAD_CAST value) < 0)
        wr->failed = true;
}

static void attrf(writer *wr, const char *name, const char *format, ...) __attribute__((format(printf, 3, 4)));
static void attrf(writer *wr, const char *name, const char *format, ...)
{
    char buf[512];
    va_list args;
    va_start(args, format);
    vsnprintf(buf, sizeof buf, format, args);
    va_end(args);
    attr(wr, name, buf);
}

static void element_text(writer *wr, const char *element, const char *content)
{
    if (xmlTextWriterWriteElement(wr->w, BAD_CAST element, BAD_CAST content) < 0)
        wr->failed = true;
}

/* Writes and frees the text as the content of the open element. */
static void body(writer *wr, text *t)
{
    if (t->failed || xmlTextWriterWriteString(wr->w, BAD_CAST(t->data ? t->data : "")) < 0)
        wr->failed = true;
    free(t->data);
    *t = (text){0};
}

/* <source id> with a float array of count * stride and an accessor naming the params. */
static void float_source(writer *wr, const char *id, text *values, uint32_t count, uint32_t stride,
                         const char *const *params, uint32_t param_count, const char *type)
{
    start(wr, "source");
    attr(wr, "id", id);
    start(wr, "float_array");
    attrf(wr, "id", "%s-array", id);
    attrf(wr, "count", "%u", count * stride);
    body(wr, values);
    end(wr);
    start(wr, "technique_common");
    start(wr, "accessor");
    attrf(wr, "source", "#%s-array", id);
    attrf(wr, "count", "%u", count);
    attrf(wr, "stride", "%u", stride);
    for (uint32_t i = 0; i < param_count; i++) {
        start(wr, "param");
        attr(wr, "name", params[i]);
        attr(wr, "type", type);
        end(wr);
    }
    end(wr);
    end(wr);
    end(wr);
}

static void name_source(writer *wr, const char *id, text *names, uint32_t count, const char *param)
{
    start(wr, "source");
    attr(wr, "id", id);
    start(wr, "Name_array");
    attrf(wr, "id", "%s-array", id);
    attrf(wr, "count", "%u", count);
    body(wr, names);
    end(wr);
    start(wr, "technique_common");
    start(wr, "accessor");
    attrf(wr, "source", "#%s-array", id);
    attrf(wr, "count", "%u", count);
    attr(wr, "stride", "1");
    start(wr, "param");
    attr(wr, "name", param);
    attr(wr, "type", "name");
    end(wr);
    end(wr);
    end(wr);
    end(wr);
}

/* An <input semantic source [offset] [set]> (offset, set < 0: none). */
static void input(writer *wr, const char *semantic, const char *source, int offset, int set)
{
    start(wr, "input");
    attr(wr, "semantic", semantic);
    attrf(wr, "source", "#%s", source);
    if (offset >= 0)
        attrf(wr, "offset", "%d", offset);
    if (set >= 0)
        attrf(wr, "set", "%d", set);
    end(wr);
}

/* ---- ids ------------------------------------------------------------------------------------ */

static bool id_char(char c, bool first)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' ||
           (!first && ((c >= '0' && c <= '9') || c == '-')) /* not '.': COLLADA targets use it */;
}

/* Ids for the nodes, then the meshes (Assimp names both by id): the names made valid XML
 * names, unique across the document (a repeated one gets its index). */
static char **make_ids(const sinew_model *m)
{
    uint32_t count = m->node_count + m->mesh_count;
    char **ids = calloc(count ? count : 1, sizeof *ids);
    for (uint32_t i = 0; ids && i < count; i++) {
        const char *name = i < m->node_count ? m->node_names[i] : m->meshes[i - m->node_count].name;
        size_t n = strlen(name);
        ids[i] = malloc(n + 16);
        if (!ids[i])
            continue;
        size_t k = 0;
        if (n == 0 || !id_char(name[0], true))
            ids[i][k++] = '_';
        for (size_t c = 0; c < n; c++)
            ids[i][k++] = id_char(name[c], false) ? name[c] : '_';
        ids[i][k] = 0;
        bool taken = strcmp(ids[i], "scene") == 0 || strncmp(ids[i], "material", 8) == 0 ||
                     strncmp(ids[i], "skin", 4) == 0 || strncmp(ids[i], "clip", 4) == 0;
        for (uint32_t j = 0; j < i && !taken; j++)
            taken = ids[j] && strcmp(ids[j], ids[i]) == 0;
        if (taken)
            snprintf(ids[i] + k, 16, "_%u", i);
    }
    return ids;
}

/* ---- library parts ------------------------------------------------------------------------- */

static void write_materials(writer *wr)
{
    const sinew_model *m = wr->model;
    start(wr, "library_effects");
    for (uint32_t i = 0; i < m->material_count; i++) {
        start(wr, "effect");
        attrf(wr, "id", "material%u-effect", i);
        start(wr, "profile_COMMON");
        start(wr, "technique");
        attr(wr, "sid", "common");
        start(wr, "phong");
        start(wr, "diffuse");
        text t = {0};
        for (int c = 0; c < 4; c++)
            text_float(&t, m->materials[i].base_color[c]);
        start(wr, "color");
        body(wr, &t);
        end(wr);
        end(wr);
        end(wr);
        end(wr);
        end(wr);
        end(wr);
    }
    end(wr);
    start(wr, "library_materials");
    for (uint32_t i = 0; i < m->material_count; i++) {
        start(wr, "material");
        attrf(wr, "id", "material%u", i);
        attr(wr, "name", m->materials[i].name);
        start(wr, "instance_effect");
        attrf(wr, "url", "#material%u-effect", i);
        end(wr);
        end(wr);
    }
    end(wr);
}

static void write_geometry(writer *wr, uint32_t index)
{
    const sinew_mesh *mesh = &wr->model->meshes[index];
    char id[64];
    static const char *const xyz[] = {"X", "Y", "Z"}, *const st[] = {"S", "T"}, *const rgba[] = {"R", "G", "B", "A"};
    start(wr, "geometry");
    attr(wr, "id", wr->ids[wr->model->node_count + index]);
    attr(wr, "name", mesh->name);
    start(wr, "mesh");
    text t = {0};
    for (size_t i = 0; i < (size_t)mesh->vertex_count * 3; i++)
        text_float(&t, mesh->positions[i]);
    snprintf(id, sizeof id, "mesh%u-positions", index);
    float_source(wr, id, &t, mesh->vertex_count, 3, xyz, 3, "float");
    for (size_t i = 0; i < (size_t)mesh->vertex_count * 3; i++)
        text_float(&t, mesh->normals[i]);
    snprintf(id, sizeof id, "mesh%u-normals", index);
    float_source(wr, id, &t, mesh->vertex_count, 3, xyz, 3, "float");
    if (mesh->uvs) {
        for (size_t i = 0; i < (size_t)mesh->vertex_count * 2; i++)
            text_float(&t, mesh->uvs[i]);
        snprintf(id, sizeof id, "mesh%u-uvs", index);
        float_source(wr, id, &t, mesh->vertex_count, 2, st, 2, "float");
    }
    if (mesh->colors) { /* sRGB-encoded, as the reader (and other tools) take COLLADA's colours */
        for (size_t i = 0; i < (size_t)mesh->vertex_count * 4; i++) {
            float c = mesh->colors[i];
            text_float(&t, i % 4 == 3 ? c : c <= 0.0031308f ? 12.92f * c : 1.055f * powf(c, 1.0f / 2.4f) - 0.055f);
        }
        snprintf(id, sizeof id, "mesh%u-colors", index);
        float_source(wr, id, &t, mesh->vertex_count, 4, rgba, 4, "float");
    }
    start(wr, "vertices");
    attrf(wr, "id", "mesh%u-vertices", index);
    snprintf(id, sizeof id, "mesh%u-positions", index);
    input(wr, "POSITION", id, -1, -1);
    end(wr);
    start(wr, "triangles");
    attr(wr, "material", "material");
    attrf(wr, "count", "%u", mesh->index_count / 3);
    snprintf(id, sizeof id, "mesh%u-vertices", index);
    input(wr, "VERTEX", id, 0, -1);
    snprintf(id, sizeof id, "mesh%u-normals", index);
    input(wr, "NORMAL", id, 0, -1);
    if (mesh->uvs) {
        snprintf(id, sizeof id, "mesh%u-uvs", index);
        input(wr, "TEXCOORD", id, 0, 0);
    }
    if (mesh->colors) {
        snprintf(id, sizeof id, "mesh%u-colors", index);
        input(wr, "COLOR", id, 0, 0);
    }
    for (uint32_t i = 0; i < mesh->index_count; i++)
        text_uint(&t, mesh->indices[i]);
    start(wr, "p");
    body(wr, &t);
    end(wr);
    end(wr);
    end(wr);
    end(wr);
}

static void write_controller(writer *wr, uint32_t index)
{
    const sinew_model *m = wr->model;
    const sinew_mesh *mesh = &m->meshes[index];
    const sinew_skin *skin = &m->skins[mesh->skin];
    char id[64];
    start(wr, "controller");
    attrf(wr, "id", "skin%u", index);
    start(wr, "skin");
    attrf(wr, "source", "#%s", wr->ids[m->node_count + index]);
    element_text(wr, "bind_shape_matrix", "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1");
    text t = {0};
    for (uint32_t j = 0; j < skin->joint_count; j++) {
        if (t.size)
            text_put(&t, " ");
        text_put(&t, wr->ids[skin->joints[j]]);
    }
    snprintf(id, sizeof id, "skin%u-joints", index);
    name_source(wr, id, &t, skin->joint_count, "JOINT");
    for (uint32_t j = 0; j < skin->joint_count; j++)
        text_matrix(&t, &skin->inverse_bind[j]);
    static const char *const transform[] = {"TRANSFORM"}, *const weight[] = {"WEIGHT"};
    snprintf(id, sizeof id, "skin%u-bind-poses", index);
    float_source(wr, id, &t, skin->joint_count, 16, transform, 1, "float4x4");
    /* one weight value per influence that is not zero */
    uint32_t k = mesh->influence_count, weights = 0;
    text counts = {0}, pairs = {0};
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        uint32_t n = 0;
        for (uint32_t i = 0; i < k && mesh->weights[v * k + i] > 0.0f; i++, n++) {
            text_float(&t, mesh->weights[v * k + i]);
            text_uint(&pairs, mesh->joints[v * k + i]);
            text_uint(&pairs, weights++);
        }
        text_uint(&counts, n);
    }
    snprintf(id, sizeof id, "skin%u-weights", index);
    float_source(wr, id, &t, weights, 1, weight, 1, "float");
    start(wr, "joints");
    snprintf(id, sizeof id, "skin%u-joints", index);
    input(wr, "JOINT", id, -1, -1);
    snprintf(id, sizeof id, "skin%u-bind-poses", index);
    input(wr, "INV_BIND_MATRIX", id, -1, -1);
    end(wr);
    start(wr, "vertex_weights");
    attrf(wr, "count", "%u", mesh->vertex_count);
    snprintf(id, sizeof id, "skin%u-joints", index);
    input(wr, "JOINT", id, 0, -1);
    snprintf(id, sizeof id, "skin%u-weights", index);
    input(wr, "WEIGHT", id, 1, -1);
    start(wr, "vcount");
    body(wr, &counts);
    end(wr);
    start(wr, "v");
    body(wr, &pairs);
    end(wr);
    end(wr);
    end(wr);
    end(wr);
}

/* ---- animation ------------------------------------------------------------------------------- */

static int compare_floats(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

/* The node's local transform in a clip at a time on its keys' timeline (rest where it has
 * no track). */
static void node_at(const sinew_model *m, const sinew_clip *clip, const sinew_track *track, uint32_t node, float t,
                    sinew_mat4 *out)
{
    sinew_transform local = m->node_rest[node];
    float *targets[SINEW_CHANNEL_COUNT] = {local.translation, local.rotation, local.scale};
    for (int k = 0; track && k < SINEW_CHANNEL_COUNT; k++)
        if (track->channels[k].key_count)
            sinew_channel_eval_keys(clip, &track->channels[k], k, t, NULL, targets[k]);
    sinew_transform_to_mat4(&local, out);
}

static const sinew_track *find_track(const sinew_clip *clip, uint32_t node)
{
    for (uint32_t i = 0; i < clip->track_count; i++)
        if (clip->tracks[i].node == node)
            return &clip->tracks[i];
    return NULL;
}

/* Key times of a node in one clip, on its keys' timeline (clip time + start): its
 * channels' keys, both ends, cubic spans sampled. */
static uint32_t clip_times(const sinew_clip *clip, const sinew_track *track, float *out, uint32_t capacity, bool *step)
{
    uint32_t n = 0;
    const float from = clip->start, to = clip->start + clip->duration;
    out[n++] = from;
    out[n++] = to;
    *step = track != NULL;
    for (int k = 0; track && k < SINEW_CHANNEL_COUNT; k++) {
        const sinew_channel *ch = &track->channels[k];
        if (ch->key_count == 0)
            continue;
        *step = *step && ch->interp == SINEW_INTERP_STEP;
        for (uint32_t i = 0; i < ch->key_count && n < capacity; i++) {
            float t = clip->times[ch->first_key + i];
            if (t >= from && t <= to)
                out[n++] = t;
        }
        if (ch->interp == SINEW_INTERP_CUBIC || ch->interp == SINEW_INTERP_BEZIER)
            for (uint32_t i = 0; (float)i / CUBIC_RATE < clip->duration && n < capacity; i++)
                out[n++] = from + (float)i / CUBIC_RATE;
    }
    qsort(out, n, sizeof *out, compare_floats);
    uint32_t unique = 0;
    for (uint32_t i = 0; i < n; i++)
        if (unique == 0 || out[i] != out[unique - 1])
            out[unique++] = out[i];
    return unique;
}

static bool node_animated(const sinew_model *m, uint32_t node)
{
    for (uint32_t c = 0; c < m->clip_count; c++)
        if (find_track(&m->clips[c], node))
            return true;
    return false;
}

static float clip_start(const sinew_model *m, uint32_t clip)
{
    float start = 0.0f;
    for (uint32_t c = 0; c < clip; c++)
        start += m->clips[c].duration + CLIP_GAP;
    return start;
}

static void write_animation(writer *wr, uint32_t node, float *times, uint32_t capacity)
{
    const sinew_model *m = wr->model;
    text in = {0}, out = {0}, interp = {0};
    uint32_t keys = 0;
    for (uint32_t c = 0; c < m->clip_count; c++) {
        const sinew_clip *clip = &m->clips[c];
        const sinew_track *track = find_track(clip, node);
        bool step;
        uint32_t n = clip_times(clip, track, times, capacity, &step);
        float start_at = clip_start(m, c);
        for (uint32_t i = 0; i < n; i++) {
            sinew_mat4 matrix;
            node_at(m, clip, track, node, times[i], &matrix);
            text_float(&in, start_at + (times[i] - clip->start));
            text_matrix(&out, &matrix);
            if (interp.size)
                text_put(&interp, " ");
            text_put(&interp, step ? "STEP" : "LINEAR");
            keys++;
        }
    }
    char id[300];
    start(wr, "animation");
    attrf(wr, "id", "%s-anim", wr->ids[node]);
    static const char *const time[] = {"TIME"}, *const transform[] = {"TRANSFORM"};
    snprintf(id, sizeof id, "%s-anim-input", wr->ids[node]);
    float_source(wr, id, &in, keys, 1, time, 1, "float");
    snprintf(id, sizeof id, "%s-anim-output", wr->ids[node]);
    float_source(wr, id, &out, keys, 16, transform, 1, "float4x4");
    snprintf(id, sizeof id, "%s-anim-interpolation", wr->ids[node]);
    name_source(wr, id, &interp, keys, "INTERPOLATION");
    start(wr, "sampler");
    attrf(wr, "id", "%s-anim-sampler", wr->ids[node]);
    snprintf(id, sizeof id, "%s-anim-input", wr->ids[node]);
    input(wr, "INPUT", id, -1, -1);
    snprintf(id, sizeof id, "%s-anim-output", wr->ids[node]);
    input(wr, "OUTPUT", id, -1, -1);
    snprintf(id, sizeof id, "%s-anim-interpolation", wr->ids[node]);
    input(wr, "INTERPOLATION", id, -1, -1);
    end(wr);
    start(wr, "channel");
    attrf(wr, "source", "#%s-anim-sampler", wr->ids[node]);
    attrf(wr, "target", "%s/transform", wr->ids[node]);
    end(wr);
    end(wr);
}

static bool write_animations(writer *wr)
{
    const sinew_model *m = wr->model;
    if (m->clip_count == 0)
        return true;
    /* room for every key of one node in one clip */
    uint32_t capacity = 2;
    for (uint32_t c = 0; c < m->clip_count; c++) {
        uint32_t here = 2 + 3 * m->clips[c].time_count + (uint32_t)(3.0f * CUBIC_RATE * m->clips[c].duration) + 3;
        capacity = here > capacity ? here : capacity;
    }
    float *times = malloc(capacity * sizeof *times);
    if (!times)
        return false;
    start(wr, "library_animations");
    for (uint32_t n = 0; n < m->node_count; n++)
        if (node_animated(m, n))
            write_animation(wr, n, times, capacity);
    end(wr);
    free(times);
    start(wr, "library_animation_clips");
    for (uint32_t c = 0; c < m->clip_count; c++) {
        start(wr, "animation_clip");
        attrf(wr, "id", "clip%u", c);
        attr(wr, "name", m->clips[c].name);
        attrf(wr, "start", "%.9g", (double)clip_start(m, c));
        attrf(wr, "end", "%.9g", (double)(clip_start(m, c) + m->clips[c].duration));
        for (uint32_t n = 0; n < m->node_count; n++)
            if (node_animated(m, n)) {
                start(wr, "instance_animation");
                attrf(wr, "url", "#%s-anim", wr->ids[n]);
                end(wr);
            }
        end(wr);
    }
    end(wr);
    return true;
}

/* ---- scene ------------------------------------------------------------------------------------ */

static void bind_material(writer *wr, int32_t material)
{
    if (material < 0)
        return;
    start(wr, "bind_material");
    start(wr, "technique_common");
    start(wr, "instance_material");
    attr(wr, "symbol", "material");
    attrf(wr, "target", "#material%d", material);
    end(wr);
    end(wr);
    end(wr);
}

static void write_node(writer *wr, uint32_t node)
{
    const sinew_model *m = wr->model;
    start(wr, "node");
    attr(wr, "id", wr->ids[node]);
    attr(wr, "sid", wr->ids[node]);
    attr(wr, "name", m->node_names[node]);
    attr(wr, "type", sinew_model_node_is_joint(m, node) ? "JOINT" : "NODE");
    sinew_mat4 matrix;
    sinew_transform_to_mat4(&m->node_rest[node], &matrix);
    text t = {0};
    text_matrix(&t, &matrix);
    start(wr, "matrix");
    attr(wr, "sid", "transform");
    body(wr, &t);
    end(wr);
    for (uint32_t i = 0; i < m->instance_count; i++) {
        const sinew_instance *in = &m->instances[i];
        const sinew_mesh *mesh = &m->meshes[in->mesh];
        if (in->node != node || mesh->skin >= 0)
            continue;
        start(wr, "instance_geometry");
        attrf(wr, "url", "#%s", wr->ids[m->node_count + in->mesh]);
        bind_material(wr, mesh->material);
        end(wr);
    }
    for (uint32_t c = node + 1; c < m->node_count; c++)
        if (m->node_parents[c] == (int32_t)node)
            write_node(wr, c);
    end(wr);
}

/* Skinned meshes are placed by their joints: each is instanced once, at the scene's top. */
static void write_skinned_instances(writer *wr)
{
    const sinew_model *m = wr->model;
    for (uint32_t i = 0; i < m->mesh_count; i++) {
        const sinew_mesh *mesh = &m->meshes[i];
        if (mesh->skin < 0)
            continue;
        const sinew_skin *skin = &m->skins[mesh->skin];
        uint32_t root = skin->joint_count ? skin->joints[0] : 0;
        while (m->node_parents[root] >= 0 && sinew_model_node_is_joint(m, (uint32_t)m->node_parents[root]))
            root = (uint32_t)m->node_parents[root];
        start(wr, "node");
        attrf(wr, "id", "skinned-mesh%u", i);
        attr(wr, "name", mesh->name);
        attr(wr, "type", "NODE");
        start(wr, "instance_controller");
        attrf(wr, "url", "#skin%u", i);
        char skeleton[300];
        snprintf(skeleton, sizeof skeleton, "#%s", wr->ids[root]);
        element_text(wr, "skeleton", skeleton);
        bind_material(wr, mesh->material);
        end(wr);
        end(wr);
    }
}

sinew_result sinew_model_write_collada(const sinew_model *model, const char *path, sinew_error *error)
{
    if (!model || !path)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_model_write_collada: NULL argument");
    char why[256];
    if (!import_xml_load(why, sizeof why))
        return sinew_fail(error, SINEW_ERROR_UNSUPPORTED, "%s: writing COLLADA needs libxml2, and %s", path, why);
    for (uint32_t i = 0; model->node_inherit && i < model->node_count; i++)
        if (model->node_inherit[i] != SINEW_INHERIT_NORMAL)
            return sinew_fail(error, SINEW_ERROR_LIMIT,
                              "%s: node \"%s\" does not inherit its parent's scale as COLLADA does (an FBX inherit "
                              "type); write a .sinew file instead",
                              path, model->node_names[i]);
    writer wr = {.model = model, .ids = make_ids(model)};
    const uint32_t id_count = model->node_count + model->mesh_count;
    for (uint32_t i = 0; wr.ids && i < id_count; i++)
        if (!wr.ids[i])
            wr.failed = true;
    if (!wr.ids || wr.failed) {
        for (uint32_t i = 0; wr.ids && i < id_count; i++)
            free(wr.ids[i]);
        free(wr.ids);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    /* Built in memory and written whole (import_write_file): a failure leaves no half file. */
    xmlBufferPtr buffer = xmlBufferCreate();
    wr.w = buffer ? xmlNewTextWriterMemory(buffer, 0) : NULL;
    if (!wr.w) {
        xmlBufferFree(buffer);
        for (uint32_t i = 0; i < id_count; i++)
            free(wr.ids[i]);
        free(wr.ids);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    xmlTextWriterSetIndent(wr.w, 1);
    xmlTextWriterSetIndentString(wr.w, BAD_CAST "  ");
    if (xmlTextWriterStartDocument(wr.w, NULL, "utf-8", NULL) < 0)
        wr.failed = true;
    start(&wr, "COLLADA");
    attr(&wr, "xmlns", "http://www.collada.org/2005/11/COLLADASchema");
    attr(&wr, "version", "1.4.1");
    start(&wr, "asset");
    start(&wr, "contributor");
    element_text(&wr, "authoring_tool", "sinew");
    end(&wr);
    element_text(&wr, "created", "2026-01-01T00:00:00Z");
    element_text(&wr, "modified", "2026-01-01T00:00:00Z");
    start(&wr, "unit");
    attr(&wr, "name", "meter");
    attr(&wr, "meter", "1");
    end(&wr);
    element_text(&wr, "up_axis", "Y_UP");
    end(&wr);
    write_materials(&wr);
    start(&wr, "library_geometries");
    for (uint32_t i = 0; i < model->mesh_count; i++)
        write_geometry(&wr, i);
    end(&wr);
    start(&wr, "library_controllers");
    for (uint32_t i = 0; i < model->mesh_count; i++)
        if (model->meshes[i].skin >= 0)
            write_controller(&wr, i);
    end(&wr);
    if (!write_animations(&wr))
        wr.failed = true;
    start(&wr, "library_visual_scenes");
    start(&wr, "visual_scene");
    attr(&wr, "id", "scene");
    attr(&wr, "name", "scene");
    for (uint32_t n = 0; n < model->node_count; n++)
        if (model->node_parents[n] < 0)
            write_node(&wr, n);
    write_skinned_instances(&wr);
    end(&wr);
    end(&wr);
    start(&wr, "scene");
    start(&wr, "instance_visual_scene");
    attr(&wr, "url", "#scene");
    end(&wr);
    end(&wr);
    end(&wr);
    if (xmlTextWriterEndDocument(wr.w) < 0)
        wr.failed = true;
    xmlFreeTextWriter(wr.w);
    for (uint32_t i = 0; i < id_count; i++)
        free(wr.ids[i]);
    free(wr.ids);
    sinew_result result =
        wr.failed ? sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", path)
                  : import_write_file(path, xmlBufferContent(buffer), (size_t)xmlBufferLength(buffer), error);
    xmlBufferFree(buffer);
    return result;
}
