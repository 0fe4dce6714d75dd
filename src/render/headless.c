/* An off-screen OpenGL 3.3 core context through EGL: no window, no display server. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/internal.h"
#include "gl.h"

#include "sinew/headless.h"
#include "internal.h"

struct sinew_headless {
    EGLDisplay display;
    EGLContext context;
    int width, height, samples;
    GLuint fbo, color, depth;          /* what is drawn into (multisampled when samples > 1) */
    GLuint resolve_fbo, resolve_color; /* single-sample copy for reading, when samples > 1 */
    char description[320];
};

static bool has_extension(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return true;
    return false;
}

/* Initialises `display`; on failure terminates nothing and returns false. */
static bool try_display(EGLDisplay display, EGLDisplay *out)
{
    if (display == EGL_NO_DISPLAY)
        return false;
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor))
        return false;
    *out = display;
    return true;
}

static bool context_on(sinew_headless *h, EGLDisplay display)
{
    if (!eglBindAPI(EGL_OPENGL_API))
        return false;
    static const EGLint config_attributes[] = {EGL_SURFACE_TYPE, 0, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config;
    EGLint count = 0;
    if (!eglChooseConfig(display, config_attributes, &config, 1, &count) || count < 1)
        return false;
    static const EGLint context_attributes[] = {
        EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
    if (context == EGL_NO_CONTEXT)
        return false;
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
        eglDestroyContext(display, context);
        return false;
    }
    h->display = display;
    h->context = context;
    return true;
}

/* Display platforms in order: SINEW_EGL_PLATFORM (surfaceless, device or default) picks one. */
static bool open_context(sinew_headless *h, char *tried, size_t tried_size)
{
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const char *only = getenv("SINEW_EGL_PLATFORM");
    bool any = !only || !*only;
    size_t used = 0;
    tried[0] = '\0';
    EGLDisplay display;
    if ((any || !strcmp(only, "surfaceless")) && has_extension(client, "EGL_MESA_platform_surfaceless")) {
        used += (size_t)snprintf(tried + used, tried_size - used, "surfaceless");
        if (try_display(eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL), &display)) {
            if (context_on(h, display))
                return true;
        }
    }
    /* EGL_EXT_device_base is enumeration and query together: NVIDIA's driver lists only it. */
    if ((any || !strcmp(only, "device")) && has_extension(client, "EGL_EXT_platform_device") &&
        (has_extension(client, "EGL_EXT_device_enumeration") || has_extension(client, "EGL_EXT_device_base"))) {
        EGLDeviceEXT devices[16];
        EGLint count = 0;
        if (eglQueryDevicesEXT(16, devices, &count)) {
            for (EGLint i = 0; i < count; i++) {
                if (used < tried_size)
                    used += (size_t)snprintf(tried + used, tried_size - used, "%sdevice %d", used ? ", " : "", i);
                if (try_display(eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL), &display)) {
                    if (context_on(h, display))
                        return true;
                }
            }
        }
    }
    if (any || !strcmp(only, "default")) {
        if (used < tried_size)
            snprintf(tried + used, tried_size - used, "%sdefault display", used ? ", " : "");
        if (try_display(eglGetDisplay(EGL_DEFAULT_DISPLAY), &display)) {
            if (context_on(h, display))
                return true;
        }
    }
    return false;
}

/* libepoxy ends the process (abort) when it cannot open libEGL.so.1, or libOpenGL.so.0 or
 * libGL.so.1 for desktop GL's functions: they are looked for first, so that a machine without
 * them (a GPU driver without glvnd, a container with only the driver's own libraries) gets an
 * error. Each is loaded once and stays loaded, as libepoxy then loads them itself. */
static sinew_lazy_library libegl = {.soname = "libEGL.so.1"}, libopengl = {.soname = "libOpenGL.so.0"},
                          libgl = {.soname = "libGL.so.1"};

static bool egl_libraries(char *why, size_t size)
{
    if (!sinew_lazy_load(&libegl, why, size))
        return false;
    if (sinew_lazy_load(&libopengl, NULL, 0) || sinew_lazy_load(&libgl, NULL, 0))
        return true;
    snprintf(why, size, "cannot load libOpenGL.so.0 or libGL.so.1");
    return false;
}

static GLuint renderbuffer(int samples, GLenum format, int width, int height)
{
    GLuint rb = 0;
    glGenRenderbuffers(1, &rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    if (samples > 1)
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, width, height);
    else
        glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
    return rb;
}

static sinew_result make_framebuffers(sinew_headless *h, sinew_error *error)
{
    glGenFramebuffers(1, &h->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, h->fbo);
    h->color = renderbuffer(h->samples, GL_RGBA8, h->width, h->height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, h->color);
    h->depth = renderbuffer(h->samples, GL_DEPTH_COMPONENT24, h->width, h->height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, h->depth);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return sinew_fail(error, SINEW_ERROR_GRAPHICS, "the %dx%d framebuffer (%d samples) is incomplete (0x%04x)",
                          h->width, h->height, h->samples, status);
    if (h->samples > 1) {
        glGenFramebuffers(1, &h->resolve_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, h->resolve_fbo);
        h->resolve_color = renderbuffer(1, GL_RGBA8, h->width, h->height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, h->resolve_color);
        status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE)
            return sinew_fail(error, SINEW_ERROR_GRAPHICS, "the %dx%d resolve framebuffer is incomplete (0x%04x)",
                              h->width, h->height, status);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, h->fbo);
    return SINEW_OK;
}

