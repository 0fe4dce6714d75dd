/* The import's allocation accounting (alloc.h): a byte limit of its own, the deadline, and the
 * failure sweep. */
#include <errno.h>
#ifdef SINEW_ALLOC_TRACE
#include <execinfo.h>
#endif
#include <malloc.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

#include "../core/internal.h" /* sinew_pages_alloc */
#include "internal.h"

typedef struct import_alloc {
    uint64_t limit; /* bytes the readers may hold; UINT64_MAX: none */
    uint64_t in_use, peak;
    uint64_t count;                               /* allocations so far */
    uint64_t fail_at;                             /* fail the allocation with this number (1 first); 0: none */
    double deadline;                              /* CLOCK_MONOTONIC seconds; 0: none */
    uint32_t polls;                               /* deadline checks since the clock was last read */
    bool (*progress)(float fraction, void *user); /* asked every PROGRESS_EVERY seconds; NULL: none */
    void *progress_user;
    double next_progress;
    bool over_limit, failed, late, cancelled;
} import_alloc;

static _Thread_local import_alloc *current;
static _Thread_local uint64_t sweep_fail_at; /* the tests' hook: the next import fails this allocation */
static _Thread_local uint64_t last_count;

static double monotonic_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

#define PROGRESS_EVERY 0.05

void import_alloc_begin(import_alloc_state *state, uint64_t limit, double seconds,
                        bool (*progress)(float fraction, void *user), void *progress_user)
{
    import_alloc *a = (import_alloc *)state->opaque;
    _Static_assert(sizeof(import_alloc) <= sizeof state->opaque, "room for the state");
    *a = (import_alloc){.limit = limit ? limit : UINT64_MAX,
                        .fail_at = sweep_fail_at,
                        .deadline = seconds > 0.0 ? monotonic_seconds() + seconds : 0.0,
                        .progress = progress,
                        .progress_user = progress_user};
    state->outer = current;
    current = a;
}

