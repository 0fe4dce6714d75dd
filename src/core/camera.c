/* Orbit and free-fly cameras: shared yaw/pitch, so switching keeps the view. */
#include <math.h>
#include <string.h>

#include <cglm/cglm.h>

#include "sinew/camera.h"

#define PITCH_LIMIT 1.5533430f /* 89 degrees */
#define MIN_DISTANCE 1e-4f

sinew_camera sinew_camera_default(void)
{
    sinew_camera c = {.mode = SINEW_CAMERA_ORBIT, .pitch = 0.3f, .distance = 3.0f, .scene_radius = 1.0f};
    sinew_camera_eye(&c, c.position);
    return c;
}

/* Unit vector from the eye towards what it looks at. */
static void forward_of(const sinew_camera *c, float out[3])
{
    float cp = cosf(c->pitch);
    out[0] = -sinf(c->yaw) * cp;
    out[1] = -sinf(c->pitch);
    out[2] = -cosf(c->yaw) * cp;
}

void sinew_camera_basis(const sinew_camera *camera, float forward[3], float right[3], float up[3])
{
    float f[3];
    forward_of(camera, f);
    float r[3] = {cosf(camera->yaw), 0.0f, -sinf(camera->yaw)};
    float u[3];
    glm_vec3_cross(r, f, u);
    if (forward)
        glm_vec3_copy(f, forward);
    if (right)
        glm_vec3_copy(r, right);
    if (up)
        glm_vec3_copy(u, up);
}

void sinew_camera_eye(const sinew_camera *camera, float eye[3])
{
    if (camera->mode == SINEW_CAMERA_FLY) {
        glm_vec3_copy((float *)camera->position, eye);
        return;
    }
    float f[3];
    forward_of(camera, f);
    for (int i = 0; i < 3; i++)
        eye[i] = camera->target[i] - f[i] * camera->distance;
}

static float clamp_pitch(float pitch)
{
    return pitch > PITCH_LIMIT ? PITCH_LIMIT : pitch < -PITCH_LIMIT ? -PITCH_LIMIT : pitch;
}

static float fov_of(const sinew_camera *c)
{
    return c->fov_y > 0.0f ? c->fov_y : glm_rad(45.0f);
}

/* The orbit distance at which the box's corners fit the view around `target`, given the view's
 * basis and half-angle tangents (perspective: each corner at its own depth; parallel: the
 * view's height at the pivot). */
static float dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static float fit_distance(float corners[8][3], const float target[3], const float f[3], const float right[3],
                          const float up[3], float tan_h, float tan_v, bool parallel)
{
    float d = 0.0f;
    for (int k = 0; k < 8; k++) {
        float p[3] = {corners[k][0] - target[0], corners[k][1] - target[1], corners[k][2] - target[2]};
        float x = fabsf(dot3(p, right)), y = fabsf(dot3(p, up)), z = dot3(p, f);
        float need = fmaxf(x / tan_h, y / tan_v) - (parallel ? 0.0f : z);
        d = fmaxf(d, need);
    }
    return d;
}

void sinew_camera_frame(sinew_camera *camera, const float min[3], const float max[3], float aspect)
{
    float center[3], lo[3], hi[3], radius = 0.0f;
    for (int i = 0; i < 3; i++) {
        lo[i] = min[i], hi[i] = max[i];
        if (!(lo[i] <= hi[i]) || !isfinite(lo[i]) || !isfinite(hi[i]))
            lo[i] = hi[i] = 0.0f;
        center[i] = 0.5f * (lo[i] + hi[i]);
        radius += 0.25f * (hi[i] - lo[i]) * (hi[i] - lo[i]);
    }
    radius = sqrtf(radius);
    if (radius < 1e-3f) { /* a point: a unit sphere around it */
        radius = 1.0f;
        for (int i = 0; i < 3; i++)
            lo[i] = center[i] - 0.57735f, hi[i] = center[i] + 0.57735f;
    }
    /* the box's corners fill 95% of the narrower side of the view, seen along the camera's
     * direction: its projection centred (a few refinements, as perspective is not symmetric) */
    float half_v = 0.5f * fov_of(camera);
    float tan_v = tanf(half_v) * 0.95f, tan_h = tanf(half_v) * (aspect > 0.0f ? aspect : 1.0f) * 0.95f;
    float corners[8][3], f[3], right[3], up[3];
    for (int k = 0; k < 8; k++)
        for (int i = 0; i < 3; i++)
            corners[k][i] = (k >> i) & 1 ? hi[i] : lo[i];
    sinew_camera_basis(camera, f, right, up);
    float d = fit_distance(corners, center, f, right, up, tan_h, tan_v, camera->orthographic);
    for (int pass = 0; pass < 4 && !camera->orthographic; pass++) {
        float x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
        for (int k = 0; k < 8; k++) {
            float p[3] = {corners[k][0] - center[0], corners[k][1] - center[1], corners[k][2] - center[2]};
            float depth = fmaxf(d + glm_vec3_dot(p, f), 1e-6f);
            float x = glm_vec3_dot(p, right) / depth, y = glm_vec3_dot(p, up) / depth;
            x0 = fminf(x0, x), x1 = fmaxf(x1, x), y0 = fminf(y0, y), y1 = fmaxf(y1, y);
        }
        /* move the target sideways so that the extents are even, at the target's depth */
        float sx = 0.5f * (x0 + x1) * d, sy = 0.5f * (y0 + y1) * d;
        for (int i = 0; i < 3; i++)
            center[i] += right[i] * sx + up[i] * sy;
        d = fit_distance(corners, center, f, right, up, tan_h, tan_v, false);
    }
    sinew_camera_mode mode = camera->mode;
    camera->mode = SINEW_CAMERA_ORBIT;
    glm_vec3_copy(center, camera->target);
    camera->distance = fmaxf(d, radius * 0.05f);
    camera->scene_radius = radius;
    sinew_camera_set_mode(camera, mode);
}

