/* Inter-Quake Model (.iqm, version 2) files, read by sinew (Assimp 5.2.5 reads their meshes
 * but no joints, weights or animations, and refuses animation-only files).
 *
 * What a file holds (Lee Salzman's iqm.txt): a header of offsets and counts; a text block of
 * NUL-terminated names; meshes (a name, a material name that is the texture's file name, a
 * range of vertices and of triangles); vertex arrays (position, texture coordinate, normal,
 * tangent, blend indexes, blend weights, colour), each in one format for every vertex;
 * triangles as three vertex indices; joints (name, parent before child, translation, rotation
 * x y z w, scale, relative to the parent); poses, one per joint, each with 10 channels
 * (translation, rotation, scale) that are an offset plus, where the channel's mask bit is
 * set, the next unsigned short of the frame times a scale; animations (name, a range of
 * frames, frames a second, a loop flag).
 *
 * How sinew takes it: a root node, "<IQMRoot>", turns the file's Z-up space to Y-up (as
 * Assimp does); the joints are nodes below it; meshes are instanced at the root, skinned to
 * one skin of every joint (inverse bind matrices from the joints' rest transforms); texture
 * v is flipped (the file's images start at the top) and triangles are turned to
 * counter-clockwise. Each animation is a clip with a linear key a frame, a looping one with
 * its first frame again at the end; a channel that does not change is one key. A file of
 * poses without joints (an animation-only file, such as raylib's guyanim.iqm) gets nodes
 * named "pose N" in the poses' hierarchy: sinew_retarget() applies such clips joint by joint
 * to a model of the same hierarchy.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

#define IQM_MAGIC "INTERQUAKEMODEL"
#define IQM_HEADER_SIZE 124u

enum {
    H_VERSION,
    H_FILESIZE,
    H_FLAGS,
    H_NUM_TEXT,
    H_OFS_TEXT,
    H_NUM_MESHES,
    H_OFS_MESHES,
    H_NUM_VERTEXARRAYS,
    H_NUM_VERTEXES,
    H_OFS_VERTEXARRAYS,
    H_NUM_TRIANGLES,
    H_OFS_TRIANGLES,
    H_OFS_ADJACENCY,
    H_NUM_JOINTS,
    H_OFS_JOINTS,
    H_NUM_POSES,
    H_OFS_POSES,
    H_NUM_ANIMS,
    H_OFS_ANIMS,
    H_NUM_FRAMES,
    H_NUM_FRAMECHANNELS,
    H_OFS_FRAMES,
    H_COUNT = 27
};

enum { VA_POSITION, VA_TEXCOORD, VA_NORMAL, VA_TANGENT, VA_BLENDINDEXES, VA_BLENDWEIGHTS, VA_COLOR, VA_KNOWN };
enum { F_BYTE, F_UBYTE, F_SHORT, F_USHORT, F_INT, F_UINT, F_HALF, F_FLOAT, F_DOUBLE, F_COUNT };
static const uint32_t FORMAT_SIZE[F_COUNT] = {1, 1, 2, 2, 4, 4, 2, 4, 8};

#define JOINT_SIZE 48u /* name, parent, translate[3], rotate[4], scale[3] */
#define POSE_SIZE 88u  /* parent, mask, offset[10], scale[10] */
#define ANIM_SIZE 20u  /* name, first frame, frame count, frame rate, flags */
#define MESH_SIZE 24u  /* name, material, first vertex, vertex count, first triangle, triangle count */
#define ARRAY_SIZE 20u /* type, flags, format, size, offset */
#define MAX_INFLUENCES 16u

typedef struct vertex_array {
    uint32_t format, size, offset; /* size: components a vertex */
    bool present;
} vertex_array;

typedef struct iqm {
    const char *path;
    const unsigned char *b;
    size_t size;
    raw_model *m;
    sinew_error *error;
    uint32_t h[H_COUNT];
    vertex_array arrays[VA_KNOWN];
    uint32_t joint_count; /* nodes after the root: joints, or poses when there are none */
} iqm;

