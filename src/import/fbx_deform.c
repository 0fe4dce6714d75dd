/* What deforms an FBX geometry besides its skin's clusters: blend shapes, the skin's method
 * (linear, dual quaternion, or the two blended per vertex) and vertex caches; and the weight
 * tracks of the blend channels.
 *
 *   reading ........ fbx_deform_read: collect_channels (BlendShape -> BlendShapeChannel ->
 *                    Shape, or a geometry's own Shape nodes before FBX 7.2), add_channels
 *                    (model morph channels, once a geometry), skin_method, read_cache
 *   emitting ....... fbx_deform_emit: shape_target a shape, then DQ weights and the cache
 *   weight tracks .. fbx_weight_tracks: each channel's DeformPercent baked to linear keys
 *
 * As the tools (and ufbx) read them: a channel's shapes are whole at their FullWeights
 * (percent; 100 when absent), except in Blender's files, whose FullWeights give each offset
 * a weight; the channel's DeformPercent (percent) is its weight; Shape offsets are added to
 * the control points they name. SkinningType "DualQuaternion" skins every vertex with dual
 * quaternions, "Blend" mixes linear and dual quaternion by BlendWeights (0 where a point has
 * none). A VertexCacheDeformer's channel of its Cache file gives every control point's
 * position frame by frame, replacing what the mesh would otherwise show. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fbx_scene.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

#define WEIGHT_TOLERANCE 1e-5 /* of a weight: linear keys stray at most this far from the curve */

/* ---- blend channels --------------------------------------------------------------------- */

/* A channel of the geometry being read: its object (or NULL for a Shape node of the geometry
 * itself in a 7.0/7.1 file), its name and its weight where nothing animates it (percent). */
typedef struct channel_source {
    const fbx_object *object;
    const char *name;
    size_t name_len;
    double percent;
} channel_source;

typedef struct collect {
    scene *s;
    fbx_deform *d;
    channel_source *channels;
    uint32_t channel_capacity, shape_capacity;
} collect;

static sinew_result push_shape(collect *c, const fbx_node *node, const char *name, size_t name_len, double full_weight,
                               const double *scale)
{
    fbx_deform *d = c->d;
    if (d->shape_count == c->shape_capacity) {
        uint32_t cap = c->shape_capacity ? c->shape_capacity * 2 : 8;
        fbx_shape_source *grown = realloc(d->shapes, cap * sizeof *grown);
        if (!grown)
            return fbx_oom(c->s);
        d->shapes = grown;
        c->shape_capacity = cap;
    }
    d->shapes[d->shape_count++] = (fbx_shape_source){.node = node,
                                                     .name = name,
                                                     .name_len = name_len,
                                                     .full_weight = full_weight,
                                                     .vertex_scale = scale,
                                                     .channel = d->channel_count - 1};
    return SINEW_OK;
}

static sinew_result push_channel(collect *c, const fbx_object *o, const char *name, size_t name_len, double percent)
{
    if (c->d->channel_count == c->channel_capacity) {
        uint32_t cap = c->channel_capacity ? c->channel_capacity * 2 : 8;
        channel_source *grown = realloc(c->channels, cap * sizeof *grown);
        if (!grown)
            return fbx_oom(c->s);
        c->channels = grown;
        c->channel_capacity = cap;
    }
    c->channels[c->d->channel_count++] = (channel_source){o, name, name_len, percent};
    return SINEW_OK;
}

/* A node's first value as a name ("Shape: "Name"", or "Class::Name"). */
static void node_name(const fbx_node *n, const char **name, size_t *len)
{
    *name = "";
    *len = 0;
    if (n->value_count && n->values[0].type == FBX_STRING)
        fbx_object_name(&n->values[0], name, len);
}

/* The Default of a model's Channel named `name` or "`name` (Shape)" (FBX 5.x keeps a shape's
 * weight there), or NAN. */
