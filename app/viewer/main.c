/* sinew-view: the desktop viewer (GTK 4), first cut: a GtkGLArea running sinew's renderer on
 * a model (FILE, or the built-in demo humanoid), playing its clip on a clock independent of
 * the frame rate, a play button and a scrub bar with the time, orbit camera (drag to rotate,
 * shift-drag or middle-drag to pan, wheel to zoom, F to frame all), Space to play/pause,
 * and `--screenshot OUT.png --quit` for tests. Work in progress for the viewer issue: no
 * file dialog, hierarchy, display panel, log panel or settings yet. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>
#include <gtk/gtk.h>
#include <stb/stb_image_write.h>

#include "sinew/sinew.h"

typedef struct viewer {
    GtkWidget *window, *area, *scale, *time_label, *play_button;
    const char *path, *clip_name, *screenshot;
    bool quit_after_screenshot;
    sinew_model *model;
    const sinew_clip *clip;
    sinew_player *player;
    sinew_renderer *renderer;
    sinew_mat4 *worlds;
    sinew_camera camera;
    sinew_render_options options;
    double time;        /* clip time, seconds */
    gint64 last_frame;  /* frame clock, microseconds; 0: not playing */
    bool playing, framed, updating_scale;
    double drag_yaw, drag_pitch, drag_x, drag_y;
    char *error;        /* what went wrong, shown in the window */
    int exit_code;
} viewer;

static void set_time_label(viewer *v)
{
    char text[96];
    float duration = v->clip ? v->clip->duration : 0.0f;
    snprintf(text, sizeof text, "%.2f / %.2f s  frame %d", v->time, (double)duration, (int)floor(v->time * 30.0 + 1e-6));
    gtk_label_set_text(GTK_LABEL(v->time_label), text);
    v->updating_scale = true;
    gtk_range_set_value(GTK_RANGE(v->scale), v->time);
    v->updating_scale = false;
}

static bool pose(viewer *v)
{
    sinew_error error = {0};
    return sinew_player_update(v->player, (float)v->time, SINEW_WRAP_LOOP, NULL, v->worlds, v->model->node_count,
                               &error) == SINEW_OK;
}

static void frame_all(viewer *v)
{
    float lo[3], hi[3];
    int w = gtk_widget_get_width(v->area), h = gtk_widget_get_height(v->area);
    if (v->renderer && pose(v) && sinew_renderer_bounds(v->renderer, v->worlds, v->model->node_count, lo, hi))
        sinew_camera_frame(&v->camera, lo, hi, h > 0 ? (float)w / (float)h : 1.0f);
}

static void save_screenshot(viewer *v, int width, int height)
{
    unsigned char *rgb = malloc((size_t)width * height * 3);
    if (!rgb)
        return;
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    stbi_flip_vertically_on_write(1);
    if (!stbi_write_png(v->screenshot, width, height, 3, rgb, width * 3)) {
        fprintf(stderr, "sinew-view: %s: cannot write the screenshot\n", v->screenshot);
        v->exit_code = 2;
    }
    free(rgb);
}

static gboolean close_window(gpointer data)
{
    viewer *v = data;
    gtk_window_destroy(GTK_WINDOW(v->window));
    return G_SOURCE_REMOVE;
}