sinew_result sinew_headless_create(const sinew_headless_desc *desc, sinew_headless **out, sinew_error *error)
{
    if (!desc || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_headless_create: no desc or no output");
    *out = NULL;
    if (desc->width < 1 || desc->height < 1 || desc->width > 16384 || desc->height > 16384)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "image size %dx%d is outside 1x1..16384x16384",
                          desc->width, desc->height);
    char why[256];
    if (!render_gl_load(why, sizeof why))
        return sinew_fail(error, SINEW_ERROR_GRAPHICS, "no OpenGL: %s", why);
    if (!egl_libraries(why, sizeof why))
        return sinew_fail(error, SINEW_ERROR_GRAPHICS,
                          "no OpenGL through EGL: %s (install libegl1 and libopengl0 with Mesa's EGL, "
                          "libegl-mesa0, or a GPU driver's)",
                          why);
    sinew_headless *h = calloc(1, sizeof *h);
    if (!h)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "out of memory");
    h->width = desc->width;
    h->height = desc->height;
    char tried[200];
    if (!open_context(h, tried, sizeof tried)) {
        free(h);
        return sinew_fail(error, SINEW_ERROR_GRAPHICS,
                          "no OpenGL 3.3 core context through EGL (tried: %s; EGL error 0x%04x); "
                          "install Mesa's EGL (libegl-mesa0, libgl1-mesa-dri) or a GPU driver",
                          tried[0] ? tried : "no EGL platform", (unsigned)eglGetError());
    }
    GLint max_samples = 1;
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    h->samples = desc->samples == 0 ? 4 : desc->samples;
    if (h->samples > max_samples)
        h->samples = max_samples;
    if (h->samples < 1)
        h->samples = 1;
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
    sinew_result result = SINEW_OK;
    if (desc->width > max_size || desc->height > max_size)
        result = sinew_fail(error, SINEW_ERROR_GRAPHICS, "image size %dx%d is over this GL's limit of %d", desc->width,
                            desc->height, max_size);
    else
        result = make_framebuffers(h, error);
    if (result != SINEW_OK) {
        sinew_headless_free(h);
        return result;
    }
    snprintf(h->description, sizeof h->description, "%s / %s", (const char *)glGetString(GL_RENDERER),
             (const char *)glGetString(GL_VERSION));
    glViewport(0, 0, h->width, h->height);
    *out = h;
    return SINEW_OK;
}

void sinew_headless_free(sinew_headless *h)
{
    if (!h)
        return;
    if (h->context != EGL_NO_CONTEXT && h->context) {
        eglMakeCurrent(h->display, EGL_NO_SURFACE, EGL_NO_SURFACE, h->context);
        glDeleteFramebuffers(1, &h->fbo);
        glDeleteFramebuffers(1, &h->resolve_fbo);
        glDeleteRenderbuffers(1, &h->color);
        glDeleteRenderbuffers(1, &h->depth);
        glDeleteRenderbuffers(1, &h->resolve_color);
        eglMakeCurrent(h->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(h->display, h->context);
        /* No eglTerminate: an EGL display is one per process and platform, shared with
         * anyone else in the process using it (a toolkit, a second renderer); terminating
         * it would pull it from under them. */
        eglReleaseThread();
    }
    free(h);
}

void sinew_headless_finish(sinew_headless *h)
{
    if (h)
        glFinish();
}

void sinew_headless_bind(sinew_headless *h)
{
    eglMakeCurrent(h->display, EGL_NO_SURFACE, EGL_NO_SURFACE, h->context);
    glBindFramebuffer(GL_FRAMEBUFFER, h->fbo);
    glViewport(0, 0, h->width, h->height);
}

sinew_result sinew_headless_read(sinew_headless *h, uint8_t *rgba, sinew_error *error)
{
    if (!h || !rgba)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_headless_read: no context or no buffer");
    GLuint source = h->fbo;
    if (h->samples > 1) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, h->fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, h->resolve_fbo);
        glBlitFramebuffer(0, 0, h->width, h->height, 0, 0, h->width, h->height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        source = h->resolve_fbo;
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, source);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, h->width, h->height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    glBindFramebuffer(GL_FRAMEBUFFER, h->fbo);
    GLenum gl_error = glGetError();
    if (gl_error != GL_NO_ERROR)
        return sinew_fail(error, SINEW_ERROR_GRAPHICS, "reading the frame back failed (OpenGL error 0x%04x)", gl_error);
    render_flip_rows(rgba, (size_t)h->width * 4, h->height);
    return SINEW_OK;
}

void render_flip_rows(unsigned char *pixels, size_t row_bytes, int rows)
{
    for (int y = 0; y < rows / 2; y++) {
        unsigned char *a = pixels + row_bytes * (size_t)y, *b = pixels + row_bytes * (size_t)(rows - 1 - y);
        for (size_t i = 0; i < row_bytes; i++) {
            unsigned char t = a[i];
            a[i] = b[i];
            b[i] = t;
        }
    }
}

const char *sinew_headless_description(const sinew_headless *h)
{
    return h ? h->description : "";
}
