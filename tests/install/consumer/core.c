/* The runtime alone: a muscle solved at a new length, and a parallel loop of the job system
 * (libsinew_core, libc and its threads, cglm). */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>

#include <sinew/jobs.h>
#include <sinew/muscle.h>

static void add(void *user, uint32_t first, uint32_t count, uint32_t thread)
{
    (void)thread;
    (void)first;
    atomic_fetch_add((_Atomic uint32_t *)user, count);
}

int main(void)
{
    const double radii[3] = {0.01, 0.02, 0.01}, coefficients[3] = {0, 1, 0};
    sinew_muscle_profile profile = {3, radii, coefficients, 0.3};
    double out[3];
    sinew_muscle_state state;
    if (sinew_muscle_solve(&profile, 0.25, out, 3, &state, NULL) != SINEW_OK)
        return 1;
    printf("volume %.9g of %.9g\n", state.volume, state.rest_volume);
    sinew_jobs *jobs = NULL;
    _Atomic uint32_t items = 0;
    if (sinew_jobs_create(&(sinew_jobs_desc){.threads = 3}, &jobs, NULL) != SINEW_OK)
        return 1;
    sinew_jobs_run(jobs, 1000, 10, add, &items);
    sinew_jobs_free(jobs);
    if (items != 1000)
        return 1;
    return fabs(state.volume - state.rest_volume) < 1e-12 ? 0 : 1;
}
