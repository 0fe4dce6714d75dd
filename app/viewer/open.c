/* sinew-view: the scene shown and how files are opened: the built-in demo at once, a file on a
 * worker thread (app_scene_open) while the window keeps its scene, with a progress bar and
 * Cancel; the new scene replaces the old one only when it is ready and the renderer takes it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>
#include <gtk/gtk.h>

#include "viewer.h"

double view_duration(const viewer *v)
{
    return v->scene.clip ? v->scene.clip->duration : 0.0;
}

/* Plays clip `index` (-1: the rest pose) of the current model from its start. */
bool view_use_clip(viewer *v, int32_t index)
{
    sinew_error error = {0};
    if (app_scene_use_clip(&v->scene, index, &error) != SINEW_OK) {
        view_show_error(v, error.message);
        return false;
    }
    app_crowd_close(&v->crowd);                                          /* remade for the new clip when shown */
    if (v->pose.blend_clip >= 0 || v->pose.root_motion || v->pose.ik_on) /* the panel's blending is of the clip shown */
        view_apply_pose_ops(v);
    if (v->play.time > view_duration(v))
        v->play.time = 0.0;
    view_update_timeline(v);
    return true;
}

/* A renderer for `scene` in the area's context: false (error shown) when GL refuses the
 * model; true with *out NULL when there is no context yet (on_realize makes it). */
bool view_make_renderer(viewer *v, const app_scene *scene, sinew_renderer **out)
{
    *out = NULL;
    if (!v->area || !gtk_widget_get_realized(v->area))
        return true;
    gtk_gl_area_make_current(GTK_GL_AREA(v->area));
    if (gtk_gl_area_get_error(GTK_GL_AREA(v->area)))
        return true;
    sinew_error error = {0};
    sinew_renderer_desc desc = {.model = scene->model, .muscles = scene->muscle_set};
    if (sinew_renderer_create(&desc, out, &error) != SINEW_OK) {
        view_show_error(v, error.message);
        return false;
    }
    if (v->hdri && sinew_renderer_set_environment(*out, v->hdri, &error) != SINEW_OK)
        view_show_error(v, error.message); /* the studio lights the model instead */
    return true;
}

static void resolve_joints(viewer *v)
{
    int32_t node = v->select ? sinew_model_find_joint(v->scene.model, v->select) : -1;
    if (v->select)
        v->options.select_joint = node >= 0, v->options.selected_joint = node >= 0 ? (uint32_t)node : 0;
    node = v->heatmap ? sinew_model_find_joint(v->scene.model, v->heatmap) : -1;
    if (v->heatmap)
        v->options.heatmap = node >= 0, v->options.heatmap_joint = node >= 0 ? (uint32_t)node : 0;
}

/* Makes `incoming` the scene (the viewer owns it from here, whatever happens; `incoming` is
 * left empty). When the renderer refuses the model, the error shows and the old scene stays. */
