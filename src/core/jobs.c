/* The job system (sinew/jobs.h): workers that take chunks from one atomic counter.
 *
 * A run is published as a generation: `ticket` holds the generation in its high 32 bits
 * and the next chunk in its low 32, and a thread takes a chunk by compare-and-swap on it,
 * so a late worker (one that wakes after its generation is over) can never take a chunk of
 * the next. The run's function, data and sizes are written before the ticket is released
 * and are not changed until every chunk of the generation is done, so whoever took a chunk
 * reads them safely. Workers spin (with the pause instruction) for spin_us after their last
 * chunk, then sleep on a condition variable; the caller wakes them only when some sleep.
 * The caller takes chunks too and, when none are left, waits for the ones in flight:
 * spinning first, then yielding its processor (on a busy machine the worker it waits for
 * may be queued behind it).
 *
 * A worker the machine preempts while it holds a chunk makes the caller wait for it, up to
 * a scheduler time slice: on a machine busy with other work that can cost more than the
 * worker brings. So the caller watches each run: when it waited for stragglers longer than
 * half of its own working time (and over 20 microseconds) twice in a row, one worker fewer
 * takes chunks ("active" threads); every 64 runs one more is tried again. On a quiet
 * machine all threads stay active; on a busy one the run degrades towards the caller alone,
 * which is what one thread would do. */
#define _GNU_SOURCE
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "internal.h"
#include "sinew/jobs.h"

#define MAX_THREADS 256u

struct sinew_jobs {
    sinew_allocator allocator;
    uint32_t threads;
    uint64_t spin_ns;
    _Atomic uint64_t ticket; /* generation << 32 | next chunk */
    _Atomic uint32_t done;   /* chunks finished in this generation */
    _Atomic uint32_t sleepers;
    _Atomic bool quit;
    /* the run of the current generation: written before the ticket, read after it */
    _Atomic(sinew_job_fn) fn;
    _Atomic(void *) user;
    _Atomic uint32_t total, grain, chunks;
    _Atomic uint32_t active; /* threads that may take chunks in this run, the caller included */
    uint32_t strikes, calm;  /* the caller's: slow runs in a row, runs since the last change */
    pthread_mutex_t lock;
    pthread_cond_t wake;
    uint32_t generation; /* the caller's */
    uint32_t started;    /* workers running */
    pthread_t workers[];
};

typedef struct worker_arg {
    sinew_jobs *jobs;
    uint32_t index;
} worker_arg;

static inline void cpu_relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#elif defined(__aarch64__)
    __asm__ __volatile__("yield");
#endif
}

static uint64_t now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (uint64_t)t.tv_sec * 1000000000u + (uint64_t)t.tv_nsec;
}

/* Takes and runs chunks of generation `gen` until there are none left. */
static void take_chunks(sinew_jobs *j, uint32_t gen, uint32_t thread)
{
    uint64_t t = atomic_load_explicit(&j->ticket, memory_order_acquire);
    for (;;) {
        if ((uint32_t)(t >> 32) != gen)
            return;
        uint32_t chunk = (uint32_t)t;
        if (chunk >= atomic_load_explicit(&j->chunks, memory_order_relaxed))
            return;
        if (!atomic_compare_exchange_weak_explicit(&j->ticket, &t, t + 1, memory_order_acq_rel, memory_order_acquire))
            continue; /* t now holds the ticket as it is */
        uint32_t grain = atomic_load_explicit(&j->grain, memory_order_relaxed);
        uint32_t total = atomic_load_explicit(&j->total, memory_order_relaxed);
        uint32_t first = chunk * grain;
        uint32_t count = total - first < grain ? total - first : grain;
        atomic_load_explicit(&j->fn, memory_order_relaxed)(atomic_load_explicit(&j->user, memory_order_relaxed), first,
                                                           count, thread);
        atomic_fetch_add_explicit(&j->done, 1, memory_order_acq_rel);
        t = atomic_load_explicit(&j->ticket, memory_order_acquire);
    }
}

static void *worker_main(void *p)
{
    worker_arg *arg = p;
    sinew_jobs *j = arg->jobs;
    uint32_t index = arg->index;
    uint32_t seen = 0;
    for (;;) {
        /* spin a while for the next generation, then sleep */
        uint64_t until = now_ns() + j->spin_ns;
        uint32_t gen = seen;
        for (int i = 0;; i++) {
            gen = (uint32_t)(atomic_load_explicit(&j->ticket, memory_order_acquire) >> 32);
            if (gen != seen || atomic_load_explicit(&j->quit, memory_order_acquire))
                break;
            cpu_relax();
            if ((i & 63) == 63 && now_ns() > until)
                break;
        }
        if (gen == seen && !atomic_load(&j->quit)) {
            pthread_mutex_lock(&j->lock);
            atomic_fetch_add(&j->sleepers, 1);
            while ((gen = (uint32_t)(atomic_load(&j->ticket) >> 32)) == seen && !atomic_load(&j->quit))
                pthread_cond_wait(&j->wake, &j->lock);
            atomic_fetch_sub(&j->sleepers, 1);
            pthread_mutex_unlock(&j->lock);
        }
        if (atomic_load(&j->quit))
            return NULL;
        seen = gen;
        if (index < atomic_load_explicit(&j->active, memory_order_relaxed))
            take_chunks(j, gen, index);
    }
}

uint32_t sinew_cpu_count(void)
{
#ifdef CPU_COUNT
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0)
        return (uint32_t)CPU_COUNT(&set);
