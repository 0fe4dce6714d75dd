/* Display switches and camera specs read from text (command lines, settings files). */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "internal.h"

typedef struct switch_entry {
    const char *name;
    size_t offset; /* of a bool in sinew_render_options */
} switch_entry;

static const switch_entry SWITCHES[] = {
    {"materials", offsetof(sinew_render_options, materials)},
    {"lighting", offsetof(sinew_render_options, lighting)},
    {"wireframe", offsetof(sinew_render_options, wireframe)},
    {"meshes", offsetof(sinew_render_options, meshes)},
    {"skeleton", offsetof(sinew_render_options, skeleton)},
    {"joint-axes", offsetof(sinew_render_options, joint_axes)},
    {"joint-names", offsetof(sinew_render_options, joint_names)},
    {"normals", offsetof(sinew_render_options, normals)},
    {"grid", offsetof(sinew_render_options, grid)},
    {"axes", offsetof(sinew_render_options, axes)},
    {"muscles", offsetof(sinew_render_options, muscles)},
};
#define SWITCH_COUNT (sizeof SWITCHES / sizeof SWITCHES[0])

static const char *const NAMES[] = {"materials",  "lighting",    "wireframe",  "meshes",        "skeleton",
                                    "joint-axes", "joint-names", "normals",    "grid",          "axes",
                                    "muscles",    "shading",     "skinning",   "background", "normal-length", NULL};

static const char *const SHADINGS[] = {"phong", "gouraud", "flat"};

const char *const *sinew_render_option_names(void)
{
    return NAMES;
}

static const switch_entry *find_switch(const char *name)
{
    for (size_t i = 0; i < SWITCH_COUNT; i++)
        if (strcmp(SWITCHES[i].name, name) == 0)
            return &SWITCHES[i];
    return NULL;
}

bool sinew_render_option_is_switch(const char *name)
{
    return name && find_switch(name);
}

static bool parse_bool(const char *v, bool *out)
{
    static const char *const yes[] = {"on", "true", "yes", "1"}, *const no[] = {"off", "false", "no", "0"};
    for (int i = 0; i < 4; i++) {
        if (strcasecmp(v, yes[i]) == 0)
            return *out = true, true;
        if (strcasecmp(v, no[i]) == 0)
            return *out = false, true;
    }
    return false;
}

/* RRGGBB, #RRGGBB, or r,g,b with components in 0..1. */
static bool parse_color(const char *v, float out[3])
{
    const char *hex = v[0] == '#' ? v + 1 : v;
    if (strlen(hex) == 6 && strspn(hex, "0123456789abcdefABCDEF") == 6) {
        unsigned long rgb = strtoul(hex, NULL, 16);
        for (int i = 0; i < 3; i++)
            out[i] = (float)((rgb >> (16 - 8 * i)) & 0xff) / 255.0f;
        return true;
    }
    float c[3];
    char tail;
    if (sscanf(v, "%f,%f,%f%c", &c[0], &c[1], &c[2], &tail) != 3)
        return false;
    for (int i = 0; i < 3; i++)
        if (!(c[i] >= 0.0f && c[i] <= 1.0f))
            return false;
    memcpy(out, c, sizeof c);
    return true;
}

sinew_result sinew_render_option_set(sinew_render_options *o, const char *name, const char *value, sinew_error *error)
{
    if (!o || !name)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_render_option_set: no options or no name");
    const switch_entry *s = find_switch(name);
    if (s) {
        bool on = true;
        if (value && !parse_bool(value, &on))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s: expected on or off, not \"%s\"", name, value);
        *(bool *)((char *)o + s->offset) = on;
        return SINEW_OK;
    }
    if (!value)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s needs a value", name);
    if (strcmp(name, "shading") == 0) {
        for (int i = 0; i < 3; i++)
            if (strcasecmp(value, SHADINGS[i]) == 0)
                return o->shading = (sinew_shading)i, SINEW_OK;
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "shading: expected phong, gouraud or flat, not \"%s\"",
                          value);
    }
    if (strcmp(name, "skinning") == 0) {
        if (strcasecmp(value, "gpu") == 0 || strcasecmp(value, "cpu") == 0) {
            o->skinning = strcasecmp(value, "gpu") == 0 ? SINEW_SKINNING_GPU : SINEW_SKINNING_CPU;
            return SINEW_OK;
        }
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "skinning: expected gpu or cpu, not \"%s\"", value);
    }
    if (strcmp(name, "background") == 0) {
        if (parse_color(value, o->background))
            return SINEW_OK;
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "background: expected RRGGBB, #RRGGBB or r,g,b in 0..1, not \"%s\"", value);
    }
    if (strcmp(name, "normal-length") == 0) {
        char *end = NULL;
        errno = 0;
        double d = strtod(value, &end);
        if (end == value || *end || errno || !(d >= 0.0) || !isfinite(d))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "normal-length: expected a length >= 0 (0 = automatic), not \"%s\"", value);
        o->normal_length = (float)d;
        return SINEW_OK;
    }
    return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "unknown display option \"%s\"", name);
}

sinew_result sinew_render_option_get(const sinew_render_options *o, const char *name, char *out, size_t size,
                                     sinew_error *error)
{
    if (!o || !name || !out || !size)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_render_option_get: missing argument");
    const switch_entry *s = find_switch(name);
    if (s)
        snprintf(out, size, "%s", *(const bool *)((const char *)o + s->offset) ? "on" : "off");
    else if (strcmp(name, "shading") == 0)
        snprintf(out, size, "%s", SHADINGS[o->shading <= SINEW_SHADING_FLAT ? o->shading : 0]);
    else if (strcmp(name, "skinning") == 0)
        snprintf(out, size, "%s", o->skinning == SINEW_SKINNING_CPU ? "cpu" : "gpu");
    else if (strcmp(name, "background") == 0)
        snprintf(out, size, "#%02x%02x%02x", (unsigned)lroundf(o->background[0] * 255.0f),
                 (unsigned)lroundf(o->background[1] * 255.0f), (unsigned)lroundf(o->background[2] * 255.0f));
    else if (strcmp(name, "normal-length") == 0)
        snprintf(out, size, "%.9g", o->normal_length);
    else
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "unknown display option \"%s\"", name);
    return SINEW_OK;
}

/* Reads exactly `count` comma-separated finite numbers. */
static bool parse_numbers(const char *text, double *out, int count)
{
    const char *p = text;
    for (int i = 0; i < count; i++) {
        char *end = NULL;
        errno = 0;
        out[i] = strtod(p, &end);
        if (end == p || errno || !isfinite(out[i]))
            return false;
        if (i + 1 < count) {
            if (*end != ',')
                return false;
            p = end + 1;
        } else if (*end) {
            return false;
        }
    }
    return true;
}

sinew_result sinew_camera_parse(const char *text, sinew_camera *camera, bool *frame_all, sinew_error *error)
{
    const double rad = 3.14159265358979323846 / 180.0;
    if (!text || !camera)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_camera_parse: missing argument");
    double v[5];
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
                      "camera \"%s\": expected orbit:YAW,PITCH[,DISTANCE] or fly:X,Y,Z,YAW,PITCH (degrees)", text);
}

int sinew_render_option_parse(sinew_render_options *options, int argc, char *const *argv, int i, const char **name_out,
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