static bool adopt_scene(viewer *v, app_scene *incoming)
{
    const sinew_model *model = incoming->model;
    bool *hidden = calloc(model->instance_count + 1, sizeof *hidden);
    sinew_renderer *renderer = NULL;
    if (!hidden || !view_make_renderer(v, incoming, &renderer)) {
        if (!hidden)
            view_show_error(v, "out of memory");
        free(hidden);
        app_scene_close(incoming);
        return false;
    }
    if (renderer) /* make_renderer left the area's context current */
        sinew_renderer_free(v->renderer);
    v->renderer = renderer;
    v->renderer_warnings = 0;
    app_crowd_close(&v->crowd); /* of the old model: remade for the new one when shown */
    app_scene_close(&v->scene);
    v->scene = *incoming;
    if (v->up)
        app_scene_set_up_axis(&v->scene, v->up);
    memset(incoming, 0, sizeof *incoming); /* the viewer's now */
    v->pose.blend_clip = -1;               /* the panel's blending starts over with each model */
    v->pose.ik_on = false;
    panels_clips_changed(v);
    if (!v->placeholder) /* the command line's --blend, --morph, ... are the file's, not the demo's */
        view_apply_pose_ops(v);
    free(v->hidden);
    v->hidden = hidden;
    v->options.hidden_instances = v->hidden;
    for (int i = 0; i < v->scene.note_count; i++)
        panels_log(v, v->scene.notes[i]);
    if (v->play.time > view_duration(v))
        v->play.time = 0.0;
    resolve_joints(v);
    /* Nothing to see but a skeleton: show it, for this file only (not saved in the settings,
     * and given back when a file with meshes comes) */
    int skeleton = settings_option_index("skeleton");
    if (app_vertex_count(model) == 0 && !v->options.skeleton) {
        v->options.skeleton = true;
        v->skeleton_shown_for_file = true;
        if (skeleton >= 0)
            v->overridden[skeleton] = true;
    } else if (app_vertex_count(model) > 0 && v->skeleton_shown_for_file) {
        v->options.skeleton = false;
        v->skeleton_shown_for_file = false;
        if (skeleton >= 0)
            v->overridden[skeleton] = false;
    }
    v->look.framed = false; /* with what the camera keeps */
    v->look.keep_now = v->look.camera_keep;
    v->look.camera_keep = CAMERA_FRAME;
    if (v->window) {
        char title[600];
        snprintf(title, sizeof title, "%s — sinew", model->source);
        gtk_window_set_title(GTK_WINDOW(v->window), title);
        GtkStringList *names = gtk_string_list_new(NULL);
        for (uint32_t i = 0; i < model->clip_count; i++)
            gtk_string_list_append(names, model->clips[i].name);
        gtk_string_list_append(names, model->clip_count ? "(rest pose)" : "(no clips: rest pose)");
        v->updating = true;
        gtk_drop_down_set_model(GTK_DROP_DOWN(v->clip_list), G_LIST_MODEL(names));
        gtk_drop_down_set_selected(GTK_DROP_DOWN(v->clip_list),
                                   v->scene.clip_index >= 0 ? (guint)v->scene.clip_index : model->clip_count);
        v->updating = false;
        g_object_unref(names);
        view_update_timeline(v);
        view_show_time(v);
        panels_model_changed(v);
        panels_options_changed(v);
        v->status_due = true; /* the status bar's vertex and joint counts are the new model's */
        /* --select / --heatmap name joints of every model opened; the hierarchy shows the one
         * selected, or else the heat map's joint (its row selected, its transforms shown) */
        int32_t select = v->select ? sinew_model_find_joint(model, v->select) : -1;
        if (select < 0 && v->heatmap) {
            select = sinew_model_find_joint(model, v->heatmap);
            if (select >= 0 && v->heatmap_check)
                gtk_check_button_set_active(GTK_CHECK_BUTTON(v->heatmap_check), true);
        }
        if (select >= 0)
            panels_select(v, select);
        resolve_joints(v);
        gtk_gl_area_queue_render(GTK_GL_AREA(v->area));
    }
    return true;
}

/* Opens a built-in model at once (the demo at start), with --anim's clips when `anim`; the
 * error shows on failure, and when the clips are what failed the model opens without them. */
bool view_open_now(viewer *v, const char *path, const char *clip_name, bool anim)
{
    app_scene scene;
    sinew_error error = {0};
    app_scene_desc desc = {.path = path,
                           .clip = clip_name,
                           .muscles = APP_MUSCLES_IF_ANY,
                           .anim = anim ? v->anim : NULL,
                           .name_map = v->name_map};
    sinew_result r = app_scene_open(&scene, &desc, &error);
    if (r != SINEW_OK && desc.anim) {
        view_show_error(v, error.message);
        desc.anim = NULL;
        desc.clip = NULL;
        r = app_scene_open(&scene, &desc, &error);
    }
    if (r != SINEW_OK) {
        view_show_error(v, error.message);
        return false;
    }
    return adopt_scene(v, &scene);
}

/* ---- opening a file on a worker thread ---------------------------------------------------- */

