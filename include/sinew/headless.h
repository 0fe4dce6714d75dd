/* sinew/headless.h — an off-screen OpenGL 3.3 core context through EGL, no window.
 *
 * What: creates an EGL display without a window system (EGL_MESA_platform_surfaceless,
 * then EGL_EXT_platform_device, then the default display), a core-profile context made
 * current without a surface, and a framebuffer object of the requested size (multisampled
 * when asked and available, resolved into a single-sample buffer for reading). Works on
 * Mesa's llvmpipe without a GPU and on a vendor driver with one.
 * What not: no window, no swap, no vsync; one context per thread at a time.
 * Memory: the context and its framebuffers belong to the sinew_headless object.
 * Errors: SINEW_ERROR_GRAPHICS with what EGL or GL said when no display, config or 3.3
 * core context can be had, or the framebuffer is incomplete; SINEW_ERROR_INVALID_ARGUMENT
 * for a bad size.
 */
#ifndef SINEW_HEADLESS_H
#define SINEW_HEADLESS_H

#include <stdint.h>

#include "sinew/result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sinew_headless sinew_headless;

typedef struct sinew_headless_desc {
    int width, height; /* pixels, 1..16384 */
    int samples;       /* multisample count; 0 = 4; 1 = none; clamped to GL_MAX_SAMPLES */
} sinew_headless_desc;

/* Creates the context, makes it current on this thread and binds its framebuffer. */
sinew_result sinew_headless_create(const sinew_headless_desc *desc, sinew_headless **out, sinew_error *error);
void sinew_headless_free(sinew_headless *headless);

/* Makes the context current and binds the framebuffer to draw into (after other GL use). */
void sinew_headless_bind(sinew_headless *headless);

/* Resolves the frame and reads it as 8-bit RGBA, top row first, width*height*4 bytes. */
sinew_result sinew_headless_read(sinew_headless *headless, uint8_t *rgba, sinew_error *error);
/* Waits until everything drawn in the context is finished (glFinish): for timing frames. */
void sinew_headless_finish(sinew_headless *headless);

/* What EGL/GL report: "llvmpipe (LLVM 15.0.6, 256 bits) / 4.5 (Core Profile) Mesa 22.3.6". */
const char *sinew_headless_description(const sinew_headless *headless);

#ifdef __cplusplus
}
#endif
#endif
