/* app/common/scene.h: the scene both apps show, `sinew` (render, pose, bench) and sinew-view.
 *
 * What: a model (a file, the built-in demo humanoid or the seed's arm), the clip chosen by name
 * or index, its muscles by one rule, and one way to pose it (a sinew_player: world matrices,
 * then the muscle rig). Framing over a time range and the sinew_frame to draw.
 * What not: no OpenGL context and no renderer (the CLI draws off-screen, the viewer in its
 * window: each makes its renderer for scene->model in its own context); no printing.
 * Errors come back in a sinew_error; notes for a log (muscles attached, a muscle file beside
 * the model that does not fit) in scene->notes.
 * Threads: app_scene_open() touches nothing global; the viewer runs it on a worker thread and
 * hands the finished scene to the window. */
#ifndef SINEW_APP_SCENE_H
#define SINEW_APP_SCENE_H

#include "app.h"

#define APP_BUILTIN_ARM "builtin:arm"     /* the seed's arm, flexing, with its biceps */
#define APP_BUILTIN_DEMO "builtin:demo"   /* the demo humanoid, with its biceps */
#define APP_BUILTIN_MORPH "builtin:morph" /* the synthetic 64-joint tube with 50 bulges, 5 animated */

/* The import helper's limits, as both apps take them on their command lines:
 * --import-timeout SECONDS (0: none) and --import-memory MIB (0: none); absent: the library's
 * defaults (120 s; 256 MiB and 64 times the file's size, at most half the memory). */
typedef struct app_import_options {
    double timeout;        /* sinew_import_desc.timeout */
    uint64_t memory_limit; /* sinew_import_desc.memory_limit */
    bool warm_heap;        /* a program that imports a file and exits (the CLI): app_warm_heap first */
} app_import_options;
/* Before an in-process import of `path` (FBX, glTF, COLLADA, IQM, BVH) of 64 KiB or more: takes a
 * block of twice its size (2 to 24 MiB, whole 2 MB pages) from the heap, starting at a 2 MB
 * boundary, has it in huge pages and filled in, and frees it, so that the import's small blocks
 * (libxml2's tree, a glTF's channels) come from the heap's top already faulted in, a fault a 2 MB
 * page instead of a 4 KiB one. A .sinew file is left alone (the library fills in the pages of
 * the buffer it reads one into, and a 2 MB page warmed beside it cost more than it saved). Only
 * for a process whose heap keeps what is
 * freed (the CLI sets M_TRIM_THRESHOLD and M_MMAP_THRESHOLD above that size) and that exits soon
 * after: it changes the program's heap, which the library leaves alone, and keeps up to 2 MB of
 * untouched address space below the block. */
void app_warm_heap(const char *path);
/* Reads one of them at argv[i]: the arguments used (2), 0 when argv[i] is not one, -1 with the
 * error filled for a missing or bad value. */
int app_import_option_parse(app_import_options *options, int argc, char *const *argv, int i, sinew_error *error);
#define APP_IMPORT_OPTIONS_HELP                                                                                        \
    "  --import-timeout S    stop reading a file after S seconds (default 120; 0: never)\n"                            \
    "  --import-memory MIB   stop reading a file that needs more than MIB MiB (default: 256 MiB and 64 times\n"        \
    "                        the file's size, at most half the memory; 0: no limit)\n"

/* Which muscles a scene attaches. A model's own are a .sinew file's stored muscles, or the
 * built-in models' biceps. */
typedef enum app_muscle_mode {
    APP_MUSCLES_NONE = 0,
    /* the model's own, else MODEL.muscles.json beside the file when there is one; one that
     * cannot be read or does not fit the model is a note, not an error (the viewer) */
    APP_MUSCLES_IF_ANY,
    /* the same, but one that is there and cannot be read or does not fit is an error (sinew
     * convert: what it stores must be what the user has) */
    APP_MUSCLES_IF_PRESENT,
    /* muscle_path, else the model's own, else the file beside it; missing, unreadable or not
     * fitting is an error (sinew --muscles) */
    APP_MUSCLES_REQUIRED
} app_muscle_mode;

