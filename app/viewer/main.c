/* sinew-view: the desktop viewer (GTK 4).
 *
 * A GtkGLArea runs sinew's renderer on one model at a time: FILE, a file opened with the
 * Open button or dropped on the window, or the built-in demo humanoid. A file that fails
 * to open leaves the scene as it was and shows the error above it; one that takes long shows
 * its progress and can be cancelled. The clip plays on a
 * clock independent of the frame rate (speed 0.1x-4x, reverse, loop / once / ping-pong);
 * a scrub bar with keyframe ticks, time and frame; Space, Left/Right (a frame), Home/End.
 * Orbit camera: drag rotates, shift-drag or middle-drag pans, the wheel zooms, F frames all;
 * Tab switches to the free-fly camera (W/A/S/D, Q/E, drag to look). Keys are the settings
 * file's [keys]. The status bar gives fps, vertices and joints. `--screenshot OUT.png --quit` writes the
 * first frame and leaves, with the display, camera and time options of `sinew render`.
 *
 * open.c opens files (on a worker thread, with progress and Cancel) and swaps the scene,
 * panels.c has the side panel (hierarchy, display, log), settings.c the settings file. */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <epoxy/gl.h>
#include <gtk/gtk.h>
#include <stb_image_write.h>

#include "sinew/sinew.h"

#include "viewer.h"

/* ---- model ------------------------------------------------------------------------------- */

/* Shows (and logs, and prints on stderr) an error above the scene; NULL hides it. */
void view_show_error(viewer *v, const char *message)
{
    if (message) {
        fprintf(stderr, "sinew-view: %s\n", message);
        char line[1100];
        snprintf(line, sizeof line, "error: %s", message);
        panels_log(v, line);
    }
    if (!v->error_label)
        return;
    gtk_label_set_text(GTK_LABEL(v->error_label), message);
    gtk_widget_set_visible(v->error_bar, message != NULL);
}

void view_redraw(viewer *v)
{
    if (v->area && !v->closing)
        gtk_gl_area_queue_render(GTK_GL_AREA(v->area));
}

/* The worlds at the current time; once a time (the tick, the panel and the draw all ask). */
bool view_pose(viewer *v)
{
    return v->scene.model && app_scene_pose(&v->scene, v->play.time, SINEW_WRAP_CLAMP, NULL) == SINEW_OK;
}

void view_recent_changed(viewer *v)
{
    if (!v->recent_menu)
        return;
    g_menu_remove_all(v->recent_menu);
    for (int i = 0; i < 10 && v->recent[i]; i++) {
        char *base = g_path_get_basename(v->recent[i]);
        GMenuItem *item = g_menu_item_new(base, NULL);
        g_menu_item_set_action_and_target_value(item, "win.open-recent", g_variant_new_string(v->recent[i]));
        g_menu_append_item(v->recent_menu, item);
        g_object_unref(item);
        g_free(base);
    }
}

static void on_open_recent(GSimpleAction *action, GVariant *parameter, gpointer data)
{
    (void)action;
    view_open_other(data, g_variant_get_string(parameter, NULL));
}

/* ---- timeline ------------------------------------------------------------------------------ */

static int compare_floats(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

/* The scrub bar's range and keyframe ticks: the distinct key times of the clip's channels
 * inside its window (a clip may be a window onto keys it shares with other clips). */
/* The rate the clip was keyed at: the spacing its key times share (a file keyed at 24 fps
 * steps by 1/24 s), when 4 gaps in 5 have it and it is between 1 and 240 a second; else
 * FRAME_RATE (keys baked at uneven times, as sinew's FBX bake places them, show no rate). */
static double clip_frame_rate(const float *times, size_t n)
{
    size_t best_count = 0, gaps = n > 1 ? n - 1 : 0;
    double best = 0.0;
    for (size_t i = 0; i + 1 < n && i < 64; i++) { /* candidates: the first gaps */
        double gap = times[i + 1] - times[i];
        size_t same = 0;
        for (size_t j = 0; j + 1 < n; j++)
            same += fabs((times[j + 1] - times[j]) - gap) < 1e-4 * fmax(gap, 1e-3);
        if (same > best_count)
            best_count = same, best = gap;
    }
    if (gaps == 0 || best_count * 5 < gaps * 4 || !(best >= 1.0 / 240.0 && best <= 1.0))
        return FRAME_RATE;
    double rate = 1.0 / best, rounded = floor(rate + 0.5);
    return fabs(rate - rounded) < 0.01 * rounded ? rounded : rate; /* 23.99997 is 24 */
}

double view_frame_rate(const viewer *v)
{
    return v->play.frame_rate > 0.0 ? v->play.frame_rate : FRAME_RATE;
}

/* The frame at `time` (s): a thousandth of a frame short of one counts as it (a float time or
 * duration of a long clip is off by more than that of a millionth: 01_01.bvh's last key, 2,751
 * frames at 120.0005 fps, is at frame 2750.99994). */
static double frame_at(const viewer *v, double time)
{
    return floor(time * view_frame_rate(v) + 1e-3);
}

void view_update_timeline(viewer *v)
{
    if (!v->scale)
        return;
    v->updating = true;
    double d = view_duration(v);
    gtk_range_set_range(GTK_RANGE(v->scale), 0.0, d > 0.0 ? d : 1.0);
    gtk_scale_clear_marks(GTK_SCALE(v->scale));
    const sinew_clip *clip = v->scene.clip;
    size_t count = 0;
    for (uint32_t t = 0; clip && t < clip->track_count; t++)
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++)
            count += clip->tracks[t].channels[k].key_count;
    float *times = count ? malloc(count * sizeof *times) : NULL;
    if (times) {
        size_t n = 0;
        for (uint32_t t = 0; t < clip->track_count; t++)
            for (int k = 0; k < SINEW_CHANNEL_COUNT; k++) {
                const sinew_channel *ch = &clip->tracks[t].channels[k];
                for (uint32_t i = 0; i < ch->key_count; i++) {
                    float at = clip->times[ch->first_key + i] - clip->start;
                    if (at >= 0.0f && at <= clip->duration)
                        times[n++] = at;
                }
            }
        qsort(times, n, sizeof *times, compare_floats);
        size_t distinct = 0;
        for (size_t i = 0; i < n; i++)
            if (i == 0 || times[i] != times[distinct - 1])
                times[distinct++] = times[i];
        size_t step = distinct > MAX_TICKS ? (distinct + MAX_TICKS - 1) / MAX_TICKS : 1;
        for (size_t i = 0; i < distinct; i += step)
            gtk_scale_add_mark(GTK_SCALE(v->scale), times[i], GTK_POS_BOTTOM, NULL);
        count = distinct;
    }
    free(v->play.key_times); /* kept for the key jumps (Up / Down) */
    v->play.key_times = times;
    v->play.key_time_count = times ? count : 0;
    /* the file's own frame rate (FBX's time mode), else the usual spacing of the clip's keys */
    v->play.frame_rate = v->scene.clip && v->scene.clip->frame_rate > 0.0f
                             ? v->scene.clip->frame_rate
                             : clip_frame_rate(v->play.key_times, v->play.key_time_count);
    v->updating = false;
}

void view_show_time(viewer *v)
{
    char text[128];
    double rate = view_frame_rate(v);
    snprintf(text, sizeof text, "%6.3f / %.3f s   frame %d / %d at %g fps", v->play.time, view_duration(v),
             (int)frame_at(v, v->play.time), (int)frame_at(v, view_duration(v)), rate);
    gtk_label_set_text(GTK_LABEL(v->time_label), text);
    v->updating = true;
    gtk_range_set_value(GTK_RANGE(v->scale), v->play.time);
    if (v->frame_spin) {
        gtk_spin_button_set_range(GTK_SPIN_BUTTON(v->frame_spin), 0.0, frame_at(v, view_duration(v)));
        gtk_spin_button_set_value(GTK_SPIN_BUTTON(v->frame_spin), frame_at(v, v->play.time));
    }
    v->updating = false;
}

static void set_time(viewer *v, double t)
{
    double d = view_duration(v);
    v->play.time = t < 0.0 ? 0.0 : t > d ? d : t;
    view_show_time(v);
    if ((v->selected >= 0 || v->shape_count) && view_pose(v)) {
        panels_frame_drawn(v);
        panels_weights_changed(v);
    }
    gtk_gl_area_queue_render(GTK_GL_AREA(v->area));
}

static void set_playing(viewer *v, bool playing)
{
    v->play.playing = playing;
    v->play.last_frame = 0;
    gtk_button_set_icon_name(GTK_BUTTON(v->play_button),
                             playing ? "media-playback-pause-symbolic" : "media-playback-start-symbolic");
}

void view_set_playing(viewer *v, bool playing)
{
    set_playing(v, playing);
}

/* Advances the clock by dt seconds of wall time. */
static void advance(viewer *v, double dt)
{
    double d = view_duration(v);
    if (d <= 0.0)
        return;
    double t = v->play.time + dt * v->play.speed * v->play.direction;
    if (v->play.mode == PLAY_LOOP) {
        t = fmod(t, d);
        if (t < 0.0)
            t += d;
    } else if (v->play.mode == PLAY_ALL_CLIPS && (t >= d || t < 0.0) && v->scene.model->clip_count > 1) {
        /* the next clip (the previous when reversed), wrapping; the list shows which */
        uint32_t n = v->scene.model->clip_count;
        int32_t at = v->scene.clip ? (int32_t)(v->scene.clip - v->scene.model->clips) : 0;
        int32_t next = (int32_t)(((uint32_t)at + (t >= d ? 1u : n - 1u)) % n);
        double over = t >= d ? t - d : -t;
        gtk_drop_down_set_selected(GTK_DROP_DOWN(v->clip_list), (guint)next); /* on_clip plays it from 0 */
        d = view_duration(v);
        t = t >= 0.0 ? fmin(over, d) : fmax(d - over, 0.0);
    } else if (v->play.mode == PLAY_ONCE || v->play.mode == PLAY_ALL_CLIPS) {
        if (t >= d || t <= 0.0) {
            t = t >= d ? d : 0.0;
            set_playing(v, false);
        }
    } else {
        while (t > d || t < 0.0) {
            t = t > d ? 2.0 * d - t : -t;
            v->play.direction = -v->play.direction;
        }
    }
    v->play.time = t;
}

static void show_status(viewer *v);
static void stop_recording(viewer *v, const char *why);
static gboolean on_key(GtkEventControllerKey *controller, guint key, guint code, GdkModifierType state, gpointer data);

static gboolean close_window(gpointer data);

