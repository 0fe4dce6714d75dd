/* The renderer: uploads a model once, draws a pose each frame.
 *
 * Index: memory layout and creation (meshes, textures, palette texture buffer, overlay
 * buffers) - per-frame palette and CPU skinning - mesh passes (surface, wireframe,
 * normals) - overlay passes (grid, skeleton, names) - bounds.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cglm/cglm.h>
#include <stb_image.h>

#include "internal.h"
#include "sinew/anim.h"
#include "sinew/morph.h"

#define WARNING_SIZE 320
#define ALIGN16(x) (((x) + 15) & ~(size_t)15)

enum {
    BUF_POSITION,
    BUF_NORMAL,
    BUF_UV,
    BUF_TANGENT,
    BUF_JOINTS0,
    BUF_JOINTS1,
    BUF_WEIGHTS0,
    BUF_WEIGHTS1,
    BUF_STREAM,
    BUF_DQ,
    BUF_MORPH,
    BUF_COLOR,
    BUF_COUNT
};

/* Targets with weight one GPU draw takes (the shader's uniform arrays); a mesh with more
 * at once is morphed on the CPU that frame. */
#define GPU_MORPHS 16
/* The largest buffer of morph offsets put on the GPU (bytes); larger meshes morph on the CPU. */
#define GPU_MORPH_BYTES ((size_t)256 << 20)

/* CPU-skinned vertices as streamed: position, normal, tangent (xyz, handedness). */
#define STREAM_FLOATS 10
#define STREAM_STRIDE (STREAM_FLOATS * 4)

typedef struct render_mesh {
    GLuint vao_static; /* rest vertices: rigid meshes and GPU skinning */
    GLuint vao_stream; /* CPU-skinned positions, normals and tangents from BUF_STREAM */
    GLuint buffers[BUF_COUNT];
    GLuint indices;
    int influence_sets; /* 0 rigid, 1 for up to 4 influences, 2 for up to 8 */
    /* crowds' levels of detail (made at the first crowd drawn with them): their triangles in
     * `indices` (CPU skinning), and levels 1.. on their own vertices (GPU skinning), or NULL */
    render_lod lod;
    struct render_mesh *lod_meshes;
    bool lod_built;
    uint64_t streamed;          /* the frame whose CPU-skinned vertices BUF_STREAM holds (0: none) */
    uint32_t stream_room;       /* characters' vertices BUF_STREAM has room for (a crowd's batch) */
    uint32_t streamed_instance; /* and the instance they are of (instances' weights differ) */
    GLuint morph_texture;       /* the offsets of BUF_MORPH as a buffer texture, 0 when they stay on the CPU */
    int morph_texels;           /* texels a vertex of a target: 1 (position), 2 (and normal) */
} render_mesh;

typedef struct mesh_uniforms {
    GLint model, view_proj, gpu_sets, dq_mode, dq_offset, palette_offset, instance_stride, rigid_record, instance_base,
        palette, morph, morph_count, morph_vertices, morph_texels, morph_target, morph_weight, heat_joint, heat_rigid,
        gouraud, key_dir, fill_dir, eye, base_color, use_texture, texture, mode, heat, override, normal_length,
        metallic, roughness, emissive, normal_scale, occlusion_strength, maps, map_mr, map_normal, map_occlusion,
        map_emissive, flat, vertex_colors, alpha_cutoff, alpha_coverage;
} mesh_uniforms;

struct sinew_renderer {
    const sinew_model *model;
    sinew_allocator allocator;
    render_programs programs;
    render_effects fx;                        /* environment, shadow map, depth pre-pass */
    mesh_uniforms mesh_u, normals_u, depth_u; /* mesh_u: of the mesh program in use (programs.mesh) */
    mesh_uniforms variant_u[RENDER_MESH_VARIANTS];
    GLint overlay_matrix, overlay_point_size, overlay_round;
    render_mesh *meshes;
    GLuint (*textures)[SINEW_MAP_COUNT]; /* a material's maps, 0 when it has none or it could not be read */
    uint32_t *skin_offsets;              /* first palette matrix of each skin */
    bool *skin_on_gpu;                   /* false: this skin is too big for the GPU path */
    uint32_t total_joints;
    sinew_mat4 *palettes;        /* total_joints matrices */
    sinew_dq_joint *dq_palettes; /* the same as dual-quaternion joints, when a skin needs them */
    uint8_t *skin_mode;          /* each skin's sinew_skin_method in the last frame drawn */
    bool any_dq;                 /* some skin needs dual-quaternion joints */
    float *stream;               /* largest mesh's vertex count * STREAM_FLOATS */
    float *morphed;              /* largest mesh's vertex count * 10: morphed positions, normals, tangents */
    float *target_weights;       /* the most targets a mesh has */
    const float *weights;        /* the frame's morph channel weights (NULL: the defaults) */
    float cache_time;            /* and where vertex caches are read */
    bool no_cache;
    bool *skeleton_nodes; /* node_count flags */
    overlay_list overlay; /* world-space geometry, then text quads */
    GLuint palette_buffer, palette_texture;
    /* a crowd: each character's palettes (total_joints records) then the world matrices of the
     * nodes its placed meshes hang from, in the order of their level of detail
     * (crowd_slot[character]: its place) */
    sinew_mat4 *crowd_records;
    uint32_t *crowd_place; /* instance_count: a placed instance's node record after the palettes */
    uint32_t *crowd_nodes; /* node_count: those nodes, crowd_node_count of them */
    uint32_t crowd_node_count;
    float *crowd_stream;      /* a CPU-skinned crowd's vertices: a mesh's for each of crowd_stream_threads */
    size_t crowd_stream_room; /* floats a thread's part holds */
    uint32_t crowd_stream_threads;
    uint32_t *crowd_slot;
    uint8_t *crowd_level;
    uint32_t crowd_capacity;  /* characters crowd_records holds */
    uint32_t crowd_center;    /* the node whose position stands for a character's (levels of detail) */
    float crowd_radius;       /* and the radius of the model's rest bounds; < 0: not yet found */
    uint32_t crowd_triangles; /* of every mesh instance */
    float crowd_far_error;    /* the largest far_error of the instances' meshes (levels of detail) */
    GLuint crowd_buffer, crowd_texture;
    uint32_t max_buffer_texels; /* GL_MAX_TEXTURE_BUFFER_SIZE */
    GLuint muscle_vao, muscle_vertices, muscle_indices;
    uint32_t muscle_vertex_capacity, muscle_index_capacity;
    float *muscle_scratch; /* position + normal a vertex */
    uint32_t *muscle_index_scratch;
    GLuint overlay_vao, overlay_buffer, quad_indices;
    char (*warnings)[WARNING_SIZE];
    uint32_t warning_count, warning_capacity;
    bool lod_warned; /* the warning that crowds are drawn without levels of detail was given */
    uint64_t frame;  /* counts draws, so a mesh is skinned on the CPU once a frame */
    char gl_name[256];
};

static const float IDENTITY[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

static void *default_alloc(size_t size, void *user)
{
    (void)user;
    return aligned_alloc(16, ALIGN16(size));
}

static void default_free(void *ptr, void *user)
{
    (void)user;
    free(ptr);
}

sinew_render_options sinew_render_options_default(void)
{
    return (sinew_render_options){0};
}

void sinew_render_options_background(const sinew_render_options *o, float rgb[3])
{
    static const float GREY[3] = {0.16f, 0.17f, 0.19f};
    memcpy(rgb, o && o->background_set ? o->background : GREY, 3 * sizeof *rgb);
}

static void warn(sinew_renderer *r, const char *format, ...) __attribute__((format(printf, 2, 3)));
static void warn(sinew_renderer *r, const char *format, ...)
{
    if (r->warning_count >= r->warning_capacity)
        return;
    va_list args;
    va_start(args, format);
    vsnprintf(r->warnings[r->warning_count++], WARNING_SIZE, format, args);
    va_end(args);
}

/* Sizes every CPU-side array once, so the whole renderer is one allocation. */
typedef struct layout {
    size_t meshes, textures, skin_offsets, skin_on_gpu, skin_mode, palettes, dq_palettes, stream, morphed,
        target_weights, skeleton, overlay, warnings, muscle, muscle_index, crowd_place, crowd_nodes, total;
} layout;

static layout plan_layout(const sinew_model *m, uint32_t total_joints, uint32_t max_vertices, uint32_t max_targets,
                          uint32_t warnings, uint32_t muscle_vertices, uint32_t muscle_indices)
{
    layout l;
    size_t at = ALIGN16(sizeof(sinew_renderer));
#define PLACE(field, bytes)                                                                                            \
    l.field = at;                                                                                                      \
    at += ALIGN16(bytes)
    PLACE(meshes, (size_t)m->mesh_count * sizeof(render_mesh));
    PLACE(textures, (size_t)m->material_count * SINEW_MAP_COUNT * sizeof(GLuint));
    PLACE(skin_offsets, (size_t)m->skin_count * sizeof(uint32_t));
    PLACE(skin_on_gpu, (size_t)m->skin_count * sizeof(bool));
    PLACE(skin_mode, (size_t)m->skin_count);
    PLACE(palettes, (size_t)total_joints * sizeof(sinew_mat4));
    PLACE(dq_palettes, (size_t)total_joints * sizeof(sinew_dq_joint));
    PLACE(stream, (size_t)max_vertices * STREAM_FLOATS * sizeof(float));
    PLACE(morphed, (size_t)max_vertices * 10 * sizeof(float));
    PLACE(target_weights, (size_t)max_targets * sizeof(float));
    PLACE(skeleton, (size_t)m->node_count * sizeof(bool));
    PLACE(overlay, ((size_t)overlay_capacity(m->node_count) + OVERLAY_TEXT_VERTICES) * sizeof(overlay_vertex));
    PLACE(warnings, (size_t)warnings * WARNING_SIZE);
    PLACE(muscle, (size_t)muscle_vertices * 6 * sizeof(float));
    PLACE(muscle_index, (size_t)muscle_indices * sizeof(uint32_t));
    PLACE(crowd_place, (size_t)m->instance_count * sizeof(uint32_t));
    PLACE(crowd_nodes, (size_t)m->node_count * sizeof(uint32_t));
#undef PLACE
    l.total = at;
    return l;
}

static GLuint make_buffer(GLenum target, size_t bytes, const void *data, GLenum usage)
{
    GLuint b = 0;
    glGenBuffers(1, &b);
    glBindBuffer(target, b);
    glBufferData(target, (GLsizeiptr)bytes, data, usage);
    return b;
}

static void float_attribute(GLuint location, GLuint buffer, int size, GLsizei stride, size_t offset)
{
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glEnableVertexAttribArray(location);
    glVertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, stride, (const void *)offset);
}

/* Joints and weights of a mesh spread over `sets` groups of four, zero-padded, so the
 * shader always reads uvec4/vec4 pairs whatever the file's influence count. */
static void upload_influences(render_mesh *rm, const sinew_mesh *mesh, int sets, void *scratch)
{
    uint32_t n = mesh->vertex_count, k = mesh->influence_count;
    float *weights = scratch;                                 /* 16 bytes a vertex */
    uint16_t *joints = (uint16_t *)(weights + 4 * (size_t)n); /* then 8 bytes a vertex */
    for (int set = 0; set < sets; set++) {
        for (uint32_t v = 0; v < n; v++)
            for (uint32_t c = 0; c < 4; c++) {
                uint32_t src = (uint32_t)set * 4 + c;
                bool used = src < k;
                joints[v * 4 + c] = used ? mesh->joints[(size_t)v * k + src] : 0;
                weights[v * 4 + c] = used ? mesh->weights[(size_t)v * k + src] : 0.0f;
            }
        rm->buffers[BUF_JOINTS0 + set] = make_buffer(GL_ARRAY_BUFFER, (size_t)n * 8, joints, GL_STATIC_DRAW);
        rm->buffers[BUF_WEIGHTS0 + set] = make_buffer(GL_ARRAY_BUFFER, (size_t)n * 16, weights, GL_STATIC_DRAW);
    }
}

