/* A model posed and drawn off-screen: loading, context, renderer, framing, drawing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

#define FRAMING_SAMPLES 60

static bool resolve_joint(const sinew_model *m, const char *name, const char *option, bool *on, uint32_t *out)
{
    *on = false;
    if (!name)
        return true;
    int32_t node = sinew_model_find_joint(m, name);
    if (node < 0) {
        cli_error("%s: %s \"%s\": no node of that name (see `sinew info`)", m->source, option, name);
        return false;
    }
    *on = true;
    *out = (uint32_t)node;
    return true;
}

/* Whether this warning was printed before in this process (a command that makes several scenes,
 * `bench crowd` one a run, would say the same thing again each time). */
static bool printed_before(const char *text)
{
    static uint64_t seen[64];
    static size_t seen_count;
    uint64_t h = 1469598103934665603ull;
    for (const unsigned char *c = (const unsigned char *)text; *c; c++)
        h = (h ^ *c) * 1099511628211ull;
    for (size_t i = 0; i < seen_count; i++)
        if (seen[i] == h)
            return true;
    if (seen_count < sizeof seen / sizeof *seen)
        seen[seen_count++] = h;
    return false;
}

/* The renderer's warnings not printed yet. */
static void print_warnings(cli_scene *s)
{
    for (; s->warnings_printed < sinew_renderer_warning_count(s->renderer); s->warnings_printed++) {
        const char *text = sinew_renderer_warning(s->renderer, s->warnings_printed);
        if (!printed_before(text))
            fprintf(stderr, "sinew: warning: %s\n", text);
    }
}

