/* sinew/camera.h — orbit and free-fly cameras for looking at a posed model.
 *
 * What: one camera value with two modes that share yaw and pitch, so switching mode keeps
 * the view exactly. Orbit: looks at `target` from `distance` away; free-fly: stands at
 * `position`. Frame-all places the orbit target and distance so that a bounding box fills
 * the view. View and projection matrices come out column-major (OpenGL clip space).
 * What not: no input handling and no animation of the camera; the viewer maps mouse and
 * keys onto these calls.
 * Memory: plain values; nothing allocated.
 * Errors: none; degenerate input (zero distance, empty box) is clamped to something drawable.
 * Conventions: right-handed, Y up, radians. Yaw 0 and pitch 0 look along -Z (the camera
 * stands on +Z, in front of a model facing +Z); positive yaw swings the eye around +Y
 * towards +X; positive pitch raises the eye and looks down.
 */
#ifndef SINEW_CAMERA_H
#define SINEW_CAMERA_H

#include <stdbool.h>

#include "sinew/model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sinew_camera_mode { SINEW_CAMERA_ORBIT = 0, SINEW_CAMERA_FLY = 1 } sinew_camera_mode;

typedef struct sinew_camera {
    sinew_camera_mode mode;
    float yaw, pitch;   /* radians, shared by both modes; pitch is kept within ±89° */
    float target[3];    /* orbit: the point looked at */
    float distance;     /* orbit: eye to target; also the pivot distance when switching */
    float position[3];  /* free-fly: the eye */
    float fov_y;        /* vertical field of view in radians; 0 means 45° */
    float near_plane;   /* 0 means automatic from the distance / scene size */
    float far_plane;    /* 0 means automatic */
    float scene_radius; /* set by frame-all; used for automatic clip planes and speeds */
    bool orthographic;  /* parallel projection: the view's height is what the perspective view shows
                         * at the orbit distance (so switching keeps the framing) */
} sinew_camera;

/* Views along the axes, as Blender's numpad and f3d's keys give them. */
typedef enum sinew_camera_view_axis {
    SINEW_VIEW_FRONT = 0, /* from +Z, looking along -Z (a model facing +Z shows its face) */
    SINEW_VIEW_BACK = 1,  /* from -Z */
    SINEW_VIEW_RIGHT = 2, /* from +X (the model's left side) */
    SINEW_VIEW_LEFT = 3,  /* from -X */
    SINEW_VIEW_TOP = 4,   /* from above (pitch 89°, the limit) */
    SINEW_VIEW_BOTTOM = 5 /* from below */
} sinew_camera_view_axis;

/* An orbit camera at yaw 0, pitch 0.3, distance 3 around the origin. */
sinew_camera sinew_camera_default(void);

/* Eye position, unit forward (view direction), right and up vectors. */
void sinew_camera_eye(const sinew_camera *camera, float eye[3]);
void sinew_camera_basis(const sinew_camera *camera, float forward[3], float right[3], float up[3]);

/* Orbit mode: target and distance so that the box's corners, seen along the camera's
 * direction, fill 95% of the view at `aspect` (width / height) on its tighter side, centred
 * (a long model fills the frame's width; perspective and parallel views alike). Keeps
 * yaw/pitch; scene_radius becomes the box's bounding sphere's. */
void sinew_camera_frame(sinew_camera *camera, const float min[3], const float max[3], float aspect);

/* Turns the camera to look along an axis: sets yaw and pitch only (orbit: around the same
 * target, at the same distance; frame-all afterwards to fit). */
void sinew_camera_look_along(sinew_camera *camera, sinew_camera_view_axis axis);

/* Switches mode keeping the eye, the direction and the pivot distance. */
void sinew_camera_set_mode(sinew_camera *camera, sinew_camera_mode mode);

/* Orbit: turn around the target. Free-fly: look around (turn the head). */
void sinew_camera_rotate(sinew_camera *camera, float delta_yaw, float delta_pitch);
/* Moves the target (orbit) or the eye (fly) along the view's right and up vectors. */
void sinew_camera_pan(sinew_camera *camera, float right, float up);
/* Orbit: distance *= factor (factor < 1 zooms in). Fly: moves forward by (1 - factor) * distance. */
void sinew_camera_zoom(sinew_camera *camera, float factor);
/* Free-fly motion in world units: forward along the view, right, and up along +Y.
 * In orbit mode the target moves the same way. */
void sinew_camera_move(sinew_camera *camera, float forward, float right, float up);

void sinew_camera_view(const sinew_camera *camera, sinew_mat4 *view);
void sinew_camera_projection(const sinew_camera *camera, float aspect, sinew_mat4 *projection);

#ifdef __cplusplus
}
#endif
#endif
