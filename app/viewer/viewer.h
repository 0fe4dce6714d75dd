/* sinew-view's shared state and the functions its files share (main.c: scene, timeline,
 * drawing, input, window; panels.c: hierarchy, display, log; settings.c: the settings file). */
#ifndef SINEW_VIEW_H
#define SINEW_VIEW_H

#include <epoxy/gl.h>
#include <gtk/gtk.h>

#include "crowd.h"
#include "scene.h"
#include "sinew/sinew.h"

#define FRAME_RATE 30.0 /* frame numbers and Left/Right steps when the clip's keys show no rate */
#define MAX_TICKS 400
#define RECORD_FPS 30.0 /* frames a second of F9's videos */

typedef enum play_mode { PLAY_LOOP, PLAY_ONCE, PLAY_PING_PONG, PLAY_ALL_CLIPS } play_mode;

/* Actions that have a key (settings file [keys]: action = key name as GDK names it). */
/* clang-format off */
typedef enum view_action {
    ACTION_PLAY, ACTION_PREVIOUS_FRAME, ACTION_NEXT_FRAME, ACTION_FIRST, ACTION_LAST, ACTION_FRAME_ALL,
    ACTION_CAMERA_MODE, ACTION_MATERIALS, ACTION_LIGHTING, ACTION_SHADING, ACTION_WIREFRAME, ACTION_SKELETON,
    ACTION_NORMALS, ACTION_GRID, ACTION_AXES, ACTION_JOINT_NAMES, ACTION_JOINT_AXES, ACTION_MUSCLES, ACTION_MESHES,
    ACTION_SKIN_METHOD, ACTION_CROWD, ACTION_PREVIOUS_KEY, ACTION_NEXT_KEY, ACTION_HELP, ACTION_SCREENSHOT,
    ACTION_VIEW_FRONT, ACTION_VIEW_SIDE, ACTION_VIEW_TOP, ACTION_ORTHOGRAPHIC, ACTION_RESET_VIEW, ACTION_PREVIOUS_FILE,
    ACTION_NEXT_FILE, ACTION_RECORD, ACTION_FOLLOW,
    ACTION_FORWARD, ACTION_BACK, ACTION_LEFT, ACTION_RIGHT, ACTION_DOWN, ACTION_UP, ACTION_COUNT
} view_action;
/* clang-format on */

typedef struct view_key {
    const char *action; /* name in the settings file */
    const char *option; /* render option it toggles, or NULL */
    const char *default_key;
    guint key; /* GDK key value in use */
} view_key;

/* Key maps (settings [view] key-map, --key-map): sinew's, or Blender's habits (Home frames
 * all, Shift+Left/Right first/last frame, middle-drag orbits, shift-middle pans, ctrl-middle
 * zooms; the left button does not move the view). */
typedef enum view_key_map { KEY_MAP_SINEW, KEY_MAP_BLENDER, KEY_MAP_COUNT } view_key_map;

/* The state of sinew-view, by concern: the clock (play), the camera and how files frame (look),
 * the pose operations of the Display panel and the command line (pose), F9's recording (rec);
 * then the document (the file, its scene, the load under way), the widgets and the settings. */

/* Playback: the clip's clock. */
typedef struct view_playback {
    double time, speed;
    play_mode mode;
    int direction; /* ping-pong: +1 or -1 */
    gint64 last_frame;
    gint64 last_tick; /* the frame clock's previous tick (0: none yet) */
    bool playing;
    double start_time; /* --time, applied to the file's clip once it is open; NAN: none */
    float *key_times;  /* the clip's distinct key times, sorted (the timeline's ticks, every one) */
    size_t key_time_count;
    double frame_rate; /* the clip's own (its usual key spacing), else FRAME_RATE */
} view_playback;

/* The camera and how the next file is framed. */
typedef struct view_look {
    sinew_camera camera;
    /* How much of the camera the next file's framing keeps: CAMERA_KEEP_GIVEN, what --camera gave
     * (a fly camera's position, an orbit's distance; as `sinew render`); CAMERA_KEEP_ALL, the
     * whole view (a reload). camera_keep is for the file being opened, keep_now for the one shown. */
    enum { CAMERA_FRAME, CAMERA_KEEP_GIVEN, CAMERA_KEEP_ALL } camera_keep, keep_now;
    app_camera_placement placement; /* --camera-position, --camera-focal-point: at the first framing */
    bool framed;
    /* Follow (key T, --track, settings [view] follow): the camera moves over the ground with the
     * clip's root, from where it was when the view was framed or Follow turned on */
    bool follow, follow_given;
    app_follow followed;
    GtkWidget *follow_check;
    bool held[ACTION_COUNT]; /* fly keys held down */
    double drag_x, drag_y;
} view_look;

