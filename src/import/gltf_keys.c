/* glTF samplers that Assimp 5.2.5 flattens: STEP and CUBICSPLINE.
 *
 * Assimp turns every glTF sampler into linear keys: a STEP channel ramps between its keys,
 * and a CUBICSPLINE channel loses its tangents (Assimp keeps the value of each
 * (in-tangent, value, out-tangent) triplet). For .gltf and .glb files sinew reads those
 * samplers again from the file and puts the keys back with their real interpolation; the
 * cubic keys keep the triplet layout sinew's sampler expects.
 *
 * Index:
 *   file and buffers ..... load_document (JSON, GLB chunks), buffer_bytes (GLB BIN, data: URI, file)
 *   accessors ............ read_accessor (float and normalised integer components)
 *   gltf_restore_interpolation
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "../core/internal.h"
#include "internal.h"

typedef struct blob {
    unsigned char *bytes;
    size_t size;
} blob;

typedef struct document {
    const char *path;
    cJSON *json;
    blob file;     /* the whole file (a .glb's BIN chunk points into it) */
    blob glb_bin;  /* not owned */
    blob *buffers; /* buffers loaded on demand (the GLB one is glb_bin itself) */
    int buffer_count;
} document;

static uint32_t le32(const unsigned char *p)
{
    return p[0] | p[1] << 8 | p[2] << 16 | (uint32_t)p[3] << 24;
}

/* Parses a .gltf (JSON) or .glb (12-byte header, JSON chunk, optional BIN chunk). */
static bool load_document(const char *path, document *doc)
{
    memset(doc, 0, sizeof *doc);
    doc->path = path;
    if (!import_read_file(path, &doc->file.bytes, &doc->file.size))
        return false;
    const unsigned char *b = doc->file.bytes;
    size_t n = doc->file.size;
    if (n >= 20 && memcmp(b, "glTF", 4) == 0) {
        uint32_t json_len = le32(b + 12);
        if (le32(b + 16) != 0x4E4F534Au || json_len > n - 20)
            return false;
        doc->json = cJSON_ParseWithLength((const char *)b + 20, json_len);
        size_t at = 20 + (size_t)json_len;
        if (at + 8 <= n && le32(b + at + 4) == 0x004E4942u) {
            uint32_t bin_len = le32(b + at);
            if (bin_len <= n - at - 8)
                doc->glb_bin = (blob){(unsigned char *)b + at + 8, bin_len};
        }
    } else {
        doc->json = cJSON_ParseWithLength((const char *)b, n);
    }
    return doc->json != NULL;
}

static void free_document(document *doc)
{
    for (int i = 0; i < doc->buffer_count; i++)
        if (doc->buffers[i].bytes != doc->glb_bin.bytes)
            free(doc->buffers[i].bytes);
    free(doc->buffers);
    cJSON_Delete(doc->json);
    free(doc->file.bytes);
}

static int base64_value(int c)
{
    if (c >= 'A' && c <= 'Z')
        return c - 'A';
    if (c >= 'a' && c <= 'z')
        return c - 'a' + 26;
    if (c >= '0' && c <= '9')
        return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
}

static bool base64_decode(const char *text, blob *out)
{
    size_t len = strlen(text);
    out->bytes = malloc(len / 4 * 3 + 3);
    if (!out->bytes)
        return false;
    uint32_t acc = 0;
    int bits = 0;
    size_t n = 0;
    for (const char *p = text; *p && *p != '='; p++) {
        int v = base64_value((unsigned char)*p);
        if (v < 0)
            return false;
        acc = acc << 6 | (uint32_t)v;
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out->bytes[n++] = (unsigned char)(acc >> bits);
        }
    }
    out->size = n;
    return true;
}

/* The bytes of buffer `index`: the GLB BIN chunk, a base64 data: URI, or a file beside
 * the document. NULL when it cannot be had. */
