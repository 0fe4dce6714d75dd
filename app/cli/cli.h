/* Shared pieces of the `sinew` command: exit codes, model loading, posing helpers. */
#ifndef SINEW_CLI_H
#define SINEW_CLI_H

#include <stdio.h>

#include "sinew/sinew.h"

enum { EXIT_OK = 0, EXIT_USAGE = 1, EXIT_BAD_INPUT = 2 };

/* Prints "sinew: <message>" to stderr. */
void cli_error(const char *format, ...) __attribute__((format(printf, 1, 2)));

/* Loads a model file (any format Assimp reads) or prints the error; NULL on failure. */
sinew_model *cli_load_model(const char *path);

/* Resolves --clip NAME|INDEX; NULL spec picks clip 0 (or none when the model has none).
 * Returns false (after printing why) when the clip does not exist. */
bool cli_pick_clip(const sinew_model *model, const char *spec, int32_t *clip);

/* The double nearest the shortest decimal that reads back as `value`, so JSON shows
 * 0.1 rather than 0.100000001490116 for a float 0.1; tiny values below 1e-12 become 0. */
double cli_json_float(float value);

/* True when `arg` is --help or -h. */
bool cli_is_help(const char *arg);

/* A posed model: locals, world matrices, scratch for one skin palette. */
typedef struct cli_pose {
    const sinew_model *model;
    sinew_transform *locals;
    sinew_mat4 *worlds;
    sinew_mat4 *palette;
    void *context_memory;
    sinew_sample_context *context;
} cli_pose;

bool cli_pose_init(cli_pose *pose, const sinew_model *model, const sinew_clip *clip);
bool cli_pose_at(cli_pose *pose, const sinew_clip *clip, float time, sinew_wrap wrap);
void cli_pose_free(cli_pose *pose);

int cmd_info(int argc, char **argv);
int cmd_pose(int argc, char **argv);

#endif
