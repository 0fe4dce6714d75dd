/* app/common/crowd.h: many characters of one model, as `sinew render --crowd`, `sinew bench
 * crowd` and the viewer's crowd show them.
 *
 * What: `count` characters on a square grid on the ground (y = 0), `spacing` metres apart,
 * each playing a clip from its own time (character c starts (c mod 27) * 0.37 s in): the clip given,
 * or the model's clips in turn. One clip layout a clip, one player a character; posing runs
 * over the characters on a job system (sinew/jobs.h), each character's world matrices placed
 * by its grid root. What not: no drawing (sinew_frame.crowd_count and crowd_worlds do that)
 * and no printing. */
#ifndef SINEW_APP_CROWD_H
#define SINEW_APP_CROWD_H

#include "app.h"
#include "scene.h"
#include "sinew/jobs.h"

typedef struct app_crowd {
    const sinew_model *model;
    const sinew_clip *clip; /* as asked: every character plays it; NULL: the clips in turn */
    uint32_t count, columns;
    float spacing;
    uint32_t layout_count;
    sinew_clip_layout **layouts; /* one a clip played */
    unsigned char *states;       /* count characters' memory */
    size_t state_size;
    sinew_character **characters; /* one clip each (sinew/character.h) */
    sinew_mat4 *roots;            /* count grid placements */
    sinew_mat4 *worlds;           /* count * node_count: the last pose */
    double time;
    sinew_jobs *jobs;        /* borrowed; NULL: the calling thread */
    uint32_t frame_at_least; /* app_crowd_bounds() covers the grid of at least this many (0: count) */
} app_crowd;

typedef struct app_crowd_desc {
    const sinew_model *model; /* must outlive the crowd */
    const sinew_clip *clip;   /* every character plays it; NULL: the model's clips in turn */
    uint32_t count;           /* 1 .. APP_CROWD_MAX */
    float spacing;            /* metres between neighbours; <= 0: 1 */
    sinew_jobs *jobs;
} app_crowd_desc;

#define APP_CROWD_MAX 100000u

sinew_result app_crowd_open(app_crowd *crowd, const app_crowd_desc *desc, sinew_error *error);
/* The same crowd (model, clips, spacing, jobs, framing) with `count` characters. */
sinew_result app_crowd_resize(app_crowd *crowd, uint32_t count, sinew_error *error);

/* Spacing for a crowd of the scene's model: its footprint on the ground (the wider of x and z)
 * over its clip, `samples` times, and a quarter more (at least 5 cm). */
float app_crowd_spacing(app_scene *scene, sinew_renderer *renderer, int samples);
/* Poses every character at `time` (looping its clip). */
void app_crowd_pose(app_crowd *crowd, double time);
/* Grows one character's box (lo, hi, at its origin) to the grid's. */
void app_crowd_bounds(const app_crowd *crowd, float lo[3], float hi[3]);
void app_crowd_close(app_crowd *crowd);

#endif