/* The whole window as it shows (the view and the panels) into a PNG: --screenshot-window. */
static void save_window(viewer *v)
{
    int w = gtk_widget_get_width(v->window), h = gtk_widget_get_height(v->window);
    GdkPaintable *paintable = gtk_widget_paintable_new(v->window);
    GtkSnapshot *snapshot = gtk_snapshot_new();
    gdk_paintable_snapshot(paintable, snapshot, w, h);
    GskRenderNode *node = gtk_snapshot_free_to_node(snapshot);
    GskRenderer *renderer = gtk_native_get_renderer(GTK_NATIVE(v->window));
    GdkTexture *texture = node && renderer ? gsk_renderer_render_texture(renderer, node, NULL) : NULL;
    if (!texture || !gdk_texture_save_to_png(texture, v->window_shot)) {
        fprintf(stderr, "sinew-view: cannot write the window to %s\n", v->window_shot);
        v->exit_code = 4;
    }
    if (texture)
        g_object_unref(texture);
    if (node)
        gsk_render_node_unref(node);
    g_object_unref(paintable);
}

static gboolean on_tick(GtkWidget *widget, GdkFrameClock *clock, gpointer data)
{
    (void)widget;
    viewer *v = data;
    gint64 now = gdk_frame_clock_get_frame_time(clock);
    double dt = v->play.last_tick ? (double)(now - v->play.last_tick) * 1e-6 : 0.0;
    v->play.last_tick = now;
    if (v->look.camera.mode == SINEW_CAMERA_FLY) { /* keys held: metres a second from the scene's size */
        float speed = 0.8f * (v->look.camera.scene_radius > 0.0f ? v->look.camera.scene_radius : 1.0f) * (float)dt;
        float f = (float)(v->look.held[ACTION_FORWARD] - v->look.held[ACTION_BACK]);
        float r = (float)(v->look.held[ACTION_RIGHT] - v->look.held[ACTION_LEFT]);
        float u = (float)(v->look.held[ACTION_UP] - v->look.held[ACTION_DOWN]);
        if (f != 0.0f || r != 0.0f || u != 0.0f) {
            sinew_camera_move(&v->look.camera, f * speed, r * speed, u * speed);
            view_redraw(v);
        }
    }
    if (v->status_due) {
        v->status_due = false;
        show_status(v);
    }
    /* the renderer's warnings (textures it could not read; a crowd without levels of detail, at its
     * first draw), logged here rather than in the draw, as the status is */
    for (; v->renderer && v->renderer_warnings < sinew_renderer_warning_count(v->renderer); v->renderer_warnings++) {
        char line[1024]; /* the renderer's warnings name the model where it matters */
        snprintf(line, sizeof line, "warning: %s", sinew_renderer_warning(v->renderer, v->renderer_warnings));
        panels_log(v, line);
    }
    if (v->window_shot && !v->load && !v->press && v->frames_drawn > 2) { /* panels laid out by now */
        save_window(v);
        v->window_shot = NULL;
        if (v->quit_after_screenshot && !v->screenshot) /* at default priority: a playing scene's redraws
                                                         * (priority 120) starve idle sources on a slow machine */
            g_idle_add_full(G_PRIORITY_DEFAULT, close_window, v, NULL);
    }
    if (v->pose.fade_from > 0.0 &&
        v->pose.blend_scale) { /* the Cross-fade button: the weight to 1 over half a second */
        double w = fmin(1.0, ((double)now * 1e-6 - v->pose.fade_from) / 0.5);
        if (w >= 1.0)
            v->pose.fade_from = 0.0;
        gtk_range_set_value(GTK_RANGE(v->pose.blend_scale), w * w * (3.0 - 2.0 * w));
    }
    if (v->rec.record_end) {
        if (v->rec.record_error[0])
            view_show_error(v, v->rec.record_error);
        stop_recording(v, v->rec.record_end);
        v->rec.record_end = NULL;
        v->rec.record_error[0] = 0;
    }
    if (v->rec.title_due) { /* recording: the title says so and where */
        v->rec.title_due = false;
        char title[4300];
        if (v->rec.recording)
            snprintf(title, sizeof title, "● recording %s (F9 stops) — sinew", v->rec.video_path);
        else
            snprintf(title, sizeof title, "%s — sinew", v->scene.model ? v->scene.model->source : "sinew");
        gtk_window_set_title(GTK_WINDOW(v->window), title);
    }
    if (v->sliders && !v->load && v->scene.model) { /* the test hook: sliders set once the file is open */
        char **items = g_strsplit(v->sliders, ",", -1);
        for (int i = 0; items[i]; i++)
            if (!panels_set_slider(v, g_strstrip(items[i])))
                fprintf(stderr, "sinew-view: SINEW_VIEW_SLIDERS: no shape key \"%s\"\n", items[i]);
        g_strfreev(items);
        g_free(v->sliders);
        v->sliders = NULL; /* the camera stays, as it does when a hand moves a slider */
    }
    if (v->press && !v->load && v->look.framed) { /* --press: once the file is open and drawn, before the
                                                     screenshot, as a hand would */
        char **names = g_strsplit(v->press, ",", -1);
        v->press = NULL;
        for (int i = 0; names[i]; i++) {
            const char *name = g_strstrip(names[i]);
            GdkModifierType state = 0; /* shift+NAME, ctrl+NAME */
            for (bool more = true; more;) {
                more = false;
                if (g_ascii_strncasecmp(name, "shift+", 6) == 0)
                    state |= GDK_SHIFT_MASK, name += 6, more = true;
                else if (g_ascii_strncasecmp(name, "ctrl+", 5) == 0)
                    state |= GDK_CONTROL_MASK, name += 5, more = true;
            }
            guint key = gdk_keyval_from_name(name);
            if (key == GDK_KEY_VoidSymbol || key == 0 || !on_key(NULL, key, 0, state, v))
                fprintf(stderr, "sinew-view: --press: \"%s\" is no key bound to an action\n", names[i]);
        }
        g_strfreev(names);
    }
    if (v->play.playing) {
        if (v->rec.recording) /* the video's clock, not the wall's: every frame 1/RECORD_FPS s on */
            advance(v, v->play.speed > 0.0 ? 1.0 / RECORD_FPS / v->play.speed : 0.0);
        else if (v->play.last_frame)
            advance(v, (double)(now - v->play.last_frame) * 1e-6);
        v->play.last_frame = now;
        view_show_time(v);
        if ((v->selected >= 0 || v->shape_count) && view_pose(v)) { /* not from the draw: a label may resize */
            panels_frame_drawn(v);
            panels_weights_changed(v);
        }
        gtk_gl_area_queue_render(GTK_GL_AREA(v->area));
    }
    return G_SOURCE_CONTINUE;
}

/* ---- drawing -------------------------------------------------------------------------------- */

/* The crowd for the scene's model, made when the toggle is on and the model changed (spaced
 * by one character's footprint over its clip). False with the error shown when it cannot be. */
static bool crowd_ready(viewer *v)
{
    if (v->crowd.count && v->crowd.model == v->scene.model)
        return true;
    app_crowd_close(&v->crowd);
    sinew_error error = {0};
    if (!v->jobs && sinew_jobs_create(&(sinew_jobs_desc){0}, &v->jobs, &error) != SINEW_OK) {
        view_show_error(v, error.message);
        return false;
    }
    app_crowd_desc d = {.model = v->scene.model,
                        .clip = v->scene.clip,
                        .count = v->crowd_size,
                        .spacing = app_crowd_spacing(&v->scene, v->renderer, 5),
                        .jobs = v->jobs};
    if (app_crowd_open(&v->crowd, &d, &error) != SINEW_OK) {
        view_show_error(v, error.message);
        v->crowd_on = false;
        return false;
    }
    return true;
}

static void frame_all(viewer *v)
{
    float lo[3], hi[3];
    int w = gtk_widget_get_width(v->area), h = gtk_widget_get_height(v->area);
    if (!v->renderer)
        return;
    v->options.grid_height = app_scene_ground(&v->scene, v->renderer, 60); /* as `sinew render` places it */
    if (!app_scene_bounds(&v->scene, v->renderer, v->play.time, v->play.time, 1, SINEW_WRAP_CLAMP, lo, hi))
        return;
    if (v->crowd_on && crowd_ready(v))
        app_crowd_bounds(&v->crowd, lo, hi);
    sinew_camera keep = v->look.camera;
    sinew_camera_frame(&v->look.camera, lo, hi, h > 0 ? (float)w / (float)h : 1.0f);
    if (v->look.keep_now == CAMERA_KEEP_ALL) { /* the grid's spacing follows the new file's size */
        float radius = v->look.camera.scene_radius;
        v->look.camera = keep;
        v->look.camera.scene_radius = radius;
    } else if (v->look.keep_now == CAMERA_KEEP_GIVEN && keep.mode == SINEW_CAMERA_FLY) {
        memcpy(v->look.camera.position, keep.position, sizeof keep.position);
    } else if (v->look.keep_now == CAMERA_KEEP_GIVEN) {
        v->look.camera.distance = keep.distance;
    }
    if (v->look.keep_now != CAMERA_KEEP_ALL) { /* --camera-position, --camera-focal-point: once */
        app_camera_place(&v->look.camera, &v->look.placement);
        v->look.placement.has_position = v->look.placement.has_focal = false;
    }
    v->look.keep_now = CAMERA_FRAME; /* the next framing (F, a crowd) frames all */
    app_scene_follow(&v->scene, v->play.time, SINEW_WRAP_CLAMP, &v->look.followed, NULL);
}

void view_set_follow(viewer *v, bool on)
{
    v->look.follow = on;
    v->look.follow_given = false; /* the user's choice from now on: saved */
    if (on && v->renderer && v->scene.model)
        app_scene_follow(&v->scene, v->play.time, SINEW_WRAP_CLAMP, &v->look.followed, NULL);
    if (v->look.follow_check) {
        v->updating = true;
        gtk_check_button_set_active(GTK_CHECK_BUTTON(v->look.follow_check), on);
        v->updating = false;
    }
    view_redraw(v);
}

void view_toggle_crowd(viewer *v, bool on)
{
    v->crowd_on = on;
    v->look.framed = false;
    if (v->crowd_check) {
        v->updating = true;
        gtk_check_button_set_active(GTK_CHECK_BUTTON(v->crowd_check), on);
        v->updating = false;
    }
    view_redraw(v);
}

/* Writes the frame to v->screenshot: --screenshot (a failure sets the exit status, 4 as
 * sinew's) or F12 (the path goes to the log and stdout, a failure to the error bar). */