typedef struct app_scene_desc {
    const char *path;     /* a model file, APP_BUILTIN_ARM or APP_BUILTIN_DEMO (NULL: the demo) */
    sinew_model *model;   /* instead of path: a model the scene takes over (freed on failure too) */
    const char *clip;     /* a clip's name or index; NULL: the first (none: the rest pose) */
    const char *anim;     /* --anim: another file whose clips are retargeted onto the model (first), or NULL */
    const char *name_map; /* --name-map: JSON {"source joint": "model joint"} for --anim, or NULL */
    app_muscle_mode muscles;
    const char *muscle_path; /* APP_MUSCLES_REQUIRED: this file instead of the model's own */
    double muscle_scale;     /* sinew_muscle_rig_set_scale(); 0: 1 */
    /* importing a file (sinew/import.h): */
    bool isolate, assimp; /* also $SINEW_IMPORT_ISOLATE and $SINEW_IMPORTER=assimp */
    int stderr_fd;
    app_import_options import;
    bool (*progress)(float fraction, void *user); /* sinew_import_desc.progress: false cancels */
    void *progress_user;
    /* how it is shown and posed once open (the viewer sets its own later): */
    const char *up;                   /* app_scene_set_up_axis(); NULL: as the file says */
    const struct app_pose_spec *pose; /* app_scene_set_pose_ops(); NULL: the clip plays alone */
} app_scene_desc;

#define APP_SCENE_NOTES 4
#define APP_MAX_LAYERS 8
#define APP_MAX_IK 4
#define APP_MAX_MORPHS 32

/* What the command lines ask of a pose beyond playing one clip (sinew/blend.h), as written:
 * --blend CLIP:W,CLIP:W,...  --additive CLIP:W  --crossfade A,B,SECONDS  --ik JOINT:X,Y,Z
 * (repeatable)  --root-motion. */
typedef struct app_pose_spec app_pose_spec;
struct app_pose_spec {
    const char *blend, *additive, *crossfade;
    const char *ik[APP_MAX_IK];
    int ik_count;
    bool root_motion;
    const char *morph[APP_MAX_MORPHS]; /* --morph MESH:TARGET=W (repeatable) */
    int morph_count;
};

/* Reads one of those options at argv[i]: the arguments used, 0 when it is not one. */
int app_pose_option_parse(app_pose_spec *spec, int argc, char *const *argv, int i);
#define APP_POSE_OPTIONS_HELP                                                                                          \
    "  --blend CLIP:W,CLIP:W  blends clips with weights (the rest pose fills weight under 0.1); CLIP:W@JOINT\n"        \
    "                         moves only JOINT and the nodes below it (a mask: an upper-body wave)\n"                  \
    "  --additive CLIP:W      adds CLIP's motion from its first frame, times W, on top (@JOINT as --blend)\n"          \
    "  --crossfade A,B,T      fades from clip A to clip B over T seconds from time 0 (phases synced with --loop)\n"    \
    "  --ik JOINT:X,Y,Z       two-bone IK: JOINT (with its parent and grandparent) reaches X,Y,Z (world), bending\n"   \
    "                         the way it already bends (repeatable, up to 4)\n"                                        \
    "  --root-motion          takes the root's horizontal motion and yaw out: the character stays in place\n"          \
    "  --morph MESH:TARGET=W  sets a morph target's weight by hand, over what the clip gives (also TARGET=W or\n"      \
    "                         CHANNEL=W; names or indices as `sinew info` lists them; repeatable)\n"

typedef struct app_layer {
    int32_t clip;
    float weight;
    int32_t mask_joint; /* >= 0: the layer moves only this joint and the nodes below it */
} app_layer;

/* The pose operations a scene carries out (app_scene_set_pose_ops), resolved against its model:
 * what the scene's sinew_character is made of, with the scene's clip. */
typedef struct app_pose_ops {
    app_layer blend[APP_MAX_LAYERS]; /* none: the scene's clip alone (or fading into fade_to) */
    uint32_t blend_count;
    app_layer additive[APP_MAX_LAYERS];
    uint32_t additive_count;
    int32_t fade_to; /* < 0: no cross-fade */
    float fade_seconds;
    uint32_t ik_end[APP_MAX_IK];
    float ik_target[APP_MAX_IK][3];
    uint32_t ik_count;
    bool root_motion;
} app_pose_ops;

