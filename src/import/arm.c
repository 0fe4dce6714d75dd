/* The seed 003 arm as a model: two rods (cylinders built like muscle tubes) on "upper" and
 * "lower" nodes under "arm", and an optional "flex" clip on the elbow. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/internal.h"
#include "internal.h"
#include "sinew/arm.h"
#include "sinew/muscle.h"

#define ROD_SEGMENTS 16
#define FLEX_KEYS 31

enum { NODE_ARM, NODE_UPPER, NODE_LOWER, NODE_COUNT };

/* Rotation about +Z by `angle` as a quaternion. */
static void z_rotation(double angle, float q[4])
{
    q[0] = 0.0f, q[1] = 0.0f, q[2] = (float)sin(angle * 0.5), q[3] = (float)cos(angle * 0.5);
}

/* The lower rod leaves the elbow at pi - angle from the upper rod's +X. */
static void elbow_rotation(double angle, float q[4])
{
    z_rotation(M_PI - angle, q);
}

static sinew_result make_rod(raw_model *m, uint32_t index, const char *name, double length, double radius)
{
    raw_mesh *mesh = &m->meshes[index];
    double radii[2] = {radius, radius};
    uint32_t nv, ni;
    sinew_muscle_surface_size(2, ROD_SEGMENTS, &nv, &ni);
    mesh->name = raw_strdup(name);
    mesh->vertex_count = nv;
    mesh->index_count = ni;
    mesh->positions = malloc((size_t)nv * 3 * sizeof(float));
    mesh->normals = malloc((size_t)nv * 3 * sizeof(float));
    mesh->indices = malloc((size_t)ni * sizeof(uint32_t));
    if (!mesh->name || !mesh->positions || !mesh->normals || !mesh->indices)
        return SINEW_ERROR_OUT_OF_MEMORY;
    sinew_muscle_surface_desc d = {.node_count = 2,
                                   .radii = radii,
                                   .insertion = {(float)length, 0.0f, 0.0f},
                                   .segments = ROD_SEGMENTS,
                                   .out_positions = mesh->positions,
                                   .out_normals = mesh->normals,
                                   .vertex_capacity = nv,
                                   .out_indices = mesh->indices,
                                   .index_capacity = ni};
    mesh->skin = -1;
    mesh->material = 0;
    m->instances[index] = (sinew_instance){index, index == 0 ? NODE_UPPER : NODE_LOWER, 0};
    return sinew_muscle_surface(&d, NULL);
}

static sinew_result make_flex_clip(raw_model *m, const sinew_arm_desc *d)
{
    float duration = d->flex_duration > 0.0f ? d->flex_duration : 2.0f;
    raw_clip *clip = raw_model_add_rotation_clip(m, "flex", duration, 1, FLEX_KEYS);
    if (!clip)
        return SINEW_ERROR_OUT_OF_MEMORY;
    clip->tracks[0].node = NODE_LOWER;
    float *values = clip->tracks[0].channels[SINEW_CHANNEL_ROTATION].values;
    for (int k = 0; k < FLEX_KEYS; k++) {
        double blend = 0.5 - 0.5 * cos(2.0 * M_PI * k / (FLEX_KEYS - 1)); /* from, to, back, easing at both ends */
        elbow_rotation(d->flex_from + (d->flex_to - d->flex_from) * blend, &values[k * 4]);
    }
    return SINEW_OK;
}

static sinew_result check_desc(const sinew_arm_desc *d, sinew_error *error)
{
    const double v[4] = {d->free_to_origin, d->origin_to_elbow, d->elbow_to_insertion, d->insertion_to_free};
    for (int i = 0; i < 4; i++)
        if (!(v[i] > 0.0) || !isfinite(v[i]))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "arm: distance %d is %g; all four must be > 0",
                              i + 1, v[i]);
    const double angles[3] = {d->elbow_angle, d->flex_from, d->flex_to};
    for (int i = 0; i < 3; i++)
        if (!(angles[i] >= 0.0 && angles[i] <= M_PI))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "arm: elbow angle %g degrees is outside 0..180",
                              angles[i] * 180.0 / M_PI);
    if (!(d->rod_radius >= 0.0) || !isfinite(d->rod_radius))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "arm: rod radius %g", d->rod_radius);
    return SINEW_OK;
}

