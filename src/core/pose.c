/* Local transforms -> world matrices -> skinning matrices, and TRS <-> matrix. */
#include <math.h>
#include <string.h>

#include <cglm/cglm.h>

#include "internal.h"
#include "sinew/anim.h"

#define AS_MAT4(p) ((vec4 *)(p)->m)

void sinew_transform_to_mat4(const sinew_transform *t, sinew_mat4 *out)
{
    versor q;
    glm_vec4_copy((float *)t->rotation, q);
    glm_quat_mat4(q, AS_MAT4(out));
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            out->m[c * 4 + r] *= t->scale[c];
    out->m[12] = t->translation[0];
    out->m[13] = t->translation[1];
    out->m[14] = t->translation[2];
}

void sinew_mat4_decompose(const sinew_mat4 *matrix, sinew_transform *out)
{
    const float *m = matrix->m;
    vec3 axes[3];
    for (int c = 0; c < 3; c++) {
        glm_vec3_copy((float *)&m[c * 4], axes[c]);
        out->scale[c] = glm_vec3_norm(axes[c]);
    }
    vec3 cross;
    glm_vec3_cross(axes[0], axes[1], cross);
    if (glm_vec3_dot(cross, axes[2]) < 0.0f)
        out->scale[0] = -out->scale[0]; /* mirrored: put the reflection on x */
    mat4 rotation;
    glm_mat4_identity(rotation);
    for (int c = 0; c < 3; c++) {
        float s = out->scale[c];
        if (s != 0.0f)
            glm_vec3_scale(axes[c], 1.0f / s, rotation[c]);
    }
    versor q;
    glm_mat4_quat(rotation, q);
    glm_quat_normalize(q);
    memcpy(out->rotation, q, sizeof q);
    memcpy(out->translation, &m[12], 3 * sizeof(float));
}

static float pose_scale(pose_scales s, uint32_t node, int c)
{
    return s.base[node * s.node_stride + (size_t)c * s.comp_stride];
}

/* A node's inherited scale: its own, times its parent's inherited scale while it is
 * COMPONENTWISE_SCALE (see sinew_inherit). */
static void inherited_scale(const sinew_model *m, uint32_t node, pose_scales s, float out[3])
{
    for (int c = 0; c < 3; c++)
        out[c] = pose_scale(s, node, c);
    int32_t p = m->node_parents[node];
    while (p >= 0 && m->node_inherit[node] == SINEW_INHERIT_COMPONENTWISE_SCALE) {
        for (int c = 0; c < 3; c++)
            out[c] *= pose_scale(s, (uint32_t)p, c);
        node = (uint32_t)p;
        p = m->node_parents[node];
    }
}

void sinew_pose_world_inherit(const sinew_model *m, uint32_t node, const float translation[3], const float rotation[4],
                              const float scale[3], pose_scales scales, const sinew_mat4 *worlds, sinew_mat4 *out)
{
    uint32_t parent = (uint32_t)m->node_parents[node];
    float inherit[3], applied[3];
    inherited_scale(m, parent, scales, inherit);
    /* The scale that ends the parent's world matrix, taken off to leave it unscaled. */
    for (int c = 0; c < 3; c++)
        applied[c] =
            m->node_inherit[parent] == SINEW_INHERIT_COMPONENTWISE_SCALE ? inherit[c] : pose_scale(scales, parent, c);
    sinew_mat4 unscaled = worlds[parent];
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 4; r++)
            unscaled.m[c * 4 + r] = applied[c] != 0.0f ? unscaled.m[c * 4 + r] / applied[c] : 0.0f;
    sinew_transform local = {{0}, {rotation[0], rotation[1], rotation[2], rotation[3]}, {0}};
    bool componentwise = m->node_inherit[node] == SINEW_INHERIT_COMPONENTWISE_SCALE;
    for (int c = 0; c < 3; c++) {
        local.translation[c] = translation[c] * inherit[c];
        local.scale[c] = componentwise ? scale[c] * inherit[c] : scale[c];
    }
    float q2 = local.rotation[0] * local.rotation[0] + local.rotation[1] * local.rotation[1] +
               local.rotation[2] * local.rotation[2] + local.rotation[3] * local.rotation[3];
    if (q2 > 0.0f)
        for (int c = 0; c < 4; c++)
            local.rotation[c] /= sqrtf(q2);
    sinew_mat4 l;
    sinew_transform_to_mat4(&local, &l);
    glm_mat4_mul(AS_MAT4(&unscaled), AS_MAT4(&l), AS_MAT4(out));
}

sinew_result sinew_local_to_world(const sinew_model *model, const sinew_transform *locals, uint32_t local_count,
                                  const sinew_mat4 *root, sinew_mat4 *worlds, uint32_t world_count, sinew_error *error)
{
    if (!model || !locals || !worlds)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_local_to_world: NULL argument");
    if (local_count < model->node_count || world_count < model->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_local_to_world: spans of %u locals and %u worlds, the model has %u nodes", local_count,
                          world_count, model->node_count);
    const pose_scales scales = {locals[0].scale, sizeof(sinew_transform) / sizeof(float), 1};
    for (uint32_t i = 0; i < model->node_count; i++) {
        int32_t parent = model->node_parents[i];
        if (parent >= 0 && model->node_inherit && model->node_inherit[i] != SINEW_INHERIT_NORMAL) {
            sinew_pose_world_inherit(model, i, locals[i].translation, locals[i].rotation, locals[i].scale, scales,
                                     worlds, &worlds[i]);
            continue;
        }
        sinew_mat4 local;
        sinew_transform_to_mat4(&locals[i], &local);
        const sinew_mat4 *base = parent >= 0 ? &worlds[parent] : root;
        if (base)
            glm_mat4_mul(AS_MAT4(base), AS_MAT4(&local), AS_MAT4(&worlds[i]));
        else
            worlds[i] = local;
    }
    return SINEW_OK;
}

sinew_result sinew_skin_palette(const sinew_skin *skin, const sinew_mat4 *worlds, uint32_t world_count,
                                sinew_mat4 *palette, uint32_t palette_count, sinew_error *error)
{
    if (!skin || !worlds || !palette)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_palette: NULL argument");
    if (palette_count < skin->joint_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_skin_palette: %u matrices given, the skin has %u joints", palette_count,
                          skin->joint_count);
    for (uint32_t j = 0; j < skin->joint_count; j++) {
        uint32_t node = skin->joints[j];
        if (node >= world_count)
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "sinew_skin_palette: joint %u is node %u, past the %u world matrices", j, node,
                              world_count);
        glm_mat4_mul(AS_MAT4(&worlds[node]), AS_MAT4(&skin->inverse_bind[j]), AS_MAT4(&palette[j]));
    }
    return SINEW_OK;
}