#endif
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (uint32_t)n : 1u;
}

sinew_result sinew_jobs_create(const sinew_jobs_desc *desc, sinew_jobs **out, sinew_error *error)
{
    if (!out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_jobs_create: NULL output");
    *out = NULL;
    sinew_jobs_desc d = desc ? *desc : (sinew_jobs_desc){0};
    if (d.allocator && (!d.allocator->alloc || !d.allocator->free))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_jobs_create: allocator without alloc or free");
    uint32_t threads = d.threads ? d.threads : sinew_cpu_count();
    if (threads > MAX_THREADS)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_jobs_create: %u threads, at most %u", threads,
                          MAX_THREADS);
    sinew_allocator a = sinew_allocator_or_default(d.allocator);
    size_t size = sizeof(sinew_jobs) + threads * sizeof(pthread_t) + threads * sizeof(worker_arg);
    sinew_jobs *j = a.alloc(size, a.user);
    if (!j)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "sinew_jobs_create: out of memory");
    memset(j, 0, size);
    j->allocator = a;
    j->threads = threads;
    j->spin_ns = (uint64_t)(d.spin_us ? d.spin_us : 50) * 1000u;
    atomic_init(&j->active, threads);
    pthread_mutex_init(&j->lock, NULL);
    pthread_cond_init(&j->wake, NULL);
    worker_arg *args = (worker_arg *)&j->workers[threads];
    for (uint32_t i = 1; i < threads; i++) {
        args[i] = (worker_arg){j, i};
        if (pthread_create(&j->workers[i], NULL, worker_main, &args[i]) != 0) {
            sinew_jobs_free(j);
            return sinew_fail(error, SINEW_ERROR_IO, "sinew_jobs_create: cannot start thread %u of %u", i + 1, threads);
        }
        j->started = i;
    }
    *out = j;
    return SINEW_OK;
}

void sinew_jobs_free(sinew_jobs *j)
{
    if (!j)
        return;
    pthread_mutex_lock(&j->lock);
    atomic_store(&j->quit, true);
    pthread_cond_broadcast(&j->wake);
    pthread_mutex_unlock(&j->lock);
    for (uint32_t i = 1; i <= j->started; i++)
        pthread_join(j->workers[i], NULL);
    pthread_mutex_destroy(&j->lock);
    pthread_cond_destroy(&j->wake);
    j->allocator.free(j, j->allocator.user);
}

uint32_t sinew_jobs_threads(const sinew_jobs *j)
{
    return j ? j->threads : 1u;
}

/* Adjusts the active thread count after a run that worked `work_ns` and then waited
 * `wait_ns` for other threads' chunks (see the top of the file). */
static void adapt(sinew_jobs *j, uint32_t active, uint64_t work_ns, uint64_t wait_ns)
{
    if (active > 1 && wait_ns > work_ns / 2 && wait_ns > 20000) {
        if (++j->strikes >= 2) {
            atomic_store_explicit(&j->active, active - 1, memory_order_relaxed);
            j->strikes = 0, j->calm = 0;
        }
        return;
    }
    j->strikes = 0;
    if (active < j->threads && ++j->calm >= 64) {
        atomic_store_explicit(&j->active, active + 1, memory_order_relaxed);
        j->calm = 0;
    }
}

void sinew_jobs_run(sinew_jobs *j, uint32_t total, uint32_t grain, sinew_job_fn fn, void *user)
{
    if (!fn || total == 0)
        return;
    uint32_t threads = j ? j->threads : 1u;
    uint32_t active = j ? atomic_load_explicit(&j->active, memory_order_relaxed) : 1u;
    if (grain == 0)
        grain = total / (4 * threads) ? total / (4 * threads) : 1u;
    uint32_t chunks = (uint32_t)(((uint64_t)total + grain - 1) / grain);
    if (active == 1 || chunks == 1) {
        for (uint32_t first = 0; first < total; first += grain)
            fn(user, first, total - first < grain ? total - first : grain, 0);
        if (j && chunks > 1)
            adapt(j, 1, 0, 0);
        return;
    }
    atomic_store_explicit(&j->fn, fn, memory_order_relaxed);
    atomic_store_explicit(&j->user, user, memory_order_relaxed);
    atomic_store_explicit(&j->total, total, memory_order_relaxed);
    atomic_store_explicit(&j->grain, grain, memory_order_relaxed);
    atomic_store_explicit(&j->chunks, chunks, memory_order_relaxed);
    atomic_store_explicit(&j->done, 0, memory_order_relaxed);
    uint32_t gen = ++j->generation;
    if (gen == 0) /* 0 is the workers' "seen nothing yet" */
        gen = ++j->generation;
    uint64_t start = now_ns();
    atomic_store(&j->ticket, (uint64_t)gen << 32); /* seq_cst: ordered before the sleepers check */
    if (atomic_load(&j->sleepers) > 0) {
        pthread_mutex_lock(&j->lock);
        pthread_cond_broadcast(&j->wake);
        pthread_mutex_unlock(&j->lock);
    }
    take_chunks(j, gen, 0);
    uint64_t worked = now_ns();
    for (uint32_t i = 0; atomic_load_explicit(&j->done, memory_order_acquire) != chunks; i++) {
        if (i < 2000)
            cpu_relax();
        else
            sched_yield();
    }
    adapt(j, active, worked - start, now_ns() - worked);
}
