/* Shared pieces of the `sinew` command: exit codes, model loading, posing helpers. */
#ifndef SINEW_CLI_H
#define SINEW_CLI_H

#include <stdio.h>

#include "crowd.h"
#include "scene.h"
#include "sinew/sinew.h"

/* One exit status per kind of fault, in every command (README, sinew.1):
 * 1: the command line is wrong (unknown option, malformed or out-of-range value);
 * 2: an input is unreadable or malformed, or lacks what was named (a clip, a joint);
 * 3: this machine lacks something the command needs (an OpenGL 3.3 context, ffmpeg);
 * 4: an output cannot be written (no space, no permission, it is an input, it exists). */
/* The most pixels a picture may have (--size): 8192x8192. */
#define CLI_MAX_PIXELS (8192.0 * 8192.0)
/* The most samples --samples takes (GPUs offer 8 to 32; more is refused, not clamped silently). */
#define CLI_MAX_SAMPLES 16

enum { EXIT_OK = 0, EXIT_USAGE = 1, EXIT_BAD_INPUT = 2, EXIT_UNAVAILABLE = 3, EXIT_OUTPUT = 4 };

/* --import-timeout / --import-memory, wherever they are on the command line (main.c). */
extern app_import_options cli_import;
/* --quiet (any command): import warnings are not printed. */
extern bool cli_quiet;
/* Prints a model's import warnings on stderr ("sinew: warning: ..."), unless --quiet. */
void cli_print_warnings(const sinew_model *model);
/* A progress line on stderr while long work runs (frames done, rate, time left), only on a
 * terminal and without --quiet; cleared at the end. */
typedef struct cli_progress {
    const char *what;
    uint32_t total;
    bool live;
    double started, shown;
} cli_progress;
void cli_progress_start(cli_progress *p, const char *what, uint32_t total);
void cli_progress_update(cli_progress *p, uint32_t done);
void cli_progress_end(cli_progress *p);

/* A note on stderr (not with --quiet) when a time lies outside the clip: what it became. */
void cli_note_times(const sinew_clip *clip, const double *times, uint32_t count, bool loop);

/* Prints "sinew: <message>" to stderr. */
void cli_error(const char *format, ...) __attribute__((format(printf, 1, 2)));

/* Loads a model file (any format sinew reads), or APP_BUILTIN_ARM / APP_BUILTIN_DEMO; prints
 * the error and returns NULL on failure. */
sinew_model *cli_load_model(const char *path);

/* The double nearest the shortest decimal that reads back as `value`, so JSON shows
 * 0.1 rather than 0.100000001490116 for a float 0.1; tiny values below 1e-12 become 0. */
double cli_json_float(float value);

/* Option values, strictly (all of the text); each prints "COMMAND: bad OPTION ..." and
 * returns false otherwise. Sizes are WIDTHxHEIGHT, each 1..16384. */
bool cli_parse_count(const char *command, const char *option, const char *text, long lo, long hi, long *out);
bool cli_parse_size(const char *command, const char *text, int *width, int *height);

/* --threads N at argv[*i] (1..most): the value; advances *i past it. */
bool cli_threads_arg(int argc, char **argv, int *i, uint32_t most, uint32_t *out);

/* Seconds on the monotonic clock (the benchmarks' timer). */
double cli_now_seconds(void);

/* True when `arg` is --help or -h. */
bool cli_is_help(const char *arg);

/* A model posed and drawn off-screen: what `render` and `bench render` share. */
typedef struct cli_scene_desc {
    /* the scene as both apps describe it (file or model, clip, --anim, --up, the pose spec);
     * its muscle mode comes from `muscles` below */
    app_scene_desc scene;
    const char *muscles; /* NULL: none; "": the file beside the model; else a muscle file */
    const char *camera, *select, *heatmap;
    int width, height, samples;
    bool loop, skeleton_set, orthographic;
    uint32_t gpu_joint_limit;
    sinew_render_options options;
    uint32_t crowd;                 /* > 0: that many characters on a grid (app_crowd), each at its own time and clip */
    uint32_t threads;               /* the crowd's job system: 0 = the cores this process may use */
    app_camera_placement placement; /* --camera-position, --camera-focal-point, --fov */
    const char *hdri;               /* --hdri FILE: the environment (sinew_renderer_set_environment) */
} cli_scene_desc;