/* One file being opened: app_scene_open() runs on its own thread; the window keeps its scene,
 * shows the progress and a Cancel button, and takes the new scene when it is ready. A newer
 * open (or Cancel, or closing the window) asks the older one to stop. */
struct view_load {
    viewer *v;
    char *path, *clip;
    int32_t fallback; /* a reload: the clip index to try when the clip's name is gone (-1: none) */
    char note[512];   /* what the reload did instead, for the log */
    app_scene scene;
    sinew_error error;
    sinew_result result;
    gint cancel;   /* atomic */
    gint progress; /* atomic: the import's fraction in thousandths, or -1000 while reading */
    GThread *thread;
    gint64 started;
};

static bool load_progress(float fraction, void *user)
{
    view_load *l = user;
    g_atomic_int_set(&l->progress, (gint)(fraction * 1000.0f));
    return !g_atomic_int_get(&l->cancel);
}

static gboolean load_finished(gpointer data);

static gpointer load_thread(gpointer data)
{
    view_load *l = data;
    app_scene_desc desc = {.path = l->path,
                           .anim = l->v->anim,
                           .name_map = l->v->name_map,
                           .clip = l->clip,
                           .muscles = APP_MUSCLES_IF_ANY,
                           .import = l->v->import,
                           .progress = load_progress,
                           .progress_user = l};
    l->result = app_scene_open(&l->scene, &desc, &l->error);
    if (l->result != SINEW_OK && l->result != SINEW_ERROR_CANCELLED && l->fallback >= 0 && l->clip) {
        /* --watch: the new version lacks the clip's name; the same index, else the first clip */
        char index[16];
        snprintf(index, sizeof index, "%d", l->fallback);
        const char *tries[2] = {index, NULL};
        for (int i = 0; i < 2 && l->result != SINEW_OK; i++) {
            desc.clip = tries[i];
            sinew_error error = {0};
            if (app_scene_open(&l->scene, &desc, &error) == SINEW_OK) {
                snprintf(l->note, sizeof l->note, "the file changed: it has no clip \"%s\" now; showing %s (%s)",
                         l->clip, l->scene.clip ? l->scene.clip->name : "the rest pose",
                         i == 0 ? "the clip at the same place in the list" : "the first clip");
                l->result = SINEW_OK;
            }
        }
    }
    /* at the default priority: an idle one waits behind the redraws of a scene that is playing
     * (on a software renderer they never leave it idle), so the file would open only on leaving */
    g_idle_add_full(G_PRIORITY_DEFAULT, load_finished, l, NULL);
    return NULL;
}

static void load_free(view_load *l)
{
    app_scene_close(&l->scene); /* empty when it failed or was adopted */
    g_free(l->path);
    g_free(l->clip);
    g_free(l);
}

/* The progress line while a file opens. */
static gboolean load_tick(gpointer data)
{
    viewer *v = data;
    view_load *l = v->load;
    if (!l) {
        v->load_timer = 0;
        return G_SOURCE_REMOVE;
    }
    int progress = g_atomic_int_get(&l->progress);
    if (progress < 0)
        gtk_progress_bar_pulse(GTK_PROGRESS_BAR(v->load_progress));
    else
        gtk_progress_bar_set_fraction(GTK_PROGRESS_BAR(v->load_progress), progress / 1000.0);
    char *base = g_path_get_basename(l->path), text[600];
    snprintf(text, sizeof text, "Opening %s… %.1f s", base, (double)(g_get_monotonic_time() - l->started) * 1e-6);
    g_free(base);
    gtk_label_set_text(GTK_LABEL(v->load_label), text);
    return G_SOURCE_CONTINUE;
}

static void remember_file(viewer *v, const char *path)
{
    char *absolute = g_canonicalize_filename(path, NULL);
    char *uri = g_filename_to_uri(absolute, NULL, NULL);
    if (uri)
        gtk_recent_manager_add_item(gtk_recent_manager_get_default(), uri);
    g_free(uri);
    g_free(v->last_folder);
    v->last_folder = g_path_get_dirname(absolute);
    int at = 0; /* to the front of the recent list, once */
    while (at < 9 && v->recent[at] && strcmp(v->recent[at], absolute) != 0)
        at++;
    g_free(v->recent[at]);
    memmove(&v->recent[1], &v->recent[0], (size_t)at * sizeof v->recent[0]);
    v->recent[0] = absolute;
    view_recent_changed(v);
}

