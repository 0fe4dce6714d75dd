/* Morph targets, vertex caches and one instance posed whole (sinew/morph.h).
 *
 *   weights ........ sinew_sample_weights, sinew_morph_target_weights (in-between shapes)
 *   morphing ....... check_morph, add_target_scalar / add_target_avx2, finish_directions
 *   caches ......... sinew_cache_vertices, sinew_smooth_normals
 *   deform ......... sinew_deform_scratch_size, sinew_deform_instance
 *
 * The reference is the scalar code: out = base, then out += w * offset target by target in
 * the mesh's order, each target's deltas in vertex order. The AVX2+FMA path adds eight
 * consecutive vertices of a target (24 floats) with three fused multiply-adds where the
 * target's vertex numbers run consecutively, and the reference's loop elsewhere; the order
 * of additions is the same, so the two differ by FMA's single rounding only. */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "sinew/morph.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

/* ---- weights ---- */

sinew_result sinew_sample_weights(const sinew_model *model, const sinew_clip *clip, float time, sinew_wrap wrap,
                                  float *weights, uint32_t weight_count, sinew_error *error)
{
    if (!model || (model->morph_channel_count && !weights))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_sample_weights: NULL model or output");
    if (weight_count < model->morph_channel_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_sample_weights: room for %u weights, the model has %u channels", weight_count,
                          model->morph_channel_count);
    for (uint32_t c = 0; c < model->morph_channel_count; c++)
        weights[c] = model->morph_channels[c].default_weight;
    if (!clip)
        return SINEW_OK;
    float t = sinew_clip_time(clip, time, wrap);
    for (uint32_t i = 0; i < clip->weight_track_count; i++) {
        const sinew_weight_track *track = &clip->weight_tracks[i];
        if (track->channel >= model->morph_channel_count)
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "sinew_sample_weights: clip \"%s\" animates channel %u of %u", clip->name, track->channel,
                              model->morph_channel_count);
        if (track->keys.key_count)
            sinew_channel_eval(clip, &track->keys, SINEW_CHANNEL_WEIGHT, t, NULL, &weights[track->channel]);
    }
    return SINEW_OK;
}

float sinew_clip_weight(const sinew_model *model, const sinew_clip *clip, uint32_t channel, float time, sinew_wrap wrap)
{
    if (!model || channel >= model->morph_channel_count)
        return 0.0f;
    float w = model->morph_channels[channel].default_weight;
    if (!clip)
        return w;
    uint32_t lo = 0, hi = clip->weight_track_count; /* tracks are sorted by channel */
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (clip->weight_tracks[mid].channel < channel)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo < clip->weight_track_count && clip->weight_tracks[lo].channel == channel &&
        clip->weight_tracks[lo].keys.key_count)
        sinew_channel_eval(clip, &clip->weight_tracks[lo].keys, SINEW_CHANNEL_WEIGHT, sinew_clip_time(clip, time, wrap),
                           NULL, &w);
    return w;
}

sinew_result sinew_player_weights(const sinew_player *player, float time, sinew_wrap wrap, float *weights,
                                  uint32_t weight_count, sinew_error *error)
{
    if (!player)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_player_weights: NULL player");
    const sinew_clip_layout *layout = sinew_player_layout(player);
    return sinew_sample_weights(sinew_layout_model(layout), sinew_layout_clip(layout), time, wrap, weights,
                                weight_count, error);
}

/* The targets [begin, end) of one channel (sorted by full weight) at channel weight w: the
 * base shape is a target of full weight 0 that moves nothing; w falls between two neighbours
 * (or beyond the last two on its side), which share it linearly. */
