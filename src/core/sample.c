/* Sampling a clip into local transforms.
 *
 * Each channel (translation, rotation, scale of one node) has its own key times. A key
 * cursor per channel remembers the last segment so that forward playback steps ahead
 * instead of searching; a jump backwards falls back to a binary search.
 * Step holds the earlier key; linear lerps vectors and slerps rotations the short way;
 * cubic is the Hermite spline of glTF with tangents scaled by the segment length; Bezier
 * solves each component's time polynomial for its parameter (2-D control points).
 */
#include <math.h>
#include <string.h>

#include <cglm/cglm.h>

#include "internal.h"
#include "sinew/anim.h"

struct sinew_sample_context {
    const sinew_clip *clip;
    uint32_t cursor_count;
    uint32_t cursors[]; /* SINEW_CHANNEL_COUNT per track */
};

size_t sinew_sample_context_size(const sinew_clip *clip)
{
    uint32_t tracks = clip ? clip->track_count : 0;
    return sizeof(sinew_sample_context) + (size_t)tracks * SINEW_CHANNEL_COUNT * sizeof(uint32_t);
}

sinew_result sinew_sample_context_init(void *memory, size_t size, const sinew_clip *clip, sinew_sample_context **out,
                                       sinew_error *error)
{
    if (!memory || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_sample_context_init: NULL argument");
    if (size < sinew_sample_context_size(clip))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_sample_context_init: %zu bytes given, the clip needs %zu", size,
                          sinew_sample_context_size(clip));
    sinew_sample_context *context = memory;
    context->clip = clip;
    context->cursor_count = clip ? clip->track_count * SINEW_CHANNEL_COUNT : 0;
    memset(context->cursors, 0, context->cursor_count * sizeof(uint32_t));
    *out = context;
    return SINEW_OK;
}

float sinew_clip_time(const sinew_clip *clip, float time, sinew_wrap wrap)
{
    float duration = clip ? clip->duration : 0.0f;
    if (!(duration > 0.0f) || !isfinite(time))
        return 0.0f;
    if (wrap == SINEW_WRAP_LOOP) {
        float t = fmodf(time, duration);
        if (t < 0.0f)
            t += duration;
        /* fmodf of exactly the duration gives 0: looping playback shows the first pose. */
        return t;
    }
    return time < 0.0f ? 0.0f : (time > duration ? duration : time);
}

uint32_t sinew_find_segment(const float *times, uint32_t count, float t, uint32_t *cursor)
{
    uint32_t k = *cursor;
    if (k >= count - 1 || times[k] > t) {
        /* Backwards jump (or a fresh cursor): binary search for the last key <= t. */
        uint32_t lo = 0, hi = count - 1;
        while (hi - lo > 1) {
            uint32_t mid = lo + (hi - lo) / 2;
            if (times[mid] <= t)
                lo = mid;
            else
                hi = mid;
        }
        k = lo;
    } else {
        while (k + 1 < count - 1 && times[k + 1] <= t)
            k++;
    }
    *cursor = k;
    return k;
}

static void hermite(const float *v0, const float *out_tangent0, const float *in_tangent1, const float *v1, float dt,
                    float s, uint32_t width, float *out)
{
    float s2 = s * s, s3 = s2 * s;
    float h00 = 2.0f * s3 - 3.0f * s2 + 1.0f;
    float h10 = s3 - 2.0f * s2 + s;
    float h01 = -2.0f * s3 + 3.0f * s2;
    float h11 = s3 - s2;
    for (uint32_t i = 0; i < width; i++)
        out[i] = h00 * v0[i] + h10 * dt * out_tangent0[i] + h01 * v1[i] + h11 * dt * in_tangent1[i];
}

float sinew_bezier(float t0, float v0, float t1, float v1, float t2, float v2, float t3, float v3, float t)
{
    float span = t3 - t0;
    if (!(span > 0.0f))
        return v0;
    float x1 = (t1 - t0) / span, x2 = (t2 - t0) / span, x = (t - t0) / span;
    float lo = 0.0f, hi = 1.0f, s = x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x);
    for (int i = 0; i < 32; i++) {
        float u = 1.0f - s;
        float err = 3.0f * u * u * s * x1 + 3.0f * u * s * s * x2 + s * s * s - x;
        if (fabsf(err) < 1e-7f)
            break;
        if (err > 0.0f)
            hi = s;
        else
            lo = s;
        float slope = 3.0f * u * u * x1 + 6.0f * u * s * (x2 - x1) + 3.0f * s * s * (1.0f - x2);
        float next = slope > 1e-6f ? s - err / slope : -1.0f;
        s = next > lo && next < hi ? next : 0.5f * (lo + hi);
    }
    float u = 1.0f - s;
    /* relative to v0, so that a level segment stays exactly level */
    return v0 + 3.0f * u * u * s * (v1 - v0) + 3.0f * u * s * s * (v2 - v0) + s * s * s * (v3 - v0);
}

bool sinew_bezier_times_ok(const float *times, const float *values, uint32_t count, uint32_t width)
{
    for (uint32_t k = 0; k < count; k++) {
        const float *key = values + (size_t)k * 5 * width;
        for (uint32_t i = 0; i < width; i++) {
            float in = key[width + i], out = key[3 * width + i];
            if ((k > 0 && !(in >= times[k - 1] && in <= times[k])) ||
                (k + 1 < count && !(out >= times[k] && out <= times[k + 1])))
                return false;
        }
    }
    return true;
}