static gboolean on_render(GtkGLArea *area, GdkGLContext *context, gpointer data)
{
    (void)context;
    viewer *v = data;
    int scale = gtk_widget_get_scale_factor(GTK_WIDGET(area));
    int width = gtk_widget_get_width(GTK_WIDGET(area)) * scale, height = gtk_widget_get_height(GTK_WIDGET(area)) * scale;
    if (!v->renderer) {
        glClearColor(0.16f, 0.17f, 0.19f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        return TRUE;
    }
    if (!v->framed) {
        frame_all(v);
        v->framed = true;
    }
    sinew_error error = {0};
    sinew_frame frame = {.worlds = v->worlds,
                         .world_count = v->model->node_count,
                         .camera = &v->camera,
                         .width = width,
                         .height = height,
                         .options = &v->options};
    if (!pose(v) || sinew_renderer_draw(v->renderer, &frame, &error) != SINEW_OK)
        fprintf(stderr, "sinew-view: %s\n", error.message);
    if (v->screenshot) {
        save_screenshot(v, width, height);
        v->screenshot = NULL;
        if (v->quit_after_screenshot) /* not from inside the draw: when GTK is idle */
            g_idle_add(close_window, v);
    }
    return TRUE;
}

static void on_realize(GtkGLArea *area, gpointer data)
{
    viewer *v = data;
    gtk_gl_area_make_current(area);
    if (gtk_gl_area_get_error(area)) {
        fprintf(stderr, "sinew-view: no OpenGL 3.3 context: %s\n", gtk_gl_area_get_error(area)->message);
        v->exit_code = 3;
        return;
    }
    sinew_error error = {0};
    sinew_renderer_desc desc = {.model = v->model};
    if (sinew_renderer_create(&desc, &v->renderer, &error) != SINEW_OK) {
        fprintf(stderr, "sinew-view: %s\n", error.message);
        v->exit_code = 3;
    }
}

static void on_unrealize(GtkGLArea *area, gpointer data)
{
    viewer *v = data;
    gtk_gl_area_make_current(area);
    sinew_renderer_destroy(v->renderer);
    v->renderer = NULL;
}

static gboolean on_tick(GtkWidget *widget, GdkFrameClock *clock, gpointer data)
{
    (void)widget;
    viewer *v = data;
    gint64 now = gdk_frame_clock_get_frame_time(clock);
    if (v->playing && v->clip && v->clip->duration > 0.0f) {
        if (v->last_frame)
            v->time = fmod(v->time + (double)(now - v->last_frame) * 1e-6, v->clip->duration);
        v->last_frame = now;
        set_time_label(v);
        gtk_gl_area_queue_render(GTK_GL_AREA(v->area));
    }
    return G_SOURCE_CONTINUE;
}

static void set_playing(viewer *v, bool playing)
{
    v->playing = playing;
    v->last_frame = 0;
    gtk_button_set_icon_name(GTK_BUTTON(v->play_button),
                             playing ? "media-playback-pause-symbolic" : "media-playback-start-symbolic");
}

static void on_play(GtkButton *button, gpointer data)
{
    (void)button;
    viewer *v = data;
    set_playing(v, !v->playing);
}

static void on_scrub(GtkRange *range, gpointer data)
{
    viewer *v = data;
    if (v->updating_scale)
        return;
    v->time = gtk_range_get_value(range);
    set_time_label(v);
    gtk_gl_area_queue_render(GTK_GL_AREA(v->area));
}

static gboolean on_key(GtkEventControllerKey *controller, guint key, guint code, GdkModifierType state, gpointer data)
{
    (void)controller, (void)code, (void)state;
    viewer *v = data;
    if (key == GDK_KEY_space) {
        set_playing(v, !v->playing);
        return TRUE;
    }
    if (key == GDK_KEY_f || key == GDK_KEY_F) {
        frame_all(v);
        gtk_gl_area_queue_render(GTK_GL_AREA(v->area));
        return TRUE;
    }
    return FALSE;
}

static void on_drag_begin(GtkGestureDrag *gesture, double x, double y, gpointer data)
{
    (void)gesture, (void)x, (void)y;
    viewer *v = data;
    v->drag_x = v->drag_y = 0.0;
}

static void on_drag_update(GtkGestureDrag *gesture, double dx, double dy, gpointer data)
{
    viewer *v = data;
    GdkModifierType mods = gtk_event_controller_get_current_event_state(GTK_EVENT_CONTROLLER(gesture));
    guint button = gtk_gesture_single_get_current_button(GTK_GESTURE_SINGLE(gesture));
    double ddx = dx - v->drag_x, ddy = dy - v->drag_y;
    v->drag_x = dx, v->drag_y = dy;
    float h = (float)fmax(1, gtk_widget_get_height(v->area));
    if (button == GDK_BUTTON_MIDDLE || (mods & GDK_SHIFT_MASK)) {
        float per_pixel = 2.0f * v->camera.distance * tanf(0.5f * (v->camera.fov_y > 0 ? v->camera.fov_y : 0.785f)) / h;
        sinew_camera_pan(&v->camera, -(float)ddx * per_pixel, (float)ddy * per_pixel);
    } else {
        sinew_camera_rotate(&v->camera, -(float)ddx * 0.01f, (float)ddy * 0.01f);
    }
    gtk_gl_area_queue_render(GTK_GL_AREA(v->area));
}

static gboolean on_scroll(GtkEventControllerScroll *controller, double dx, double dy, gpointer data)
{
    (void)controller, (void)dx;
    viewer *v = data;
    sinew_camera_zoom(&v->camera, dy > 0 ? 1.1f : 1.0f / 1.1f);
    gtk_gl_area_queue_render(GTK_GL_AREA(v->area));
    return TRUE;
}

static void on_activate(GtkApplication *app, gpointer data)
{
    viewer *v = data;
    v->window = gtk_application_window_new(app);
    char title[512];
    snprintf(title, sizeof title, "%s — sinew", v->model->source);
    gtk_window_set_title(GTK_WINDOW(v->window), title);
    gtk_window_set_default_size(GTK_WINDOW(v->window), 960, 640);

    GtkWidget *box = gtk_box_new(GTK_ORIENTATION_VERTICAL, 0);
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
    gtk_widget_add_controller(v->area, GTK_EVENT_CONTROLLER(drag));
    GtkEventController *scroll = gtk_event_controller_scroll_new(GTK_EVENT_CONTROLLER_SCROLL_VERTICAL);
    g_signal_connect(scroll, "scroll", G_CALLBACK(on_scroll), v);
    gtk_widget_add_controller(v->area, scroll);
    GtkEventController *keys = gtk_event_controller_key_new();
    g_signal_connect(keys, "key-pressed", G_CALLBACK(on_key), v);
    gtk_widget_add_controller(v->window, keys);
    gtk_box_append(GTK_BOX(box), v->area);

    GtkWidget *bar = gtk_box_new(GTK_ORIENTATION_HORIZONTAL, 6);
    gtk_widget_set_margin_start(bar, 6);
    gtk_widget_set_margin_end(bar, 6);
    v->play_button = gtk_button_new_from_icon_name("media-playback-start-symbolic");
    g_signal_connect(v->play_button, "clicked", G_CALLBACK(on_play), v);
    gtk_box_append(GTK_BOX(bar), v->play_button);
    double duration = v->clip ? v->clip->duration : 0.0;
    v->scale = gtk_scale_new_with_range(GTK_ORIENTATION_HORIZONTAL, 0.0, duration > 0 ? duration : 1.0, 1.0 / 30.0);
    gtk_scale_set_draw_value(GTK_SCALE(v->scale), FALSE);
    gtk_widget_set_hexpand(v->scale, TRUE);
    g_signal_connect(v->scale, "value-changed", G_CALLBACK(on_scrub), v);
    gtk_box_append(GTK_BOX(bar), v->scale);
    v->time_label = gtk_label_new("");
    gtk_box_append(GTK_BOX(bar), v->time_label);
    gtk_box_append(GTK_BOX(box), bar);
    gtk_window_set_child(GTK_WINDOW(v->window), box);
    set_time_label(v);
    set_playing(v, v->screenshot == NULL);
    gtk_widget_add_tick_callback(v->area, on_tick, v, NULL);
    gtk_window_present(GTK_WINDOW(v->window));
}

static const char usage[] =
    "usage: sinew-view [FILE] [--clip C] [--time T] [--screenshot OUT.png] [--quit]\n"
    "\n"
    "Opens FILE (any format sinew reads; the built-in demo humanoid without one) and plays its clip.\n"
    "Space plays and pauses; drag rotates, shift-drag or middle-drag pans, the wheel zooms, F frames all.\n"
    "  --screenshot OUT.png  writes the first frame drawn; --quit then closes the viewer\n";

int main(int argc, char **argv)
{
    viewer v = {.options = sinew_render_options_default()};
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            fputs(usage, stdout);
            return 0;
        } else if (strcmp(argv[i], "--clip") == 0 && i + 1 < argc) {
            v.clip_name = argv[++i];
        } else if (strcmp(argv[i], "--time") == 0 && i + 1 < argc) {
            v.time = atof(argv[++i]);
        } else if (strcmp(argv[i], "--screenshot") == 0 && i + 1 < argc) {
            v.screenshot = argv[++i];
        } else if (strcmp(argv[i], "--quit") == 0) {
            v.quit_after_screenshot = true;
        } else if (argv[i][0] == '-') {
            fprintf(stderr, "sinew-view: unknown option %s\n%s", argv[i], usage);
            return 1;
        } else {
            v.path = argv[i];
        }
    }
    sinew_error error = {0};
    sinew_result result = v.path ? sinew_import(&(sinew_import_desc){.path = v.path}, &v.model, &error)
                                 : sinew_demo_humanoid(&v.model, &error);
    if (result != SINEW_OK) {
        fprintf(stderr, "sinew-view: %s\n", error.message);
        return 2;
    }
    int32_t clip = v.clip_name ? sinew_model_find_clip(v.model, v.clip_name) : (v.model->clip_count ? 0 : -1);
    if (v.clip_name && clip < 0) {
        fprintf(stderr, "sinew-view: %s: no clip \"%s\"\n", v.model->source, v.clip_name);
        sinew_model_free(v.model);
        return 2;
    }
    v.clip = clip >= 0 ? &v.model->clips[clip] : NULL;
    v.worlds = malloc((v.model->node_count + 1) * sizeof *v.worlds);
    v.camera = sinew_camera_default();
    if (!v.worlds || sinew_player_create(v.model, v.clip, &v.player, &error) != SINEW_OK) {
        fprintf(stderr, "sinew-view: %s\n", error.message);
        return 2;
    }
    GtkApplication *app = gtk_application_new("org.sinew.View", G_APPLICATION_NON_UNIQUE);
    g_signal_connect(app, "activate", G_CALLBACK(on_activate), &v);
    int status = g_application_run(G_APPLICATION(app), 1, argv);
    g_object_unref(app);
    sinew_player_free(v.player);
    free(v.worlds);
    sinew_model_free(v.model);
    return status ? status : v.exit_code;
}
