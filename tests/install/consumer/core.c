/* The runtime alone: a muscle solved at a new length (libsinew_core, libc, cglm). */
#include <math.h>
#include <stdio.h>

#include <sinew/muscle.h>

int main(void)
{
    const double radii[3] = {0.01, 0.02, 0.01}, coefficients[3] = {0, 1, 0};
    sinew_muscle_profile profile = {3, radii, coefficients, 0.3};
    double out[3];
    sinew_muscle_state state;
    if (sinew_muscle_solve(&profile, 0.25, out, 3, &state, NULL) != SINEW_OK)
        return 1;
    printf("volume %.9g of %.9g\n", state.volume, state.rest_volume);
    return fabs(state.volume - state.rest_volume) < 1e-12 ? 0 : 1;
}