/* Binds the attributes both VAOs share: UVs, joints, weights (constant when absent). */
static void bind_shared_attributes(const render_mesh *rm)
{
    if (rm->buffers[BUF_UV])
        float_attribute(2, rm->buffers[BUF_UV], 2, 0, 0);
    else
        glVertexAttrib2f(2, 0.0f, 0.0f);
    if (!rm->buffers[BUF_TANGENT])
        glVertexAttrib4f(7, 0.0f, 0.0f, 0.0f, 0.0f);
    if (rm->buffers[BUF_DQ])
        float_attribute(8, rm->buffers[BUF_DQ], 1, 0, 0);
    else
        glVertexAttrib1f(8, 0.0f);
    if (rm->buffers[BUF_COLOR])
        float_attribute(9, rm->buffers[BUF_COLOR], 4, 0, 0);
    else
        glVertexAttrib4f(9, 1.0f, 1.0f, 1.0f, 1.0f);
    for (int set = 0; set < 2; set++) {
        if (set < rm->influence_sets) {
            glBindBuffer(GL_ARRAY_BUFFER, rm->buffers[BUF_JOINTS0 + set]);
            glEnableVertexAttribArray(3 + set);
            glVertexAttribIPointer(3 + set, 4, GL_UNSIGNED_SHORT, 0, NULL);
            float_attribute(5 + set, rm->buffers[BUF_WEIGHTS0 + set], 4, 0, 0);
        } else {
            glVertexAttribI4ui(3 + set, 0, 0, 0, 0);
            glVertexAttrib4f(5 + set, 0.0f, 0.0f, 0.0f, 0.0f);
        }
    }
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, rm->indices);
}

/* A mesh's morph targets for the GPU: every target's offsets for every vertex (0 where it moves
 * none), the normal's beside the position's when some target has them; none when they would
 * take more than GPU_MORPH_BYTES or the buffer texture's limit (the CPU morphs them then). */
static void upload_morphs(render_mesh *rm, const sinew_mesh *mesh, uint32_t max_texels)
{
    if (mesh->target_count == 0 || mesh->vertex_count == 0)
        return;
    int texels = 1;
    for (uint32_t t = 0; t < mesh->target_count; t++)
        if (mesh->targets[t].normals)
            texels = 2;
    size_t count = (size_t)mesh->target_count * mesh->vertex_count * (size_t)texels;
    if (count * 16 > GPU_MORPH_BYTES || count > max_texels)
        return;
    float *offsets = calloc(count * 4, sizeof *offsets);
    if (!offsets)
        return;
    for (uint32_t t = 0; t < mesh->target_count; t++) {
        const sinew_morph_target *tg = &mesh->targets[t];
        for (uint32_t k = 0; k < tg->delta_count; k++) {
            float *o = &offsets[(((size_t)t * mesh->vertex_count + tg->vertices[k]) * (size_t)texels) * 4];
            memcpy(o, &tg->positions[(size_t)k * 3], 3 * sizeof(float));
            if (tg->normals)
                memcpy(o + 4, &tg->normals[(size_t)k * 3], 3 * sizeof(float));
        }
    }
    rm->buffers[BUF_MORPH] = make_buffer(GL_TEXTURE_BUFFER, count * 16, offsets, GL_STATIC_DRAW);
    free(offsets);
    glGenTextures(1, &rm->morph_texture);
    glBindTexture(GL_TEXTURE_BUFFER, rm->morph_texture);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, rm->buffers[BUF_MORPH]);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    rm->morph_texels = texels;
}

static void upload_mesh(render_mesh *rm, const sinew_mesh *mesh, void *scratch, bool stream)
{
    size_t n = mesh->vertex_count;
    rm->influence_sets = mesh->skin >= 0 && mesh->influence_count ? (mesh->influence_count > 4 ? 2 : 1) : 0;
    if (mesh->dq_weights && rm->influence_sets)
        rm->buffers[BUF_DQ] = make_buffer(GL_ARRAY_BUFFER, n * 4, mesh->dq_weights, GL_STATIC_DRAW);
    rm->buffers[BUF_POSITION] = make_buffer(GL_ARRAY_BUFFER, n * 12, mesh->positions, GL_STATIC_DRAW);
    rm->buffers[BUF_NORMAL] = make_buffer(GL_ARRAY_BUFFER, n * 12, mesh->normals, GL_STATIC_DRAW);
    if (mesh->uvs)
        rm->buffers[BUF_UV] = make_buffer(GL_ARRAY_BUFFER, n * 8, mesh->uvs, GL_STATIC_DRAW);
    if (mesh->tangents)
        rm->buffers[BUF_TANGENT] = make_buffer(GL_ARRAY_BUFFER, n * 16, mesh->tangents, GL_STATIC_DRAW);
    if (mesh->colors)
        rm->buffers[BUF_COLOR] = make_buffer(GL_ARRAY_BUFFER, n * 16, mesh->colors, GL_STATIC_DRAW);
    upload_influences(rm, mesh, rm->influence_sets, scratch);
    glGenVertexArrays(1, &rm->vao_static);
    glBindVertexArray(rm->vao_static);
    rm->indices = make_buffer(GL_ELEMENT_ARRAY_BUFFER, (size_t)mesh->index_count * 4, mesh->indices, GL_STATIC_DRAW);
    float_attribute(0, rm->buffers[BUF_POSITION], 3, 0, 0);
    float_attribute(1, rm->buffers[BUF_NORMAL], 3, 0, 0);
    if (rm->buffers[BUF_TANGENT])
        float_attribute(7, rm->buffers[BUF_TANGENT], 4, 0, 0);
    bind_shared_attributes(rm);
    /* streamed vertices: CPU skinning, and morphs or caches the GPU does not take */
    if ((rm->influence_sets || mesh->target_count || mesh->cache) && stream) {
        glGenVertexArrays(1, &rm->vao_stream);
        glBindVertexArray(rm->vao_stream);
        rm->buffers[BUF_STREAM] = make_buffer(GL_ARRAY_BUFFER, n * STREAM_STRIDE, NULL, GL_STREAM_DRAW);
        rm->stream_room = 1;
        float_attribute(0, rm->buffers[BUF_STREAM], 3, STREAM_STRIDE, 0);
        float_attribute(1, rm->buffers[BUF_STREAM], 3, STREAM_STRIDE, 12);
        if (rm->buffers[BUF_TANGENT])
            float_attribute(7, rm->buffers[BUF_STREAM], 4, STREAM_STRIDE, 24);
        bind_shared_attributes(rm);
    }
    glBindVertexArray(0);
}

static const char *const MAP_NAMES[SINEW_MAP_COUNT] = {"base colour", "metallic-roughness", "normal", "occlusion",
                                                       "emissive"};

/* Colour maps are stored sRGB (decoded to linear by GL); data maps are linear. */
static bool map_is_srgb(int slot)
{
    return slot == SINEW_MAP_BASE_COLOR || slot == SINEW_MAP_EMISSIVE;
}

/* Decodes one of a material's maps (any stb_image format; the embedded image when the file
 * carries one, else the file it names) into a texture with mipmaps, sRGB for colours and
 * linear for data; rows are flipped because UVs have v up (OpenGL) and images store the
 * top row first. */
static GLuint load_texture(sinew_renderer *r, const sinew_material *material, int slot)
{
    const sinew_texture *map = &material->maps[slot];
    int w = 0, h = 0, channels = 0;
    unsigned char *pixels = map->image ? stbi_load_from_memory(map->image, (int)map->image_size, &w, &h, &channels, 4)
                                       : stbi_load(map->path, &w, &h, &channels, 4);
    if (!pixels) {
        const char *fallback = slot == SINEW_MAP_BASE_COLOR ? "its base colour is shown" : "it is shaded without it";
        if (map->image)
            warn(r, "%s: material \"%s\": cannot decode its embedded %s image (%u bytes: %s); %s", r->model->source,
                 material->name, MAP_NAMES[slot], map->image_size, stbi_failure_reason(), fallback);
        else
            warn(r, "%s: material \"%s\": cannot read %s texture %s (%s); %s", r->model->source, material->name,
                 MAP_NAMES[slot], map->path, stbi_failure_reason(), fallback);
        return 0;
    }
    render_flip_rows(pixels, (size_t)w * 4, h);
    bool srgb = map_is_srgb(slot);
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    stbi_image_free(pixels);
    return t;
}

/* A map shared by materials (or by two maps of one: glTF's occlusion often sits in the
 * metallic-roughness image) is decoded once when it has the same colour space. */
static GLuint shared_texture(sinew_renderer *r, uint32_t material, int slot)
{
    const sinew_material *mats = r->model->materials;
    const sinew_texture *map = &mats[material].maps[slot];
    for (uint32_t i = 0; i <= material; i++)
        for (int k = 0; k < SINEW_MAP_COUNT && (i < material || k < slot); k++) {
            const sinew_texture *other = &mats[i].maps[k];
            bool same = map->image ? other->image == map->image
                                   : other->path && !other->image && map->path && strcmp(other->path, map->path) == 0;
            if (same && r->textures[i][k] && map_is_srgb(slot) == map_is_srgb(k))
                return r->textures[i][k];
        }
    return 0;
}

static void lookup_mesh_uniforms(GLuint program, mesh_uniforms *u)
{
#define U(name) u->name = glGetUniformLocation(program, "u_" #name)
    U(model), U(view_proj), U(gpu_sets), U(dq_mode), U(dq_offset), U(palette_offset), U(instance_stride),
        U(rigid_record), U(instance_base), U(palette), U(heat_joint), U(heat_rigid), U(gouraud);
    U(morph), U(morph_count), U(morph_vertices), U(morph_texels), U(morph_target), U(morph_weight);
    U(key_dir), U(fill_dir), U(eye), U(base_color), U(use_texture), U(texture), U(mode), U(heat), U(override);
    U(normal_length), U(metallic), U(roughness), U(emissive), U(normal_scale), U(occlusion_strength), U(maps);
    U(map_mr), U(map_normal), U(map_occlusion), U(map_emissive), U(flat), U(vertex_colors), U(alpha_cutoff),
        U(alpha_coverage);
#undef U
}

/* Which skins go to the GPU: each must fit max_gpu_joints and the texture buffer. */
static void place_skins(sinew_renderer *r, uint32_t max_gpu_joints, uint32_t buffer_joints)
{
    const sinew_model *m = r->model;
    uint32_t at = 0;
    for (uint32_t s = 0; s < m->skin_count; s++) {
        uint32_t n = m->skins[s].joint_count;
        r->skin_offsets[s] = at;
        at += n;
        r->skin_on_gpu[s] = n <= max_gpu_joints && at <= buffer_joints;
        if (!r->skin_on_gpu[s])
            warn(r, "%s: skin %u has %u joints, more than GPU skinning allows here (%u); it is skinned on the CPU",
                 m->source, s, n, max_gpu_joints < buffer_joints ? max_gpu_joints : buffer_joints);
    }
}

static void mark_skeleton(sinew_renderer *r)
{
    const sinew_model *m = r->model;
    for (uint32_t n = 0; n < m->node_count; n++)
        r->skeleton_nodes[n] = m->skin_count ? sinew_model_node_is_joint(m, n) : true;
}

