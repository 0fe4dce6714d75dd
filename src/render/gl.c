/* Loading libepoxy on first use (gl.h). */
#include "../core/internal.h"
#include "gl.h"

#ifndef SINEW_EPOXY_SONAME
#error "the build names libepoxy's soname (CMakeLists.txt: SINEW_EPOXY_SONAME)"
#endif

static render_gl_api loaded;
const render_gl_api *const render_gl = &loaded;
#define RENDER_GL_NAME(name) #name,
static const char *const names[RENDER_GL_SYMBOLS] = {RENDER_GL_POINTERS(RENDER_GL_NAME)
                                                         RENDER_GL_FUNCTIONS(RENDER_GL_NAME)};
#undef RENDER_GL_NAME
static sinew_lazy_library epoxy = {
    .soname = SINEW_EPOXY_SONAME, .names = names, .symbols = loaded.symbol, .count = RENDER_GL_SYMBOLS};

bool render_gl_load(char *why, size_t size)
{
    return sinew_lazy_load(&epoxy, why, size);
}
