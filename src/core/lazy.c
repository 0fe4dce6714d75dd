/* A library loaded on first use (internal.h: sinew_lazy_open), and pages filled in ahead
 * (sinew_prefault): what a process start and its first large buffers cost. */
#include <dlfcn.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/mman.h>

#include "internal.h"

bool sinew_lazy_open(const char *soname, const char *const *names, void **functions, size_t count, char *why,
                     size_t why_size)
{
    void *library = dlopen(soname, RTLD_NOW | RTLD_LOCAL);
    if (!library) {
        snprintf(why, why_size, "cannot load %s: %s", soname, dlerror());
        return false;
    }
    for (size_t i = 0; i < count; i++)
        if (!(functions[i] = dlsym(library, names[i]))) {
            snprintf(why, why_size, "%s lacks %s", soname, names[i]);
            dlclose(library);
            return false;
        }
    return true; /* kept loaded for the life of the process */
}

void sinew_prefault(void *p, size_t size)
{
#ifdef MADV_POPULATE_WRITE
    const uintptr_t page = 4096;
    uintptr_t start = ((uintptr_t)p + page - 1) & ~(page - 1), end = ((uintptr_t)p + size) & ~(page - 1);
    if (size >= ((size_t)256 << 10) && end > start)
        madvise((void *)start, end - start, MADV_POPULATE_WRITE); /* older kernels: EINVAL, no harm */
#else
    (void)p;
    (void)size;
#endif
}
