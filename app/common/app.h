/* app/common: what the sinew command and the sinew-view viewer share and the library does
 * not do (it never parses command lines): display options and camera specs read from
 * arguments. Prints nothing; errors come back in a sinew_error. */
#ifndef SINEW_APP_H
#define SINEW_APP_H

#include <stdbool.h>

#include "sinew/sinew.h"

/* Fills `error` (when not NULL) with kind and message; returns kind. */
sinew_result app_fail(sinew_error *error, sinew_result kind, const char *format, ...)
    __attribute__((format(printf, 3, 4)));

/* Reads "orbit:YAW,PITCH[,DISTANCE]" or "fly:X,Y,Z,YAW,PITCH" (angles in degrees) into
 * `camera`, leaving what the text does not give as it was. *frame_all is set true when
 * an orbit gives no distance (or "auto"): the caller then frames the scene and keeps the
 * angles. A malformed text gives SINEW_ERROR_INVALID_ARGUMENT saying what was expected. */
sinew_result app_camera_parse(const char *text, sinew_camera *camera, bool *frame_all, sinew_error *error);

/* Reads one display option from a command line at argv[i] (what `sinew render` and
 * `sinew-view` accept): --NAME, --no-NAME or --NAME on|off for a switch (--bones is
 * --skeleton), --NAME VALUE for the others (sinew_render_option_set() names). Returns the
 * arguments used: 0 when argv[i] is not a display option, -1 with the error filled for a
 * missing or bad value. *name (may be NULL) gets the option's name. */
int app_render_option_parse(sinew_render_options *options, int argc, char *const *argv, int i, const char **name,
                            sinew_error *error);

#endif
