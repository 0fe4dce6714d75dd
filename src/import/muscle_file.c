/* Muscle files: JSON through cJSON, validated field by field; errors point at the line and
 * column of the offending field, found by walking the text along the field's path (cJSON
 * keeps no positions).
 *
 * Index: positions in the text - error messages - field readers - sizing and copying into
 * one block - public functions.
 */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cjson/cJSON.h>

#include "../core/internal.h"
#include "internal.h"
#include "sinew/arm.h"
#include "sinew/muscle_file.h"

/* ---- positions in the text --------------------------------------------------------------- */

/* One step of a path into the document: an object key, or an array index when key is NULL. */
typedef struct path_step {
    const char *key;
    int index;
} path_step;

static size_t skip_space(const char *t, size_t n, size_t p)
{
    while (p < n && (t[p] == ' ' || t[p] == '\t' || t[p] == '\n' || t[p] == '\r'))
        p++;
    return p;
}

/* p at the opening quote; returns just past the closing one. */
static size_t skip_string(const char *t, size_t n, size_t p)
{
    for (p++; p < n && t[p] != '"'; p++)
        if (t[p] == '\\')
            p++;
    return p < n ? p + 1 : n;
}

static size_t skip_value(const char *t, size_t n, size_t p)
{
    p = skip_space(t, n, p);
    if (p >= n)
        return n;
    if (t[p] == '"')
        return skip_string(t, n, p);
    if (t[p] == '{' || t[p] == '[') {
        int depth = 0;
        for (; p < n; p++) {
            if (t[p] == '"') {
                p = skip_string(t, n, p) - 1;
            } else if (t[p] == '{' || t[p] == '[') {
                depth++;
            } else if ((t[p] == '}' || t[p] == ']') && --depth == 0) {
                return p + 1;
            }
        }
        return n;
    }
    while (p < n && !strchr(",]} \t\r\n", t[p]))
        p++;
    return p;
}

/* Offset of the value (or, for a missing last key, of its object) at `path`. */
static size_t locate(const char *t, size_t n, const path_step *path, int depth)
{
    size_t p = skip_space(t, n, 0);
    for (int d = 0; d < depth && p < n; d++) {
        char open = path[d].key ? '{' : '[';
        if (t[p] != open)
            return p;
        size_t container = p;
        p = skip_space(t, n, p + 1);
        bool found = false;
        for (int i = 0; p < n && t[p] != (open == '{' ? '}' : ']'); i++) {
            if (open == '{') {
                size_t key = p + 1, key_end = skip_string(t, n, p);
                size_t len = key_end - key - 1;
                found = strlen(path[d].key) == len && strncmp(t + key, path[d].key, len) == 0;
                p = skip_space(t, n, key_end);
                p = skip_space(t, n, p + 1); /* past ':' */
            } else {
                found = i == path[d].index;
            }
            if (found)
                break;
            p = skip_space(t, n, skip_value(t, n, p));
            if (p < n && t[p] == ',')
                p = skip_space(t, n, p + 1);
        }
        if (!found)
            return container;
    }
    return p;
}

/* ---- messages ---------------------------------------------------------------------------- */

typedef struct reader {
    const char *text;
    size_t size;
    const char *name;
    sinew_error *error;
    path_step path[8];
    int depth;
} reader;

static void describe_path(const reader *r, char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (int d = 0; d < r->depth && used < size; d++) {
        if (r->path[d].key)
            used += (size_t)snprintf(out + used, size - used, "%s%s", d ? "." : "", r->path[d].key);
        else
            used += (size_t)snprintf(out + used, size - used, "[%d]", r->path[d].index);
    }
}

static void line_column(const char *t, size_t offset, int *line, int *column)
{
    *line = 1, *column = 1;
    for (size_t i = 0; i < offset; i++) {
        if (t[i] == '\n')
            (*line)++, *column = 1;
        else
            (*column)++;
    }
}

static sinew_result field_error(const reader *r, const char *format, ...) __attribute__((format(printf, 2, 3)));
static sinew_result field_error(const reader *r, const char *format, ...)
{
    char what[256], where[128];
    va_list args;
    va_start(args, format);
    vsnprintf(what, sizeof what, format, args);
    va_end(args);
    describe_path(r, where, sizeof where);
    int line, column;
    line_column(r->text, locate(r->text, r->size, r->path, r->depth), &line, &column);
    return sinew_fail(r->error, SINEW_ERROR_DATA, "%s:%d:%d: %s: %s", r->name, line, column, where, what);
}