static double channel_default(const fbx_node *model, const char *name, size_t len)
{
    for (uint32_t i = 0; model && i < model->child_count; i++) {
        const fbx_node *ch = &model->children[i];
        if (!fbx_named(ch, "Channel") || !ch->value_count || ch->values[0].type != FBX_STRING)
            continue;
        const fbx_value *v = &ch->values[0];
        bool same = v->count == len && memcmp(v->s, name, len) == 0;
        bool suffixed = v->count == len + 8 && memcmp(v->s, name, len) == 0 && memcmp(v->s + len, " (Shape)", 8) == 0;
        const fbx_node *def = fbx_child(ch, "Default");
        if ((same || suffixed) && def)
            return fbx_num(def, 0);
    }
    return NAN;
}

/* A BlendShapeChannel: its shapes in the order of their connections, whole at FullWeights. */
static sinew_result add_blend_channel(collect *c, const fbx_object *ch)
{
    scene *s = c->s;
    const fbx_node *dp = fbx_child(ch->node, "DeformPercent");
    double percent = fbx_prop_num(ch, "DeformPercent", dp ? fbx_num(dp, 0) : 0.0);
    sinew_result result = push_channel(c, ch, ch->name, ch->name_len, percent);
    uint32_t full_count = 0, shape = 0;
    const double *full = fbx_array(ch->node, "FullWeights", &full_count);
    for (uint32_t k = 0; k < ch->child_count && !result; k++) {
        const fbx_object *o = &s->objects[fbx_child_link(s, ch, k)->child];
        if (o->kind != K_SHAPE)
            continue;
        uint32_t offsets = 0;
        fbx_array(o->node, "Indexes", &offsets);
        if (s->blender && full && full_count == offsets && offsets > 0)
            result = push_shape(c, o->node, o->name, o->name_len, 100.0, full); /* Blender: a weight an offset */
        else
            result =
                push_shape(c, o->node, o->name, o->name_len, full && shape < full_count ? full[shape] : 100.0, NULL);
        shape++;
    }
    return result;
}

/* A Shape node kept in the geometry (FBX before 7.2): a channel of its own, named after it,
 * whose weight is the model's property of that name (FBX 6.x) or its channel's Default (5.x). */
static sinew_result add_shape_node(collect *c, const fbx_object *o, const fbx_node *shape, const fbx_node *model)
{
    const char *name;
    size_t len;
    node_name(shape, &name, &len);
    char key[256];
    snprintf(key, sizeof key, "%.*s", (int)(len < 255 ? len : 255), name);
    double percent = o ? fbx_prop_num(o, key, NAN) : NAN;
    if (isnan(percent))
        percent = channel_default(model, name, len);
    sinew_result result = push_channel(c, o, name, len, isnan(percent) ? 0.0 : percent);
    return result ? result : push_shape(c, shape, name, len, 100.0, NULL);
}

/* The geometry's channels, in the order of its deformers' connections. */
static sinew_result collect_channels(collect *c, const fbx_object *g)
{
    scene *s = c->s;
    sinew_result result = SINEW_OK;
    for (uint32_t k = 0; k < g->child_count && !result; k++) {
        const fbx_object *o = &s->objects[fbx_child_link(s, g, k)->child];
        if (o->kind == K_BLEND_SHAPE) {
            for (uint32_t j = 0; j < o->child_count && !result; j++) {
                const fbx_object *ch = &s->objects[fbx_child_link(s, o, j)->child];
                if (ch->kind == K_BLEND_CHANNEL)
                    result = add_blend_channel(c, ch);
            }
        } else if (o->kind == K_BLEND_CHANNEL && fbx_named(o->node, "Shape")) {
            result = add_shape_node(c, o, o->node, g->node); /* fbx_legacy.c's: the geometry is the model's node */
        }
    }
    /* FBX 7.0 and 7.1 keep shapes in the geometry too, without objects (not animated) */
    for (uint32_t i = 0; !s->legacy && s->doc.version <= 7100 && i < g->node->child_count && !result; i++)
        if (fbx_named(&g->node->children[i], "Shape"))
            result = add_shape_node(c, NULL, &g->node->children[i], NULL);
    return result;
}