static sinew_result create_gl_objects(sinew_renderer *r, uint32_t max_vertices, sinew_error *error)
{
    const sinew_model *m = r->model;
    sinew_result result = render_programs_create(&r->programs, error);
    if (result != SINEW_OK)
        return result;
    lookup_mesh_uniforms(r->programs.mesh, &r->variant_u[0]);
    r->mesh_u = r->variant_u[0];
    lookup_mesh_uniforms(r->programs.normals, &r->normals_u);
    lookup_mesh_uniforms(r->programs.depth, &r->depth_u);
    r->overlay_matrix = glGetUniformLocation(r->programs.overlay, "u_matrix");
    r->overlay_point_size = glGetUniformLocation(r->programs.overlay, "u_point_size");
    r->overlay_round = glGetUniformLocation(r->programs.overlay, "u_round");

    /* Scratch for padding joints and weights: 24 bytes a vertex. */
    void *scratch = malloc((size_t)(max_vertices ? max_vertices : 1) * 24);
    if (!scratch)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory uploading meshes", m->source);
    for (uint32_t i = 0; i < m->mesh_count; i++) {
        upload_mesh(&r->meshes[i], &m->meshes[i], scratch, true);
        upload_morphs(&r->meshes[i], &m->meshes[i], r->max_buffer_texels);
        if (m->meshes[i].target_count && !r->meshes[i].morph_texture)
            warn(r, "%s: mesh \"%s\": its %u morph targets are too big for the GPU; they are morphed on the CPU",
                 m->source, m->meshes[i].name, m->meshes[i].target_count);
    }
    free(scratch);
    for (uint32_t i = 0; i < m->material_count; i++)
        for (int k = 0; k < SINEW_MAP_COUNT; k++) {
            const sinew_texture *map = &m->materials[i].maps[k];
            if (map->path || map->image) {
                GLuint shared = shared_texture(r, i, k);
                r->textures[i][k] = shared ? shared : load_texture(r, &m->materials[i], k);
            }
        }

    /* every skin's matrices, then (when some skin needs them) its dual-quaternion joints */
    r->palette_buffer =
        make_buffer(GL_TEXTURE_BUFFER, (size_t)(r->total_joints ? r->total_joints : 1) * 128, NULL, GL_STREAM_DRAW);
    glGenTextures(1, &r->palette_texture);
    glBindTexture(GL_TEXTURE_BUFFER, r->palette_texture);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, r->palette_buffer);

    if (r->muscle_vertex_capacity) {
        glGenVertexArrays(1, &r->muscle_vao);
        glBindVertexArray(r->muscle_vao);
        r->muscle_vertices = make_buffer(GL_ARRAY_BUFFER, (size_t)r->muscle_vertex_capacity * 24, NULL, GL_STREAM_DRAW);
        float_attribute(0, r->muscle_vertices, 3, 24, 0);
        float_attribute(1, r->muscle_vertices, 3, 24, 12);
        glVertexAttrib2f(2, 0.0f, 0.0f);
        glVertexAttribI4ui(3, 0, 0, 0, 0);
        glVertexAttribI4ui(4, 0, 0, 0, 0);
        glVertexAttrib4f(5, 0.0f, 0.0f, 0.0f, 0.0f);
        glVertexAttrib4f(6, 0.0f, 0.0f, 0.0f, 0.0f);
        glVertexAttrib4f(7, 0.0f, 0.0f, 0.0f, 0.0f);
        r->muscle_indices =
            make_buffer(GL_ELEMENT_ARRAY_BUFFER, (size_t)r->muscle_index_capacity * 4, NULL, GL_STREAM_DRAW);
    }
    glGenVertexArrays(1, &r->overlay_vao);
    glBindVertexArray(r->overlay_vao);
    r->overlay_buffer = make_buffer(GL_ARRAY_BUFFER, 0, NULL, GL_STREAM_DRAW); /* filled each pass */
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(overlay_vertex), (const void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(overlay_vertex), (const void *)12);
    uint32_t quads = OVERLAY_TEXT_VERTICES / 4;
    uint32_t *idx = malloc((size_t)quads * 6 * sizeof *idx);
    if (!idx)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", m->source);
    for (uint32_t q = 0; q < quads; q++) {
        static const uint32_t pattern[6] = {0, 1, 2, 0, 2, 3};
        for (int k = 0; k < 6; k++)
            idx[q * 6 + k] = q * 4 + pattern[k];
    }
    r->quad_indices = make_buffer(GL_ELEMENT_ARRAY_BUFFER, (size_t)quads * 6 * sizeof *idx, idx, GL_STATIC_DRAW);
    free(idx);
    glBindVertexArray(0);
    GLenum gl_error = glGetError();
    if (gl_error != GL_NO_ERROR)
        return sinew_fail(error, SINEW_ERROR_GRAPHICS, "%s: OpenGL error 0x%04x while uploading the model", m->source,
                          gl_error);
    return SINEW_OK;
}

static void crowd_find_nodes(sinew_renderer *r);

sinew_result sinew_renderer_create(const sinew_renderer_desc *desc, sinew_renderer **out, sinew_error *error)
{
    if (!desc || !desc->model || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_renderer_create: no model or no output");
    *out = NULL;
    const sinew_model *m = desc->model;
    char why[256];
    if (!render_gl_load(why, sizeof why))
        return sinew_fail(error, SINEW_ERROR_GRAPHICS, "no OpenGL: %s", why);
    if (!epoxy_is_desktop_gl() || epoxy_gl_version() < 33)
        return sinew_fail(error, SINEW_ERROR_GRAPHICS, "OpenGL 3.3 core is needed; the current context is %s %s",
                          epoxy_is_desktop_gl() ? "OpenGL" : "OpenGL ES", (const char *)glGetString(GL_VERSION));
    if (desc->allocator && (!desc->allocator->alloc || !desc->allocator->free))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_renderer_create: allocator without alloc or free");
    sinew_allocator alloc = desc->allocator ? *desc->allocator : (sinew_allocator){default_alloc, default_free, NULL};

    uint32_t total_joints = 0, max_vertices = 0, max_targets = 0;
    for (uint32_t s = 0; s < m->skin_count; s++)
        total_joints += m->skins[s].joint_count;
    for (uint32_t i = 0; i < m->mesh_count; i++) {
        if (m->meshes[i].vertex_count > max_vertices)
            max_vertices = m->meshes[i].vertex_count;
        if (m->meshes[i].target_count > max_targets)
            max_targets = m->meshes[i].target_count;
    }
    uint32_t warnings = m->material_count + m->skin_count + m->mesh_count + 2; /* + crowds without levels */
    uint32_t muscle_vertices = 0, muscle_indices = 0;
    for (uint32_t i = 0; desc->muscles && i < desc->muscles->muscle_count; i++) {
        uint32_t v, n;
        sinew_muscle_surface_size(desc->muscles->muscles[i].node_count, desc->muscles->muscles[i].segments, &v, &n);
        muscle_vertices = v > muscle_vertices ? v : muscle_vertices;
        muscle_indices = n > muscle_indices ? n : muscle_indices;
    }
    layout l = plan_layout(m, total_joints, max_vertices, max_targets, warnings, muscle_vertices, muscle_indices);
    unsigned char *block = alloc.alloc(l.total, alloc.user);
    if (!block)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for the renderer", m->source);
    memset(block, 0, l.total);
    sinew_renderer *r = (sinew_renderer *)block;
    r->model = m;
    r->crowd_radius = -1.0f;
    r->allocator = alloc;
    r->meshes = (render_mesh *)(block + l.meshes);
    r->textures = (GLuint(*)[SINEW_MAP_COUNT])(block + l.textures);
    r->skin_offsets = (uint32_t *)(block + l.skin_offsets);
    r->skin_on_gpu = (bool *)(block + l.skin_on_gpu);
    r->palettes = (sinew_mat4 *)(block + l.palettes);
    r->dq_palettes = (sinew_dq_joint *)(block + l.dq_palettes);
    r->stream = (float *)(block + l.stream);
    r->skin_mode = (uint8_t *)(block + l.skin_mode);
    r->morphed = (float *)(block + l.morphed);
    r->target_weights = (float *)(block + l.target_weights);
    r->skeleton_nodes = (bool *)(block + l.skeleton);
    r->overlay.vertices = (overlay_vertex *)(block + l.overlay);
    r->overlay.capacity = overlay_capacity(m->node_count) + OVERLAY_TEXT_VERTICES;
    r->warnings = (char(*)[WARNING_SIZE])(block + l.warnings);
    r->warning_capacity = warnings;
    r->muscle_scratch = (float *)(block + l.muscle);
    r->muscle_index_scratch = (uint32_t *)(block + l.muscle_index);
    r->crowd_place = (uint32_t *)(block + l.crowd_place);
    r->crowd_nodes = (uint32_t *)(block + l.crowd_nodes);
    crowd_find_nodes(r);
    r->muscle_vertex_capacity = muscle_vertices;
    r->muscle_index_capacity = muscle_indices;
    r->total_joints = total_joints;
    snprintf(r->gl_name, sizeof r->gl_name, "%s / %s", (const char *)glGetString(GL_RENDERER),
             (const char *)glGetString(GL_VERSION));

    GLint texels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &texels);
    r->max_buffer_texels = texels > 0 ? (uint32_t)texels : 0;
    uint32_t max_gpu = desc->max_gpu_joints ? desc->max_gpu_joints : UINT32_MAX;
    place_skins(r, max_gpu, r->max_buffer_texels / 4);
    mark_skeleton(r);
    sinew_result result = create_gl_objects(r, max_vertices, error);
    if (result != SINEW_OK) {
        sinew_renderer_free(r);
        return result;
    }
    *out = r;
    return SINEW_OK;
}

void sinew_renderer_free(sinew_renderer *r)
{
    if (!r)
        return;
    for (uint32_t i = 0; i < r->model->mesh_count; i++) {
        render_mesh *rm = &r->meshes[i];
        for (int l = 0; l < RENDER_LOD_LEVELS; l++) {
            render_mesh *level = l == 0 ? rm : rm->lod_meshes ? &rm->lod_meshes[l - 1] : NULL;
            if (!level)
                continue;
            glDeleteVertexArrays(1, &level->vao_static);
            glDeleteVertexArrays(1, &level->vao_stream);
            glDeleteTextures(1, &level->morph_texture);
            glDeleteBuffers(BUF_COUNT, level->buffers);
            glDeleteBuffers(1, &level->indices);
        }
        if (rm->lod_meshes)
            r->allocator.free(rm->lod_meshes, r->allocator.user);
    }
    /* shared maps repeat a name: GL ignores names already deleted */
    glDeleteTextures((GLsizei)(r->model->material_count * SINEW_MAP_COUNT), &r->textures[0][0]);
    glDeleteTextures(1, &r->palette_texture);
    glDeleteBuffers(1, &r->palette_buffer);
    glDeleteTextures(1, &r->crowd_texture);
    glDeleteBuffers(1, &r->crowd_buffer);
    if (r->crowd_records)
        r->allocator.free(r->crowd_records, r->allocator.user);
    if (r->crowd_slot)
        r->allocator.free(r->crowd_slot, r->allocator.user);
    if (r->crowd_stream)
        r->allocator.free(r->crowd_stream, r->allocator.user);
    glDeleteVertexArrays(1, &r->overlay_vao);
    glDeleteVertexArrays(1, &r->muscle_vao);
    glDeleteBuffers(1, &r->muscle_vertices);
    glDeleteBuffers(1, &r->muscle_indices);
    glDeleteBuffers(1, &r->overlay_buffer);
    glDeleteBuffers(1, &r->quad_indices);
    render_effects_free(&r->fx);
    render_programs_free(&r->programs);
    r->allocator.free(r, r->allocator.user);
}

sinew_result sinew_renderer_set_environment(sinew_renderer *r, const char *path, sinew_error *error)
{
    if (!r)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_renderer_set_environment: no renderer");
    return render_effects_set_environment(&r->fx, path, error);
}

uint32_t sinew_renderer_warning_count(const sinew_renderer *r)
{
    return r ? r->warning_count : 0;
}

const char *sinew_renderer_warning(const sinew_renderer *r, uint32_t index)
{
    return r && index < r->warning_count ? r->warnings[index] : NULL;
}

const char *sinew_renderer_gl_name(const sinew_renderer *r)
{
    return r ? r->gl_name : "";
}

/* ---- per frame ------------------------------------------------------------------ */

/* How each skin skins this frame: as its file asks (linear, dual quaternion, mixed), or the
 * one method the options force; and whether any needs dual-quaternion joints. */
static void choose_skin_modes(sinew_renderer *r, const sinew_render_options *o)
{
    const sinew_model *m = r->model;
    r->any_dq = false;
    for (uint32_t s = 0; s < m->skin_count; s++) {
        uint32_t blend = m->skins[s].blend;
        sinew_skin_method method = !o->skin_method_set ? (sinew_skin_method)(blend <= 2 ? blend : 0)
                                   : o->skin_method == SINEW_SKIN_DUAL_QUATERNION ? SINEW_SKIN_DUAL_QUATERNION
                                                                                  : SINEW_SKIN_LINEAR;
        r->skin_mode[s] = (uint8_t)method;
        r->any_dq = r->any_dq || method != SINEW_SKIN_LINEAR;
    }
}

static sinew_result compute_palettes(sinew_renderer *r, const sinew_mat4 *worlds, uint32_t world_count,
                                     sinew_error *error)
{
    const sinew_model *m = r->model;
    for (uint32_t s = 0; s < m->skin_count; s++) {
        sinew_result result = sinew_skin_palette(&m->skins[s], worlds, world_count, &r->palettes[r->skin_offsets[s]],
                                                 m->skins[s].joint_count, error);
        if (result != SINEW_OK)
            return result;
    }
    if (r->any_dq)
        return sinew_skin_dq_palette(r->palettes, r->total_joints, r->dq_palettes, error);
    return SINEW_OK;
}

static bool mesh_is_skinned(const sinew_mesh *mesh)
{
    return mesh->skin >= 0 && mesh->influence_count > 0;
}

static void skin_range_job(void *user, uint32_t first, uint32_t count, uint32_t thread)
{
    (void)thread;
    sinew_skin_desc d = *(const sinew_skin_desc *)user;
    d.first = first, d.count = count;
    sinew_skin_vertices(&d, NULL);
}

/* The weight of each of an instance's targets this frame into r->target_weights; how many are
 * not 0. */