static const blob *buffer_bytes(document *doc, int index)
{
    const cJSON *buffers = cJSON_GetObjectItem(doc->json, "buffers");
    int count = cJSON_GetArraySize(buffers);
    if (index < 0 || index >= count)
        return NULL;
    if (!doc->buffers) {
        doc->buffers = calloc((size_t)count, sizeof *doc->buffers);
        if (!doc->buffers)
            return NULL;
        doc->buffer_count = count;
    }
    blob *b = &doc->buffers[index];
    if (b->bytes)
        return b;
    const cJSON *uri = cJSON_GetObjectItem(cJSON_GetArrayItem(buffers, index), "uri");
    if (!cJSON_IsString(uri)) {
        if (index != 0 || !doc->glb_bin.bytes)
            return NULL;
        *b = doc->glb_bin; /* points into doc->file, not freed on its own */
        return b;
    }
    const char *u = uri->valuestring;
    if (strncmp(u, "data:", 5) == 0) {
        const char *comma = strstr(u, ";base64,");
        return comma && base64_decode(comma + 8, b) ? b : NULL;
    }
    if (strstr(u, "://") || strstr(u, ".."))
        return NULL;
    char path[4096];
    const char *slash = strrchr(doc->path, '/');
    int dir = slash ? (int)(slash - doc->path + 1) : 0;
    snprintf(path, sizeof path, "%.*s%s", dir, doc->path, u);
    return import_read_file(path, &b->bytes, &b->size) ? b : NULL;
}

static int component_count(const char *type)
{
    static const struct {
        const char *name;
        int count;
    } types[] = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(type, types[i].name) == 0)
            return types[i].count;
    return 0;
}

static int json_int(const cJSON *object, const char *key, int fallback)
{
    const cJSON *item = cJSON_GetObjectItem(object, key);
    return cJSON_IsNumber(item) ? item->valueint : fallback;
}

/* One component at p: float, or a normalised integer as glTF defines it. */
static bool read_component(const unsigned char *p, int type, float *out)
{
    switch (type) {
    case 5126:
        memcpy(out, p, 4);
        return isfinite(*out);
    case 5120:
        *out = fmaxf((float)(int8_t)p[0] / 127.0f, -1.0f);
        return true;
    case 5121:
        *out = (float)p[0] / 255.0f;
        return true;
    case 5122:
        *out = fmaxf((float)(int16_t)(p[0] | p[1] << 8) / 32767.0f, -1.0f);
        return true;
    case 5123:
        *out = (float)(uint16_t)(p[0] | p[1] << 8) / 65535.0f;
        return true;
    default:
        return false;
    }
}

/* Reads accessor `index` as floats (malloc'd, count * components); false for anything
 * out of bounds, sparse, or of a type sinew does not read here. */
static bool read_accessor(document *doc, int index, int want_components, float **out, int *count)
{
    const cJSON *acc = cJSON_GetArrayItem(cJSON_GetObjectItem(doc->json, "accessors"), index);
    const cJSON *type = cJSON_GetObjectItem(acc, "type");
    if (!acc || index < 0 || !cJSON_IsString(type) || component_count(type->valuestring) != want_components ||
        cJSON_GetObjectItem(acc, "sparse"))
        return false;
    int n = json_int(acc, "count", -1), ctype = json_int(acc, "componentType", 0);
    int csize = ctype == 5126 ? 4 : (ctype == 5122 || ctype == 5123) ? 2 : 1;
    const cJSON *view =
        cJSON_GetArrayItem(cJSON_GetObjectItem(doc->json, "bufferViews"), json_int(acc, "bufferView", -1));
    const blob *buf = view ? buffer_bytes(doc, json_int(view, "buffer", -1)) : NULL;
    if (!buf || n <= 0)
        return false;
    long long start = (long long)json_int(view, "byteOffset", 0) + json_int(acc, "byteOffset", 0);
    long long stride = json_int(view, "byteStride", 0);
    long long elem = (long long)csize * want_components;
    if (stride == 0)
        stride = elem;
    long long view_end = (long long)json_int(view, "byteOffset", 0) + json_int(view, "byteLength", 0);
    if (start < 0 || stride < elem || start + stride * (n - 1) + elem > view_end || view_end > (long long)buf->size)
        return false;
    float *v = malloc((size_t)n * (size_t)want_components * sizeof(float));
    if (!v)
        return false;
    for (int i = 0; i < n; i++)
        for (int c = 0; c < want_components; c++)
            if (!read_component(buf->bytes + start + stride * i + (long long)c * csize, ctype,
                                &v[(size_t)i * want_components + c])) {
                free(v);
                return false;
            }
    *out = v;
    *count = n;
    return true;
}

