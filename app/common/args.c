/* The command-line pieces sinew and sinew-view share: display options and camera specs read
 * from arguments. Application code: the library takes values, not command lines. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"

/* Reads exactly `count` comma-separated numbers (degrees and metres, within +-1e9). */
static bool parse_numbers(const char *text, double *out, int count)
{
    return app_parse_list(text, out, count, count, -1e9, 1e9) == count;
}

sinew_result app_camera_parse(const char *text, sinew_camera *camera, bool *frame_all, sinew_error *error)
{
    const double rad = 3.14159265358979323846 / 180.0;
    if (!text || !camera)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "app_camera_parse: missing argument");
    double v[5];
    static const char *const AXES[] = {"front", "back", "right", "left", "top", "bottom", "side"};
    for (int a = 0; a < 7; a++)
        if (strcmp(text, AXES[a]) == 0) { /* a view along an axis, framed */
            camera->mode = SINEW_CAMERA_ORBIT;
            sinew_camera_look_along(camera, a == 6 ? SINEW_VIEW_RIGHT : (sinew_camera_view_axis)a);
            if (frame_all)
                *frame_all = true;
            return SINEW_OK;
        }
    if (strncmp(text, "orbit:", 6) == 0) {
        const char *args = text + 6;
        size_t len = strlen(args);
        bool auto_distance = len > 5 && strcmp(args + len - 5, ",auto") == 0;
        char angles[128];
        snprintf(angles, sizeof angles, "%.*s", (int)(auto_distance ? len - 5 : len), args);
        if (!auto_distance && parse_numbers(angles, v, 3) && v[2] > 0.0) {
            camera->distance = (float)v[2];
        } else if (parse_numbers(angles, v, 2)) {
            auto_distance = true;
        } else {
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "camera \"%s\": expected orbit:YAW,PITCH[,DISTANCE] (degrees, distance > 0)", text);
        }
        camera->mode = SINEW_CAMERA_ORBIT;
        camera->yaw = (float)(v[0] * rad);
        camera->pitch = 0.0f;
        sinew_camera_rotate(camera, 0.0f, (float)(v[1] * rad));
        if (frame_all)
            *frame_all = auto_distance;
        return SINEW_OK;
    }
    if (strncmp(text, "fly:", 4) == 0 && parse_numbers(text + 4, v, 5)) {
        camera->mode = SINEW_CAMERA_FLY;
        for (int i = 0; i < 3; i++)
            camera->position[i] = (float)v[i];
        camera->yaw = (float)(v[3] * rad);
        camera->pitch = 0.0f;
        sinew_camera_rotate(camera, 0.0f, (float)(v[4] * rad));
        if (frame_all)
            *frame_all = false;
        return SINEW_OK;
    }
    return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                      "camera \"%s\": expected orbit:YAW,PITCH[,DISTANCE], fly:X,Y,Z,YAW,PITCH (degrees) or a view: "
                      "front, back, left, right (side), top, bottom",
                      text);
}

int app_render_option_parse(sinew_render_options *options, int argc, char *const *argv, int i, const char **name_out,
                            sinew_error *error)
{
    if (i >= argc || strncmp(argv[i], "--", 2) != 0)
        return 0;
    const char *arg = argv[i] + 2;
    if (strcmp(arg, "bones") == 0)
        arg = "skeleton";
    bool off = strncmp(arg, "no-", 3) == 0 && sinew_render_option_is_switch(arg + 3);
    const char *name = off ? arg + 3 : arg;
    if (sinew_render_option_is_switch(name)) {
        if (name_out)
            *name_out = name;
        /* An explicit value may follow: --grid off. */
        if (!off && i + 1 < argc && sinew_render_option_set(options, name, argv[i + 1], NULL) == SINEW_OK)
            return 2;
        sinew_render_option_set(options, name, off ? "off" : "on", NULL);
        return 1;
    }
    for (const char *const *n = sinew_render_option_names(); *n; n++) {
        if (strcmp(*n, name) != 0)
            continue;
        if (name_out)
            *name_out = *n;
        if (i + 1 >= argc) {
            sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "--%s needs a value", name);
            return -1;
        }
        return sinew_render_option_set(options, name, argv[i + 1], error) == SINEW_OK ? 2 : -1;
    }
    return 0;
}

static sinew_result parse_point(const char *option, const char *text, float out[3], sinew_error *error)
{
    double v[3];
    if (!text || !parse_numbers(text, v, 3))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s \"%s\": expected X,Y,Z (metres)", option,
                          text ? text : "");
    for (int i = 0; i < 3; i++)
        out[i] = (float)v[i];
    return SINEW_OK;
}

static sinew_result parse_fov(const char *text, double *out, sinew_error *error)
{
    char *end = NULL;
    double v = text ? strtod(text, &end) : NAN;
    if (!text || end == text || *end != '\0' || !(v >= 1.0 && v <= 170.0))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "--fov \"%s\": expected degrees from 1 to 170",
                          text ? text : "");
    *out = v;
    return SINEW_OK;
}

int app_camera_placement_parse(app_camera_placement *p, const char *option, const char *value, sinew_error *error)
{
    sinew_result r;
    if (strcmp(option, "--fov") == 0) {
        r = parse_fov(value, &p->fov, error);
    } else if (strcmp(option, "--camera-position") == 0) {
        r = parse_point(option, value, p->position, error);
        p->has_position = r == SINEW_OK;
    } else if (strcmp(option, "--camera-focal-point") == 0) {
        r = parse_point(option, value, p->focal, error);
        p->has_focal = r == SINEW_OK;
    } else {
        return 0;
    }
    return r == SINEW_OK ? 1 : -1;
}

void app_camera_place(sinew_camera *camera, const app_camera_placement *p)
{
    if (!p || (!p->has_position && !p->has_focal))
        return;
    sinew_camera_set_mode(camera, SINEW_CAMERA_ORBIT);
    if (p->has_focal)
        memcpy(camera->target, p->focal, sizeof camera->target);
    if (!p->has_position)
        return;
    float d[3] = {camera->target[0] - p->position[0], camera->target[1] - p->position[1],
                  camera->target[2] - p->position[2]};
    float length = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (length < 1e-6f) /* the eye on the focal point: looking along -z from there */
        d[2] = -1.0f, length = 1.0f;
    for (int i = 0; i < 3; i++)
        d[i] /= length;
    /* forward = (-sin yaw cos pitch, -sin pitch, -cos yaw cos pitch) (sinew/camera.h) */
    camera->pitch = 0.0f;
    camera->yaw = atan2f(-d[0], -d[2]);
    sinew_camera_rotate(camera, 0.0f, asinf(fmaxf(-1.0f, fminf(1.0f, -d[1]))));
    camera->distance = length;
}