static void save_screenshot(viewer *v, int width, int height)
{
    bool numbered = v->screenshot == v->shot_path;
    unsigned char *rgba = malloc((size_t)width * height * 4);
    sinew_error error = {0};
    if (!rgba) {
        sinew_fail(&error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for the screenshot", v->screenshot);
    } else {
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
        app_write_image(v->screenshot, rgba, width, height, true, false, &error);
        free(rgba);
    }
    if (error.kind == SINEW_OK && numbered) {
        char line[4200];
        snprintf(line, sizeof line, "screenshot: %s", v->shot_path);
        panels_log(v, line);
        printf("sinew-view: wrote %s\n", v->shot_path);
        fflush(stdout);
    } else if (error.kind != SINEW_OK && numbered) {
        view_show_error(v, error.message);
    } else if (error.kind != SINEW_OK) {
        fprintf(stderr, "sinew-view: cannot write the screenshot: %s\n", error.message);
        v->exit_code = 4; /* as sinew's: an output that cannot be written */
    }
}

/* The next free FILE-NNN.EXT (FILE: the model's name without its extension) in
 * --screenshot-dir, else the user's `kind` folder (Pictures, Videos), else home. */
static void numbered_path(const viewer *v, GUserDirectory kind, const char *ext, char *out, size_t size)
{
    const char *dir = v->screenshot_dir ? v->screenshot_dir : g_get_user_special_dir(kind);
    if (!dir || !g_file_test(dir, G_FILE_TEST_IS_DIR))
        dir = v->screenshot_dir ? v->screenshot_dir : g_get_home_dir();
    char *base = v->path ? g_path_get_basename(v->path) : g_strdup("sinew-demo");
    char *dot = strrchr(base, '.');
    if (dot && dot != base)
        *dot = 0;
    for (int n = 1; n < 100000; n++) {
        snprintf(out, size, "%s/%s-%03d.%s", dir, base, n, ext);
        if (!g_file_test(out, G_FILE_TEST_EXISTS))
            break;
    }
    g_free(base);
}

/* F12: the next free FILE-NNN.png in --screenshot-dir, else the Pictures folder, else home;
 * written at the next draw. */
static void take_numbered_screenshot(viewer *v)
{
    if (v->screenshot) /* one is waiting for the next draw */
        return;
    numbered_path(v, G_USER_DIRECTORY_PICTURES, "png", v->shot_path, sizeof v->shot_path);
    v->screenshot = v->shot_path;
    view_redraw(v);
}

/* F9 again, one pass of the clip recorded, or the window closed: the video is finished
 * (kept when anything was recorded) and its path logged. */
static void stop_recording(viewer *v, const char *why)
{
    if (!v->rec.recording)
        return;
    v->rec.recording = false;
    sinew_error error = {0};
    bool kept = app_video_close(&v->rec.video, v->rec.recorded > 0.0, &error) == SINEW_OK;
    free(v->rec.video_frame);
    v->rec.video_frame = NULL;
    char line[4400];
    if (kept) {
        snprintf(line, sizeof line, "recorded %.2f s to %s (%s)", v->rec.recorded, v->rec.video_path, why);
        panels_log(v, line);
        printf("sinew-view: wrote %s\n", v->rec.video_path);
        fflush(stdout);
    } else if (error.kind != SINEW_OK) {
        view_show_error(v, error.message);
    }
    v->rec.title_due = true;
}

/* F9: records what the view shows, playing the clip at RECORD_FPS frames a second of clip
 * time (not the wall's: the video runs at the clip's speed however slowly frames are drawn),
 * into the next free FILE-NNN.mp4 beside F12's screenshots, until F9 again or one pass of a
 * looping or once-played clip. */
static void start_recording(viewer *v, int w, int h)
{
    v->rec.record_asked = false;
    numbered_path(v, G_USER_DIRECTORY_VIDEOS, "mp4", v->rec.video_path, sizeof v->rec.video_path);
    sinew_error error = {0};
    signal(SIGPIPE, SIG_IGN); /* a dead ffmpeg is a write error */
    v->rec.video_frame = malloc((size_t)w * (size_t)h * 4 + 1);
    if (!v->rec.video_frame || w <= 0 || h <= 0 ||
        app_video_open(&v->rec.video, v->rec.video_path, w, h, RECORD_FPS, true, &error) != SINEW_OK) {
        free(v->rec.video_frame);
        v->rec.video_frame = NULL;
        view_show_error(v, error.kind != SINEW_OK ? error.message : "out of memory for recording");
        return;
    }
    v->rec.recording = true;
    v->rec.recorded = 0.0;
    v->rec.video_width = w, v->rec.video_height = h;
    v->rec.title_due = true; /* from the next tick: a widget changed during the GL area's draw is left
                             unallocated for that frame ("Trying to snapshot ... without a current allocation") */
}

/* After a frame is drawn: it goes into the video. */
static void record_frame(viewer *v, int width, int height)
{
    sinew_error error = {0};
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (width == v->rec.video_width && height == v->rec.video_height) {
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, v->rec.video_frame);
    } else { /* the view was resized: the video keeps its size, cropped or padded from the top left */
        int w = width < v->rec.video_width ? width : v->rec.video_width,
            h = height < v->rec.video_height ? height : v->rec.video_height;
        memset(v->rec.video_frame, 0, (size_t)v->rec.video_width * (size_t)v->rec.video_height * 4);
        glPixelStorei(GL_PACK_ROW_LENGTH, v->rec.video_width);
        glReadPixels(0, height - h, w, h, GL_RGBA, GL_UNSIGNED_BYTE,
                     v->rec.video_frame + (size_t)(v->rec.video_height - h) * (size_t)v->rec.video_width * 4);
        glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    }
    if (app_video_write(&v->rec.video, v->rec.video_frame, &error) != SINEW_OK) {
        snprintf(v->rec.record_error, sizeof v->rec.record_error, "%s", error.message);
        v->rec.record_end = "ffmpeg stopped";
        return;
    }
    v->rec.recorded += v->play.playing ? v->play.speed / RECORD_FPS : 0.0;
    double d = view_duration(v);
    if ((v->play.mode == PLAY_LOOP || v->play.mode == PLAY_ONCE) && (d <= 0.0 || v->rec.recorded >= d - 1e-9))
        v->rec.record_end = d > 0.0 ? "one pass of the clip" : "the rest pose";
}

/* The root-motion path: where the root goes over the clip, drawn on the grid. */
static void root_motion_path(viewer *v)
{
    v->pose.path_segments = 0;
    double d = view_duration(v);
    if (!v->scene.ops.root_motion || !(d > 0.0) || !v->scene.model)
        return;
    uint32_t steps = (uint32_t)fmin(SINEW_MAX_FRAME_LINES, fmax(8.0, d * 30.0));
    if (!v->pose.motion_path &&
        !(v->pose.motion_path = malloc(SINEW_MAX_FRAME_LINES * 6 * sizeof *v->pose.motion_path)))
        return;
    float previous[3] = {0};
    for (uint32_t i = 0; i <= steps; i++) {
        float moved[3];
        const sinew_root_motion *motion = app_scene_pose(&v->scene, d * i / steps, SINEW_WRAP_CLAMP, NULL) == SINEW_OK
                                              ? app_scene_root_motion(&v->scene, moved, NULL)
                                              : NULL;
        if (!motion)
            return;
        const float *start = motion->start; /* where the root stays: the path starts there */
        float local[3] = {start[0] + moved[0], 0.0f, start[2] + moved[2]}, p[3];
        int32_t parent = v->scene.model->node_parents[motion->node];
        const float *m = parent >= 0 ? v->scene.worlds[parent].m : NULL; /* the path is in the root's parent space */
        for (int k = 0; k < 3; k++)
            p[k] = m ? m[k] * local[0] + m[8 + k] * local[2] + m[12 + k] : local[k];
        if (i > 0) {
            memcpy(v->pose.motion_path + v->pose.path_segments * 6, previous, sizeof previous);
            memcpy(v->pose.motion_path + v->pose.path_segments * 6 + 3, p, sizeof p);
            v->pose.path_segments++;
        }
        memcpy(previous, p, sizeof p);
    }
    v->scene.posed_at = NAN; /* posed again at the view's time when drawn */
}

/* `path`: the root-motion path is made again (not when only the IK target moved: the root's
 * motion is taken out before IK, and remaking it poses the whole clip). */
static void apply_pose_ops(viewer *v, bool path)
{
    if (!v->scene.model)
        return;
    app_pose_spec spec = v->pose.pose_ops; /* the command line's, with the panel's on top */
    char blend[128], ik[600];
    if (v->pose.blend_clip >= 0 && v->scene.clip_index >= 0) {
        snprintf(blend, sizeof blend, "%d:%.4f,%d:%.4f", v->scene.clip_index, 1.0 - v->pose.blend_weight,
                 v->pose.blend_clip, v->pose.blend_weight);
        spec.blend = blend;
    }
    spec.root_motion = spec.root_motion || v->pose.root_motion;
    if (v->pose.ik_on && v->pose.ik_joint >= 0 && spec.ik_count < APP_MAX_IK) {
        snprintf(ik, sizeof ik, "%s:%g,%g,%g", v->scene.model->node_names[v->pose.ik_joint],
                 (double)v->pose.ik_target[0], (double)v->pose.ik_target[1], (double)v->pose.ik_target[2]);
        spec.ik[spec.ik_count++] = ik;
    }
    sinew_error error = {0};
    if (app_scene_set_pose_ops(&v->scene, &spec, &error) != SINEW_OK) {
        view_show_error(v, error.message);
        v->pose.ik_on = false;
    }
    if (path)
        root_motion_path(v);
    view_redraw(v);
}

void view_apply_pose_ops(viewer *v)
{
    apply_pose_ops(v, true);
}

/* The key cheat sheet: every action with its key as bound now, and the mouse. */
static void fill_help(viewer *v)
{
    GString *text = g_string_new("<b>Keys</b> (settings.ini [keys] rebinds them; h hides this)\n");
    int half = (ACTION_COUNT + 1) / 2;
    for (int a = 0; a < half; a++) {
        g_string_append_printf(text, "<tt>%-10s %-16s", gdk_keyval_name(v->keys[a].key), v->keys[a].action);
        if (a + half < ACTION_COUNT)
            g_string_append_printf(text, "   %-10s %s", gdk_keyval_name(v->keys[a + half].key),
                                   v->keys[a + half].action);
        g_string_append(text, "</tt>");
        g_string_append_c(text, '\n');
    }
    g_string_append(text,
                    "\n<b>Mouse</b>\n<tt>drag      </tt> orbit (fly: look)\n<tt>shift-drag</tt> pan "
                    "(also middle-drag)\n<tt>wheel     </tt> zoom\n<tt>Ctrl+O    </tt> open a file (or drop one)");
    gtk_label_set_markup(GTK_LABEL(v->help), text->str);
    g_string_free(text, TRUE);
}