typedef struct cli_scene {
    app_scene scene;
    sinew_model *model;     /* scene.model */
    const sinew_clip *clip; /* scene.clip */
    sinew_headless *headless;
    sinew_renderer *renderer;
    sinew_camera camera;
    bool frame_all; /* the camera spec left the distance to framing */
    app_camera_placement placement;
    app_follow follow; /* --track */
    sinew_render_options frame_options;
    sinew_wrap wrap;
    int width, height;
    uint8_t *pixels; /* width * height * 4, top row first */
    const char *gl_name;
    uint32_t warnings_printed; /* the renderer's warnings printed so far (a crowd's come at its first draw) */
    app_crowd crowd;           /* count 0: no crowd */
    sinew_jobs *jobs;
} cli_scene;

/* --muscles as a scene wants it: NULL none, "" the model's own or the file beside it, else a file. */
void cli_scene_muscles(const char *spec, app_scene_desc *desc);
/* app_scene_open() with the import's stderr passed through and the CLI's import limits; prints
 * the error and returns its kind (SINEW_OK when the scene is open). */
sinew_result cli_scene_load(app_scene *scene, const app_scene_desc *desc);

/* Loads, makes the context and the renderer; prints the error and returns an exit code. */
int cli_scene_open(cli_scene *scene, const cli_scene_desc *desc);
/* Places the camera on the posed bounds over [from, to] (as the camera spec asks). */
bool cli_scene_frame_all(cli_scene *scene, double from, double to);
bool cli_scene_pose(cli_scene *scene, double time);
/* Moves the orbit target (or the fly eye, by the same step) to the centre of the pose
 * at `time`, keeping distance and angles: the camera follows a walking character. */
bool cli_scene_track(cli_scene *scene, double time);
/* Poses at `time` and draws (no read-back). */
bool cli_scene_draw(cli_scene *scene, double time);
/* Seconds a frame of drawing (cli_scene_draw and glFinish, each frame timed; no read-back): the
 * median of `frames` frames at 60 Hz from t = warmup / 60, after `warmup` frames from 0; and when
 * submit_seconds is given, the median of the part before glFinish (posing, palettes, GL calls:
 * the CPU's share; the rest is waiting for the GPU). */
bool cli_scene_time_frames(cli_scene *scene, int warmup, int frames, double *seconds_per_frame, double *submit_seconds);
/* Reads the frame into scene->pixels. */
bool cli_scene_read(cli_scene *scene);
void cli_scene_close(cli_scene *scene);

/* Takes --muscles [FILE.json] at argv[*i]: the file when the next argument ends in .json,
 * else "" (the file beside the model). */
const char *cli_muscles_arg(int argc, char **argv, int *i);

/* One muscle of a rig as JSON: {"name", "length", "rest_length", "delta", "volume",
 * "rest_volume", "in_range", "origin", "insertion", "radii"}. */
struct cJSON;
struct cJSON *cli_muscle_pose_json(const sinew_muscle_pose *pose);

/* An image (PNG, JPEG, BMP or TGA by the extension) through app_write_image() (whole or not at
 * all); prints the error and returns false on failure. */
bool cli_write_image(const char *path, const uint8_t *rgba, int width, int height, bool alpha);

/* Video output: app_video (raw RGBA frames piped into the ffmpeg program), errors printed. */
typedef app_video cli_video;

bool cli_video_open(cli_video *video, const char *path, int width, int height, double fps);
bool cli_video_write(cli_video *video, const uint8_t *rgba);
/* Waits for ffmpeg and puts the video in place when `keep` and ffmpeg succeeded; else removes it. */
bool cli_video_close(cli_video *video, bool keep);
/* A dead ffmpeg must give a write error, not kill sinew. */
void cli_ignore_sigpipe(void);

int cmd_info(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_bench(int argc, char **argv);
int cmd_muscle(int argc, char **argv);
int cmd_arm(int argc, char **argv);
int cmd_convert(int argc, char **argv);
int cmd_demo(int argc, char **argv);
int cmd_batch(int argc, char **argv);
int bench_eval(int argc, char **argv);
int bench_crowd(int argc, char **argv);

/* `sinew demo`: writes the demo content into dir (humanoid.dae, arm.dae and their muscle
 * files); prints each file when verbose. */
#define CLI_DEMO_HUMANOID "humanoid.dae"
int cli_demo_write(const char *dir, bool verbose, bool force); /* an exit code */
/* Removes a folder of plain files. */
bool cli_remove_tree(const char *dir);

int cmd_pose(int argc, char **argv);

#endif
