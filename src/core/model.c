/* The runtime model: reading and validating a model blob, lookups, freeing.
 *
 * Index:
 *   section kinds ......... the tags of the .sinew directory (format in internal.h)
 *   reader helpers ........ range_ok, string_at, array_at (bounds, alignment, overflow)
 *   validation ............ check_header (directory), check_nodes, check_skins, ...
 *   sinew_model_from_blob . one allocation: the blob copy, then the pointer tables
 *   sinew_model_load ...... the same from a file, read straight into that allocation
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "internal.h"
#include "sinew/muscle.h"

#define SECTION(tag, field, type)                                                                                      \
    {                                                                                                                  \
        tag, offsetof(blob_header, field), sizeof(type)                                                                \
    }
const blob_section_kind sinew_blob_section_kinds[] = {
    SECTION("STRS", strings, char),
    SECTION("NNAM", node_names, uint32_t),
    SECTION("NPAR", node_parents, int32_t),
    SECTION("NRST", node_rest, sinew_transform),
    SECTION("SKIN", skins, blob_skin),
    SECTION("MESH", meshes, blob_mesh),
    SECTION("INST", instances, blob_instance),
    SECTION("MATL", materials, blob_material),
    SECTION("CLIP", clips, blob_clip),
    SECTION("WARN", warnings, uint32_t),
    SECTION("MUSC", muscles, blob_muscle),
    SECTION("NINH", node_inherit, uint8_t),
    SECTION("MTAN", mesh_tangents, uint32_t),
    SECTION("MPBR", materials_pbr, blob_pbr),
    SECTION("MCHN", morph_channels, blob_morph_channel),
    SECTION("MTGT", morph_targets, blob_morph_target),
    SECTION("IMRF", instance_morph, uint32_t),
    SECTION("WTRK", weight_tracks, blob_weight_track),
    SECTION("VCCH", caches, blob_cache),
    SECTION("SKBL", skin_blend, uint32_t),
    SECTION("MDQW", mesh_dq, uint32_t),
    SECTION("CTLN", clip_timeline, float),
    SECTION("MFLT", mesh_flat, uint8_t),
    SECTION("MCOL", mesh_colors, uint32_t),
    SECTION("MALP", material_alpha, blob_alpha),
};
#undef SECTION
const uint32_t sinew_blob_section_kind_count = sizeof sinew_blob_section_kinds / sizeof sinew_blob_section_kinds[0];
const char *const sinew_blob_old_version_warning =
    "the .sinew file was written by an older sinew (format 3), before it kept morph targets, vertex caches and "
    "skinning methods: convert the source file again for them";

/* The allocation behind a model: this struct, the pointer tables, then the blob copy. */
typedef struct model_block {
    sinew_model model;
    sinew_muscle_set muscles;
    sinew_allocator allocator;
    const unsigned char *blob;
    size_t blob_size;
    void *owned;      /* the blob, when it is a block of its own (adopted: not copied): malloc'd or
                       * sinew_pages_alloc'd, freed by sinew_block_free */
    uint32_t version; /* of the blob: an older one adds a warning */
} model_block;

typedef struct reader {
    const unsigned char *bytes;
    size_t size;
    const char *name;
    const blob_header *header; /* the directory, decoded */
    sinew_error *error;
} reader;

static void *default_alloc(size_t size, void *user)
{
    (void)user;
    return aligned_alloc(BLOB_ALIGN, (size + BLOB_ALIGN - 1) & ~(size_t)(BLOB_ALIGN - 1));
}

static void default_free(void *ptr, void *user)
{
    (void)user;
    free(ptr);
}

sinew_allocator sinew_allocator_or_default(const sinew_allocator *allocator)
{
    return allocator ? *allocator : (sinew_allocator){default_alloc, default_free, NULL};
}

static sinew_result corrupt(const reader *r, const char *what)
{
    return sinew_fail(r->error, SINEW_ERROR_FORMAT, "%s: corrupted model data: %s", r->name, what);
}

/* True when [offset, offset + count * elem) lies inside the blob, aligned to 4. */
static bool range_ok(const reader *r, uint32_t offset, uint64_t count, uint64_t elem)
{
    if (count == 0)
        return true;
    if (offset == BLOB_NONE || offset % 4u != 0 || offset < sizeof(blob_file_header))
        return false;
    uint64_t bytes = count * elem;
    if (elem != 0 && bytes / elem != count)
        return false;
    return (uint64_t)offset + bytes <= r->size;
}

/* The array at offset, already checked by range_ok(); NULL when empty or absent. */
static const void *array_at(const reader *r, uint32_t offset, uint64_t count)
{
    if (count == 0 || offset == BLOB_NONE)
        return NULL;
    return r->bytes + offset;
}

static const char *string_at(const reader *r, uint32_t offset)
{
    if (offset == BLOB_NONE)
        return NULL;
    return (const char *)r->bytes + r->header->strings.offset + offset;
}

static sinew_texture texture_at(const reader *r, const blob_texture *t)
{
    const unsigned char *image = array_at(r, t->image.offset, t->image.count);
    return (sinew_texture){string_at(r, t->path), image, image ? t->image.count : 0};
}

static bool string_ok(const reader *r, uint32_t offset, bool optional)
{
    if (offset == BLOB_NONE)
        return optional;
    return offset < r->header->strings.count;
}

/* Checks of long float arrays go a block of FLOAT_BLOCK at a time: each block's answer is the OR
 * of its elements' (a loop without exits, which the compiler vectorises), looked at after it. */
#define FLOAT_BLOCK 64

bool sinew_floats_finite(const float *values, uint64_t count)
{
    uint64_t i = 0;
    for (; i + FLOAT_BLOCK <= count; i += FLOAT_BLOCK) {
        uint32_t bad = 0;
        for (uint32_t j = 0; j < FLOAT_BLOCK; j++) {
            uint32_t bits;
            memcpy(&bits, &values[i + j], sizeof bits);
            bad |= (bits & 0x7f800000u) == 0x7f800000u;
        }
        if (bad)
            return false;
    }
    for (; i < count; i++)
        if (!isfinite(values[i]))
            return false;
    return true;
}

bool sinew_times_ascending(const float *times, uint32_t count)
{
    uint32_t k = 1;
    for (; k + FLOAT_BLOCK <= count; k += FLOAT_BLOCK) {
        uint32_t bad = 0;
        for (uint32_t j = 0; j < FLOAT_BLOCK; j++)
            bad |= times[k + j] < times[k + j - 1];
        if (bad)
            return false;
    }
    for (; k < count; k++)
        if (times[k] < times[k - 1])
            return false;
    return true;
}

