/* The job system under ThreadSanitizer (built with -fsanitize=thread by tests/CMakeLists.txt):
 * back-to-back runs on 2, 3 and 4 threads with one-item chunks, so that late workers, stealing
 * and the end of a run race as much as they can; every item must be counted exactly once a run.
 * Any data race makes ThreadSanitizer fail the test. */
#include <stdatomic.h>
#include <stdio.h>

#include "sinew/jobs.h"

enum { ITEMS = 64, RUNS = 20000 };
static _Atomic unsigned visits[ITEMS];

static void count(void *user, uint32_t first, uint32_t n, uint32_t thread)
{
    (void)user, (void)thread;
    for (uint32_t i = first; i < first + n; i++)
        atomic_fetch_add(&visits[i], 1);
}

int main(void)
{
    for (uint32_t threads = 2; threads <= 4; threads++) {
        sinew_jobs *jobs = NULL;
        if (sinew_jobs_create(&(sinew_jobs_desc){.threads = threads, .spin_us = 5}, &jobs, NULL) != SINEW_OK)
            return 1;
        for (int r = 0; r < RUNS; r++)
            sinew_jobs_run(jobs, ITEMS, 1, count, NULL);
        sinew_jobs_free(jobs);
    }
    for (int i = 0; i < ITEMS; i++)
        if (visits[i] != 3u * RUNS) {
            fprintf(stderr, "item %d counted %u times, not %u\n", i, visits[i], 3u * RUNS);
            return 1;
        }
    printf("%d runs on 2, 3 and 4 threads: every item once a run\n", 3 * RUNS);
    return 0;
}
