/* A library loaded on first use (internal.h: sinew_lazy_load), pages filled in ahead
 * (sinew_prefault), large blocks in 2 MB pages (sinew_pages_alloc) and files read without stdio
 * (sinew_read_fully): what a process start and its first large buffers cost. */
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#if defined(__x86_64__) && defined(__has_include)
#if __has_include(<sys/platform/x86.h>)
#include <sys/platform/x86.h>
#define SINEW_LIBC_CPU_FEATURES 1
#endif
#endif

#include "internal.h"

static pthread_mutex_t lazy_lock = PTHREAD_MUTEX_INITIALIZER;

bool sinew_lazy_load(sinew_lazy_library *library, char *why, size_t why_size)
{
    pthread_mutex_lock(&lazy_lock);
    if (!library->tried) {
        library->tried = true;
        /* Functions bound as they are first called, not all at once: libxml2 and the ICU and
         * libstdc++ it brings took 12% of robot_walk.dae's `sinew info` in the dynamic linker
         * (0.93 of the time lazily). The symbols sinew calls are looked up below all the same. */
        void *handle = dlopen(library->soname, RTLD_LAZY | RTLD_LOCAL);
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

/* A feature by glibc's name and by GCC's. */
#if defined(SINEW_LIBC_CPU_FEATURES)
#define CPU_HAS(libc, gcc) CPU_FEATURE_ACTIVE(libc)
#elif defined(__x86_64__) && defined(__GNUC__)
#define CPU_HAS(libc, gcc) __builtin_cpu_supports(gcc)
#endif

bool sinew_cpu_has(sinew_cpu_feature feature)
{
#ifdef CPU_HAS
    switch (feature) {
    case SINEW_CPU_SSE42:
        return CPU_HAS(SSE4_2, "sse4.2");
    case SINEW_CPU_AVX2:
        return CPU_HAS(AVX2, "avx2");
    case SINEW_CPU_AVX2_FMA:
        return CPU_HAS(AVX2, "avx2") && CPU_HAS(FMA, "fma");
    case SINEW_CPU_AVX512:
        return CPU_HAS(AVX512F, "avx512f") && CPU_HAS(AVX512DQ, "avx512dq");
    case SINEW_CPU_AVX512BW:
        return CPU_HAS(AVX512BW, "avx512bw");
    }
#endif
    (void)feature;
    return false;
}

size_t sinew_read_fully(int fd, void *buf, size_t size)
{
    size_t got = 0;
    while (got < size) {
        ssize_t r = read(fd, (char *)buf + got, size - got);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            break;
        got += (size_t)r;
    }
    return got;
}

int sinew_open_regular(const char *path, uint64_t *size)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0)
        return -1;
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        errno = EINVAL;
        return -1;
    }
    *size = (uint64_t)st.st_size;
    return fd;
}

void sinew_prefault(void *p, size_t size)
{
#ifdef MADV_POPULATE_WRITE
    const uintptr_t page = 4096;
    uintptr_t start = ((uintptr_t)p + page - 1) & ~(page - 1), end = ((uintptr_t)p + size) & ~(page - 1);
    if (size >= ((size_t)64 << 10) && end > start)
        madvise((void *)start, end - start, MADV_POPULATE_WRITE); /* older kernels: EINVAL, no harm */
#else
    (void)p;
    (void)size;
#endif
}

/* ---- large blocks in 2 MB pages ---------------------------------------------------------- */

#define HUGE_PAGE ((size_t)2 << 20)
#define PAGE_BLOCKS 64 /* live at once, in the process; past that, blocks are malloc'd */

static struct {
    void *start;
    size_t length;
} page_blocks[PAGE_BLOCKS];
static pthread_mutex_t page_lock = PTHREAD_MUTEX_INITIALIZER;

/* Blocks freed and kept for the next sinew_large_alloc() of the same length: an engine or a batch
 * importing file after file otherwise has the kernel map and zero the same 2 MB pages again for
 * each (a tenth of robot.glb's import from memory). Kept as MADV_FREE, so the kernel may take their
 * pages back when it needs memory (a reuse then faults in fresh ones); at most CACHED_BYTES. */
#define CACHED_BLOCKS 4
#define CACHED_BYTES ((size_t)32 << 20)
static struct {
    void *start;
    size_t length;
} cached[CACHED_BLOCKS];

size_t sinew_pages_rounded(size_t size)
{
    return size && size <= SIZE_MAX / 2 ? (size + HUGE_PAGE - 1) & ~(HUGE_PAGE - 1) : 0;
}

/* The slot of a block of sinew_pages_alloc() (of NULL: a free slot), or PAGE_BLOCKS; called with
 * page_lock held. */
static size_t page_slot(const void *p)
{
    size_t slot = 0;
    while (slot < PAGE_BLOCKS && page_blocks[slot].start != p)
        slot++;
    return slot;
}