/* A view along an axis (keypad 1, 3, 7 as in Blender), or back to the opening view (R). */
static void look_along(viewer *v, int axis)
{
    if (axis < 0) {
        v->look.camera.yaw = 30.0f * (float)G_PI / 180.0f;
        v->look.camera.pitch = 15.0f * (float)G_PI / 180.0f;
        v->look.camera.orthographic = false;
        sinew_camera_set_mode(&v->look.camera, SINEW_CAMERA_ORBIT);
    } else {
        sinew_camera_look_along(&v->look.camera, (sinew_camera_view_axis)axis);
    }
    if (v->look.camera.mode == SINEW_CAMERA_ORBIT)
        frame_all(v);
    panels_options_changed(v);
    view_redraw(v);
}

static void open_neighbour(viewer *v, int step)
{
    char *next = v->path ? view_neighbour_file(v->path, step) : NULL;
    if (next)
        view_open_other(v, next);
    else
        panels_log(v, v->path ? "no other file sinew reads in this folder" : "no file open (the demo is built in)");
    g_free(next);
}

static gboolean close_window(gpointer data)
{
    viewer *v = data;
    gtk_window_close(GTK_WINDOW(v->window)); /* through close-request, like the user's close */
    return G_SOURCE_REMOVE;
}

static void show_status(viewer *v)
{
    char text[256];
    char crowd[48] = "";
    if (v->crowd_on && v->crowd.count)
        snprintf(crowd, sizeof crowd, "   crowd of %u", v->crowd.count);
    snprintf(text, sizeof text, "%.0f fps   %u vertices   %u joints%s   %s", v->fps, app_vertex_count(v->scene.model),
             app_joint_count(v->scene.model), crowd,
             v->renderer ? sinew_renderer_gl_name(v->renderer) : "no OpenGL 3.3");
    gtk_label_set_text(GTK_LABEL(v->status), text);
}

static void msaa_release(viewer *v)
{
    glDeleteFramebuffers(1, &v->msaa_fbo);
    glDeleteRenderbuffers(1, &v->msaa_color);
    glDeleteRenderbuffers(1, &v->msaa_depth);
    v->msaa_fbo = v->msaa_color = v->msaa_depth = 0;
    v->msaa_width = v->msaa_height = v->msaa_samples = 0;
}

/* Binds the multisampled framebuffer the frame is drawn into, made or remade at the view's size
 * and the samples asked for (within GL_MAX_SAMPLES, which OpenGL 3.3 makes 4 or more); false
 * when anti-aliasing is off or GL refuses it (the frame then goes straight into the GL area's). */
static bool msaa_bind(viewer *v, int width, int height)
{
    if (v->samples <= 1 || v->msaa_refused)
        return false;
    if (v->msaa_fbo && v->msaa_width == width && v->msaa_height == height && v->msaa_samples == v->samples) {
        glBindFramebuffer(GL_FRAMEBUFFER, v->msaa_fbo);
        return true;
    }
    msaa_release(v);
    GLint most = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &most);
    int samples = v->samples < most ? v->samples : most;
    if (samples <= 1) {
        v->msaa_refused = true;
        return false;
    }
    glGenFramebuffers(1, &v->msaa_fbo);
    glGenRenderbuffers(1, &v->msaa_color);
    glGenRenderbuffers(1, &v->msaa_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, v->msaa_color);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, v->msaa_depth);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, v->msaa_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, v->msaa_color);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, v->msaa_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        panels_log(v, "anti-aliasing: OpenGL refused a multisampled framebuffer; FXAA instead");
        msaa_release(v);
        v->msaa_refused = true;
        return false;
    }
    v->msaa_width = width, v->msaa_height = height, v->msaa_samples = v->samples;
    return true;
}

/* Resolves the multisampled frame into the GL area's framebuffer, which stays bound (screenshots
 * and recordings read it). */
static void msaa_resolve(viewer *v, GLuint target, int width, int height)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, v->msaa_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
    glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, target);
    if (glGetError() != GL_NO_ERROR) { /* a format the resolve refuses: without anti-aliasing from now on */
        panels_log(v, "anti-aliasing: OpenGL refused to resolve into the view; FXAA instead");
        msaa_release(v);
        v->msaa_refused = true;
        view_redraw(v);
    }
}

static gboolean on_render(GtkGLArea *area, GdkGLContext *context, gpointer data)
{
    (void)context;
    viewer *v = data;
    int scale = gtk_widget_get_scale_factor(GTK_WIDGET(area));
    int width = gtk_widget_get_width(GTK_WIDGET(area)) * scale,
        height = gtk_widget_get_height(GTK_WIDGET(area)) * scale;
    if (!v->renderer) {
        glClearColor(0.16f, 0.17f, 0.19f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        return TRUE;
    }
    if (!v->look.framed) {
        frame_all(v);
        v->look.framed = true;
    }
    bool crowd = v->crowd_on && crowd_ready(v);
    if (v->look.follow && !crowd) /* the camera moves with the model before the frame takes it */
        app_scene_follow(&v->scene, v->play.time, SINEW_WRAP_CLAMP, &v->look.followed, &v->look.camera);
    sinew_error error = {0};
    sinew_frame frame = app_scene_frame(&v->scene, &v->look.camera, &v->options, width, height);
    if (v->scene.ops.root_motion && v->pose.path_segments) { /* the root-motion path on the ground */
        for (uint32_t i = 0; i < v->pose.path_segments * 2; i++)
            v->pose.motion_path[i * 3 + 1] = v->options.grid_height;
        frame.lines = v->pose.motion_path;
        frame.line_count = v->pose.path_segments;
        frame.line_color[0] = 1.0f, frame.line_color[1] = 0.75f, frame.line_color[2] = 0.2f;
    }
    if (crowd) {
        app_crowd_pose(&v->crowd, v->play.time);
        frame.crowd_count = v->crowd.count;
        frame.crowd_worlds = v->crowd.worlds;
        frame.jobs = v->jobs;
    }
    GLint area_fbo = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &area_fbo);
    bool msaa = msaa_bind(v, width, height);
    sinew_render_options options = v->options;
    if (v->samples > 1 && !msaa) /* multisampling refused: FXAA instead */
        options.fxaa = true;
    frame.options = &options;
    if (app_scene_pose(&v->scene, v->play.time, SINEW_WRAP_CLAMP, &error) != SINEW_OK ||
        (frame.cache_time = v->scene.cache_time, sinew_renderer_draw(v->renderer, &frame, &error)) != SINEW_OK)
        view_show_error(v, error.message);
    if (msaa)
        msaa_resolve(v, (GLuint)area_fbo, width, height);
    gint64 now = g_get_monotonic_time();
    if (v->fps_since == 0)
        v->fps_since = now;
    if (++v->fps_frames >= 10 || now - v->fps_since > 1000000) {
        v->fps = v->fps_frames / fmax(1e-6, (double)(now - v->fps_since) * 1e-6);
        v->fps_frames = 0;
        v->fps_since = now;
        v->status_due = true; /* set by the next tick: a label changed while the frame is being drawn
                                 leaves its row without an allocation for that frame, so GTK skips
                                 drawing it ("Trying to snapshot GtkBox without a current allocation") */
    }
    if (v->rec.recording && !v->rec.record_end)
        record_frame(v, width, height);
    if (v->rec.record_asked && !v->load && !v->press) /* the first frame goes in at the next draw */
        start_recording(v, width, height);
    if (!v->load && !v->press && !v->sliders)
        v->frames_drawn++;
    if (v->screenshot && !v->load && !v->press && !v->sliders) { /* of the file asked for, once open and keyed */
        save_screenshot(v, width, height);
        v->screenshot = NULL;
        if (v->quit_after_screenshot && !v->window_shot) /* not from inside the draw: when GTK is idle */
            g_idle_add_full(G_PRIORITY_DEFAULT, close_window, v, NULL);
    }
    return TRUE;
}

static void on_realize(GtkGLArea *area, gpointer data)
{
    viewer *v = data;
    gtk_gl_area_make_current(area);
    GError *e = gtk_gl_area_get_error(area);
    if (e) {
        char message[600];
        snprintf(message, sizeof message, "no OpenGL 3.3 context: %s", e->message);
        view_show_error(v, message);
        v->exit_code = 3;
        return;
    }
    if (v->scene.model && !v->renderer) {
        view_make_renderer(v, &v->scene, &v->renderer);
        v->renderer_warnings = 0;
    }
    show_status(v);
}

static void on_unrealize(GtkGLArea *area, gpointer data)
{
    viewer *v = data;
    gtk_gl_area_make_current(area);
    sinew_renderer_free(v->renderer);
    v->renderer = NULL;
    v->renderer_warnings = 0;
    msaa_release(v);
}

/* ---- input ---------------------------------------------------------------------------------- */

static void on_play(GtkButton *button, gpointer data)
{
    (void)button;
    viewer *v = data;
    set_playing(v, !v->play.playing);
}

static void on_scrub(GtkRange *range, gpointer data)
{
    viewer *v = data;
    if (!v->updating)
        set_time(v, gtk_range_get_value(range));
}

static void on_clip(GObject *dropdown, GParamSpec *pspec, gpointer data)
{
    (void)pspec;
    viewer *v = data;
    if (v->updating)
        return;
    guint index = gtk_drop_down_get_selected(GTK_DROP_DOWN(dropdown));
    /* the last entry, after the clips, is the rest pose */
    int32_t clip = index < v->scene.model->clip_count ? (int32_t)index : APP_CLIP_NONE;
    if (index <= v->scene.model->clip_count && view_use_clip(v, clip))
        set_time(v, 0.0);
}

static void on_frame_entry(GtkSpinButton *spin, gpointer data)
{
    viewer *v = data;
    if (v->updating)
        return;
    set_playing(v, false);
    set_time(v, gtk_spin_button_get_value(spin) / view_frame_rate(v));
}

static void on_speed(GtkSpinButton *spin, gpointer data)
{
    viewer *v = data;
    v->play.speed = gtk_spin_button_get_value(spin);
}

static void on_reverse(GtkToggleButton *toggle, gpointer data)
{
    viewer *v = data;
    v->play.direction = gtk_toggle_button_get_active(toggle) ? -1 : 1;
}

static void on_mode(GObject *dropdown, GParamSpec *pspec, gpointer data)
{
    (void)pspec;
    viewer *v = data;
    v->play.mode = (play_mode)gtk_drop_down_get_selected(GTK_DROP_DOWN(dropdown));
}

static void on_open(GtkButton *button, gpointer data);

static void cycle_shading(viewer *v)
{
    v->options.shading = (sinew_shading)((v->options.shading + 1) % 4);
}

