/* Overlay geometry built on the CPU each frame: ground grid, world axes, bones as
 * octahedra, joint dots, joint axes and joint names (stb_easy_font quads). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <cglm/cglm.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wpedantic"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

#include "internal.h"

#define GRID_MAX_HALF_LINES 40

static const uint8_t BONE_COLOR[3] = {150, 160, 185};
static const uint8_t SELECTED_COLOR[3] = {255, 150, 30};
static const uint8_t CHILD_OF_SELECTED_COLOR[3] = {255, 200, 120};

uint32_t overlay_capacity(uint32_t node_count)
{
    uint32_t grid = (2 * GRID_MAX_HALF_LINES + 1) * 2 * 2;
    return grid + 6 + node_count * (24 + 6 + 2) + 16 + 2 * SINEW_MAX_FRAME_LINES;
}

static void push(overlay_list *list, const float p[3], const uint8_t c[3], uint8_t alpha)
{
    if (list->count >= list->capacity)
        return;
    overlay_vertex *v = &list->vertices[list->count++];
    memcpy(v->position, p, sizeof v->position);
    v->color[0] = c[0], v->color[1] = c[1], v->color[2] = c[2], v->color[3] = alpha;
}

static void push_line(overlay_list *list, const float a[3], const float b[3], const uint8_t c[3])
{
    push(list, a, c, 255);
    push(list, b, c, 255);
}

static void node_position(const overlay_frame *frame, uint32_t node, float out[3])
{
    const float *m = frame->worlds[node].m;
    out[0] = m[12], out[1] = m[13], out[2] = m[14];
}

/* A 1-2-5 step near a quarter of the scene radius: about a dozen lines each side. */
static float grid_spacing(float radius)
{
    float r = radius > 1e-6f ? radius : 1.0f;
    float target = r * 0.25f;
    float decade = powf(10.0f, floorf(log10f(target)));
    float m = target / decade;
    return decade * (m < 1.5f ? 1.0f : m < 3.5f ? 2.0f : m < 7.5f ? 5.0f : 10.0f);
}

void overlay_add_grid(overlay_list *list, const overlay_frame *frame)
{
    float spacing = grid_spacing(frame->scene_radius);
    int half = (int)ceilf(frame->scene_radius * 2.5f / spacing);
    if (half > GRID_MAX_HALF_LINES)
        half = GRID_MAX_HALF_LINES;
    if (half < 2)
        half = 2;
    float eye[3];
    sinew_camera_eye(frame->camera, eye);
    const float *focus = frame->camera->mode == SINEW_CAMERA_ORBIT ? frame->camera->target : eye;
    float cx = roundf(focus[0] / spacing) * spacing, cz = roundf(focus[2] / spacing) * spacing;
    float bg[3];
    sinew_render_options_background(frame->options, bg);
    uint8_t minor[3], major[3];
    for (int i = 0; i < 3; i++) {
        minor[i] = (uint8_t)fminf(255.0f, (bg[i] * 0.6f + 0.4f * 0.55f) * 255.0f);
        major[i] = (uint8_t)fminf(255.0f, (bg[i] * 0.35f + 0.65f * 0.62f) * 255.0f);
    }
    float extent = half * spacing;
    for (int i = -half; i <= half; i++) {
        float x = cx + i * spacing, z = cz + i * spacing;
        const uint8_t *cx_color = fabsf(x) < spacing * 0.5f ? major : minor;
        const uint8_t *cz_color = fabsf(z) < spacing * 0.5f ? major : minor;
        float y = frame->options->grid_height;
        float a[3] = {x, y, cz - extent}, b[3] = {x, y, cz + extent};
        push_line(list, a, b, cx_color);
        float c[3] = {cx - extent, y, z}, d[3] = {cx + extent, y, z};
        push_line(list, c, d, cz_color);
    }
}

