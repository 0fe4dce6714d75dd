/* glTF 2.0 read by sinew (JSON through jsmn, json.h): .gltf with external or data: URI buffers, and .glb.
 *
 * What the file says, checked against the file: nodes by index (names are for display;
 * unnamed nodes are "nodes[i]"), every primitive of every mesh, skins with every JOINTS_n /
 * WEIGHTS_n set, materials (base colour factor and texture, KHR_texture_transform applied
 * to the UVs), animations with each sampler's own interpolation (STEP, LINEAR and
 * CUBICSPLINE are the runtime's), KHR_mesh_quantization's integer attributes; morph targets
 * (POSITION, NORMAL and TANGENT offsets, sparse or not, named by the mesh's
 * extras.targetNames), each node drawing such a mesh with channels of its own (its weights,
 * else the mesh's, else 0) and "weights" animation channels split into one weight track a
 * target. Every index, count, offset and stride is checked; a bad file is refused with
 * "FILE: where in the document: what is wrong".
 *
 * Index:
 *   errors and JSON ......... fail_at, member, int_at, number_at, numbers_at
 *   file and buffers ........ load_document (JSON, GLB chunks), buffer_bytes (BIN, data:, file)
 *   accessors ............... read_accessor (types, normalisation, strides, sparse)
 *   nodes ................... build_nodes (scene roots first, parents before children)
 *   materials ............... build_materials, texture_path
 *   meshes .................. read_primitive, read_targets, build_meshes (a mesh per primitive
 *                             and skin; morph channels a node), node_channels
 *   clips ................... read_channel, build_clips
 *   raw_model_from_gltf
 */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/internal.h"
#include "internal.h"
#include "json.h"
#include "sinew/anim.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

#define GLTF_MAX_COUNT (1u << 28) /* elements in one accessor, nodes, ... */

typedef struct blob {
    unsigned char *bytes;
    size_t size;
    bool owned;
    bool loaded;
} blob;

typedef struct mesh_key {
    int mesh, skin; /* glTF mesh, glTF skin (-1: rigid) */
    uint32_t first; /* its raw meshes */
    uint32_t count;
} mesh_key;

/* A JSON array's elements by index (json_item walks). */
typedef struct table {
    const json_node **at;
    int count;
} table;

typedef struct gltf {
    const char *path;
    raw_model *m;
    sinew_error *error;
    json_doc doc;
    const json_node *json; /* doc.root */
    const unsigned char *file;
    size_t file_size;
    blob bin; /* the GLB BIN chunk (not owned) */
    bool has_bin;
    blob *buffers;
    int buffer_count;
    table accessors, views, nodes, meshes, skins, materials, textures, images, buffer_items, animations;
    int node_count;
    uint32_t *node_of; /* glTF node -> sinew node */
    bool *in_scene;    /* by glTF node */
    mesh_key *keys;
    uint32_t key_count;
    float (*uv_transform)[6]; /* by material: u' = a u + b v + c, v' = d u + e v + f */
    bool *has_uv_transform;
    int32_t *morph_first;  /* by glTF node: the model channel of its mesh's target 0, or -1 */
    uint32_t *morph_count; /* by glTF node: its mesh's targets */
    /* Samplers' input times read already (checked), by accessor: exporters give every channel of
     * a clip the same input (robot.glb: 1806 samplers, 8 inputs), read again for each it was a
     * third of the import. The most recent INPUT_CACHE, each owned here. */
#define INPUT_CACHE 16
    struct {
        int accessor;
        float *times; /* NULL: an empty slot */
        uint32_t count;
    } inputs[INPUT_CACHE];
    uint32_t input_next;
    struct place_label *labels; /* the innermost open label (label_open) */
} gltf;

/* ---- errors and JSON ------------------------------------------------------------------ */

static sinew_result fail_at(gltf *g, const char *format, ...) __attribute__((format(printf, 2, 3)));
static void labels_write(gltf *g);
static sinew_result fail_at(gltf *g, const char *format, ...)
{
    labels_write(g); /* before the arguments, which may be their texts, are read */
    char what[512];
    va_list ap;
    va_start(ap, format);
    vsnprintf(what, sizeof what, format, ap);
    va_end(ap);
    return sinew_fail_at(g->error, SINEW_ERROR_FORMAT, g->path, -1, 0, "%s: %s", g->path, what);
}

/* A place in the file for messages ("accessors[3] (animations[0].samplers[2] input)"): only
 * %d and %s, a tenth of snprintf's cost. Truncated to `size`. */
static void place(char *out, size_t size, const char *format, ...) __attribute__((format(printf, 3, 4)));
static void place(char *out, size_t size, const char *format, ...)
{
    va_list ap;
    va_start(ap, format);
    size_t n = 0;
    for (const char *f = format; *f && n + 1 < size;) {
        const char *run;
        size_t len;
        char digits[12];
        if (f[0] == '%' && f[1] == 'd') {
            int v = va_arg(ap, int);
            unsigned u = v < 0 ? 0u - (unsigned)v : (unsigned)v;
            size_t k = sizeof digits;
            do
                digits[--k] = (char)('0' + u % 10);
            while (u /= 10);
            if (v < 0)
                digits[--k] = '-';
            run = digits + k, len = sizeof digits - k, f += 2;
        } else if (f[0] == '%' && f[1] == 's') {
            run = va_arg(ap, const char *), len = strlen(run), f += 2;
        } else {
            const char *pct = strchr(f + 1, '%');
            run = f, len = pct ? (size_t)(pct - f) : strlen(f), f += len;
        }
        if (len > size - 1 - n)
            len = size - 1 - n;
        memcpy(out + n, run, len);
        n += len;
    }
    out[n] = 0;
    va_end(ap);
}

/* A place written only if a message needs it. The reader formats one for each animation channel,
 * sampler, accessor and buffer view it reads (robot.glb: some 9,000, 6% of its import), and
 * nearly none is ever shown. label_open() gives the text's buffer, empty until fail_at() (or
 * labels_write()) writes every open label into its buffer, outer ones first (an inner label's %s
 * may be an outer one's text); label_close() before the label's scope ends. The format takes %d
 * twice at most (a, then b) and %s once (s). */
typedef struct place_label {
    char text[128];
    const char *format, *s;
    int a, b;
    struct place_label *outer;
} place_label;

static const char *label_open(gltf *g, place_label *l, const char *format, int a, int b, const char *s)
{
    l->text[0] = 0;
    l->format = format, l->a = a, l->b = b, l->s = s;
    l->outer = g->labels;
    g->labels = l;
    return l->text;
}

static void label_close(gltf *g, const place_label *l)
{
    g->labels = l->outer;
}

static void label_write(place_label *l)
{
    if (!l)
        return;
    label_write(l->outer);
    const char *f = l->format;
    int pct = 0;
    for (const char *p = f; (p = strchr(p, '%')); p += 2)
        pct = pct * 4 + (p[1] == 'd' ? 1 : 2); /* the conversions in order, two bits each */
    switch (pct) {                             /* the shapes the reader uses */
    case 1:
        place(l->text, sizeof l->text, f, l->a);
        break;
    case 2:
        place(l->text, sizeof l->text, f, l->s);
        break;
    case 1 * 4 + 1:
        place(l->text, sizeof l->text, f, l->a, l->b);
        break;
    case 1 * 4 + 2:
        place(l->text, sizeof l->text, f, l->a, l->s);
        break;
    default:
        place(l->text, sizeof l->text, "%s", f);
        break;
    }
}

static void labels_write(gltf *g)
{
    label_write(g->labels);
}

