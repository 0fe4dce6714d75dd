/* Shared pieces of the `sinew` command: exit codes, model loading, posing helpers. */
#ifndef SINEW_CLI_H
#define SINEW_CLI_H

#include <stdio.h>

#include "app.h"
#include "sinew/sinew.h"

/* One exit status per kind of fault, in every command (README, sinew.1):
 * 1: the command line is wrong (unknown option, malformed or out-of-range value);
 * 2: an input is unreadable or malformed, or lacks what was named (a clip, a joint);
 * 3: this machine lacks something the command needs (an OpenGL 3.3 context, ffmpeg);
 * 4: an output cannot be written (no space, no permission, it is an input, it exists). */
enum { EXIT_OK = 0, EXIT_USAGE = 1, EXIT_BAD_INPUT = 2, EXIT_UNAVAILABLE = 3, EXIT_OUTPUT = 4 };

/* Prints "sinew: <message>" to stderr. */
void cli_error(const char *format, ...) __attribute__((format(printf, 1, 2)));

/* sinew's data folder ($SINEW_DATA, else data/ beside the program, else share/sinew relative
 * to it): buf = folder/name. */
const char *cli_data_path(const char *name, char *buf, size_t size);

/* The seed's arm (sinew/arm.h) with the distances from data/arm.muscles.json. */
typedef struct cli_arm_spec {
    double angle;              /* elbow angle, radians */
    double length;             /* > 0: the muscle length instead of the angle */
    double flex_from, flex_to; /* a "flex" clip between these angles, both 0: none */
    sinew_transform place;     /* rotate, move, scale the whole arm */
} cli_arm_spec;
sinew_model *cli_arm_model(const cli_arm_spec *spec);

#define CLI_BUILTIN_ARM "builtin:arm"

/* Loads a model file (any format Assimp reads), or the built-in arm for "builtin:arm"; prints
 * the error and returns NULL on failure. */
sinew_model *cli_load_model(const char *path);

/* Resolves --clip NAME|INDEX; NULL spec picks clip 0 (or none when the model has none).
 * Returns false (after printing why) when the clip does not exist. */
bool cli_pick_clip(const sinew_model *model, const char *spec, int32_t *clip);

/* The double nearest the shortest decimal that reads back as `value`, so JSON shows
 * 0.1 rather than 0.100000001490116 for a float 0.1; tiny values below 1e-12 become 0. */
double cli_json_float(float value);

/* Option values, strictly (all of the text); each prints "COMMAND: bad OPTION ..." and
 * returns false otherwise. Sizes are WIDTHxHEIGHT, each 1..16384. */
bool cli_parse_count(const char *command, const char *option, const char *text, long lo, long hi, long *out);
bool cli_parse_size(const char *command, const char *text, int *width, int *height);

/* Vertices drawn: every mesh instance's vertices (0 for a skeleton-only file). */
uint32_t cli_vertex_count(const sinew_model *model);

/* True when `arg` is --help or -h. */
bool cli_is_help(const char *arg);

/* A posed model: locals, world matrices, scratch for one skin palette. */
typedef struct cli_pose {
    const sinew_model *model;
    sinew_transform *locals;
    sinew_mat4 *worlds;
    sinew_mat4 *palette;
    void *context_memory;
    sinew_sample_context *context;
} cli_pose;

bool cli_pose_init(cli_pose *pose, const sinew_model *model, const sinew_clip *clip);
bool cli_pose_at(cli_pose *pose, const sinew_clip *clip, float time, sinew_wrap wrap);
void cli_pose_free(cli_pose *pose);

/* A model posed and drawn off-screen: what `render` and `bench render` share. */
typedef struct cli_scene_desc {
    const char *path, *clip, *camera, *select, *heatmap;
    sinew_model *model;  /* instead of loading path: a model the scene takes over */
    const char *muscles; /* NULL: none; "": the file beside the model; else a muscle file */
    double muscle_scale; /* sinew_muscle_rig_set_scale(); 0 = 1 */
    int width, height, samples;
    bool loop, skeleton_set;
    uint32_t gpu_joint_limit;
    sinew_render_options options;
} cli_scene_desc;

typedef struct cli_scene {
    sinew_model *model;
    const sinew_clip *clip;
    cli_pose pose;
    sinew_headless *headless;
    sinew_renderer *renderer;
    sinew_camera camera;
    bool frame_all; /* the camera spec left the distance to framing */
    bool tracking;  /* track_centre holds the last tracked centre */
    float track_centre[3];
    sinew_render_options frame_options;
    sinew_wrap wrap;
    int width, height;
    uint8_t *pixels;                 /* width * height * 4, top row first */
    sinew_muscle_set *owned_muscles; /* read from a file; NULL for a model's own */
    const sinew_muscle_set *muscle_set;
    sinew_muscle_rig *muscle_rig;
    sinew_muscle_pose *muscle_poses;
    uint32_t muscle_count;
    const char *gl_name;
} cli_scene;

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
/* Reads the frame into scene->pixels. */
bool cli_scene_read(cli_scene *scene);
void cli_scene_close(cli_scene *scene);

/* Muscles for a model: `spec` is a muscle file, or "" for the model's own (a .sinew file
 * converted with muscles) or else the one beside the model (MODEL.muscles.json). Prints the error and returns NULL on
 * failure. */
sinew_muscle_rig *cli_load_muscles(const sinew_model *model, const char *spec);
/* The same, keeping the muscle set too (the renderer sizes its buffers from it). */
sinew_muscle_rig *cli_load_muscle_set(const sinew_model *model, const char *spec, sinew_muscle_set **owned,
                                      const sinew_muscle_set **set);

/* Takes --muscles [FILE.json] at argv[*i]: the file when the next argument ends in .json,
 * else "" (the file beside the model). */
const char *cli_muscles_arg(int argc, char **argv, int *i);

/* One muscle of a rig as JSON: {"name", "length", "rest_length", "delta", "volume",
 * "rest_volume", "in_range", "origin", "insertion", "radii"}. */
struct cJSON;
struct cJSON *cli_muscle_pose_json(const sinew_muscle_pose *pose);

/* PNG output through stb_image_write and app_output (whole or not at all); prints the error and
 * returns false on failure. */
bool cli_write_png(const char *path, const uint8_t *rgba, int width, int height);

/* Video output: raw RGBA frames piped into the ffmpeg program. */
typedef struct cli_video {
    const char *path;
    int fd;
    int pid;
    size_t frame_bytes;
    bool unavailable;  /* open failed because ffmpeg is not installed */
    bool write_failed; /* the output could not be written (exit EXIT_OUTPUT) */
    app_output output; /* the temporary file ffmpeg writes */
} cli_video;

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
int bench_eval(int argc, char **argv);

/* `sinew demo`: writes the demo content into dir (humanoid.dae, arm.dae and their muscle
 * files); prints each file when verbose. */
#define CLI_DEMO_HUMANOID "humanoid.dae"
int cli_demo_write(const char *dir, bool verbose, bool force); /* an exit code */
/* Removes a folder of plain files. */
bool cli_remove_tree(const char *dir);

int cmd_pose(int argc, char **argv);

#endif