static bool texture_ok(const reader *r, const blob_texture *t)
{
    return string_ok(r, t->path, true) && range_ok(r, t->image.offset, t->image.count, 1);
}

/* Decodes the directory of a blob whose header was checked into r->header. */
static sinew_result read_directory(reader *r, const blob_file_header *f, blob_header *h)
{
    memset(h, 0, sizeof *h);
    h->source = f->source;
    h->format = f->format;
    h->version = f->version;
    if (f->section_count > BLOB_MAX_SECTIONS || sizeof *f + (uint64_t)f->section_count * sizeof(blob_section) > r->size)
        return corrupt(r, "section directory");
    bool seen[sizeof sinew_blob_section_kinds / sizeof sinew_blob_section_kinds[0]] = {false};
    for (uint32_t i = 0; i < f->section_count; i++) {
        blob_section sec;
        memcpy(&sec, r->bytes + sizeof *f + i * sizeof sec, sizeof sec);
        if (!range_ok(r, sec.offset, sec.count, sec.elem_size))
            return corrupt(r, "section out of bounds");
        for (uint32_t k = 0; k < sinew_blob_section_kind_count; k++) {
            const blob_section_kind *kind = &sinew_blob_section_kinds[k];
            if (memcmp(sec.tag, kind->tag, 4) != 0)
                continue;
            if (sec.count && sec.offset % 8u != 0) /* tables hold doubles (muscles) */
                return corrupt(r, "section not aligned");
            if (seen[k] || sec.elem_size != kind->elem_size)
                return sinew_fail(r->error, SINEW_ERROR_FORMAT, "%s: corrupted model data: section %.4s %s", r->name,
                                  kind->tag, seen[k] ? "appears twice" : "has the wrong element size");
            seen[k] = true;
            blob_span *span = (blob_span *)((char *)h + kind->field);
            *span = (blob_span){sec.offset, sec.count};
        }
    }
    return SINEW_OK;
}

/* Checks the header, the directory and that every top-level table fits in the blob, before
 * anything is allocated from its counts (the check_* functions below rely on it). Reads
 * the header and directory through copies (the bytes may be unaligned). */
static sinew_result check_header(reader *r, blob_header *h, bool checksum)
{
    blob_file_header f;
    if (r->size < sizeof f)
        return sinew_fail(r->error, SINEW_ERROR_FORMAT, "%s: truncated model data (%zu bytes, the header alone is %zu)",
                          r->name, r->size, sizeof f);
    memcpy(&f, r->bytes, sizeof f);
    if (memcmp(f.magic, BLOB_MAGIC, 8) != 0)
        return sinew_fail(r->error, SINEW_ERROR_FORMAT, "%s: not a sinew model (bad magic)", r->name);
    if (f.version < BLOB_OLDEST_VERSION || f.version > BLOB_VERSION)
        return sinew_fail(r->error, SINEW_ERROR_FORMAT,
                          "%s: unsupported sinew model version %u (this build reads %u to %u; convert the source file "
                          "again)",
                          r->name, f.version, BLOB_OLDEST_VERSION, BLOB_VERSION);
    if (f.header_size != sizeof f || f.flags != 0)
        return corrupt(r, "header size or flags");
    if (f.size != r->size)
        return sinew_fail(r->error, SINEW_ERROR_FORMAT, "%s: truncated model data (%zu bytes of %llu)", r->name,
                          r->size, (unsigned long long)f.size);
#ifndef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION /* the fuzzer's mutants get past it to the checks below */
    if (checksum && sinew_blob_checksum(r->bytes, r->size) != f.checksum)
        return sinew_fail(r->error, SINEW_ERROR_FORMAT, "%s: checksum mismatch: the model data is corrupted", r->name);
#else
    (void)checksum;
#endif
    sinew_result result = read_directory(r, &f, h);
    if (result)
        return result;
    r->header = h;
    if (h->strings.count == 0 || r->bytes[h->strings.offset + h->strings.count - 1] != '\0')
        return corrupt(r, "string pool");
    if (!string_ok(r, h->source, false) || !string_ok(r, h->format, false))
        return corrupt(r, "source name");
    uint32_t n = h->node_names.count;
    if (h->node_parents.count != n || h->node_rest.count != n || (h->node_inherit.count && h->node_inherit.count != n))
        return corrupt(r, "node table sizes differ");
    return SINEW_OK;
}

static sinew_result check_nodes(reader *r)
{
    const blob_header *h = r->header;
    uint32_t n = h->node_names.count;
    const uint32_t *names = array_at(r, h->node_names.offset, n);
    const int32_t *parents = array_at(r, h->node_parents.offset, n);
    const sinew_transform *rest = array_at(r, h->node_rest.offset, n);
    for (uint32_t i = 0; i < n; i++) {
        if (!string_ok(r, names[i], false))
            return corrupt(r, "node name");
        if (parents[i] < -1 || parents[i] >= (int32_t)i)
            return corrupt(r, "node parent is not before its child");
    }
    if (n && !sinew_floats_finite((const float *)rest, (uint64_t)n * 10))
        return corrupt(r, "node rest transform is not finite");
    const uint8_t *inherit = h->node_inherit.count ? array_at(r, h->node_inherit.offset, n) : NULL;
    for (uint32_t i = 0; inherit && i < n; i++)
        if (inherit[i] > SINEW_INHERIT_COMPONENTWISE_SCALE)
            return corrupt(r, "node inherit type");
    return SINEW_OK;
}

static sinew_result check_skins(reader *r)
{
    const blob_header *h = r->header;
    const blob_skin *skins = array_at(r, h->skins.offset, h->skins.count);
    for (uint32_t s = 0; s < h->skins.count; s++) {
        const blob_skin *skin = &skins[s];
        if (skin->joints.count > SINEW_MAX_JOINTS || skin->inverse_bind.count != skin->joints.count)
            return corrupt(r, "skin joint count");
        if (!range_ok(r, skin->joints.offset, skin->joints.count, 4) ||
            !range_ok(r, skin->inverse_bind.offset, skin->inverse_bind.count, sizeof(sinew_mat4)))
            return corrupt(r, "skin arrays out of bounds");
        const uint32_t *joints = array_at(r, skin->joints.offset, skin->joints.count);
        for (uint32_t j = 0; j < skin->joints.count; j++)
            if (joints[j] >= h->node_names.count)
                return corrupt(r, "skin joint is not a node");
        if (skin->joints.count &&
            !sinew_floats_finite(array_at(r, skin->inverse_bind.offset, 1), (uint64_t)skin->joints.count * 16))
            return corrupt(r, "inverse bind matrix is not finite");
    }
    return SINEW_OK;
}

