/* A model posed and drawn off-screen: loading, context, renderer, framing, drawing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#define FRAMING_SAMPLES 60

static bool resolve_joint(const sinew_model *m, const char *name, const char *option, int32_t *out)
{
    *out = -1;
    if (!name)
        return true;
    *out = sinew_model_find_joint(m, name);
    if (*out < 0) {
        cli_error("%s: %s \"%s\": no node of that name (see `sinew info`)", m->source, option, name);
        return false;
    }
    return true;
}

static int open_graphics(cli_scene *s, const cli_scene_desc *d)
{
    sinew_error error = {0};
    sinew_headless_desc hd = {.width = d->width, .height = d->height, .samples = d->samples};
    if (sinew_headless_create(&hd, &s->headless, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return error.kind == SINEW_ERROR_INVALID_ARGUMENT ? EXIT_USAGE : EXIT_UNAVAILABLE;
    }
    sinew_renderer_desc rd = {.model = s->model, .max_gpu_joints = d->gpu_joint_limit, .muscles = s->muscle_set};
    if (sinew_renderer_create(&rd, &s->renderer, &error) != SINEW_OK) {
        cli_error("%s: %s", s->model->source, error.message);
        return error.kind == SINEW_ERROR_GRAPHICS ? EXIT_UNAVAILABLE : EXIT_BAD_INPUT;
    }
    for (uint32_t i = 0; i < sinew_renderer_warning_count(s->renderer); i++)
        fprintf(stderr, "sinew: warning: %s\n", sinew_renderer_warning(s->renderer, i));
    s->gl_name = sinew_renderer_gl_name(s->renderer);
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
    if (d->camera && app_camera_parse(d->camera, &s->camera, &s->frame_all, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return EXIT_USAGE;
    }
    s->model = d->model ? d->model : cli_load_model(d->path);
    if (!s->model)
        return EXIT_BAD_INPUT;
    int32_t clip = -1;
    if (!cli_pick_clip(s->model, d->clip, &clip) ||
        !resolve_joint(s->model, d->select, "--select", &s->frame_options.selected_joint) ||
        !resolve_joint(s->model, d->heatmap, "--heatmap", &s->frame_options.heatmap_joint)) {
        cli_scene_close(s);
        return EXIT_BAD_INPUT;
    }
    s->clip = clip >= 0 ? &s->model->clips[clip] : NULL;
    /* Nothing to see but a skeleton: show it unless asked not to. */
    if (cli_vertex_count(s->model) == 0 && !d->skeleton_set)
        s->frame_options.skeleton = true;
    if (!cli_pose_init(&s->pose, s->model, s->clip)) {
        cli_scene_close(s);
        return EXIT_BAD_INPUT;
    }
    if (d->muscles) {
        s->muscle_rig = cli_load_muscle_set(s->model, d->muscles, &s->owned_muscles, &s->muscle_set);
        s->muscle_count = sinew_muscle_rig_count(s->muscle_rig);
        sinew_muscle_rig_set_scale(s->muscle_rig, d->muscle_scale);
        s->muscle_poses = calloc(s->muscle_count ? s->muscle_count : 1, sizeof *s->muscle_poses);
        if (!s->muscle_rig || !s->muscle_poses) {
            cli_scene_close(s);
            return EXIT_BAD_INPUT;
        }
    }
    s->pixels = malloc((size_t)d->width * (size_t)d->height * 4);
    if (!s->pixels) {
        cli_error("out of memory for a %dx%d image", d->width, d->height);
        cli_scene_close(s);
        return EXIT_BAD_INPUT;
    }
    int code = open_graphics(s, d);
    if (code != EXIT_OK)
        cli_scene_close(s);
    return code;
}

bool cli_scene_pose(cli_scene *s, double time)
{
    return cli_pose_at(&s->pose, s->clip, (float)time, s->wrap);
}

/* Frames the union of the posed bounds at evenly spaced times in [from, to], so that a
 * sequence keeps one camera. An orbit distance or a fly position from --camera is kept. */
bool cli_scene_frame_all(cli_scene *s, double from, double to)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    int samples = to > from ? FRAMING_SAMPLES : 1;
    for (int i = 0; i < samples; i++) {
        double t = samples > 1 ? from + (to - from) * i / (samples - 1) : from;
        float a[3], b[3];
        if (!cli_scene_pose(s, t))
            return false;
        if (!sinew_renderer_bounds(s->renderer, s->pose.worlds, s->model->node_count, a, b))
            continue;
        for (int k = 0; k < 3; k++)
            lo[k] = fminf(lo[k], a[k]), hi[k] = fmaxf(hi[k], b[k]);
    }
    if (!(lo[0] <= hi[0]))
        for (int k = 0; k < 3; k++)
            lo[k] = -1.0f, hi[k] = 1.0f;
    sinew_camera keep = s->camera;
    sinew_camera_frame(&s->camera, lo, hi, (float)s->width / (float)s->height);
    if (!s->frame_all) {
        if (keep.mode == SINEW_CAMERA_FLY)
            memcpy(s->camera.position, keep.position, sizeof keep.position);
        else
            s->camera.distance = keep.distance;
    }
    return true;
}

bool cli_scene_track(cli_scene *s, double time)
{
    float lo[3], hi[3];
    if (!cli_scene_pose(s, time))
        return false;
    if (!sinew_renderer_bounds(s->renderer, s->pose.worlds, s->model->node_count, lo, hi))
        return true;
    float *moved = s->camera.mode == SINEW_CAMERA_ORBIT ? s->camera.target : s->camera.position;
    for (int k = 0; k < 3; k++) {
        float centre = 0.5f * (lo[k] + hi[k]);
        float delta = centre - s->track_centre[k];
        if (s->tracking)
            moved[k] += delta;
        s->track_centre[k] = centre;
    }
    s->tracking = true;
    return true;
}

bool cli_scene_draw(cli_scene *s, double time)
{
    if (!cli_scene_pose(s, time))
        return false;
    sinew_error error = {0};
    if (s->muscle_rig && sinew_muscle_rig_update(s->muscle_rig, s->pose.worlds, s->model->node_count, s->muscle_poses,
                                                 s->muscle_count, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return false;
    }
    sinew_frame frame = {.worlds = s->pose.worlds,
                         .world_count = s->model->node_count,
                         .camera = &s->camera,
                         .width = s->width,
                         .height = s->height,
                         .options = &s->frame_options,
                         .muscles = s->muscle_poses,
                         .muscle_count = s->muscle_count};
    if (sinew_renderer_draw(s->renderer, &frame, &error) != SINEW_OK) {
        cli_error("%s: %s", s->model->source, error.message);
        return false;
    }
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
    sinew_renderer_destroy(s->renderer);
    sinew_headless_destroy(s->headless);
    cli_pose_free(&s->pose);
    if (s->model)
        sinew_model_free(s->model);
    free(s->pixels);
    free(s->muscle_poses);
    sinew_muscle_rig_free(s->muscle_rig);
    sinew_muscle_set_free(s->owned_muscles);
    memset(s, 0, sizeof *s);
}
