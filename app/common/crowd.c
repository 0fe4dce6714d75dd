/* Many characters of one model on a grid (crowd.h). */
#include "crowd.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The grid cell of character i of a grid of `count` in `columns`, centred on the origin. */
static void grid_cell(uint32_t count, uint32_t columns, float spacing, uint32_t i, float *x, float *z)
{
    uint32_t rows = (count + columns - 1) / columns;
    *x = ((float)(i % columns) - 0.5f * (float)(columns - 1)) * spacing;
    *z = ((float)(i / columns) - 0.5f * (float)(rows - 1)) * spacing;
}

static void cell(const app_crowd *c, uint32_t i, float *x, float *z)
{
    grid_cell(c->count, c->columns, c->spacing, i, x, z);
}

sinew_result app_crowd_open(app_crowd *c, const app_crowd_desc *d, sinew_error *error)
{
    memset(c, 0, sizeof *c);
    if (!d->model || d->count == 0 || d->count > APP_CROWD_MAX)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "a crowd needs 1 to %u characters, not %u",
                          APP_CROWD_MAX, d->count);
    const sinew_model *m = d->model;
    c->model = m;
    c->clip = d->clip;
    c->count = d->count;
    c->columns = (uint32_t)ceil(sqrt((double)d->count));
    c->spacing = d->spacing > 0.0f ? d->spacing : 1.0f;
    c->jobs = d->jobs;
    c->layout_count = d->clip || m->clip_count == 0 ? 1 : m->clip_count;
    c->layouts = calloc(c->layout_count, sizeof *c->layouts);
    c->characters = calloc(c->count, sizeof *c->characters);
    c->roots = malloc((size_t)c->count * sizeof *c->roots);
    c->worlds = malloc((size_t)c->count * (m->node_count ? m->node_count : 1) * sizeof *c->worlds);
    if (!c->layouts || !c->characters || !c->roots || !c->worlds) {
        app_crowd_close(c);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "out of memory for a crowd of %u", d->count);
    }
    size_t largest = 0;
    for (uint32_t l = 0; l < c->layout_count; l++) {
        const sinew_clip *clip = d->clip ? d->clip : m->clip_count ? &m->clips[l] : NULL;
        sinew_clip_layout_desc ld = {.model = m, .clip = clip};
        sinew_result result = sinew_clip_layout_create(&ld, &c->layouts[l], error);
        if (result != SINEW_OK) {
            app_crowd_close(c);
            return result;
        }
        sinew_character_layer layer = {.layout = c->layouts[l], .weight = 1.0f};
        size_t size = sinew_character_size(&(sinew_character_desc){.model = m, .layers = &layer, .layer_count = 1});
        largest = size > largest ? size : largest;
    }
    c->state_size = (largest + 63) & ~(size_t)63;
    c->states = malloc(c->state_size * c->count);
    if (!c->states) {
        app_crowd_close(c);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "out of memory for a crowd of %u", d->count);
    }
    for (uint32_t i = 0; i < c->count; i++) {
        /* each character one sinew_character playing its clip (the player's path) */
        sinew_character_layer layer = {.layout = c->layouts[i % c->layout_count], .weight = 1.0f};
        sinew_character_desc cd = {.model = m, .layers = &layer, .layer_count = 1};
        sinew_result result =
            sinew_character_init(c->states + c->state_size * i, c->state_size, &cd, &c->characters[i], error);
        if (result != SINEW_OK) {
            app_crowd_close(c);
            return result;
        }
        float x, z;
        cell(c, i, &x, &z);
        c->roots[i] = (sinew_mat4){{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x, 0, z, 1}};
    }
    return SINEW_OK;
}

static void pose_range(void *user, uint32_t first, uint32_t count, uint32_t thread)
{
    (void)thread;
    app_crowd *c = user;
    uint32_t n = c->model->node_count;
    for (uint32_t i = first; i < first + count; i++) {
        sinew_character_output o = {.root = &c->roots[i], .worlds = c->worlds + (size_t)i * n, .world_count = n};
        if (sinew_character_seek(c->characters[i], c->time + 0.37 * (i % 27), NULL) == SINEW_OK)
            sinew_character_evaluate(c->characters[i], &o, NULL);
    }
}

void app_crowd_pose(app_crowd *c, double time)
{
    c->time = time;
    sinew_jobs_run(c->jobs, c->count, 16, pose_range, c);
}

sinew_result app_crowd_resize(app_crowd *c, uint32_t count, sinew_error *error)
{
    app_crowd_desc d = {.model = c->model, .clip = c->clip, .count = count, .spacing = c->spacing, .jobs = c->jobs};
    uint32_t frame_at_least = c->frame_at_least;
    app_crowd_close(c);
    sinew_result result = app_crowd_open(c, &d, error);
    c->frame_at_least = frame_at_least;
    return result;
}

float app_crowd_spacing(app_scene *scene, sinew_renderer *renderer, int samples)
{
    float lo[3] = {-0.5f, 0.0f, -0.5f}, hi[3] = {0.5f, 1.0f, 0.5f};
    double duration = scene->clip ? scene->clip->duration : 0.0;
    app_scene_bounds(scene, renderer, 0.0, duration, samples, SINEW_WRAP_LOOP, lo, hi);
    float footprint = fmaxf(hi[0] - lo[0], hi[2] - lo[2]);
    return fmaxf(footprint * 1.25f, 0.05f);
}

void app_crowd_bounds(const app_crowd *c, float lo[3], float hi[3])
{
    uint32_t count = c->count > c->frame_at_least ? c->count : c->frame_at_least;
    uint32_t columns = (uint32_t)ceil(sqrt((double)count));
    float x0, z0, x1, z1;
    grid_cell(count, columns, c->spacing, 0, &x0, &z0);
    grid_cell(count, columns, c->spacing, count - 1, &x1, &z1);
    float xs = -x0; /* the grid is centred: its first row is the widest */
    lo[0] -= xs, hi[0] += xs;
    lo[2] += z0, hi[2] += z1;
}

void app_crowd_close(app_crowd *c)
{
    for (uint32_t l = 0; c->layouts && l < c->layout_count; l++)
        sinew_clip_layout_free(c->layouts[l]);
    free(c->layouts);
    free(c->states);
    free(c->characters);
    free(c->roots);
    free(c->worlds);
    memset(c, 0, sizeof *c);
}
