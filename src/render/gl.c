/* Loading libepoxy on first use (gl.h). */
#include <pthread.h>
#include <stdio.h>

#include "../core/internal.h"
#include "gl.h"

#ifndef SINEW_EPOXY_SONAME
#error "the build names libepoxy's soname (CMakeLists.txt: SINEW_EPOXY_SONAME)"
#endif

const render_gl_api *render_gl;

static render_gl_api loaded;
static char failure[256];
static pthread_once_t once = PTHREAD_ONCE_INIT;

static void load(void)
{
#define RENDER_GL_NAME(name) #name,
    static const char *const names[RENDER_GL_SYMBOLS] = {RENDER_GL_POINTERS(RENDER_GL_NAME)
                                                             RENDER_GL_FUNCTIONS(RENDER_GL_NAME)};
#undef RENDER_GL_NAME
    if (sinew_lazy_open(SINEW_EPOXY_SONAME, names, loaded.symbol, RENDER_GL_SYMBOLS, failure, sizeof failure))
        render_gl = &loaded;
}

bool render_gl_load(char *why, size_t size)
{
    pthread_once(&once, load);
    if (!render_gl && why && size)
        snprintf(why, size, "%s", failure);
    return render_gl != NULL;
}