static gboolean on_key(GtkEventControllerKey *controller, guint key, guint code, GdkModifierType state, gpointer data)
{
    (void)controller, (void)code;
    viewer *v = data;
    if ((state & GDK_CONTROL_MASK) && (key == GDK_KEY_o || key == GDK_KEY_O)) {
        on_open(NULL, v);
        return TRUE;
    }
    if ((state & GDK_CONTROL_MASK) && (key == GDK_KEY_q || key == GDK_KEY_Q || key == GDK_KEY_w || key == GDK_KEY_W)) {
        g_idle_add_full(G_PRIORITY_DEFAULT, close_window, v, NULL); /* as f3d and GTK apps quit */
        return TRUE;
    }
    if (state & (GDK_CONTROL_MASK | GDK_ALT_MASK))
        return FALSE;
    GtkWidget *focus = gtk_root_get_focus(GTK_ROOT(v->window));
    if (focus && (GTK_IS_TEXT(focus) || GTK_IS_EDITABLE(focus))) /* typing in the search box */
        return FALSE;
    if (key == GDK_KEY_Escape && v->help && gtk_widget_get_visible(v->help)) { /* first closes the cheat sheet */
        gtk_widget_set_visible(v->help, false);
        return TRUE;
    }
    if (key == GDK_KEY_Escape && !v->pose.ik_dragging) { /* nothing dragged, no text being edited (above) */
        g_idle_add_full(G_PRIORITY_DEFAULT, close_window, v, NULL);
        return TRUE;
    }
    int action = settings_action_for_key(v, key);
    if (v->key_map == KEY_MAP_BLENDER && (state & GDK_SHIFT_MASK) && (key == GDK_KEY_Left || key == GDK_KEY_Right))
        action = key == GDK_KEY_Left ? ACTION_FIRST : ACTION_LAST; /* Blender's jump to start / end */
    if (action < 0)
        return FALSE;
    if (v->keys[action].option) {
        char value[16];
        settings_option_changed(v, v->keys[action].option);
        sinew_render_option_get(&v->options, v->keys[action].option, value, sizeof value, NULL);
        sinew_render_option_set(&v->options, v->keys[action].option, strcmp(value, "on") == 0 ? "off" : "on", NULL);
        panels_options_changed(v);
        view_redraw(v);
        return TRUE;
    }
    switch ((view_action)action) {
    case ACTION_PLAY:
        set_playing(v, !v->play.playing);
        return TRUE;
    case ACTION_PREVIOUS_FRAME:
    case ACTION_NEXT_FRAME:
        set_playing(v, false);
        /* from the frame the time is in (3.034 s at 24 fps is in frame 72: on to 73, back to 71) */
        set_time(v, (frame_at(v, v->play.time) + (action == ACTION_NEXT_FRAME ? 1 : -1)) / view_frame_rate(v));
        return TRUE;
    case ACTION_FIRST:
        set_time(v, 0.0);
        return TRUE;
    case ACTION_LAST:
        set_time(v, view_duration(v));
        return TRUE;
    case ACTION_FRAME_ALL:
        frame_all(v);
        view_redraw(v);
        return TRUE;
    case ACTION_CAMERA_MODE:
        sinew_camera_set_mode(&v->look.camera,
                              v->look.camera.mode == SINEW_CAMERA_FLY ? SINEW_CAMERA_ORBIT : SINEW_CAMERA_FLY);
        panels_options_changed(v);
        view_redraw(v);
        return TRUE;
    case ACTION_SHADING:
        settings_option_changed(v, "shading");
        cycle_shading(v);
        panels_options_changed(v);
        view_redraw(v);
        return TRUE;
    case ACTION_PREVIOUS_KEY:
    case ACTION_NEXT_KEY: { /* the nearest key time before or after now, as Blender's Up/Down */
        set_playing(v, false);
        bool next = action == ACTION_NEXT_KEY;
        double to = next ? view_duration(v) : 0.0;
        for (size_t i = 0; i < v->play.key_time_count; i++) {
            double t = v->play.key_times[next ? i : v->play.key_time_count - 1 - i];
            if (next ? t > v->play.time + 1e-5 : t < v->play.time - 1e-5) {
                to = t;
                break;
            }
        }
        set_time(v, to);
        return TRUE;
    }
    case ACTION_CROWD:
        view_toggle_crowd(v, !v->crowd_on);
        return TRUE;
    case ACTION_FOLLOW:
        view_set_follow(v, !v->look.follow);
        return TRUE;
    case ACTION_HELP:
        fill_help(v);
        gtk_widget_set_visible(v->help, !gtk_widget_get_visible(v->help));
        return TRUE;
    case ACTION_SCREENSHOT:
        take_numbered_screenshot(v);
        return TRUE;
    case ACTION_RECORD:
        if (v->rec.recording) {
            stop_recording(v, "F9");
        } else {
            v->rec.record_asked = true; /* at the next draw, which knows the view's size */
            set_playing(v, true);
            view_redraw(v);
        }
        return TRUE;
    case ACTION_VIEW_FRONT:
    case ACTION_VIEW_SIDE:
    case ACTION_VIEW_TOP:
        look_along(v, action == ACTION_VIEW_FRONT  ? SINEW_VIEW_FRONT
                      : action == ACTION_VIEW_SIDE ? SINEW_VIEW_RIGHT
                                                   : SINEW_VIEW_TOP);
        return TRUE;
    case ACTION_RESET_VIEW:
        look_along(v, -1);
        return TRUE;
    case ACTION_ORTHOGRAPHIC:
        v->look.camera.orthographic = !v->look.camera.orthographic;
        panels_options_changed(v);
        view_redraw(v);
        return TRUE;
    case ACTION_PREVIOUS_FILE:
    case ACTION_NEXT_FILE:
        open_neighbour(v, action == ACTION_NEXT_FILE ? 1 : -1);
        return TRUE;
    case ACTION_SKIN_METHOD:
        settings_option_changed(v, "skinning-method");
        /* as the file says -> linear blend -> dual quaternion -> as the file says */
        if (!v->options.skin_method_set)
            v->options.skin_method_set = true, v->options.skin_method = SINEW_SKIN_LINEAR;
        else if (v->options.skin_method == SINEW_SKIN_LINEAR)
            v->options.skin_method = SINEW_SKIN_DUAL_QUATERNION;
        else
            v->options.skin_method_set = false, v->options.skin_method = SINEW_SKIN_LINEAR;
        panels_options_changed(v);
        view_redraw(v);
        return TRUE;
    default:
        if (action >= ACTION_FORWARD && v->look.camera.mode == SINEW_CAMERA_FLY) {
            v->look.held[action] = true;
            return TRUE;
        }
        return FALSE;
    }
}

static void on_key_released(GtkEventControllerKey *controller, guint key, guint code, GdkModifierType state,
                            gpointer data)
{
    (void)controller, (void)code, (void)state;
    viewer *v = data;
    int action = settings_action_for_key(v, key);
    if (action >= ACTION_FORWARD)
        v->look.held[action] = false;
}

static void on_drag_begin(GtkGestureDrag *gesture, double x, double y, gpointer data)
{
    (void)x, (void)y;
    viewer *v = data;
    v->look.drag_x = v->look.drag_y = 0.0;
    gtk_widget_grab_focus(v->area);
    GdkModifierType mods = gtk_event_controller_get_current_event_state(GTK_EVENT_CONTROLLER(gesture));
    guint button = gtk_gesture_single_get_current_button(GTK_GESTURE_SINGLE(gesture));
    /* ctrl-drag moves an IK target (Blender's map: ctrl-left; its ctrl-middle zooms) */
    v->pose.ik_dragging = (mods & GDK_CONTROL_MASK) && v->selected >= 0 && v->scene.worlds &&
                          (v->key_map != KEY_MAP_BLENDER || button == GDK_BUTTON_PRIMARY);
    if (v->pose.ik_dragging &&
        !(v->pose.ik_on && v->pose.ik_joint == v->selected)) { /* a new target, where the joint is */
        v->pose.ik_joint = v->selected;
        memcpy(v->pose.ik_target, v->scene.worlds[v->selected].m + 12, sizeof v->pose.ik_target);
    }
}

/* Ctrl-drag: the selected joint's IK target moves in the view's plane; a ctrl-click without
 * moving lets the joint go. */
static void on_drag_end(GtkGestureDrag *gesture, double dx, double dy, gpointer data)
{
    (void)gesture;
    viewer *v = data;
    if (v->pose.ik_dragging && fabs(dx) < 2.0 && fabs(dy) < 2.0 && v->pose.ik_on) {
        v->pose.ik_on = false;
        apply_pose_ops(v, false);
    }
    v->pose.ik_dragging = false;
}

static void on_drag_update(GtkGestureDrag *gesture, double dx, double dy, gpointer data)
{
    viewer *v = data;
    GdkModifierType mods = gtk_event_controller_get_current_event_state(GTK_EVENT_CONTROLLER(gesture));
    guint button = gtk_gesture_single_get_current_button(GTK_GESTURE_SINGLE(gesture));
    double ddx = dx - v->look.drag_x, ddy = dy - v->look.drag_y;
    v->look.drag_x = dx, v->look.drag_y = dy;
    float h = (float)fmax(1, gtk_widget_get_height(v->area));
    if (v->pose.ik_dragging) {
        float right[3], up[3], eye[3];
        sinew_camera_basis(&v->look.camera, NULL, right, up);
        sinew_camera_eye(&v->look.camera, eye);
        float fov = v->look.camera.fov_y > 0.0f ? v->look.camera.fov_y : 0.785398f;
        float depth = sqrtf((eye[0] - v->pose.ik_target[0]) * (eye[0] - v->pose.ik_target[0]) +
                            (eye[1] - v->pose.ik_target[1]) * (eye[1] - v->pose.ik_target[1]) +
                            (eye[2] - v->pose.ik_target[2]) * (eye[2] - v->pose.ik_target[2]));
        float per_pixel = 2.0f * depth * tanf(0.5f * fov) / h;
        for (int k = 0; k < 3; k++)
            v->pose.ik_target[k] += (float)ddx * per_pixel * right[k] - (float)ddy * per_pixel * up[k];
        /* the drag's chain is the last: its target moves in place once the character has it */
        uint32_t chain = (uint32_t)v->pose.pose_ops.ik_count;
        if (v->pose.ik_on && v->scene.ops.ik_count == chain + 1 &&
            v->scene.ops.ik_end[chain] == (uint32_t)v->pose.ik_joint &&
            app_scene_set_ik_target(&v->scene, chain, v->pose.ik_target)) {
            view_redraw(v);
            return;
        }
        v->pose.ik_on = true;
        apply_pose_ops(v, false);
        return;
    }
    bool blender = v->key_map == KEY_MAP_BLENDER;
    if (v->look.camera.mode == SINEW_CAMERA_FLY) {
        if (button == GDK_BUTTON_SECONDARY || button == GDK_BUTTON_PRIMARY || (blender && button == GDK_BUTTON_MIDDLE))
            sinew_camera_rotate(&v->look.camera, -(float)ddx * 0.005f, -(float)ddy * 0.005f);
    } else if (blender && button != GDK_BUTTON_MIDDLE) {
        return; /* Blender: the left button selects, the right opens menus; the middle one moves the view */
    } else if (blender && (mods & GDK_CONTROL_MASK)) {
        sinew_camera_zoom(&v->look.camera, expf((float)ddy * 0.005f));
    } else if (button == GDK_BUTTON_MIDDLE ? !blender || (mods & GDK_SHIFT_MASK) : (mods & GDK_SHIFT_MASK) != 0) {
        float fov = v->look.camera.fov_y > 0.0f ? v->look.camera.fov_y : 0.785398f;
        float per_pixel = 2.0f * v->look.camera.distance * tanf(0.5f * fov) / h;
        sinew_camera_pan(&v->look.camera, -(float)ddx * per_pixel, (float)ddy * per_pixel);
    } else {
        sinew_camera_rotate(&v->look.camera, -(float)ddx * 0.01f, (float)ddy * 0.01f);
    }
    gtk_gl_area_queue_render(GTK_GL_AREA(v->area));
}