void import_alloc_end(import_alloc_state *state, import_alloc_result *result)
{
    import_alloc *a = (import_alloc *)state->opaque;
    if (result)
        *result = (import_alloc_result){.peak = a->peak,
                                        .count = a->count,
                                        .limit = a->limit,
                                        .over_limit = a->over_limit,
                                        .refused = a->failed,
                                        .late = a->late,
                                        .cancelled = a->cancelled};
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

/* Whether the import is past its deadline or was cancelled: the clock is read every 64th call
 * (a call costs a branch); the progress callback is asked at the first reading, then every
 * PROGRESS_EVERY seconds, and returning false cancels. Once stopped it stays stopped. */
static bool past_deadline(import_alloc *a)
{
    if (!a || (a->deadline == 0.0 && !a->progress))
        return false;
    if (!a->late && !a->cancelled && ++a->polls >= 64) {
        a->polls = 0;
        double now = monotonic_seconds();
        a->late = a->deadline != 0.0 && now > a->deadline;
        if (a->progress && now >= a->next_progress) {
            a->next_progress = now + PROGRESS_EVERY;
            a->cancelled = !a->progress(-1.0f, a->progress_user);
        }
    }
    return a->late || a->cancelled;
}

bool import_late(void)
{
    return past_deadline(current);
}

/* Whether the next allocation of `size` more bytes may go ahead: past the deadline none does, so
 * that a reader unwinds as from a failed allocation. */
static bool allowed(import_alloc *a, size_t size)
{
    if (!a)
        return true;
    a->count++;
    if (past_deadline(a)) {
        errno = ENOMEM;
        return false;
    }
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

/* `n` more (fewer) bytes held by the import. */
static void charge(import_alloc *a, size_t n)
{
    a->in_use += n;
    if (a->in_use > a->peak)
        a->peak = a->in_use;
}

static void discharge(import_alloc *a, size_t n)
{
    a->in_use = a->in_use > n ? a->in_use - n : 0;
}

static void took(import_alloc *a, void *p)
{
    if (a && !p)
        a->failed = true; /* the system's malloc said no */
    if (a && p)
        charge(a, malloc_usable_size(p));
}

static void gave(import_alloc *a, void *p)
{
    if (a && p)
        discharge(a, malloc_usable_size(p));
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

void *import_large_alloc(size_t size, size_t pages_from)
{
    size_t mapped = size >= pages_from ? sinew_pages_rounded(size) : 0; /* counted as the whole mapping */
    if (!allowed(current, mapped ? mapped : size))
        return NULL;
    void *p = sinew_large_alloc(size, mapped ? pages_from : SIZE_MAX);
    size_t pages = sinew_pages_length(p);
    if (!pages)
        took(current, p);
    else if (current)
        charge(current, pages);
    return p;
}

void *import_realloc(void *ptr, size_t size)
{
    size_t pages = sinew_pages_length(ptr);
    if (pages) { /* a block in 2 MB pages: into a malloc'd one */
        void *p = import_malloc(size ? size : 1);
        if (p) {
            memcpy(p, ptr, pages < size ? pages : size);
            import_free(ptr);
        }
        return p;
    }
    size_t old = ptr ? malloc_usable_size(ptr) : 0;
    if (!allowed(current, size > old ? size - old : 0))
        return NULL;
    void *p = realloc(ptr, size);
    if (!p && size && current)
        current->failed = true;
    if (p && current) {
        discharge(current, old);
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
    size_t pages = sinew_pages_length(ptr);
    if (pages) {
        if (current)
            discharge(current, pages);
        sinew_pages_free(ptr);
        return;
    }
    gave(current, ptr);
    free(ptr);
}

/* ---- the arena ------------------------------------------------------------------------------- */

typedef struct arena_chunk {
    struct arena_chunk *next;
    size_t size, used; /* bytes after the header */
    size_t filled;     /* a mapped chunk: bytes after the header whose pages are filled in */
    bool mapped;       /* mmap'd (256 KiB and more) */
    bool pages;        /* in 2 MB pages (sinew_pages_alloc: IMPORT_PAGES_MIN and more) */
} arena_chunk;
#define ARENA_HEADER ((sizeof(arena_chunk) + 15) & ~(size_t)15)
#define ARENA_FIRST ((size_t)64 << 10)
#define ARENA_LARGEST ((size_t)4 << 20)
#define ARENA_MAP ((size_t)256 << 10)
#define ARENA_FILL ((size_t)256 << 10) /* a mapped chunk's pages are filled in this many bytes at a time */

/* Fills in the pages of a mapped chunk up to `need` bytes after its header, a window at a time
 * (one madvise instead of a page fault a page; at most a window ahead of what is used: the
 * chunks double, and filling a whole 4 MB chunk of which a document used 0.7 MB zeroed 3.3 MB
 * for nothing, a tenth of walk.fbx's import). */
static void chunk_fill(arena_chunk *c, size_t need)
{
    if (!c->mapped || need <= c->filled)
        return;
    /* windows from the chunk's start, which is at a page boundary (a 2 MB page is filled whole:
     * windows counted from after the header ended a header's length into the next 2 MB page,
     * and the kernel filled and zeroed all of that page for its first 4 KiB) */
    size_t window = c->pages ? (size_t)2 << 20 : ARENA_FILL;
    size_t end = (ARENA_HEADER + need + window - 1) / window * window - ARENA_HEADER;
    end = end < c->size ? end : c->size;
    uintptr_t page = 4096, from = ((uintptr_t)c + ARENA_HEADER + c->filled) & ~(page - 1),
              to = ((uintptr_t)c + ARENA_HEADER + end + page - 1) & ~(page - 1);
#ifdef MADV_POPULATE_WRITE
    if (to > from)
        madvise((void *)from, to - from, MADV_POPULATE_WRITE); /* older kernels: EINVAL, pages fault in */
#else
    (void)from;
    (void)to;
#endif
    c->filled = end;
}

static arena_chunk *chunk_new(size_t size)
{
    size_t total = ARENA_HEADER + size, rounded = total >= IMPORT_PAGES_MIN ? sinew_pages_rounded(total) : 0;
    bool mapped = total >= ARENA_MAP, pages = rounded != 0;
    if (pages) /* the whole mapping is the chunk's (a 512 KiB chunk has 2 MB), and counted */
        total = rounded;
    if (!allowed(current, total))
        return NULL;
    arena_chunk *c = NULL;
    if (pages && (c = sinew_pages_alloc(total, 0))) {
        /* filled in as below, a window at a time: the first touch of each 2 MB fills it */
    } else if (mapped) {
        pages = false;
        void *p = mmap(NULL, total, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        c = p == MAP_FAILED ? NULL : p;
    } else {
        c = calloc(1, total);
    }
    if (!c) {
        if (current)
            current->failed = true;
        return NULL;
    }
    if (current)
        charge(current, total);
    *c = (arena_chunk){.size = total - ARENA_HEADER, .mapped = mapped, .pages = pages};
    return c;
}

void *import_arena_take(import_arena *arena, size_t bytes)
{
    if (bytes > SIZE_MAX / 2)
        return NULL;
    bytes = (bytes + 15) & ~(size_t)15;
    arena_chunk *head = arena->head;
    if (head && head->size - head->used >= bytes) {
        void *p = (unsigned char *)head + ARENA_HEADER + head->used;
        head->used += bytes;
        chunk_fill(head, head->used);
        return p;
    }
    /* chunks of 64 KiB, 128 KiB, ... with their headers: a chunk in 2 MB pages fills its pages */
    size_t grown = head ? (ARENA_HEADER + head->size) * 2 : arena->first > ARENA_FIRST ? arena->first : ARENA_FIRST;
    if (grown > ARENA_LARGEST)
        grown = ARENA_LARGEST;
    bool own = bytes >= grown / 4;
    arena_chunk *c = chunk_new(own ? bytes : grown - ARENA_HEADER);
    if (!c)
        return NULL;
    c->used = bytes;
    chunk_fill(c, bytes);
    if (own && head) { /* behind the current chunk, which keeps its room */
        c->next = head->next;
        head->next = c;
    } else {
        c->next = head;
        arena->head = c;
    }
    return (unsigned char *)c + ARENA_HEADER;
}

void import_arena_expect(import_arena *arena, size_t bytes)
{
    size_t first = ARENA_FIRST;
    while (first < bytes && first < ARENA_LARGEST)
        first *= 2;
    arena->first = first;
}

void import_arena_free(import_arena *arena)
{
    for (arena_chunk *c = arena->head, *next; c; c = next) {
        next = c->next;
        size_t total = ARENA_HEADER + c->size;
        if (current)
            discharge(current, total);
        if (c->pages)
            sinew_pages_free(c);
        else if (c->mapped)
            munmap(c, total);
        else
            free(c);
    }
    arena->head = NULL;
}