typedef struct app_scene {
    sinew_model *model;
    int32_t clip_index; /* -1: the rest pose */
    const sinew_clip *clip;
    sinew_mat4 *worlds; /* model->node_count: the pose of the last app_scene_pose() */
    double posed_at;    /* the time `worlds` hold; NAN: none yet */
    sinew_wrap posed_wrap;
    sinew_muscle_set *owned_muscles; /* read from a file; NULL for the model's own */
    const sinew_muscle_set *muscle_set;
    sinew_muscle_rig *muscle_rig;
    sinew_muscle_pose *muscle_poses; /* muscle_count: solved with the pose */
    uint32_t muscle_count;
    char notes[APP_SCENE_NOTES][SINEW_ERROR_MESSAGE_SIZE + 96];
    int note_count;
    bool z_up;        /* another of the file's axes than +Y is shown up (app_scene_set_up_axis) */
    app_pose_ops ops; /* blending, IK, root motion (app_scene_set_pose_ops) */
    /* how the scene poses: one sinew_character of the clip and the operations, made again when
     * either changes; the layouts of the model's clips (index + 1; 0: the rest pose) as used */
    sinew_character *character;
    void *character_memory;
    sinew_clip_layout **layouts;
    float *masks;    /* node_count a layer: the layers' masks */
    sinew_mat4 root; /* what places the roots: identity, or Z up turned to Y up */
    /* morph channels (model->morph_channel_count): the weights of the last pose (the clip's,
     * blended as the pose is, then the overrides), the overrides (NAN: none) */
    float *weights, *overrides;
    float cache_time; /* the file's timeline at the last pose, for vertex caches */
} app_scene;

/* The model desc asks for: desc->path read (import options from desc), or a built-in one. */
sinew_result app_load_model(const app_scene_desc *desc, sinew_model **out, sinew_error *error);

/* Loads (or takes desc->model), picks the clip, attaches muscles, turns it up as desc->up says
 * and poses with desc->pose. Errors: the import's; SINEW_ERROR_DATA for a clip the file lacks
 * ("no clip ..."); the muscle file's with APP_MUSCLES_REQUIRED; SINEW_ERROR_INVALID_ARGUMENT
 * for a pose spec the model refuses. On failure the scene is empty (nothing to close). */
sinew_result app_scene_open(app_scene *scene, const app_scene_desc *desc, sinew_error *error);
/* Which of the file's axes is shown up, as f3d's --up: [+|-]x, y or z, case ignored ("y", as
 * sinew reads every file: the importers turn what the file says to Y up; "z" for files that say
 * nothing and are modelled Z up: a turn of -90 degrees about X). app_up_axis() checks a name
 * and gives the turn (root may be NULL). False for another name. */
bool app_up_axis(const char *axis, sinew_mat4 *root);
bool app_scene_set_up_axis(app_scene *scene, const char *axis);
/* Resolves the spec's clips and joints against the scene's model (messages name the option
 * and list what the model has) and poses with them from now on; the spec all NULL: plain play. */
sinew_result app_scene_set_pose_ops(app_scene *scene, const app_pose_spec *spec, sinew_error *error);
/* Moves IK chain `chain` (the spec's --ik, in order) to `target` without making the pose again:
 * the viewer's drag. False for a chain the scene lacks. */
bool app_scene_set_ik_target(app_scene *scene, uint32_t chain, const float target[3]);
/* What --root-motion took out at the last pose (sinew_character_root_motion()); NULL without it. */
const sinew_root_motion *app_scene_root_motion(const app_scene *scene, float translation[3], float *yaw);
/* Plays clip `index` (-1: the rest pose) from its start. On failure the clip stays. */
sinew_result app_scene_use_clip(app_scene *scene, int32_t index, sinew_error *error);
/* Poses at `time` (world matrices, then the muscles); once per time and wrap. */
sinew_result app_scene_pose(app_scene *scene, double time, sinew_wrap wrap, sinew_error *error);
/* Sets channel `channel`'s weight by hand (NAN: back to the clip's); takes effect at the
 * next pose. False for a channel the model lacks. */