static sinew_result oom(gltf *g)
{
    return sinew_fail(g->error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory while reading glTF", g->path);
}

/* A member that must have one type when present; NULL when absent (or of another type,
 * which *bad reports). */
static const json_node *member(const json_node *object, const char *key, int type, bool *bad)
{
    const json_node *item = json_get(object, key);
    if (!item)
        return NULL;
    if (item->type != type) {
        *bad = true;
        return NULL;
    }
    return item;
}

/* An integer member `key` (`item`, found already: NULL when absent) in [lo, hi]; `fallback` when
 * absent. */
static sinew_result int_of(gltf *g, const json_node *item, const char *key, const char *where, long long lo,
                           long long hi, long long fallback, long long *out)
{
    *out = fallback; /* also when refused: callers' variables are never read uninitialised */
    if (!item)
        return SINEW_OK;
    double v = json_is_number(item) ? item->number : NAN;
    if (!(v >= (double)lo && v <= (double)hi) || v != (double)(long long)v) /* in range: no overflow */
        return fail_at(g, "%s.%s: not an integer from %lld to %lld", where, key, lo, hi);
    *out = (long long)v;
    return SINEW_OK;
}

/* The same by its key. */
static sinew_result int_at(gltf *g, const json_node *object, const char *key, const char *where, long long lo,
                           long long hi, long long fallback, long long *out)
{
    return int_of(g, json_get(object, key), key, where, lo, hi, fallback, out);
}

/* An index member `key` (`item`, found already) into an array of `count`; -1 when absent and not
 * required. */
static sinew_result index_of(gltf *g, const json_node *item, const char *key, const char *where, int count,
                             bool required, int *out)
{
    if (required && !item)
        return fail_at(g, "%s: no \"%s\"", where, key);
    long long v;
    sinew_result r = int_of(g, item, key, where, 0, count > 0 ? count - 1 : -1, -1, &v);
    if (r && count == 0)
        return fail_at(g, "%s.%s: refers to an element of an array the file does not have", where, key);
    *out = (int)v;
    return r;
}

static sinew_result index_at(gltf *g, const json_node *object, const char *key, const char *where, int count,
                             bool required, int *out)
{
    return index_of(g, json_get(object, key), key, where, count, required, out);
}

/* `n` finite numbers of an array member (exactly n); `fallback` when absent. */
static sinew_result numbers_at(gltf *g, const json_node *object, const char *key, const char *where, int n,
                               const double *fallback, double *out)
{
    const json_node *item = json_get(object, key);
    if (!item) {
        memcpy(out, fallback, (size_t)n * sizeof *out);
        return SINEW_OK;
    }
    if (!json_is_array(item) || json_size(item) != n)
        return fail_at(g, "%s.%s: not an array of %d numbers", where, key, n);
    int i = 0;
    const json_node *v;
    JSON_FOR_EACH(v, item)
    {
        if (!json_is_number(v) || !isfinite(v->number))
            return fail_at(g, "%s.%s[%d]: not a finite number", where, key, i);
        out[i++] = v->number;
    }
    return SINEW_OK;
}

/* A finite number (`fallback` when absent). */
static sinew_result number_at(gltf *g, const json_node *object, const char *key, const char *where, double fallback,
                              float *out)
{
    const json_node *item = json_get(object, key);
    if (item && !(json_is_number(item) && isfinite(item->number)))
        return fail_at(g, "%s.%s: not a finite number", where, key);
    *out = (float)(item ? item->number : fallback);
    return SINEW_OK;
}

/* An array's elements into a table (none: an empty table); false when out of memory. */
static bool table_of(const json_node *array, table *out)
{
    out->count = json_size(array);
    out->at = malloc((out->count ? (size_t)out->count : 1) * sizeof *out->at);
    int i = 0;
    const json_node *e;
    JSON_FOR_EACH(e, array)
    {
        if (out->at && i < out->count)
            out->at[i++] = e;
    }
    return out->at != NULL;
}

/* Element i of a table, or NULL. */
static const json_node *item(const table *t, int i)
{
    return i >= 0 && i < t->count ? t->at[i] : NULL;
}

/* A top-level array (or none) as a table; an object of another type is refused. */
static sinew_result top_array(gltf *g, const char *key, table *out)
{
    bool bad = false;
    const json_node *array = member(g->json, key, JSON_ARRAY, &bad);
    if (bad)
        return fail_at(g, "\"%s\" is not an array", key);
    if (array && json_size(array) > (int)GLTF_MAX_COUNT)
        return fail_at(g, "\"%s\" has more elements than sinew reads", key);
    return table_of(array, out) ? SINEW_OK : oom(g);
}

static const char *string_at(const json_node *object, const char *key)
{
    const json_node *item = json_get(object, key);
    return json_is_string(item) ? item->string : NULL;
}

/* ---- file and buffers ----------------------------------------------------------------- */

static uint32_t le32(const unsigned char *p)
{
    return p[0] | p[1] << 8 | p[2] << 16 | (uint32_t)p[3] << 24;
}

bool gltf_sniff(const unsigned char *head, size_t size)
{
    return size >= 4 && memcmp(head, "glTF", 4) == 0;
}

static sinew_result load_document(gltf *g)
{
    const unsigned char *b = g->file;
    size_t n = g->file_size;
    const char *text = (const char *)b;
    size_t text_size = n;
    if (gltf_sniff(b, n)) {
        if (n < 20)
            return fail_at(g, "GLB header: the file ends inside the 12-byte header and first chunk header");
        if (le32(b + 4) != 2)
            return fail_at(g, "GLB header: version %u (sinew reads glTF 2.0)", le32(b + 4));
        if (le32(b + 8) != n)
            return fail_at(g, "GLB header: length %u, but the file has %zu bytes", le32(b + 8), n);
        uint32_t json_len = le32(b + 12);
        if (le32(b + 16) != 0x4E4F534Au)
            return fail_at(g, "GLB: the first chunk is not JSON");
        if (json_len > n - 20)
            return fail_at(g, "GLB: the JSON chunk (%u bytes) runs past the end of the file", json_len);
        text = (const char *)b + 20;
        text_size = json_len;
        size_t at = 20 + (size_t)json_len;
        at = (at + 3) & ~(size_t)3;
        if (at + 8 <= n && le32(b + at + 4) == 0x004E4942u) {
            uint32_t bin_len = le32(b + at);
            if (bin_len > n - at - 8)
                return fail_at(g, "GLB: the BIN chunk (%u bytes) runs past the end of the file", bin_len);
            g->bin = (blob){(unsigned char *)b + at + 8, bin_len, false, true};
            g->has_bin = true;
        }
    }
    if (text_size >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0) {
        text += 3;
        text_size -= 3;
    }
    size_t offset;
    const char *why;
    sinew_result parsed = json_parse(text, text_size, false, &g->doc, &offset, &why);
    if (parsed == SINEW_ERROR_OUT_OF_MEMORY)
        return oom(g);
    g->json = g->doc.root;
    if (parsed != SINEW_OK) {
        fail_at(g, "not valid JSON (at byte %zu of the JSON text: %s)", offset, why);
        if (g->error) /* where in the file: the JSON text starts after a .glb's header */
            g->error->offset = (int64_t)(offset + (size_t)(text - (const char *)g->file));
        return SINEW_ERROR_FORMAT;
    }
    if (!json_is_object(g->json))
        return fail_at(g, "the JSON document is not an object");
    const char *version = string_at(json_get(g->json, "asset"), "version");
    if (!version)
        return fail_at(g, "asset.version: missing (not a glTF 2.0 file)");
    if (strncmp(version, "2.", 2) != 0)
        return fail_at(g,
                       "asset.version is \"%s\" (sinew reads glTF 2.0; glTF 1.0 goes through Assimp with "
                       "SINEW_IMPORTER=assimp)",
                       version);
    const json_node *required = json_get(g->json, "extensionsRequired"), *e;
    JSON_FOR_EACH(e, required)
    {
        if (!json_is_string(e))
            continue;
        if (strcmp(e->string, "KHR_mesh_quantization") == 0 || strcmp(e->string, "KHR_texture_transform") == 0)
            continue;
        if (strcmp(e->string, "KHR_draco_mesh_compression") == 0 || strcmp(e->string, "EXT_meshopt_compression") == 0)
            return fail_at(g,
                           "requires %s (compressed geometry), which sinew does not decode; export it again "
                           "without compression",
                           e->string);
        if (!raw_model_warn(g->m, "%s: requires the extension %s, which sinew does not know; it is ignored", g->path,
                            e->string))
            return oom(g);
    }
    return SINEW_OK;
}

/* Decodes base64 (padding optional, at the end only); false for any other character. */
static bool base64_decode(const char *text, blob *out)
{
    size_t len = strlen(text), end = strcspn(text, "=");
    out->bytes = malloc(len / 4 * 3 + 3);
    if (!out->bytes)
        return false;
    out->owned = true;
    out->size = import_base64_decode(text, end, out->bytes);
    return out->size != SIZE_MAX && strspn(text + end, "=") == len - end;
}

/* The bytes of a base64 data: URI (`where` names it in messages); out->bytes is owned. */
static sinew_result data_uri_bytes(gltf *g, const char *uri, const char *where, blob *out)
{
    const char *comma = strstr(uri, ";base64,");
    if (!comma)
        return fail_at(g, "%s.uri: a data: URI that is not base64", where);
    if (!base64_decode(comma + 8, out))
        return out->bytes ? fail_at(g, "%s.uri: not valid base64", where) : oom(g);
    return SINEW_OK;
}

/* The bytes of buffer `index`: the GLB BIN chunk, a base64 data: URI, or a file beside the
 * document, at least as long as the buffer's byteLength. */
static sinew_result buffer_bytes(gltf *g, int index, const blob **out)
{
    blob *b = &g->buffers[index];
    *out = b;
    if (b->loaded)
        return SINEW_OK;
    const json_node *buffer = item(&g->buffer_items, index);
    char where[64];
    place(where, sizeof where, "buffers[%d]", index);
    long long length;
    sinew_result r = int_at(g, buffer, "byteLength", where, 1, (long long)1 << 40, -1, &length);
    if (r)
        return r;
    if (length < 0)
        return fail_at(g, "%s: no byteLength", where);
    const char *uri = string_at(buffer, "uri");
    if (!uri) {
        if (index != 0 || !g->has_bin)
            return fail_at(g, "%s: no uri, and it is not the GLB's BIN chunk", where);
        *b = g->bin;
    } else if (strncmp(uri, "data:", 5) == 0) {
        if ((r = data_uri_bytes(g, uri, where, b)))
            return r;
    } else {
        if (strstr(uri, "://"))
            return fail_at(g, "%s.uri: \"%.200s\" is not a file beside the model (sinew reads no URLs)", where, uri);
        char name[4096], file[8192];
        import_uri_decode(uri, name, sizeof name);
        const char *slash = strrchr(g->path, '/');
        int dir = slash ? (int)(slash - g->path + 1) : 0;
        snprintf(file, sizeof file, "%.*s%s", dir, g->path, name);
        if (!import_read_file(file, &b->bytes, &b->size))
            return errno == ENOMEM ? oom(g)
                                   : sinew_fail(g->error, SINEW_ERROR_IO, "%s: %s: cannot read the buffer file %s: %s",
                                                g->path, where, file, strerror(errno));
        b->owned = true;
    }
    b->loaded = true;
    if ((long long)b->size < length)
        return fail_at(g, "%s: byteLength is %lld, but the buffer has %zu bytes", where, length, b->size);
    b->size = (size_t)length;
    return SINEW_OK;
}

/* ---- accessors ------------------------------------------------------------------------ */

static int type_components(const char *type)
{
    static const struct {
        const char *name;
        int count;
    } types[] = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}, {"MAT2", 4}, {"MAT3", 9}, {"MAT4", 16}};
    for (size_t i = 0; type && i < sizeof types / sizeof types[0]; i++)
        if (strcmp(type, types[i].name) == 0)
            return types[i].count;
    return 0;
}

static inline int component_size(long long type)
{
    switch (type) {
    case 5120:
    case 5121:
        return 1;
    case 5122:
    case 5123:
        return 2;
    case 5125:
    case 5126:
        return 4;
    default:
        return 0;
    }
}

/* One component: the stored number, or a normalised integer as glTF defines it. */
static inline double component(const unsigned char *p, long long type, bool normalized)
{
    switch (type) {
    case 5120:
        return normalized ? fmax((int8_t)p[0] / 127.0, -1.0) : (int8_t)p[0];
    case 5121:
        return normalized ? p[0] / 255.0 : p[0];
    case 5122: {
        int16_t v = (int16_t)(uint16_t)(p[0] | p[1] << 8);
        return normalized ? fmax(v / 32767.0, -1.0) : v;
    }
    case 5123: {
        uint16_t v = (uint16_t)(p[0] | p[1] << 8);
        return normalized ? v / 65535.0 : v;
    }
    case 5125:
        return (double)le32(p);
    default: {
        float f;
        memcpy(&f, p, 4);
        return f;
    }
    }
}

/* Where `count` elements of `elem` bytes (every `stride`) live: view `view` of the file
 * at `offset`; checked against the view and the buffer. */