/* Model morph channels for the geometry's channels: made the first time, shared by every mesh
 * and instance of it after. */
static sinew_result add_channels(collect *c, const fbx_object *g)
{
    scene *s = c->s;
    raw_model *m = s->model;
    fbx_deform *d = c->d;
    uint32_t gi = (uint32_t)(g - s->objects);
    if (d->channel_count == 0)
        return SINEW_OK;
    if (s->geometry_channel[gi] >= 0) {
        d->first_channel = s->geometry_channel[gi];
        return SINEW_OK;
    }
    uint32_t n = m->morph_channel_count + d->channel_count;
    raw_morph_channel *channels = realloc(m->morph_channels, n * sizeof *channels);
    if (channels)
        m->morph_channels = channels;
    int32_t *objects = realloc(s->channel_object, n * sizeof *objects);
    if (objects)
        s->channel_object = objects;
    if (!channels || !objects)
        return fbx_oom(s);
    d->first_channel = (int32_t)m->morph_channel_count;
    s->geometry_channel[gi] = d->first_channel;
    for (uint32_t i = 0; i < d->channel_count; i++) {
        const channel_source *src = &c->channels[i];
        char *name = malloc(src->name_len + 1);
        if (!name)
            return fbx_oom(s);
        memcpy(name, src->name, src->name_len);
        name[src->name_len] = 0;
        uint32_t k = m->morph_channel_count++;
        m->morph_channels[k] = (raw_morph_channel){name, (float)(src->percent / 100.0)};
        s->channel_object[k] = src->object ? (int32_t)(src->object - s->objects) : -1;
    }
    return SINEW_OK;
}

/* ---- the skin's method ------------------------------------------------------------------ */

/* SkinningType: "Linear" and "Rigid" blend linearly, "DualQuaternion" with dual quaternions,
 * "Blend" both, by each control point's BlendWeights (0 for points it does not list). */
static sinew_result skin_method(scene *s, const fbx_object *skin, fbx_deform *d)
{
    d->blend = SINEW_SKIN_BLEND_LINEAR;
    if (!skin)
        return SINEW_OK;
    const fbx_node *type = fbx_child(skin->node, "SkinningType");
    if (!type || !type->value_count || type->values[0].type != FBX_STRING)
        return SINEW_OK;
    if (fbx_str_is(type, 0, "DualQuaternion")) {
        d->blend = SINEW_SKIN_BLEND_DUAL_QUATERNION;
        return SINEW_OK;
    }
    if (!fbx_str_is(type, 0, "Blend"))
        return SINEW_OK;
    uint32_t ni = 0, nw = 0;
    const double *idx = fbx_array(skin->node, "Indexes", &ni);
    const double *w = fbx_array(skin->node, "BlendWeights", &nw);
    if (!idx || !w || ni == 0)
        return SINEW_OK; /* no point is blended: linear */
    if (ni != nw)
        return fbx_fail_data(s, "skin has another number of blend weights than of their indices", skin);
    d->dq = calloc(d->point_count ? d->point_count : 1, sizeof *d->dq);
    if (!d->dq)
        return fbx_oom(s);
    for (uint32_t i = 0; i < ni; i++) {
        if (!(idx[i] >= 0 && idx[i] < d->point_count) || !isfinite(w[i]))
            return fbx_fail_data(s, "skin has a blend weight of a vertex outside its mesh, or one that is not finite",
                                 skin);
        d->dq[(uint32_t)idx[i]] = (float)fmin(fmax(w[i], 0.0), 1.0);
    }
    d->blend = SINEW_SKIN_BLEND_MIXED;
    return SINEW_OK;
}

/* ---- vertex caches ---------------------------------------------------------------------- */