static uint32_t u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float f32(const unsigned char *p)
{
    uint32_t v = u32(p);
    float f;
    memcpy(&f, &v, sizeof f);
    return f;
}

static sinew_result oom(iqm *q)
{
    return sinew_fail(q->error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the IQM file", q->path);
}

bool iqm_sniff(const unsigned char *head, size_t size)
{
    return size >= sizeof IQM_MAGIC && memcmp(head, IQM_MAGIC, sizeof IQM_MAGIC) == 0;
}

/* A table of count elements of elem bytes at offset, inside the file. */
static sinew_result table(iqm *q, uint32_t offset, uint32_t count, uint32_t elem, const char *what)
{
    if (count == 0)
        return SINEW_OK;
    if (offset > q->size || (uint64_t)count * elem > q->size - offset)
        return sinew_fail(q->error, SINEW_ERROR_FORMAT,
                          "%s: the IQM %s (%u x %u bytes at offset %u) runs past the end of the file (%zu bytes)",
                          q->path, what, count, elem, offset, q->size);
    return SINEW_OK;
}

/* A name in the text block, or NULL (with the error set) when the offset is not one. */
static const char *text(iqm *q, uint32_t offset, const char *what, sinew_result *r)
{
    uint32_t n = q->h[H_NUM_TEXT];
    const char *base = (const char *)q->b + q->h[H_OFS_TEXT];
    if (offset < n && memchr(base + offset, 0, n - offset))
        return base + offset;
    *r = sinew_fail(q->error, SINEW_ERROR_FORMAT, "%s: the %s's name (text offset %u) is not in the IQM text block",
                    q->path, what, offset);
    return NULL;
}

static sinew_result read_header(iqm *q)
{
    if (q->size < IQM_HEADER_SIZE || !iqm_sniff(q->b, q->size))
        return sinew_fail(q->error, SINEW_ERROR_FORMAT, "%s: not an IQM file (no INTERQUAKEMODEL header)", q->path);
    for (int i = 0; i < H_COUNT; i++)
        q->h[i] = u32(q->b + 16 + 4 * i);
    if (q->h[H_VERSION] != 2)
        return sinew_fail(q->error, SINEW_ERROR_FORMAT, "%s: IQM version %u (sinew reads version 2)", q->path,
                          q->h[H_VERSION]);
    if (q->h[H_FILESIZE] != q->size)
        return sinew_fail(q->error, SINEW_ERROR_FORMAT,
                          "%s: the IQM header gives a file of %u bytes, the file has %zu (cut short or padded?)",
                          q->path, q->h[H_FILESIZE], q->size);
    sinew_result r = table(q, q->h[H_OFS_TEXT], q->h[H_NUM_TEXT], 1, "text block");
    if (!r && q->h[H_NUM_TEXT] && q->b[q->h[H_OFS_TEXT] + q->h[H_NUM_TEXT] - 1] != 0)
        r = sinew_fail(q->error, SINEW_ERROR_FORMAT, "%s: the IQM text block does not end with a NUL", q->path);
    if (!r)
        r = table(q, q->h[H_OFS_MESHES], q->h[H_NUM_MESHES], MESH_SIZE, "mesh table");
    if (!r)
        r = table(q, q->h[H_OFS_VERTEXARRAYS], q->h[H_NUM_VERTEXARRAYS], ARRAY_SIZE, "vertex array table");
    if (!r)
        r = table(q, q->h[H_OFS_TRIANGLES], q->h[H_NUM_TRIANGLES], 12, "triangle table");
    if (!r)
        r = table(q, q->h[H_OFS_JOINTS], q->h[H_NUM_JOINTS], JOINT_SIZE, "joint table");
    if (!r)
        r = table(q, q->h[H_OFS_POSES], q->h[H_NUM_POSES], POSE_SIZE, "pose table");
    if (!r)
        r = table(q, q->h[H_OFS_ANIMS], q->h[H_NUM_ANIMS], ANIM_SIZE, "animation table");
    if (!r && (uint64_t)q->h[H_NUM_FRAMES] * q->h[H_NUM_FRAMECHANNELS] > UINT32_MAX / 2)
        r = sinew_fail(q->error, SINEW_ERROR_FORMAT, "%s: %u IQM frames of %u channels is too many", q->path,
                       q->h[H_NUM_FRAMES], q->h[H_NUM_FRAMECHANNELS]);
    if (!r)
        r = table(q, q->h[H_OFS_FRAMES], q->h[H_NUM_FRAMES] * q->h[H_NUM_FRAMECHANNELS], 2, "frame data");
    if (r)
        return r;
    if (q->h[H_NUM_JOINTS] && q->h[H_NUM_POSES] && q->h[H_NUM_JOINTS] != q->h[H_NUM_POSES])
        return sinew_fail(q->error, SINEW_ERROR_FORMAT, "%s: %u IQM joints but %u poses (one a joint)", q->path,
                          q->h[H_NUM_JOINTS], q->h[H_NUM_POSES]);
    q->joint_count = q->h[H_NUM_JOINTS] ? q->h[H_NUM_JOINTS] : q->h[H_NUM_POSES];
    if (q->joint_count > 65535)
        return sinew_fail(q->error, SINEW_ERROR_FORMAT, "%s: %u IQM joints", q->path, q->joint_count);
    return SINEW_OK;
}

/* ---- the skeleton --------------------------------------------------------------------------- */

static const unsigned char *joint_at(const iqm *q, uint32_t j)
{
    return q->b + q->h[H_OFS_JOINTS] + (size_t)j * JOINT_SIZE;
}

static const unsigned char *pose_at(const iqm *q, uint32_t j)
{
    return q->b + q->h[H_OFS_POSES] + (size_t)j * POSE_SIZE;
}

static sinew_result build_nodes(iqm *q)
{
    raw_model *m = q->m;
    uint32_t n = 1 + q->joint_count;
    m->node_count = n;
    m->node_names = calloc(n, sizeof *m->node_names);
    m->node_parents = calloc(n, sizeof *m->node_parents);
    m->node_rest = calloc(n, sizeof *m->node_rest);
    if (!m->node_names || !m->node_parents || !m->node_rest || !(m->node_names[0] = raw_strdup("<IQMRoot>")))
        return oom(q);
    /* Z up to Y up: y' = z, z' = -y, a quarter turn about -X */
    m->node_parents[0] = -1;
    m->node_rest[0] = (sinew_transform){{0, 0, 0}, {-(float)M_SQRT1_2, 0, 0, (float)M_SQRT1_2}, {1, 1, 1}};
    sinew_result r = SINEW_OK;
    for (uint32_t j = 0; j < q->joint_count && !r; j++) {
        sinew_transform *rest = &m->node_rest[1 + j];
        int32_t parent;
        char name[32];
        const char *label = name;
        if (q->h[H_NUM_JOINTS]) {
            const unsigned char *p = joint_at(q, j);
            label = text(q, u32(p), "joint", &r);
            parent = (int32_t)u32(p + 4);
            for (int k = 0; k < 3; k++) {
                rest->translation[k] = f32(p + 8 + 4 * k);
                rest->scale[k] = f32(p + 36 + 4 * k);
            }
            for (int k = 0; k < 4; k++)
                rest->rotation[k] = f32(p + 20 + 4 * k);
        } else { /* poses only: the channels' offsets (the first frame's values of animated ones) */
            const unsigned char *p = pose_at(q, j);
            snprintf(name, sizeof name, "pose %u", j);
            parent = (int32_t)u32(p);
            *rest = (sinew_transform){{0, 0, 0}, {0, 0, 0, 1}, {1, 1, 1}};
            for (int c = 0; c < 10; c++) {
                float v = f32(p + 8 + 4 * c);
                if (c < 3)
                    rest->translation[c] = v;
                else if (c < 7)
                    rest->rotation[c - 3] = v;
                else
                    rest->scale[c - 7] = v;
            }
        }
        if (r)
            break;
        if (parent >= (int32_t)j || parent < -1)
            return sinew_fail(q->error, SINEW_ERROR_FORMAT,
                              "%s: IQM joint %u (\"%s\") has parent %d, not one before it", q->path, j, label, parent);
        bool finite = true;
        for (int k = 0; k < 4; k++)
            finite = finite && isfinite(rest->rotation[k]) &&
                     (k == 3 || (isfinite(rest->translation[k]) && isfinite(rest->scale[k])));
        if (!finite)
            return sinew_fail(q->error, SINEW_ERROR_FORMAT,
                              "%s: IQM joint %u (\"%s\") has a transform that is not finite", q->path, j, label);
        m->node_parents[1 + j] = parent + 1;
        if (!(m->node_names[1 + j] = raw_strdup(label)))
            return oom(q);
    }
    return r;
}

/* One skin of every joint, inverse binds from the joints' rest transforms (in the file's space:
 * the vertices are there, and the root's turn comes with the joints' world matrices). */
static sinew_result build_skin(iqm *q)
{
    raw_model *m = q->m;
    uint32_t n = q->joint_count;
    dmat *world = malloc(((size_t)n + 1) * sizeof *world);
    m->skins = calloc(1, sizeof *m->skins);
    if (!world || !m->skins) {
        free(world);
        return oom(q);
    }
    m->skin_count = 1;
    raw_skin *skin = &m->skins[0];
    skin->joints = calloc(n, sizeof *skin->joints);
    skin->inverse_bind = calloc(n, sizeof *skin->inverse_bind);
    if (!skin->joints || !skin->inverse_bind) {
        free(world);
        return oom(q);
    }
    skin->joint_count = n;
    for (uint32_t j = 0; j < n; j++) {
        const sinew_transform *t = &m->node_rest[1 + j];
        double tt[3], tq[4], ts[3];
        for (int k = 0; k < 4; k++) {
            tq[k] = t->rotation[k];
            if (k < 3)
                tt[k] = t->translation[k], ts[k] = t->scale[k];
        }
        dmat local = dmat_from_trs(tt, tq, ts);
        int32_t parent = m->node_parents[1 + j] - 1;
        world[j] = parent >= 0 ? dmat_mul(&world[parent], &local) : local;
        dmat inverse = dmat_inverse_affine(&world[j]);
        dmat_to_float(&inverse, &skin->inverse_bind[j]);
        skin->joints[j] = 1 + j;
    }
    free(world);
    return SINEW_OK;
}

/* ---- meshes --------------------------------------------------------------------------------- */

static double component(const unsigned char *p, uint32_t format)
{
    switch (format) {
    case F_BYTE:
        return (int8_t)p[0];
    case F_UBYTE:
        return p[0];
    case F_SHORT:
        return (int16_t)(p[0] | p[1] << 8);
    case F_USHORT:
        return (uint16_t)(p[0] | p[1] << 8);
    case F_INT:
        return (int32_t)u32(p);
    case F_UINT:
        return u32(p);
    case F_FLOAT:
        return f32(p);
    case F_DOUBLE: {
        uint64_t v = (uint64_t)u32(p) | (uint64_t)u32(p + 4) << 32;
        double d;
        memcpy(&d, &v, sizeof d);
        return d;
    }
    default: { /* half */
        uint32_t h = (uint32_t)(p[0] | p[1] << 8), e = (h >> 10) & 31, f = h & 1023;
        double v = e == 0 ? ldexp(f, -24) : e == 31 ? (f ? NAN : INFINITY) : ldexp(f + 1024, (int)e - 25);
        return h & 0x8000 ? -v : v;
    }
    }
}

/* Component c of vertex v of an array (0 past its size). */
static double array_value(const iqm *q, const vertex_array *a, uint32_t v, uint32_t c)
{
    if (c >= a->size)
        return 0.0;
    return component(q->b + a->offset + ((size_t)v * a->size + c) * FORMAT_SIZE[a->format], a->format);
}

static sinew_result read_arrays(iqm *q)
{
    for (uint32_t i = 0; i < q->h[H_NUM_VERTEXARRAYS]; i++) {
        const unsigned char *p = q->b + q->h[H_OFS_VERTEXARRAYS] + (size_t)i * ARRAY_SIZE;
        uint32_t type = u32(p), format = u32(p + 8), size = u32(p + 12), offset = u32(p + 16);
        if (type >= VA_KNOWN || type == VA_TANGENT)
            continue; /* custom arrays; tangents are made again (the flipped v turns their handedness) */
        static const char *const names[VA_KNOWN] = {"position",    "texture coordinate", "normal", "tangent",
                                                    "blend index", "blend weight",       "colour"};
        if (format >= F_COUNT || size == 0 || size > MAX_INFLUENCES)
            return sinew_fail(q->error, SINEW_ERROR_FORMAT, "%s: the IQM %s array has format %u and %u components",
                              q->path, names[type], format, size);
        char what[64];
        snprintf(what, sizeof what, "%s array", names[type]);
        sinew_result r = table(q, offset, q->h[H_NUM_VERTEXES], size * FORMAT_SIZE[format], what);
        if (r)
            return r;
        q->arrays[type] = (vertex_array){format, size, offset, true};
    }
    if (q->h[H_NUM_MESHES] && !q->arrays[VA_POSITION].present)
        return sinew_fail(q->error, SINEW_ERROR_FORMAT, "%s: IQM meshes without a position array", q->path);
    return SINEW_OK;
}

static sinew_result build_mesh(iqm *q, uint32_t index, bool skinned)
{
    raw_model *m = q->m;
    const unsigned char *p = q->b + q->h[H_OFS_MESHES] + (size_t)index * MESH_SIZE;
    sinew_result r = SINEW_OK;
    const char *name = text(q, u32(p), "mesh", &r), *material = r ? NULL : text(q, u32(p + 4), "mesh material", &r);
    if (r)
        return r;
    uint32_t first = u32(p + 8), count = u32(p + 12), first_tri = u32(p + 16), tris = u32(p + 20);
    if (first > q->h[H_NUM_VERTEXES] || count > q->h[H_NUM_VERTEXES] - first || first_tri > q->h[H_NUM_TRIANGLES] ||
        tris > q->h[H_NUM_TRIANGLES] - first_tri)
        return sinew_fail(q->error, SINEW_ERROR_FORMAT,
                          "%s: IQM mesh \"%s\" has vertices [%u, +%u) and triangles [%u, +%u) outside the file's %u "
                          "and %u",
                          q->path, name, first, count, first_tri, tris, q->h[H_NUM_VERTEXES], q->h[H_NUM_TRIANGLES]);
    raw_mesh *mesh = &m->meshes[m->mesh_count++];
    *mesh = (raw_mesh){.skin = -1, .material = (int32_t)index, .vertex_count = count, .index_count = tris * 3};
    mesh->name = raw_strdup(name);
    mesh->positions = malloc((size_t)count * 3 * sizeof(float) + 1);
    mesh->indices = malloc((size_t)tris * 3 * sizeof(uint32_t) + 1);
    if (!mesh->name || !mesh->positions || !mesh->indices)
        return oom(q);
    const vertex_array *pos = &q->arrays[VA_POSITION], *uv = &q->arrays[VA_TEXCOORD], *nor = &q->arrays[VA_NORMAL];
    const vertex_array *bi = &q->arrays[VA_BLENDINDEXES], *bw = &q->arrays[VA_BLENDWEIGHTS];
    if (nor->present && !(mesh->normals = malloc((size_t)count * 3 * sizeof(float) + 1)))
        return oom(q);
    if (uv->present && !(mesh->uvs = malloc((size_t)count * 2 * sizeof(float) + 1)))
        return oom(q);
    const vertex_array *color = &q->arrays[VA_COLOR];
    if (color->present && !(mesh->colors = malloc((size_t)count * 4 * sizeof(float) + 1)))
        return oom(q);
    /* integer colours are normalised (IQM's usual ubyte4: 0..255) */
    double full = color->format == F_UBYTE    ? 255.0
                  : color->format == F_BYTE   ? 127.0
                  : color->format == F_USHORT ? 65535.0
                  : color->format == F_SHORT  ? 32767.0
                  : color->format == F_UINT   ? 4294967295.0
                  : color->format == F_INT    ? 2147483647.0
                                              : 1.0;
    for (uint32_t v = 0; mesh->colors && v < count; v++)
        for (uint32_t c = 0; c < 4; c++)
            mesh->colors[v * 4 + c] = c < color->size
                                          ? (float)fmin(fmax(array_value(q, color, first + v, c) / full, 0.0), 1.0)
                                      : c == 3 ? 1.0f
                                               : 0.0f;
    if (mesh->colors)
        raw_colors_from_srgb(mesh->colors, 4, count, mesh->colors);
    for (uint32_t v = 0; v < count; v++)
        for (uint32_t c = 0; c < 3; c++) {
            mesh->positions[v * 3 + c] = (float)array_value(q, pos, first + v, c);
            if (mesh->normals)
                mesh->normals[v * 3 + c] = (float)array_value(q, nor, first + v, c);
            if (mesh->uvs && c < 2) /* the file's images start at the top; sinew's v goes up */
                mesh->uvs[v * 2 + c] =
                    (float)(c ? 1.0 - array_value(q, uv, first + v, c) : array_value(q, uv, first + v, c));
        }
    for (uint32_t v = 0; v < count; v++) {
        bool finite = true;
        for (uint32_t c = 0; c < 3; c++)
            finite = finite && isfinite(mesh->positions[v * 3 + c]) &&
                     (!mesh->normals || isfinite(mesh->normals[v * 3 + c])) &&
                     (!mesh->uvs || c == 2 || isfinite(mesh->uvs[v * 2 + c]));
        if (!finite)
            return sinew_fail(q->error, SINEW_ERROR_DATA,
                              "%s: IQM mesh \"%s\": vertex %u has a position, normal or texture coordinate that is not "
                              "finite",
                              q->path, name, first + v);
    }
    for (uint32_t t = 0; t < tris; t++) {
        const unsigned char *tri = q->b + q->h[H_OFS_TRIANGLES] + ((size_t)first_tri + t) * 12;
        static const int order[3] = {0, 2, 1}; /* clockwise in the file */
        for (int k = 0; k < 3; k++) {
            uint32_t vertex = u32(tri + 4 * order[k]);
            if (vertex < first || vertex - first >= count)
                return sinew_fail(q->error, SINEW_ERROR_FORMAT,
                                  "%s: IQM mesh \"%s\": triangle %u uses vertex %u, outside the mesh's [%u, %u)",
                                  q->path, name, first_tri + t, vertex, first, first + count);
            mesh->indices[t * 3 + (uint32_t)k] = vertex - first;
        }
    }
    if (skinned && bi->present && bw->present) {
        uint32_t slots = bi->size < bw->size ? bi->size : bw->size;
        bool normalised = bw->format == F_UBYTE || bw->format == F_USHORT;
        double unit = bw->format == F_UBYTE ? 255.0 : 65535.0;
        mesh->skin = 0;
        mesh->influence_count = slots;
        mesh->joints = malloc((size_t)count * slots * sizeof *mesh->joints + 1);
        mesh->weights = malloc((size_t)count * slots * sizeof *mesh->weights + 1);
        if (!mesh->joints || !mesh->weights)
            return oom(q);
        uint32_t bad = 0;
        for (uint32_t v = 0; v < count; v++)
            for (uint32_t s = 0; s < slots; s++) {
                double j = array_value(q, bi, first + v, s), w = array_value(q, bw, first + v, s);
                w = normalised ? w / unit : w;
                bool ok = j >= 0.0 && j < (double)q->joint_count && isfinite(w) && w >= 0.0;
                bad += !ok && w > 0.0;
                mesh->joints[v * slots + s] = ok ? (uint32_t)j : UINT32_MAX;
                mesh->weights[v * slots + s] = ok ? (float)w : 0.0f;
            }
        if (bad && !raw_model_warn(m, "%s: mesh \"%s\": %u influences name joints the file does not have (left out)",
                                   q->path, name, bad))
            return oom(q);
    }
    m->instances[m->instance_count++] = (sinew_instance){m->mesh_count - 1, 0, 0};
    raw_material *mat = &m->materials[index];
    *mat = (raw_material){.base_color = {1, 1, 1, 1}, .roughness = 1.0f, .normal_scale = 1, .occlusion_strength = 1};
    if (!(mat->name = raw_strdup(material)))
        return oom(q);
    if (*material && !import_material_texture(m, q->path, material, material, &mat->maps[SINEW_MAP_BASE_COLOR].path))
        return oom(q);
    return SINEW_OK;
}

static sinew_result build_meshes(iqm *q)
{
    raw_model *m = q->m;
    uint32_t n = q->h[H_NUM_MESHES];
    if (!n)
        return SINEW_OK;
    m->meshes = calloc(n, sizeof *m->meshes);
    m->instances = calloc(n, sizeof *m->instances);
    m->materials = calloc(n, sizeof *m->materials);
    if (!m->meshes || !m->instances || !m->materials)
        return oom(q);
    m->material_count = n;
    bool skinned = q->joint_count > 0 && q->arrays[VA_BLENDINDEXES].present && q->arrays[VA_BLENDWEIGHTS].present;
    sinew_result r = skinned ? build_skin(q) : SINEW_OK;
    for (uint32_t i = 0; i < n && !r; i++)
        r = build_mesh(q, i, skinned);
    return r;
}

/* ---- animations ----------------------------------------------------------------------------- */

/* Where each pose's animated channels are in a frame: slot[j * 10 + c], or -1 for a channel
 * that keeps its offset. Values are read from the frames as they are needed (a file may
 * claim billions of frames of nothing). */
static sinew_result frame_slots(iqm *q, int32_t **out)
{
    uint32_t poses = q->h[H_NUM_POSES];
    *out = NULL;
    int32_t *slot = malloc(((size_t)poses * 10 + 1) * sizeof *slot);
    if (!slot)
        return oom(q);
    int32_t used = 0;
    for (uint32_t j = 0; j < poses; j++) {
        uint32_t mask = u32(pose_at(q, j) + 4);
        for (uint32_t c = 0; c < 10; c++)
            slot[j * 10 + c] = (mask >> c) & 1u ? used++ : -1;
    }
    if ((uint32_t)used != q->h[H_NUM_FRAMECHANNELS]) {
        free(slot);
        return sinew_fail(q->error, SINEW_ERROR_FORMAT,
                          "%s: the IQM poses animate %d channels, the frames hold %u a frame", q->path, used,
                          q->h[H_NUM_FRAMECHANNELS]);
    }
    *out = slot;
    return SINEW_OK;
}

/* Pose j's channel c at frame f: its offset, plus the frame's value times its scale when animated. */
static float channel_value(const iqm *q, const int32_t *slot, uint32_t f, uint32_t j, uint32_t c)
{
    const unsigned char *p = pose_at(q, j);
    float value = f32(p + 8 + 4 * c);
    int32_t s = slot[j * 10 + c];
    if (s >= 0) {
        const unsigned char *v = q->b + q->h[H_OFS_FRAMES] + ((size_t)f * q->h[H_NUM_FRAMECHANNELS] + (uint32_t)s) * 2;
        value += (float)(v[0] | v[1] << 8) * f32(p + 48 + 4 * c);
    }
    return value;
}

static sinew_result build_clip(iqm *q, uint32_t index, const int32_t *slot, raw_clip *clip)
{
    const unsigned char *p = q->b + q->h[H_OFS_ANIMS] + (size_t)index * ANIM_SIZE;
    sinew_result r = SINEW_OK;
    const char *name = text(q, u32(p), "animation", &r);
    if (r)
        return r;
    uint32_t first = u32(p + 4), frames = u32(p + 8), flags = u32(p + 16);
    float rate = f32(p + 12);
    if (first > q->h[H_NUM_FRAMES] || frames > q->h[H_NUM_FRAMES] - first)
        return sinew_fail(q->error, SINEW_ERROR_FORMAT, "%s: IQM animation \"%s\" has frames [%u, +%u), the file %u",
                          q->path, name, first, frames, q->h[H_NUM_FRAMES]);
    if (!(rate >= 1e-3f) || !isfinite(rate)) { /* none, or so few that the times overflow */
        if (!raw_model_warn(q->m, "%s: IQM animation \"%s\" gives %g frames a second: played at 30", q->path, name,
                            (double)rate))
            return oom(q);
        rate = 30.0f;
    }
    bool loop = flags & 1u;
    uint32_t keys = frames + (loop && frames > 1);
    const uint32_t poses = q->h[H_NUM_POSES], joints = q->joint_count;
    clip->name = raw_strdup(name);
    clip->duration = frames ? (float)(keys - 1) / rate : 0.0f;
    clip->tracks = calloc(joints ? joints : 1, sizeof *clip->tracks);
    if (!clip->name || !clip->tracks)
        return oom(q);
    clip->track_count = frames && poses ? joints : 0;
    for (uint32_t j = 0; j < clip->track_count; j++) {
        raw_track *track = &clip->tracks[j];
        track->node = 1 + j;
        uint32_t mask = u32(pose_at(q, j) + 4);
        static const uint32_t kinds[3] = {SINEW_CHANNEL_TRANSLATION, SINEW_CHANNEL_ROTATION, SINEW_CHANNEL_SCALE};
        static const uint32_t firsts[3] = {0, 3, 7}, widths[3] = {3, 4, 3};
        for (int k = 0; k < 3; k++) {
            uint32_t bits = ((1u << widths[k]) - 1u) << firsts[k];
            uint32_t n = (mask & bits) ? keys : 1; /* a channel that does not change: one key */
            raw_channel *ch = &track->channels[kinds[k]];
            *ch = (raw_channel){.interp = SINEW_INTERP_LINEAR, .count = n};
            ch->times = malloc(n * sizeof *ch->times);
            ch->values = malloc((size_t)n * widths[k] * sizeof *ch->values);
            if (!ch->times || !ch->values)
                return oom(q);
            for (uint32_t key = 0; key < n; key++) {
                uint32_t f = first + (key < frames ? key : 0); /* a loop's last key is its first frame */
                ch->times[key] = (float)key / rate;
                for (uint32_t c = 0; c < widths[k]; c++)
                    ch->values[key * widths[k] + c] = channel_value(q, slot, f, j, firsts[k] + c);
            }
        }
    }
    return SINEW_OK;
}

static sinew_result build_clips(iqm *q)
{
    raw_model *m = q->m;
    uint32_t n = q->h[H_NUM_ANIMS];
    if (!n)
        return SINEW_OK;
    if (q->h[H_NUM_POSES] != q->joint_count)
        return sinew_fail(q->error, SINEW_ERROR_FORMAT, "%s: IQM animations with %u poses for %u joints", q->path,
                          q->h[H_NUM_POSES], q->joint_count);
    int32_t *slot;
    sinew_result r = frame_slots(q, &slot);
    if (r)
        return r;
    if (!(m->clips = calloc(n, sizeof *m->clips))) {
        free(slot);
        return oom(q);
    }
    for (uint32_t i = 0; i < n && !r; i++) {
        r = build_clip(q, i, slot, &m->clips[i]);
        m->clip_count = i + 1;
    }
    free(slot);
    return r;
}

sinew_result raw_model_from_iqm(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                sinew_error *error)
{
    memset(model, 0, sizeof *model);
    iqm q = {.path = path, .b = bytes, .size = size, .m = model, .error = error};
    model->source = raw_strdup(path);
    model->format = raw_strdup("iqm");
    sinew_result r = !model->source || !model->format ? oom(&q) : read_header(&q);
    if (!r)
        r = build_nodes(&q);
    if (!r)
        r = read_arrays(&q);
    if (!r)
        r = build_meshes(&q);
    if (!r)
        r = build_clips(&q);
    /* joints no mesh is bound to: a skeleton all the same (the root turns Z up to Y up) */
    if (!r && model->skin_count == 0 && q.joint_count && !raw_model_joints_from(model, 1))
        r = oom(&q);
    if (r)
        raw_model_free(model);
    return r;
}