static gboolean on_scroll(GtkEventControllerScroll *controller, double dx, double dy, gpointer data)
{
    (void)controller, (void)dx;
    viewer *v = data;
    sinew_camera_zoom(&v->look.camera, dy > 0 ? 1.1f : 1.0f / 1.1f);
    gtk_gl_area_queue_render(GTK_GL_AREA(v->area));
    return TRUE;
}

static gboolean on_drop(GtkDropTarget *target, const GValue *value, double x, double y, gpointer data)
{
    (void)target, (void)x, (void)y;
    viewer *v = data;
    if (!G_VALUE_HOLDS(value, G_TYPE_FILE))
        return FALSE;
    char *path = g_file_get_path(g_value_get_object(value));
    if (path)
        view_open_other(v, path);
    g_free(path);
    return path != NULL;
}

static void on_open_response(GtkNativeDialog *dialog, int response, gpointer data)
{
    viewer *v = data;
    if (response == GTK_RESPONSE_ACCEPT) {
        GFile *file = gtk_file_chooser_get_file(GTK_FILE_CHOOSER(dialog));
        char *path = file ? g_file_get_path(file) : NULL;
        if (path)
            view_open_other(v, path);
        g_free(path);
        if (file)
            g_object_unref(file);
    }
    g_object_unref(dialog);
}

static void on_open(GtkButton *button, gpointer data)
{
    (void)button;
    viewer *v = data;
    GtkFileChooserNative *dialog = gtk_file_chooser_native_new("Open a model", GTK_WINDOW(v->window),
                                                               GTK_FILE_CHOOSER_ACTION_OPEN, "_Open", "_Cancel");
    GtkFileFilter *models = gtk_file_filter_new();
    gtk_file_filter_set_name(models, "Animated models");
    /* suffixes match in any case (GTK 4.4): WALK.BVH as walk.bvh */
    static const char *const suffixes[] = {"dae", "gltf", "glb", "fbx", "bvh", "x", "md5mesh", "smd", "iqm", "sinew"};
    for (size_t i = 0; i < sizeof suffixes / sizeof suffixes[0]; i++)
        gtk_file_filter_add_suffix(models, suffixes[i]);
    gtk_file_chooser_add_filter(GTK_FILE_CHOOSER(dialog), models);
    GtkFileFilter *all = gtk_file_filter_new();
    gtk_file_filter_set_name(all, "All files");
    gtk_file_filter_add_pattern(all, "*");
    gtk_file_chooser_add_filter(GTK_FILE_CHOOSER(dialog), all);
    if (v->last_folder) {
        GFile *folder = g_file_new_for_path(v->last_folder);
        gtk_file_chooser_set_current_folder(GTK_FILE_CHOOSER(dialog), folder, NULL);
        g_object_unref(folder);
    }
    g_signal_connect(dialog, "response", G_CALLBACK(on_open_response), v);
    gtk_native_dialog_show(GTK_NATIVE_DIALOG(dialog));
}

static void on_cancel_open(GtkButton *button, gpointer data)
{
    (void)button;
    viewer *v = data;
    if (v->load)
        gtk_label_set_text(GTK_LABEL(v->load_label), "Cancelling…");
    view_cancel_open(v, false);
}

static void on_close_error(GtkButton *button, gpointer data)
{
    (void)button;
    view_show_error(data, NULL);
}

/* ---- window --------------------------------------------------------------------------------- */

/* Remembers the window's size for the settings file. */
static gboolean on_close_request(GtkWindow *window, gpointer data)
{
    viewer *v = data;
    gtk_window_get_default_size(window, &v->width, &v->height);
    /* The widgets go next: their last signals (a list row deselected, a check unset) must not
     * reach the handlers, which would draw into or query widgets half destroyed. */
    stop_recording(v, "the window closed");
    v->updating = true;
    v->closing = true;
    return FALSE;
}

typedef struct startup {
    viewer *v;
    const char *path, *clip;
    int width, height;
    int panel; /* page of the side panel shown first */
} startup;

/* A bar above the view (an error, a file opening): its button at the end, hidden until needed. */
static void end_bar(GtkWidget *box, GtkWidget *bar, GtkWidget *button, GCallback on_click, viewer *v)
{
    g_signal_connect(button, "clicked", on_click, v);
    gtk_box_append(GTK_BOX(bar), button);
    gtk_widget_set_visible(bar, FALSE);
    gtk_box_append(GTK_BOX(box), bar);
}

/* The header bar: Open and the Recent menu. */
static void build_header(viewer *v)
{
    GtkWidget *header = gtk_header_bar_new();
    GtkWidget *open = gtk_button_new_with_mnemonic("_Open…");
    g_signal_connect(open, "clicked", G_CALLBACK(on_open), v);
    gtk_header_bar_pack_start(GTK_HEADER_BAR(header), open);
    v->recent_menu = g_menu_new();
    view_recent_changed(v);
    GtkWidget *recent = gtk_menu_button_new();
    gtk_menu_button_set_label(GTK_MENU_BUTTON(recent), "Recent");
    gtk_menu_button_set_menu_model(GTK_MENU_BUTTON(recent), G_MENU_MODEL(v->recent_menu));
    gtk_header_bar_pack_start(GTK_HEADER_BAR(header), recent);
    static const GActionEntry actions[] = {{.name = "open-recent", .activate = on_open_recent, .parameter_type = "s"}};
    g_action_map_add_action_entries(G_ACTION_MAP(v->window), actions, 1, v);
    gtk_window_set_titlebar(GTK_WINDOW(v->window), header);
}

/* The error bar and the bar of a file being opened (what, how long, how far, and Cancel). */
static void build_bars(viewer *v, GtkWidget *box)
{
    v->error_bar = gtk_box_new(GTK_ORIENTATION_HORIZONTAL, 6);
    gtk_widget_add_css_class(v->error_bar, "sinew-error");
    GtkCssProvider *css = gtk_css_provider_new();
    gtk_css_provider_load_from_data(css,
                                    ".sinew-error { background: #c01c28; color: white; }\n"
                                    ".sinew-help { background: rgba(20, 22, 26, 0.82); color: #e8e8e8; padding: 10px; "
                                    "border-radius: 6px; }",
                                    -1);
    gtk_style_context_add_provider_for_display(gdk_display_get_default(), GTK_STYLE_PROVIDER(css),
                                               GTK_STYLE_PROVIDER_PRIORITY_APPLICATION);
    g_object_unref(css);
    v->error_label = gtk_label_new("");
    gtk_label_set_wrap(GTK_LABEL(v->error_label), TRUE);
    gtk_label_set_selectable(GTK_LABEL(v->error_label), TRUE);
    gtk_widget_set_hexpand(v->error_label, TRUE);
    gtk_label_set_xalign(GTK_LABEL(v->error_label), 0.0f);
    gtk_widget_set_margin_start(v->error_label, 8);
    gtk_box_append(GTK_BOX(v->error_bar), v->error_label);
    end_bar(box, v->error_bar, gtk_button_new_from_icon_name("window-close-symbolic"), G_CALLBACK(on_close_error), v);

    v->load_bar = gtk_box_new(GTK_ORIENTATION_HORIZONTAL, 8);
    gtk_widget_set_margin_start(v->load_bar, 8);
    gtk_widget_set_margin_end(v->load_bar, 4);
    v->load_label = gtk_label_new("");
    gtk_label_set_ellipsize(GTK_LABEL(v->load_label), PANGO_ELLIPSIZE_MIDDLE);
    gtk_box_append(GTK_BOX(v->load_bar), v->load_label);
    v->load_progress = gtk_progress_bar_new();
    gtk_widget_set_hexpand(v->load_progress, TRUE);
    gtk_widget_set_valign(v->load_progress, GTK_ALIGN_CENTER);
    gtk_box_append(GTK_BOX(v->load_bar), v->load_progress);
    end_bar(box, v->load_bar, gtk_button_new_with_mnemonic("_Cancel"), G_CALLBACK(on_cancel_open), v);
}

