/* The import's allocation accounting (alloc.h): a byte limit of its own and the failure sweep. */
#include <errno.h>
#ifdef SINEW_ALLOC_TRACE
#include <execinfo.h>
#endif
#include <malloc.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

typedef struct import_alloc {
    uint64_t limit; /* bytes the readers may hold; UINT64_MAX: none */
    uint64_t in_use, peak;
    uint64_t count;   /* allocations so far */
    uint64_t fail_at; /* fail the allocation with this number (1 first); 0: none */
    bool over_limit, failed;
} import_alloc;

static _Thread_local import_alloc *current;
static _Thread_local uint64_t sweep_fail_at; /* the tests' hook: the next import fails this allocation */
static _Thread_local uint64_t last_count;

void import_alloc_begin(import_alloc_state *state, uint64_t limit)
{
    import_alloc *a = (import_alloc *)state->opaque;
    _Static_assert(sizeof(import_alloc) <= sizeof state->opaque, "room for the state");
    *a = (import_alloc){.limit = limit ? limit : UINT64_MAX, .fail_at = sweep_fail_at};
    state->outer = current;
    current = a;
}

void import_alloc_end(import_alloc_state *state, import_alloc_result *result)
{
    import_alloc *a = (import_alloc *)state->opaque;
    if (result)
        *result = (import_alloc_result){
            .peak = a->peak, .count = a->count, .limit = a->limit, .over_limit = a->over_limit, .refused = a->failed};
    last_count = a->count;
    current = state->outer;
}

void import_alloc_sweep(uint64_t fail_at)
{
    sweep_fail_at = fail_at;
}

uint64_t import_alloc_last_count(void)
{
    return last_count;
}

/* Whether the next allocation of `size` more bytes may go ahead. */
static bool allowed(import_alloc *a, size_t size)
{
    if (!a)
        return true;
    a->count++;
    if (a->fail_at && a->count == a->fail_at) {
        a->failed = true;
#ifdef SINEW_ALLOC_TRACE
        void *frames[16];
        backtrace_symbols_fd(frames, backtrace(frames, 16), 2);
#endif
        errno = ENOMEM;
        return false;
    }
    if (a->limit != UINT64_MAX && (size > a->limit || a->in_use > a->limit - size)) {
        a->over_limit = true;
        errno = ENOMEM;
        return false;
    }
    return true;
}

static void took(import_alloc *a, void *p)
{
    if (a && !p)
        a->failed = true; /* the system's malloc said no */
    if (!a || !p)
        return;
    a->in_use += malloc_usable_size(p);
    if (a->in_use > a->peak)
        a->peak = a->in_use;
}

static void gave(import_alloc *a, void *p)
{
    if (!a || !p)
        return;
    size_t n = malloc_usable_size(p);
    a->in_use = a->in_use > n ? a->in_use - n : 0;
}

void *import_malloc(size_t size)
{
    if (!allowed(current, size))
        return NULL;
    void *p = malloc(size);
    took(current, p);
    return p;
}

void *import_calloc(size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size)
        return NULL;
    if (!allowed(current, count * size))
        return NULL;
    void *p = calloc(count, size);
    took(current, p);
    return p;
}

void *import_realloc(void *ptr, size_t size)
{
    size_t old = ptr ? malloc_usable_size(ptr) : 0;
    if (!allowed(current, size > old ? size - old : 0))
        return NULL;
    void *p = realloc(ptr, size);
    if (!p && size && current)
        current->failed = true;
    if (p && current) {
        current->in_use = current->in_use > old ? current->in_use - old : 0;
        took(current, p);
    }
    return p;
}

char *import_strdup(const char *text)
{
    return raw_strdup(text); /* builder.c's: its malloc is import_malloc there */
}

void import_free(void *ptr)
{
    gave(current, ptr);
    free(ptr);
}