static sinew_result make_nodes(raw_model *m, const sinew_arm_desc *d)
{
    static const char *const names[NODE_COUNT] = {"arm", "upper", "lower"};
    m->node_count = NODE_COUNT;
    m->node_names = calloc(NODE_COUNT, sizeof *m->node_names);
    m->node_parents = calloc(NODE_COUNT, sizeof *m->node_parents);
    m->node_rest = calloc(NODE_COUNT, sizeof *m->node_rest);
    if (!m->node_names || !m->node_parents || !m->node_rest)
        return SINEW_ERROR_OUT_OF_MEMORY;
    for (int n = 0; n < NODE_COUNT; n++) {
        m->node_names[n] = raw_strdup(names[n]);
        if (!m->node_names[n])
            return SINEW_ERROR_OUT_OF_MEMORY;
        m->node_parents[n] = n - 1;
        m->node_rest[n] = (sinew_transform){{0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}};
    }
    sinew_transform place = d->place;
    bool no_rotation = !place.rotation[0] && !place.rotation[1] && !place.rotation[2] && !place.rotation[3];
    if (no_rotation)
        place.rotation[3] = 1.0f;
    for (int i = 0; i < 3; i++)
        if (place.scale[i] == 0.0f)
            place.scale[i] = 1.0f;
    m->node_rest[NODE_ARM] = place;
    m->node_rest[NODE_LOWER].translation[0] = (float)(d->free_to_origin + d->origin_to_elbow);
    elbow_rotation(d->elbow_angle, m->node_rest[NODE_LOWER].rotation);
    return SINEW_OK;
}

sinew_result sinew_arm_model(const sinew_arm_desc *desc, sinew_model **out, sinew_error *error)
{
    if (!desc || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_arm_model: no desc or no output");
    *out = NULL;
    sinew_result result = check_desc(desc, error);
    if (result != SINEW_OK)
        return result;
    double upper = desc->free_to_origin + desc->origin_to_elbow;
    double lower = desc->elbow_to_insertion + desc->insertion_to_free;
    double radius = desc->rod_radius > 0.0 ? desc->rod_radius : 0.04 * upper;
    raw_model raw = {.source = raw_strdup("built-in arm"), .format = raw_strdup("sinew arm"), .muscles = desc->muscles};
    result = raw.source && raw.format ? make_nodes(&raw, desc) : SINEW_ERROR_OUT_OF_MEMORY;
    if (result == SINEW_OK) {
        raw.mesh_count = raw.instance_count = 2;
        raw.material_count = 1;
        raw.meshes = calloc(2, sizeof *raw.meshes);
        raw.instances = calloc(2, sizeof *raw.instances);
        raw.materials = calloc(1, sizeof *raw.materials);
        result = raw.meshes && raw.instances && raw.materials ? SINEW_OK : SINEW_ERROR_OUT_OF_MEMORY;
    }
    if (result == SINEW_OK) {
        raw.materials[0] = (raw_material){.name = raw_strdup("rod"), .base_color = {0.55f, 0.57f, 0.6f, 1.0f}};
        result = raw.materials[0].name ? make_rod(&raw, 0, "upper rod", upper, radius) : SINEW_ERROR_OUT_OF_MEMORY;
    }
    if (result == SINEW_OK)
        result = make_rod(&raw, 1, "lower rod", lower, radius);
    if (result == SINEW_OK && (desc->flex_from != 0.0 || desc->flex_to != 0.0))
        result = make_flex_clip(&raw, desc);
    void *bytes = NULL;
    size_t size = 0;
    if (result == SINEW_OK)
        result = raw_model_build(&raw, &bytes, &size, error);
    else
        sinew_fail(error, result, "arm: out of memory");
    raw_model_free(&raw);
    if (result == SINEW_OK)
        result = sinew_model_from_blob(bytes, size, "built-in arm", NULL, out, error);
    free(bytes);
    return result;
}