/* The cache a VertexCacheDeformer of the geometry reads (its positions channel), as frames
 * of the geometry's control points. A file that is missing, unreadable or of another point
 * count is a warning: the mesh keeps its shape. */
static sinew_result read_cache(scene *s, const fbx_object *g, fbx_deform *d)
{
    for (uint32_t k = 0; k < g->child_count; k++) {
        const fbx_object *def = &s->objects[fbx_child_link(s, g, k)->child];
        if (def->kind != K_CACHE_DEFORMER)
            continue;
        const fbx_value *channel = fbx_prop_string(def, "ChannelName");
        char name[256] = "";
        if (channel)
            snprintf(name, sizeof name, "%.*s", (int)channel->count, channel->s);
        size_t len = strlen(name);
        if (len >= 8 && strcmp(name + len - 8, "_normals") == 0)
            continue; /* Maya writes the normals as a channel of their own */
        const fbx_object *file = fbx_linked(s, def, K_CACHE, true, true);
        const fbx_value *rel = file ? fbx_prop_string(file, "CacheFileName") : NULL;
        const fbx_value *abs = file ? fbx_prop_string(file, "CacheAbsoluteFileName") : NULL;
        char ref[1024] = "", looked[1024] = "";
        char *path = NULL;
        const fbx_value *tries[2] = {rel, abs};
        for (int t = 0; t < 2 && !path; t++) {
            if (!tries[t] || !tries[t]->count)
                continue;
            snprintf(ref, sizeof ref, "%.*s", (int)tries[t]->count, tries[t]->s);
            path = import_find_texture(s->path, ref, false, looked, sizeof looked);
            if (!path)
                path = import_find_texture(s->path, ref, true, looked, sizeof looked);
        }
        if (!path) {
            if (!raw_model_warn(s->model,
                                "%s: mesh \"%.*s\": its vertex cache \"%s\" is missing (looked for %s); the mesh shows "
                                "its base shape",
                                s->path, (int)g->name_len, g->name, ref[0] ? ref : "(no file name)", looked))
                return fbx_oom(s);
            return SINEW_OK;
        }
        fbx_cache_data data = {0};
        char why[512];
        sinew_result result = fbx_cache_read(path, name[0] ? name : NULL, s->frame_rate, &data, why, sizeof why);
        free(path);
        if (result == SINEW_ERROR_OUT_OF_MEMORY)
            return fbx_oom(s);
        if (result == SINEW_OK && data.point_count != d->point_count) {
            snprintf(why, sizeof why, "its cache has %u points a frame, the mesh %u", data.point_count, d->point_count);
            result = SINEW_ERROR_DATA;
        }
        if (result) {
            fbx_cache_free(&data);
            return raw_model_warn(s->model,
                                  "%s: mesh \"%.*s\": vertex cache left out: %s; the mesh shows its base shape",
                                  s->path, (int)g->name_len, g->name, why)
                       ? SINEW_OK
                       : fbx_oom(s);
        }
        d->frame_count = data.frame_count;
        d->frame_times = data.times;
        d->frames = data.positions;
        return SINEW_OK;
    }
    return SINEW_OK;
}

sinew_result fbx_deform_read(scene *s, const fbx_object *g, const fbx_object *skin, uint32_t point_count,
                             fbx_deform *out)
{
    memset(out, 0, sizeof *out);
    out->first_channel = -1;
    out->point_count = point_count;
    collect c = {.s = s, .d = out};
    sinew_result result = collect_channels(&c, g);
    if (!result)
        result = add_channels(&c, g);
    free(c.channels);
    if (!result)
        result = skin_method(s, skin, out);
    if (!result)
        result = read_cache(s, g, out);
    return result;
}

void fbx_deform_free(fbx_deform *d)
{
    free(d->shapes);
    free(d->dq);
    free(d->frame_times);
    free(d->frames);
    memset(d, 0, sizeof *d);
}

/* ---- one mesh's deformers --------------------------------------------------------------- */