/* The pose operations: the Display panel's blending (a second clip and its weight, root motion,
 * an IK target) over the command line's. */
typedef struct view_pose_ops {
    GtkWidget *blend_list, *blend_scale, *root_motion_check;
    int32_t blend_clip;  /* -1: none */
    double blend_weight; /* 0..1 */
    double fade_from;    /* a cross-fade under way: its start (monotonic seconds), else 0 */
    bool root_motion;
    bool ik_on; /* ctrl-drag set an IK target for ik_joint */
    bool ik_dragging;
    int32_t ik_joint;
    float ik_target[3];
    float *motion_path; /* the root-motion path: path_segments * 6 floats */
    uint32_t path_segments;
    app_pose_spec pose_ops; /* --blend, --additive, --crossfade, --ik, --root-motion */
} view_pose_ops;

/* F9: the clip recorded to FILE-NNN.mp4, a frame every 1/RECORD_FPS s of clip time. */
typedef struct view_recording {
    app_video video;
    bool recording, record_asked, title_due;
    const char *record_end; /* why the recording stops at the next tick, or NULL */
    char record_error[SINEW_ERROR_MESSAGE_SIZE];
    char video_path[4096];
    int video_width, video_height;
    unsigned char *video_frame;
    double recorded; /* seconds of clip time recorded */
} view_recording;

typedef struct viewer {
    view_playback play;
    view_look look;
    view_pose_ops pose;
    view_recording rec;
    GtkWidget *window, *area, *scale, *time_label, *play_button, *clip_list, *status, *error_bar, *error_label;
    GtkWidget *node_list, *node_search, *transform_label, *heatmap_check, *log_view, *camera_list;
    GtkWidget *option_checks[32]; /* by index into sinew_render_option_names() */
    bool overridden[32];          /* set on the command line and not changed since: not saved */
    GtkWidget *panels;            /* the side panel's notebook */
    GtkWidget *shading_list;
    GtkWidget *skin_method_list; /* as the file says | linear blend | dual quaternion */
    /* the Shape keys panel: a row a morph channel (a check: set by hand; a slider: its weight) */
    GtkWidget *shape_box;
    GtkWidget **shape_checks, **shape_scales;
    uint32_t shape_count;
    const char *screenshot, *select, *heatmap;
    const char *window_shot; /* --screenshot-window: the whole window (panels too), once open and drawn */
    int frames_drawn;
    char shot_path[4096];       /* F12: the numbered file being written (screenshot points here) */
    const char *screenshot_dir; /* --screenshot-dir: where F12 writes; NULL: Pictures, else home */
    const char *press;          /* --press: key names pressed once the file is open, comma-separated */
    char *sliders;              /* $SINEW_VIEW_SLIDERS: Shape keys sliders set once the file is open (tests) */
    const char *up;             /* --up [+|-]x|y|z: the axis shown up */
    view_key_map key_map;
    GtkWidget *key_map_list;
    /* anti-aliasing: the frame is drawn into a multisampled framebuffer of `samples` samples (1:
     * straight into the GL area's) and resolved into the GL area's (settings [view] samples, --samples) */
    int samples;
    GLuint msaa_fbo, msaa_color, msaa_depth;
    int msaa_width, msaa_height, msaa_samples;
    bool msaa_refused; /* GL refused multisampling: the frames are smoothed by FXAA instead */
    char *hdri;        /* --hdri, settings [view] hdri: the environment file; NULL: the studio */
    bool hdri_given, samples_given, key_map_given; /* on the command line: not saved */
    const char *anim, *name_map; /* --anim OTHER (--name-map M.json): its clips on every file opened */
    GtkWidget *help;             /* the key cheat sheet over the view (H) */
    GtkWidget *frame_spin;       /* the frame number, typed or stepped */
    char *path;                  /* the file shown (NULL: the demo): next/previous file, --watch */
    bool watch;                  /* --watch: reload the file when it changes on disk */
    GFileMonitor *monitor;
    guint reload_timer;
    bool quit_after_screenshot;
    int32_t reload_clip;  /* --watch: the shown clip's index for the reload being started, else -1 */
    bool play_after_open; /* another file opened by hand: it plays once open */
    app_scene scene;      /* the model shown, its clip, muscles and pose */
    sinew_renderer *renderer;
    /* the crowd toggle (key C, --crowd N): crowd_size characters of the scene's model */
    uint32_t crowd_size;
    bool crowd_on;
    app_crowd crowd; /* built for crowd.model; rebuilt when the scene's model changes */
    sinew_jobs *jobs;
    GtkWidget *crowd_check;
    struct view_load *load; /* a file being opened, or NULL */
    GtkWidget *load_bar, *load_label, *load_progress;
    guint load_timer;
    app_import_options import;    /* --import-timeout, --import-memory */
    bool *hidden;                 /* instance_count flags */
    bool skeleton_shown_for_file; /* the skeleton switch was turned on for a file without meshes */
    bool closing;                 /* the window is being closed: widgets are going away */
    double quit_after;            /* --quit-after: seconds, 0 for never */
    bool status_due;              /* the status bar's figures changed in a draw: shown at the next tick */
    uint32_t renderer_warnings;   /* the renderer's warnings logged so far (0 for each new renderer) */
    int32_t selected;             /* node, -1 for none */
    sinew_render_options options;
    bool updating;    /* widgets are being set from the state: their signals change nothing */
    bool placeholder; /* the demo opening as the file's stand-in: the command line's pose options wait */
    gint64 fps_since;
    int fps_frames;
    double fps;
    int width, height;
    char *last_folder;
    char *recent[10]; /* files opened, newest first (settings [files] recent) */
    GMenu *recent_menu;
    char *settings_path;
    view_key keys[ACTION_COUNT];
    int exit_code;
} viewer;