/* The first `size` bytes of a block's pages filled in (one call instead of a fault a page). */
static void fill_in(void *start, size_t size)
{
#ifdef MADV_POPULATE_WRITE
    if (size)
        madvise(start, (size + 4095) & ~(size_t)4095, MADV_POPULATE_WRITE);
#else
    (void)start;
    (void)size;
#endif
}

void *sinew_pages_alloc(size_t size, size_t populate)
{
#if defined(MADV_HUGEPAGE)
    size_t length = sinew_pages_rounded(size);
    if (!length)
        return NULL;
    /* a mapping a huge page longer, trimmed to the 2 MB boundaries inside it */
    unsigned char *map = mmap(NULL, length + HUGE_PAGE, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (map == MAP_FAILED)
        return NULL;
    unsigned char *start = (unsigned char *)(((uintptr_t)map + HUGE_PAGE - 1) & ~(uintptr_t)(HUGE_PAGE - 1));
    if (start > map)
        munmap(map, (size_t)(start - map));
    if (map + HUGE_PAGE > start)
        munmap(start + length, (size_t)(map + HUGE_PAGE - start));
    pthread_mutex_lock(&page_lock);
    size_t slot = page_slot(NULL);
    if (slot < PAGE_BLOCKS)
        page_blocks[slot].start = start, page_blocks[slot].length = length;
    pthread_mutex_unlock(&page_lock);
    if (slot == PAGE_BLOCKS) {
        munmap(start, length);
        return NULL;
    }
    madvise(start, length, MADV_HUGEPAGE); /* where the kernel has no transparent huge pages: 4 KiB pages */
    fill_in(start, populate < size ? populate : size);
    return start;
#else
    (void)size;
    (void)populate;
    return NULL;
#endif
}

/* A kept block of exactly `length` bytes, live again, or NULL; its contents are whatever they are. */
static void *cached_take(size_t length)
{
    void *start = NULL;
    pthread_mutex_lock(&page_lock);
    size_t slot = page_slot(NULL);
    for (size_t i = 0; i < CACHED_BLOCKS && slot < PAGE_BLOCKS && !start; i++)
        if (cached[i].start && cached[i].length == length) {
            start = cached[i].start;
            cached[i].start = NULL;
            page_blocks[slot].start = start, page_blocks[slot].length = length;
        }
    pthread_mutex_unlock(&page_lock);
    return start;
}

/* Keeps a block no longer live for cached_take(), or says false. */
static bool cached_keep(void *start, size_t length)
{
#ifdef MADV_FREE
    pthread_mutex_lock(&page_lock);
    size_t kept = 0, free_slot = CACHED_BLOCKS;
    for (size_t i = 0; i < CACHED_BLOCKS; i++) {
        kept += cached[i].start ? cached[i].length : 0;
        if (!cached[i].start)
            free_slot = i;
    }
    bool keep = free_slot < CACHED_BLOCKS && length <= CACHED_BYTES - kept;
    if (keep) /* reserved: only this thread writes the slot, after the madvise */
        cached[free_slot].length = 0, cached[free_slot].start = start;
    pthread_mutex_unlock(&page_lock);
    if (!keep)
        return false;
    /* before it can be taken again: a later MADV_FREE would drop what a new owner wrote */
    bool lazy = madvise(start, length, MADV_FREE) == 0;
    pthread_mutex_lock(&page_lock);
    if (lazy)
        cached[free_slot].length = length;
    else
        cached[free_slot].start = NULL;
    pthread_mutex_unlock(&page_lock);
    return lazy;
#else
    (void)start;
    (void)length;
    return false;
#endif
}

size_t sinew_pages_length(const void *p)
{
    if (!p || ((uintptr_t)p & (HUGE_PAGE - 1))) /* not 2 MB aligned: not one (the common case, no lock) */
        return 0;
    pthread_mutex_lock(&page_lock);
    size_t slot = page_slot(p), length = slot < PAGE_BLOCKS ? page_blocks[slot].length : 0;
    pthread_mutex_unlock(&page_lock);
    return length;
}

bool sinew_pages_free(void *p)
{
    if (!p || ((uintptr_t)p & (HUGE_PAGE - 1)))
        return false;
    pthread_mutex_lock(&page_lock);
    size_t slot = page_slot(p), length = 0;
    if (slot < PAGE_BLOCKS) {
        length = page_blocks[slot].length;
        page_blocks[slot].start = NULL;
    }
    pthread_mutex_unlock(&page_lock);
    if (length && !cached_keep(p, length))
        munmap(p, length);
    return length != 0;
}

void *sinew_large_alloc(size_t size, size_t pages_from)
{
    void *p = NULL;
    if (size >= pages_from && (p = cached_take(sinew_pages_rounded(size))))
        fill_in(p, size); /* pages the kernel took back */
    else if (size >= pages_from)
        p = sinew_pages_alloc(size, size);
    if (!p && (p = malloc(size ? size : 1)))
        sinew_prefault(p, size);
    return p;
}

void sinew_block_free(void *p)
{
    if (!sinew_pages_free(p))
        free(p);
}
