/* Pictures of a clip in one call (sinew/snapshot.h): headless context, renderer, the clip's
 * arrays, a camera fitted to every frame, and each frame read back. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sinew/headless.h"
#include "sinew/snapshot.h"

#define SNAPSHOT_MAX_PIXELS (64u * 1024u * 1024u)

typedef struct snapshot {
    sinew_headless *headless;
    sinew_renderer *renderer;
    float *worlds;  /* frames * node_count * 16 */
    float *weights; /* frames * channel_count */
} snapshot;

static void snapshot_free(snapshot *s)
{
    sinew_renderer_free(s->renderer);
    sinew_headless_free(s->headless);
    free(s->worlds);
    free(s->weights);
}

static sinew_frame frame_at(const sinew_snapshot_desc *d, const snapshot *s, uint32_t f, float time,
                            const sinew_camera *camera, const sinew_render_options *options)
{
    const sinew_model *m = d->model;
    const sinew_clip *clip = d->clip;
    return (sinew_frame){.worlds = (const sinew_mat4 *)(s->worlds + (size_t)f * m->node_count * 16),
                         .world_count = m->node_count,
                         .camera = camera,
                         .width = d->width ? d->width : 320,
                         .height = d->height ? d->height : 240,
                         .options = options,
                         .weights = m->morph_channel_count ? s->weights + (size_t)f * m->morph_channel_count : NULL,
                         .weight_count = m->morph_channel_count,
                         .cache_time = clip ? clip->timeline + sinew_clip_time(clip, time, d->wrap) : 0.0f};
}

sinew_result sinew_render_snapshots(const sinew_snapshot_desc *d, sinew_error *error)
{
    if (!d || !d->model)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_render_snapshots: no model");
    const sinew_model *m = d->model;
    int width = d->width ? d->width : 320, height = d->height ? d->height : 240;
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_render_snapshots: size %dx%d (1 to 16384 a side)",
                          width, height);
    const float zero = 0.0f;
    const float *times = d->time_count ? d->times : &zero;
    uint32_t frames = d->time_count ? d->time_count : 1;
    if (!times)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_render_snapshots: %u times but no array",
                          d->time_count);
    uint64_t pixels = (uint64_t)width * (uint64_t)height * frames;
    if (pixels > SNAPSHOT_MAX_PIXELS)
        return sinew_fail(error, SINEW_ERROR_LIMIT,
                          "sinew_render_snapshots: %u pictures of %dx%d are over the limit of %u Mpixels", frames,
                          width, height, SNAPSHOT_MAX_PIXELS >> 20);
    if (!d->rgba || d->rgba_size < pixels * 4)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_render_snapshots: the output holds %zu bytes, %llu needed", d->rgba ? d->rgba_size : 0,
                          (unsigned long long)(pixels * 4));

    snapshot s = {0};
    size_t nodes = m->node_count ? m->node_count : 1, channels = m->morph_channel_count;
    s.worlds = malloc(frames * nodes * 16 * sizeof(float));
    s.weights = channels ? malloc(frames * channels * sizeof(float)) : NULL;
    sinew_result r = SINEW_OK;
    if (!s.worlds || (channels && !s.weights))
        r = sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for %u poses", m->source, frames);
    if (r == SINEW_OK)
        r = sinew_clip_arrays(&(sinew_clip_arrays_desc){.model = m,
                                                        .clip = d->clip,
                                                        .times = times,
                                                        .time_count = frames,
                                                        .wrap = d->wrap,
                                                        .worlds = s.worlds,
                                                        .weights = s.weights},
                              error);
    if (r == SINEW_OK)
        r = sinew_headless_create(&(sinew_headless_desc){.width = width, .height = height, .samples = d->samples},
                                  &s.headless, error);
    if (r == SINEW_OK)
        r = sinew_renderer_create(&(sinew_renderer_desc){.model = m, .muscles = m->muscles}, &s.renderer, error);
    if (r != SINEW_OK) {
        snapshot_free(&s);
        return r;
    }

    sinew_render_options options = d->options ? *d->options : sinew_render_options_default();
    sinew_camera camera;
    if (d->camera) {
        camera = *d->camera;
    } else {
        float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        sinew_render_options plain = sinew_render_options_default();
        for (uint32_t f = 0; f < frames; f++) {
            float a[3], b[3];
            sinew_frame frame = frame_at(d, &s, f, times[f], NULL, &plain);
            if (!sinew_renderer_frame_bounds(s.renderer, &frame, a, b))
                continue;
            for (int k = 0; k < 3; k++)
                lo[k] = fminf(lo[k], a[k]), hi[k] = fmaxf(hi[k], b[k]);
        }
        if (!(lo[0] <= hi[0]))
            for (int k = 0; k < 3; k++)
                lo[k] = -1.0f, hi[k] = 1.0f;
        if (!d->options) {
            options.grid_height = lo[1];
            options.skeleton = sinew_model_vertex_total(m) == 0; /* a skeleton-only file (BVH) shows its bones */
        }
        camera = sinew_camera_default();
        camera.yaw = 30.0f * (float)M_PI / 180.0f;
        camera.pitch = 15.0f * (float)M_PI / 180.0f;
        sinew_camera_frame(&camera, lo, hi, (float)width / (float)height);
    }
    for (uint32_t f = 0; r == SINEW_OK && f < frames; f++) {
        sinew_frame frame = frame_at(d, &s, f, times[f], &camera, &options);
        sinew_headless_bind(s.headless);
        r = sinew_renderer_draw(s.renderer, &frame, error);
        if (r == SINEW_OK)
            r = sinew_headless_read(s.headless, d->rgba + (size_t)f * width * height * 4, error);
    }
    snapshot_free(&s);
    return r;
}
