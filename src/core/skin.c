/* CPU linear-blend skinning (the scalar reference) and rigid transforms of vertices. */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "sinew/anim.h"

/* Normal transform for a 3x3 part given as columns c0, c1, c2: the cofactor matrix,
 * which is det * inverse-transpose; its sign is fixed by det so mirrored matrices keep
 * normals outward. The caller renormalises. */
static void transform_normal(const float *m, const float *n, float *out)
{
    const float *c0 = &m[0], *c1 = &m[4], *c2 = &m[8];
    float k0[3] = {c1[1] * c2[2] - c1[2] * c2[1], c1[2] * c2[0] - c1[0] * c2[2], c1[0] * c2[1] - c1[1] * c2[0]};
    float k1[3] = {c2[1] * c0[2] - c2[2] * c0[1], c2[2] * c0[0] - c2[0] * c0[2], c2[0] * c0[1] - c2[1] * c0[0]};
    float k2[3] = {c0[1] * c1[2] - c0[2] * c1[1], c0[2] * c1[0] - c0[0] * c1[2], c0[0] * c1[1] - c0[1] * c1[0]};
    float det = c0[0] * k0[0] + c0[1] * k0[1] + c0[2] * k0[2];
    float sign = det < 0.0f ? -1.0f : 1.0f;
    float x = sign * (k0[0] * n[0] + k1[0] * n[1] + k2[0] * n[2]);
    float y = sign * (k0[1] * n[0] + k1[1] * n[1] + k2[1] * n[2]);
    float z = sign * (k0[2] * n[0] + k1[2] * n[1] + k2[2] * n[2]);
    float len = sqrtf(x * x + y * y + z * z);
    float inv = len > 0.0f ? 1.0f / len : 0.0f;
    out[0] = x * inv;
    out[1] = y * inv;
    out[2] = z * inv;
}

static void transform_point(const float *m, const float *p, float *out)
{
    out[0] = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
    out[1] = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
    out[2] = m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14];
}

sinew_result sinew_skin_vertices(const sinew_skin_desc *desc, sinew_error *error)
{
    if (!desc || !desc->mesh || !desc->palette || !desc->out_positions)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: NULL mesh, palette or output");
    const sinew_mesh *mesh = desc->mesh;
    if (mesh->influence_count == 0 || !mesh->joints || !mesh->weights)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: mesh \"%s\" is not skinned",
                          mesh->name);
    if (desc->first > mesh->vertex_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_skin_vertices: first vertex %u past the %u vertices", desc->first, mesh->vertex_count);
    uint32_t count = desc->count ? desc->count : mesh->vertex_count - desc->first;
    if (count > mesh->vertex_count - desc->first)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: range %u+%u past the %u vertices",
                          desc->first, count, mesh->vertex_count);
    size_t stride = desc->out_stride ? desc->out_stride : 3 * sizeof(float);
    if (stride < 3 * sizeof(float))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_skin_vertices: stride %zu below 12 bytes",
                          stride);

    const uint32_t k = mesh->influence_count;
    for (uint32_t v = desc->first; v < desc->first + count; v++) {
        const uint16_t *joints = &mesh->joints[(size_t)v * k];
        const float *weights = &mesh->weights[(size_t)v * k];
        float blended[16] = {0};
        for (uint32_t i = 0; i < k; i++) {
            float w = weights[i];
            if (w == 0.0f)
                break; /* weights are sorted: the rest are zero too */
            if (joints[i] >= desc->palette_count)
                return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                                  "sinew_skin_vertices: vertex %u uses joint %u, the palette has %u", v, joints[i],
                                  desc->palette_count);
            const float *m = desc->palette[joints[i]].m;
            for (int e = 0; e < 16; e++)
                blended[e] += w * m[e];
        }
        float *out_p = (float *)((char *)desc->out_positions + (size_t)v * stride);
        transform_point(blended, &mesh->positions[(size_t)v * 3], out_p);
        if (desc->out_normals) {
            float *out_n = (float *)((char *)desc->out_normals + (size_t)v * stride);
            transform_normal(blended, &mesh->normals[(size_t)v * 3], out_n);
        }
    }
    return SINEW_OK;
}

sinew_result sinew_transform_vertices(const sinew_mesh *mesh, const sinew_mat4 *matrix, float *out_positions,
                                      float *out_normals, size_t out_stride, sinew_error *error)
{
    if (!mesh || !matrix || !out_positions)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_transform_vertices: NULL argument");
    size_t stride = out_stride ? out_stride : 3 * sizeof(float);
    if (stride < 3 * sizeof(float))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_transform_vertices: stride %zu below 12 bytes",
                          stride);
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        transform_point(matrix->m, &mesh->positions[(size_t)v * 3],
                        (float *)((char *)out_positions + (size_t)v * stride));
        if (out_normals)
            transform_normal(matrix->m, &mesh->normals[(size_t)v * 3],
                             (float *)((char *)out_normals + (size_t)v * stride));
    }
    return SINEW_OK;
}