static sinew_result view_span_in(gltf *g, const char *vw, int view, long long offset, long long count, long long elem,
                                 bool strided, const char *where, const unsigned char **base, long long *stride)
{
    static const json_key KEYS[] = {JSON_KEY("buffer"), JSON_KEY("byteOffset"), JSON_KEY("byteLength"),
                                    JSON_KEY("byteStride")};
    const json_node *field[4];
    json_pick(item(&g->views, view), KEYS, 4, field);
    int buffer;
    long long voff, vlen, vstride;
    sinew_result r;
    if ((r = index_of(g, field[0], "buffer", vw, g->buffer_count, true, &buffer)) ||
        (r = int_of(g, field[1], "byteOffset", vw, 0, (long long)1 << 40, 0, &voff)) ||
        (r = int_of(g, field[2], "byteLength", vw, 1, (long long)1 << 40, -1, &vlen)) ||
        (r = int_of(g, field[3], "byteStride", vw, 4, 252, 0, &vstride)))
        return r;
    if (vlen < 0)
        return fail_at(g, "%s: no byteLength", vw);
    const blob *b;
    if ((r = buffer_bytes(g, buffer, &b)))
        return r;
    if (voff + vlen > (long long)b->size)
        return fail_at(g, "%s: bytes %lld..%lld lie outside buffers[%d] (%zu bytes)", vw, voff, voff + vlen, buffer,
                       b->size);
    *stride = strided && vstride ? vstride : elem;
    if (*stride < elem)
        return fail_at(g, "%s: byteStride %lld is smaller than %s's element (%lld bytes)", vw, *stride, where, elem);
    if (offset + *stride * (count - 1) + elem > vlen)
        return fail_at(g, "%s: %lld elements from byte %lld do not fit in %s (%lld bytes)", where, count, offset, vw,
                       vlen);
    *base = b->bytes + voff + offset;
    return SINEW_OK;
}

static sinew_result view_span(gltf *g, int view, long long offset, long long count, long long elem, bool strided,
                              const char *where, const unsigned char **base, long long *stride)
{
    place_label vw;
    sinew_result r = view_span_in(g, label_open(g, &vw, "bufferViews[%d]", view, 0, NULL), view, offset, count, elem,
                                  strided, where, base, stride);
    label_close(g, &vw);
    return r;
}

/* Accessor `index` as doubles (count * components, malloc'd), with `want` components
 * (SCALAR 1, VECn n, MAT4 16) and a component type among `types` (a 0-terminated list). */
/* Element i of an accessor's output: a double, or a float (esize 4: the value rounded once). */
static inline void put(void *v, size_t esize, size_t i, double x)
{
    if (esize == 4)
        ((float *)v)[i] = (float)x;
    else
        ((double *)v)[i] = x;
}

static inline bool finite_at(const void *v, size_t esize, size_t i)
{
    return esize == 4 ? isfinite(((const float *)v)[i]) : isfinite(((const double *)v)[i]);
}

/* `count` elements of `comps` integer components of type `ctype` (no matrix padding) at `base`,
 * every `stride` bytes, into v as component() reads them, a loop for each type. */
static void decode_integers(void *v, size_t esize, const unsigned char *base, long long stride, long long count,
                            int comps, long long ctype, bool normalized)
{
#define DECODE(TYPE)                                                                                                   \
    for (long long i = 0; i < count; i++)                                                                              \
        for (int c = 0; c < comps; c++)                                                                                \
            put(v, esize, (size_t)(i * comps + c),                                                                     \
                component(base + stride * i + (long long)component_size(TYPE) * c, TYPE, normalized));
    switch (ctype) { /* component() inlined with its type known: its switch folds away */
    case 5120:
        DECODE(5120)
        break;
    case 5121:
        DECODE(5121)
        break;
    case 5122:
        DECODE(5122)
        break;
    case 5123:
        DECODE(5123)
        break;
    default: /* 5125 (5126 is read before this) */
        DECODE(5125)
        break;
    }
#undef DECODE
}

/* read_accessor() into doubles (esize 8) or floats (esize 4: animation keys, which the model
 * keeps as floats: a float accessor is then copied, not widened and narrowed again). */
static sinew_result read_accessor_in(gltf *g, int index, const char *where, int want, const long long *types,
                                     size_t esize, void **out, uint32_t *out_count)
{
    *out = NULL;
    const json_node *a = item(&g->accessors, index);
    if (!json_is_object(a))
        return fail_at(g, "%s: not an object", where);
    enum { TYPE, COMPONENT_TYPE, COUNT, BYTE_OFFSET, NORMALIZED, BUFFER_VIEW, SPARSE, KEY_COUNT };
    static const json_key KEYS[KEY_COUNT] = {JSON_KEY("type"),       JSON_KEY("componentType"), JSON_KEY("count"),
                                             JSON_KEY("byteOffset"), JSON_KEY("normalized"),    JSON_KEY("bufferView"),
                                             JSON_KEY("sparse")};
    const json_node *field[KEY_COUNT];
    json_pick(a, KEYS, KEY_COUNT, field);
    const char *type = json_is_string(field[TYPE]) ? field[TYPE]->string : NULL;
    int comps = type_components(type);
    long long ctype, count, offset;
    sinew_result r;
    if ((r = int_of(g, field[COMPONENT_TYPE], "componentType", where, 5120, 5126, -1, &ctype)) ||
        (r = int_of(g, field[COUNT], "count", where, 1, GLTF_MAX_COUNT, -1, &count)) ||
        (r = int_of(g, field[BYTE_OFFSET], "byteOffset", where, 0, (long long)1 << 40, 0, &offset)))
        return r;
    if (count < 0)
        return fail_at(g, "%s: no count", where);
    if (comps != want)
        return fail_at(g, "%s: type \"%s\" where %d components a element are needed", where, type ? type : "(none)",
                       want);
    bool allowed = false;
    for (const long long *t = types; *t; t++)
        allowed |= *t == ctype;
    if (!allowed || !component_size(ctype))
        return fail_at(g, "%s: componentType %lld is not allowed here", where, ctype);
    bool normalized = json_is_true(field[NORMALIZED]);
    if (normalized && (ctype == 5126 || ctype == 5125))
        return fail_at(g, "%s: normalized with componentType %lld", where, ctype);
    int csize = component_size(ctype);
    long long elem = (long long)csize * comps;
    /* Matrices of 1- and 2-byte components pad each column to 4 bytes. */
    int column = want == 16 ? 4 : want == 9 ? 3 : want;
    long long column_bytes = (want >= 9 && csize < 4) ? (((long long)csize * column + 3) & ~3LL) : csize * column;
    if (want >= 9)
        elem = column_bytes * (want / column);
    void *v = malloc((size_t)count * (size_t)comps * esize);
    if (!v)
        return oom(g);
    int view;
    if ((r = index_of(g, field[BUFFER_VIEW], "bufferView", where, g->views.count, false, &view))) {
        free(v);
        return r;
    }
    if (view < 0) {
        for (long long i = 0; i < count * comps; i++)
            put(v, esize, (size_t)i, 0.0);
    } else {
        const unsigned char *base;
        long long stride;
        if ((r = view_span(g, view, offset, count, elem, true, where, &base, &stride))) {
            free(v);
            return r;
        }
        if (ctype == 5126 && column_bytes == (long long)csize * column && esize == 4 && stride == elem)
            memcpy(v, base, (size_t)count * (size_t)elem);                   /* floats, packed, into floats */
        else if (ctype == 5126 && column_bytes == (long long)csize * column) /* floats, no padded matrix columns */
            for (long long i = 0; i < count; i++) {
                const unsigned char *e = base + stride * i;
                for (int c = 0; c < comps; c++) {
                    float f;
                    memcpy(&f, e + 4 * c, 4);
                    put(v, esize, (size_t)(i * comps + c), f);
                }
            }
        else if (want < 9) /* integers of one type a loop (a switch an element cost a skinned mesh's joints) */
            decode_integers(v, esize, base, stride, count, comps, ctype, normalized);
        else
            for (long long i = 0; i < count; i++)
                for (int c = 0; c < comps; c++)
                    put(v, esize, (size_t)(i * comps + c),
                        component(base + stride * i + column_bytes * (c / column) + (long long)csize * (c % column),
                                  ctype, normalized));
    }
    const json_node *sparse = field[SPARSE];
    if (sparse) {
        char sw[160];
        labels_write(g); /* `where` (rare: the text now) */
        place(sw, sizeof sw, "%s.sparse", where);
        long long n, itype, ioff, voff;
        int iview, vview;
        const json_node *ind = json_get(sparse, "indices");
        const json_node *val = json_get(sparse, "values");
        const unsigned char *ib, *vb;
        long long is, vs;
        int nviews = g->views.count;
        if ((r = int_at(g, sparse, "count", sw, 1, count, -1, &n)) ||
            (r = index_at(g, ind, "bufferView", sw, nviews, true, &iview)) ||
            (r = int_at(g, ind, "componentType", sw, 5121, 5125, -1, &itype)) ||
            (r = int_at(g, ind, "byteOffset", sw, 0, (long long)1 << 40, 0, &ioff)) ||
            (r = index_at(g, val, "bufferView", sw, nviews, true, &vview)) ||
            (r = int_at(g, val, "byteOffset", sw, 0, (long long)1 << 40, 0, &voff))) {
            free(v);
            return r;
        }
        if (n < 0 || (itype != 5121 && itype != 5123 && itype != 5125)) {
            free(v);
            return fail_at(g, "%s: no count, or indices of componentType %lld", sw, itype);
        }
        if ((r = view_span(g, iview, ioff, n, component_size(itype), false, sw, &ib, &is)) ||
            (r = view_span(g, vview, voff, n, elem, false, sw, &vb, &vs))) {
            free(v);
            return r;
        }
        for (long long k = 0; k < n; k++) {
            double at = component(ib + is * k, itype, false);
            if (at >= (double)count) {
                free(v);
                return fail_at(g, "%s: index %.0f is not below the accessor's count %lld", sw, at, count);
            }
            for (int c = 0; c < comps; c++)
                put(v, esize, (size_t)((long long)at * comps + c),
                    component(vb + vs * k + (long long)csize * c, ctype, normalized));
        }
    }
    size_t n = (size_t)count * (size_t)comps;
    bool finite = esize == 4 ? sinew_floats_finite(v, n) : true; /* floats a block at a time */
    for (size_t i = 0; i < n && (esize != 4 || !finite); i++)    /* doubles, or where the bad one is */
        if (!finite_at(v, esize, i)) {
            free(v);
            return fail_at(g, "%s: element %zu is not a finite number", where, i / (size_t)comps);
        }
    *out = v;
    *out_count = (uint32_t)count;
    return SINEW_OK;
}

static sinew_result read_accessor_as(gltf *g, int index, const char *use, int want, const long long *types,
                                     size_t esize, void **out, uint32_t *out_count)
{
    place_label where;
    sinew_result r = read_accessor_in(g, index, label_open(g, &where, "accessors[%d] (%s)", index, 0, use), want, types,
                                      esize, out, out_count);
    label_close(g, &where);
    return r;
}