/* main.c */
void view_show_error(viewer *v, const char *message);
void view_redraw(viewer *v);
bool view_pose(viewer *v);
void view_recent_changed(viewer *v); /* rebuilds the Recent menu */

double view_duration(const viewer *v); /* of the clip playing; 0 for the rest pose */
void view_toggle_crowd(viewer *v, bool on);
void view_set_follow(viewer *v, bool on); /* Follow: from where the clip's root is now */
double view_frame_rate(const viewer *v);  /* of the clip: frame numbers and Left/Right steps */
void view_update_timeline(viewer *v);     /* the scrub bar's range and key ticks */
void view_show_time(viewer *v);

/* open.c */
/* Plays clip `index` (-1: the rest pose) from its start; the error shows on failure. */
bool view_use_clip(viewer *v, int32_t index);
/* A renderer for `scene` in the area's context: false (error shown) when GL refuses the
 * model; true with *out NULL when there is no context yet. */
bool view_make_renderer(viewer *v, const app_scene *scene, sinew_renderer **out);
/* Opens a built-in model (APP_BUILTIN_DEMO) at once; the error shows on failure. */
bool view_open_now(viewer *v, const char *path, const char *clip_name, bool anim);
typedef struct view_load view_load;
/* Opens a file on a worker thread (the scene stays until the new one is ready; a failure
 * shows its error); a newer open supersedes one under way. */
void view_open_file(viewer *v, const char *path, const char *clip_name);
/* Opens another file by hand (the dialog, a drop, Page Up/Down, Recent): from time 0, playing,
 * framed on its own, as f3d and Blender do. */
void view_open_other(viewer *v, const char *path);
void view_set_playing(viewer *v, bool playing);
/* Asks the open under way to stop; `wait`: also waits for its thread and drops it (leaving). */
void view_cancel_open(viewer *v, bool wait);
/* The file beside the current one (by name, formats sinew reads), `step` +1 or -1, wrapping; NULL when none. */
char *view_neighbour_file(const char *path, int step);

/* panels.c */
GtkWidget *panels_create(viewer *v);
void panels_model_changed(viewer *v);   /* rebuilds the hierarchy and the log */
void panels_options_changed(viewer *v); /* the display checks follow the options */
void panels_frame_drawn(viewer *v);     /* the selected node's transforms */
void panels_log(viewer *v, const char *line);
void panels_select(viewer *v, int32_t node);
void panels_clips_changed(viewer *v);   /* the blend list follows the model's clips */
void panels_weights_changed(viewer *v); /* the Shape keys sliders follow the pose's weights */
/* Sets a Shape keys slider as a hand would (check on, the value): "CHANNEL=W", a channel by name
 * or index; the SINEW_VIEW_SLIDERS test hook (comma-separated). False when none is named so. */
bool panels_set_slider(viewer *v, const char *text);

/* main.c: the Display panel's blending, root motion and IK target onto the scene (with the
 * command line's --blend, ... as the base); the error shows when the model refuses them. */
void view_apply_pose_ops(viewer *v);

/* settings.c */
/* Index of a display option in sinew_render_option_names(), or -1. */
int settings_option_index(const char *name);
/* The user changed option `name` in the window: it is saved at exit again. */
void settings_option_changed(viewer *v, const char *name);
void settings_defaults(viewer *v);
/* The key maps' names in settings and on the command line. */
extern const char *const KEY_MAP_NAMES[KEY_MAP_COUNT];
/* Switches the key map: the keys not rebound by the user follow the new map's defaults. */
void settings_set_key_map(viewer *v, view_key_map map);
/* Reads the settings file (missing: defaults); a bad line goes to the log on stderr. */
void settings_load(viewer *v);
bool settings_save(viewer *v);
/* The action a key press means, or -1. */
int settings_action_for_key(const viewer *v, guint key);

#endif