void sinew_camera_set_mode(sinew_camera *camera, sinew_camera_mode mode)
{
    float f[3];
    forward_of(camera, f);
    if (camera->distance < MIN_DISTANCE)
        camera->distance = MIN_DISTANCE;
    if (mode == SINEW_CAMERA_FLY) {
        sinew_camera_eye(camera, camera->position);
    } else {
        float eye[3];
        sinew_camera_eye(camera, eye);
        for (int i = 0; i < 3; i++)
            camera->target[i] = eye[i] + f[i] * camera->distance;
    }
    camera->mode = mode;
}

void sinew_camera_look_along(sinew_camera *camera, sinew_camera_view_axis axis)
{
    static const float YAW[] = {0.0f, 180.0f, 90.0f, -90.0f, 0.0f, 0.0f},
                       PITCH[] = {0.0f, 0.0f, 0.0f, 0.0f, 89.0f, -89.0f};
    if ((unsigned)axis > SINEW_VIEW_BOTTOM)
        return;
    camera->yaw = glm_rad(YAW[axis]);
    camera->pitch = clamp_pitch(glm_rad(PITCH[axis]));
}

void sinew_camera_rotate(sinew_camera *camera, float delta_yaw, float delta_pitch)
{
    camera->yaw = fmodf(camera->yaw + delta_yaw, 2.0f * GLM_PIf);
    camera->pitch = clamp_pitch(camera->pitch + delta_pitch);
}

static void translate(sinew_camera *camera, const float d[3])
{
    float *p = camera->mode == SINEW_CAMERA_FLY ? camera->position : camera->target;
    glm_vec3_add(p, (float *)d, p);
}

void sinew_camera_pan(sinew_camera *camera, float right, float up)
{
    float r[3], u[3], d[3];
    sinew_camera_basis(camera, NULL, r, u);
    for (int i = 0; i < 3; i++)
        d[i] = r[i] * right + u[i] * up;
    translate(camera, d);
}

void sinew_camera_zoom(sinew_camera *camera, float factor)
{
    if (!(factor > 0.0f) || !isfinite(factor))
        return;
    if (camera->mode == SINEW_CAMERA_FLY) {
        sinew_camera_move(camera, (1.0f - factor) * camera->distance, 0.0f, 0.0f);
        return;
    }
    camera->distance *= factor;
    if (camera->distance < MIN_DISTANCE)
        camera->distance = MIN_DISTANCE;
}

void sinew_camera_move(sinew_camera *camera, float forward, float right, float up)
{
    float f[3], r[3], d[3];
    sinew_camera_basis(camera, f, r, NULL);
    for (int i = 0; i < 3; i++)
        d[i] = f[i] * forward + r[i] * right;
    d[1] += up;
    translate(camera, d);
}

void sinew_camera_view(const sinew_camera *camera, sinew_mat4 *view)
{
    float eye[3], f[3], r[3], u[3];
    sinew_camera_eye(camera, eye);
    sinew_camera_basis(camera, f, r, u);
    float *m = view->m;
    memset(m, 0, sizeof view->m);
    m[0] = r[0], m[4] = r[1], m[8] = r[2], m[12] = -glm_vec3_dot(r, eye);
    m[1] = u[0], m[5] = u[1], m[9] = u[2], m[13] = -glm_vec3_dot(u, eye);
    m[2] = -f[0], m[6] = -f[1], m[10] = -f[2], m[14] = glm_vec3_dot(f, eye);
    m[15] = 1.0f;
}

void sinew_camera_projection(const sinew_camera *camera, float aspect, sinew_mat4 *projection)
{
    float radius = camera->scene_radius > 0.0f ? camera->scene_radius : 1.0f;
    float reach = camera->mode == SINEW_CAMERA_ORBIT ? camera->distance + radius : radius * 4.0f;
    float far_plane = camera->far_plane > 0.0f ? camera->far_plane : reach * 8.0f + radius * 8.0f;
    float near_plane = camera->near_plane > 0.0f ? camera->near_plane : far_plane * 1e-4f;
    mat4 p;
    aspect = aspect > 0.0f ? aspect : 1.0f;
    if (camera->orthographic) {
        /* what the perspective view shows at the pivot distance; planes either side of the eye,
         * so nothing behind it is cut when the view is parallel */
        float pivot = camera->distance > 0.0f ? camera->distance : radius;
        float half = pivot * tanf(0.5f * fov_of(camera));
        glm_ortho(-half * aspect, half * aspect, -half, half, -far_plane, far_plane, p);
    } else {
        glm_perspective(fov_of(camera), aspect, near_plane, far_plane, p);
    }
    memcpy(projection->m, p, sizeof projection->m);
}