static bool mesh_arrays_ok(const reader *r, const blob_mesh *m, uint32_t joint_limit)
{
    uint64_t v = m->vertex_count;
    if (!range_ok(r, m->positions, v, 12) || !range_ok(r, m->normals, v, 12) ||
        !range_ok(r, m->indices, m->index_count, 4))
        return false;
    if (m->uvs != BLOB_NONE && !range_ok(r, m->uvs, v, 8))
        return false;
    if (m->influence_count &&
        (!range_ok(r, m->joints, v * m->influence_count, 2) || !range_ok(r, m->weights, v * m->influence_count, 4)))
        return false;
    if (v && (!sinew_floats_finite(array_at(r, m->positions, v), v * 3) ||
              !sinew_floats_finite(array_at(r, m->normals, v), v * 3)))
        return false;
    if (v && m->uvs != BLOB_NONE && !sinew_floats_finite(array_at(r, m->uvs, v), v * 2))
        return false;
    const uint32_t *indices = array_at(r, m->indices, m->index_count);
    for (uint32_t i = 0; i < m->index_count; i++)
        if (indices[i] >= m->vertex_count)
            return false;
    if (m->influence_count) {
        uint64_t k = v * m->influence_count;
        const uint16_t *joints = array_at(r, m->joints, k);
        const float *weights = array_at(r, m->weights, k);
        for (uint64_t i = 0; i < k; i++)
            if (joints[i] >= joint_limit || !isfinite(weights[i]) || weights[i] < 0.0f)
                return false;
    }
    return true;
}

/* MTAN, MCOL: absent, or an offset a mesh of 4 finite floats a vertex (BLOB_NONE: none). */
static bool mesh_optional_ok(const reader *r, const blob_span *span, const blob_mesh *meshes, uint32_t mesh_count)
{
    if (span->count && span->count != mesh_count)
        return false;
    const uint32_t *offsets = array_at(r, span->offset, span->count); /* NULL: none */
    for (uint32_t i = 0; offsets && i < mesh_count; i++) {
        uint64_t v = meshes[i].vertex_count;
        if (offsets[i] != BLOB_NONE &&
            (!range_ok(r, offsets[i], v, 16) || (v && !sinew_floats_finite(array_at(r, offsets[i], v), v * 4))))
            return false;
    }
    return true;
}

static sinew_result check_meshes(reader *r)
{
    const blob_header *h = r->header;
    const blob_skin *skins = array_at(r, h->skins.offset, h->skins.count);
    const blob_mesh *meshes = array_at(r, h->meshes.offset, h->meshes.count);
    for (uint32_t i = 0; i < h->meshes.count; i++) {
        const blob_mesh *m = &meshes[i];
        if (!string_ok(r, m->name, false) || m->index_count % 3 != 0 || m->influence_count > SINEW_MAX_INFLUENCES)
            return corrupt(r, "mesh header");
        if (m->material < -1 || m->material >= (int32_t)h->materials.count)
            return corrupt(r, "mesh material index");
        if (m->skin < -1 || m->skin >= (int32_t)h->skins.count || (m->skin >= 0) != (m->influence_count > 0))
            return corrupt(r, "mesh skin index");
        uint32_t joint_limit = m->skin >= 0 ? skins[m->skin].joints.count : 0;
        if (!mesh_arrays_ok(r, m, joint_limit))
            return corrupt(r, "mesh arrays");
    }
    if (!mesh_optional_ok(r, &h->mesh_tangents, meshes, h->meshes.count))
        return corrupt(r, "mesh tangents");
    if (!mesh_optional_ok(r, &h->mesh_colors, meshes, h->meshes.count))
        return corrupt(r, "mesh colours");
    if (h->mesh_flat.count && h->mesh_flat.count != h->meshes.count)
        return corrupt(r, "mesh flat normals table");
    const uint8_t *flat = array_at(r, h->mesh_flat.offset, h->mesh_flat.count); /* NULL: none */
    for (uint32_t i = 0; flat && i < h->meshes.count; i++)
        if (flat[i] > 1)
            return corrupt(r, "mesh flat normals");
    const blob_material *materials = array_at(r, h->materials.offset, h->materials.count);
    for (uint32_t i = 0; i < h->materials.count; i++)
        if (!string_ok(r, materials[i].name, false) || !sinew_floats_finite(materials[i].base_color, 4) ||
            !texture_ok(r, &materials[i].base_color_map))
            return corrupt(r, "material");
    if (h->materials_pbr.count && h->materials_pbr.count != h->materials.count)
        return corrupt(r, "material PBR table");
    const blob_pbr *pbr = array_at(r, h->materials_pbr.offset, h->materials_pbr.count); /* NULL: none */
    for (uint32_t i = 0; pbr && i < h->materials.count; i++) {
        bool maps_ok = true;
        for (int k = 0; k < SINEW_MAP_COUNT - 1; k++)
            maps_ok &= texture_ok(r, &pbr[i].maps[k]);
        if (!maps_ok || !sinew_floats_finite(&pbr[i].metallic, 7) || pbr[i].flags > 1)
            return corrupt(r, "material PBR parameters");
    }
    if (h->material_alpha.count && h->material_alpha.count != h->materials.count)
        return corrupt(r, "material alpha table");
    const blob_alpha *alpha = array_at(r, h->material_alpha.offset, h->material_alpha.count); /* NULL: none */
    for (uint32_t i = 0; alpha && i < h->materials.count; i++)
        if (alpha[i].mode > SINEW_ALPHA_BLEND || !(alpha[i].cutoff >= 0.0f && alpha[i].cutoff <= 1.0f))
            return corrupt(r, "material alpha");
    const blob_instance *instances = array_at(r, h->instances.offset, h->instances.count);
    for (uint32_t i = 0; i < h->instances.count; i++)
        if (instances[i].mesh >= h->meshes.count || instances[i].node >= h->node_names.count)
            return corrupt(r, "mesh instance");
    return SINEW_OK;
}