static void inbetween_weights(const sinew_morph_target *targets, uint32_t begin, uint32_t end, float w, float *out)
{
    for (uint32_t i = begin; i < end; i++)
        out[i] = 0.0f;
    /* keys: -1 is the base shape */
    int64_t last_negative = -1;
    for (uint32_t i = begin; i < end; i++)
        if (targets[i].full_weight < 0.0f)
            last_negative = i;
    int64_t prev = -1, next = -1;
    if (w > 0.0f) {
        if (last_negative >= 0)
            prev = last_negative;
        for (int64_t i = last_negative >= 0 ? last_negative + 1 : begin; i < end; i++) {
            prev = next;
            next = i;
            if (targets[i].full_weight > w)
                break;
        }
    } else {
        int64_t first_positive = last_negative >= 0 ? last_negative + 1 : begin;
        if (first_positive < end)
            prev = first_positive;
        for (int64_t i = last_negative; i >= (int64_t)begin; i--) {
            prev = next;
            next = i;
            if (targets[i].full_weight < w)
                break;
        }
    }
    float wp = prev >= 0 ? targets[prev].full_weight : 0.0f, wn = next >= 0 ? targets[next].full_weight : 0.0f;
    float span = wn - wp;
    if (span == 0.0f)
        return;
    float t = (w - wp) / span;
    if (prev >= 0)
        out[prev] = 1.0f - t;
    if (next >= 0)
        out[next] = t;
}

sinew_result sinew_morph_target_weights(const sinew_mesh *mesh, const float *channel_weights, uint32_t channel_count,
                                        float *target_weights, uint32_t target_count, sinew_error *error)
{
    if (!mesh || (mesh->target_count && (!channel_weights || !target_weights)))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_morph_target_weights: NULL argument");
    if (channel_count < mesh->morph_channel_count || target_count < mesh->target_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_morph_target_weights: mesh \"%s\" has %u channels and %u targets, given %u and %u",
                          mesh->name, mesh->morph_channel_count, mesh->target_count, channel_count, target_count);
    const sinew_morph_target *targets = mesh->targets;
    for (uint32_t i = 0; i < mesh->target_count;) {
        uint32_t end = i + 1;
        while (end < mesh->target_count && targets[end].channel == targets[i].channel)
            end++;
        float w = channel_weights[targets[i].channel];
        if (end == i + 1 && targets[i].full_weight == 1.0f)
            target_weights[i] = w; /* the common case, exactly */
        else
            inbetween_weights(targets, i, end, w, target_weights);
        i = end;
    }
    return SINEW_OK;
}

/* ---- morphing ---- */

typedef struct morph_call {
    const sinew_mesh *mesh;
    const float *weights;
    uint32_t first, end;
    float *out_p, *out_n, *out_t;
} morph_call;

static sinew_result check_morph(const sinew_morph_desc *desc, morph_call *call, sinew_error *error)
{
    if (!desc || !desc->mesh || !desc->out_positions)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_morph_vertices: NULL mesh or output");
    const sinew_mesh *mesh = desc->mesh;
    if (desc->out_tangents && !mesh->tangents && mesh->vertex_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_morph_vertices: mesh \"%s\" has no tangents",
                          mesh->name);
    if (desc->out_normals && !mesh->normals && mesh->vertex_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_morph_vertices: mesh \"%s\" has no normals",
                          mesh->name);
    if (desc->first > mesh->vertex_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_morph_vertices: first vertex %u past the %u vertices", desc->first,
                          mesh->vertex_count);
    uint32_t count = desc->count ? desc->count : mesh->vertex_count - desc->first;
    if (count > mesh->vertex_count - desc->first)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_morph_vertices: range %u+%u past the %u vertices",
                          desc->first, count, mesh->vertex_count);
    *call = (morph_call){mesh,
                         desc->target_weights,
                         desc->first,
                         desc->first + count,
                         desc->out_positions,
                         desc->out_normals,
                         desc->out_tangents};
    return SINEW_OK;
}