static sinew_result read_accessor(gltf *g, int index, const char *use, int want, const long long *types, double **out,
                                  uint32_t *out_count)
{
    return read_accessor_as(g, index, use, want, types, sizeof **out, (void **)out, out_count);
}

static const long long FLOAT_ONLY[] = {5126, 0};

/* ---- nodes ---------------------------------------------------------------------------- */

typedef struct walk {
    int *stack;
    int *parent; /* by glTF node: its parent, -1, or -2 not seen yet */
} walk;

static sinew_result node_rest(gltf *g, const json_node *n, const char *where, sinew_transform *out)
{
    static const double zero[3] = {0, 0, 0}, one[3] = {1, 1, 1}, unit_q[4] = {0, 0, 0, 1};
    static const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    sinew_result r;
    if (json_get(n, "matrix")) {
        double mat[16];
        if ((r = numbers_at(g, n, "matrix", where, 16, identity, mat)))
            return r;
        sinew_mat4 m4;
        for (int i = 0; i < 16; i++)
            m4.m[i] = (float)mat[i];
        sinew_mat4_decompose(&m4, out);
        return SINEW_OK;
    }
    double t[3], q[4], s[3];
    if ((r = numbers_at(g, n, "translation", where, 3, zero, t)) ||
        (r = numbers_at(g, n, "rotation", where, 4, unit_q, q)) || (r = numbers_at(g, n, "scale", where, 3, one, s)))
        return r;
    double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(len > 0))
        return fail_at(g, "%s.rotation: a zero quaternion", where);
    for (int c = 0; c < 3; c++) {
        out->translation[c] = (float)t[c];
        out->scale[c] = (float)s[c];
    }
    for (int c = 0; c < 4; c++)
        out->rotation[c] = (float)(q[c] / len);
    return SINEW_OK;
}

/* Appends glTF node `root` and its subtree, depth first, parents before children (a
 * pending node's sinew parent waits in node_of until it is placed). */
static sinew_result add_subtree(gltf *g, walk *w, int root)
{
    raw_model *m = g->m;
    int top = 0;
    w->stack[top++] = root;
    w->parent[root] = -1;
    g->node_of[root] = UINT32_MAX;
    while (top > 0) {
        int i = w->stack[--top];
        uint32_t at = m->node_count++;
        int32_t p = g->node_of[i] == UINT32_MAX ? -1 : (int32_t)g->node_of[i];
        g->node_of[i] = at;
        char where[48];
        place(where, sizeof where, "nodes[%d]", i);
        const json_node *n = item(&g->nodes, i);
        const char *name = string_at(n, "name");
        m->node_names[at] = raw_strdup(name && *name ? name : where);
        if (!m->node_names[at])
            return oom(g);
        m->node_parents[at] = p;
        sinew_result r = node_rest(g, n, where, &m->node_rest[at]);
        if (r)
            return r;
        table children;
        if (!table_of(json_get(n, "children"), &children))
            return oom(g);
        /* Pushed in reverse so that children come out in the file's order. */
        for (int k = children.count - 1; k >= 0; k--) {
            const json_node *c = children.at[k];
            double v = json_is_number(c) ? c->number : -1;
            int child = v >= 0 && v < g->node_count && v == floor(v) ? (int)v : -1;
            if (child < 0 || w->parent[child] != -2) {
                free(children.at);
                return child < 0 ? fail_at(g, "%s.children[%d]: not a node index", where, k)
                                 : fail_at(g,
                                           "%s.children[%d]: node %d has more than one parent, or is its own "
                                           "ancestor",
                                           where, k, child);
            }
            w->parent[child] = i;
            g->node_of[child] = at;
            w->stack[top++] = child;
        }
        free(children.at);
    }
    return SINEW_OK;
}

/* The nodes: the scene's roots first (the default scene, else the first), then every other
 * parentless node (joints may live outside the scene); meshes are drawn only under the
 * scene's roots. */
static sinew_result build_nodes(gltf *g)
{
    raw_model *m = g->m;
    int n = g->node_count;
    if (n == 0)
        return SINEW_OK;
    m->node_names = calloc((size_t)n, sizeof *m->node_names);
    m->node_parents = calloc((size_t)n, sizeof *m->node_parents);
    m->node_rest = calloc((size_t)n, sizeof *m->node_rest);
    g->node_of = calloc((size_t)n, sizeof *g->node_of);
    g->in_scene = calloc((size_t)n, sizeof *g->in_scene);
    bool *has_parent = calloc((size_t)n, sizeof *has_parent), *is_root = calloc((size_t)n, sizeof *is_root);
    int *order = malloc((size_t)n * sizeof *order);
    walk w = {malloc((size_t)n * sizeof(int)), malloc((size_t)n * sizeof(int))};
    sinew_result r = SINEW_OK;
    if (!m->node_names || !m->node_parents || !m->node_rest || !g->node_of || !g->in_scene || !has_parent || !is_root ||
        !order || !w.stack || !w.parent)
        r = oom(g);
    for (int i = 0; i < n && !r; i++) {
        w.parent[i] = -2;
        const json_node *node = item(&g->nodes, i), *c;
        if (!json_is_object(node))
            r = fail_at(g, "nodes[%d]: not an object", i);
        JSON_FOR_EACH(c, json_get(node, "children"))
        {
            double v = json_is_number(c) ? c->number : -1;
            if (v >= 0 && v < n && v == floor(v))
                has_parent[(int)v] = true;
        }
    }
    const json_node *scenes = json_get(g->json, "scenes");
    int scene = -1;
    if (!r && json_size(scenes) > 0 &&
        !(r = index_at(g, g->json, "scene", "the document", json_size(scenes), false, &scene)) && scene < 0)
        scene = 0;
    const json_node *scene_nodes = scene >= 0 ? json_get(json_item(scenes, scene), "nodes") : NULL;
    int order_count = 0, k = 0;
    const json_node *s;
    JSON_FOR_EACH(s, scene_nodes)
    {
        if (r)
            break;
        double v = json_is_number(s) ? s->number : -1;
        if (!(v >= 0 && v < n) || v != floor(v))
            r = fail_at(g, "scenes[%d].nodes[%d]: not a node index", scene, k);
        else if (has_parent[(int)v])
            r = fail_at(g, "scenes[%d].nodes[%d]: node %d is a root of the scene and also a child", scene, k, (int)v);
        else if (!is_root[(int)v]) {
            is_root[(int)v] = true;
            order[order_count++] = (int)v;
        }
        k++;
    }
    int scene_roots = scene_nodes ? order_count : n;
    for (int i = 0; i < n && !r; i++)
        if (!has_parent[i] && !is_root[i])
            order[order_count++] = i;
    uint32_t scene_end = 0;
    for (int i = 0; i < order_count && !r; i++) {
        r = add_subtree(g, &w, order[i]);
        if (i < scene_roots)
            scene_end = m->node_count;
    }
    if (!r && m->node_count != (uint32_t)n)
        r = fail_at(g, "nodes: %u of %d nodes are in a cycle of children", n - m->node_count, n);
    for (int i = 0; i < n && !r; i++)
        g->in_scene[i] = g->node_of[i] < scene_end;
    free(has_parent);
    free(is_root);
    free(order);
    free(w.stack);
    free(w.parent);
    return r;
}

/* ---- materials ------------------------------------------------------------------------ */

#define GLTF_MAX_IMAGE (1u << 28) /* bytes of one embedded image */

/* An image embedded in the file: a bufferView (GLB) or a base64 data: URI, copied into the
 * material as the encoded bytes (PNG, JPEG, ... as stored) for the renderer to decode. */
static sinew_result embedded_image(gltf *g, const json_node *img, int image, const char *uri, const char *material,
                                   raw_texture *out)
{
    char where[64];
    place(where, sizeof where, "images[%d]", image);
    const unsigned char *bytes = NULL;
    size_t size = 0;
    blob decoded = {0};
    sinew_result r = SINEW_OK;
    if (uri) {
        if ((r = data_uri_bytes(g, uri, where, &decoded))) {
            free(decoded.bytes);
            return r;
        }
        bytes = decoded.bytes, size = decoded.size;
    } else {
        int view;
        long long length, stride;
        if (!json_get(img, "bufferView"))
            return fail_at(g, "%s: neither a uri nor a bufferView", where);
        if ((r = index_at(g, img, "bufferView", where, g->views.count, true, &view)) ||
            (r = int_at(g, item(&g->views, view), "byteLength", where, 1, (long long)1 << 40, -1, &length)))
            return r;
        if (length < 1)
            return fail_at(g, "bufferViews[%d]: no byteLength", view);
        if ((r = view_span(g, view, 0, 1, length, false, where, &bytes, &stride)))
            return r;
        size = (size_t)length;
    }
    if (size > GLTF_MAX_IMAGE) {
        free(decoded.bytes);
        return raw_model_warn(g->m,
                              "%s: material \"%s\": %s is %zu bytes, more than sinew keeps (%u); the "
                              "material keeps its colour",
                              g->path, material, where, size, GLTF_MAX_IMAGE)
                   ? SINEW_OK
                   : oom(g);
    }
    out->image = malloc(size ? size : 1);
    if (!out->image) {
        free(decoded.bytes);
        return oom(g);
    }
    memcpy(out->image, bytes, size);
    out->image_size = (uint32_t)size;
    free(decoded.bytes);
    return SINEW_OK;
}

/* A material's image: the file an image names, resolved (tried beside the model by name
 * when missing), or the embedded bytes; none (with a warning) when the image is in a format
 * sinew does not read. */
static sinew_result texture_of(gltf *g, int texture, const char *material, raw_texture *out)
{
    char where[64];
    place(where, sizeof where, "textures[%d]", texture);
    const json_node *t = item(&g->textures, texture);
    int image;
    sinew_result r = index_at(g, t, "source", where, g->images.count, false, &image);
    if (r)
        return r;
    /* Images in other formats (KHR_texture_basisu, EXT_texture_webp) keep "source" as a fallback. */
    if (image < 0) {
        return raw_model_warn(g->m, "%s: material \"%s\": %s has no image sinew can read", g->path, material, where)
                   ? SINEW_OK
                   : oom(g);
    }
    const json_node *img = item(&g->images, image);
    const char *uri = string_at(img, "uri");
    if (!uri || strncmp(uri, "data:", 5) == 0)
        return embedded_image(g, img, image, uri, material, out);
    char name[4096];
    import_uri_decode(uri, name, sizeof name);
    return import_material_texture(g->m, g->path, material, name, &out->path) ? SINEW_OK : oom(g);
}

static const char *const MAP_NAMES[SINEW_MAP_COUNT] = {"baseColorTexture", "metallicRoughnessTexture", "normalTexture",
                                                       "occlusionTexture", "emissiveTexture"};