void overlay_add_lines(overlay_list *list, const overlay_frame *frame)
{
    uint8_t c[3];
    for (int k = 0; k < 3; k++)
        c[k] = (uint8_t)fminf(255.0f, fmaxf(0.0f, frame->line_color[k] * 255.0f + 0.5f));
    uint32_t n = frame->line_count < SINEW_MAX_FRAME_LINES ? frame->line_count : SINEW_MAX_FRAME_LINES;
    for (uint32_t i = 0; i < n; i++)
        push_line(list, frame->lines + i * 6, frame->lines + i * 6 + 3, c);
}

void overlay_add_axes(overlay_list *list, const overlay_frame *frame)
{
    static const uint8_t colors[3][3] = {{230, 60, 60}, {80, 200, 80}, {70, 120, 240}};
    float length = 2.0f * grid_spacing(frame->scene_radius);
    float origin[3] = {0.0f, 0.0f, 0.0f};
    for (int axis = 0; axis < 3; axis++) {
        float tip[3] = {0.0f, 0.0f, 0.0f};
        tip[axis] = length;
        push_line(list, origin, tip, colors[axis]);
    }
}

/* Blender-style octahedral bone from head a to tail b, each face shaded towards the camera. */
static void add_bone(overlay_list *list, const float a[3], const float b[3], float max_width, const float light[3],
                     const uint8_t color[3])
{
    float d[3];
    glm_vec3_sub((float *)b, (float *)a, d);
    float length = glm_vec3_norm(d);
    if (length < 1e-7f)
        return;
    float dir[3];
    glm_vec3_scale(d, 1.0f / length, dir);
    float axis[3] = {0.0f, 0.0f, 0.0f};
    float ax = fabsf(dir[0]), ay = fabsf(dir[1]), az = fabsf(dir[2]);
    axis[ax <= ay && ax <= az ? 0 : ay <= az ? 1 : 2] = 1.0f;
    float u[3], v[3];
    glm_vec3_crossn(dir, axis, u);
    glm_vec3_cross(dir, u, v);
    float width = fminf(length * 0.1f, max_width);
    float mid[3], ring[4][3];
    for (int i = 0; i < 3; i++)
        mid[i] = a[i] + d[i] * 0.15f;
    for (int i = 0; i < 3; i++) {
        ring[0][i] = mid[i] + u[i] * width;
        ring[1][i] = mid[i] + v[i] * width;
        ring[2][i] = mid[i] - u[i] * width;
        ring[3][i] = mid[i] - v[i] * width;
    }
    for (int k = 0; k < 4; k++) {
        const float *r0 = ring[k], *r1 = ring[(k + 1) % 4];
        const float *apex[2] = {a, b};
        for (int end = 0; end < 2; end++) {
            float e1[3], e2[3], n[3];
            glm_vec3_sub((float *)r0, (float *)apex[end], e1);
            glm_vec3_sub((float *)r1, (float *)apex[end], e2);
            glm_vec3_crossn(e1, e2, n);
            float shade = 0.4f + 0.6f * fabsf(glm_vec3_dot(n, (float *)light));
            uint8_t c[3] = {(uint8_t)(color[0] * shade), (uint8_t)(color[1] * shade), (uint8_t)(color[2] * shade)};
            push(list, apex[end], c, 255);
            push(list, r0, c, 255);
            push(list, r1, c, 255);
        }
    }
}

void overlay_add_bones(overlay_list *list, const overlay_frame *frame)
{
    const sinew_model *m = frame->model;
    float f[3], up[3], light[3];
    sinew_camera_basis(frame->camera, f, NULL, up);
    for (int i = 0; i < 3; i++)
        light[i] = -f[i] + 0.6f * up[i];
    glm_vec3_normalize(light);
    int32_t selected = options_selected(frame->options);
    for (uint32_t n = 0; n < m->node_count; n++) {
        int32_t p = m->node_parents[n];
        if (!frame->skeleton_nodes[n] || p < 0 || !frame->skeleton_nodes[p])
            continue;
        float a[3], b[3];
        node_position(frame, (uint32_t)p, a);
        node_position(frame, n, b);
        const uint8_t *color = p == selected            ? SELECTED_COLOR
                               : (int32_t)n == selected ? CHILD_OF_SELECTED_COLOR
                                                        : BONE_COLOR;
        add_bone(list, a, b, frame->scene_radius * 0.04f, light, color);
    }
}