/* `*checked`: the times range last found good (first key << 32 | count), which channels sharing
 * their times (the builder writes them once) do not check again. */
static bool channel_ok(const reader *r, const blob_clip *c, const sinew_channel *ch, int kind, uint64_t *checked)
{
    if (ch->key_count == 0)
        return true;
    if (ch->interp > SINEW_INTERP_BEZIER || (ch->interp == SINEW_INTERP_BEZIER && kind == SINEW_CHANNEL_ROTATION))
        return false;
    uint64_t stride = sinew_channel_stride(kind, ch->interp);
    if ((uint64_t)ch->first_key + ch->key_count > c->times.count ||
        (uint64_t)ch->first_value + ch->key_count * stride > c->values.count)
        return false;
    /* The keys the channel takes (clips may share longer arrays: each checks its own). */
    const float *times = (const float *)array_at(r, c->times.offset, c->times.count) + ch->first_key;
    const float *values = (const float *)array_at(r, c->values.offset, c->values.count) + ch->first_value;
    uint64_t range = (uint64_t)ch->first_key << 32 | ch->key_count;
    if (range != *checked) {
        if (!sinew_floats_finite(times, ch->key_count) || !sinew_times_ascending(times, ch->key_count))
            return false;
        *checked = range;
    }
    if (!sinew_floats_finite(values, ch->key_count * stride))
        return false;
    if (ch->interp == SINEW_INTERP_BEZIER)
        return sinew_bezier_times_ok(times, values, ch->key_count, sinew_channel_width(kind));
    return true;
}

static sinew_result check_clips(reader *r)
{
    const blob_header *h = r->header;
    const blob_clip *clips = array_at(r, h->clips.offset, h->clips.count);
    for (uint32_t i = 0; i < h->clips.count; i++) {
        const blob_clip *c = &clips[i];
        if (!string_ok(r, c->name, false) || !isfinite(c->duration) || c->duration < 0.0f || !isfinite(c->start) ||
            c->reserved != 0)
            return corrupt(r, "clip header");
        if (!range_ok(r, c->tracks.offset, c->tracks.count, sizeof(sinew_track)) ||
            !range_ok(r, c->times.offset, c->times.count, 4) || !range_ok(r, c->values.offset, c->values.count, 4))
            return corrupt(r, "clip arrays out of bounds");
        const sinew_track *tracks = array_at(r, c->tracks.offset, c->tracks.count);
        uint64_t checked = UINT64_MAX;
        for (uint32_t t = 0; t < c->tracks.count; t++) {
            if (tracks[t].node >= h->node_names.count || (t > 0 && tracks[t].node <= tracks[t - 1].node))
                return corrupt(r, "track node");
            for (int kind = 0; kind < SINEW_CHANNEL_COUNT; kind++)
                if (!channel_ok(r, c, &tracks[t].channels[kind], kind, &checked))
                    return corrupt(r, "track keys");
        }
    }
    const uint32_t *warnings = array_at(r, h->warnings.offset, h->warnings.count);
    for (uint32_t i = 0; i < h->warnings.count; i++)
        if (!string_ok(r, warnings[i], false))
            return corrupt(r, "warning text");
    return SINEW_OK;
}

/* Version 4's deformer sections: morph channels and targets, the instances' channels, clips'
 * weight tracks, vertex caches, skins' blend and meshes' dual-quaternion weights. */