/* KHR_texture_transform of a texture info into the material's UV transform (sinew keeps
 * one UV set a mesh: the base colour map's transform is applied to the UVs). */
static sinew_result texture_transform(gltf *g, int material, const json_node *tt, const char *where, long long *set)
{
    static const double zero2[2] = {0, 0}, one2[2] = {1, 1};
    double offset[2], scale[2], rotation = 0;
    sinew_result r;
    if ((r = numbers_at(g, tt, "offset", where, 2, zero2, offset)) ||
        (r = numbers_at(g, tt, "scale", where, 2, one2, scale)) ||
        (r = int_at(g, tt, "texCoord", where, 0, 255, *set, set)))
        return r;
    const json_node *rot = json_get(tt, "rotation");
    if (rot && !(json_is_number(rot) && isfinite(rot->number)))
        return fail_at(g, "%s: KHR_texture_transform.rotation is not a number", where);
    rotation = rot ? rot->number : 0;
    /* translation * rotation * scale (the extension's definition). */
    double c = cos(rotation), s = sin(rotation);
    float *t = g->uv_transform[material];
    t[0] = (float)(c * scale[0]);
    t[1] = (float)(s * scale[1]);
    t[2] = (float)offset[0];
    t[3] = (float)(-s * scale[0]);
    t[4] = (float)(c * scale[1]);
    t[5] = (float)offset[1];
    g->has_uv_transform[material] = true;
    return SINEW_OK;
}

/* One texture info of material `material` (its "index", "texCoord" and transform) into map `slot`. */
static sinew_result material_map(gltf *g, int material, const json_node *info, const char *where, raw_material *out,
                                 int slot)
{
    int texture;
    long long set;
    sinew_result r;
    if ((r = index_at(g, info, "index", where, g->textures.count, true, &texture)) ||
        (r = int_at(g, info, "texCoord", where, 0, 255, 0, &set)))
        return r;
    const json_node *tt = json_get(json_get(info, "extensions"), "KHR_texture_transform");
    if (tt && slot == SINEW_MAP_BASE_COLOR && (r = texture_transform(g, material, tt, where, &set)))
        return r;
    if (tt && slot != SINEW_MAP_BASE_COLOR &&
        !raw_model_warn(g->m,
                        "%s: material \"%s\": the KHR_texture_transform of its %s is not applied (sinew "
                        "keeps the base colour map's)",
                        g->path, out->name, MAP_NAMES[slot]))
        return oom(g);
    if (set != 0 && !raw_model_warn(g->m, "%s: material \"%s\" maps its %s with TEXCOORD_%lld; sinew uses TEXCOORD_0",
                                    g->path, out->name, MAP_NAMES[slot], set))
        return oom(g);
    return texture_of(g, texture, out->name, &out->maps[slot]);
}

static sinew_result build_materials(gltf *g)
{
    raw_model *m = g->m;
    int n = g->materials.count;
    if (n == 0)
        return SINEW_OK;
    m->materials = calloc((size_t)n, sizeof *m->materials);
    g->uv_transform = calloc((size_t)n, sizeof *g->uv_transform);
    g->has_uv_transform = calloc((size_t)n, sizeof *g->has_uv_transform);
    if (!m->materials || !g->uv_transform || !g->has_uv_transform)
        return oom(g);
    m->material_count = (uint32_t)n;
    for (int i = 0; i < n; i++) {
        const json_node *mat = item(&g->materials, i);
        char where[48];
        place(where, sizeof where, "materials[%d]", i);
        const char *name = string_at(mat, "name");
        raw_material *out = &m->materials[i];
        if (!(out->name = raw_strdup(name && *name ? name : where)))
            return oom(g);
        const json_node *pbr = json_get(mat, "pbrMetallicRoughness");
        static const double white[4] = {1, 1, 1, 1}, black[3] = {0, 0, 0};
        double color[4], emissive[3];
        sinew_result r = numbers_at(g, pbr, "baseColorFactor", where, 4, white, color);
        if (r)
            return r;
        for (int c = 0; c < 4; c++)
            out->base_color[c] = (float)fmin(fmax(color[c], 0.0), 1.0);
        out->metallic_roughness = true;
        if ((r = number_at(g, pbr, "metallicFactor", where, 1.0, &out->metallic)) ||
            (r = number_at(g, pbr, "roughnessFactor", where, 1.0, &out->roughness)))
            return r;
        if ((r = numbers_at(g, mat, "emissiveFactor", where, 3, black, emissive)))
            return r;
        const json_node *strength =
            json_get(json_get(json_get(mat, "extensions"), "KHR_materials_emissive_strength"), "emissiveStrength");
        double gain = json_is_number(strength) && isfinite(strength->number) ? strength->number : 1.0;
        for (int c = 0; c < 3; c++)
            out->emissive[c] = (float)(emissive[c] * gain);
        const json_node *mode = json_get(mat, "alphaMode");
        if (mode && !json_is_string(mode))
            return fail_at(g, "%s.alphaMode: not a string", where);
        static const char *const MODES[] = {
            [SINEW_ALPHA_OPAQUE] = "OPAQUE", [SINEW_ALPHA_MASK] = "MASK", [SINEW_ALPHA_BLEND] = "BLEND"};
        for (int k = 0; mode && k < 3; k++)
            if (strcmp(mode->string, MODES[k]) == 0)
                out->alpha_mode = (sinew_alpha_mode)k;
        if (mode && strcmp(mode->string, MODES[out->alpha_mode]) != 0 &&
            !raw_model_warn(m, "%s: %s: alphaMode \"%s\" is not OPAQUE, MASK or BLEND; drawn opaque", g->path, where,
                            mode->string))
            return oom(g);
        if ((r = number_at(g, mat, "alphaCutoff", where, 0.5, &out->alpha_cutoff)))
            return r;
        const json_node *normal = json_get(mat, "normalTexture");
        const json_node *occlusion = json_get(mat, "occlusionTexture");
        if ((r = number_at(g, normal, "scale", where, 1.0, &out->normal_scale)) ||
            (r = number_at(g, occlusion, "strength", where, 1.0, &out->occlusion_strength)))
            return r;
        const json_node *infos[SINEW_MAP_COUNT] = {[SINEW_MAP_BASE_COLOR] = json_get(pbr, "baseColorTexture"),
                                                   [SINEW_MAP_METALLIC_ROUGHNESS] =
                                                       json_get(pbr, "metallicRoughnessTexture"),
                                                   [SINEW_MAP_NORMAL] = normal,
                                                   [SINEW_MAP_OCCLUSION] = occlusion,
                                                   [SINEW_MAP_EMISSIVE] = json_get(mat, "emissiveTexture")};
        for (int k = 0; k < SINEW_MAP_COUNT; k++)
            if (infos[k] && (r = material_map(g, i, infos[k], where, out, k)))
                return r;
    }
    return SINEW_OK;
}

/* ---- meshes --------------------------------------------------------------------------- */

static const long long POSITION_TYPES[] = {5126, 5120, 5121, 5122, 5123, 0};
static const long long NORMAL_TYPES[] = {5126, 5120, 5122, 0};
static const long long TANGENT_TYPES[] = {5126, 5120, 5122, 0}; /* float, or normalised (quantization) */
static const long long UV_TYPES[] = {5126, 5120, 5121, 5122, 5123, 0};
static const long long JOINT_TYPES[] = {5121, 5123, 0};
static const long long COLOR_TYPES[] = {5126, 5121, 5123, 0}; /* float, or normalised unsigned */
static const long long WEIGHT_TYPES[] = {5126, 5121, 5123, 0};
static const long long INDEX_TYPES[] = {5121, 5123, 5125, 0};

/* An attribute of a primitive as floats (malloc'd), or NULL when the primitive has none. */
static sinew_result attribute(gltf *g, const json_node *attrs, const char *name, const char *where, int want,
                              const long long *types, uint32_t vertex_count, float **out)
{
    *out = NULL;
    if (!json_get(attrs, name))
        return SINEW_OK;
    char use[160];
    place(use, sizeof use, "%s %s", where, name);
    int index;
    sinew_result r = index_at(g, attrs, name, where, g->accessors.count, true, &index);
    float *f = NULL; /* read as the floats the mesh keeps (each value rounded once, as before) */
    uint32_t count = 0;
    if (r || (r = read_accessor_as(g, index, use, want, types, sizeof *f, (void **)&f, &count)))
        return r;
    if (vertex_count != UINT32_MAX && count != vertex_count) {
        free(f);
        return fail_at(g, "%s: %s has %u elements for the primitive's %u vertices", where, name, count, vertex_count);
    }
    *out = f;
    return SINEW_OK;
}

/* COLOR_0 (VEC3 or VEC4, linear, as glTF stores it) as RGBA: alpha 1 where the file gives none. */
static sinew_result vertex_colors(gltf *g, const json_node *attrs, const char *where, uint32_t vertex_count,
                                  float **out)
{
    *out = NULL;
    int index;
    sinew_result r = index_at(g, attrs, "COLOR_0", where, g->accessors.count, false, &index);
    if (r || index < 0)
        return r;
    const json_node *type = json_get(item(&g->accessors, index), "type");
    bool rgb = json_is_string(type) && strcmp(type->string, "VEC3") == 0;
    float *c = NULL;
    if ((r = attribute(g, attrs, "COLOR_0", where, rgb ? 3 : 4, COLOR_TYPES, vertex_count, &c)) || !rgb) {
        *out = c;
        return r;
    }
    float *rgba = malloc(((size_t)vertex_count + 1) * 4 * sizeof *rgba);
    if (!rgba) {
        free(c);
        return oom(g);
    }
    for (uint32_t v = 0; v < vertex_count; v++) {
        memcpy(&rgba[(size_t)v * 4], &c[(size_t)v * 3], 3 * sizeof *c);
        rgba[(size_t)v * 4 + 3] = 1.0f;
    }
    free(c);
    *out = rgba;
    return SINEW_OK;
}