/* m's 3x3 part times v. */
static void direction(const dmat *m, const double v[3], float out[3])
{
    for (int r = 0; r < 3; r++)
        out[r] = (float)(m->m[r] * v[0] + m->m[4 + r] * v[1] + m->m[8 + r] * v[2]);
}

/* The target of one shape on a mesh: an offset for each vertex whose control point the shape
 * moves. `map` (point_count entries of -1) is left as it was found. */
static sinew_result shape_target(scene *s, const fbx_deform *d, const fbx_shape_source *sh, const uint32_t *points,
                                 uint32_t vertex_count, const dmat *place, const dmat *normal_place, int32_t *map,
                                 raw_morph_target *t)
{
    const char *name = sh->name;
    size_t name_len = sh->name_len;
    uint32_t ni = 0, nv = 0, nn = 0;
    const double *idx = fbx_array(sh->node, "Indexes", &ni);
    const double *off = fbx_array(sh->node, "Vertices", &nv);
    const double *nrm = fbx_array(sh->node, "Normals", &nn);
    if ((uint64_t)ni * 3 != nv)
        return sinew_fail(s->error, SINEW_ERROR_DATA,
                          "%s: blend shape \"%.*s\" has %u offsets for %u vertex indices (it should have one a vertex)",
                          s->path, (int)name_len, name, nv / 3, ni);
    for (uint32_t k = 0; k < ni; k++) {
        if (!(idx[k] >= 0 && idx[k] < d->point_count))
            return sinew_fail(s->error, SINEW_ERROR_DATA,
                              "%s: blend shape \"%.*s\" moves vertex %.0f of a mesh of %u vertices", s->path,
                              (int)name_len, name, idx[k], d->point_count);
        for (int c = 0; c < 3; c++)
            if (!isfinite(off[k * 3 + c]))
                return sinew_fail(s->error, SINEW_ERROR_DATA,
                                  "%s: blend shape \"%.*s\" has an offset that is not finite", s->path, (int)name_len,
                                  name);
    }
    bool normals = nrm && nn == nv;
    for (uint32_t k = 0; k < ni; k++)
        map[(uint32_t)idx[k]] = (int32_t)k;
    uint32_t n = 0;
    for (uint32_t v = 0; v < vertex_count; v++)
        n += map[points[v]] >= 0;
    memset(t, 0, sizeof *t);
    t->name = malloc(name_len + 1);
    t->vertices = malloc((n ? n : 1) * sizeof *t->vertices);
    t->positions = malloc((n ? n : 1) * 3 * sizeof *t->positions);
    t->normals = normals ? malloc((n ? n : 1) * 3 * sizeof *t->normals) : NULL;
    sinew_result result = SINEW_OK;
    if (!t->name || !t->vertices || !t->positions || (normals && !t->normals)) {
        result = fbx_oom(s);
    } else {
        memcpy(t->name, name, name_len);
        t->name[name_len] = 0;
        t->channel = sh->channel;
        t->full_weight = sh->vertex_scale ? 1.0f : (float)(sh->full_weight / 100.0);
        if (t->full_weight == 0.0f)
            t->full_weight = 1e-6f; /* a shape whole at 0 percent: the in-between rule needs it apart from 0 */
        for (uint32_t v = 0; v < vertex_count; v++) {
            int32_t k = map[points[v]];
            if (k < 0)
                continue;
            double scale = sh->vertex_scale ? sh->vertex_scale[k] / 100.0 : 1.0;
            double o[3] = {off[k * 3] * scale, off[k * 3 + 1] * scale, off[k * 3 + 2] * scale};
            t->vertices[t->delta_count] = v;
            direction(place, o, &t->positions[t->delta_count * 3]);
            if (normals) {
                double q[3] = {nrm[k * 3] * scale, nrm[k * 3 + 1] * scale, nrm[k * 3 + 2] * scale};
                direction(normal_place, q, &t->normals[t->delta_count * 3]);
            }
            t->delta_count++;
        }
    }
    for (uint32_t k = 0; k < ni; k++)
        map[(uint32_t)idx[k]] = -1;
    return result;
}