static uint32_t instance_targets(sinew_renderer *r, const sinew_instance *inst)
{
    const sinew_model *m = r->model;
    const sinew_mesh *mesh = &m->meshes[inst->mesh];
    if (mesh->target_count == 0)
        return 0;
    float defaults[64];
    const float *channels = r->weights ? r->weights + inst->morph_first : NULL;
    if (!channels) {
        if (mesh->morph_channel_count > 64)
            return 0;
        for (uint32_t c = 0; c < mesh->morph_channel_count; c++)
            defaults[c] = m->morph_channels[inst->morph_first + c].default_weight;
        channels = defaults;
    }
    if (sinew_morph_target_weights(mesh, channels, mesh->morph_channel_count, r->target_weights, mesh->target_count,
                                   NULL) != SINEW_OK)
        return 0;
    uint32_t n = 0;
    for (uint32_t t = 0; t < mesh->target_count; t++)
        n += r->target_weights[t] != 0.0f;
    return n;
}

/* Whether the instance's vertices come from the CPU this frame (r->stream): a vertex cache,
 * CPU skinning, or morph targets the GPU cannot take (too many at once, or too big). */
static bool on_cpu(const sinew_renderer *r, const sinew_render_options *o, const sinew_mesh *mesh,
                   const render_mesh *rm, uint32_t morphs)
{
    if (mesh->cache && !r->no_cache)
        return true;
    if (morphs && (!rm->morph_texture || morphs > GPU_MORPHS))
        return true;
    return mesh_is_skinned(mesh) && (o->skinning == SINEW_SKINNING_CPU || !r->skin_on_gpu[mesh->skin]);
}

/* Interleaves positions, normals and tangents (any may be NULL but positions) into r->stream. */
static void interleave(sinew_renderer *r, uint32_t n, const float *p, const float *nrm, const float *t)
{
    for (uint32_t v = 0; v < n; v++) {
        float *o = &r->stream[(size_t)v * STREAM_FLOATS];
        memcpy(o, &p[(size_t)v * 3], 12);
        if (nrm)
            memcpy(o + 3, &nrm[(size_t)v * 3], 12);
        if (t)
            memcpy(o + 6, &t[(size_t)v * 4], 16);
    }
}

/* How the CPU skins a skinned mesh into `out` (STREAM_FLOATS a vertex), from a palette of
 * total_joints records, and from r->morphed when the mesh was morphed there. */
static sinew_skin_desc stream_skin_desc(const sinew_renderer *r, const sinew_mesh *mesh, bool morphed,
                                        const sinew_mat4 *palettes, const sinew_dq_joint *dq_palettes, float *out)
{
    size_t n = mesh->vertex_count;
    const float *p = r->morphed, *nrm = r->morphed + n * 3, *t = r->morphed + n * 6;
    return (sinew_skin_desc){.mesh = mesh,
                             .palette = palettes + r->skin_offsets[mesh->skin],
                             .palette_count = r->model->skins[mesh->skin].joint_count,
                             .method = (sinew_skin_method)r->skin_mode[mesh->skin],
                             .dq_palette = dq_palettes + r->skin_offsets[mesh->skin],
                             .positions = morphed ? p : NULL,
                             .normals = morphed && mesh->normals ? nrm : NULL,
                             .tangents = morphed && mesh->tangents ? t : NULL,
                             .out_positions = out,
                             .out_normals = out + 3,
                             .out_tangents = mesh->tangents ? out + 6 : NULL,
                             .out_stride = STREAM_STRIDE};
}

/* The mesh morphed by the targets at r->target_weights into r->morphed (positions, then
 * normals and tangents where it has them). */
static sinew_result morph_scratch(sinew_renderer *r, const sinew_mesh *mesh, sinew_error *error)
{
    size_t n = mesh->vertex_count;
    return sinew_morph_vertices(&(sinew_morph_desc){.mesh = mesh,
                                                    .target_weights = r->target_weights,
                                                    .out_positions = r->morphed,
                                                    .out_normals = mesh->normals ? r->morphed + n * 3 : NULL,
                                                    .out_tangents = mesh->tangents ? r->morphed + n * 6 : NULL},
                                error);
}

/* A skinned mesh (from r->morphed when `morphed`) into r->stream, over `jobs` when given. */
static sinew_result skin_stream(sinew_renderer *r, const sinew_mesh *mesh, bool morphed, const sinew_mat4 *palettes,
                                const sinew_dq_joint *dq_palettes, sinew_jobs *jobs, sinew_error *error)
{
    sinew_skin_desc d = stream_skin_desc(r, mesh, morphed, palettes, dq_palettes, r->stream);
    if (!jobs)
        return sinew_skin_vertices(&d, error);
    sinew_jobs_run(jobs, mesh->vertex_count, 4096, skin_range_job, &d);
    return SINEW_OK;
}

/* Fills r->stream with an instance's vertices as the CPU poses them: a vertex cache's (mesh
 * space, smooth normals), or the morph targets at r->target_weights (`morphs` of them not 0)
 * then the skin (world space; mesh space for a rigid mesh), from a palette of total_joints
 * records (matrices and dual-quaternion joints: r->palettes and r->dq_palettes, or a crowd
 * character's), over `jobs` when given (the ranges cannot fail: the model's joint indices were
 * checked when it was loaded). */
static sinew_result fill_stream(sinew_renderer *r, const sinew_mesh *mesh, uint32_t morphs, const sinew_mat4 *palettes,
                                const sinew_dq_joint *dq_palettes, sinew_jobs *jobs, sinew_error *error)
{
    uint32_t n = mesh->vertex_count;
    float *p = r->morphed, *nrm = r->morphed + (size_t)n * 3, *t = r->morphed + (size_t)n * 6;
    if (mesh->cache && !r->no_cache) {
        sinew_result result = sinew_cache_vertices(mesh, r->cache_time, p, error);
        if (result == SINEW_OK)
            result = sinew_smooth_normals(mesh, p, nrm, 0, error);
        if (result == SINEW_OK)
            interleave(r, n, p, nrm, mesh->tangents);
        return result;
    }
    bool morphed = morphs > 0;
    sinew_result result = morphed ? morph_scratch(r, mesh, error) : SINEW_OK;
    if (result != SINEW_OK)
        return result;
    if (!mesh_is_skinned(mesh)) {
        interleave(r, n, morphed ? p : mesh->positions, morphed ? nrm : mesh->normals,
                   morphed && mesh->tangents ? t : mesh->tangents);
        return SINEW_OK;
    }
    return skin_stream(r, mesh, morphed, palettes, dq_palettes, jobs, error);
}

/* The morph uniforms of a GPU draw: the targets with weight (up to GPU_MORPHS), or none. */
static void set_morph_uniforms(const sinew_renderer *r, const mesh_uniforms *u, const sinew_mesh *mesh,
                               const render_mesh *rm, uint32_t morphs)
{
    int targets[GPU_MORPHS];
    float weights[GPU_MORPHS];
    int n = 0;
    for (uint32_t t = 0; morphs && t < mesh->target_count && n < GPU_MORPHS; t++)
        if (r->target_weights[t] != 0.0f)
            targets[n] = (int)t, weights[n++] = r->target_weights[t];
    glUniform1i(u->morph_count, n);
    if (!n)
        return;
    glActiveTexture(GL_TEXTURE6);
    glBindTexture(GL_TEXTURE_BUFFER, rm->morph_texture);
    glActiveTexture(GL_TEXTURE0);
    glUniform1i(u->morph_vertices, (GLint)mesh->vertex_count);
    glUniform1i(u->morph_texels, rm->morph_texels);
    glUniform1iv(u->morph_target, n, targets);
    glUniform1fv(u->morph_weight, n, weights);
}

/* Index of `node` in the mesh's skin, or -1. */
static int32_t skin_joint_of(const sinew_model *m, const sinew_mesh *mesh, int32_t node)
{
    if (node < 0 || mesh->skin < 0)
        return -1;
    const sinew_skin *skin = &m->skins[mesh->skin];
    for (uint32_t j = 0; j < skin->joint_count; j++)
        if (skin->joints[j] == (uint32_t)node)
            return (int32_t)j;
    return -1;
}

typedef struct frame_state {
    const sinew_frame *frame;
    const sinew_render_options *o;
    float view_proj[16];
    float proj11; /* the projection's [1][1]: pixels of a world unit at clip w = 1, over half the height */
    float eye[3], key[3], fill[3];
    uint32_t dq_offset; /* records from a joint's matrix to its dual-quaternion joint */
    const render_effects *fx;
    const render_effect_frame *ef;
} frame_state;

static void set_common_uniforms(GLuint program, const mesh_uniforms *u, const frame_state *fs)
{
    glUseProgram(program);
    glUniformMatrix4fv(u->view_proj, 1, GL_FALSE, fs->view_proj);
    glUniform3fv(u->eye, 1, fs->eye);
    glUniform3fv(u->key_dir, 1, fs->key);
    glUniform3fv(u->fill_dir, 1, fs->fill);
    glUniform1i(u->palette, 0);
    glUniform1i(u->texture, 1);
    glUniform1i(u->map_mr, 2);
    glUniform1i(u->map_normal, 3);
    glUniform1i(u->map_occlusion, 4);
    glUniform1i(u->map_emissive, 5);
    glUniform1i(u->instance_stride, 0);
    glUniform1i(u->rigid_record, -1);
    glUniform1i(u->instance_base, 0);
    glUniform1i(u->morph, 6);
    glUniform1i(u->morph_count, 0);
    glUniform1i(u->dq_offset, (GLint)fs->dq_offset);
    if (u->mode >= 0) /* the mesh program: its surfaces' effects */
        render_effects_uniforms(fs->fx, program, fs->ef);
}

/* Binds the VAO and sets the skinning and morph uniforms of one instance; streams vertices
 * the CPU poses first when needed (once a frame and instance: the normals pass reuses them). */
static sinew_result prepare_instance(sinew_renderer *r, const mesh_uniforms *u, const frame_state *fs, uint32_t index,
                                     sinew_error *error)
{
    const sinew_instance *inst = &r->model->instances[index];
    const sinew_mesh *mesh = &r->model->meshes[inst->mesh];
    render_mesh *rm = &r->meshes[inst->mesh];
    int32_t heat_node = options_heatmap(fs->o);
    uint32_t morphs = instance_targets(r, inst);
    bool cpu = on_cpu(r, fs->o, mesh, rm, morphs);
    bool placed = !mesh_is_skinned(mesh) || (mesh->cache && !r->no_cache); /* by its node's matrix */
    glUniformMatrix4fv(u->model, 1, GL_FALSE, placed ? fs->frame->worlds[inst->node].m : IDENTITY);
    int32_t heat = placed ? -1 : skin_joint_of(r->model, mesh, heat_node);
    glUniform1i(u->heat_joint, heat);
    glUniform1f(u->heat_rigid, placed && (int32_t)inst->node == heat_node ? 1.0f : 0.0f);
    glUniform1i(u->morph_count, 0);
    if (cpu) {
        if (rm->streamed != r->frame || rm->streamed_instance != index) {
            sinew_result result = fill_stream(r, mesh, morphs, r->palettes, r->dq_palettes, NULL, error);
            if (result != SINEW_OK)
                return result;
            glBindBuffer(GL_ARRAY_BUFFER, rm->buffers[BUF_STREAM]);
            glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)mesh->vertex_count * STREAM_STRIDE, r->stream);
            rm->streamed = r->frame;
            rm->streamed_instance = index;
        }
        glBindVertexArray(rm->vao_stream);
        glUniform1i(u->gpu_sets, 0);
        return SINEW_OK;
    }
    glBindVertexArray(rm->vao_static);
    set_morph_uniforms(r, u, mesh, rm, morphs);
    if (placed) {
        glUniform1i(u->gpu_sets, 0);
        return SINEW_OK;
    }
    glUniform1i(u->gpu_sets, rm->influence_sets);
    glUniform1i(u->dq_mode, r->skin_mode[mesh->skin]);
    glUniform1i(u->palette_offset, (GLint)r->skin_offsets[mesh->skin]);
    return SINEW_OK;
}

static int shading_mode(const sinew_render_options *o)
{
    if (o->unlit)
        return 0;
    return o->shading == SINEW_SHADING_GOURAUD ? 2
           : o->shading == SINEW_SHADING_FLAT  ? 3
           : o->shading == SINEW_SHADING_PBR   ? 4
                                               : 1;
}

/* How a material's alpha is drawn (NULL: opaque): a mask discards what is below its cutoff; a
 * blend is drawn as the multisampled pixel's coverage (and its alpha as one, so that the
 * resolved alpha is the coverage), in any order, and without multisampling only its wholly
 * transparent texels are left out. */
