/* Muscle files: JSON through the library's reader (json.h), validated field by field; errors
 * name the field's path and point at the line and column where its value starts (or, for a
 * missing field, its object).
 *
 * Index: error messages - field readers - sizing and copying into one block - public functions.
 */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../core/internal.h"
#include "internal.h"
#include "json.h"
#include "sinew/arm.h"
#include "sinew/muscle_file.h"

/* One step of a path into the document: an object key, or an array index when key is NULL. */
typedef struct path_step {
    const char *key;
    int index;
} path_step;

/* ---- messages ---------------------------------------------------------------------------- */

typedef struct reader {
    const char *text;
    const char *name;
    sinew_error *error;
    const json_node *root;
    path_step path[8];
    const json_node *at[8]; /* the value at each step of the path; NULL where it is missing */
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

static sinew_result field_error(const reader *r, const char *format, ...) __attribute__((format(printf, 2, 3)));
static sinew_result field_error(const reader *r, const char *format, ...)
{
    char what[256], where[128];
    va_list args;
    va_start(args, format);
    vsnprintf(what, sizeof what, format, args);
    va_end(args);
    describe_path(r, where, sizeof where);
    const json_node *at = r->root; /* the deepest value on the path that is there */
    for (int d = r->depth - 1; d >= 0; d--)
        if (r->at[d]) {
            at = r->at[d];
            break;
        }
    int line, column; /* a string's offset is past its opening quote */
    json_line_column(r->text, at->offset - (at->type == JSON_STRING), &line, &column);
    return sinew_fail(r->error, SINEW_ERROR_DATA, "%s:%d:%d: %s: %s", r->name, line, column, where, what);
}

static void push_key(reader *r, const char *key, const json_node *value)
{
    r->at[r->depth] = value;
    r->path[r->depth++] = (path_step){key, 0};
}

static void push_index(reader *r, int index, const json_node *value)
{
    r->at[r->depth] = value;
    r->path[r->depth++] = (path_step){NULL, index};
}

/* ---- field readers ------------------------------------------------------------------------ */

/* Numbers in a muscle file (radii, coefficients, offsets, lengths) stay within this: larger
 * ones overflow the volume's squares and cubes (a radius of 8e306 made the valid range NaN). */
#define MAX_MAGNITUDE SINEW_MUSCLE_MAX_MAGNITUDE

/* Reads a number array of exactly `count` (count > 0) or of 2..max entries (count 0). */
static sinew_result read_numbers(reader *r, const json_node *array, uint32_t count, uint32_t max, double *out,
                                 uint32_t *got)
{
    if (!json_is_array(array))
        return field_error(r, "expected an array of numbers");
    uint32_t n = (uint32_t)json_size(array);
    if (count ? n != count : (n < 2 || n > max))
        return count ? field_error(r, "expected %u numbers, found %u", count, n)
                     : field_error(r, "expected 2 to %u numbers (a muscle has at least 2 nodes), found %u", max, n);
    uint32_t i = 0;
    const json_node *v;
    JSON_FOR_EACH(v, array)
    {
        push_index(r, (int)i, v);
        if (!json_is_number(v) || !isfinite(v->number))
            return field_error(r, "expected a number");
        if (fabs(v->number) > MAX_MAGNITUDE)
            return field_error(r, "%g is out of range (at most %g either way)", v->number, MAX_MAGNITUDE);
        r->depth--;
        out[i++] = v->number;
    }
    if (got)
        *got = n;
    return SINEW_OK;
}

static sinew_result read_attachment(reader *r, const json_node *o, sinew_muscle_attachment *a, const char **joint)
{
    if (!json_is_object(o))
        return field_error(r, "expected {\"joint\": NAME, \"offset\": [x, y, z]}");
    *joint = NULL;
    const json_node *j = json_get(o, "joint");
    if (j) {
        push_key(r, "joint", j);
        if (!json_is_string(j) || !j->string[0])
            return field_error(r, "expected a joint name");
        r->depth--;
        *joint = j->string;
    }
    double offset[3] = {0, 0, 0};
    const json_node *off = json_get(o, "offset");
    if (off) {
        push_key(r, "offset", off);
        sinew_result result = read_numbers(r, off, 3, 3, offset, NULL);
        if (result != SINEW_OK)
            return result;
        r->depth--;
    }
    for (int i = 0; i < 3; i++)
        a->offset[i] = (float)offset[i];
    return SINEW_OK;
}

static sinew_result read_color(reader *r, const json_node *c, float out[3])
{
    if (json_is_string(c)) {
        const char *s = c->string[0] == '#' ? c->string + 1 : c->string;
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
    const json_node *name_node; /* where the name is, for messages */
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
    push_index(r, (int)later, NULL);
    push_key(r, "name", drafts[later].name_node);
    return field_error(r, "\"%s\" is already the name of muscle %u", drafts[later].def.name, first);
}

static sinew_result read_muscle(reader *r, const json_node *m, muscle_draft *d)
{
    memset(d, 0, sizeof *d);
    d->def.segments = 16;
    d->def.color[0] = 0.69f, d->def.color[1] = 0.23f, d->def.color[2] = 0.18f;
    if (!json_is_object(m))
        return field_error(r, "expected a muscle object");
    const json_node *name = json_get(m, "name");
    push_key(r, "name", name);
    if (!json_is_string(name) || !name->string[0])
        return field_error(r, name ? "expected a non-empty name" : "missing: every muscle needs a name");
    r->depth--;
    d->def.name = name->string;
    d->name_node = name;
    static const char *const ends[2] = {"origin", "insertion"};
    for (int e = 0; e < 2; e++) {
        const json_node *o = json_get(m, ends[e]);
        push_key(r, ends[e], o);
        if (!o)
            return field_error(r, "missing: every muscle needs an origin and an insertion");
        sinew_result result =
            read_attachment(r, o, e ? &d->def.insertion : &d->def.origin, e ? &d->insertion_joint : &d->origin_joint);
        if (result != SINEW_OK)
            return result;
        r->depth--;
    }
    const json_node *radii = json_get(m, "radii");
    push_key(r, "radii", radii);
    if (!radii)
        return field_error(r, "missing: the rest radius of every node");
    sinew_result result = read_numbers(r, radii, 0, SINEW_MUSCLE_MAX_NODES, d->radii, &d->def.node_count);
    if (result != SINEW_OK)
        return result;
    for (uint32_t i = 0; i < d->def.node_count; i++) {
        push_index(r, (int)i, json_item(radii, (int)i));
        if (!(d->radii[i] > 0.0))
            return field_error(r, "radius %g must be greater than 0", d->radii[i]);
        r->depth--;
    }
    r->depth--;
    const json_node *coefficients = json_get(m, "coefficients");
    push_key(r, "coefficients", coefficients);
    if (!coefficients)
        return field_error(r, "missing: a growth coefficient for every node");
    result = read_numbers(r, coefficients, d->def.node_count, d->def.node_count, d->coefficients, NULL);
    if (result != SINEW_OK)
        return result;
    r->depth--;
    const json_node *rest = json_get(m, "rest_length");
    if (rest) {
        push_key(r, "rest_length", rest);
        if (!json_is_number(rest) || !(rest->number > 0.0) || !(rest->number <= MAX_MAGNITUDE))
            return field_error(r, "expected a length greater than 0 and at most %g", MAX_MAGNITUDE);
        r->depth--;
        d->def.rest_length = rest->number;
    }
    const json_node *segments = json_get(m, "segments");
    if (segments) {
        push_key(r, "segments", segments);
        if (!json_is_number(segments) || segments->number != floor(segments->number) || segments->number < 3 ||
            segments->number > 256)
            return field_error(r, "expected a whole number of segments, 3..256");
        r->depth--;
        d->def.segments = (uint32_t)segments->number;
    }
    const json_node *color = json_get(m, "color");
    if (color) {
        push_key(r, "color", color);
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

static sinew_result read_muscles(reader *r, void *out)
{
    const json_node *root = r->root, *muscles = json_get(root, "muscles");
    push_key(r, "muscles", muscles);
    if (!json_is_object(root) || !json_is_array(muscles) || json_size(muscles) == 0)
        return field_error(r, "expected {\"muscles\": [ ... ]} with at least one muscle");
    uint32_t count = (uint32_t)json_size(muscles);
    muscle_draft *drafts = calloc(count, sizeof *drafts);
    if (!drafts)
        return sinew_fail(r->error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", r->name);
    sinew_result result = SINEW_OK;
    uint32_t i = 0;
    const json_node *m;
    JSON_FOR_EACH(m, muscles)
    {
        push_index(r, (int)i, m);
        result = read_muscle(r, m, &drafts[i++]);
        r->depth = 1;
        if (result != SINEW_OK)
            break;
    }
    if (result == SINEW_OK)
        result = check_unique_names(r, drafts, count);
    if (result == SINEW_OK)
        result = build_set(r->name, drafts, count, (sinew_muscle_set **)out, r->error);
    free(drafts);
    return result;
}

/* The document in `text` read by `read` (muscles or the arm). */
static sinew_result read_json(const char *text, size_t size, const char *name,
                              sinew_result (*read)(reader *r, void *out), void *out, sinew_error *error)
{
    json_doc doc;
    sinew_result result = json_parse_named(text, size, name, &doc, error);
    if (result != SINEW_OK)
        return result;
    reader r = {.text = text, .name = name, .error = error, .root = doc.root};
    result = read(&r, out);
    json_free(&doc);
    return result;
}

sinew_result sinew_muscle_set_parse(const char *text, size_t size, const char *name, sinew_muscle_set **out,
                                    sinew_error *error)
{
    if (!out || (!text && size))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_muscle_set_parse: no text or no output");
    *out = NULL;
    return read_json(text ? text : "", size, name ? name : "muscles", read_muscles, out, error);
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

static sinew_result read_arm(reader *r, void *out_arm)
{
    sinew_arm_desc *out = out_arm;
    static const char *const names[5] = {"free_to_origin", "origin_to_elbow", "elbow_to_insertion", "insertion_to_free",
                                         "rod_radius"};
    double *fields[5] = {&out->free_to_origin, &out->origin_to_elbow, &out->elbow_to_insertion, &out->insertion_to_free,
                         &out->rod_radius};
    const json_node *root = r->root, *arm = json_get(root, "arm");
    push_key(r, "arm", arm);
    if (!json_is_object(root) || !json_is_object(arm))
        return field_error(r, "expected {\"arm\": {\"free_to_origin\": .., \"origin_to_elbow\": .., "
                              "\"elbow_to_insertion\": .., \"insertion_to_free\": ..}}");
    for (int i = 0; i < 5; i++) {
        const json_node *v = json_get(arm, names[i]);
        push_key(r, names[i], v);
        if (!v && i == 4) {
            r->depth--;
            continue;
        }
        if (!v)
            return field_error(r, "missing: the arm needs its four distances");
        if (!json_is_number(v) || !(v->number > 0.0) || !isfinite(v->number))
            return field_error(r, "expected a distance greater than 0");
        *fields[i] = v->number;
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
    sinew_result result = read_json((const char *)bytes, size, path, read_arm, out, error);
    import_free(bytes);
    return result;
}
