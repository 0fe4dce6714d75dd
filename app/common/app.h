/* app/common: what the sinew command and the sinew-view viewer share and the library does
 * not do (it never parses command lines): display options and camera specs read from
 * arguments. Prints nothing; errors come back in a sinew_error. */
#ifndef SINEW_APP_H
#define SINEW_APP_H

#include <stdbool.h>
#include <stdio.h>

#include "sinew/sinew.h"

/* Numbers, strictly: the whole text, plain decimal (no blanks, "nan", "inf" or hex), finite,
 * within [lo, hi]. The list form reads min..max numbers separated by commas and returns how
 * many, or -1. Sizes are WIDTHxHEIGHT, each within lo..hi. */
int app_parse_list(const char *text, double *out, int min, int max, double lo, double hi);
bool app_parse_number(const char *text, double lo, double hi, double *out);
bool app_parse_integer(const char *text, long lo, long hi, long *out);
bool app_parse_size(const char *text, int lo, int hi, int *width, int *height);

/* The largest time in seconds (either sign) an option takes: about 115 days (the runtime's
 * times are floats). */
#define APP_MAX_SECONDS 1e7

/* Output files, whole or not at all (output.c): written to a hidden temporary file in the
 * target's folder and renamed over the target only when every write, the flush and the close
 * succeeded; an existing target that is not a regular file (/dev/stdout, a FIFO) is written in
 * place with every write checked. Errors say "PATH: cannot write: REASON". */
typedef struct app_output {
    char path[4096], temp[4096];
    FILE *file;
    bool in_place; /* writing the target itself */
    bool external; /* another program writes the temporary file (ffmpeg) */
    bool failed;
    int saved_errno;
} app_output;

sinew_result app_output_open(app_output *o, const char *path, sinew_error *error);
bool app_output_write(app_output *o, const void *bytes, size_t size);
/* The file to hand to another program that writes the output (after app_output_release()). */
const char *app_output_temp_path(const app_output *o);
void app_output_release(app_output *o);
/* Checks, closes and renames into place; on failure removes the temporary file. */
sinew_result app_output_commit(app_output *o, sinew_error *error);
void app_output_abort(app_output *o);

/* Refuses an output that is one of the inputs (same file, by device and inode or real path). */
sinew_result app_output_check(const char *output, const char *const *inputs, size_t input_count, sinew_error *error);

/* What a file name's extension asks to be written as (no extension, as /dev/stdout: PNG). */
typedef enum app_image_format {
    APP_IMAGE_UNKNOWN,
    APP_IMAGE_PNG,
    APP_IMAGE_JPEG, /* quality 92 */
    APP_IMAGE_BMP,
    APP_IMAGE_TGA,
    APP_VIDEO /* .mp4 .m4v .mov .mkv .webm .gif: through ffmpeg */
} app_image_format;
app_image_format app_image_format_of(const char *path);
/* Whether `path` ends in "." and `ext`, case ignored. */
bool app_has_extension(const char *path, const char *ext);

/* An RGBA image as RGB PNG, JPEG, BMP or TGA (by the extension; another is refused) through
 * app_output (flip: the rows come bottom first). */
/* Video: raw RGBA frames piped into the ffmpeg program, which writes a temporary file beside
 * the target, put in place by app_video_close(). */
typedef struct app_video {
    const char *path;
    int fd;
    int pid;
    size_t frame_bytes;
    bool unavailable;  /* open failed because ffmpeg is not installed */
    bool write_failed; /* the output could not be written (exit EXIT_OUTPUT) */
    app_output output; /* the temporary file ffmpeg writes */
} app_video;

/* Starts ffmpeg for `path` (MP4, WebM, MKV, MOV, GIF by the extension); `flip`: frames come
 * bottom row first (glReadPixels). SIGPIPE should be ignored: a dead ffmpeg is a write error. */
sinew_result app_video_open(app_video *video, const char *path, int width, int height, double fps, bool flip,
                            sinew_error *error);
sinew_result app_video_write(app_video *video, const uint8_t *rgba, sinew_error *error);
/* Waits for ffmpeg and puts the video in place when `keep` and ffmpeg succeeded; else removes it. */
sinew_result app_video_close(app_video *video, bool keep, sinew_error *error);

sinew_result app_write_image(const char *path, const unsigned char *rgba, int width, int height, bool flip, bool alpha,
                             sinew_error *error);

/* Makes the folders of `path` that are missing (as mkdir -p on its parent). */
sinew_result app_make_parent_folders(const char *path, sinew_error *error);

/* A player with its own clip layout and state (sinew/anim.h), for one character. */
typedef struct app_player {
    sinew_clip_layout *layout;
    sinew_player *player;
    void *memory;
} app_player;
sinew_result app_player_open(app_player *p, const sinew_model *model, const sinew_clip *clip, sinew_error *error);
void app_player_close(app_player *p);

/* Reads "orbit:YAW,PITCH[,DISTANCE]" or "fly:X,Y,Z,YAW,PITCH" (angles in degrees) into
 * `camera`, leaving what the text does not give as it was. *frame_all is set true when
 * an orbit gives no distance (or "auto"): the caller then frames the scene and keeps the
 * angles. A malformed text gives SINEW_ERROR_INVALID_ARGUMENT saying what was expected. */
sinew_result app_camera_parse(const char *text, sinew_camera *camera, bool *frame_all, sinew_error *error);

/* f3d's camera placement: --camera-position X,Y,Z and --camera-focal-point X,Y,Z (world
 * metres) and --fov DEGREES (vertical, 1..170). app_camera_place() applies them after framing:
 * the focal point becomes the orbit target (else the framed centre stays), the position the eye
 * (else the framed distance and angles stay). */
typedef struct app_camera_placement {
    bool has_position, has_focal;
    float position[3], focal[3];
    double fov; /* degrees; 0: the camera's own (45) */
} app_camera_placement;
/* Takes --camera-position, --camera-focal-point or --fov and its value into `placement`: 1 when
 * `option` is one of them, 0 when it is not, -1 for a bad value (the error says what was expected). */
int app_camera_placement_parse(app_camera_placement *placement, const char *option, const char *value,
                               sinew_error *error);
void app_camera_place(sinew_camera *camera, const app_camera_placement *placement);

/* Reads one display option from a command line at argv[i] (what `sinew render` and
 * `sinew-view` accept): --NAME, --no-NAME or --NAME on|off for a switch (--bones is
 * --skeleton), --NAME VALUE for the others (sinew_render_option_set() names). Returns the
 * arguments used: 0 when argv[i] is not a display option, -1 with the error filled for a
 * missing or bad value. *name (may be NULL) gets the option's name. */
int app_render_option_parse(sinew_render_options *options, int argc, char *const *argv, int i, const char **name,
                            sinew_error *error);

#endif
