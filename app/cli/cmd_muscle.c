/* `sinew muscle FILE.json`: one muscle of a muscle file at a given length. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cjson.h"
#include "cli.h"

static const char muscle_usage[] =
    "usage: sinew muscle FILE.json [--name M] [--length L] [--json]\n"
    "\n"
    "Solves one muscle of a muscle file at length L (default: its rest length): the radius growth delta\n"
    "that keeps the volume of its truncated cones equal to the rest volume, the new radii, and the range\n"
    "of lengths at which every radius stays positive.\n"
    "\n"
    "  --name M     the muscle (default: the first in the file)\n"
    "  --length L   origin-to-insertion length, in the file's units\n"
    "  --json       print {\"muscle\", \"length\", \"rest_length\", \"delta\", \"volume\", \"rest_volume\",\n"
    "               \"rest_radii\", \"coefficients\", \"radii\", \"valid_length\": [min, max]} (volumes with pi;\n"
    "               an unbounded max is null), plus \"valid_length_open\": [bool, bool]\n"
    "\n"
    "The muscle needs a \"rest_length\" in the file; muscles on a rig take theirs from the rest pose.\n";

static cJSON *number_array(const double *v, uint32_t n)
{
    cJSON *a = cJSON_CreateArray();
    for (uint32_t i = 0; i < n; i++)
        cJSON_AddItemToArray(a, cJSON_CreateNumber(v[i]));
    return a;
}

static void print_json(const sinew_muscle_def *m, const sinew_muscle_state *st, const double *radii,
                       const sinew_muscle_range *range)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "muscle", m->name);
    cJSON_AddNumberToObject(o, "length", st->length);
    cJSON_AddNumberToObject(o, "rest_length", st->rest_length);
    cJSON_AddNumberToObject(o, "delta", st->delta);
    cJSON_AddNumberToObject(o, "volume", st->volume);
    cJSON_AddNumberToObject(o, "rest_volume", st->rest_volume);
    cJSON_AddItemToObject(o, "rest_radii", number_array(m->radii, m->node_count));
    cJSON_AddItemToObject(o, "coefficients", number_array(m->coefficients, m->node_count));
    cJSON_AddItemToObject(o, "radii", number_array(radii, m->node_count));
    cJSON *valid = cJSON_AddArrayToObject(o, "valid_length");
    cJSON_AddItemToArray(valid, cJSON_CreateNumber(range->min_length));
    cJSON_AddItemToArray(valid,
                         isfinite(range->max_length) ? cJSON_CreateNumber(range->max_length) : cJSON_CreateNull());
    cJSON *open = cJSON_AddArrayToObject(o, "valid_length_open");
    cJSON_AddItemToArray(open, cJSON_CreateBool(range->min_open));
    cJSON_AddItemToArray(open, cJSON_CreateBool(range->max_open));
    cli_json_print(o, true);
}

static void print_text(const sinew_muscle_def *m, const sinew_muscle_state *st, const double *radii,
                       const sinew_muscle_range *range)
{
    printf("muscle:       %s (%u nodes)\n", m->name, m->node_count);
    printf("length:       %.9g (rest %.9g)\n", st->length, st->rest_length);
    printf("delta:        %.9g\n", st->delta);
    printf("volume:       %.9g (rest %.9g, relative drift %.2e)\n", st->volume, st->rest_volume,
           fabs(st->volume - st->rest_volume) / st->rest_volume);
    printf("valid length: %s%.9g, %.9g%s\n", range->min_open ? "(" : "[", range->min_length, range->max_length,
           range->max_open ? ")" : "]");
    printf("node  rest radius  coefficient  radius\n");
    for (uint32_t i = 0; i < m->node_count; i++)
        printf("%4u  %11.6g  %11.6g  %.9g\n", i, m->radii[i], m->coefficients[i], radii[i]);
}

int cmd_muscle(int argc, char **argv)
{
    const char *path = NULL, *name = NULL;
    double length = NAN;
    bool json = false;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        bool v = i + 1 < argc;
        if (cli_is_help(a)) {
            fputs(muscle_usage, stdout);
            return EXIT_OK;
        } else if (strcmp(a, "--json") == 0) {
            json = true;
        } else if (strcmp(a, "--name") == 0 && v) {
            name = argv[++i];
        } else if (strcmp(a, "--length") == 0 && v) {
            const char *text = argv[++i];
            if (!app_parse_number(text, 1e-300, 1e300, &length)) {
                cli_error("muscle: bad --length \"%s\": expected a positive number", text);
                return EXIT_USAGE;
            }
        } else if (a[0] == '-' && a[1]) {
            cli_error("muscle: unknown option or missing value \"%s\"\n%s", a, muscle_usage);
            return EXIT_USAGE;
        } else if (!path) {
            path = a;
        } else {
            cli_error("muscle: one FILE only (got \"%s\" and \"%s\")", path, a);
            return EXIT_USAGE;
        }
    }
    if (!path) {
        cli_error("muscle: no FILE given\n%s", muscle_usage);
        return EXIT_USAGE;
    }
    sinew_muscle_set *set = NULL;
    sinew_error error = {0};
    if (sinew_muscle_set_read(path, &set, &error) != SINEW_OK) {
        cli_error("%s", error.message);
        return EXIT_BAD_INPUT;
    }
    int code = EXIT_BAD_INPUT;
    int32_t index = name ? sinew_muscle_set_find(set, name) : 0;
    const sinew_muscle_def *m = index >= 0 ? &set->muscles[index] : NULL;
    if (!m) {
        cli_error("%s: no muscle \"%s\" (the file has %u)", path, name, set->muscle_count);
    } else if (!(m->rest_length > 0.0)) {
        cli_error("%s: muscle \"%s\" has no rest_length: on a rig it takes the rest pose's distance "
                  "(sinew pose MODEL --muscles %s)",
                  path, m->name, path);
    } else {
        sinew_muscle_profile profile = {m->node_count, m->radii, m->coefficients, m->rest_length};
        double radii[SINEW_MUSCLE_MAX_NODES];
        sinew_muscle_state st;
        sinew_muscle_range range;
        if (isnan(length))
            length = m->rest_length;
        if (sinew_muscle_valid_range(&profile, &range, &error) != SINEW_OK ||
            sinew_muscle_solve(&profile, length, radii, SINEW_MUSCLE_MAX_NODES, &st, &error) != SINEW_OK) {
            cli_error("%s: muscle \"%s\": %s", path, m->name, error.message);
        } else {
            (json ? print_json : print_text)(m, &st, radii, &range);
            code = EXIT_OK;
        }
    }
    sinew_muscle_set_free(set);
    return code;
}