void overlay_add_joint_axes(overlay_list *list, const overlay_frame *frame)
{
    static const uint8_t colors[3][3] = {{240, 50, 50}, {60, 220, 60}, {60, 110, 255}};
    float length = frame->scene_radius * 0.06f;
    for (uint32_t n = 0; n < frame->model->node_count; n++) {
        if (!frame->skeleton_nodes[n])
            continue;
        const float *m = frame->worlds[n].m;
        float o[3] = {m[12], m[13], m[14]};
        for (int axis = 0; axis < 3; axis++) {
            float d[3] = {m[axis * 4], m[axis * 4 + 1], m[axis * 4 + 2]};
            float len = glm_vec3_norm(d);
            float tip[3];
            for (int i = 0; i < 3; i++)
                tip[i] = o[i] + (len > 0.0f ? d[i] / len * length : 0.0f);
            push_line(list, o, tip, colors[axis]);
        }
    }
}

void overlay_add_joints(overlay_list *list, const overlay_frame *frame, bool selected_only)
{
    static const uint8_t JOINT_COLOR[3] = {235, 235, 240};
    int32_t selected = options_selected(frame->options);
    for (uint32_t n = 0; n < frame->model->node_count; n++) {
        if (selected_only ? (int32_t)n != selected : !frame->skeleton_nodes[n])
            continue;
        float p[3];
        node_position(frame, n, p);
        push(list, p, selected_only ? SELECTED_COLOR : JOINT_COLOR, 255);
    }
}

/* Names of the skeleton's joints (all with joint_names, else only the selected one) as
 * pixel-space quads, y down, placed beside each joint's projected position. */
void overlay_add_names(overlay_list *list, const overlay_frame *frame)
{
    const sinew_model *m = frame->model;
    const sinew_render_options *o = frame->options;
    float scale = frame->height >= 1000 ? 2.0f : 1.0f;
    for (uint32_t n = 0; n < m->node_count; n++) {
        bool is_selected = (int32_t)n == options_selected(o);
        if (!(is_selected || (o->joint_names && frame->skeleton_nodes[n])))
            continue;
        float p[3];
        node_position(frame, n, p);
        vec4 clip, world = {p[0], p[1], p[2], 1.0f};
        mat4 vp;
        memcpy(vp, frame->view_proj, sizeof vp);
        glm_mat4_mulv(vp, world, clip);
        if (clip[3] <= 0.0f)
            continue;
        float x = (clip[0] / clip[3] * 0.5f + 0.5f) * frame->width;
        float y = (0.5f - clip[1] / clip[3] * 0.5f) * frame->height;
        if (x < 0.0f || y < 0.0f || x > frame->width || y > frame->height)
            continue;
        char name[64];
        snprintf(name, sizeof name, "%s", m->node_names[n]);
        unsigned char color[4] = {255, 255, 255, 255};
        if (is_selected)
            memcpy(color, SELECTED_COLOR, 3);
        uint32_t room = list->capacity - list->count;
        int quads = stb_easy_font_print((x + 6.0f) / scale, (y - 4.0f) / scale, name, color,
                                        &list->vertices[list->count], (int)(room * sizeof(overlay_vertex)));
        for (int q = 0; q < quads * 4; q++) {
            overlay_vertex *v = &list->vertices[list->count + q];
            v->position[0] *= scale;
            v->position[1] *= scale;
        }
        list->count += (uint32_t)quads * 4;
    }
}