static sinew_result check_deformers(reader *r)
{
    const blob_header *h = r->header;
    const blob_mesh *meshes = array_at(r, h->meshes.offset, h->meshes.count);
    if ((h->skin_blend.count && h->skin_blend.count != h->skins.count) ||
        (h->mesh_dq.count && h->mesh_dq.count != h->meshes.count) ||
        (h->instance_morph.count && h->instance_morph.count != h->instances.count) ||
        (h->clip_timeline.count && h->clip_timeline.count != 2 * h->clips.count))
        return corrupt(r, "deformer table sizes");
    const uint32_t *blend = array_at(r, h->skin_blend.offset, h->skin_blend.count);
    for (uint32_t i = 0; blend && i < h->skin_blend.count; i++)
        if (blend[i] > SINEW_SKIN_BLEND_MIXED)
            return corrupt(r, "skin blend");
    const uint32_t *dq = array_at(r, h->mesh_dq.offset, h->mesh_dq.count);
    for (uint32_t i = 0; dq && i < h->mesh_dq.count; i++) {
        uint64_t v = meshes[i].vertex_count;
        if (dq[i] == BLOB_NONE)
            continue;
        if (!range_ok(r, dq[i], v, 4))
            return corrupt(r, "mesh dual-quaternion weights");
        const float *w = array_at(r, dq[i], v);
        for (uint64_t k = 0; k < v; k++)
            if (!(w[k] >= 0.0f && w[k] <= 1.0f))
                return corrupt(r, "mesh dual-quaternion weights");
    }
    const blob_morph_channel *channels = array_at(r, h->morph_channels.offset, h->morph_channels.count);
    for (uint32_t i = 0; i < h->morph_channels.count; i++)
        if (!string_ok(r, channels[i].name, false) || !isfinite(channels[i].default_weight))
            return corrupt(r, "morph channel");
    const blob_morph_target *targets = array_at(r, h->morph_targets.offset, h->morph_targets.count);
    for (uint32_t i = 0; i < h->morph_targets.count; i++) {
        const blob_morph_target *t = &targets[i];
        if (t->mesh >= h->meshes.count || (i > 0 && t->mesh < targets[i - 1].mesh) || !string_ok(r, t->name, false) ||
            t->channel >= h->morph_channels.count || !isfinite(t->full_weight) || t->full_weight == 0.0f)
            return corrupt(r, "morph target");
        if (i > 0 && t->mesh == targets[i - 1].mesh &&
            (t->channel < targets[i - 1].channel ||
             (t->channel == targets[i - 1].channel && !(t->full_weight > targets[i - 1].full_weight))))
            return corrupt(r, "morph targets out of order");
        uint64_t n = t->delta_count;
        if (n > meshes[t->mesh].vertex_count || !range_ok(r, t->vertices, n, 4) || !range_ok(r, t->positions, n, 12) ||
            (t->normals != BLOB_NONE && !range_ok(r, t->normals, n, 12)) ||
            (t->tangents != BLOB_NONE && !range_ok(r, t->tangents, n, 12)))
            return corrupt(r, "morph target arrays");
        const uint32_t *v = array_at(r, t->vertices, n);
        for (uint64_t k = 0; k < n; k++)
            if (v[k] >= meshes[t->mesh].vertex_count || (k > 0 && v[k] <= v[k - 1]))
                return corrupt(r, "morph target vertices");
        if (n && (!sinew_floats_finite(array_at(r, t->positions, n), n * 3) ||
                  (t->normals != BLOB_NONE && !sinew_floats_finite(array_at(r, t->normals, n), n * 3)) ||
                  (t->tangents != BLOB_NONE && !sinew_floats_finite(array_at(r, t->tangents, n), n * 3))))
            return corrupt(r, "morph target offsets");
    }
    /* every instance's channels lie within the model's */
    const blob_instance *instances = array_at(r, h->instances.offset, h->instances.count);
    const uint32_t *first = array_at(r, h->instance_morph.offset, h->instance_morph.count);
    for (uint32_t i = 0; i < h->morph_targets.count; i++)
        for (uint32_t k = 0; k < h->instances.count; k++)
            if (instances[k].mesh == targets[i].mesh &&
                (uint64_t)(first ? first[k] : 0) + targets[i].channel >= h->morph_channels.count)
                return corrupt(r, "instance morph channels");
    const blob_clip *clips = array_at(r, h->clips.offset, h->clips.count);
    const blob_weight_track *tracks = array_at(r, h->weight_tracks.offset, h->weight_tracks.count);
    for (uint32_t i = 0; i < h->weight_tracks.count; i++) {
        const blob_weight_track *t = &tracks[i];
        if (t->clip >= h->clips.count || t->channel >= h->morph_channels.count ||
            (i > 0 && (t->clip < tracks[i - 1].clip ||
                       (t->clip == tracks[i - 1].clip && t->channel <= tracks[i - 1].channel))) ||
            t->keys.interp == SINEW_INTERP_BEZIER ||
            !channel_ok(r, &clips[t->clip], &t->keys, SINEW_CHANNEL_WEIGHT, &(uint64_t){UINT64_MAX}))
            return corrupt(r, "weight track");
    }
    const blob_cache *caches = array_at(r, h->caches.offset, h->caches.count);
    for (uint32_t i = 0; i < h->caches.count; i++) {
        const blob_cache *c = &caches[i];
        if (c->mesh >= h->meshes.count || (i > 0 && c->mesh <= caches[i - 1].mesh) || c->frame_count == 0)
            return corrupt(r, "vertex cache");
        uint64_t values = (uint64_t)c->frame_count * meshes[c->mesh].vertex_count * 3;
        if (!range_ok(r, c->times, c->frame_count, 4) || !range_ok(r, c->positions, values, 4))
            return corrupt(r, "vertex cache arrays");
        const float *times = array_at(r, c->times, c->frame_count);
        if (!sinew_floats_finite(times, c->frame_count) ||
            (values && !sinew_floats_finite(array_at(r, c->positions, values), values)))
            return corrupt(r, "vertex cache values");
        for (uint32_t k = 1; k < c->frame_count; k++)
            if (!(times[k] > times[k - 1]))
                return corrupt(r, "vertex cache times");
    }
    const float *timeline = array_at(r, h->clip_timeline.offset, h->clip_timeline.count);
    if (timeline && !sinew_floats_finite(timeline, h->clip_timeline.count))
        return corrupt(r, "clip timeline");
    for (uint32_t i = 1; timeline && i < h->clip_timeline.count; i += 2)
        if (timeline[i] < 0.0f)
            return corrupt(r, "clip frame rate");
    return SINEW_OK;
}

static bool numbers_ok(const reader *r, uint32_t offset, uint32_t count, bool positive)
{
    if (offset % 8u != 0 || !range_ok(r, offset, count, sizeof(double)))
        return false;
    const double *values = array_at(r, offset, count);
    for (uint32_t i = 0; i < count; i++)
        if (!(fabs(values[i]) <= SINEW_MUSCLE_MAX_MAGNITUDE) || (positive && !(values[i] > 0.0)))
            return false;
    return true;
}

/* The same limits as the muscle JSON reader puts on a muscle. */
static sinew_result check_muscles(reader *r)
{
    const blob_header *h = r->header;
    const blob_muscle *muscles = array_at(r, h->muscles.offset, h->muscles.count);
    for (uint32_t i = 0; i < h->muscles.count; i++) {
        const blob_muscle *m = &muscles[i];
        if (!string_ok(r, m->name, false) || !string_ok(r, m->origin_joint, true) ||
            !string_ok(r, m->insertion_joint, true))
            return corrupt(r, "muscle name");
        if (m->node_count == 0 || m->node_count > SINEW_MUSCLE_MAX_NODES || m->segments < 3 || m->segments > 256 ||
            !(m->rest_length >= 0.0 && m->rest_length <= SINEW_MUSCLE_MAX_MAGNITUDE))
            return corrupt(r, "muscle header");
        bool near = true;
        for (int k = 0; k < 3; k++)
            near = near && fabsf(m->origin_offset[k]) <= SINEW_MUSCLE_MAX_MAGNITUDE &&
                   fabsf(m->insertion_offset[k]) <= SINEW_MUSCLE_MAX_MAGNITUDE;
        if (!near || !sinew_floats_finite(m->color, 3))
            return corrupt(r, "muscle attachment");
        if (!numbers_ok(r, m->radii, m->node_count, true) || !numbers_ok(r, m->coefficients, m->node_count, false))
            return corrupt(r, "muscle radii or coefficients");
    }
    return SINEW_OK;
}

/* Each table starts on an 8-byte boundary, whatever the size of the one before
 * (sinew_instance is 12 bytes). */
static size_t table_bytes(size_t count, size_t elem)
{
    return (count * elem + 7) & ~(size_t)7;
}

