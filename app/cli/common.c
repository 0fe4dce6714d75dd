/* Loading, clip selection and posing shared by the subcommands. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cjson.h"
#include "cli.h"

void cli_error(const char *format, ...)
{
    va_list args;
    va_start(args, format);
    fputs("sinew: ", stderr);
    vfprintf(stderr, format, args);
    fputc('\n', stderr);
    va_end(args);
}

bool cli_quiet;

void cli_print_warnings(const sinew_model *model)
{
    for (uint32_t i = 0; model && !cli_quiet && i < model->warning_count; i++)
        fprintf(stderr, "sinew: warning: %s\n", model->warnings[i]);
}

void cli_progress_start(cli_progress *p, const char *what, uint32_t total)
{
    memset(p, 0, sizeof *p);
    p->what = what;
    p->total = total;
    p->live = total > 1 && !cli_quiet && isatty(STDERR_FILENO);
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    p->started = (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

void cli_progress_update(cli_progress *p, uint32_t done)
{
    if (!p->live)
        return;
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    double now = (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
    if (done < p->total && now - p->shown < 0.1)
        return;
    p->shown = now;
    double rate = done / (now - p->started > 1e-6 ? now - p->started : 1e-6);
    double left = rate > 0.0 ? (p->total - done) / rate : 0.0;
    if (done == 0)
        fprintf(stderr, "\r%s: 0/%u frames   ", p->what, p->total);
    else
        fprintf(stderr, "\r%s: %u/%u frames, %.1f a second, %d:%02d left   ", p->what, done, p->total, rate,
                (int)left / 60, (int)left % 60);
    fflush(stderr);
}

void cli_progress_end(cli_progress *p)
{
    if (p->live && p->shown > 0.0)
        fputs("\r\033[K", stderr); /* the line goes: the summary follows on stdout */
    p->live = false;
}

void cli_note_times(const sinew_clip *clip, const double *times, uint32_t count, bool loop)
{
    if (cli_quiet || !clip || !(clip->duration >= 0.0f))
        return;
    uint32_t outside = 0, first = 0;
    for (uint32_t i = 0; i < count; i++)
        if (times[i] < 0.0 || times[i] > (double)clip->duration + 1e-6) {
            if (outside++ == 0)
                first = i;
        }
    if (!outside)
        return;
    double t = times[first];
    double to = sinew_clip_time(clip, (float)t, loop ? SINEW_WRAP_LOOP : SINEW_WRAP_CLAMP);
    char more[48] = "";
    if (outside > 1)
        snprintf(more, sizeof more, " (and %u more time%s)", outside - 1, outside > 2 ? "s" : "");
    fprintf(stderr, "sinew: note: %g s lies outside clip \"%s\" (0 to %g s)%s: %s to %g s%s\n", t,
            clip->name ? clip->name : "", (double)clip->duration, more, loop ? "wrapped" : "clamped", to,
            loop ? "" : " (--loop wraps instead)");
}

double cli_json_float(float value)
{
    if (fabsf(value) < 1e-12f)
        return 0.0;
    char text[32];
    for (int digits = 6; digits < 9; digits++) {
        snprintf(text, sizeof text, "%.*g", digits, (double)value);
        if ((float)strtod(text, NULL) == value)
            return strtod(text, NULL);
    }
    snprintf(text, sizeof text, "%.9g", (double)value);
    return strtod(text, NULL);
}

bool cli_threads_arg(int argc, char **argv, int *i, uint32_t most, uint32_t *out)
{
    long n = 0;
    if (*i + 1 >= argc) {
        cli_error("%s: --threads needs a count (1..%u)", argv[0], most);
        return false;
    }
    if (!cli_parse_count(argv[0], "--threads", argv[++*i], 1, most, &n))
        return false;
    *out = (uint32_t)n;
    return true;
}

double cli_now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

bool cli_is_help(const char *arg)
{
    return strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0;
}

sinew_model *cli_load_model(const char *path)
{
    sinew_model *model = NULL;
    sinew_error error = {0};
    app_scene_desc desc = {.path = path, .stderr_fd = STDERR_FILENO, .import = cli_import};
    if (app_load_model(&desc, &model, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return NULL;
    }
    return model;
}

const char *cli_muscles_arg(int argc, char **argv, int *i)
{
    if (*i + 1 < argc) {
        const char *next = argv[*i + 1];
        size_t n = strlen(next);
        if (n > 5 && strcmp(next + n - 5, ".json") == 0) {
            ++*i;
            return next;
        }
    }
    return "";
}

cJSON *cli_muscle_pose_json(const sinew_muscle_pose *p)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", p->name);
    cJSON_AddNumberToObject(o, "length", p->distance);
    cJSON_AddNumberToObject(o, "rest_length", p->state.rest_length);
    cJSON_AddNumberToObject(o, "delta", p->state.delta);
    cJSON_AddNumberToObject(o, "volume", p->state.volume);
    cJSON_AddNumberToObject(o, "rest_volume", p->state.rest_volume);
    cJSON_AddBoolToObject(o, "in_range", p->in_range);
    cJSON *ends[2] = {cJSON_AddArrayToObject(o, "origin"), cJSON_AddArrayToObject(o, "insertion")};
    for (int k = 0; k < 3; k++) {
        cJSON_AddItemToArray(ends[0], cJSON_CreateNumber(cli_json_float(p->origin[k])));
        cJSON_AddItemToArray(ends[1], cJSON_CreateNumber(cli_json_float(p->insertion[k])));
    }
    cJSON *radii = cJSON_AddArrayToObject(o, "radii");
    for (uint32_t k = 0; k < p->node_count; k++)
        cJSON_AddItemToArray(radii, cJSON_CreateNumber(p->radii[k]));
    return o;
}

bool cli_parse_count(const char *command, const char *option, const char *text, long lo, long hi, long *out)
{
    long n = 0;
    if (!app_parse_integer(text, lo, hi, &n)) {
        cli_error("%s: bad %s \"%s\": expected a whole number in %ld..%ld", command, option, text, lo, hi);
        return false;
    }
    *out = n;
    return true;
}

bool cli_parse_size(const char *command, const char *text, int *width, int *height)
{
    if (!app_parse_size(text, 1, 16384, width, height)) {
        cli_error("%s: bad --size \"%s\": expected WIDTHxHEIGHT, each 1..16384", command, text);
        return false;
    }
    /* 4 samples of colour and depth and the image read back: 36 bytes a pixel */
    double pixels = (double)*width * (double)*height;
    if (pixels > CLI_MAX_PIXELS) {
        cli_error("%s: --size %s is %.0f megapixels, more than %.0f (8192x8192): its framebuffers and image would "
                  "take %.1f GB",
                  command, text, pixels / 1e6, CLI_MAX_PIXELS / 1e6, pixels * 36.0 / 1e9);
        return false;
    }
    return true;
}