/* The transpose of the inverse of m's 3x3 part (normals' offsets go through it). */
static dmat normal_matrix(const dmat *m)
{
    dmat inv = dmat_inverse_affine(m), out = dmat_identity();
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            out.m[c * 4 + r] = inv.m[r * 4 + c];
    return out;
}

static sinew_result emit_targets(scene *s, const fbx_deform *d, const uint32_t *points, const dmat *place,
                                 raw_mesh *mesh)
{
    if (d->shape_count == 0)
        return SINEW_OK;
    int32_t *map = malloc((d->point_count ? d->point_count : 1) * sizeof *map);
    mesh->targets = calloc(d->shape_count, sizeof *mesh->targets);
    if (!map || !mesh->targets) {
        free(map);
        return fbx_oom(s);
    }
    for (uint32_t p = 0; p < d->point_count; p++)
        map[p] = -1;
    dmat normal_place = normal_matrix(place);
    sinew_result result = SINEW_OK;
    for (uint32_t i = 0; i < d->shape_count && !result; i++) {
        result = shape_target(s, d, &d->shapes[i], points, mesh->vertex_count, place, &normal_place, map,
                              &mesh->targets[mesh->target_count]);
        mesh->target_count++; /* counted even when it failed: raw_mesh_free frees what it holds */
    }
    free(map);
    return result;
}

static sinew_result emit_cache(scene *s, const fbx_deform *d, const uint32_t *points, const dmat *place, raw_mesh *mesh)
{
    raw_vertex_cache *cache = calloc(1, sizeof *cache);
    if (!cache)
        return fbx_oom(s);
    mesh->cache = cache;
    size_t values = (size_t)mesh->vertex_count * 3;
    cache->times = malloc(d->frame_count * sizeof *cache->times);
    cache->positions = malloc((values ? values : 1) * d->frame_count * sizeof *cache->positions);
    if (!cache->times || !cache->positions)
        return fbx_oom(s);
    cache->frame_count = d->frame_count;
    memcpy(cache->times, d->frame_times, d->frame_count * sizeof *cache->times);
    for (uint32_t f = 0; f < d->frame_count; f++) {
        const float *frame = d->frames + (size_t)f * d->point_count * 3;
        float *out = cache->positions + f * values;
        for (uint32_t v = 0; v < mesh->vertex_count; v++) {
            const float *p = &frame[(size_t)points[v] * 3];
            double q[3] = {p[0], p[1], p[2]};
            for (int r = 0; r < 3; r++)
                out[v * 3 + r] =
                    (float)(place->m[r] * q[0] + place->m[4 + r] * q[1] + place->m[8 + r] * q[2] + place->m[12 + r]);
        }
    }
    return SINEW_OK;
}

sinew_result fbx_deform_emit(scene *s, const fbx_deform *d, const uint32_t *points, const dmat *place, raw_mesh *mesh)
{
    sinew_result result = emit_targets(s, d, points, place, mesh);
    if (!result && d->dq && mesh->skin >= 0) {
        mesh->dq_weights = malloc((mesh->vertex_count ? mesh->vertex_count : 1) * sizeof *mesh->dq_weights);
        if (!mesh->dq_weights)
            return fbx_oom(s);
        for (uint32_t v = 0; v < mesh->vertex_count; v++)
            mesh->dq_weights[v] = d->dq[points[v]];
    }
    if (!result && d->frame_count)
        result = emit_cache(s, d, points, place, mesh);
    return result;
}

/* ---- weight tracks ---------------------------------------------------------------------- */

typedef struct weight_curve {
    const scene *s;
    uint32_t object;
    int32_t stack;
    double start, rest; /* clip start on the file's timeline; the channel's percent without animation */
} weight_curve;

static double weight_at(const weight_curve *w, double t)
{
    return fbx_animated_value(w->s, w->object, P_DEFORM_PERCENT, w->stack, w->start + t, w->start, w->rest) / 100.0;
}