/* The GL area with its mouse, scroll, drop and key controllers, under the key cheat sheet (H). */
static GtkWidget *build_view(viewer *v)
{
    v->area = gtk_gl_area_new();
    gtk_gl_area_set_required_version(GTK_GL_AREA(v->area), 3, 3);
    gtk_gl_area_set_has_depth_buffer(GTK_GL_AREA(v->area), TRUE);
    gtk_widget_set_vexpand(v->area, TRUE);
    gtk_widget_set_focusable(v->area, TRUE);
    g_signal_connect(v->area, "realize", G_CALLBACK(on_realize), v);
    g_signal_connect(v->area, "unrealize", G_CALLBACK(on_unrealize), v);
    g_signal_connect(v->area, "render", G_CALLBACK(on_render), v);
    GtkGesture *drag = gtk_gesture_drag_new();
    gtk_gesture_single_set_button(GTK_GESTURE_SINGLE(drag), 0);
    g_signal_connect(drag, "drag-begin", G_CALLBACK(on_drag_begin), v);
    g_signal_connect(drag, "drag-update", G_CALLBACK(on_drag_update), v);
    g_signal_connect(drag, "drag-end", G_CALLBACK(on_drag_end), v);
    gtk_widget_add_controller(v->area, GTK_EVENT_CONTROLLER(drag));
    GtkEventController *scroll = gtk_event_controller_scroll_new(GTK_EVENT_CONTROLLER_SCROLL_VERTICAL);
    g_signal_connect(scroll, "scroll", G_CALLBACK(on_scroll), v);
    gtk_widget_add_controller(v->area, scroll);
    GtkDropTarget *drop = gtk_drop_target_new(G_TYPE_FILE, GDK_ACTION_COPY);
    g_signal_connect(drop, "drop", G_CALLBACK(on_drop), v);
    gtk_widget_add_controller(v->window, GTK_EVENT_CONTROLLER(drop));
    GtkEventController *keys = gtk_event_controller_key_new();
    gtk_event_controller_set_propagation_phase(keys, GTK_PHASE_CAPTURE);
    g_signal_connect(keys, "key-pressed", G_CALLBACK(on_key), v);
    g_signal_connect(keys, "key-released", G_CALLBACK(on_key_released), v);
    gtk_widget_add_controller(v->window, keys);
    GtkWidget *overlay = gtk_overlay_new(); /* the key cheat sheet (H) over the view */
    gtk_overlay_set_child(GTK_OVERLAY(overlay), v->area);
    v->help = gtk_label_new("");
    gtk_widget_add_css_class(v->help, "sinew-help");
    gtk_widget_set_halign(v->help, GTK_ALIGN_START);
    gtk_widget_set_valign(v->help, GTK_ALIGN_START);
    gtk_widget_set_margin_start(v->help, 12);
    gtk_widget_set_margin_top(v->help, 12);
    gtk_widget_set_can_target(v->help, FALSE);
    gtk_widget_set_visible(v->help, FALSE);
    gtk_overlay_add_overlay(GTK_OVERLAY(overlay), v->help);
    return overlay;
}

/* The timeline: play, scrub, time and frame number. */
static void build_timeline(viewer *v, GtkWidget *box)
{
    GtkWidget *bar = gtk_box_new(GTK_ORIENTATION_HORIZONTAL, 6);
    gtk_widget_set_margin_start(bar, 6);
    gtk_widget_set_margin_end(bar, 6);
    gtk_widget_set_margin_top(bar, 4);
    v->play_button = gtk_button_new_from_icon_name("media-playback-start-symbolic");
    gtk_widget_set_tooltip_text(v->play_button, "Play / pause (Space)");
    g_signal_connect(v->play_button, "clicked", G_CALLBACK(on_play), v);
    gtk_box_append(GTK_BOX(bar), v->play_button);
    v->scale = gtk_scale_new_with_range(GTK_ORIENTATION_HORIZONTAL, 0.0, 1.0, 1.0 / FRAME_RATE);
    gtk_scale_set_draw_value(GTK_SCALE(v->scale), FALSE);
    gtk_widget_set_hexpand(v->scale, TRUE);
    g_signal_connect(v->scale, "value-changed", G_CALLBACK(on_scrub), v);
    gtk_box_append(GTK_BOX(bar), v->scale);
    v->time_label = gtk_label_new("");
    gtk_box_append(GTK_BOX(bar), v->time_label);
    gtk_box_append(GTK_BOX(bar), gtk_label_new("Frame"));
    v->frame_spin = gtk_spin_button_new_with_range(0.0, 1.0, 1.0);
    gtk_spin_button_set_digits(GTK_SPIN_BUTTON(v->frame_spin), 0);
    gtk_widget_set_tooltip_text(v->frame_spin, "Go to a frame (at the clip's key rate)");
    g_signal_connect(v->frame_spin, "value-changed", G_CALLBACK(on_frame_entry), v);
    gtk_box_append(GTK_BOX(bar), v->frame_spin);
    gtk_box_append(GTK_BOX(box), bar);
}

/* Clip, speed, direction, play mode and the status line. */
static void build_controls(viewer *v, GtkWidget *box)
{
    GtkWidget *controls = gtk_box_new(GTK_ORIENTATION_HORIZONTAL, 6);
    gtk_widget_set_margin_start(controls, 6);
    gtk_widget_set_margin_end(controls, 6);
    gtk_widget_set_margin_bottom(controls, 4);
    gtk_box_append(GTK_BOX(controls), gtk_label_new("Clip"));
    v->clip_list = gtk_drop_down_new(NULL, NULL);
    g_signal_connect(v->clip_list, "notify::selected", G_CALLBACK(on_clip), v);
    gtk_box_append(GTK_BOX(controls), v->clip_list);
    gtk_box_append(GTK_BOX(controls), gtk_label_new("Speed"));
    GtkWidget *speed = gtk_spin_button_new_with_range(0.1, 4.0, 0.1);
    gtk_spin_button_set_value(GTK_SPIN_BUTTON(speed), v->play.speed);
    g_signal_connect(speed, "value-changed", G_CALLBACK(on_speed), v);
    gtk_box_append(GTK_BOX(controls), speed);
    GtkWidget *reverse = gtk_toggle_button_new_with_label("Reverse");
    g_signal_connect(reverse, "toggled", G_CALLBACK(on_reverse), v);
    gtk_box_append(GTK_BOX(controls), reverse);
    static const char *const modes[] = {"Loop", "Once", "Ping-pong", "All clips", NULL};
    GtkWidget *mode = gtk_drop_down_new_from_strings(modes);
    g_signal_connect(mode, "notify::selected", G_CALLBACK(on_mode), v);
    gtk_box_append(GTK_BOX(controls), mode);
    v->status = gtk_label_new("");
    gtk_widget_set_hexpand(v->status, TRUE);
    gtk_label_set_xalign(GTK_LABEL(v->status), 1.0f);
    gtk_label_set_ellipsize(GTK_LABEL(v->status), PANGO_ELLIPSIZE_END);
    gtk_box_append(GTK_BOX(controls), v->status);
    gtk_box_append(GTK_BOX(box), controls);
}

static void on_activate(GtkApplication *app, gpointer data)
{
    startup *s = data;
    viewer *v = s->v;
    v->window = gtk_application_window_new(app);
    gtk_window_set_default_size(GTK_WINDOW(v->window), s->width, s->height);
    g_signal_connect(v->window, "close-request", G_CALLBACK(on_close_request), v);
    build_header(v);

    GtkWidget *box = gtk_box_new(GTK_ORIENTATION_VERTICAL, 0);
    build_bars(v, box);
    GtkWidget *overlay = build_view(v);

    GtkWidget *paned = gtk_paned_new(GTK_ORIENTATION_HORIZONTAL);
    gtk_paned_set_start_child(GTK_PANED(paned), overlay);
    GtkWidget *panels = v->panels = panels_create(v);
    gtk_paned_set_end_child(GTK_PANED(paned), panels);
    gtk_paned_set_resize_end_child(GTK_PANED(paned), FALSE);
    gtk_paned_set_shrink_end_child(GTK_PANED(paned), FALSE);
    gtk_widget_set_vexpand(paned, TRUE);
    gtk_box_append(GTK_BOX(box), paned);
    build_timeline(v, box);
    build_controls(v, box);

    gtk_window_set_child(GTK_WINDOW(v->window), box);

    /* The demo first (--anim's clips on it only when it is what is shown); a file given opens on
     * a worker thread and replaces it, or its error shows above the demo. --camera's view is the
     * file's then (the demo's open used to spend it, and a fly camera was framed away). */
    int camera_keep = v->look.camera_keep;
    v->placeholder = s->path != NULL;
    bool demo = view_open_now(v, APP_BUILTIN_DEMO, s->path ? NULL : s->clip, !s->path);
    v->placeholder = false;
    if (demo && !s->path && !isnan(v->play.start_time)) {
        v->play.time = v->play.start_time;
        if (v->play.time > view_duration(v))
            v->play.time = view_duration(v);
    }
    if (s->path) {
        v->look.camera_keep = camera_keep;
        view_open_file(v, s->path, s->clip);
    } else
        v->play.start_time = NAN;
    view_show_time(v);
    set_playing(v, v->screenshot == NULL);
    gtk_widget_add_tick_callback(v->area, on_tick, v, NULL);
    /* the page asked for once the panel is in the window (switching pages moves the focus, which
     * GTK looks up in the window: before, it logs a gtk_root_get_focus CRITICAL) */
    gtk_notebook_set_current_page(GTK_NOTEBOOK(panels), s->panel);
    if (v->quit_after > 0.0)
        g_timeout_add((guint)(v->quit_after * 1000.0), close_window, v);
    gtk_window_present(GTK_WINDOW(v->window));
}

static const char usage[] =
    "usage: sinew-view [FILE] [--clip C] [--time T] [--camera SPEC] [display options] [--size WxH]\n"
    "                  [--crowd N] [--watch] [--screenshot OUT.png] [--quit | --quit-after S]\n"
    "\n"
    "Opens FILE (any format sinew reads, or a .sinew; without one, the built-in demo humanoid) and plays its\n"
    "clip. Open… or drop a file on the window to open another; a file that fails shows its error above the\n"
    "scene, which stays. Space plays and pauses, Left/Right step a frame (at the clip's key rate, else 1/30 s),\n"
    "Up/Down jump to the next/previous key, Home/End go to the ends (the clip list ends with the rest pose,\n"
    "--clip none);\n"
    "drag rotates, shift-drag or middle-drag pans, the wheel zooms, F frames all; Tab switches to the fly\n"
    "camera (W/A/S/D, Q/E, drag to look) and back. Keys 1-9, 0 and M toggle the display switches (see the\n"
    "Display panel), Shift+H hides the meshes, K cycles the skinning method (as the file says, linear blend,\n"
    "dual quaternion), C a crowd of the model, T has the camera follow the model (a capture that walks away\n"
    "stays in view). H shows every key; F12 saves a numbered screenshot, F9 records the clip to MP4\n"
    "(ffmpeg); keypad 1/3/7 look from the front, side and top, keypad 5 switches to a parallel projection,\n"
    "R resets the view; Page Up/Down open the previous/next\n"
    "file in the folder; the clip list's play mode \"All clips\" plays them in turn. Settings:\n"
    "~/.config/sinew/settings.ini ([display], [view], [window], [files], [keys]); the options below override them for\n"
    "the run.\n"
    "\n"
    "  --clip C, --time T, --camera orbit:YAW,PITCH[,DIST] | fly:X,Y,Z,YAW,PITCH, --select JOINT,\n"
    "  --heatmap JOINT and the display options (--skeleton, --no-grid, --wireframe, --shading flat, ...)\n"
    "                        as `sinew render` takes them (see `sinew render --help`)\n"
    "  --size WxH            the window's size (default: as last closed, else 1200x760)\n"
    "  --panel NAME          the side panel's page shown first: hierarchy, display, shape-keys (each morph\n"
    "                        channel's weight live, a check and slider to set it by hand) or log\n"
    "  --track               the camera follows the clip's root over the ground (the node --root-motion\n"
    "                        takes: a capture's hips), as key T switches and `sinew render --track` does\n"
    "  --crowd N             shows N characters of the model on a grid, each at its own time (key C\n"
    "                        toggles a crowd of 100, or of N)\n"
    "  --blend C:W,C:W, --additive C:W, --crossfade A,B,T, --ik JOINT:X,Y,Z, --root-motion\n"
    "                        combine clips as `sinew pose --help` says\n"
    "  --anim OTHER          OTHER's clips retargeted onto each file opened (--name-map M.json: joint names)\n"
    "  --up [+|-]X|Y|Z       which of the file's axes is up (z: files modelled Z up that do not say so)\n"
    "  --hdri FILE.hdr       the environment lighting physically based shading (default: the built-in studio)\n"
    "  --samples N           anti-aliasing: N samples a pixel (default 4; 1 = off)\n"
    "  --key-map sinew|blender  Blender's: Home frames all, middle-drag orbits, shift-middle pans,\n"
    "                        ctrl-middle zooms, Shift+Left/Right first/last frame\n";