/* Bytes of pointer tables that follow the model_block struct. */
static size_t tables_size(const blob_header *h)
{
    size_t size = 0;
    size += table_bytes(h->node_names.count, sizeof(char *));
    size += table_bytes((size_t)h->warnings.count + 1, sizeof(char *)); /* + a warning about an older format */
    size += table_bytes(h->skins.count, sizeof(sinew_skin));
    size += table_bytes(h->meshes.count, sizeof(sinew_mesh));
    size += table_bytes(h->materials.count, sizeof(sinew_material));
    size += table_bytes(h->clips.count, sizeof(sinew_clip));
    size += table_bytes(h->muscles.count, sizeof(sinew_muscle_def));
    size += table_bytes(h->instances.count, sizeof(sinew_instance));
    size += table_bytes(h->morph_channels.count, sizeof(sinew_morph_channel));
    size += table_bytes(h->morph_targets.count, sizeof(sinew_morph_target));
    size += table_bytes(h->weight_tracks.count, sizeof(sinew_weight_track));
    size += table_bytes(h->caches.count, sizeof(sinew_vertex_cache));
    return (size + BLOB_ALIGN - 1) & ~(size_t)(BLOB_ALIGN - 1);
}

/* Takes `bytes` (rounded up to 8) from a cursor in the table area. */
static void *take(unsigned char **cursor, size_t bytes)
{
    void *p = *cursor;
    *cursor += (bytes + 7) & ~(size_t)7;
    return p;
}

/* Instances, morph channels, the meshes' targets, dual-quaternion weights and caches. */
static void fill_deformers(sinew_model *m, const reader *r, sinew_mesh *meshes, unsigned char **cursor)
{
    const blob_header *h = r->header;
    m->instance_count = h->instances.count;
    sinew_instance *instances = take(cursor, m->instance_count * sizeof(sinew_instance));
    const blob_instance *binst = array_at(r, h->instances.offset, m->instance_count);
    const uint32_t *first = array_at(r, h->instance_morph.offset, h->instance_morph.count);
    for (uint32_t i = 0; i < m->instance_count; i++)
        instances[i] = (sinew_instance){binst[i].mesh, binst[i].node, first ? first[i] : 0};
    m->instances = instances;

    m->morph_channel_count = h->morph_channels.count;
    sinew_morph_channel *channels = take(cursor, m->morph_channel_count * sizeof(sinew_morph_channel));
    const blob_morph_channel *bch = array_at(r, h->morph_channels.offset, m->morph_channel_count);
    for (uint32_t i = 0; i < m->morph_channel_count; i++)
        channels[i] = (sinew_morph_channel){string_at(r, bch[i].name), bch[i].default_weight};
    m->morph_channels = channels;

    sinew_morph_target *targets = take(cursor, h->morph_targets.count * sizeof(sinew_morph_target));
    const blob_morph_target *bt = array_at(r, h->morph_targets.offset, h->morph_targets.count);
    for (uint32_t i = 0; i < h->morph_targets.count; i++) {
        targets[i] = (sinew_morph_target){
            .name = string_at(r, bt[i].name),
            .channel = bt[i].channel,
            .full_weight = bt[i].full_weight,
            .delta_count = bt[i].delta_count,
            .vertices = array_at(r, bt[i].vertices, bt[i].delta_count),
            .positions = array_at(r, bt[i].positions, bt[i].delta_count),
            .normals = bt[i].normals == BLOB_NONE ? NULL : array_at(r, bt[i].normals, bt[i].delta_count),
            .tangents = bt[i].tangents == BLOB_NONE ? NULL : array_at(r, bt[i].tangents, bt[i].delta_count),
        };
        sinew_mesh *mesh = &meshes[bt[i].mesh];
        if (mesh->target_count++ == 0)
            mesh->targets = &targets[i];
        if (bt[i].channel + 1 > mesh->morph_channel_count)
            mesh->morph_channel_count = bt[i].channel + 1;
    }

    const uint32_t *dq = array_at(r, h->mesh_dq.offset, h->mesh_dq.count);
    for (uint32_t i = 0; dq && i < h->mesh_dq.count; i++)
        meshes[i].dq_weights = dq[i] == BLOB_NONE ? NULL : array_at(r, dq[i], meshes[i].vertex_count);

    sinew_vertex_cache *caches = take(cursor, h->caches.count * sizeof(sinew_vertex_cache));
    const blob_cache *bc = array_at(r, h->caches.offset, h->caches.count);
    for (uint32_t i = 0; i < h->caches.count; i++) {
        uint64_t values = (uint64_t)bc[i].frame_count * meshes[bc[i].mesh].vertex_count * 3;
        caches[i] = (sinew_vertex_cache){bc[i].frame_count, array_at(r, bc[i].times, bc[i].frame_count),
                                         array_at(r, bc[i].positions, values)};
        meshes[bc[i].mesh].cache = &caches[i];
    }
}

