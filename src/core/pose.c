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

sinew_result sinew_local_to_world(const sinew_model *model, const sinew_transform *locals, uint32_t local_count,
                                  const sinew_mat4 *root, sinew_mat4 *worlds, uint32_t world_count, sinew_error *error)
{
    if (!model || !locals || !worlds)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_local_to_world: NULL argument");
    if (local_count < model->node_count || world_count < model->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_local_to_world: spans of %u locals and %u worlds, the model has %u nodes", local_count,
                          world_count, model->node_count);
    for (uint32_t i = 0; i < model->node_count; i++) {
        sinew_mat4 local;
        sinew_transform_to_mat4(&locals[i], &local);
        int32_t parent = model->node_parents[i];
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