/* --watch: a change to the file (written in place, or replaced by rename as editors and
 * exporters do) reopens it a moment later, keeping the clip, the time and the camera. */
static gboolean reload_file(gpointer data)
{
    viewer *v = data;
    v->reload_timer = 0;
    if (!v->path || v->closing)
        return G_SOURCE_REMOVE;
    panels_log(v, "the file changed on disk: reopening it");
    v->play.start_time = v->play.time;
    v->look.camera_keep = CAMERA_KEEP_ALL;
    v->reload_clip = v->scene.clip ? v->scene.clip_index : -1; /* if its name is gone ("none" never is) */
    view_open_file(v, v->path, v->scene.clip ? v->scene.clip->name : "none");
    return G_SOURCE_REMOVE;
}

static void on_file_changed(GFileMonitor *monitor, GFile *file, GFile *other, GFileMonitorEvent event, gpointer data)
{
    (void)monitor, (void)file, (void)other;
    viewer *v = data;
    if (event != G_FILE_MONITOR_EVENT_CHANGES_DONE_HINT && event != G_FILE_MONITOR_EVENT_CREATED &&
        event != G_FILE_MONITOR_EVENT_RENAMED && event != G_FILE_MONITOR_EVENT_MOVED_IN)
        return;
    if (v->reload_timer)
        g_source_remove(v->reload_timer);
    v->reload_timer = g_timeout_add(300, reload_file, v);
}

static void watch_file(viewer *v)
{
    if (v->monitor) {
        g_file_monitor_cancel(v->monitor);
        g_object_unref(v->monitor);
        v->monitor = NULL;
    }
    if (!v->watch || !v->path)
        return;
    GFile *file = g_file_new_for_path(v->path);
    v->monitor = g_file_monitor_file(file, G_FILE_MONITOR_WATCH_MOVES, NULL, NULL);
    g_object_unref(file);
    if (v->monitor)
        g_signal_connect(v->monitor, "changed", G_CALLBACK(on_file_changed), v);
}

/* Without dots: app_has_extension() checks the dot itself. */
static const char *const FILE_EXTENSIONS[] = {"fbx",     "gltf", "glb", "dae", "sinew", "bvh",  "x",   "smd",
                                              "md5mesh", "iqm",  "obj", "3ds", "ply",   "ms3d", "b3d", "md2",
                                              "md3",     "mdl",  "lwo", "ase", "ac",    "off",  "stl", "blend"};

static bool readable_name(const char *name)
{
    for (size_t i = 0; i < sizeof FILE_EXTENSIONS / sizeof FILE_EXTENSIONS[0]; i++)
        if (app_has_extension(name, FILE_EXTENSIONS[i]))
            return true;
    return false;
}

static int by_name(const void *a, const void *b)
{
    return g_utf8_collate(*(char *const *)a, *(char *const *)b);
}

char *view_neighbour_file(const char *path, int step)
{
    char *folder = g_path_get_dirname(path), *base = g_path_get_basename(path), *found = NULL;
    GDir *dir = g_dir_open(folder, 0, NULL);
    GPtrArray *names = g_ptr_array_new_with_free_func(g_free);
    for (const char *name; dir && (name = g_dir_read_name(dir));) {
        char *full = g_build_filename(folder, name, NULL);
        if (readable_name(name) && g_file_test(full, G_FILE_TEST_IS_REGULAR))
            g_ptr_array_add(names, g_strdup(name));
        g_free(full);
    }
    if (dir)
        g_dir_close(dir);
    qsort(names->pdata, names->len, sizeof(char *), by_name);
    guint at = names->len;
    for (guint i = 0; i < names->len; i++)
        if (strcmp(names->pdata[i], base) == 0)
            at = i;
    if (names->len > 1 || (names->len == 1 && at == names->len)) {
        guint next = at == names->len
                         ? (step > 0 ? 0 : names->len - 1)
                         : (guint)((at + names->len + (guint)(step > 0 ? 1 : names->len - 1)) % names->len);
        found = g_build_filename(folder, (const char *)names->pdata[next], NULL);
    }
    g_ptr_array_unref(names);
    g_free(folder);
    g_free(base);
    return found;
}

