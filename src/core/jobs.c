/* The job system (sinew/jobs.h): a static split of the chunks with stealing.
 *
 * A run splits its chunks into one contiguous range a thread ("slot"): thread t first takes
 * the chunks of its own range, in order, so that a thread handles the same items run after
 * run (a character's player state stays in its core's cache), and then steals from the
 * other ranges, so that a late or preempted thread costs nothing but its own chunk in hand.
 * A slot is one 64-bit atomic, generation << 32 | next chunk, on its own cache line; a
 * chunk is taken by compare-and-swap on it. The caller publishes a run as a generation:
 * parameters, then the slots tagged with it, then `ticket` (the generation, which idle
 * workers watch). When every chunk is done the caller closes the slots (next = all ones),
 * so that a worker that wakes late can never take a chunk of a finished run, nor of the
 * next (its generation differs). Workers spin (with the pause instruction) for spin_us
 * after their last run, then sleep on a condition variable; the caller wakes them only when
 * some sleep. The caller takes chunks too and, when none are left, waits for the ones in
 * flight: spinning first, then yielding its processor (on a busy machine the worker it
 * waits for may be queued behind it).
 *
 * A worker the machine preempts while it holds a chunk makes the caller wait for it, up to
 * a scheduler time slice: on a machine busy with other work that can cost more than the
 * worker brings. So the caller watches each run: when, on average over the last runs, its
 * wait for stragglers cost more than the others' chunks saved it (slower than the caller
 * alone), one worker fewer takes part ("active" threads); later one more is tried again
 * (see adapt()). On a quiet machine
 * all threads stay active; on a busy one the run degrades towards the caller alone, which is
 * what one thread would do. */
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
    void *memory; /* as allocated: the struct is aligned to 64 bytes inside it */
    uint32_t threads;
    uint64_t spin_ns;
    /* each written by every thread on its own cache line, away from what they only read */
    _Alignas(64) _Atomic uint64_t ticket; /* generation << 32: the run idle workers wait for */
    _Alignas(64) _Atomic uint32_t done;   /* chunks finished in this generation */
    _Alignas(64) _Atomic uint32_t sleepers;
    _Atomic bool quit;
    /* the run of the current generation: written before the ticket, read after it */
    _Atomic(sinew_job_fn) fn;
    _Atomic(void *) user;
    _Alignas(64) _Atomic uint32_t total, grain, chunks;
    _Atomic uint32_t run_active; /* threads (slots) of the current run */
    _Atomic uint32_t active;     /* threads the next run may use, the caller included */
    struct slot *slots;          /* threads of them, 64-byte aligned */
    /* the caller's (adapt()): */
    double gain;            /* running mean of what the extra threads brought a run, ns */
    uint32_t runs_on_count; /* runs since the active count last changed */
    uint32_t probe_wait;    /* runs on fewer threads before one more is tried */
    bool probing;           /* the last change added a thread */
    pthread_mutex_t lock;
    pthread_cond_t wake;
    uint32_t generation; /* the caller's */
    uint32_t started;    /* workers running */
    pthread_t workers[];
};

typedef struct slot {
    _Alignas(64) _Atomic uint64_t next; /* generation << 32 | next chunk of this range */
} slot;

#define CLOSED 0xffffffffu

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

/* Takes and runs chunks of range `r` of generation `gen` until it has none left; false when
 * the generation is over (nothing more to take anywhere). */
static bool take_range(sinew_jobs *j, uint32_t gen, uint32_t r, uint32_t active, uint32_t thread, uint32_t *taken)
{
    uint32_t chunks = atomic_load_explicit(&j->chunks, memory_order_relaxed);
    uint32_t end = (uint32_t)((uint64_t)chunks * (r + 1) / active);
    _Atomic uint64_t *next = &j->slots[r].next;
    uint64_t t = atomic_load_explicit(next, memory_order_acquire);
    for (;;) {
        if ((uint32_t)(t >> 32) != gen)
            return false;
        uint32_t chunk = (uint32_t)t;
        if (chunk >= end)
            return true; /* this range is done (or closed) */
        if (!atomic_compare_exchange_weak_explicit(next, &t, t + 1, memory_order_acq_rel, memory_order_acquire))
            continue; /* t now holds the slot as it is */
        uint32_t grain = atomic_load_explicit(&j->grain, memory_order_relaxed);
        uint32_t total = atomic_load_explicit(&j->total, memory_order_relaxed);
        uint32_t first = chunk * grain;
        uint32_t count = total - first < grain ? total - first : grain;
        atomic_load_explicit(&j->fn, memory_order_relaxed)(atomic_load_explicit(&j->user, memory_order_relaxed), first,
                                                           count, thread);
        atomic_fetch_add_explicit(&j->done, 1, memory_order_acq_rel);
        ++*taken;
        t = atomic_load_explicit(next, memory_order_acquire);
    }
}

/* Thread `thread`'s part of generation `gen`: its own range, then the others'. Returns the
 * chunks it ran. */