static void set_alpha(const mesh_uniforms *u, const sinew_material *mat)
{
    sinew_alpha_mode mode = mat ? mat->alpha_mode : SINEW_ALPHA_OPAQUE;
    glUniform1f(u->alpha_cutoff, mode == SINEW_ALPHA_MASK    ? mat->alpha_cutoff
                                 : mode == SINEW_ALPHA_BLEND ? 1.0f / 255.0f
                                                             : -1.0f);
    glUniform1i(u->alpha_coverage, mode == SINEW_ALPHA_BLEND);
    if (mode == SINEW_ALPHA_BLEND) {
        glEnable(GL_SAMPLE_ALPHA_TO_COVERAGE);
        glEnable(GL_SAMPLE_ALPHA_TO_ONE);
    } else {
        glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
        glDisable(GL_SAMPLE_ALPHA_TO_ONE);
    }
}

/* The mesh's material, and its shading: the frame's, each triangle flat for a mesh whose file
 * asks for flat normals (Phong and Gouraud become flat; physically based shading takes the
 * triangle's normal). */
static void set_material(sinew_renderer *r, const frame_state *fs, const sinew_mesh *mesh)
{
    static const float CLAY[4] = {0.50f, 0.48f, 0.45f, 1.0f};
    static const float NO_MATERIAL[4] = {0.70f, 0.70f, 0.70f, 1.0f};
    static const float BLACK[3] = {0.0f, 0.0f, 0.0f};
    static const GLuint NO_MAPS[SINEW_MAP_COUNT] = {0};
    const mesh_uniforms *u = &r->mesh_u;
    const float *color = CLAY, *emissive = BLACK;
    float metallic = 0.0f, roughness = 0.5f, normal_scale = 1.0f, occlusion = 1.0f;
    const GLuint *maps = NO_MAPS;
    if (!fs->o->clay) {
        color = NO_MATERIAL;
        if (mesh->material >= 0) {
            const sinew_material *mat = &r->model->materials[mesh->material];
            color = mat->base_color;
            emissive = mat->emissive;
            metallic = mat->metallic, roughness = mat->roughness;
            normal_scale = mat->normal_scale, occlusion = mat->occlusion_strength;
            maps = r->textures[mesh->material];
        }
    }
    glUniform4fv(u->base_color, 1, color);
    glUniform1i(u->vertex_colors, !fs->o->clay && mesh->colors); /* clay: the shape alone */
    set_alpha(u, !fs->o->clay && mesh->material >= 0 ? &r->model->materials[mesh->material] : NULL);
    glUniform1i(u->use_texture, maps[SINEW_MAP_BASE_COLOR] != 0);
    glUniform1f(u->metallic, metallic);
    glUniform1f(u->roughness, roughness);
    glUniform3fv(u->emissive, 1, emissive);
    glUniform1f(u->normal_scale, normal_scale);
    glUniform1f(u->occlusion_strength, occlusion);
    /* normal maps need UVs to find their frame */
    bool normal_map = maps[SINEW_MAP_NORMAL] && mesh->uvs;
    glUniform4i(u->maps, maps[SINEW_MAP_METALLIC_ROUGHNESS] != 0, normal_map, maps[SINEW_MAP_OCCLUSION] != 0,
                maps[SINEW_MAP_EMISSIVE] != 0);
    for (int k = 0; k < SINEW_MAP_COUNT; k++) {
        glActiveTexture(GL_TEXTURE1 + k);
        glBindTexture(GL_TEXTURE_2D, maps[k]);
    }
    glActiveTexture(GL_TEXTURE0);
    int mode = shading_mode(fs->o);
    bool flat = mesh->flat_normals && mode != 0;
    if (flat && (mode == 1 || mode == 2))
        mode = 3;
    glUniform1i(u->mode, mode);
    glUniform1i(u->gouraud, mode == 2);
    glUniform1i(u->flat, flat);
}

static bool instance_hidden(const sinew_render_options *o, uint32_t i)
{
    return o->hidden_instances && o->hidden_instances[i];
}

/* The mesh program with the frame's uniforms and shading (heat map on or off). */
static void begin_mesh_pass(sinew_renderer *r, const frame_state *fs, bool heat)
{
    const mesh_uniforms *u = &r->mesh_u;
    set_common_uniforms(r->programs.mesh, u, fs);
    int mode = shading_mode(fs->o);
    glUniform1i(u->mode, mode);
    glUniform1i(u->gouraud, mode == 2);
    glUniform1i(u->flat, 0);
    glUniform1i(u->heat, heat);
}

static sinew_result draw_meshes(sinew_renderer *r, const frame_state *fs, sinew_error *error)
{
    const sinew_model *m = r->model;
    const sinew_render_options *o = fs->o;
    const mesh_uniforms *u = &r->mesh_u;
    begin_mesh_pass(r, fs, options_heatmap(o) >= 0);
    static const float WIRE[4] = {0.06f, 0.06f, 0.08f, 1.0f}, NONE[4] = {0, 0, 0, 0};
    for (uint32_t i = 0; i < m->instance_count; i++) {
        if (instance_hidden(o, i))
            continue;
        const sinew_mesh *mesh = &m->meshes[m->instances[i].mesh];
        sinew_result result = prepare_instance(r, u, fs, i, error);
        if (result != SINEW_OK)
            return result;
        set_material(r, fs, mesh);
        glUniform4fv(u->override, 1, NONE);
        if (o->wireframe) {
            glEnable(GL_POLYGON_OFFSET_FILL);
            glPolygonOffset(1.0f, 1.0f);
        }
        glDrawElements(GL_TRIANGLES, (GLsizei)mesh->index_count, GL_UNSIGNED_INT, NULL);
        glDisable(GL_POLYGON_OFFSET_FILL);
        if (o->wireframe) {
            glUniform4fv(u->override, 1, WIRE);
            glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
            glDrawElements(GL_TRIANGLES, (GLsizei)mesh->index_count, GL_UNSIGNED_INT, NULL);
            glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        }
    }
    set_alpha(u, NULL); /* the overlays after: no coverage from alpha */
    return SINEW_OK;
}

/* The depth of every shown mesh instance through view_proj (the shadow map, the pre-pass). */
static sinew_result draw_depth(sinew_renderer *r, const frame_state *fs, const float *view_proj, sinew_error *error)
{
    const sinew_model *m = r->model;
    const mesh_uniforms *u = &r->depth_u;
    frame_state depth = *fs;
    memcpy(depth.view_proj, view_proj, sizeof depth.view_proj);
    set_common_uniforms(r->programs.depth, u, &depth);
    glUniform1i(u->gouraud, 0);
    for (uint32_t i = 0; i < m->instance_count; i++) {
        if (instance_hidden(fs->o, i))
            continue;
        sinew_result result = prepare_instance(r, u, &depth, i, error);
        if (result != SINEW_OK)
            return result;
        glDrawElements(GL_TRIANGLES, (GLsizei)m->meshes[m->instances[i].mesh].index_count, GL_UNSIGNED_INT, NULL);
    }
    return SINEW_OK;
}

/* Makes the mesh program with the frame's effects compiled in the one in use. */
static sinew_result use_mesh_variant(sinew_renderer *r, const render_effect_frame *ef, sinew_error *error)
{
    unsigned flags =
        (ef->shadows ? RENDER_WITH_SHADOWS : 0u) | (ef->ao ? RENDER_WITH_AO : 0u) | (ef->tone ? RENDER_WITH_TONE : 0u);
    bool fresh = !r->programs.mesh_variant[flags];
    GLuint program = render_mesh_variant(&r->programs, flags, error);
    if (!program)
        return error ? error->kind : SINEW_ERROR_GRAPHICS;
    if (fresh)
        lookup_mesh_uniforms(program, &r->variant_u[flags]);
    r->programs.mesh = program;
    r->mesh_u = r->variant_u[flags];
    return SINEW_OK;
}

/* The shadow map and the depth pre-pass the frame's effects need, drawn into their own
 * framebuffers; the caller's framebuffers are bound again after. */
static sinew_result draw_effect_passes(sinew_renderer *r, const frame_state *fs, sinew_error *error)
{
    const render_effect_frame *ef = fs->ef;
    GLint draw_fbo = 0, read_fbo = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw_fbo);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fbo);
    sinew_result result = SINEW_OK;
    if (ef->shadows) {
        render_effects_begin_shadow(&r->fx);
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(2.0f, 4.0f);
        result = draw_depth(r, fs, ef->light_view_proj, error);
        glDisable(GL_POLYGON_OFFSET_FILL);
    }
    if (result == SINEW_OK && ef->depth_pass) {
        render_effects_begin_depth(&r->fx, ef);
        result = draw_depth(r, fs, fs->view_proj, error);
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)draw_fbo);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)read_fbo);
    glViewport(0, 0, fs->frame->width, fs->frame->height);
    render_effects_bind(&r->fx);
    return result;
}

static sinew_result draw_normals(sinew_renderer *r, const frame_state *fs, float length, sinew_error *error)
{
    const sinew_model *m = r->model;
    const mesh_uniforms *u = &r->normals_u;
    set_common_uniforms(r->programs.normals, u, fs);
    glUniform1i(u->gouraud, 0);
    glUniform1f(u->normal_length, length);
    for (uint32_t i = 0; i < m->instance_count; i++) {
        if (instance_hidden(fs->o, i))
            continue;
        sinew_result result = prepare_instance(r, u, fs, i, error);
        if (result != SINEW_OK)
            return result;
        glDrawArrays(GL_POINTS, 0, (GLsizei)m->meshes[m->instances[i].mesh].vertex_count);
    }
    return SINEW_OK;
}

/* Muscles as Gouraud-shaded tubes, each built on the CPU into the scratch sized at create. */
static sinew_result draw_muscles(sinew_renderer *r, const frame_state *fs, sinew_error *error)
{
    const mesh_uniforms *u = &r->mesh_u;
    set_common_uniforms(r->programs.mesh, u, fs);
    int mode = !fs->o->unlit ? 2 : 0;
    glUniform1i(u->mode, mode);
    glUniform1i(u->gouraud, mode == 2);
    glUniform1i(u->flat, 0);
    glUniform1i(u->vertex_colors, 0);
    set_alpha(u, NULL);
    glUniform1i(u->heat, 0);
    glUniform1i(u->gpu_sets, 0);
    glUniform1i(u->heat_joint, -1);
    glUniform1i(u->use_texture, 0);
    glUniformMatrix4fv(u->model, 1, GL_FALSE, IDENTITY);
    static const float NONE[4] = {0, 0, 0, 0};
    glUniform4fv(u->override, 1, NONE);
    glBindVertexArray(r->muscle_vao);
    for (uint32_t i = 0; i < fs->frame->muscle_count; i++) {
        const sinew_muscle_pose *p = &fs->frame->muscles[i];
        uint32_t nv, ni;
        sinew_muscle_surface_size(p->node_count, p->segments, &nv, &ni);
        sinew_muscle_surface_desc d = {.node_count = p->node_count,
                                       .radii = p->radii,
                                       .segments = p->segments,
                                       .out_positions = r->muscle_scratch,
                                       .out_normals = r->muscle_scratch + 3,
                                       .out_stride = 24,
                                       .vertex_capacity = r->muscle_vertex_capacity,
                                       .out_indices = r->muscle_index_scratch,
                                       .index_capacity = r->muscle_index_capacity};
        memcpy(d.origin, p->origin, sizeof d.origin);
        memcpy(d.insertion, p->insertion, sizeof d.insertion);
        sinew_error local = {0};
        if (sinew_muscle_surface(&d, &local) != SINEW_OK) {
            if (nv > r->muscle_vertex_capacity || ni > r->muscle_index_capacity)
                return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                                  "muscle \"%s\" is larger than the muscles the renderer was created for", p->name);
            continue; /* ends at one point: nothing to draw this frame */
        }
        float color[4] = {sinew_srgb_to_linear(p->color[0]), sinew_srgb_to_linear(p->color[1]),
                          sinew_srgb_to_linear(p->color[2]), 1}; /* the mesh shader works in linear light */
        if (!p->in_range) /* stretched or squashed past what it can do: washed out */
            for (int k = 0; k < 3; k++)
                color[k] = 0.5f * color[k] + 0.25f;
        glUniform4fv(u->base_color, 1, color);
        glBindBuffer(GL_ARRAY_BUFFER, r->muscle_vertices);
        glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)nv * 24, r->muscle_scratch);
        glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, (GLsizeiptr)ni * 4, r->muscle_index_scratch);
        glDrawElements(GL_TRIANGLES, (GLsizei)ni, GL_UNSIGNED_INT, NULL);
    }
    return SINEW_OK;
}