typedef struct key_list {
    float *times, *values;
    uint32_t count, capacity;
} key_list;

static bool push_key(key_list *k, double t, double v)
{
    if (k->count == k->capacity) {
        uint32_t cap = k->capacity ? k->capacity * 2 : 16;
        float *times = realloc(k->times, cap * sizeof *times);
        if (times)
            k->times = times;
        float *values = realloc(k->values, cap * sizeof *values);
        if (values)
            k->values = values;
        if (!times || !values)
            return false;
        k->capacity = cap;
    }
    k->times[k->count] = (float)t;
    k->values[k->count++] = (float)v;
    return true;
}

/* Keys between a and b (exclusive of a, inclusive of b) so that linear interpolation stays
 * within WEIGHT_TOLERANCE of the curve: a span is halved while the curve strays at a quarter,
 * the half or three quarters of it (the half alone misses an ease in and out, which passes
 * through it), at most 2^12 pieces a span. */
static bool bake_span(const weight_curve *w, double a, double va, double b, double vb, int depth, key_list *k)
{
    double mid = 0.5 * (a + b), vm = weight_at(w, mid);
    bool strays = fabs(vm - 0.5 * (va + vb)) > WEIGHT_TOLERANCE;
    for (int q = 1; q <= 3 && !strays; q += 2)
        strays = fabs(weight_at(w, a + 0.25 * q * (b - a)) - (va + 0.25 * q * (vb - va))) > WEIGHT_TOLERANCE;
    if (depth < 12 && b - a > 1e-6 && strays)
        return bake_span(w, a, va, mid, vm, depth + 1, k) && bake_span(w, mid, vm, b, vb, depth + 1, k);
    return push_key(k, b, vb);
}

static bool object_animated(const scene *s, uint32_t o, uint32_t stack)
{
    const fbx_object *obj = &s->objects[o];
    for (uint32_t b = obj->first_binding; b < obj->first_binding + obj->binding_count; b++)
        if (s->bindings[b].stack == stack && s->bindings[b].prop == P_DEFORM_PERCENT)
            return true;
    return false;
}

static sinew_result weight_track(scene *s, uint32_t channel, uint32_t stack, double start, raw_clip *clip)
{
    uint32_t o = (uint32_t)s->channel_object[channel];
    weight_curve w = {s, o, (int32_t)stack, start, s->model->morph_channels[channel].default_weight * 100.0};
    float *times = NULL;
    uint32_t n = 0;
    if (fbx_object_key_times(s, o, (int32_t)stack, start, clip->duration, &times, &n))
        return fbx_oom(s);
    key_list k = {0};
    bool ok = n > 0 && push_key(&k, times[0], weight_at(&w, times[0]));
    for (uint32_t i = 1; ok && i < n; i++)
        ok = bake_span(&w, times[i - 1], k.values[k.count - 1], times[i], weight_at(&w, times[i]), 0, &k);
    free(times);
    raw_weight_track *tracks =
        ok ? realloc(clip->weight_tracks, (clip->weight_track_count + 1) * sizeof *tracks) : NULL;
    if (!tracks) {
        free(k.times);
        free(k.values);
        return fbx_oom(s);
    }
    clip->weight_tracks = tracks;
    tracks[clip->weight_track_count++] = (raw_weight_track){
        channel, {.interp = SINEW_INTERP_LINEAR, .count = k.count, .times = k.times, .values = k.values}};
    return SINEW_OK;
}

sinew_result fbx_weight_tracks(scene *s, uint32_t stack, double start, raw_clip *clip)
{
    for (uint32_t c = 0; c < s->model->morph_channel_count; c++) {
        if (s->channel_object[c] < 0 || !object_animated(s, (uint32_t)s->channel_object[c], stack))
            continue;
        sinew_result result = weight_track(s, c, stack, start, clip);
        if (result)
            return result;
    }
    return SINEW_OK;
}