/* Shortest-path spherical interpolation of unit quaternions. Keys less than about 3 degrees
 * apart are lerped and normalised (the same to float precision); not through cglm's
 * glm_quat_slerp, which returns the first key outright when their dot product rounds to 1,
 * so that a slow turn (keys 0.03 degrees apart) would step instead of turning. */
void sinew_slerp_shortest(const float *a, const float *b, float s, float *out)
{
    versor from, to;
    glm_vec4_copy((float *)a, from);
    glm_vec4_copy((float *)b, to);
    float cosine = glm_vec4_dot(from, to);
    if (cosine < 0.0f) {
        glm_vec4_negate(to);
        cosine = -cosine;
    }
    if (cosine > 0.9997f) {
        glm_vec4_lerp(from, to, s, out);
    } else {
        float angle = acosf(cosine), inv = 1.0f / sinf(angle);
        float wa = sinf((1.0f - s) * angle) * inv, wb = sinf(s * angle) * inv;
        for (int i = 0; i < 4; i++)
            out[i] = wa * from[i] + wb * to[i];
    }
    glm_quat_normalize(out);
}

void sinew_channel_eval(const sinew_clip *clip, const sinew_channel *channel, int kind, float time, uint32_t *cursor,
                        float *out)
{
    sinew_channel_eval_keys(clip, channel, kind, clip->start + time, cursor, out);
}

void sinew_channel_eval_keys(const sinew_clip *clip, const sinew_channel *channel, int kind, float time,
                             uint32_t *cursor, float *out)
{
    const uint32_t width = sinew_channel_width(kind);
    const uint32_t stride = sinew_channel_stride(kind, channel->interp);
    const uint32_t value_at = channel->interp == SINEW_INTERP_CUBIC ? width : 0; /* skip the in-tangent */
    const float *times = clip->times + channel->first_key;
    const float *values = clip->values + channel->first_value;
    const uint32_t n = channel->key_count;

    if (n == 1 || time <= times[0]) {
        memcpy(out, values + value_at, width * sizeof(float));
        return;
    }
    if (time >= times[n - 1]) {
        memcpy(out, values + (size_t)(n - 1) * stride + value_at, width * sizeof(float));
        return;
    }
    uint32_t local_cursor = 0;
    uint32_t k = sinew_find_segment(times, n, time, cursor ? cursor : &local_cursor);
    const float *a = values + (size_t)k * stride;
    const float *b = a + stride;
    float dt = times[k + 1] - times[k];
    float s = dt > 0.0f ? (time - times[k]) / dt : 0.0f;

    switch (channel->interp) {
    case SINEW_INTERP_STEP:
        memcpy(out, a, width * sizeof(float));
        return;
    case SINEW_INTERP_CUBIC:
        /* key layout: in-tangent a[0..w), value a[w..2w), out-tangent a[2w..3w) */
        hermite(a + width, a + 2 * width, b, b + width, dt, s, width, out);
        if (kind == SINEW_CHANNEL_ROTATION)
            glm_quat_normalize(out);
        return;
    case SINEW_INTERP_BEZIER:
        /* key layout: value [0, w), in time [w, 2w), in value [2w, 3w), out time, out value */
        for (uint32_t i = 0; i < width; i++)
            out[i] = sinew_bezier(times[k], a[i], a[3 * width + i], a[4 * width + i], b[width + i], b[2 * width + i],
                                  times[k + 1], b[i], time);
        if (kind == SINEW_CHANNEL_ROTATION)
            glm_quat_normalize(out);
        return;
    default:
        if (kind == SINEW_CHANNEL_ROTATION) {
            sinew_slerp_shortest(a, b, s, out);
        } else {
            for (uint32_t i = 0; i < width; i++)
                out[i] = a[i] + (b[i] - a[i]) * s;
        }
        return;
    }
}

sinew_result sinew_sample(const sinew_sample_desc *desc, sinew_error *error)
{
    if (!desc || !desc->model || !desc->locals)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_sample: NULL model or output");
    const sinew_model *model = desc->model;
    const sinew_clip *clip = desc->clip;
    if (desc->local_count < model->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_sample: %u local transforms given, the model has %u nodes", desc->local_count,
                          model->node_count);
    if (desc->context && desc->context->clip != clip)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_sample: the context was made for another clip");
    if (!isfinite(desc->time))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_sample: time is not finite");

    if (model->node_count)
        memcpy(desc->locals, model->node_rest, (size_t)model->node_count * sizeof(sinew_transform));
    if (!clip)
        return SINEW_OK;
    float t = clip->start + sinew_clip_time(clip, desc->time, desc->wrap);
    for (uint32_t i = 0; i < clip->track_count; i++) {
        const sinew_track *track = &clip->tracks[i];
        sinew_transform *local = &desc->locals[track->node];
        float *targets[SINEW_CHANNEL_COUNT] = {local->translation, local->rotation, local->scale};
        for (int kind = 0; kind < SINEW_CHANNEL_COUNT; kind++) {
            if (track->channels[kind].key_count == 0)
                continue;
            uint32_t *cursor = desc->context ? &desc->context->cursors[i * SINEW_CHANNEL_COUNT + kind] : NULL;
            sinew_channel_eval_keys(clip, &track->channels[kind], kind, t, cursor, targets[kind]);
        }
    }
    return SINEW_OK;
}
