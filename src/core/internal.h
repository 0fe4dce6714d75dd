/* Cross-file internals of src/core (no promise to library users).
 *
 * The model blob, version 1: the layout sinew_model_from_blob() reads and the import
 * builder writes; the start of the .sinew runtime file format. Little-endian.
 *
 *   blob_header                      at offset 0
 *   string pool, tables, arrays      anywhere after it, each aligned to 16 bytes
 *
 * Every reference is a byte offset from the start of the blob (blob_span: offset and
 * element count). Strings are offsets into the pool, which ends with a NUL; BLOB_NONE
 * marks an absent string or array. The checksum is CRC-32 (IEEE) of
 * the whole blob, computed with the checksum field set to 0.
 */
#ifndef SINEW_CORE_INTERNAL_H
#define SINEW_CORE_INTERNAL_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include "sinew/model.h"

#define BLOB_MAGIC "SINEW\r\n\x1a"
#define BLOB_VERSION 1u
#define BLOB_NONE 0xffffffffu
#define BLOB_ALIGN 16u

typedef struct blob_span {
    uint32_t offset;
    uint32_t count;
} blob_span;

typedef struct blob_header {
    char magic[8];
    uint32_t version;
    uint32_t header_size;
    uint64_t size;
    uint32_t checksum;
    uint32_t flags;
    blob_span strings;      /* bytes */
    uint32_t source;        /* string */
    uint32_t format;        /* string */
    blob_span node_names;   /* uint32_t strings */
    blob_span node_parents; /* int32_t */
    blob_span node_rest;    /* sinew_transform */
    blob_span skins;        /* blob_skin */
    blob_span meshes;       /* blob_mesh */
    blob_span instances;    /* sinew_instance */
    blob_span materials;    /* blob_material */
    blob_span clips;        /* blob_clip */
    blob_span warnings;     /* uint32_t strings */
} blob_header;

typedef struct blob_skin {
    blob_span joints;       /* uint32_t */
    blob_span inverse_bind; /* sinew_mat4 */
} blob_skin;

typedef struct blob_mesh {
    uint32_t name;
    uint32_t vertex_count;
    uint32_t index_count;
    uint32_t influence_count;
    int32_t skin;
    int32_t material;
    uint32_t positions; /* offsets of vertex_count elements (influence_count per vertex for joints/weights) */
    uint32_t normals;
    uint32_t uvs; /* BLOB_NONE when absent */
    uint32_t indices;
    uint32_t joints; /* BLOB_NONE for a rigid mesh */
    uint32_t weights;
} blob_mesh;

typedef struct blob_material {
    uint32_t name;
    float base_color[4];
    uint32_t diffuse_texture; /* BLOB_NONE when absent */
} blob_material;

typedef struct blob_clip {
    uint32_t name;
    float duration;
    blob_span tracks; /* sinew_track */
    blob_span times;  /* float */
    blob_span values; /* float */
} blob_clip;

uint32_t sinew_crc32(uint32_t crc, const void *bytes, size_t size);

/* The checksum a blob of `size` >= sizeof(blob_header) bytes should carry. */
uint32_t sinew_blob_checksum(const void *bytes, size_t size);

/* Fills error (when not NULL) with kind and a printf-style message; returns kind. */
sinew_result sinew_fail(sinew_error *error, sinew_result kind, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Width in floats of one key value of a channel kind (translation/scale 3, rotation 4). */
static inline uint32_t sinew_channel_width(int kind)
{
    return kind == SINEW_CHANNEL_ROTATION ? 4u : 3u;
}

/* Floats one key takes in the value array. */
static inline uint32_t sinew_channel_stride(int kind, uint32_t interp)
{
    return sinew_channel_width(kind) * (interp == SINEW_INTERP_CUBIC ? 3u : 1u);
}

#endif