static raw_track *track_of_node(raw_model *m, raw_clip *clip, const char *name)
{
    for (uint32_t t = 0; t < clip->track_count; t++)
        if (strcmp(m->node_names[clip->tracks[t].node], name) == 0)
            return &clip->tracks[t];
    return NULL;
}

/* Replaces one channel's keys with the sampler's own; false when the file's data cannot
 * be read (the channel then keeps Assimp's keys). */
static bool restore_channel(document *doc, const cJSON *sampler, uint32_t interp, int kind, raw_channel *ch)
{
    int width = kind == SINEW_CHANNEL_ROTATION ? 4 : 3;
    float *times = NULL, *values = NULL;
    int n_times = 0, n_values = 0;
    if (!read_accessor(doc, json_int(sampler, "input", -1), 1, &times, &n_times) ||
        !read_accessor(doc, json_int(sampler, "output", -1), width, &values, &n_values) ||
        n_values != n_times * (interp == SINEW_INTERP_CUBIC ? 3 : 1)) {
        free(times);
        free(values);
        return false;
    }
    free(ch->times);
    free(ch->values);
    *ch = (raw_channel){.interp = interp, .count = (uint32_t)n_times, .times = times, .values = values};
    return true;
}

void gltf_restore_interpolation(const char *path, raw_model *m)
{
    document doc;
    if (!load_document(path, &doc)) {
        free_document(&doc);
        return; /* Assimp read it; nothing more to learn */
    }
    const cJSON *animations = cJSON_GetObjectItem(doc.json, "animations");
    const cJSON *nodes = cJSON_GetObjectItem(doc.json, "nodes");
    if (cJSON_GetArraySize(animations) != (int)m->clip_count) {
        free_document(&doc);
        return;
    }
    uint32_t restored = 0, failed = 0;
    for (uint32_t a = 0; a < m->clip_count; a++) {
        const cJSON *anim = cJSON_GetArrayItem(animations, (int)a);
        const cJSON *samplers = cJSON_GetObjectItem(anim, "samplers"), *channel;
        cJSON_ArrayForEach(channel, cJSON_GetObjectItem(anim, "channels"))
        {
            const cJSON *sampler = cJSON_GetArrayItem(samplers, json_int(channel, "sampler", -1));
            const cJSON *how = cJSON_GetObjectItem(sampler, "interpolation");
            if (!cJSON_IsString(how))
                continue;
            uint32_t interp = strcmp(how->valuestring, "STEP") == 0          ? SINEW_INTERP_STEP
                              : strcmp(how->valuestring, "CUBICSPLINE") == 0 ? SINEW_INTERP_CUBIC
                                                                             : SINEW_INTERP_LINEAR;
            if (interp == SINEW_INTERP_LINEAR)
                continue;
            const cJSON *target = cJSON_GetObjectItem(channel, "target");
            const cJSON *path_item = cJSON_GetObjectItem(target, "path");
            const cJSON *name = cJSON_GetObjectItem(cJSON_GetArrayItem(nodes, json_int(target, "node", -1)), "name");
            int kind = !cJSON_IsString(path_item)                           ? -1
                       : strcmp(path_item->valuestring, "translation") == 0 ? SINEW_CHANNEL_TRANSLATION
                       : strcmp(path_item->valuestring, "rotation") == 0    ? SINEW_CHANNEL_ROTATION
                       : strcmp(path_item->valuestring, "scale") == 0       ? SINEW_CHANNEL_SCALE
                                                                            : -1;
            raw_track *track =
                kind >= 0 && cJSON_IsString(name) ? track_of_node(m, &m->clips[a], name->valuestring) : NULL;
            if (track && restore_channel(&doc, sampler, interp, kind, &track->channels[kind]))
                restored++;
            else if (kind >= 0)
                failed++;
        }
    }
    if (restored)
        raw_model_warn(m, "%u glTF STEP/CUBICSPLINE channels were read again from the file (Assimp makes them linear)",
                       restored);
    if (failed)
        raw_model_warn(m, "%u glTF STEP/CUBICSPLINE channels could not be read again; they play linearly", failed);
    free_document(&doc);
}