/* ---- overlay ------------------------------------------------------------------------ */

typedef struct overlay_range {
    uint32_t first, count;
} overlay_range;

static overlay_range add_range(overlay_list *list, const overlay_frame *of,
                               void (*add)(overlay_list *, const overlay_frame *))
{
    overlay_range range = {list->count, 0};
    add(list, of);
    range.count = list->count - range.first;
    return range;
}

static void draw_overlay_range(GLenum mode, overlay_range range)
{
    if (range.count)
        glDrawArrays(mode, (GLint)range.first, (GLsizei)range.count);
}

static void add_all_joints(overlay_list *list, const overlay_frame *of)
{
    overlay_add_joints(list, of, false);
}

static void add_selected_joint(overlay_list *list, const overlay_frame *of)
{
    overlay_add_joints(list, of, true);
}

static void draw_overlay(sinew_renderer *r, const frame_state *fs, bool before_meshes)
{
    const sinew_render_options *o = fs->o;
    overlay_frame of = {.model = r->model,
                        .skeleton_nodes = r->skeleton_nodes,
                        .worlds = fs->frame->worlds,
                        .options = o,
                        .camera = fs->frame->camera,
                        .view_proj = fs->view_proj,
                        .width = fs->frame->width,
                        .height = fs->frame->height,
                        .scene_radius = fs->frame->camera->scene_radius > 0.0f ? fs->frame->camera->scene_radius : 1.0f,
                        .lines = fs->frame->lines,
                        .line_count = fs->frame->lines ? fs->frame->line_count : 0,
                        .line_color = fs->frame->line_color};
    overlay_list *list = &r->overlay;
    list->count = 0;
    overlay_range lines = {0}, grid = {0}, axes = {0}, bones = {0}, joint_axes = {0}, joints = {0}, selected = {0},
                  names = {0};
    if (before_meshes) {
        if (!o->hide_grid)
            grid = add_range(list, &of, overlay_add_grid);
        if (o->axes)
            axes = add_range(list, &of, overlay_add_axes);
        if (of.line_count)
            lines = add_range(list, &of, overlay_add_lines);
    } else {
        if (o->skeleton) {
            bones = add_range(list, &of, overlay_add_bones);
            joints = add_range(list, &of, add_all_joints);
        }
        if (o->joint_axes)
            joint_axes = add_range(list, &of, overlay_add_joint_axes);
        if (o->skeleton || o->joint_names)
            selected = add_range(list, &of, add_selected_joint);
        names = add_range(list, &of, overlay_add_names);
    }
    if (!list->count)
        return;
    glUseProgram(r->programs.overlay);
    glBindVertexArray(r->overlay_vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->overlay_buffer);
    /* A fresh store of just what this pass uses (the whole capacity, text room included, is
     * over a megabyte and would be orphaned twice a frame). */
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(list->count * sizeof(overlay_vertex)), list->vertices, GL_STREAM_DRAW);
    glUniformMatrix4fv(r->overlay_matrix, 1, GL_FALSE, fs->view_proj);
    glUniform1i(r->overlay_round, 0);
    if (before_meshes) {
        draw_overlay_range(GL_LINES, grid);
        draw_overlay_range(GL_LINES, axes);
        draw_overlay_range(GL_LINES, lines);
        return;
    }
    /* The skeleton goes over the mesh: bones depth-tested among themselves only. */
    glClear(GL_DEPTH_BUFFER_BIT);
    draw_overlay_range(GL_TRIANGLES, bones);
    glDisable(GL_DEPTH_TEST);
    draw_overlay_range(GL_LINES, joint_axes);
    glUniform1i(r->overlay_round, 1);
    float dot = fs->frame->height >= 1000 ? 2.0f : 1.0f;
    glUniform1f(r->overlay_point_size, 7.0f * dot);
    draw_overlay_range(GL_POINTS, joints);
    glUniform1f(r->overlay_point_size, 12.0f * dot);
    draw_overlay_range(GL_POINTS, selected);
    glUniform1i(r->overlay_round, 0);
    if (names.count) {
        mat4 ortho;
        glm_ortho(0.0f, (float)fs->frame->width, (float)fs->frame->height, 0.0f, -1.0f, 1.0f, ortho);
        glUniformMatrix4fv(r->overlay_matrix, 1, GL_FALSE, (const float *)ortho);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->quad_indices);
        glDrawElementsBaseVertex(GL_TRIANGLES, (GLsizei)(names.count / 4 * 6), GL_UNSIGNED_INT, NULL,
                                 (GLint)names.first);
    }
    glEnable(GL_DEPTH_TEST);
}

/* A crowd's skeletons (the skeleton switch on, or a file without meshes): each character's
 * bones and joints, one character a pass through the overlay buffer. */
static void draw_crowd_skeletons(sinew_renderer *r, const frame_state *fs)
{
    const sinew_frame *frame = fs->frame;
    const uint32_t n = r->model->node_count;
    overlay_frame of = {.model = r->model,
                        .skeleton_nodes = r->skeleton_nodes,
                        .options = fs->o,
                        .camera = frame->camera,
                        .view_proj = fs->view_proj,
                        .width = frame->width,
                        .height = frame->height,
                        .scene_radius = frame->camera->scene_radius > 0.0f ? frame->camera->scene_radius : 1.0f};
    glUseProgram(r->programs.overlay);
    glBindVertexArray(r->overlay_vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->overlay_buffer);
    glUniformMatrix4fv(r->overlay_matrix, 1, GL_FALSE, fs->view_proj);
    float dot = frame->height >= 1000 ? 2.0f : 1.0f;
    glUniform1f(r->overlay_point_size, 5.0f * dot);
    for (uint32_t c = 0; c < frame->crowd_count; c++) {
        of.worlds = frame->crowd_worlds + (size_t)c * n;
        overlay_list *list = &r->overlay;
        list->count = 0;
        overlay_range bones = add_range(list, &of, overlay_add_bones);
        overlay_range joints = add_range(list, &of, add_all_joints);
        if (!list->count)
            continue;
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(list->count * sizeof(overlay_vertex)), list->vertices,
                     GL_STREAM_DRAW);
        glUniform1i(r->overlay_round, 0);
        draw_overlay_range(GL_TRIANGLES, bones);
        glUniform1i(r->overlay_round, 1);
        draw_overlay_range(GL_POINTS, joints);
    }
    glUniform1i(r->overlay_round, 0);
}

/* Lights ride with the camera: the key from above-left, the fill from the right. */
static void camera_lights(const sinew_camera *camera, frame_state *fs)
{
    float f[3], right[3], up[3];
    sinew_camera_basis(camera, f, right, up);
    for (int i = 0; i < 3; i++) {
        fs->key[i] = -f[i] * 0.8f + up[i] * 0.75f - right[i] * 0.45f;
        fs->fill[i] = -f[i] * 0.6f - up[i] * 0.15f + right[i] * 0.8f;
    }
    glm_vec3_normalize(fs->key);
    glm_vec3_normalize(fs->fill);
    sinew_camera_eye(camera, fs->eye);
}

/* ---- crowds ---------------------------------------------------------------------- */

/* A crowd character's node records: those of instances drawn where their node is (rigid, or
 * a vertex cache's), each node once. */
static void crowd_find_nodes(sinew_renderer *r)
{
    const sinew_model *m = r->model;
    for (uint32_t i = 0; i < m->instance_count; i++) {
        const sinew_mesh *mesh = &m->meshes[m->instances[i].mesh];
        uint32_t node = m->instances[i].node, k = 0;
        if (mesh_is_skinned(mesh) && !mesh->cache) {
            r->crowd_place[i] = UINT32_MAX;
            continue;
        }
        while (k < r->crowd_node_count && r->crowd_nodes[k] != node)
            k++;
        if (k == r->crowd_node_count)
            r->crowd_nodes[r->crowd_node_count++] = node;
        r->crowd_place[i] = k;
    }
}

/* Characters a crowd draw call holds at most. */
#define CROWD_BATCH 64u

/* Records a crowd character takes: its palettes (matrices, then dual-quaternion joints when a
 * skin needs them), then the world matrices of the nodes its placed meshes hang from. */
static uint32_t crowd_palette_records(const sinew_renderer *r)
{
    return r->total_joints * (r->any_dq ? 2u : 1u);
}

static uint32_t crowd_stride(const sinew_renderer *r)
{
    return crowd_palette_records(r) + r->crowd_node_count;
}

typedef struct crowd_work {
    sinew_renderer *r;
    const sinew_mat4 *worlds;
} crowd_work;

/* The node that stands for a character's position (the one nearest the middle of the rest
 * pose's bounds) and the bounds' radius, found once. */
static void crowd_extent(sinew_renderer *r, const frame_state *fs)
{
    const sinew_model *m = r->model;
    r->crowd_center = 0;
    r->crowd_radius = 0.0f;
    r->crowd_triangles = 0;
    for (uint32_t i = 0; i < m->instance_count; i++)
        r->crowd_triangles += m->meshes[m->instances[i].mesh].index_count / 3;
    sinew_mat4 *rest = r->allocator.alloc(((size_t)m->node_count + 1) * sizeof *rest, r->allocator.user);
    float lo[3], hi[3];
    /* the frame's own options, weights and cache time: the bounds set them in the renderer, and
     * the crowd is drawn with them after (the default options' weights were none: no morphs) */
    sinew_frame frame = *fs->frame;
    frame.worlds = rest, frame.world_count = m->node_count, frame.crowd_count = 0;
    if (rest && sinew_local_to_world(m, m->node_rest, m->node_count, NULL, rest, m->node_count, NULL) == SINEW_OK &&
        sinew_renderer_frame_bounds(r, &frame, lo, hi)) {
        float mid[3] = {(lo[0] + hi[0]) * 0.5f, (lo[1] + hi[1]) * 0.5f, (lo[2] + hi[2]) * 0.5f}, best = INFINITY;
        r->crowd_radius = 0.5f * sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
        for (uint32_t i = 0; i < m->node_count; i++) {
            const float *p = rest[i].m + 12;
            float d = (p[0] - mid[0]) * (p[0] - mid[0]) + (p[1] - mid[1]) * (p[1] - mid[1]) +
                      (p[2] - mid[2]) * (p[2] - mid[2]);
            if (d < best)
                best = d, r->crowd_center = i;
        }
    }
    if (rest)
        r->allocator.free(rest, r->allocator.user);
}

/* Each character's level of detail from its size on screen (all 0 without levels), and its
 * place among the records: level 0's characters first, then level 1's, ...; start[l] and
 * count[l] give each level's range. */
static void crowd_levels(sinew_renderer *r, const frame_state *fs, uint32_t start[RENDER_LOD_LEVELS],
                         uint32_t count[RENDER_LOD_LEVELS])
{
    const sinew_frame *frame = fs->frame;
    const uint32_t n = r->model->node_count;
    bool lod = !fs->o->crowd_full_detail;
    if (lod && r->crowd_radius < 0.0f)
        crowd_extent(r, fs);
    for (int l = 0; l < RENDER_LOD_LEVELS; l++)
        count[l] = 0;
    for (uint32_t c = 0; c < frame->crowd_count; c++) {
        int level = 0;
        if (lod && r->crowd_radius > 0.0f) {
            const float *p = frame->crowd_worlds[(size_t)c * n + r->crowd_center].m + 12, *vp = fs->view_proj;
            float w = vp[3] * p[0] + vp[7] * p[1] + vp[11] * p[2] + vp[15];
            /* the sphere's radius in pixels: radius * proj[1][1] / w, half the viewport high */
            level = w > 0.0f ? render_lod_level(r->crowd_radius * fs->proj11 / w * 0.5f * (float)frame->height,
                                                r->crowd_triangles, r->crowd_far_error)
                             : RENDER_LOD_LEVELS - 1;
        }
        r->crowd_level[c] = (uint8_t)level;
        count[level]++;
    }
    for (int l = 0, at = 0; l < RENDER_LOD_LEVELS; at += (int)count[l], l++)
        start[l] = (uint32_t)at;
    uint32_t next[RENDER_LOD_LEVELS];
    memcpy(next, start, sizeof next);
    for (uint32_t c = 0; c < frame->crowd_count; c++)
        r->crowd_slot[c] = next[r->crowd_level[c]]++;
}