static void push_key(reader *r, const char *key)
{
    r->path[r->depth++] = (path_step){key, 0};
}

static void push_index(reader *r, int index)
{
    r->path[r->depth++] = (path_step){NULL, index};
}

/* ---- field readers ------------------------------------------------------------------------ */

/* Numbers in a muscle file (radii, coefficients, offsets, lengths) stay within this: larger
 * ones overflow the volume's squares and cubes (a radius of 8e306 made the valid range NaN). */
#define MAX_MAGNITUDE SINEW_MUSCLE_MAX_MAGNITUDE

/* Reads a number array of exactly `count` (count > 0) or of 2..max entries (count 0). */
static sinew_result read_numbers(reader *r, const cJSON *array, uint32_t count, uint32_t max, double *out,
                                 uint32_t *got)
{
    if (!cJSON_IsArray(array))
        return field_error(r, "expected an array of numbers");
    uint32_t n = (uint32_t)cJSON_GetArraySize(array);
    if (count ? n != count : (n < 2 || n > max))
        return count ? field_error(r, "expected %u numbers, found %u", count, n)
                     : field_error(r, "expected 2 to %u numbers (a muscle has at least 2 nodes), found %u", max, n);
    uint32_t i = 0;
    for (const cJSON *v = array->child; v; v = v->next, i++) {
        push_index(r, (int)i);
        if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
            return field_error(r, "expected a number");
        if (fabs(v->valuedouble) > MAX_MAGNITUDE)
            return field_error(r, "%g is out of range (at most %g either way)", v->valuedouble, MAX_MAGNITUDE);
        r->depth--;
        out[i] = v->valuedouble;
    }
    if (got)
        *got = n;
    return SINEW_OK;
}

static sinew_result read_attachment(reader *r, const cJSON *o, sinew_muscle_attachment *a, const char **joint)
{
    if (!cJSON_IsObject(o))
        return field_error(r, "expected {\"joint\": NAME, \"offset\": [x, y, z]}");
    *joint = NULL;
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(o, "joint");
    if (j) {
        push_key(r, "joint");
        if (!cJSON_IsString(j) || !j->valuestring[0])
            return field_error(r, "expected a joint name");
        r->depth--;
        *joint = j->valuestring;
    }
    double offset[3] = {0, 0, 0};
    const cJSON *off = cJSON_GetObjectItemCaseSensitive(o, "offset");
    if (off) {
        push_key(r, "offset");
        sinew_result result = read_numbers(r, off, 3, 3, offset, NULL);
        if (result != SINEW_OK)
            return result;
        r->depth--;
    }
    for (int i = 0; i < 3; i++)
        a->offset[i] = (float)offset[i];
    return SINEW_OK;
}

static sinew_result read_color(reader *r, const cJSON *c, float out[3])
{
    if (cJSON_IsString(c)) {
        const char *s = c->valuestring[0] == '#' ? c->valuestring + 1 : c->valuestring;
        if (strlen(s) == 6 && strspn(s, "0123456789abcdefABCDEF") == 6) {
            unsigned long rgb = strtoul(s, NULL, 16);
            for (int i = 0; i < 3; i++)
                out[i] = (float)((rgb >> (16 - 8 * i)) & 0xff) / 255.0f;
            return SINEW_OK;
        }
        return field_error(r, "expected \"#rrggbb\" or [r, g, b] in 0..1");
    }
    double rgb[3];
    sinew_result result = read_numbers(r, c, 3, 3, rgb, NULL);
    if (result != SINEW_OK)
        return result;
    for (int i = 0; i < 3; i++) {
        if (!(rgb[i] >= 0.0 && rgb[i] <= 1.0))
            return field_error(r, "colour components must be in 0..1");
        out[i] = (float)rgb[i];
    }
    return SINEW_OK;
}

/* The parsed numbers and names of one muscle, before they are copied into the set. */
typedef struct muscle_draft {
    sinew_muscle_def def;
    const char *origin_joint, *insertion_joint;
    double radii[SINEW_MUSCLE_MAX_NODES], coefficients[SINEW_MUSCLE_MAX_NODES];
} muscle_draft;

