/* Display switches by name and value (settings files, and the apps' command lines). */
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
    bool inverted; /* the field turns the switch off (clay: materials off) */
} switch_entry;

static const switch_entry SWITCHES[] = {
    {"materials", offsetof(sinew_render_options, clay), true},
    {"lighting", offsetof(sinew_render_options, unlit), true},
    {"wireframe", offsetof(sinew_render_options, wireframe), false},
    {"meshes", offsetof(sinew_render_options, hide_meshes), true},
    {"skeleton", offsetof(sinew_render_options, skeleton), false},
    {"joint-axes", offsetof(sinew_render_options, joint_axes), false},
    {"joint-names", offsetof(sinew_render_options, joint_names), false},
    {"normals", offsetof(sinew_render_options, normals), false},
    {"grid", offsetof(sinew_render_options, hide_grid), true},
    {"axes", offsetof(sinew_render_options, axes), false},
    {"muscles", offsetof(sinew_render_options, hide_muscles), true},
    {"lod", offsetof(sinew_render_options, crowd_full_detail), true},
    {"shadows", offsetof(sinew_render_options, shadows), false},
    {"ssao", offsetof(sinew_render_options, ssao), false},
    {"outline", offsetof(sinew_render_options, outline), false},
    {"hdri-background", offsetof(sinew_render_options, environment_background), false},
    {"fxaa", offsetof(sinew_render_options, fxaa), false},
};
#define SWITCH_COUNT (sizeof SWITCHES / sizeof SWITCHES[0])

static const char *const NAMES[] = {"materials",       "lighting",    "wireframe",  "meshes",        "skeleton",
                                    "joint-axes",      "joint-names", "normals",    "grid",          "axes",
                                    "muscles",         "lod",         "shadows",    "ssao",          "outline",
                                    "hdri-background", "fxaa",        "shading",    "skinning",      "skinning-method",
                                    "tone-mapping",    "exposure",    "background", "normal-length", NULL};

static const char *const TONES[] = {"auto", "none", "aces", "neutral"};

static const char *const SHADINGS[] = {"phong", "gouraud", "flat", "pbr"};

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

/* The index of `value` among `count` names, case ignored; -1 when it is none of them. */
static int find_name(const char *const *names, int count, const char *value)
{
    for (int i = 0; i < count; i++)
        if (strcasecmp(value, names[i]) == 0)
            return i;
    return -1;
}

/* The whole text as a finite number within [lo, hi]. */
static bool parse_number(const char *v, double lo, double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    double d = strtod(v, &end);
    if (end == v || *end || errno || !isfinite(d) || !(d >= lo && d <= hi))
        return false;
    *out = d;
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
        *(bool *)((char *)o + s->offset) = s->inverted ? !on : on;
        return SINEW_OK;
    }
    if (!value)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s needs a value", name);
    if (strcmp(name, "shading") == 0) {
        int i = find_name(SHADINGS, 4, value);
        if (i >= 0)
            return o->shading = (sinew_shading)i, SINEW_OK;
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "shading: expected phong, gouraud, flat or pbr, not \"%s\"", value);
    }
    if (strcmp(name, "skinning") == 0) {
        if (strcasecmp(value, "gpu") == 0 || strcasecmp(value, "cpu") == 0) {
            o->skinning = strcasecmp(value, "gpu") == 0 ? SINEW_SKINNING_GPU : SINEW_SKINNING_CPU;
            return SINEW_OK;
        }
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "skinning: expected gpu or cpu, not \"%s\"", value);
    }
    if (strcmp(name, "skinning-method") == 0) {
        if (strcasecmp(value, "file") == 0 || strcasecmp(value, "auto") == 0)
            return o->skin_method_set = false, o->skin_method = SINEW_SKIN_LINEAR, SINEW_OK;
        if (strcasecmp(value, "lbs") == 0 || strcasecmp(value, "linear") == 0)
            return o->skin_method_set = true, o->skin_method = SINEW_SKIN_LINEAR, SINEW_OK;
        if (strcasecmp(value, "dqs") == 0 || strcasecmp(value, "dual-quaternion") == 0)
            return o->skin_method_set = true, o->skin_method = SINEW_SKIN_DUAL_QUATERNION, SINEW_OK;
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "skinning-method: expected file (each skin as its file asks), lbs (linear blend) or dqs "
                          "(dual quaternion), not \"%s\"",
                          value);
    }
    if (strcmp(name, "background") == 0) {
        if (strcasecmp(value, "transparent") == 0 || strcasecmp(value, "none") == 0)
            return o->transparent = true, SINEW_OK;
        if (parse_color(value, o->background))
            return o->transparent = false, o->background_set = true, SINEW_OK;
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "background: expected RRGGBB, #RRGGBB, r,g,b in 0..1 or transparent, not \"%s\"", value);
    }
    if (strcmp(name, "tone-mapping") == 0) {
        int i = find_name(TONES, 4, value);
        if (i >= 0)
            return o->tone_mapping = (sinew_tone_mapping)i, SINEW_OK;
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "tone-mapping: expected auto, none, aces or neutral, not \"%s\"", value);
    }
    double d = 0.0;
    if (strcmp(name, "exposure") == 0) {
        if (!parse_number(value, -10.0, 10.0, &d))
            return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                              "exposure: expected stops from -10 to 10 (0: as lit), not \"%s\"", value);
        o->exposure = (float)d;
        return SINEW_OK;
    }
    if (strcmp(name, "normal-length") == 0) {
        if (!parse_number(value, 0.0, INFINITY, &d))
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
        snprintf(out, size, "%s", *(const bool *)((const char *)o + s->offset) != s->inverted ? "on" : "off");
    else if (strcmp(name, "shading") == 0)
        snprintf(out, size, "%s", SHADINGS[o->shading <= SINEW_SHADING_PBR ? o->shading : 0]);
    else if (strcmp(name, "skinning") == 0)
        snprintf(out, size, "%s", o->skinning == SINEW_SKINNING_CPU ? "cpu" : "gpu");
    else if (strcmp(name, "skinning-method") == 0)
        snprintf(out, size, "%s",
                 !o->skin_method_set                            ? "file"
                 : o->skin_method == SINEW_SKIN_DUAL_QUATERNION ? "dqs"
                                                                : "lbs");
    else if (strcmp(name, "background") == 0 && o->transparent)
        snprintf(out, size, "transparent");
    else if (strcmp(name, "background") == 0) {
        float bg[3];
        sinew_render_options_background(o, bg);
        snprintf(out, size, "#%02x%02x%02x", (unsigned)lroundf(bg[0] * 255.0f), (unsigned)lroundf(bg[1] * 255.0f),
                 (unsigned)lroundf(bg[2] * 255.0f));
    } else if (strcmp(name, "normal-length") == 0)
        snprintf(out, size, "%.9g", o->normal_length);
    else if (strcmp(name, "tone-mapping") == 0)
        snprintf(out, size, "%s", TONES[(unsigned)o->tone_mapping <= SINEW_TONE_MAPPING_NEUTRAL ? o->tone_mapping : 0]);
    else if (strcmp(name, "exposure") == 0)
        snprintf(out, size, "%.9g", o->exposure);
    else
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "unknown display option \"%s\"", name);
    return SINEW_OK;
}