/* The mesh's levels of detail, made and uploaded the first time a crowd asks for them. */
static sinew_result crowd_lods(sinew_renderer *r, const sinew_mesh *mesh, render_mesh *rm, sinew_error *error)
{
    if (rm->lod_built)
        return SINEW_OK;
    uint32_t *indices;
    char why[300] = "";
    if (!render_lod_build(mesh, &r->allocator, &indices, &rm->lod, why, sizeof why))
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory simplifying mesh \"%s\"",
                          r->model->source, mesh->name);
    rm->lod_built = true;
    if (why[0] && !r->lod_warned) { /* once: every mesh is drawn whole, and crowds cost many times more */
        r->lod_warned = true;
        warn(r, "crowds are drawn without levels of detail (every character whole): %s", why);
    }
    if (!indices)
        return SINEW_OK;
    glBindVertexArray(rm->vao_static); /* the element buffer is the VAOs' state: both share it */
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, rm->indices);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)rm->lod.total * 4, indices, GL_STATIC_DRAW);
    /* levels 1.. on their own vertices, for the GPU path */
    rm->lod_meshes = r->allocator.alloc((RENDER_LOD_LEVELS - 1) * sizeof *rm->lod_meshes, r->allocator.user);
    void *scratch = r->allocator.alloc((size_t)mesh->vertex_count * 24 + 16, r->allocator.user);
    bool ok = rm->lod_meshes && scratch;
    if (rm->lod_meshes)
        memset(rm->lod_meshes, 0, (RENDER_LOD_LEVELS - 1) * sizeof *rm->lod_meshes);
    for (int l = 1; ok && l < RENDER_LOD_LEVELS; l++) {
        sinew_mesh level;
        void *memory;
        ok = render_lod_compact(mesh, indices + rm->lod.first[l], rm->lod.count[l], &r->allocator, &level, &memory);
        if (ok) {
            upload_mesh(&rm->lod_meshes[l - 1], &level, scratch, false);
            r->allocator.free(memory, r->allocator.user);
        }
    }
    r->allocator.free(indices, r->allocator.user);
    if (scratch)
        r->allocator.free(scratch, r->allocator.user);
    if (!ok)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for the levels of mesh \"%s\"",
                          r->model->source, mesh->name);
    return SINEW_OK;
}

/* Palettes (matrices, and dual-quaternion joints after them when a skin needs them) and placed
 * nodes' worlds of a range of characters. */
static void crowd_records(void *user, uint32_t first, uint32_t count, uint32_t thread)
{
    (void)thread;
    crowd_work *w = user;
    sinew_renderer *r = w->r;
    const sinew_model *m = r->model;
    uint32_t stride = crowd_stride(r), palette = crowd_palette_records(r);
    for (uint32_t c = first; c < first + count; c++) {
        sinew_mat4 *block = r->crowd_records + (size_t)r->crowd_slot[c] * stride;
        const sinew_mat4 *worlds = w->worlds + (size_t)c * m->node_count;
        for (uint32_t s = 0; s < m->skin_count; s++)
            sinew_skin_palette(&m->skins[s], worlds, m->node_count, block + r->skin_offsets[s], m->skins[s].joint_count,
                               NULL);
        if (r->any_dq)
            sinew_skin_dq_palette(block, r->total_joints, (sinew_dq_joint *)(block + r->total_joints), NULL);
        for (uint32_t k = 0; k < r->crowd_node_count; k++)
            block[palette + k] = worlds[r->crowd_nodes[k]];
    }
}

/* Makes room for `count` characters' records, CPU and GPU side. */
static sinew_result crowd_reserve(sinew_renderer *r, uint32_t count, sinew_error *error)
{
    size_t bytes = (size_t)count * crowd_stride(r) * sizeof(sinew_mat4);
    if (bytes / 16 > r->max_buffer_texels)
        return sinew_fail(error, SINEW_ERROR_LIMIT,
                          "%s: a crowd of %u characters needs %zu texels of palettes, GL_MAX_TEXTURE_BUFFER_SIZE is %u",
                          r->model->source, count, bytes / 16, r->max_buffer_texels);
    if (count <= r->crowd_capacity)
        return SINEW_OK;
    sinew_mat4 *records = r->allocator.alloc(bytes, r->allocator.user);
    uint32_t *slots = r->allocator.alloc((size_t)count * (sizeof(uint32_t) + 1) + 16, r->allocator.user);
    if (!records || !slots) {
        if (records)
            r->allocator.free(records, r->allocator.user);
        if (slots)
            r->allocator.free(slots, r->allocator.user);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory for a crowd of %u characters",
                          r->model->source, count);
    }
    if (r->crowd_records)
        r->allocator.free(r->crowd_records, r->allocator.user);
    if (r->crowd_slot)
        r->allocator.free(r->crowd_slot, r->allocator.user);
    r->crowd_records = records;
    r->crowd_slot = slots;
    r->crowd_level = (uint8_t *)(slots + count);
    r->crowd_capacity = count;
    if (!r->crowd_buffer) {
        glGenBuffers(1, &r->crowd_buffer);
        glGenTextures(1, &r->crowd_texture);
    }
    glBindBuffer(GL_TEXTURE_BUFFER, r->crowd_buffer);
    glBufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)bytes, NULL, GL_STREAM_DRAW);
    glBindTexture(GL_TEXTURE_BUFFER, r->crowd_texture);
    glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, r->crowd_buffer);
    return SINEW_OK;
}

/* Vertices a CPU-skinned crowd streams at once (bytes): a batch of characters, each skinned on
 * one of the frame's threads and copied into the mapped buffer, then drawn one after another. */
#define CROWD_STREAM_BYTES ((size_t)32 << 20)

typedef struct crowd_skin_work {
    sinew_renderer *r;
    const sinew_mesh *mesh;
    bool morphed;   /* r->morphed holds the mesh morphed by the frame's weights */
    uint32_t first; /* the batch's first character */
    float *mapped;  /* the batch's vertices, character after character (write-only memory) */
} crowd_skin_work;

static void crowd_skin_job(void *user, uint32_t first, uint32_t count, uint32_t thread)
{
    const crowd_skin_work *w = user;
    const sinew_renderer *r = w->r;
    size_t n = w->mesh->vertex_count, floats = n * STREAM_FLOATS;
    float *out = r->crowd_stream + (size_t)thread * r->crowd_stream_room;
    for (uint32_t k = first; k < first + count; k++) {
        const sinew_mat4 *block = r->crowd_records + (size_t)r->crowd_slot[w->first + k] * crowd_stride(r);
        sinew_skin_desc d =
            stream_skin_desc(r, w->mesh, w->morphed, block, (const sinew_dq_joint *)(block + r->total_joints), out);
        sinew_skin_vertices(&d, NULL); /* cannot fail: the model's joints were checked when it was loaded */
        memcpy(w->mapped + k * floats, out, floats * sizeof(float));
    }
}

/* One CPU-skinned mesh of every character: morphed once (the frame's weights, shared), then in
 * batches: the batch's characters skinned on the frame's threads straight into the stream
 * buffer (mapped, its old contents dropped, so no wait for the last batch's draws), then drawn,
 * each from its own range (base vertex). Without a mapping, character after character. */
static sinew_result draw_crowd_cpu_mesh(sinew_renderer *r, const frame_state *fs, const sinew_mesh *mesh,
                                        render_mesh *rm, uint32_t morphs, sinew_error *error)
{
    const mesh_uniforms *u = &r->mesh_u;
    const sinew_frame *frame = fs->frame;
    uint32_t stride = crowd_stride(r), n = mesh->vertex_count;
    uint32_t threads = frame->jobs ? sinew_jobs_threads(frame->jobs) : 1;
    glBindVertexArray(rm->vao_stream);
    glBindBuffer(GL_ARRAY_BUFFER, rm->buffers[BUF_STREAM]);
    glUniform1i(u->gpu_sets, 0);
    glUniform1i(u->instance_stride, 0);
    glUniform1i(u->rigid_record, -1);
    rm->streamed = 0; /* BUF_STREAM no longer holds one character's vertices */
    size_t floats = (size_t)n * STREAM_FLOATS;
    if (r->crowd_stream_room < floats || r->crowd_stream_threads < threads) { /* a stream for each thread */
        if (r->crowd_stream)
            r->allocator.free(r->crowd_stream, r->allocator.user);
        r->crowd_stream = r->allocator.alloc(floats * threads * sizeof(float), r->allocator.user);
        r->crowd_stream_room = r->crowd_stream ? floats : 0;
        r->crowd_stream_threads = r->crowd_stream ? threads : 0;
    }
    bool morphed = morphs > 0;
    sinew_result result = morphed ? morph_scratch(r, mesh, error) : SINEW_OK;
    if (result != SINEW_OK)
        return result;
    uint32_t batch = (uint32_t)(CROWD_STREAM_BYTES / ((size_t)n * STREAM_STRIDE + 1));
    batch = batch < 1 ? 1 : batch > frame->crowd_count ? frame->crowd_count : batch;
    if (batch > rm->stream_room) {
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)batch * n * STREAM_STRIDE), NULL, GL_STREAM_DRAW);
        rm->stream_room = batch;
    }
    for (uint32_t first = 0; first < frame->crowd_count; first += batch) {
        uint32_t count = frame->crowd_count - first < batch ? frame->crowd_count - first : batch;
        crowd_skin_work w = {r, mesh, morphed, first, NULL};
        if (r->crowd_stream)
            w.mapped = glMapBufferRange(GL_ARRAY_BUFFER, 0, (GLsizeiptr)((size_t)count * n * STREAM_STRIDE),
                                        GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
        if (w.mapped) {
            sinew_jobs_run(frame->jobs, count, 1, crowd_skin_job, &w);
            if (glUnmapBuffer(GL_ARRAY_BUFFER) != GL_TRUE)
                w.mapped = NULL; /* the mapping's memory was lost: character after character */
        }
        for (uint32_t k = 0; k < count; k++) {
            uint32_t c = first + k, base = 0;
            if (!w.mapped) {
                const sinew_mat4 *block = r->crowd_records + (size_t)r->crowd_slot[c] * stride;
                if ((result = skin_stream(r, mesh, morphed, block, (const sinew_dq_joint *)(block + r->total_joints),
                                          frame->jobs, error)))
                    return result;
                glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)n * STREAM_STRIDE, r->stream);
            } else {
                base = k * n;
            }
            int level = r->crowd_level[c];
            glDrawElementsBaseVertex(GL_TRIANGLES, (GLsizei)rm->lod.count[level], GL_UNSIGNED_INT,
                                     (const void *)((uintptr_t)rm->lod.first[level] * 4), (GLint)base);
        }
    }
    return SINEW_OK;
}