static uint32_t take_chunks(sinew_jobs *j, uint32_t gen, uint32_t thread)
{
    uint32_t active = atomic_load_explicit(&j->run_active, memory_order_relaxed), taken = 0;
    for (uint32_t k = 0; thread < active && k < active; k++)
        if (!take_range(j, gen, (thread + k) % active, active, thread, &taken))
            break;
    return taken;
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
    size_t head = sizeof(sinew_jobs) + threads * sizeof(pthread_t) + threads * sizeof(worker_arg);
    head = (head + 63) & ~(size_t)63;
    size_t size = head + threads * sizeof(slot);
    void *memory = a.alloc(size + 64, a.user);
    if (!memory)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "sinew_jobs_create: out of memory");
    sinew_jobs *j = (sinew_jobs *)(((uintptr_t)memory + 63) & ~(uintptr_t)63);
    memset(j, 0, size);
    j->allocator = a;
    j->memory = memory;
    j->slots = (slot *)((char *)j + head);
    j->threads = threads;
    j->spin_ns = (uint64_t)(d.spin_us ? d.spin_us : 50) * 1000u;
    atomic_init(&j->active, threads);
    j->probe_wait = 64;
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
    j->allocator.free(j->memory, j->allocator.user);
}

uint32_t sinew_jobs_threads(const sinew_jobs *j)
{
    return j ? j->threads : 1u;
}

/* Adjusts the active thread count after a run in which the caller worked `work_ns` on `mine`
 * of the `chunks` and then waited `wait_ns` for the others' (see the top of the file). The
 * others saved it about (chunks - mine) * work_ns / mine; gain - wait is what the extra
 * threads brought this run (negative: slower than the caller alone). Its running mean over
 * the last runs (a moving average, 1/8 a run) decides: after at least 8 runs on a count, a
 * negative mean drops a thread. After `probe_wait` runs on fewer threads than it has (64,
 * doubling up to 4096 each time a retried thread is dropped again within 32 runs, back to 64
 * when one stays), one more is tried. */
static void adapt(sinew_jobs *j, uint32_t active, uint64_t work_ns, uint64_t wait_ns, uint32_t mine, uint32_t chunks)
{
    j->runs_on_count++;
    if (active > 1) {
        double saved = mine ? (double)(chunks - mine) * (double)work_ns / mine : 0.0;
        j->gain += ((saved - (double)wait_ns) - j->gain) / 8.0;
        if (j->runs_on_count >= 8 && j->gain < 0.0) {
            atomic_store_explicit(&j->active, active - 1, memory_order_relaxed);
            if (j->probing) /* a retried thread that did not pay: wait longer next time */
                j->probe_wait = j->probe_wait * 2 > 4096 ? 4096 : j->probe_wait * 2;
            j->probing = false, j->runs_on_count = 0, j->gain = 0.0;
            return;
        }
        if (j->probing && j->runs_on_count >= 32)
            j->probing = false, j->probe_wait = 64;
    }
    if (active < j->threads && j->runs_on_count >= j->probe_wait) {
        atomic_store_explicit(&j->active, active + 1, memory_order_relaxed);
        j->probing = true, j->runs_on_count = 0, j->gain = 0.0;
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
            adapt(j, 1, 0, 0, chunks, chunks);
        return;
    }
    atomic_store_explicit(&j->fn, fn, memory_order_relaxed);
    atomic_store_explicit(&j->user, user, memory_order_relaxed);
    atomic_store_explicit(&j->total, total, memory_order_relaxed);
    atomic_store_explicit(&j->grain, grain, memory_order_relaxed);
    atomic_store_explicit(&j->chunks, chunks, memory_order_relaxed);
    atomic_store_explicit(&j->done, 0, memory_order_relaxed);
    if (active > chunks)
        active = chunks;
    atomic_store_explicit(&j->run_active, active, memory_order_relaxed);
    uint32_t gen = ++j->generation;
    if (gen == 0) /* 0 is the workers' "seen nothing yet" */
        gen = ++j->generation;
    for (uint32_t r = 0; r < active; r++)
        atomic_store_explicit(&j->slots[r].next, (uint64_t)gen << 32 | (uint32_t)((uint64_t)chunks * r / active),
                              memory_order_relaxed);
    uint64_t start = now_ns();
    atomic_store(&j->ticket, (uint64_t)gen << 32); /* seq_cst: ordered before the sleepers check */
    if (atomic_load(&j->sleepers) > 0) {
        pthread_mutex_lock(&j->lock);
        pthread_cond_broadcast(&j->wake);
        pthread_mutex_unlock(&j->lock);
    }
    uint32_t mine = take_chunks(j, gen, 0);
    uint64_t worked = now_ns();
    for (uint32_t i = 0; atomic_load_explicit(&j->done, memory_order_acquire) != chunks; i++) {
        if (i < 2000)
            cpu_relax();
        else
            sched_yield();
    }
    for (uint32_t r = 0; r < active; r++) /* no late worker takes from a finished run */
        atomic_store_explicit(&j->slots[r].next, (uint64_t)gen << 32 | CLOSED, memory_order_release);
    adapt(j, active, worked - start, now_ns() - worked, mine, chunks);
}