static int by_name_then_index(const void *a, const void *b)
{
    const muscle_draft *const *x = a, *const *y = b;
    int c = strcmp((*x)->def.name, (*y)->def.name);
    return c ? c : (*x < *y ? -1 : *x > *y);
}

/* Two muscles of one name: the later one is refused, naming the earlier (sorted: n log n, a
 * pairwise check never finished at 100,000 muscles). */
static sinew_result check_unique_names(reader *r, muscle_draft *drafts, uint32_t count)
{
    muscle_draft **order = malloc((size_t)count * sizeof *order);
    if (!order)
        return sinew_fail(r->error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", r->name);
    for (uint32_t i = 0; i < count; i++)
        order[i] = &drafts[i];
    qsort(order, count, sizeof *order, by_name_then_index);
    uint32_t first = count, later = count;
    for (uint32_t i = 1; i < count; i++) {
        if (strcmp(order[i - 1]->def.name, order[i]->def.name) != 0)
            continue;
        uint32_t k = (uint32_t)(order[i - 1] - drafts), j = (uint32_t)(order[i] - drafts);
        if (j < later) /* report the duplicate that comes first in the file */
            first = k, later = j;
    }
    free(order);
    if (later == count)
        return SINEW_OK;
    push_index(r, (int)later);
    push_key(r, "name");
    return field_error(r, "\"%s\" is already the name of muscle %u", drafts[later].def.name, first);
}

static sinew_result read_muscle(reader *r, const cJSON *m, muscle_draft *d)
{
    memset(d, 0, sizeof *d);
    d->def.segments = 16;
    d->def.color[0] = 0.69f, d->def.color[1] = 0.23f, d->def.color[2] = 0.18f;
    if (!cJSON_IsObject(m))
        return field_error(r, "expected a muscle object");
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(m, "name");
    push_key(r, "name");
    if (!cJSON_IsString(name) || !name->valuestring[0])
        return field_error(r, name ? "expected a non-empty name" : "missing: every muscle needs a name");
    r->depth--;
    d->def.name = name->valuestring;
    static const char *const ends[2] = {"origin", "insertion"};
    for (int e = 0; e < 2; e++) {
        const cJSON *o = cJSON_GetObjectItemCaseSensitive(m, ends[e]);
        push_key(r, ends[e]);
        if (!o)
            return field_error(r, "missing: every muscle needs an origin and an insertion");
        sinew_result result =
            read_attachment(r, o, e ? &d->def.insertion : &d->def.origin, e ? &d->insertion_joint : &d->origin_joint);
        if (result != SINEW_OK)
            return result;
        r->depth--;
    }
    const cJSON *radii = cJSON_GetObjectItemCaseSensitive(m, "radii");
    push_key(r, "radii");
    if (!radii)
        return field_error(r, "missing: the rest radius of every node");
    sinew_result result = read_numbers(r, radii, 0, SINEW_MUSCLE_MAX_NODES, d->radii, &d->def.node_count);
    if (result != SINEW_OK)
        return result;
    for (uint32_t i = 0; i < d->def.node_count; i++) {
        push_index(r, (int)i);
        if (!(d->radii[i] > 0.0))
            return field_error(r, "radius %g must be greater than 0", d->radii[i]);
        r->depth--;
    }
    r->depth--;
    const cJSON *coefficients = cJSON_GetObjectItemCaseSensitive(m, "coefficients");
    push_key(r, "coefficients");
    if (!coefficients)
        return field_error(r, "missing: a growth coefficient for every node");
    result = read_numbers(r, coefficients, d->def.node_count, d->def.node_count, d->coefficients, NULL);
    if (result != SINEW_OK)
        return result;
    r->depth--;
    const cJSON *rest = cJSON_GetObjectItemCaseSensitive(m, "rest_length");
    if (rest) {
        push_key(r, "rest_length");
        if (!cJSON_IsNumber(rest) || !(rest->valuedouble > 0.0) || !(rest->valuedouble <= MAX_MAGNITUDE))
            return field_error(r, "expected a length greater than 0 and at most %g", MAX_MAGNITUDE);
        r->depth--;
        d->def.rest_length = rest->valuedouble;
    }
    const cJSON *segments = cJSON_GetObjectItemCaseSensitive(m, "segments");
    if (segments) {
        push_key(r, "segments");
        if (!cJSON_IsNumber(segments) || segments->valuedouble != floor(segments->valuedouble) ||
            segments->valuedouble < 3 || segments->valuedouble > 256)
            return field_error(r, "expected a whole number of segments, 3..256");
        r->depth--;
        d->def.segments = (uint32_t)segments->valuedouble;
    }
    const cJSON *color = cJSON_GetObjectItemCaseSensitive(m, "color");
    if (color) {
        push_key(r, "color");
        result = read_color(r, color, d->def.color);
        if (result != SINEW_OK)
            return result;
        r->depth--;
    }
    return SINEW_OK;
}

/* ---- one block ------------------------------------------------------------------------------ */

static size_t text_size(const char *s)
{
    return s ? strlen(s) + 1 : 0;
}

static char *copy_text(char **at, const char *s)
{
    if (!s)
        return NULL;
    size_t n = strlen(s) + 1;
    char *out = memcpy(*at, s, n);
    *at += n;
    return out;
}

static sinew_result build_set(const char *name, const muscle_draft *drafts, uint32_t count, sinew_muscle_set **out,
                              sinew_error *error)
{
    size_t numbers = 0, texts = text_size(name);
    for (uint32_t i = 0; i < count; i++) {
        numbers += 2 * (size_t)drafts[i].def.node_count;
        texts +=
            text_size(drafts[i].def.name) + text_size(drafts[i].origin_joint) + text_size(drafts[i].insertion_joint);
    }
    size_t head = sizeof(sinew_muscle_set) + count * sizeof(sinew_muscle_def);
    head = (head + 7) & ~(size_t)7;
    unsigned char *block = malloc(head + numbers * sizeof(double) + texts);
    if (!block)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    sinew_muscle_set *set = (sinew_muscle_set *)block;
    sinew_muscle_def *defs = (sinew_muscle_def *)(set + 1);
    double *num = (double *)(block + head);
    char *text = (char *)(num + numbers);
    set->source = copy_text(&text, name);
    set->muscle_count = count;
    set->muscles = defs;
    for (uint32_t i = 0; i < count; i++) {
        const muscle_draft *d = &drafts[i];
        sinew_muscle_def *def = &defs[i];
        *def = d->def;
        def->name = copy_text(&text, d->def.name);
        def->origin.joint = copy_text(&text, d->origin_joint);
        def->insertion.joint = copy_text(&text, d->insertion_joint);
        memcpy(num, d->radii, d->def.node_count * sizeof(double));
        def->radii = num;
        num += d->def.node_count;
        memcpy(num, d->coefficients, d->def.node_count * sizeof(double));
        def->coefficients = num;
        num += d->def.node_count;
    }
    *out = set;
    return SINEW_OK;
}

/* ---- public ----------------------------------------------------------------------------------- */

/* Parses NUL-terminated text; NULL with a FILE:LINE:COLUMN error when it is not JSON. */
static cJSON *parse_json(const char *text, size_t size, const char *name, sinew_error *error)
{
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithOpts(text, &end, true);
    if (!root) {
        int line, column;
        size_t at = end && end >= text ? (size_t)(end - text) : 0;
        line_column(text, at > size ? size : at, &line, &column);
        sinew_fail(error, SINEW_ERROR_FORMAT, "%s:%d:%d: not valid JSON here", name, line, column);
    }
    return root;
}

static sinew_result read_document(reader *r, const cJSON *root, sinew_muscle_set **out)
{
    const cJSON *muscles = cJSON_GetObjectItemCaseSensitive(root, "muscles");
    push_key(r, "muscles");
    if (!cJSON_IsObject(root) || !cJSON_IsArray(muscles) || cJSON_GetArraySize(muscles) == 0)
        return field_error(r, "expected {\"muscles\": [ ... ]} with at least one muscle");
    uint32_t count = (uint32_t)cJSON_GetArraySize(muscles);
    muscle_draft *drafts = calloc(count, sizeof *drafts);
    if (!drafts)
        return sinew_fail(r->error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", r->name);
    sinew_result result = SINEW_OK;
    uint32_t i = 0;
    for (const cJSON *m = muscles->child; m && result == SINEW_OK; m = m->next, i++) {
        push_index(r, (int)i);
        result = read_muscle(r, m, &drafts[i]);
        r->depth = 1;
    }
    if (result == SINEW_OK)
        result = check_unique_names(r, drafts, count);
    if (result == SINEW_OK)
        result = build_set(r->name, drafts, count, out, r->error);
    free(drafts);
    return result;
}

sinew_result sinew_muscle_set_parse(const char *text, size_t size, const char *name, sinew_muscle_set **out,
                                    sinew_error *error)
{
    if (!out || (!text && size))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_muscle_set_parse: no text or no output");
    *out = NULL;
    name = name ? name : "muscles";
    char *copy = malloc(size + 1); /* cJSON wants a terminated string */
    if (!copy)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    if (size)
        memcpy(copy, text, size);
    copy[size] = '\0';
    reader r = {.text = copy, .size = size, .name = name, .error = error};
    cJSON *root = parse_json(copy, size, name, error);
    sinew_result result = root ? read_document(&r, root, out) : SINEW_ERROR_FORMAT;
    cJSON_Delete(root);
    free(copy);
    return result;
}

sinew_result sinew_muscle_set_read(const char *path, sinew_muscle_set **out, sinew_error *error)
{
    if (!path || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_muscle_set_read: no path or no output");
    unsigned char *bytes = NULL;
    size_t size = 0;
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
        return sinew_fail(error, SINEW_ERROR_IO, "%s: not a regular file (a muscle file is JSON text)", path);
    if (!import_read_file(path, &bytes, &size))
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot read the muscle file: %s", path, strerror(errno));
    sinew_result result = sinew_muscle_set_parse((const char *)bytes, size, path, out, error);
    import_free(bytes); /* import_read_file's */
    return result;
}

void sinew_muscle_path_for(const char *model_path, char *out, size_t size)
{
    const char *slash = strrchr(model_path, '/');
    const char *dot = strrchr(model_path, '.');
    size_t stem = dot && (!slash || dot > slash) ? (size_t)(dot - model_path) : strlen(model_path);
    snprintf(out, size, "%.*s.muscles.json", (int)stem, model_path);
}

/* ---- the arm's distances ------------------------------------------------------------------- */

static sinew_result read_arm(reader *r, const cJSON *root, sinew_arm_desc *out)
{
    static const char *const names[5] = {"free_to_origin", "origin_to_elbow", "elbow_to_insertion", "insertion_to_free",
                                         "rod_radius"};
    double *fields[5] = {&out->free_to_origin, &out->origin_to_elbow, &out->elbow_to_insertion, &out->insertion_to_free,
                         &out->rod_radius};
    const cJSON *arm = cJSON_GetObjectItemCaseSensitive(root, "arm");
    push_key(r, "arm");
    if (!cJSON_IsObject(root) || !cJSON_IsObject(arm))
        return field_error(r, "expected {\"arm\": {\"free_to_origin\": .., \"origin_to_elbow\": .., "
                              "\"elbow_to_insertion\": .., \"insertion_to_free\": ..}}");
    for (int i = 0; i < 5; i++) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(arm, names[i]);
        push_key(r, names[i]);
        if (!v && i == 4) {
            r->depth--;
            continue;
        }
        if (!v)
            return field_error(r, "missing: the arm needs its four distances");
        if (!cJSON_IsNumber(v) || !(v->valuedouble > 0.0) || !isfinite(v->valuedouble))
            return field_error(r, "expected a distance greater than 0");
        *fields[i] = v->valuedouble;
        r->depth--;
    }
    return SINEW_OK;
}

sinew_result sinew_arm_read(const char *path, sinew_arm_desc *out, sinew_error *error)
{
    if (!path || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_arm_read: no path or no output");
    unsigned char *bytes = NULL;
    size_t size = 0;
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
        return sinew_fail(error, SINEW_ERROR_IO, "%s: not a regular file (the arm file is JSON text)", path);
    if (!import_read_file(path, &bytes, &size))
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot read the arm file", path);
    reader r = {.text = (const char *)bytes, .size = size, .name = path, .error = error};
    cJSON *root = parse_json((const char *)bytes, size, path, error);
    sinew_result result = root ? read_arm(&r, root, out) : SINEW_ERROR_FORMAT;
    cJSON_Delete(root);
    import_free(bytes);
    return result;
}