/* Every instance of the model for every character: one instanced draw a mesh. */
static sinew_result draw_crowd(sinew_renderer *r, const frame_state *fs, sinew_error *error)
{
    const sinew_model *m = r->model;
    const sinew_frame *frame = fs->frame;
    sinew_result result = crowd_reserve(r, frame->crowd_count, error);
    if (result != SINEW_OK)
        return result;
    for (uint32_t i = 0; i < m->instance_count; i++) { /* every mesh's levels, once (those without: the full list) */
        render_mesh *rm = &r->meshes[m->instances[i].mesh];
        if (!fs->o->crowd_full_detail)
            result = crowd_lods(r, &m->meshes[m->instances[i].mesh], rm, error);
        else if (!rm->lod_built)
            for (int l = 0; l < RENDER_LOD_LEVELS; l++)
                rm->lod.first[l] = 0, rm->lod.count[l] = m->meshes[m->instances[i].mesh].index_count;
        if (result != SINEW_OK)
            return result;
        if (rm->lod.far_error > r->crowd_far_error)
            r->crowd_far_error = rm->lod.far_error;
    }
    uint32_t level_start[RENDER_LOD_LEVELS], level_count[RENDER_LOD_LEVELS];
    crowd_levels(r, fs, level_start, level_count);
    /* The records are uploaded with glBufferSubData, so that the driver keeps them in video
     * memory: written through a mapping (no second copy, 3.8 ms less of the CPU's frame for
     * 5,888 humanoids) they stayed in system memory, and the vertex shader's reads of them
     * made the GPU's frame a third slower (NVIDIA H200). */
    crowd_work work = {r, frame->crowd_worlds};
    sinew_jobs_run(frame->jobs, frame->crowd_count, 8, crowd_records, &work);
    uint32_t stride = crowd_stride(r);
    glBindBuffer(GL_TEXTURE_BUFFER, r->crowd_buffer);
    glBufferSubData(GL_TEXTURE_BUFFER, 0, (GLsizeiptr)((size_t)frame->crowd_count * stride * sizeof(sinew_mat4)),
                    r->crowd_records);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, r->crowd_texture);
    const mesh_uniforms *u = &r->mesh_u;
    static const float NONE[4] = {0, 0, 0, 0};
    begin_mesh_pass(r, fs, false);
    glUniform1i(u->heat_joint, -1);
    glUniform1f(u->heat_rigid, 0.0f);
    glUniform4fv(u->override, 1, NONE);
    glUniformMatrix4fv(u->model, 1, GL_FALSE, IDENTITY);
    for (uint32_t i = 0; i < m->instance_count; i++) {
        if (instance_hidden(fs->o, i))
            continue;
        const sinew_instance *inst = &m->instances[i];
        const sinew_mesh *mesh = &m->meshes[inst->mesh];
        render_mesh *rm = &r->meshes[inst->mesh];
        set_material(r, fs, mesh);
        uint32_t morphs = instance_targets(r, inst);
        bool cpu = on_cpu(r, fs->o, mesh, rm, morphs);
        bool placed = !mesh_is_skinned(mesh) || (mesh->cache && !r->no_cache);
        if (cpu && !placed) {
            result = draw_crowd_cpu_mesh(r, fs, mesh, rm, morphs, error);
            if (result != SINEW_OK)
                return result;
            continue;
        }
        glUniform1i(u->morph_count, 0);
        if (cpu) { /* a placed mesh the CPU morphs or caches: the same vertices for every character */
            result = fill_stream(r, mesh, morphs, r->palettes, r->dq_palettes, NULL, error);
            if (result != SINEW_OK)
                return result;
            glBindBuffer(GL_ARRAY_BUFFER, rm->buffers[BUF_STREAM]);
            glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)mesh->vertex_count * STREAM_STRIDE, r->stream);
            rm->streamed = 0; /* not this frame's single-character vertices */
        } else {
            set_morph_uniforms(r, u, mesh, rm, morphs);
        }
        glUniform1i(u->instance_stride, (GLint)stride);
        if (!placed) {
            glUniform1i(u->gpu_sets, rm->influence_sets);
            glUniform1i(u->dq_mode, r->skin_mode[mesh->skin]);
            glUniform1i(u->palette_offset, (GLint)r->skin_offsets[mesh->skin]);
            glUniform1i(u->rigid_record, -1);
        } else {
            glUniform1i(u->gpu_sets, 0);
            glUniform1i(u->rigid_record, (GLint)(crowd_palette_records(r) + r->crowd_place[i]));
        }
        /* in batches: Mesa's software renderer shades all of a draw's vertices into one buffer
         * first, which grows past its caches (and costs page faults) with thousands of
         * instances; GPUs do not mind the extra draws */
        for (int l = 0; l < RENDER_LOD_LEVELS; l++) { /* each level's characters: a range of the records */
            /* levels 1.. on their own vertices when there are such; else ranges of the mesh's indices */
            const render_mesh *level = l && rm->lod_meshes && !cpu && !morphs ? &rm->lod_meshes[l - 1] : NULL;
            glBindVertexArray(level ? level->vao_static : cpu ? rm->vao_stream : rm->vao_static);
            uint32_t first = level ? 0 : rm->lod.first[l], count = rm->lod.count[l];
            for (uint32_t done = 0; done < level_count[l]; done += CROWD_BATCH) {
                uint32_t n = level_count[l] - done < CROWD_BATCH ? level_count[l] - done : CROWD_BATCH;
                glUniform1i(u->instance_base, (GLint)(level_start[l] + done));
                glDrawElementsInstanced(GL_TRIANGLES, (GLsizei)count, GL_UNSIGNED_INT,
                                        (const void *)((uintptr_t)first * 4), (GLsizei)n);
            }
        }
    }
    glUniform1i(u->instance_stride, 0);
    glUniform1i(u->rigid_record, -1);
    glUniform1i(u->instance_base, 0);
    set_alpha(u, NULL);
    return SINEW_OK;
}

sinew_result sinew_renderer_draw(sinew_renderer *r, const sinew_frame *frame, sinew_error *error)
{
    if (!r || !frame || !frame->camera || !frame->options || !frame->worlds)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_renderer_draw: missing frame fields");
    const sinew_model *m = r->model;
    if (frame->world_count < m->node_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_renderer_draw: %u world matrices for %u nodes",
                          frame->world_count, m->node_count);
    if (frame->width <= 0 || frame->height <= 0)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_renderer_draw: viewport %dx%d", frame->width,
                          frame->height);
    if (frame->crowd_count && !frame->crowd_worlds)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_renderer_draw: a crowd of %u without worlds",
                          frame->crowd_count);
    if (frame->weights && frame->weight_count < m->morph_channel_count)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_renderer_draw: %u weights for %u morph channels",
                          frame->weight_count, m->morph_channel_count);
    frame_state fs = {.frame = frame, .o = frame->options, .dq_offset = r->total_joints};
    r->frame++;
    r->weights = frame->weights;
    r->cache_time = frame->cache_time;
    r->no_cache = frame->no_cache;
    sinew_mat4 view, proj;
    sinew_camera_view(frame->camera, &view);
    sinew_camera_projection(frame->camera, (float)frame->width / (float)frame->height, &proj);
    glm_mat4_mul((vec4 *)proj.m, (vec4 *)view.m, (vec4 *)fs.view_proj);
    fs.proj11 = proj.m[5];
    camera_lights(frame->camera, &fs);

    choose_skin_modes(r, frame->options);
    sinew_result result = compute_palettes(r, frame->worlds, frame->world_count, error);
    if (result != SINEW_OK)
        return result;
    if (r->total_joints) {
        /* the matrices, then the dual-quaternion joints (64 bytes, as a matrix: 4 texels each) */
        glBindBuffer(GL_TEXTURE_BUFFER, r->palette_buffer);
        glBufferSubData(GL_TEXTURE_BUFFER, 0, (GLsizeiptr)r->total_joints * 64, r->palettes);
        if (r->any_dq)
            glBufferSubData(GL_TEXTURE_BUFFER, (GLintptr)r->total_joints * 64, (GLsizeiptr)r->total_joints * 64,
                            r->dq_palettes);
    }
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, r->palette_texture);

    render_effect_frame ef;
    result = render_effects_prepare(&r->fx, &ef, frame, fs.key, view.m, proj.m, frame->crowd_count > 0, error);
    if (result != SINEW_OK)
        return result;
    fs.fx = &r->fx;
    fs.ef = &ef;
    result = use_mesh_variant(r, &ef, error);
    if (result != SINEW_OK)
        return result;
    if (frame->muscle_count && !r->muscle_vao)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_renderer_draw: muscles in a frame of a renderer created without them");
    /* FXAA: the frame goes into a texture first, then smoothed into the caller's framebuffer */
    GLint target = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
    bool fxaa = frame->options->fxaa && render_effects_begin_fxaa(&r->fx, frame->width, frame->height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    glDisable(GL_SAMPLE_ALPHA_TO_ONE);
    result = draw_effect_passes(r, &fs, error);
    if (result != SINEW_OK)
        goto failed;

    float bg[3];
    sinew_render_options_background(frame->options, bg);
    glViewport(0, 0, frame->width, frame->height);
    if (frame->options->transparent) /* black: multisampled edges resolve to premultiplied colours */
        glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    else
        glClearColor(bg[0], bg[1], bg[2], 1.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    glDisable(GL_SAMPLE_ALPHA_TO_ONE);
    glEnable(GL_PROGRAM_POINT_SIZE);
    if (ef.background)
        render_effects_background(&r->fx, &r->programs, &ef);
    draw_overlay(r, &fs, true);
    if (ef.ground)
        render_effects_ground(&r->fx, &r->programs, &ef);
    if (frame->crowd_count) {
        result = !frame->options->hide_meshes ? draw_crowd(r, &fs, error) : SINEW_OK;
        if (result == SINEW_OK && frame->options->skeleton)
            draw_crowd_skeletons(r, &fs);
        if (fxaa)
            render_effects_fxaa(&r->fx, &r->programs, (GLuint)target, frame->width, frame->height);
        glBindVertexArray(0);
        glUseProgram(0);
        if (result != SINEW_OK)
            return result;
        GLenum crowd_error = glGetError();
        if (crowd_error != GL_NO_ERROR)
            return sinew_fail(error, SINEW_ERROR_GRAPHICS, "%s: OpenGL error 0x%04x while drawing a crowd", m->source,
                              crowd_error);
        return SINEW_OK;
    }
    if (!frame->options->hide_meshes) {
        result = draw_meshes(r, &fs, error);
        if (result == SINEW_OK && frame->options->normals) {
            float radius = frame->camera->scene_radius > 0.0f ? frame->camera->scene_radius : 1.0f;
            float length = frame->options->normal_length > 0.0f ? frame->options->normal_length : radius * 0.03f;
            result = draw_normals(r, &fs, length, error);
        }
        if (result != SINEW_OK)
            goto failed;
    }
    if (!frame->options->hide_muscles && frame->muscle_count) {
        result = draw_muscles(r, &fs, error);
        if (result != SINEW_OK)
            goto failed;
    }
    if (ef.outline)
        render_effects_outline(&r->fx, &r->programs, &ef);
    draw_overlay(r, &fs, false);
    if (fxaa)
        render_effects_fxaa(&r->fx, &r->programs, (GLuint)target, frame->width, frame->height);
    glBindVertexArray(0);
    glUseProgram(0);
    GLenum gl_error = glGetError();
    if (gl_error != GL_NO_ERROR)
        return sinew_fail(error, SINEW_ERROR_GRAPHICS, "%s: OpenGL error 0x%04x while drawing", m->source, gl_error);
    return SINEW_OK;
failed: /* the caller's framebuffer bound again */
    if (fxaa)
        glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
    glBindVertexArray(0);
    glUseProgram(0);
    return result;
}

/* ---- bounds --------------------------------------------------------------------------- */

static void grow(float min[3], float max[3], const float p[3])
{
    for (int i = 0; i < 3; i++) {
        if (p[i] < min[i])
            min[i] = p[i];
        if (p[i] > max[i])
            max[i] = p[i];
    }
}

bool sinew_renderer_frame_bounds(sinew_renderer *r, const sinew_frame *frame, float min[3], float max[3])
{
    const sinew_model *m = r->model;
    for (int i = 0; i < 3; i++)
        min[i] = INFINITY, max[i] = -INFINITY;
    if (!frame || !frame->worlds || frame->world_count < m->node_count || !frame->options ||
        (frame->weights && frame->weight_count < m->morph_channel_count))
        return false;
    const sinew_mat4 *worlds = frame->worlds;
    r->weights = frame->weights;
    r->cache_time = frame->cache_time;
    r->no_cache = frame->no_cache;
    choose_skin_modes(r, frame->options);
    if (compute_palettes(r, worlds, frame->world_count, NULL) != SINEW_OK)
        return false;
    bool any = false;
    for (uint32_t i = 0; i < m->instance_count; i++) {
        const sinew_instance *inst = &m->instances[i];
        const sinew_mesh *mesh = &m->meshes[inst->mesh];
        if (fill_stream(r, mesh, instance_targets(r, inst), r->palettes, r->dq_palettes, NULL, NULL) != SINEW_OK)
            continue;
        r->meshes[inst->mesh].streamed = 0; /* r->stream now holds the bounds' vertices */
        bool placed = !mesh_is_skinned(mesh) || (mesh->cache && !r->no_cache);
        const float *w = worlds[inst->node].m;
        for (uint32_t v = 0; v < mesh->vertex_count; v++) {
            const float *p = &r->stream[(size_t)v * STREAM_FLOATS];
            float q[3];
            for (int k = 0; k < 3; k++)
                q[k] = placed ? w[k] * p[0] + w[4 + k] * p[1] + w[8 + k] * p[2] + w[12 + k] : p[k];
            grow(min, max, q);
        }
        any = any || mesh->vertex_count > 0;
    }
    if (any)
        return true;
    /* Nothing with vertices (a skeleton-only file): the joints. */
    for (uint32_t n = 0; n < m->node_count; n++)
        if (r->skeleton_nodes[n]) {
            grow(min, max, &worlds[n].m[12]);
            any = true;
        }
    return any;
}

bool sinew_renderer_bounds(sinew_renderer *r, const sinew_mat4 *worlds, uint32_t world_count, float min[3],
                           float max[3])
{
    sinew_render_options o = sinew_render_options_default();
    sinew_frame frame = {.worlds = worlds, .world_count = world_count, .options = &o};
    return sinew_renderer_frame_bounds(r, &frame, min, max);
}
