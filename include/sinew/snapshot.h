/* sinew/snapshot.h — pictures of a clip in one call, without a window.
 *
 * What: sinew_render_snapshots() makes an off-screen context (sinew/headless.h), a renderer
 * (sinew/render.h) for the model, poses the clip at each time (sinew_clip_arrays()), and reads
 * each frame back as 8-bit RGBA. The camera, unless given, is framed as `sinew render` frames
 * a clip: from 30 degrees right and 15 above the model's front, fitting the posed model over
 * all the times; the grid lies under the lowest point. For previews, contact sheets and the
 * Python binding's sinew.render().
 * What not: no video or image files (the caller encodes the pixels).
 * Memory: the context, renderer and pose arrays are made and freed inside the call; the
 * caller owns `rgba`.
 * Errors: SINEW_ERROR_GRAPHICS (no EGL display or GL 3.3 context), SINEW_ERROR_INVALID_ARGUMENT
 * (a bad size, no output), SINEW_ERROR_LIMIT (over 64 Mpixels in all), SINEW_ERROR_OUT_OF_MEMORY,
 * and what the renderer or sinew_clip_arrays() report.
 * Threads: makes its context current on the calling thread and releases nothing else of it.
 */
#ifndef SINEW_SNAPSHOT_H
#define SINEW_SNAPSHOT_H

#include "sinew/arrays.h"
#include "sinew/camera.h"
#include "sinew/render.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sinew_snapshot_desc {
    const sinew_model *model;
    const sinew_clip *clip; /* NULL: the rest pose */
    const float *times;     /* time_count seconds (wrapped or clamped by `wrap`); NULL with a count of 0:
                               one picture at time 0 */
    uint32_t time_count;
    sinew_wrap wrap;
    int width, height;                   /* pixels; 0: 320 x 240 */
    int samples;                         /* multisampling: 0 = 4, 1 = none */
    const sinew_render_options *options; /* NULL: sinew_render_options_default(), the grid under the model */
    const sinew_camera *camera;          /* NULL: framed as above */
    uint8_t *rgba;                       /* out: max(time_count, 1) pictures of width * height * 4 bytes,
                                            top row first */
    size_t rgba_size;                    /* bytes at rgba */
} sinew_snapshot_desc;

sinew_result sinew_render_snapshots(const sinew_snapshot_desc *desc, sinew_error *error);

#ifdef __cplusplus
}
#endif
#endif
