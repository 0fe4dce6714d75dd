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

void sinew_camera_frame(sinew_camera *camera, const float min[3], const float max[3], float aspect)
{
    float center[3], radius = 0.0f;
    for (int i = 0; i < 3; i++) {
        float lo = min[i], hi = max[i];
        if (!(lo <= hi) || !isfinite(lo) || !isfinite(hi))
            lo = hi = 0.0f;
        center[i] = 0.5f * (lo + hi);
        radius += 0.25f * (hi - lo) * (hi - lo);
    }
    radius = sqrtf(radius);
    if (radius < 1e-3f)
        radius = 1.0f;
    float half_v = 0.5f * fov_of(camera);
    float half_h = atanf(tanf(half_v) * (aspect > 0.0f ? aspect : 1.0f));
    float half = half_v < half_h ? half_v : half_h;
    sinew_camera_mode mode = camera->mode;
    camera->mode = SINEW_CAMERA_ORBIT;
    glm_vec3_copy(center, camera->target);
    camera->distance = radius / sinf(half) * 1.05f;
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