static const char usage_more[] =
    "  --watch               reloads FILE when it changes on disk (keeping the clip, time and camera)\n"
    "  --screenshot OUT.png  writes the first frame drawn (the drawing area only)\n"
    "  --screenshot-window OUT.png  writes the whole window (the view and the side panel) once drawn\n"
    "  --screenshot-dir DIR  where F12 writes FILE-001.png, ... and F9 records FILE-001.mp4, ... (default: the\n"
    "                        Pictures and Videos folders, else home)\n"
    "  --press KEYS          presses keys (GDK names, comma-separated: h,KP_1,F12) once FILE is open and drawn\n"
    "  --camera-position X,Y,Z, --camera-focal-point X,Y,Z\n"
    "                        the eye and the point it looks at and orbits (world metres, as f3d's)\n"
    "  --fov DEG             vertical field of view (default 45)\n"
    "  --quit                leaves after the screenshot\n"
    "  --quit-after S        leaves S seconds after the window opens (playing meanwhile)\n" APP_IMPORT_OPTIONS_HELP
    "exit status (as sinew's): 0 ok, 1 usage error, 2 FILE failed to open (with --screenshot), 3 no OpenGL 3.3,\n"
    "4 the screenshot could not be written\n"
    "  --version             prints sinew-view's version\n";

int main(int argc, char **argv)
{
    viewer v = {.options = sinew_render_options_default(),
                .play = {.speed = 1.0, .direction = 1, .start_time = NAN},
                .selected = -1,
                .reload_clip = -1,
                .crowd_size = 100};
    settings_defaults(&v);
    settings_load(&v);
    v.look.camera = sinew_camera_default();
    v.look.camera.yaw = 30.0f * (float)G_PI / 180.0f; /* as `sinew render` frames a model */
    v.look.camera.pitch = 15.0f * (float)G_PI / 180.0f;
    startup s = {.v = &v, .width = v.width, .height = v.height};
    for (int i = 1; i < argc; i++) {
        sinew_error error = {0};
        const char *option = NULL;
        int used = app_render_option_parse(&v.options, argc, argv, i, &option, &error);
        int import_used = used == 0 ? app_import_option_parse(&v.import, argc, argv, i, &error) : 0;
        if (used < 0 || import_used < 0) {
            fprintf(stderr, "sinew-view: %s\n", error.message);
            return 1;
        }
        int ops_used = used == 0 && import_used == 0 ? app_pose_option_parse(&v.pose.pose_ops, argc, argv, i) : 0;
        if (ops_used > 0) {
            i += ops_used - 1;
        } else if (import_used > 0) {
            i += import_used - 1;
        } else if (used > 0) {
            int index = settings_option_index(option);
            if (index >= 0)
                v.overridden[index] = true;
            i += used - 1;
        } else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            fputs(usage, stdout);
            fputs(usage_more, stdout);
            return 0;
        } else if (strcmp(argv[i], "--version") == 0) {
            printf("sinew-view %s\n", sinew_version());
            return 0;
        } else if (strcmp(argv[i], "--quit") == 0) {
            v.quit_after_screenshot = true;
        } else if (strcmp(argv[i], "--watch") == 0) {
            v.watch = true;
        } else if (strcmp(argv[i], "--track") == 0) {
            v.look.follow = v.look.follow_given = true;
        } else if (argv[i][0] == '-' && i + 1 < argc) {
            const char *o = argv[i], *value = argv[++i];
            bool frame = true;
            int placed = 0;
            if (strcmp(o, "--clip") == 0) {
                s.clip = value;
            } else if (strcmp(o, "--time") == 0) {
                if (!app_parse_number(value, -APP_MAX_SECONDS, APP_MAX_SECONDS, &v.play.start_time)) {
                    fprintf(stderr, "sinew-view: bad --time \"%s\": expected seconds (within +-%g)\n", value,
                            APP_MAX_SECONDS);
                    return 1;
                }
            } else if (strcmp(o, "--screenshot-window") == 0) {
                v.window_shot = value;
            } else if (strcmp(o, "--screenshot") == 0) {
                v.screenshot = value;
            } else if (strcmp(o, "--screenshot-dir") == 0) {
                v.screenshot_dir = value;
            } else if (strcmp(o, "--press") == 0) {
                v.press = value;
            } else if (strcmp(o, "--anim") == 0) {
                v.anim = value;
            } else if (strcmp(o, "--name-map") == 0) {
                v.name_map = value;
            } else if (strcmp(o, "--hdri") == 0) {
                g_free(v.hdri);
                v.hdri = g_strdup(value);
                v.hdri_given = true;
            } else if (strcmp(o, "--samples") == 0) {
                long n = 0;
                if (!app_parse_integer(value, 1, 16, &n)) {
                    fprintf(stderr, "sinew-view: bad --samples \"%s\": expected 1 (off) to 16\n", value);
                    return 1;
                }
                v.samples = (int)n;
                v.samples_given = true;
            } else if (strcmp(o, "--key-map") == 0) {
                int map = -1;
                for (int m = 0; m < KEY_MAP_COUNT; m++)
                    if (g_ascii_strcasecmp(value, KEY_MAP_NAMES[m]) == 0)
                        map = m;
                if (map < 0) {
                    fprintf(stderr, "sinew-view: bad --key-map \"%s\": expected sinew or blender\n", value);
                    return 1;
                }
                settings_set_key_map(&v, (view_key_map)map);
                v.key_map_given = true;
            } else if (strcmp(o, "--up") == 0) {
                if (!app_up_axis(value, NULL)) {
                    fprintf(stderr, "sinew-view: bad --up \"%s\": expected [+|-]x, y or z\n", value);
                    return 1;
                }
                v.up = value;
            } else if (strcmp(o, "--quit-after") == 0) {
                if (!app_parse_number(value, 0.0, 86400.0, &v.quit_after) || !(v.quit_after > 0.0)) {
                    fprintf(stderr, "sinew-view: bad --quit-after \"%s\": expected seconds in (0, 86400]\n", value);
                    return 1;
                }
            } else if (strcmp(o, "--crowd") == 0) {
                double n = 0;
                if (!app_parse_number(value, 1, APP_CROWD_MAX, &n) || n != floor(n)) {
                    fprintf(stderr, "sinew-view: bad --crowd \"%s\": expected a whole number in 1..%u\n", value,
                            APP_CROWD_MAX);
                    return 1;
                }
                v.crowd_size = (uint32_t)n;
                v.crowd_on = true;
            } else if (strcmp(o, "--panel") == 0) {
                static const char *const pages[] = {"hierarchy", "display", "shape-keys", "log"};
                s.panel = -1;
                for (int p = 0; p < 4; p++)
                    if (strcmp(value, pages[p]) == 0)
                        s.panel = p;
                if (s.panel < 0) {
                    fprintf(stderr, "sinew-view: bad --panel \"%s\": hierarchy, display, shape-keys or log\n", value);
                    return 1;
                }
            } else if (strcmp(o, "--select") == 0) {
                v.select = value;
            } else if (strcmp(o, "--heatmap") == 0) {
                v.heatmap = value;
            } else if (strcmp(o, "--size") == 0) {
                if (!app_parse_size(value, 64, 16384, &s.width, &s.height)) {
                    fprintf(stderr, "sinew-view: bad --size \"%s\": expected WIDTHxHEIGHT, each 64..16384\n", value);
                    return 1;
                }
            } else if ((placed = app_camera_placement_parse(&v.look.placement, o, value, &error)) != 0) {
                if (placed < 0) {
                    fprintf(stderr, "sinew-view: %s\n", error.message);
                    return 1;
                }
                if (v.look.placement.fov > 0.0)
                    v.look.camera.fov_y = (float)(v.look.placement.fov * M_PI / 180.0);
            } else if (strcmp(o, "--camera") == 0) {
                if (app_camera_parse(value, &v.look.camera, &frame, &error) != SINEW_OK) {
                    fprintf(stderr, "sinew-view: %s\n", error.message);
                    return 1;
                }
                v.look.camera_keep = frame ? CAMERA_FRAME : CAMERA_KEEP_GIVEN;
            } else {
                fprintf(stderr, "sinew-view: unknown option %s\n%s%s", o, usage, usage_more);
                return 1;
            }
        } else if (argv[i][0] == '-') {
            fprintf(stderr, "sinew-view: unknown option or missing value %s\n%s%s", argv[i], usage, usage_more);
            return 1;
        } else {
            s.path = argv[i];
        }
    }
    GtkApplication *app = gtk_application_new("org.sinew.View", G_APPLICATION_NON_UNIQUE);
    g_signal_connect(app, "activate", G_CALLBACK(on_activate), &s);
    const char *sliders = getenv("SINEW_VIEW_SLIDERS");
    if (sliders && *sliders)
        v.sliders = g_strdup(sliders);
    int status = g_application_run(G_APPLICATION(app), 1, argv);
    view_cancel_open(&v, true);
    g_object_unref(app);
    settings_save(&v);
    for (int i = 0; i < 10; i++)
        g_free(v.recent[i]);
    app_crowd_close(&v.crowd);
    sinew_jobs_free(v.jobs);
    if (v.monitor)
        g_object_unref(v.monitor);
    free(v.pose.motion_path);
    g_free(v.path);
    free(v.play.key_times);
    app_scene_close(&v.scene);
    g_free(v.settings_path);
    g_free(v.last_folder);
    g_free(v.hdri);
    free(v.hidden);
    return status ? status : v.exit_code;
}
