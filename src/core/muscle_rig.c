/* Muscles bound to a model's joints: ends follow world matrices, radii re-solved each frame. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "sinew/anim.h"
#include "sinew/muscle_rig.h"

typedef struct rig_muscle {
    sinew_muscle_def def; /* strings and arrays point into the rig's block */
    int32_t nodes[2];     /* origin, insertion; -1: a point in model space */
    sinew_muscle_profile profile;
    sinew_muscle_range range;
    double *radii;
} rig_muscle;

struct sinew_muscle_rig {
    uint32_t count;
    double scale;
    rig_muscle *muscles;
};

static void end_point(const rig_muscle *rm, int end, const sinew_mat4 *worlds, float out[3])
{
    const float *o = end ? rm->def.insertion.offset : rm->def.origin.offset;
    int32_t node = rm->nodes[end];
    if (node < 0) {
        memcpy(out, o, 3 * sizeof(float));
        return;
    }
    const float *w = worlds[node].m;
    for (int k = 0; k < 3; k++)
        out[k] = w[k] * o[0] + w[4 + k] * o[1] + w[8 + k] * o[2] + w[12 + k];
}

static double distance(const float a[3], const float b[3])
{
    double d = 0.0;
    for (int k = 0; k < 3; k++)
        d += ((double)b[k] - a[k]) * ((double)b[k] - a[k]);
    return sqrt(d);
}

static sinew_result bind(const sinew_model *model, const sinew_muscle_set *set, rig_muscle *rm, const sinew_mat4 *rest,
                         sinew_error *error)
{
    const sinew_muscle_attachment *ends[2] = {&rm->def.origin, &rm->def.insertion};
    for (int e = 0; e < 2; e++) {
        rm->nodes[e] = -1;
        if (!ends[e]->joint)
            continue;
        rm->nodes[e] = model ? sinew_model_find_joint(model, ends[e]->joint) : -1;
        if (rm->nodes[e] < 0)
            return sinew_fail(error, SINEW_ERROR_DATA, "%s: muscle \"%s\": %s joint \"%s\" is not a node of %s",
                              set->source, rm->def.name, e ? "insertion" : "origin", ends[e]->joint,
                              model ? model->source : "the model (none given)");
    }
    double rest_length = rm->def.rest_length;
    if (!(rest_length > 0.0)) {
        float a[3], b[3];
        end_point(rm, 0, rest, a);
        end_point(rm, 1, rest, b);
        rest_length = distance(a, b);
        if (!(rest_length > 0.0))
            return sinew_fail(error, SINEW_ERROR_DATA,
                              "%s: muscle \"%s\": its ends meet in the rest pose, so it has no rest length (give "
                              "\"rest_length\" or move an offset)",
                              set->source, rm->def.name);
    }
    rm->profile = (sinew_muscle_profile){rm->def.node_count, rm->def.radii, rm->def.coefficients, rest_length};
    return sinew_muscle_valid_range(&rm->profile, &rm->range, error);
}

/* Rest-pose world matrices of the model (identity table when there is no model). */
static sinew_mat4 *rest_worlds(const sinew_model *model)
{
    uint32_t n = model && model->node_count ? model->node_count : 1;
    sinew_mat4 *worlds = calloc(n, sizeof *worlds);
    sinew_transform *locals = calloc(n, sizeof *locals);
    if (worlds && locals && model) {
        sinew_sample_desc d = {.model = model, .locals = locals, .local_count = model->node_count};
        if (sinew_sample(&d, NULL) != SINEW_OK ||
            sinew_local_to_world(model, locals, n, NULL, worlds, n, NULL) != SINEW_OK) {
            free(worlds);
            worlds = NULL;
        }
    }
    free(locals);
    return worlds;
}