static int open_graphics(cli_scene *s, const cli_scene_desc *d)
{
    sinew_error error = {0};
    sinew_headless_desc hd = {.width = d->width, .height = d->height, .samples = d->samples};
    if (sinew_headless_create(&hd, &s->headless, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return error.kind == SINEW_ERROR_INVALID_ARGUMENT ? EXIT_USAGE : EXIT_UNAVAILABLE;
    }
    sinew_renderer_desc rd = {.model = s->model, .max_gpu_joints = d->gpu_joint_limit, .muscles = s->scene.muscle_set};
    if (sinew_renderer_create(&rd, &s->renderer, &error) != SINEW_OK) {
        cli_error("%s: %s", s->model->source, error.message);
        return error.kind == SINEW_ERROR_GRAPHICS ? EXIT_UNAVAILABLE : EXIT_BAD_INPUT;
    }
    print_warnings(s);
    if (d->hdri && sinew_renderer_set_environment(s->renderer, d->hdri, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return EXIT_BAD_INPUT;
    }
    s->gl_name = sinew_renderer_gl_name(s->renderer);
    return EXIT_OK;
}

void cli_scene_muscles(const char *spec, app_scene_desc *desc)
{
    desc->muscles = spec ? APP_MUSCLES_REQUIRED : APP_MUSCLES_NONE;
    desc->muscle_path = spec && spec[0] ? spec : NULL;
}

sinew_result cli_scene_load(app_scene *scene, const app_scene_desc *desc)
{
    app_scene_desc d = *desc;
    d.stderr_fd = STDERR_FILENO;
    d.import = cli_import;
    sinew_error error = {0};
    if (app_scene_open(scene, &d, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return error.kind;
    }
    cli_print_warnings(scene->model);
    return SINEW_OK;
}

/* The crowd: spaced by one character's footprint over its clip, on a job system. */
static int open_crowd(cli_scene *s, const cli_scene_desc *d)
{
    sinew_error error = {0};
    if (sinew_jobs_create(&(sinew_jobs_desc){.threads = d->threads}, &s->jobs, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return EXIT_UNAVAILABLE;
    }
    app_crowd_desc cd = {.model = s->model,
                         .clip = d->scene.clip ? s->clip : NULL,
                         .count = d->crowd,
                         .spacing = app_crowd_spacing(&s->scene, s->renderer, FRAMING_SAMPLES),
                         .jobs = s->jobs};
    if (app_crowd_open(&s->crowd, &cd, &error) != SINEW_OK) {
        cli_error("%s: %s", s->model->source, error.message);
        return EXIT_BAD_INPUT;
    }
    return EXIT_OK;
}

int cli_scene_open(cli_scene *s, const cli_scene_desc *d)
{
    memset(s, 0, sizeof *s);
    s->width = d->width;
    s->height = d->height;
    s->frame_options = d->options;
    s->wrap = d->loop ? SINEW_WRAP_LOOP : SINEW_WRAP_CLAMP;
    s->camera = sinew_camera_default();
    s->camera.yaw = 30.0f * (float)M_PI / 180.0f;
    s->camera.pitch = 15.0f * (float)M_PI / 180.0f;
    s->frame_all = true;
    sinew_error error = {0};
    s->camera.orthographic = d->orthographic;
    s->placement = d->placement;
    if (d->placement.fov > 0.0)
        s->camera.fov_y = (float)(d->placement.fov * M_PI / 180.0);
    if (d->camera && app_camera_parse(d->camera, &s->camera, &s->frame_all, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        if (d->scene.model)
            sinew_model_free(d->scene.model);
        return EXIT_USAGE;
    }
    app_scene_desc ad = d->scene;
    cli_scene_muscles(d->muscles, &ad);
    sinew_result loaded = cli_scene_load(&s->scene, &ad);
    if (loaded != SINEW_OK)
        return loaded == SINEW_ERROR_INVALID_ARGUMENT ? EXIT_USAGE : EXIT_BAD_INPUT; /* a pose spec */
    s->model = s->scene.model;
    s->clip = s->scene.clip;
    sinew_render_options *o = &s->frame_options;
    if (!resolve_joint(s->model, d->select, "--select", &o->select_joint, &o->selected_joint) ||
        !resolve_joint(s->model, d->heatmap, "--heatmap", &o->heatmap, &o->heatmap_joint)) {
        cli_scene_close(s);
        return EXIT_BAD_INPUT;
    }
    /* Nothing to see but a skeleton: show it unless asked not to. */
    if (app_vertex_count(s->model) == 0 && !d->skeleton_set)
        s->frame_options.skeleton = true;
    s->pixels = malloc((size_t)d->width * (size_t)d->height * 4);
    if (!s->pixels) {
        cli_error("out of memory for a %dx%d image", d->width, d->height);
        cli_scene_close(s);
        return EXIT_BAD_INPUT;
    }
    int code = open_graphics(s, d);
    if (code == EXIT_OK && d->crowd)
        code = open_crowd(s, d);
    if (code != EXIT_OK)
        cli_scene_close(s);
    return code;
}

bool cli_scene_pose(cli_scene *s, double time)
{
    sinew_error error = {0};
    if (app_scene_pose(&s->scene, time, s->wrap, &error) != SINEW_OK) {
        cli_error("%s: %s", s->model->source, error.message);
        return false;
    }
    return true;
}

/* Frames the union of the posed bounds at evenly spaced times in [from, to], so that a
 * sequence keeps one camera. An orbit distance or a fly position from --camera is kept. */
bool cli_scene_frame_all(cli_scene *s, double from, double to)
{
    float lo[3], hi[3];
    if (!cli_scene_pose(s, from) || !cli_scene_pose(s, to))
        return false;
    s->frame_options.grid_height = app_scene_ground(&s->scene, s->renderer, FRAMING_SAMPLES);
    app_scene_bounds(&s->scene, s->renderer, from, to, FRAMING_SAMPLES, s->wrap, lo, hi);
    if (s->crowd.count)
        app_crowd_bounds(&s->crowd, lo, hi);
    sinew_camera keep = s->camera;
    sinew_camera_frame(&s->camera, lo, hi, (float)s->width / (float)s->height);
    if (!s->frame_all) {
        if (keep.mode == SINEW_CAMERA_FLY)
            memcpy(s->camera.position, keep.position, sizeof keep.position);
        else
            s->camera.distance = keep.distance;
    }
    app_camera_place(&s->camera, &s->placement);
    return true;
}

bool cli_scene_track(cli_scene *s, double time)
{
    if (!cli_scene_pose(s, time))
        return false;
    app_scene_follow(&s->scene, time, s->wrap, &s->follow, &s->camera);
    return true;
}

bool cli_scene_draw(cli_scene *s, double time)
{
    if (!cli_scene_pose(s, time))
        return false;
    sinew_error error = {0};
    sinew_frame frame = app_scene_frame(&s->scene, &s->camera, &s->frame_options, s->width, s->height);
    if (s->crowd.count) {
        app_crowd_pose(&s->crowd, time);
        frame.crowd_count = s->crowd.count;
        frame.crowd_worlds = s->crowd.worlds;
        frame.jobs = s->jobs;
    }
    if (sinew_renderer_draw(s->renderer, &frame, &error) != SINEW_OK) {
        cli_error("%s: %s", s->model->source, error.message);
        return false;
    }
    print_warnings(s);
    return true;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The median of n values (sorted in place). */
static double median(double *v, int n)
{
    if (n <= 0)
        return 0.0;
    qsort(v, (size_t)n, sizeof *v, compare_doubles);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

bool cli_scene_time_frames(cli_scene *s, int warmup, int frames, double *seconds_per_frame, double *submit_seconds)
{
    double t = 0.0;
    for (int i = 0; i < warmup; i++, t += 1.0 / 60.0)
        if (!cli_scene_draw(s, t))
            return false;
    sinew_headless_finish(s->headless);
    /* each frame finished and timed on its own; the median, since the machines these run on
     * are shared and another process's burst would otherwise land in the mean */
    size_t room = (size_t)(frames > 0 ? frames : 1);
    double *each = malloc(room * 2 * sizeof *each); /* frame times, then their parts before glFinish */
    if (!each)
        return false;
    double *submit = each + room;
    for (int i = 0; i < frames; i++, t += 1.0 / 60.0) {
        double start = cli_now_seconds();
        if (!cli_scene_draw(s, t)) {
            free(each);
            return false;
        }
        submit[i] = cli_now_seconds() - start;
        sinew_headless_finish(s->headless);
        each[i] = cli_now_seconds() - start;
    }
    *seconds_per_frame = median(each, frames);
    if (submit_seconds)
        *submit_seconds = median(submit, frames);
    free(each);
    return true;
}

bool cli_scene_read(cli_scene *s)
{
    sinew_error error = {0};
    if (sinew_headless_read(s->headless, s->pixels, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return false;
    }
    return true;
}

void cli_scene_close(cli_scene *s)
{
    app_crowd_close(&s->crowd);
    sinew_jobs_free(s->jobs);
    sinew_renderer_free(s->renderer);
    sinew_headless_free(s->headless);
    app_scene_close(&s->scene);
    free(s->pixels);
    memset(s, 0, sizeof *s);
}
