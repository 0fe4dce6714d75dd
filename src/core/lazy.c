/* A library loaded on first use (internal.h: sinew_lazy_load), and pages filled in ahead
 * (sinew_prefault): what a process start and its first large buffers cost. */
#include <dlfcn.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/mman.h>

#include "internal.h"

static pthread_mutex_t lazy_lock = PTHREAD_MUTEX_INITIALIZER;

bool sinew_lazy_load(sinew_lazy_library *library, char *why, size_t why_size)
{
    pthread_mutex_lock(&lazy_lock);
    if (!library->tried) {
        library->tried = true;
        void *handle = dlopen(library->soname, RTLD_NOW | RTLD_LOCAL);
        if (!handle)
            snprintf(library->failure, sizeof library->failure, "cannot load %s: %s", library->soname, dlerror());
        for (size_t i = 0; handle && i < library->count; i++)
            if (!(library->symbols[i] = dlsym(handle, library->names[i]))) {
                snprintf(library->failure, sizeof library->failure, "%s lacks %s", library->soname, library->names[i]);
                dlclose(handle);
                handle = NULL;
            }
        library->loaded = handle != NULL; /* kept loaded for the life of the process */
    }
    bool loaded = library->loaded;
    pthread_mutex_unlock(&lazy_lock);
    if (!loaded && why && why_size)
        snprintf(why, why_size, "%s", library->failure);
    return loaded;
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