/* The first of a target's deltas at or past vertex v. */
static uint32_t first_delta(const sinew_morph_target *t, uint32_t v)
{
    uint32_t lo = 0, hi = t->delta_count;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (t->vertices[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* out[v] += w * offsets[k] (3 floats) for the deltas [k, end) (`stride` floats a vertex out). */
static void add_deltas_scalar(const uint32_t *vertices, const float *offsets, uint32_t k, uint32_t end, float w,
                              float *out, uint32_t stride)
{
    for (; k < end; k++) {
        float *o = &out[(size_t)vertices[k] * stride];
        const float *d = &offsets[(size_t)k * 3];
        o[0] += w * d[0], o[1] += w * d[1], o[2] += w * d[2];
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
/* The same for positions and normals (stride 3), eight consecutive vertices at a time. */
__attribute__((target("avx2,fma"))) static void add_deltas_avx2(const uint32_t *vertices, const float *offsets,
                                                                uint32_t k, uint32_t end, float w, float *out)
{
    const __m256 wv = _mm256_set1_ps(w);
    while (k < end) {
        if (k + 8 <= end && vertices[k + 7] - vertices[k] == 7) {
            /* ascending and distinct, so eight apart by 7 are consecutive */
            float *o = &out[(size_t)vertices[k] * 3];
            const float *d = &offsets[(size_t)k * 3];
            _mm256_storeu_ps(o, _mm256_fmadd_ps(wv, _mm256_loadu_ps(d), _mm256_loadu_ps(o)));
            _mm256_storeu_ps(o + 8, _mm256_fmadd_ps(wv, _mm256_loadu_ps(d + 8), _mm256_loadu_ps(o + 8)));
            _mm256_storeu_ps(o + 16, _mm256_fmadd_ps(wv, _mm256_loadu_ps(d + 16), _mm256_loadu_ps(o + 16)));
            k += 8;
            continue;
        }
        /* a gap: one vertex the reference's way (fused, as above) */
        float *o = &out[(size_t)vertices[k] * 3];
        const float *d = &offsets[(size_t)k * 3];
        o[0] = fmaf(w, d[0], o[0]), o[1] = fmaf(w, d[1], o[1]), o[2] = fmaf(w, d[2], o[2]);
        k++;
    }
}

static bool have_avx2(void)
{
    return sinew_cpu_has(SINEW_CPU_AVX2_FMA);
}
#endif

static void normalize_at(float *v)
{
    float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > 0.0f) {
        float inv = 1.0f / len;
        v[0] *= inv, v[1] *= inv, v[2] *= inv;
    }
}

static void morph_range(const morph_call *c, bool simd)
{
    const sinew_mesh *mesh = c->mesh;
    size_t n = c->end - c->first;
    memcpy(c->out_p + (size_t)c->first * 3, mesh->positions + (size_t)c->first * 3, n * 3 * sizeof(float));
    if (c->out_n)
        memcpy(c->out_n + (size_t)c->first * 3, mesh->normals + (size_t)c->first * 3, n * 3 * sizeof(float));
    if (c->out_t)
        memcpy(c->out_t + (size_t)c->first * 4, mesh->tangents + (size_t)c->first * 4, n * 4 * sizeof(float));
    if (!c->weights || n == 0)
        return;
    bool turned_n = false, turned_t = false;
#if defined(__x86_64__) && defined(__GNUC__)
    simd = simd && have_avx2();
#else
    simd = false;
#endif
    for (uint32_t i = 0; i < mesh->target_count; i++) {
        const sinew_morph_target *t = &mesh->targets[i];
        float w = c->weights[i];
        if (w == 0.0f || t->delta_count == 0)
            continue;
        uint32_t k = first_delta(t, c->first), end = k;
        while (end < t->delta_count && t->vertices[end] < c->end)
            end++;
        if (k == end)
            continue;
#if defined(__x86_64__) && defined(__GNUC__)
        if (simd) {
            add_deltas_avx2(t->vertices, t->positions, k, end, w, c->out_p);
            if (c->out_n && t->normals)
                add_deltas_avx2(t->vertices, t->normals, k, end, w, c->out_n);
        } else
#endif
        {
            add_deltas_scalar(t->vertices, t->positions, k, end, w, c->out_p, 3);
            if (c->out_n && t->normals)
                add_deltas_scalar(t->vertices, t->normals, k, end, w, c->out_n, 3);
        }
        if (c->out_t && t->tangents)
            add_deltas_scalar(t->vertices, t->tangents, k, end, w, c->out_t, 4);
        turned_n = turned_n || (c->out_n && t->normals);
        turned_t = turned_t || (c->out_t && t->tangents);
    }
    for (size_t v = c->first; turned_n && v < c->end; v++)
        normalize_at(&c->out_n[v * 3]);
    for (size_t v = c->first; turned_t && v < c->end; v++)
        normalize_at(&c->out_t[v * 4]);
}

sinew_result sinew_morph_vertices(const sinew_morph_desc *desc, sinew_error *error)
{
    morph_call call;
    sinew_result result = check_morph(desc, &call, error);
    if (result == SINEW_OK)
        morph_range(&call, true);
    return result;
}

sinew_result sinew_morph_vertices_scalar(const sinew_morph_desc *desc, sinew_error *error)
{
    morph_call call;
    sinew_result result = check_morph(desc, &call, error);
    if (result == SINEW_OK)
        morph_range(&call, false);
    return result;
}

/* ---- caches ---- */

sinew_result sinew_cache_vertices(const sinew_mesh *mesh, float time, float *out_positions, sinew_error *error)
{
    if (!mesh || !out_positions)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_cache_vertices: NULL mesh or output");
    const sinew_vertex_cache *cache = mesh->cache;
    if (!cache || cache->frame_count == 0)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_cache_vertices: mesh \"%s\" has no vertex cache",
                          mesh->name);
    size_t values = (size_t)mesh->vertex_count * 3;
    uint32_t n = cache->frame_count;
    if (n == 1 || !(time > cache->times[0])) {
        memcpy(out_positions, cache->positions, values * sizeof(float));
        return SINEW_OK;
    }
    if (time >= cache->times[n - 1]) {
        memcpy(out_positions, cache->positions + (n - 1) * values, values * sizeof(float));
        return SINEW_OK;
    }
    uint32_t cursor = 0;
    uint32_t k = sinew_find_segment(cache->times, n, time, &cursor);
    float dt = cache->times[k + 1] - cache->times[k];
    float s = dt > 0.0f ? (time - cache->times[k]) / dt : 0.0f;
    const float *a = cache->positions + k * values, *b = a + values;
    for (size_t i = 0; i < values; i++)
        out_positions[i] = a[i] + (b[i] - a[i]) * s;
    return SINEW_OK;
}

sinew_result sinew_smooth_normals(const sinew_mesh *mesh, const float *positions, float *out_normals, size_t stride,
                                  sinew_error *error)
{
    if (!mesh || !positions || !out_normals)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_smooth_normals: NULL argument");
    size_t s = stride ? stride : 3 * sizeof(float);
    if (s < 3 * sizeof(float))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_smooth_normals: stride %zu below 12 bytes", s);
#define AT(base, v) ((float *)((char *)(base) + (size_t)(v)*s))
#define AT_CONST(base, v) ((const float *)((const char *)(base) + (size_t)(v)*s))
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        memset(AT(out_normals, v), 0, 3 * sizeof(float));
    for (uint32_t i = 0; i + 2 < mesh->index_count; i += 3) {
        uint32_t a = mesh->indices[i], b = mesh->indices[i + 1], c = mesh->indices[i + 2];
        if (a >= mesh->vertex_count || b >= mesh->vertex_count || c >= mesh->vertex_count)
            continue;
        const float *pa = AT_CONST(positions, a), *pb = AT_CONST(positions, b), *pc = AT_CONST(positions, c);
        float e1[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
        float e2[3] = {pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]};
        float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        uint32_t corners[3] = {a, b, c};
        for (int k = 0; k < 3; k++) {
            float *o = AT(out_normals, corners[k]);
            o[0] += n[0], o[1] += n[1], o[2] += n[2];
        }
    }
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        normalize_at(AT(out_normals, v));
#undef AT
#undef AT_CONST
    return SINEW_OK;
}

/* ---- one instance posed whole ---- */

/* Scratch of one mesh: its skin's palettes, its target weights, its morphed positions and
 * normals (16-byte aligned parts). */
static size_t align16(size_t n)
{
    return (n + 15) & ~(size_t)15;
}

static size_t mesh_scratch(const sinew_model *model, const sinew_mesh *mesh)
{
    size_t joints =
        mesh->skin >= 0 && (uint32_t)mesh->skin < model->skin_count ? model->skins[mesh->skin].joint_count : 0;
    return align16(joints * sizeof(sinew_mat4)) + align16(joints * sizeof(sinew_dq_joint)) +
           align16((size_t)mesh->target_count * sizeof(float)) +
           align16((size_t)mesh->morph_channel_count * sizeof(float)) + 2 * align16((size_t)mesh->vertex_count * 12);
}

size_t sinew_deform_scratch_size(const sinew_model *model)
{
    size_t largest = 16;
    for (uint32_t i = 0; model && i < model->mesh_count; i++) {
        size_t s = mesh_scratch(model, &model->meshes[i]);
        largest = s > largest ? s : largest;
    }
    return largest;
}

/* Places mesh-space positions (3 floats a vertex) and normals with one matrix. */
static void place(const sinew_mat4 *m, const float *p, const float *n, uint32_t count, float *out_p, float *out_n,
                  size_t stride)
{
    const float *a = m->m;
    /* normals through the cofactor of the 3x3 part, as sinew_transform_vertices() */
    float k[9] = {a[5] * a[10] - a[6] * a[9], a[6] * a[8] - a[4] * a[10], a[4] * a[9] - a[5] * a[8],
                  a[9] * a[2] - a[10] * a[1], a[10] * a[0] - a[8] * a[2], a[8] * a[1] - a[9] * a[0],
                  a[1] * a[6] - a[2] * a[5],  a[2] * a[4] - a[0] * a[6],  a[0] * a[5] - a[1] * a[4]};
    float det = a[0] * k[0] + a[1] * k[1] + a[2] * k[2];
    float sign = det < 0.0f ? -1.0f : 1.0f;
    for (uint32_t v = 0; v < count; v++) {
        const float *q = &p[(size_t)v * 3];
        float *o = (float *)((char *)out_p + (size_t)v * stride);
        for (int r = 0; r < 3; r++)
            o[r] = a[r] * q[0] + a[4 + r] * q[1] + a[8 + r] * q[2] + a[12 + r];
        if (!out_n || !n)
            continue;
        const float *d = &n[(size_t)v * 3];
        float *on = (float *)((char *)out_n + (size_t)v * stride);
        for (int r = 0; r < 3; r++)
            on[r] = sign * (k[r * 3] * d[0] + k[r * 3 + 1] * d[1] + k[r * 3 + 2] * d[2]);
        normalize_at(on);
    }
}

sinew_result sinew_deform_instance(const sinew_deform_desc *desc, sinew_error *error)
{
    if (!desc || !desc->model || !desc->worlds || !desc->out_positions)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_deform_instance: NULL model, worlds or output");
    const sinew_model *model = desc->model;
    if (desc->instance >= model->instance_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_deform_instance: instance %u of %u",
                          desc->instance, model->instance_count);
    if (desc->world_count < model->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_deform_instance: %u world matrices for %u nodes",
                          desc->world_count, model->node_count);
    const sinew_instance *in = &model->instances[desc->instance];
    const sinew_mesh *mesh = &model->meshes[in->mesh];
    if (desc->weights && desc->weight_count < model->morph_channel_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_deform_instance: %u weights for %u morph channels", desc->weight_count,
                          model->morph_channel_count);
    size_t need = mesh_scratch(model, mesh);
    if (!desc->scratch || desc->scratch_size < need || ((uintptr_t)desc->scratch & 15))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_deform_instance: scratch of %zu bytes (16-byte aligned) needed, %zu given", need,
                          desc->scratch ? desc->scratch_size : 0);
    size_t stride = desc->out_stride ? desc->out_stride : 12;
    if (stride < 12)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_deform_instance: stride %zu below 12 bytes",
                          stride);
    const sinew_skin *skin =
        mesh->skin >= 0 && (uint32_t)mesh->skin < model->skin_count ? &model->skins[mesh->skin] : NULL;
    uint32_t joints = skin ? skin->joint_count : 0;
    char *at = desc->scratch;
    sinew_mat4 *palette = (sinew_mat4 *)at;
    at += align16(joints * sizeof(sinew_mat4));
    sinew_dq_joint *dq = (sinew_dq_joint *)at;
    at += align16(joints * sizeof(sinew_dq_joint));
    float *target_weights = (float *)at;
    at += align16((size_t)mesh->target_count * sizeof(float));
    float *defaults = (float *)at;
    at += align16((size_t)mesh->morph_channel_count * sizeof(float));
    float *positions = (float *)at;
    at += align16((size_t)mesh->vertex_count * 12);
    float *normals = (float *)at;
    const sinew_mat4 *node_world = &desc->worlds[in->node];
    sinew_result r;

    if (mesh->cache && !desc->no_cache) {
        if ((r = sinew_cache_vertices(mesh, desc->cache_time, positions, error)) != SINEW_OK)
            return r;
        if ((r = sinew_smooth_normals(mesh, positions, normals, 0, error)) != SINEW_OK)
            return r;
        place(node_world, positions, normals, mesh->vertex_count, desc->out_positions, desc->out_normals, stride);
        return SINEW_OK;
    }

    const float *p = mesh->positions, *n = mesh->normals;
    if (mesh->target_count) {
        /* the mesh's channels: the model's from morph_first, or their defaults */
        const float *channel_weights = desc->weights ? desc->weights + in->morph_first : NULL;
        if (!channel_weights) {
            for (uint32_t c = 0; c < mesh->morph_channel_count; c++)
                defaults[c] = model->morph_channels[in->morph_first + c].default_weight;
            channel_weights = defaults;
        }
        if ((r = sinew_morph_target_weights(mesh, channel_weights, mesh->morph_channel_count, target_weights,
                                            mesh->target_count, error)) != SINEW_OK)
            return r;
        bool any = false;
        for (uint32_t t = 0; t < mesh->target_count; t++)
            any = any || target_weights[t] != 0.0f;
        if (any) {
            if ((r = sinew_morph_vertices(&(sinew_morph_desc){.mesh = mesh,
                                                              .target_weights = target_weights,
                                                              .out_positions = positions,
                                                              .out_normals = mesh->normals ? normals : NULL},
                                          error)) != SINEW_OK)
                return r;
            p = positions;
            n = mesh->normals ? normals : NULL;
        }
    }

    if (!skin || mesh->influence_count == 0) {
        place(node_world, p, n, mesh->vertex_count, desc->out_positions, desc->out_normals, stride);
        return SINEW_OK;
    }
    if ((r = sinew_skin_palette(skin, desc->worlds, desc->world_count, palette, joints, error)) != SINEW_OK)
        return r;
    sinew_skin_method method = desc->force_method                                ? desc->method
                               : skin->blend == SINEW_SKIN_BLEND_DUAL_QUATERNION ? SINEW_SKIN_DUAL_QUATERNION
                               : skin->blend == SINEW_SKIN_BLEND_MIXED           ? SINEW_SKIN_MIXED
                                                                                 : SINEW_SKIN_LINEAR;
    if (method != SINEW_SKIN_LINEAR && (r = sinew_skin_dq_palette(palette, joints, dq, error)) != SINEW_OK)
        return r;
    return sinew_skin_vertices(&(sinew_skin_desc){.mesh = mesh,
                                                  .palette = palette,
                                                  .palette_count = joints,
                                                  .method = method,
                                                  .dq_palette = dq,
                                                  .positions = p,
                                                  .normals = n,
                                                  .out_positions = desc->out_positions,
                                                  .out_normals = desc->out_normals && n ? desc->out_normals : NULL,
                                                  .out_stride = stride},
                               error);
}