/* Triangle corners of a primitive (mode 4, 5 or 6), from its indices or 0..n-1. */
static sinew_result primitive_indices(gltf *g, const json_node *prim, const char *where, long long mode,
                                      uint32_t vertex_count, raw_mesh *out)
{
    int index;
    sinew_result r = index_at(g, prim, "indices", where, g->accessors.count, false, &index);
    if (r)
        return r;
    double *v = NULL;
    uint32_t n = vertex_count;
    if (index >= 0) {
        char use[160];
        place(use, sizeof use, "%s indices", where);
        if ((r = read_accessor(g, index, use, 1, INDEX_TYPES, &v, &n)))
            return r;
    }
    uint32_t tris = mode == 4 ? n / 3 : n >= 3 ? n - 2 : 0;
    if (mode == 4 && n % 3) {
        free(v);
        return fail_at(g, "%s: %u indices is not a whole number of triangles", where, n);
    }
    out->indices = malloc(((size_t)tris * 3 + 1) * sizeof *out->indices);
    if (!out->indices) {
        free(v);
        return oom(g);
    }
    uint32_t k = 0;
    for (uint32_t t = 0; t < tris; t++) {
        uint32_t c[3];
        if (mode == 4)
            c[0] = t * 3, c[1] = t * 3 + 1, c[2] = t * 3 + 2;
        else if (mode == 5) /* strips alternate their winding */
            c[0] = t, c[1] = t % 2 ? t + 2 : t + 1, c[2] = t % 2 ? t + 1 : t + 2;
        else
            c[0] = t + 1, c[1] = t + 2, c[2] = 0;
        for (int j = 0; j < 3; j++) {
            double idx = v ? v[c[j]] : c[j];
            if (idx >= vertex_count) {
                free(v);
                return fail_at(g, "%s: index %.0f is not below the vertex count %u", where, idx, vertex_count);
            }
            out->indices[k++] = (uint32_t)idx;
        }
    }
    free(v);
    out->index_count = k;
    return SINEW_OK;
}

/* Joints and weights of every JOINTS_n / WEIGHTS_n set (any number of sets). */
static sinew_result primitive_influences(gltf *g, const json_node *attrs, const char *where, uint32_t joint_count,
                                         raw_mesh *out)
{
    int sets = 0;
    char name[32];
    for (;; sets++) {
        place(name, sizeof name, "JOINTS_%d", sets);
        if (!json_get(attrs, name))
            break;
    }
    if (sets == 0)
        return SINEW_OK;
    uint32_t n = out->vertex_count, slots = (uint32_t)sets * 4;
    out->joints = calloc((size_t)n * slots, sizeof *out->joints);
    out->weights = calloc((size_t)n * slots, sizeof *out->weights);
    if (!out->joints || !out->weights)
        return oom(g);
    out->influence_count = slots;
    for (int s = 0; s < sets; s++) {
        float *joints = NULL, *weights = NULL;
        sinew_result r;
        place(name, sizeof name, "JOINTS_%d", s);
        if ((r = attribute(g, attrs, name, where, 4, JOINT_TYPES, n, &joints)))
            return r;
        place(name, sizeof name, "WEIGHTS_%d", s);
        if ((r = attribute(g, attrs, name, where, 4, WEIGHT_TYPES, n, &weights))) {
            free(joints);
            return r;
        }
        if (!weights) {
            free(joints);
            return fail_at(g, "%s: JOINTS_%d without WEIGHTS_%d", where, s, s);
        }
        for (uint32_t v = 0; v < n; v++)
            for (int c = 0; c < 4; c++) {
                float j = joints[v * 4 + c], w = weights[v * 4 + c];
                size_t at = (size_t)v * slots + (size_t)s * 4 + (size_t)c;
                if (w < 0) {
                    free(joints);
                    free(weights);
                    return fail_at(g, "%s: WEIGHTS_%d of vertex %u is negative", where, s, v);
                }
                if (w > 0 && j >= (float)joint_count) {
                    free(joints);
                    free(weights);
                    return fail_at(g, "%s: JOINTS_%d of vertex %u names joint %.0f of a skin with %u joints", where, s,
                                   v, j, joint_count);
                }
                out->joints[at] = w > 0 ? (uint32_t)j : 0;
                out->weights[at] = w;
            }
        free(joints);
        free(weights);
    }
    return SINEW_OK;
}

/* A primitive's morph targets: each target's POSITION, NORMAL and TANGENT offsets (VEC3, of
 * as many elements as the primitive's vertices), named by the mesh's extras.targetNames. */
static sinew_result read_targets(gltf *g, const json_node *gm, const json_node *prim, const char *where, raw_mesh *out)
{
    const json_node *targets = json_get(prim, "targets");
    if (!targets)
        return SINEW_OK;
    if (!json_is_array(targets))
        return fail_at(g, "%s.targets: not an array", where);
    int n = json_size(targets);
    if (n == 0)
        return SINEW_OK;
    if (!(out->targets = calloc((size_t)n, sizeof *out->targets)))
        return oom(g);
    const json_node *names = json_get(json_get(gm, "extras"), "targetNames");
    static const char *const attrs[3] = {"POSITION", "NORMAL", "TANGENT"};
    static const long long *const types[3] = {POSITION_TYPES, NORMAL_TYPES, TANGENT_TYPES};
    for (int t = 0; t < n; t++) {
        raw_morph_target *rt = &out->targets[out->target_count++];
        const json_node *target = json_item(targets, t), *name = json_item(names, t);
        char tw[96], label[32];
        place(tw, sizeof tw, "%s.targets[%d]", where, t);
        place(label, sizeof label, "target %d", t);
        if (!json_is_object(target))
            return fail_at(g, "%s: not an object", tw);
        if (!(rt->name = raw_strdup(json_is_string(name) && *name->string ? name->string : label)))
            return oom(g);
        rt->channel = (uint32_t)t;
        rt->full_weight = 1.0f;
        float **dst[3] = {&rt->positions, &rt->normals, &rt->tangents};
        for (int a = 0; a < 3; a++) {
            sinew_result r = attribute(g, target, attrs[a], tw, 3, types[a], out->vertex_count, dst[a]);
            if (r)
                return r;
        }
        if (!rt->positions && !(rt->positions = calloc((size_t)out->vertex_count * 3 + 1, sizeof *rt->positions)))
            return oom(g);
        if (!(rt->vertices = malloc(((size_t)out->vertex_count + 1) * sizeof *rt->vertices)))
            return oom(g);
        for (uint32_t v = 0; v < out->vertex_count; v++)
            rt->vertices[v] = v;
        rt->delta_count = out->vertex_count;
    }
    return SINEW_OK;
}

/* One primitive as a raw mesh. Points and lines are left out (*out->vertex_count == 0). */
static sinew_result read_primitive(gltf *g, int mesh, int k, int skin, raw_mesh *out)
{
    const json_node *gm = item(&g->meshes, mesh);
    const json_node *prims = json_get(gm, "primitives");
    const json_node *prim = json_item(prims, k);
    char where[64];
    place(where, sizeof where, "meshes[%d].primitives[%d]", mesh, k);
    const char *name = string_at(gm, "name");
    char base[256], label[300];
    if (name && *name)
        place(base, sizeof base, "%s", name);
    else
        place(base, sizeof base, "meshes[%d]", mesh);
    if (json_size(prims) > 1)
        place(label, sizeof label, "%s-%d", base, k);
    else
        place(label, sizeof label, "%s", base);
    memset(out, 0, sizeof *out);
    out->skin = -1;
    out->material = -1;
    if (!(out->name = raw_strdup(label)))
        return oom(g);
    long long mode;
    sinew_result r = int_at(g, prim, "mode", where, 0, 6, 4, &mode);
    if (r)
        return r;
    if (mode < 4)
        return raw_model_warn(g->m, "%s: mesh \"%s\" draws %s; sinew draws triangles only", g->path, label,
                              mode == 0 ? "points" : "lines")
                   ? SINEW_OK
                   : oom(g);
    const json_node *attrs = json_get(prim, "attributes");
    if (!json_is_object(attrs) || !json_get(attrs, "POSITION"))
        return fail_at(g, "%s: no POSITION attribute", where);
    int material;
    if ((r = index_at(g, prim, "material", where, (int)g->m->material_count, false, &material)))
        return r;
    out->material = material;
    uint32_t n = 0;
    {
        int index;
        char use[160];
        place(use, sizeof use, "%s POSITION", where);
        if ((r = index_at(g, attrs, "POSITION", where, g->accessors.count, true, &index)) ||
            (r = read_accessor_as(g, index, use, 3, POSITION_TYPES, sizeof *out->positions, (void **)&out->positions,
                                  &n))) /* floats, each rounded once */
            return r;
    }
    out->vertex_count = n;
    if ((r = attribute(g, attrs, "NORMAL", where, 3, NORMAL_TYPES, n, &out->normals)) ||
        (r = attribute(g, attrs, "TEXCOORD_0", where, 2, UV_TYPES, n, &out->uvs)) ||
        (r = attribute(g, attrs, "TANGENT", where, 4, TANGENT_TYPES, n, &out->tangents)) ||
        (r = vertex_colors(g, attrs, where, n, &out->colors)) ||
        (r = primitive_indices(g, prim, where, mode, n, out)) || (r = read_targets(g, gm, prim, where, out)))
        return r;
    if (!out->normals) { /* "client implementations MUST calculate flat normals and the provided tangents (if
                            present) MUST be ignored" (glTF 2.0, 3.7.2.1) */
        out->flat_normals = true;
        free(out->tangents);
        out->tangents = NULL;
    }
    /* The texture transform in glTF's UV space (v down), then v up as the runtime has it. */
    for (uint32_t i = 0; out->uvs && i < n; i++) {
        float u = out->uvs[i * 2], v = out->uvs[i * 2 + 1];
        if (material >= 0 && g->has_uv_transform[material]) {
            const float *t = g->uv_transform[material];
            out->uvs[i * 2] = t[0] * u + t[1] * v + t[2];
            v = t[3] * u + t[4] * v + t[5];
        }
        out->uvs[i * 2 + 1] = 1.0f - v;
    }
    /* glTF's bitangent (w * normal x tangent) points up the image, where its normal maps put +Y
     * (the Khronos sample viewer's and three.js's reading): sinew's +v, so w is kept; only
     * the sign is: the spec allows any w but uses its sign alone. */
    for (uint32_t i = 0; out->tangents && i < n; i++)
        out->tangents[i * 4 + 3] = out->tangents[i * 4 + 3] < 0.0f ? -1.0f : 1.0f;
    if (skin >= 0) {
        uint32_t joints = g->m->skins[skin].joint_count;
        if ((r = primitive_influences(g, attrs, where, joints, out)))
            return r;
        if (out->influence_count)
            out->skin = skin;
        else if (!raw_model_warn(g->m, "%s: mesh \"%s\" is placed with a skin but has no JOINTS_0; it is drawn rigid",
                                 g->path, label))
            return oom(g);
    }
    return SINEW_OK;
}

