/* A library loaded on first use (internal.h: sinew_lazy_open). */
#include <dlfcn.h>
#include <stdio.h>

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
