/* sinew/jobs.h — a small job system: one parallel loop at a time over N threads.
 *
 * What: sinew_jobs_run() splits [0, total) into chunks of `grain` items and calls
 * fn(user, first, count, thread) for each, on the calling thread and on the workers, and
 * returns when every chunk is done. Chunks are taken one at a time from a shared counter,
 * so a thread that the machine does not run (a busy machine, a descheduled worker) simply
 * takes fewer: the caller takes whatever is left, and N threads are not slower than one by
 * more than a chunk a thread. Idle workers spin for a short while (spin_us) and then sleep
 * on a condition variable, so they cost nothing between frames.
 *
 * `thread` is 0 for the caller and 1 .. threads - 1 for the workers: index per-thread
 * scratch with it (a character's world matrices, a skinning buffer).
 *
 *   sinew_jobs *jobs;
 *   sinew_jobs_create(&(sinew_jobs_desc){0}, &jobs, &error);       // the cores this process may use
 *   each frame: sinew_jobs_run(jobs, characters, 16, update_characters, &frame);
 *   at the end: sinew_jobs_free(jobs);
 *
 * One sinew_jobs_run() at a time per sinew_jobs (from one thread); fn must not call
 * sinew_jobs_run() on the same sinew_jobs.
 */
#ifndef SINEW_JOBS_H
#define SINEW_JOBS_H

#include <stdint.h>

#include "sinew/model.h"
#include "sinew/result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sinew_jobs sinew_jobs;

typedef struct sinew_jobs_desc {
    uint32_t threads;                 /* threads that run chunks, the caller included; 0: sinew_cpu_count() */
    uint32_t spin_us;                 /* how long an idle worker spins before it sleeps; 0: 50 microseconds */
    const sinew_allocator *allocator; /* NULL: malloc/free */
} sinew_jobs_desc;

typedef void (*sinew_job_fn)(void *user, uint32_t first, uint32_t count, uint32_t thread);

/* Starts threads - 1 workers. SINEW_ERROR_INVALID_ARGUMENT for more than 256 threads;
 * SINEW_ERROR_OUT_OF_MEMORY; SINEW_ERROR_IO when a thread cannot be started. */
sinew_result sinew_jobs_create(const sinew_jobs_desc *desc, sinew_jobs **out, sinew_error *error);
/* Stops and joins the workers. NULL is fine. */
void sinew_jobs_free(sinew_jobs *jobs);

/* Threads that run chunks, the caller included. */
uint32_t sinew_jobs_threads(const sinew_jobs *jobs);

/* Runs fn over [0, total) in chunks of `grain` items (0: total / (4 * threads), at least 1)
 * and returns when all are done. NULL jobs runs everything on the calling thread. */
void sinew_jobs_run(sinew_jobs *jobs, uint32_t total, uint32_t grain, sinew_job_fn fn, void *user);

/* The processors this process may run on (its affinity mask), at least 1. */
uint32_t sinew_cpu_count(void);

#ifdef __cplusplus
}
#endif
#endif