static sinew_result build_skins(gltf *g)
{
    raw_model *m = g->m;
    int n = g->skins.count;
    if (n == 0)
        return SINEW_OK;
    if (!(m->skins = calloc((size_t)n, sizeof *m->skins)))
        return oom(g);
    m->skin_count = (uint32_t)n;
    for (int i = 0; i < n; i++) {
        const json_node *skin = item(&g->skins, i);
        char where[48];
        place(where, sizeof where, "skins[%d]", i);
        const json_node *joints = json_get(skin, "joints");
        int count = json_size(joints);
        if (!json_is_array(joints) || count == 0)
            return fail_at(g, "%s.joints: not a non-empty array", where);
        raw_skin *out = &m->skins[i];
        out->joints = calloc((size_t)count, sizeof *out->joints);
        out->inverse_bind = calloc((size_t)count, sizeof *out->inverse_bind);
        if (!out->joints || !out->inverse_bind)
            return oom(g);
        out->joint_count = (uint32_t)count;
        int k = 0;
        const json_node *j;
        JSON_FOR_EACH(j, joints)
        {
            double v = json_is_number(j) ? j->number : -1;
            if (!(v >= 0 && v < g->node_count) || v != floor(v))
                return fail_at(g, "%s.joints[%d]: not a node index", where, k);
            out->joints[k++] = g->node_of[(int)v];
        }
        int ibm;
        sinew_result r = index_at(g, skin, "inverseBindMatrices", where, g->accessors.count, false, &ibm);
        if (r)
            return r;
        if (ibm < 0) {
            for (int a = 0; a < count; a++)
                for (int c = 0; c < 16; c++)
                    out->inverse_bind[a].m[c] = c % 5 == 0 ? 1.0f : 0.0f;
            continue;
        }
        double *v;
        uint32_t got;
        char use[96];
        place(use, sizeof use, "%s inverseBindMatrices", where);
        if ((r = read_accessor(g, ibm, use, 16, FLOAT_ONLY, &v, &got)))
            return r;
        if (got < (uint32_t)count) {
            free(v);
            return fail_at(g, "%s: %u inverse bind matrices for %d joints", where, got, count);
        }
        for (int a = 0; a < count; a++)
            for (int c = 0; c < 16; c++)
                out->inverse_bind[a].m[c] = (float)v[a * 16 + c];
        free(v);
    }
    return SINEW_OK;
}

/* The raw meshes of glTF mesh `mesh` drawn with `skin` (made on first use). */
static sinew_result meshes_for(gltf *g, int mesh, int skin, const mesh_key **out)
{
    for (uint32_t i = 0; i < g->key_count; i++)
        if (g->keys[i].mesh == mesh && g->keys[i].skin == skin) {
            *out = &g->keys[i];
            return SINEW_OK;
        }
    raw_model *m = g->m;
    const json_node *gm = item(&g->meshes, mesh);
    const json_node *prims = json_get(gm, "primitives");
    int count = json_size(prims);
    if (!json_is_array(prims) || count == 0)
        return fail_at(g, "meshes[%d].primitives: not a non-empty array", mesh);
    mesh_key *keys = realloc(g->keys, (g->key_count + 1) * sizeof *keys);
    raw_mesh *meshes = realloc(m->meshes, (m->mesh_count + (size_t)count) * sizeof *meshes);
    if (keys)
        g->keys = keys;
    if (meshes)
        m->meshes = meshes;
    if (!keys || !meshes)
        return oom(g);
    mesh_key *key = &g->keys[g->key_count++];
    *key = (mesh_key){mesh, skin, m->mesh_count, 0};
    for (int k = 0; k < count; k++) {
        raw_mesh *rm = &m->meshes[m->mesh_count];
        sinew_result r = read_primitive(g, mesh, k, skin, rm);
        m->mesh_count++; /* counted even when it fails: raw_model_free frees what it holds */
        if (r)
            return r;
        if (rm->vertex_count == 0 || rm->index_count == 0) {
            raw_mesh_free(rm);
            m->mesh_count--;
        }
    }
    key->count = m->mesh_count - key->first;
    /* every primitive has the mesh's targets (the spec's rule: the weights are the mesh's) */
    for (uint32_t i = key->first + 1; i < key->first + key->count; i++)
        if (m->meshes[i].target_count != m->meshes[key->first].target_count)
            return fail_at(g, "meshes[%d]: its primitives have %u and %u morph targets (they must have as many)", mesh,
                           m->meshes[key->first].target_count, m->meshes[i].target_count);
    *out = key;
    return SINEW_OK;
}

/* A node's weights (its "weights", else its mesh's, else 0) as morph channels of its own,
 * named after the targets; the first of them in g->morph_first. */
static sinew_result node_channels(gltf *g, int node, int mesh, const mesh_key *key)
{
    raw_model *m = g->m;
    uint32_t n = key->count ? m->meshes[key->first].target_count : 0;
    if (n == 0)
        return SINEW_OK;
    const json_node *gn = item(&g->nodes, node), *gm = item(&g->meshes, mesh);
    const json_node *weights = json_get(gn, "weights");
    char where[48];
    place(where, sizeof where, "nodes[%d].weights", node);
    if (!weights) {
        weights = json_get(gm, "weights");
        place(where, sizeof where, "meshes[%d].weights", mesh);
    }
    if (weights && (!json_is_array(weights) || json_size(weights) != (int)n))
        return fail_at(g, "%s: not an array of %u numbers, one a morph target", where, n);
    raw_morph_channel *grown = realloc(m->morph_channels, (m->morph_channel_count + n) * sizeof *grown);
    if (!grown)
        return oom(g);
    m->morph_channels = grown;
    g->morph_first[node] = (int32_t)m->morph_channel_count;
    g->morph_count[node] = n;
    for (uint32_t t = 0; t < n; t++) {
        const json_node *w = json_item(weights, (int)t);
        if (weights && (!json_is_number(w) || !isfinite(w->number)))
            return fail_at(g, "%s[%u]: not a finite number", where, t);
        raw_morph_channel *c = &m->morph_channels[m->morph_channel_count];
        c->default_weight = w ? (float)w->number : 0.0f;
        if (!(c->name = raw_strdup(m->meshes[key->first].targets[t].name)))
            return oom(g);
        m->morph_channel_count++;
    }
    return SINEW_OK;
}

static sinew_result build_meshes(gltf *g)
{
    raw_model *m = g->m;
    uint32_t cap = 0;
    g->morph_first = malloc(((size_t)g->node_count + 1) * sizeof *g->morph_first);
    g->morph_count = calloc((size_t)g->node_count + 1, sizeof *g->morph_count);
    if (!g->morph_first || !g->morph_count)
        return oom(g);
    for (int i = 0; i < g->node_count; i++)
        g->morph_first[i] = -1;
    for (int i = 0; i < g->node_count; i++) {
        const json_node *node = item(&g->nodes, i);
        char where[48];
        place(where, sizeof where, "nodes[%d]", i);
        int mesh, skin;
        sinew_result r;
        if ((r = index_at(g, node, "mesh", where, g->meshes.count, false, &mesh)) ||
            (r = index_at(g, node, "skin", where, (int)m->skin_count, false, &skin)))
            return r;
        if (mesh < 0 || !g->in_scene[i])
            continue;
        const mesh_key *key = NULL;
        if ((r = meshes_for(g, mesh, skin, &key)) || (r = node_channels(g, i, mesh, key)))
            return r;
        if (m->instance_count + key->count > cap) {
            cap = (m->instance_count + key->count) * 2;
            sinew_instance *grown = realloc(m->instances, cap * sizeof *grown);
            if (!grown)
                return oom(g);
            m->instances = grown;
        }
        uint32_t first = g->morph_first[i] >= 0 ? (uint32_t)g->morph_first[i] : 0;
        for (uint32_t k = 0; k < key->count; k++)
            m->instances[m->instance_count++] = (sinew_instance){key->first + k, g->node_of[i], first};
    }
    return SINEW_OK;
}

/* ---- clips ---------------------------------------------------------------------------- */

static const long long ROTATION_TYPES[] = {5126, 5120, 5121, 5122, 5123, 0};

/* A sampler's interpolation, input times (checked ascending) and output values (`elements`
 * elements of `comps` components a key, three times that for CUBICSPLINE), malloc'd. */
static sinew_result read_sampler(gltf *g, const json_node *s, const char *sw, int comps, uint32_t elements,
                                 const long long *types, uint32_t *interp, float **times, uint32_t *nt, float **values)
{
    static const json_key KEYS[] = {JSON_KEY("interpolation"), JSON_KEY("input"), JSON_KEY("output")};
    const json_node *field[3];
    json_pick(s, KEYS, 3, field);
    const char *how = json_is_string(field[0]) ? field[0]->string : NULL;
    *interp = !how || strcmp(how, "LINEAR") == 0 ? SINEW_INTERP_LINEAR
              : strcmp(how, "STEP") == 0         ? SINEW_INTERP_STEP
              : strcmp(how, "CUBICSPLINE") == 0  ? SINEW_INTERP_CUBIC
                                                 : UINT32_MAX;
    if (*interp == UINT32_MAX)
        return fail_at(g, "%s.interpolation: \"%s\" is not LINEAR, STEP or CUBICSPLINE", sw, how);
    int input, output;
    sinew_result r;
    if ((r = index_of(g, field[1], "input", sw, g->accessors.count, true, &input)) ||
        (r = index_of(g, field[2], "output", sw, g->accessors.count, true, &output)))
        return r;
    uint32_t nv = 0;
    place_label use;
    int cached = -1;
    for (int i = 0; i < INPUT_CACHE && cached < 0; i++)
        if (g->inputs[i].times && g->inputs[i].accessor == input)
            cached = i;
    if (cached >= 0) {
        *nt = g->inputs[cached].count;
        if (!(*times = malloc((size_t)*nt * sizeof **times)))
            return oom(g);
        memcpy(*times, g->inputs[cached].times, (size_t)*nt * sizeof **times);
    } else {
        r = read_accessor_as(g, input, label_open(g, &use, "%s input", 0, 0, sw), 1, FLOAT_ONLY, sizeof **times,
                             (void **)times, nt);
        label_close(g, &use);
        if (r)
            return r;
    }
    r = read_accessor_as(g, output, label_open(g, &use, "%s output", 0, 0, sw), comps, types, sizeof **values,
                         (void **)values, &nv);
    label_close(g, &use);
    if (r) {
        free(*times);
        *times = NULL;
        return r;
    }
    uint32_t per_key = *interp == SINEW_INTERP_CUBIC ? 3 : 1;
    uint64_t want = (uint64_t)*nt * per_key * elements;
    for (uint32_t k = 0; k < *nt && !r && cached < 0; k++) /* a cached input was checked when read */
        if ((*times)[k] < 0 || (k > 0 && (*times)[k] <= (*times)[k - 1]))
            r = fail_at(g, "%s input: key %u at %g s is negative or not after the key before it", sw, k,
                        (double)(*times)[k]);
    if (!r && nv != want)
        r = fail_at(g, "%s: %u output values for %u keys (%s needs %llu a key)", sw, nv, *nt, how ? how : "LINEAR",
                    (unsigned long long)(want / (*nt ? *nt : 1)));
    if (r) {
        free(*times);
        free(*values);
        *times = *values = NULL;
    } else if (cached < 0) { /* keep a copy (none when out of memory: it is only a cache) */
        uint32_t slot = g->input_next++ % INPUT_CACHE;
        float *copy = malloc((size_t)(*nt ? *nt : 1) * sizeof *copy);
        if (copy) {
            free(g->inputs[slot].times);
            memcpy(copy, *times, (size_t)*nt * sizeof *copy);
            g->inputs[slot].accessor = input;
            g->inputs[slot].times = copy;
            g->inputs[slot].count = *nt;
        }
    }
    return r;
}