static void fill_model(model_block *b, const reader *r, unsigned char *tables)
{
    const blob_header *h = r->header;
    sinew_model *m = &b->model;
    unsigned char *cursor = tables;
    m->source = string_at(r, h->source);
    m->format = string_at(r, h->format);

    m->node_count = h->node_names.count;
    const char **names = take(&cursor, m->node_count * sizeof(char *));
    const uint32_t *name_offsets = array_at(r, h->node_names.offset, m->node_count);
    for (uint32_t i = 0; i < m->node_count; i++)
        names[i] = string_at(r, name_offsets[i]);
    m->node_names = names;
    m->node_parents = array_at(r, h->node_parents.offset, m->node_count);
    m->node_rest = array_at(r, h->node_rest.offset, m->node_count);
    m->node_inherit = h->node_inherit.count ? array_at(r, h->node_inherit.offset, m->node_count) : NULL;

    m->warning_count = h->warnings.count;
    const char **warnings = take(&cursor, (m->warning_count + 1) * sizeof(char *));
    const uint32_t *warning_offsets = array_at(r, h->warnings.offset, m->warning_count);
    for (uint32_t i = 0; i < m->warning_count; i++)
        warnings[i] = string_at(r, warning_offsets[i]);
    if (h->version < BLOB_VERSION)
        warnings[m->warning_count++] = sinew_blob_old_version_warning;
    m->warnings = warnings;

    m->skin_count = h->skins.count;
    sinew_skin *skins = take(&cursor, m->skin_count * sizeof(sinew_skin));
    const blob_skin *bskins = array_at(r, h->skins.offset, m->skin_count);
    for (uint32_t i = 0; i < m->skin_count; i++) {
        skins[i].joint_count = bskins[i].joints.count;
        skins[i].joints = array_at(r, bskins[i].joints.offset, bskins[i].joints.count);
        skins[i].inverse_bind = array_at(r, bskins[i].inverse_bind.offset, bskins[i].joints.count);
        skins[i].blend = h->skin_blend.count ? ((const uint32_t *)array_at(r, h->skin_blend.offset, 1))[i] : 0;
    }
    m->skins = skins;

    m->mesh_count = h->meshes.count;
    sinew_mesh *meshes = take(&cursor, m->mesh_count * sizeof(sinew_mesh));
    const blob_mesh *bmeshes = array_at(r, h->meshes.offset, m->mesh_count);
    const uint32_t *tangents = array_at(r, h->mesh_tangents.offset, h->mesh_tangents.count); /* NULL: none */
    const uint8_t *flat = array_at(r, h->mesh_flat.offset, h->mesh_flat.count);
    const uint32_t *colors = array_at(r, h->mesh_colors.offset, h->mesh_colors.count);
    for (uint32_t i = 0; i < m->mesh_count; i++) {
        const blob_mesh *bm = &bmeshes[i];
        uint64_t k = (uint64_t)bm->vertex_count * bm->influence_count;
        meshes[i] = (sinew_mesh){
            .name = string_at(r, bm->name),
            .vertex_count = bm->vertex_count,
            .index_count = bm->index_count,
            .positions = array_at(r, bm->positions, bm->vertex_count),
            .normals = array_at(r, bm->normals, bm->vertex_count),
            .uvs = array_at(r, bm->uvs, bm->vertex_count),
            .tangents = tangents ? array_at(r, tangents[i], bm->vertex_count) : NULL,
            .indices = array_at(r, bm->indices, bm->index_count),
            .influence_count = bm->influence_count,
            .joints = array_at(r, bm->joints, k),
            .weights = array_at(r, bm->weights, k),
            .skin = bm->skin,
            .material = bm->material,
            .flat_normals = flat && flat[i],
            .colors = colors ? array_at(r, colors[i], bm->vertex_count) : NULL,
        };
    }
    m->meshes = meshes;
    fill_deformers(m, r, meshes, &cursor);

    m->material_count = h->materials.count;
    sinew_material *materials = take(&cursor, m->material_count * sizeof(sinew_material));
    const blob_material *bmats = array_at(r, h->materials.offset, m->material_count);
    const blob_pbr *pbr = array_at(r, h->materials_pbr.offset, h->materials_pbr.count); /* NULL: none */
    const blob_alpha *alpha = array_at(r, h->material_alpha.offset, h->material_alpha.count);
    for (uint32_t i = 0; i < m->material_count; i++) {
        materials[i] = (sinew_material){.name = string_at(r, bmats[i].name),
                                        .alpha_mode = alpha ? (sinew_alpha_mode)alpha[i].mode : SINEW_ALPHA_OPAQUE,
                                        .alpha_cutoff = alpha ? alpha[i].cutoff : 0.5f,
                                        .metallic = 0.0f,
                                        .roughness = 0.5f,
                                        .normal_scale = 1.0f,
                                        .occlusion_strength = 1.0f};
        memcpy(materials[i].base_color, bmats[i].base_color, sizeof materials[i].base_color);
        materials[i].maps[SINEW_MAP_BASE_COLOR] = texture_at(r, &bmats[i].base_color_map);
        if (!pbr)
            continue;
        const blob_pbr *p = &pbr[i];
        materials[i].metallic = p->metallic;
        materials[i].roughness = p->roughness;
        memcpy(materials[i].emissive, p->emissive, sizeof p->emissive);
        materials[i].normal_scale = p->normal_scale;
        materials[i].occlusion_strength = p->occlusion_strength;
        materials[i].metallic_roughness = p->flags & 1;
        for (int k = 1; k < SINEW_MAP_COUNT; k++)
            materials[i].maps[k] = texture_at(r, &p->maps[k - 1]);
    }
    m->materials = materials;

    m->clip_count = h->clips.count;
    sinew_clip *clips = take(&cursor, m->clip_count * sizeof(sinew_clip));
    const blob_clip *bclips = array_at(r, h->clips.offset, m->clip_count);
    for (uint32_t i = 0; i < m->clip_count; i++) {
        const blob_clip *bc = &bclips[i];
        clips[i] = (sinew_clip){
            .name = string_at(r, bc->name),
            .duration = bc->duration,
            .start = bc->start,
            .track_count = bc->tracks.count,
            .tracks = array_at(r, bc->tracks.offset, bc->tracks.count),
            .time_count = bc->times.count,
            .value_count = bc->values.count,
            .times = array_at(r, bc->times.offset, bc->times.count),
            .values = array_at(r, bc->values.offset, bc->values.count),
            .timeline = h->clip_timeline.count ? ((const float *)array_at(r, h->clip_timeline.offset, 1))[2 * i] : 0.0f,
            .frame_rate =
                h->clip_timeline.count ? ((const float *)array_at(r, h->clip_timeline.offset, 1))[2 * i + 1] : 0.0f,
        };
    }
    const blob_weight_track *btracks = array_at(r, h->weight_tracks.offset, h->weight_tracks.count);
    sinew_weight_track *tracks = take(&cursor, h->weight_tracks.count * sizeof(sinew_weight_track));
    for (uint32_t i = 0; i < h->weight_tracks.count; i++) {
        tracks[i] = (sinew_weight_track){btracks[i].channel, btracks[i].keys};
        sinew_clip *c = &clips[btracks[i].clip];
        if (c->weight_track_count++ == 0)
            c->weight_tracks = &tracks[i];
    }
    m->clips = clips;

    sinew_muscle_def *defs = take(&cursor, h->muscles.count * sizeof(sinew_muscle_def));
    const blob_muscle *bmuscles = array_at(r, h->muscles.offset, h->muscles.count);
    for (uint32_t i = 0; i < h->muscles.count; i++) {
        const blob_muscle *bm = &bmuscles[i];
        defs[i] = (sinew_muscle_def){
            .name = string_at(r, bm->name),
            .origin = {.joint = string_at(r, bm->origin_joint)},
            .insertion = {.joint = string_at(r, bm->insertion_joint)},
            .rest_length = bm->rest_length,
            .node_count = bm->node_count,
            .radii = array_at(r, bm->radii, bm->node_count),
            .coefficients = array_at(r, bm->coefficients, bm->node_count),
            .segments = bm->segments,
        };
        memcpy(defs[i].origin.offset, bm->origin_offset, sizeof bm->origin_offset);
        memcpy(defs[i].insertion.offset, bm->insertion_offset, sizeof bm->insertion_offset);
        memcpy(defs[i].color, bm->color, sizeof bm->color);
    }
    if (h->muscles.count) {
        b->muscles = (sinew_muscle_set){.source = m->source, .muscle_count = h->muscles.count, .muscles = defs};
        m->muscles = &b->muscles;
    }
}