bool app_scene_override_weight(app_scene *scene, uint32_t channel, float weight);
/* "MESH:TARGET=W" (or "TARGET=W", or "CHANNEL=W"; a target or channel by name or index) into
 * an override, as --morph gives it; an error lists what the model has. */
sinew_result app_scene_parse_morph(app_scene *scene, const char *text, sinew_error *error);
/* The frame to draw of the last pose. */
sinew_frame app_scene_frame(const app_scene *scene, const sinew_camera *camera, const sinew_render_options *options,
                            int width, int height);
/* The union of the posed bounds at `samples` evenly spaced times in [from, to] (one when
 * from == to); false when nothing has extent (lo/hi then hold -1..1). Leaves the scene posed at `to`. */
bool app_scene_bounds(app_scene *scene, sinew_renderer *renderer, double from, double to, int samples, sinew_wrap wrap,
                      float lo[3], float hi[3]);
/* The camera following the model (`sinew render --track`, sinew-view's Follow): the orbit camera's
 * target, or the fly camera's position, moves over the ground as far as the clip's root moved since
 * it was last noted. The root is the node --root-motion takes (the topmost node the clip
 * translates, a skin's joint where there is one: a capture's hips), so that the camera does not
 * sway with the arms and legs, stays still for a clip that goes nowhere, and lets a jump go up
 * in the view. With `camera` NULL, the first time, or a new clip, the root is only noted; a clip
 * that translates no node moves nothing. Leaves the scene posed at `time`. */
typedef struct app_follow {
    bool noted;
    const sinew_clip *clip; /* the clip `node` is the root of */
    int32_t node;           /* -1: none */
    float at[3];            /* where it was (world) */
} app_follow;
void app_scene_follow(app_scene *scene, double time, sinew_wrap wrap, app_follow *follow, sinew_camera *camera);
/* Where the ground grid goes: the lowest posed point over the whole clip (the rest pose
 * without one), `samples` times; 0 when nothing has extent. Leaves the scene posed at the clip's end. */
float app_scene_ground(app_scene *scene, sinew_renderer *renderer, int samples);
void app_scene_close(app_scene *scene);

/* What the scene holds, for a status line: every mesh instance's vertices (0 for a skeleton
 * only), nodes that are joints. */
uint32_t app_vertex_count(const sinew_model *model);
uint32_t app_joint_count(const sinew_model *model);

/* The nodes in tree order (each node, then its children's subtrees in index order; roots in
 * index order), as a hierarchy panel lists them: order[0 .. node_count), depth[node] its level
 * (roots 0). Returns how many were written (node_count). */
uint32_t app_tree_order(const sinew_model *model, uint32_t *order, uint32_t *depth);
/* Edits (insert, delete, change; case ignored) from a to b; 99 for names over 63 bytes. */
int app_edit_distance(const char *a, const char *b);

/* The clip `text` names (sinew_model_pick_clip()); APP_CLIP_NONE for "none" (the rest pose;
 * unless a clip is named so); APP_CLIP_ERROR with "no clip ..." in the error, which lists the
 * clips by index and name and suggests the nearest name to a misspelt one. */
#define APP_CLIP_NONE (-1)
#define APP_CLIP_ERROR (-2)
int32_t app_pick_clip(const sinew_model *model, const char *text, sinew_error *error);

/* sinew's data folder ($SINEW_DATA, else data/ beside the program, else share/sinew relative
 * to it): buf = folder/name. */
const char *app_data_path(const char *name, char *buf, size_t size);

/* The seed's arm (sinew/arm.h) with the distances and the biceps of data/arm.muscles.json. */
typedef struct app_arm_spec {
    double angle;              /* elbow angle, radians */
    double length;             /* > 0: the muscle length instead of the angle */
    double flex_from, flex_to; /* a "flex" clip between these angles, both 0: none */
    sinew_transform place;     /* rotate, move, scale the whole arm */
} app_arm_spec;
sinew_result app_arm_model(const app_arm_spec *spec, sinew_model **out, sinew_error *error);

#endif