/* A "weights" channel: the node's morph channels, one weight track each (the output holds
 * every target's weight at each key, CUBICSPLINE: every in-tangent, value, out-tangent). */
static sinew_result read_weights(gltf *g, int node, const json_node *s, const char *sw, raw_clip *clip)
{
    uint32_t n = g->morph_count[node];
    if (n == 0) {
        labels_write(g); /* `sw` is a label's text */
        return raw_model_warn(g->m, "%s: %s animates the morph weights of node %d, whose mesh has no morph targets",
                              g->path, sw, node)
                   ? SINEW_OK
                   : oom(g);
    }
    uint32_t interp, nt;
    float *times = NULL, *values = NULL;
    sinew_result r = read_sampler(g, s, sw, 1, n, ROTATION_TYPES, &interp, &times, &nt, &values);
    if (r)
        return r;
    uint32_t per_key = interp == SINEW_INTERP_CUBIC ? 3 : 1;
    raw_weight_track *grown = realloc(clip->weight_tracks, (clip->weight_track_count + n) * sizeof *grown);
    if (!grown)
        r = oom(g);
    else
        clip->weight_tracks = grown;
    for (uint32_t t = 0; t < n && !r; t++) {
        raw_weight_track *tr = &clip->weight_tracks[clip->weight_track_count++];
        memset(tr, 0, sizeof *tr);
        tr->channel = (uint32_t)g->morph_first[node] + t;
        tr->keys.interp = interp;
        tr->keys.count = nt;
        tr->keys.finite = true; /* copied from checked accessors */
        tr->keys.times = malloc(((size_t)nt + 1) * sizeof *tr->keys.times);
        tr->keys.values = malloc(((size_t)nt * per_key + 1) * sizeof *tr->keys.values);
        if (!tr->keys.times || !tr->keys.values) {
            r = oom(g);
            break;
        }
        if (nt) /* the times rise (read_sampler) */
            clip->duration = fmaxf(clip->duration, times[nt - 1]);
        for (uint32_t k = 0; k < nt; k++) {
            tr->keys.times[k] = times[k];
            for (uint32_t e = 0; e < per_key; e++) /* key k's in-tangents, values, out-tangents */
                tr->keys.values[k * per_key + e] = values[((size_t)k * per_key + e) * n + t];
        }
    }
    free(times);
    free(values);
    return r;
}

/* One channel: its sampler's keys as a raw channel of the node's track. */
static sinew_result read_channel_in(gltf *g, int a, const char *where, const json_node *channel, const table *samplers,
                                    raw_clip *clip)
{
    static const json_key CHANNEL_KEYS[] = {JSON_KEY("target"), JSON_KEY("sampler")};
    static const json_key TARGET_KEYS[] = {JSON_KEY("node"), JSON_KEY("path")};
    const json_node *field[2], *aim[2];
    json_pick(channel, CHANNEL_KEYS, 2, field);
    const json_node *target = field[0];
    int node, sampler;
    sinew_result r;
    if (!json_is_object(target))
        return fail_at(g, "%s: no target", where);
    json_pick(target, TARGET_KEYS, 2, aim);
    if ((r = index_of(g, field[1], "sampler", where, samplers->count, true, &sampler)) ||
        (r = index_of(g, aim[0], "node", where, g->node_count, false, &node)))
        return r;
    if (node < 0)
        return SINEW_OK; /* targets something an extension defines */
    const char *path = json_is_string(aim[1]) ? aim[1]->string : NULL;
    int kind = !path                              ? -2
               : strcmp(path, "translation") == 0 ? SINEW_CHANNEL_TRANSLATION
               : strcmp(path, "rotation") == 0    ? SINEW_CHANNEL_ROTATION
               : strcmp(path, "scale") == 0       ? SINEW_CHANNEL_SCALE
               : strcmp(path, "weights") == 0     ? -1
                                                  : -2;
    if (kind == -2)
        return fail_at(g, "%s.target.path: \"%s\" is not translation, rotation, scale or weights", where,
                       path ? path : "(none)");
    const json_node *s = item(samplers, sampler);
    place_label sampler_label;
    const char *sw = label_open(g, &sampler_label, "animations[%d].samplers[%d]", a, sampler, NULL);
    if (kind == -1) {
        r = read_weights(g, node, s, sw, clip);
        label_close(g, &sampler_label);
        return r;
    }
    int width = kind == SINEW_CHANNEL_ROTATION ? 4 : 3;
    uint32_t interp, nt = 0;
    float *times = NULL, *values = NULL;
    r = read_sampler(g, s, sw, width, 1, kind == SINEW_CHANNEL_ROTATION ? ROTATION_TYPES : FLOAT_ONLY, &interp, &times,
                     &nt, &values);
    label_close(g, &sampler_label);
    if (r)
        return r;
    raw_track *track = NULL;
    uint32_t at = g->node_of[node];
    for (uint32_t t = 0; t < clip->track_count && !r; t++)
        if (clip->tracks[t].node == at)
            track = &clip->tracks[t];
    if (!r && !track) {
        track = &clip->tracks[clip->track_count++];
        track->node = at;
    }
    raw_channel *ch = r ? NULL : &track->channels[kind];
    if (ch && ch->count)
        r = fail_at(g, "%s: a second channel for the %s of node %d", where, path, node);
    if (!r) { /* the channel keeps the sampler's arrays */
        ch->interp = interp;
        ch->count = nt;
        ch->times = times;
        ch->values = values;
        ch->finite = true; /* read_accessor_in checked */
        times = values = NULL;
        if (nt) /* the times rise (read_sampler) */
            clip->duration = fmaxf(clip->duration, ch->times[nt - 1]);
    }
    free(times);
    free(values);
    return r;
}

static sinew_result read_channel(gltf *g, int a, int c, const json_node *channel, const table *samplers, raw_clip *clip)
{
    place_label where;
    sinew_result r = read_channel_in(g, a, label_open(g, &where, "animations[%d].channels[%d]", a, c, NULL), channel,
                                     samplers, clip);
    label_close(g, &where);
    return r;
}

static sinew_result build_clips(gltf *g)
{
    raw_model *m = g->m;
    sinew_result r = top_array(g, "animations", &g->animations);
    int n = g->animations.count;
    if (r || n == 0)
        return r;
    if (!(m->clips = calloc((size_t)n, sizeof *m->clips)))
        return oom(g);
    for (int a = 0; a < n; a++) {
        const json_node *anim = item(&g->animations, a);
        raw_clip *clip = &m->clips[m->clip_count++];
        const char *name = string_at(anim, "name");
        char fallback[32];
        place(fallback, sizeof fallback, "clip %d", a);
        table channels, samplers;
        bool listed = table_of(json_get(anim, "channels"), &channels);
        listed &= table_of(json_get(anim, "samplers"), &samplers);
        int count = channels.count;
        if (!listed || !(clip->name = raw_strdup(name && *name ? name : fallback)) ||
            !(clip->tracks = calloc(count ? (size_t)count : 1, sizeof *clip->tracks)))
            r = oom(g);
        for (int c = 0; c < count && !r; c++)
            r = read_channel(g, a, c, channels.at[c], &samplers, clip);
        free(channels.at);
        free(samplers.at);
        if (r)
            return r;
    }
    return SINEW_OK;
}

/* ---- entry ---------------------------------------------------------------------------- */

sinew_result raw_model_from_gltf(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                 sinew_error *error)
{
    memset(model, 0, sizeof *model);
    gltf g = {.path = path, .m = model, .error = error, .file = bytes, .file_size = size};
    model->source = raw_strdup(path);
    model->format = raw_strdup(gltf_sniff(bytes, size) ? "glb" : "gltf");
    sinew_result r = !model->source || !model->format ? oom(&g) : load_document(&g);
    if (!r)
        r = top_array(&g, "buffers", &g.buffer_items);
    if (!r && (g.buffer_count = g.buffer_items.count) > 0 &&
        !(g.buffers = calloc((size_t)g.buffer_count, sizeof *g.buffers)))
        r = oom(&g);
    if (!r)
        r = top_array(&g, "accessors", &g.accessors);
    if (!r)
        r = top_array(&g, "bufferViews", &g.views);
    if (!r)
        r = top_array(&g, "nodes", &g.nodes);
    if (!r)
        r = top_array(&g, "meshes", &g.meshes);
    if (!r)
        r = top_array(&g, "skins", &g.skins);
    if (!r)
        r = top_array(&g, "materials", &g.materials);
    if (!r)
        r = top_array(&g, "textures", &g.textures);
    if (!r)
        r = top_array(&g, "images", &g.images);
    g.node_count = g.nodes.count;
    if (!r)
        r = build_nodes(&g);
    if (!r)
        r = build_materials(&g);
    if (!r)
        r = build_skins(&g);
    if (!r)
        r = build_meshes(&g);
    if (!r)
        r = build_clips(&g);
    for (int i = 0; g.buffers && i < g.buffer_count; i++)
        if (g.buffers[i].owned)
            free(g.buffers[i].bytes);
    free(g.buffers);
    free(g.node_of);
    free(g.in_scene);
    free(g.keys);
    free(g.uv_transform);
    free(g.has_uv_transform);
    free(g.morph_first);
    free(g.morph_count);
    for (int i = 0; i < INPUT_CACHE; i++)
        free(g.inputs[i].times);
    const table *tables[] = {&g.accessors, &g.views,    &g.nodes,  &g.meshes,       &g.skins,
                             &g.materials, &g.textures, &g.images, &g.buffer_items, &g.animations};
    for (size_t i = 0; i < sizeof tables / sizeof tables[0]; i++)
        free(tables[i]->at);
    json_free(&g.doc);
    if (r)
        raw_model_free(model);
    return r;
}