static gboolean load_finished(gpointer data)
{
    view_load *l = data;
    viewer *v = l->v;
    g_thread_join(l->thread);
    if (v->load != l || v->closing) { /* superseded by a newer open, given up, or the window is going */
        if (v->load == l)
            v->load = NULL;
        load_free(l);
        return G_SOURCE_REMOVE;
    }
    v->load = NULL;
    if (v->load_bar)
        gtk_widget_set_visible(v->load_bar, FALSE);
    bool opened = false;
    if (l->result == SINEW_OK && g_atomic_int_get(&l->cancel)) {
        panels_log(v, "opening cancelled");
    } else if (l->result == SINEW_OK) {
        opened = adopt_scene(v, &l->scene);
        if (opened) {
            view_show_error(v, NULL);
            if (l->note[0]) {
                panels_log(v, l->note);
                fprintf(stderr, "sinew-view: %s: %s\n", l->path, l->note);
            }
            remember_file(v, l->path);
            if (!v->path || strcmp(v->path, l->path) != 0) {
                g_free(v->path);
                v->path = g_strdup(l->path);
                watch_file(v);
            }
        }
    } else if (l->result != SINEW_ERROR_CANCELLED) {
        view_show_error(v, l->error.message);
    } else {
        panels_log(v, l->error.message);
    }
    if (!opened && v->screenshot) /* a screenshot run says so in its exit status (2, as sinew's) */
        v->exit_code = 2;
    if (opened && !isnan(v->play.start_time)) /* --time: against the file's clip, not the demo's */
        v->play.time = v->play.start_time;
    v->play.start_time = NAN;
    /* a --screenshot run shows the moment asked for, still */
    if (opened && v->play_after_open && !v->screenshot && !v->window_shot)
        view_set_playing(v, true);
    v->play_after_open = false;
    if (v->play.time > view_duration(v))
        v->play.time = view_duration(v);
    view_show_time(v);
    view_redraw(v);
    load_free(l);
    return G_SOURCE_REMOVE;
}

void view_open_other(viewer *v, const char *path)
{
    /* another file, as f3d and Blender open one: from its start, playing, framed on its own */
    v->play.start_time = 0.0;
    v->look.camera_keep = CAMERA_FRAME;
    v->play_after_open = true;
    view_open_file(v, path, NULL);
}

void view_open_file(viewer *v, const char *path, const char *clip_name)
{
    if (v->load) /* the newer open wins */
        g_atomic_int_set(&v->load->cancel, 1);
    view_load *l = g_new0(view_load, 1);
    *l = (view_load){.v = v,
                     .path = g_strdup(path),
                     .clip = g_strdup(clip_name),
                     .fallback = v->reload_clip,
                     .progress = -1000,
                     .started = g_get_monotonic_time()};
    v->reload_clip = -1;
    v->load = l;
    if (v->load_bar) {
        gtk_widget_set_visible(v->load_bar, TRUE);
        load_tick(v);
        if (!v->load_timer)
            v->load_timer = g_timeout_add(100, load_tick, v);
    }
    l->thread = g_thread_new("sinew-open", load_thread, l);
}

void view_cancel_open(viewer *v, bool wait)
{
    view_load *l = v->load;
    if (!l)
        return;
    g_atomic_int_set(&l->cancel, 1);
    if (!wait)
        return;
    /* leaving: wait for the thread here, its idle callback will not run */
    v->load = NULL;
    g_thread_join(l->thread);
    g_idle_remove_by_data(l);
    load_free(l);
}