sinew_result sinew_muscle_rig_create(const sinew_model *model, const sinew_muscle_set *set, sinew_muscle_rig **out,
                                     sinew_error *error)
{
    if (!set || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_muscle_rig_create: no muscles or no output");
    *out = NULL;
    size_t texts = 0, numbers = 0;
    for (uint32_t i = 0; i < set->muscle_count; i++) {
        const sinew_muscle_def *d = &set->muscles[i];
        texts += strlen(d->name) + 1;
        numbers += 3 * (size_t)d->node_count; /* radii, coefficients, solved radii */
    }
    size_t head = sizeof(sinew_muscle_rig) + set->muscle_count * sizeof(rig_muscle);
    head = (head + 7) & ~(size_t)7;
    unsigned char *block = calloc(1, head + numbers * sizeof(double) + texts);
    sinew_mat4 *rest = rest_worlds(model);
    if (!block || !rest) {
        free(block);
        free(rest);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory binding muscles", set->source);
    }
    sinew_muscle_rig *rig = (sinew_muscle_rig *)block;
    rig->count = set->muscle_count;
    rig->scale = 1.0;
    rig->muscles = (rig_muscle *)(rig + 1);
    double *num = (double *)(block + head);
    char *text = (char *)(num + numbers);
    sinew_result result = SINEW_OK;
    for (uint32_t i = 0; i < set->muscle_count && result == SINEW_OK; i++) {
        const sinew_muscle_def *d = &set->muscles[i];
        rig_muscle *rm = &rig->muscles[i];
        rm->def = *d;
        rm->def.name = strcpy(text, d->name);
        text += strlen(d->name) + 1;
        size_t n = d->node_count;
        rm->def.radii = memcpy(num, d->radii, n * sizeof(double));
        rm->def.coefficients = memcpy(num + n, d->coefficients, n * sizeof(double));
        rm->radii = num + 2 * n;
        num += 3 * n;
        result = bind(model, set, rm, rest, error);
        /* Joint names are resolved: the rig keeps node indices, not the set's strings. */
        rm->def.origin.joint = rm->def.insertion.joint = NULL;
    }
    free(rest);
    if (result != SINEW_OK) {
        free(block);
        return result;
    }
    *out = rig;
    return SINEW_OK;
}

void sinew_muscle_rig_free(sinew_muscle_rig *rig)
{
    free(rig);
}

void sinew_muscle_rig_set_scale(sinew_muscle_rig *rig, double scale)
{
    if (rig)
        rig->scale = scale > 0.0 && isfinite(scale) ? scale : 1.0;
}

uint32_t sinew_muscle_rig_count(const sinew_muscle_rig *rig)
{
    return rig ? rig->count : 0;
}

/* The valid length nearest to `length`, a hair inside open ends. */
static double clamp_length(const sinew_muscle_range *r, double length)
{
    double lo = r->min_open ? fmax(r->min_length * (1.0 + 1e-9), 1e-12) : r->min_length;
    double hi = r->max_open ? r->max_length * (1.0 - 1e-9) : r->max_length;
    return length < lo ? lo : length > hi ? hi : length;
}

sinew_result sinew_muscle_rig_update(sinew_muscle_rig *rig, const sinew_mat4 *worlds, uint32_t world_count,
                                     sinew_muscle_pose *poses, uint32_t pose_count, sinew_error *error)
{
    if (!rig || !poses || pose_count < rig->count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_muscle_rig_update: room for %u of %u muscles",
                          pose_count, rig ? rig->count : 0);
    for (uint32_t i = 0; i < rig->count; i++) {
        rig_muscle *rm = &rig->muscles[i];
        for (int e = 0; e < 2; e++)
            if (rm->nodes[e] >= 0 && (!worlds || (uint32_t)rm->nodes[e] >= world_count))
                return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                                  "sinew_muscle_rig_update: %u world matrices, muscle \"%s\" needs node %d",
                                  world_count, rm->def.name, rm->nodes[e]);
        sinew_muscle_pose *p = &poses[i];
        memset(p, 0, sizeof *p);
        p->name = rm->def.name;
        end_point(rm, 0, worlds, p->origin);
        end_point(rm, 1, worlds, p->insertion);
        memcpy(p->color, rm->def.color, sizeof p->color);
        p->segments = rm->def.segments;
        p->node_count = rm->def.node_count;
        p->radii = rm->radii;
        p->range = rm->range;
        double length = distance(p->origin, p->insertion), s = rig->scale;
        double solve_at = clamp_length(&rm->range, length / s);
        p->in_range = solve_at == length / s;
        sinew_result result =
            sinew_muscle_solve(&rm->profile, solve_at, rm->radii, rm->def.node_count, &p->state, error);
        if (result != SINEW_OK)
            return result;
        if (s != 1.0) {
            for (uint32_t k = 0; k < rm->def.node_count; k++)
                rm->radii[k] *= s;
            p->state.length *= s;
            p->state.rest_length *= s;
            p->state.delta *= s;
            p->state.volume *= s * s * s;
            p->state.rest_volume *= s * s * s;
        }
        p->distance = length;
    }
    return SINEW_OK;
}