/* from_blob and load: `file` is the .sinew path the bytes came from, or NULL. */
static sinew_result open_blob(const void *bytes, size_t size, const char *name, const char *file, bool adopt,
                              bool built, const sinew_allocator *allocator, sinew_model **out, sinew_error *error)
{
    *out = NULL;
    if (!name)
        name = "model data";
    if (allocator && (!allocator->alloc || !allocator->free))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "%s: allocator without alloc or free", name);
    sinew_allocator alloc = sinew_allocator_or_default(allocator);

    /* The header, the directory and the table sizes are checked on the caller's bytes
     * before their counts size any allocation; the copy has the same directory. */
    size_t head = (sizeof(model_block) + BLOB_ALIGN - 1) & ~(size_t)(BLOB_ALIGN - 1);
    blob_header header;
    reader early = {.bytes = bytes, .size = size, .name = name, .error = error};
    sinew_result result = check_header(&early, &header, !built);
    if (result)
        return result;
    size_t tables = tables_size(&header) + (file ? (strlen(file) + BLOB_ALIGN) & ~(size_t)(BLOB_ALIGN - 1) : 0);
    adopt = adopt && !allocator; /* the model's memory is the caller's allocator's: copied into it */
    size_t room = head + tables + (adopt ? 0 : size);
    unsigned char *block = alloc.alloc(room, alloc.user);
    if (!block)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu bytes", name, room);
    unsigned char *copy = adopt ? (unsigned char *)bytes : block + head + tables;
    if (!adopt)
        memcpy(copy, bytes, size);

    reader r = {.bytes = copy, .size = size, .name = name, .header = &header, .error = error};
    if ((result = check_nodes(&r)) || (result = check_skins(&r)) || (result = check_meshes(&r)) ||
        (result = check_clips(&r)) || (result = check_deformers(&r)) || (result = check_muscles(&r))) {
        alloc.free(block, alloc.user);
        return result;
    }
    model_block *b = (model_block *)block;
    memset(b, 0, sizeof *b);
    b->allocator = alloc;
    b->blob = copy;
    b->blob_size = size;
    b->owned = adopt ? copy : NULL;
    fill_model(b, &r, block + head);
    if (file) {
        char *path = (char *)block + head + tables_size(&header);
        strcpy(path, file);
        b->model.converted_from = b->model.source;
        b->model.source = path;
        b->muscles.source = path;
    }
    *out = &b->model;
    return SINEW_OK;
}

sinew_result sinew_model_from_blob(const void *bytes, size_t size, const char *name, const sinew_allocator *allocator,
                                   sinew_model **out, sinew_error *error)
{
    if (!out || (!bytes && size))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_model_from_blob: NULL argument");
    return open_blob(bytes, size, name, NULL, false, false, allocator, out, error);
}

sinew_result sinew_model_adopt_blob(void *bytes, size_t size, bool built, const char *name,
                                    const sinew_allocator *allocator, sinew_model **out, sinew_error *error)
{
    return open_blob(bytes, size, name, NULL, true, built, allocator, out, error);
}

sinew_result sinew_model_load(const char *path, const sinew_allocator *allocator, sinew_model **out, sinew_error *error)
{
    if (!path || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_model_load: NULL argument");
    *out = NULL;
    uint64_t file_size;
    int fd = sinew_open_regular(path, &file_size);
    if (fd < 0 && errno == EINVAL)
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot read: not a regular file", path);
    if (fd < 0)
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    size_t n = (size_t)file_size;
    /* A blob of a megabyte and more in 2 MB pages: the model keeps it (without an allocator), and
     * reading it and checking its checksum touch every page. */
    void *bytes = sinew_large_alloc(n, MODEL_PAGES_MIN);
    if (!bytes) {
        close(fd);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu bytes", path, n);
    }
    errno = 0;
    size_t got = sinew_read_fully(fd, bytes, n);
    bool failed = got < n && errno != 0;
    int why = errno;
    close(fd);
    sinew_result result = failed ? sinew_fail(error, SINEW_ERROR_IO, "%s: cannot read: %s", path, strerror(why))
                                 : open_blob(bytes, got, path, path, true, false, allocator, out, error);
    if (result != SINEW_OK || allocator) /* else the model keeps the bytes (adopted) */
        sinew_block_free(bytes);
    return result;
}

void sinew_model_blob(const sinew_model *model, const void **bytes, size_t *size)
{
    const model_block *b = (const model_block *)model;
    *bytes = b->blob;
    *size = b->blob_size;
}

void sinew_model_free(sinew_model *model)
{
    if (!model)
        return;
    model_block *b = (model_block *)model;
    void *owned = b->owned;
    b->allocator.free(b, b->allocator.user);
    sinew_block_free(owned);
}

int32_t sinew_model_find_node(const sinew_model *model, const char *name)
{
    for (uint32_t i = 0; i < model->node_count; i++)
        if (strcmp(model->node_names[i], name) == 0)
            return (int32_t)i;
    return -1;
}

int32_t sinew_model_find_joint(const sinew_model *model, const char *name)
{
    for (uint32_t i = 0; i < model->node_count; i++)
        if (strcmp(model->node_names[i], name) == 0 && sinew_model_node_is_joint(model, i))
            return (int32_t)i;
    return sinew_model_find_node(model, name);
}

int32_t sinew_model_find_clip(const sinew_model *model, const char *name)
{
    for (uint32_t i = 0; i < model->clip_count; i++)
        if (strcmp(model->clips[i].name, name) == 0)
            return (int32_t)i;
    return -1;
}

int32_t sinew_model_pick_clip(const sinew_model *model, const char *text)
{
    int32_t clip = sinew_model_find_clip(model, text);
    if (clip >= 0)
        return clip;
    char *end = NULL;
    long index = strtol(text, &end, 10);
    return end != text && *end == '\0' && index >= 0 && index < (long)model->clip_count ? (int32_t)index : -1;
}

bool sinew_model_node_is_joint(const sinew_model *model, uint32_t node)
{
    for (uint32_t s = 0; s < model->skin_count; s++)
        for (uint32_t j = 0; j < model->skins[s].joint_count; j++)
            if (model->skins[s].joints[j] == node)
                return true;
    return false;
}
