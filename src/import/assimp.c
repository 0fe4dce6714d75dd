/* Assimp -> raw model.
 *
 * Index:
 *   read_nodes ........ the whole node hierarchy, depth first (parents before children)
 *   axis_conversion ... FBX files keep their up axis and unit in metadata: turn them into
 *                       a root transform (COLLADA's Assimp already folds them into the root)
 *   read_meshes ....... triangles, normals, UVs, a skin per skinned mesh (bone -> node by name,
 *                       offset matrix = inverse bind with the bind-shape matrix already in it),
 *                       anim meshes as morph targets (read_targets: offsets from the base)
 *   read_morph_keys ... mesh-morph animation channels as weight tracks
 *   read_clips ........ ticks -> seconds (ticks per second 0 falls back to 25), one track per node;
 *                       glTF STEP/CUBICSPLINE samplers are read again by gltf_keys.c, and
 *                       COLLADA <animation_clip>s cut out of Assimp's one clip by collada_clips.c
 *   raw_model_from_assimp
 */
#include <ctype.h>
#include <iconv.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/metadata.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cglm/cglm.h>

#include "../core/internal.h"
#include "internal.h"
#include "sinew/anim.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

/* The rate Assimp's own viewer assumes when a file gives none (aiAnimation::mTicksPerSecond 0). */
#define FALLBACK_TICKS_PER_SECOND 25.0

/* What Assimp does to the scene: triangles, shared vertices, normals where missing, and
 * its own consistency check. No LimitBoneWeights (sinew keeps up to 8 influences), no
 * FindInvalidData (it would hide NaN input that sinew must report). */
#define IMPORT_FLAGS                                                                                                   \
    (aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType | aiProcess_GenSmoothNormals |    \
     aiProcess_ValidateDataStructure)

typedef struct context {
    const char *path;
    const struct aiScene *scene;
    raw_model *model;
    const struct aiNode **nodes; /* sinew node index -> Assimp node */
    bool *joints;                /* nodes named by some bone, so far */
    sinew_error *error;
    uint32_t *mesh_of;    /* Assimp mesh -> raw mesh, UINT32_MAX for none */
    int32_t *morph_first; /* by raw mesh: its first morph channel, or -1 */
} context;

static sinew_result oom(context *c)
{
    return sinew_fail(c->error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory while importing", c->path);
}

static void to_mat4(const struct aiMatrix4x4 *a, sinew_mat4 *out)
{
    /* aiMatrix4x4 is row-major (a1..a4 is the first row); sinew is column-major. */
    const float rows[4][4] = {{a->a1, a->a2, a->a3, a->a4},
                              {a->b1, a->b2, a->b3, a->b4},
                              {a->c1, a->c2, a->c3, a->c4},
                              {a->d1, a->d2, a->d3, a->d4}};
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            out->m[c * 4 + r] = rows[r][c];
}

/* ---- nodes -------------------------------------------------------------------------------- */

static uint32_t count_nodes(const struct aiNode *node)
{
    uint32_t n = 1;
    for (unsigned i = 0; i < node->mNumChildren; i++)
        n += count_nodes(node->mChildren[i]);
    return n;
}

static bool add_node(context *c, const struct aiNode *node, int32_t parent, uint32_t *next)
{
    raw_model *m = c->model;
    uint32_t index = (*next)++;
    c->nodes[index] = node;
    m->node_parents[index] = parent;
    if (!(m->node_names[index] = raw_strdup(node->mName.data)))
        return false;
    sinew_mat4 local;
    to_mat4(&node->mTransformation, &local);
    sinew_mat4_decompose(&local, &m->node_rest[index]);
    for (unsigned i = 0; i < node->mNumChildren; i++)
        if (!add_node(c, node->mChildren[i], (int32_t)index, next))
            return false;
    return true;
}

static sinew_result read_nodes(context *c)
{
    raw_model *m = c->model;
    uint32_t n = count_nodes(c->scene->mRootNode);
    m->node_names = calloc(n, sizeof(char *));
    m->node_parents = calloc(n, sizeof(int32_t));
    m->node_rest = calloc(n, sizeof(sinew_transform));
    c->nodes = calloc(n, sizeof(*c->nodes));
    c->joints = calloc(n, sizeof(*c->joints));
    if (!m->node_names || !m->node_parents || !m->node_rest || !c->nodes || !c->joints)
        return oom(c);
    m->node_count = n;
    uint32_t next = 0;
    if (!add_node(c, c->scene->mRootNode, -1, &next))
        return oom(c);
    return SINEW_OK;
}

/* Nodes may share a name (robot.glb names mesh nodes after the bones they sit on), and
 * Assimp links bones and channels to nodes by name alone. Among several nodes of one name
 * sinew prefers, in order: a node already known to be a joint, a node whose parent is a
 * joint, a node that holds no mesh, the first in depth-first order. `joints` marks nodes already known to be joints
 * (may be NULL). Returns -1 when no node has the name; *ambiguous tells whether the rules
 * above had to pick. */
static int32_t find_node(const context *c, const char *name, const bool *joints, bool *ambiguous)
{
    int32_t best = -1, best_score = -1, matches = 0, best_ties = 0;
    for (uint32_t i = 0; i < c->model->node_count; i++) {
        if (strcmp(c->model->node_names[i], name) != 0)
            continue;
        matches++;
        int32_t parent = c->model->node_parents[i];
        int32_t score =
            (joints && joints[i]) * 4 + (joints && parent >= 0 && joints[parent]) * 2 + (c->nodes[i]->mNumMeshes == 0);
        if (score > best_score) {
            best = (int32_t)i;
            best_score = score;
            best_ties = 1;
        } else if (score == best_score) {
            best_ties++;
        }
    }
    if (ambiguous)
        *ambiguous = matches > 1 && best_ties > 1;
    return best;
}

static const struct aiMetadataEntry *metadata_find(const struct aiMetadata *meta, const char *key)
{
    for (unsigned i = 0; meta && i < meta->mNumProperties; i++)
        if (strcmp(meta->mKeys[i].data, key) == 0)
            return &meta->mValues[i];
    return NULL;
}

static bool metadata_int(const struct aiMetadata *meta, const char *key, int *out)
{
    const struct aiMetadataEntry *e = metadata_find(meta, key);
    if (!e || e->mType != AI_INT32)
        return false;
    *out = *(const int32_t *)e->mData;
    return true;
}

static bool metadata_real(const struct aiMetadata *meta, const char *key, double *out)
{
    const struct aiMetadataEntry *e = metadata_find(meta, key);
    if (e && e->mType == AI_FLOAT)
        *out = *(const float *)e->mData;
    else if (e && e->mType == AI_DOUBLE)
        *out = *(const double *)e->mData;
    else
        return false;
    return true;
}

/* FBX: Assimp reports the file's axes (UpAxis, FrontAxis, CoordAxis with signs) and its
 * unit (UnitScaleFactor, centimetres per unit) but applies neither. The conversion to
 * Y-up metres goes into the root node's rest transform. */
static void axis_conversion(context *c)
{
    const struct aiMetadata *meta = c->scene->mMetaData;
    int up, up_sign, front, front_sign, coord, coord_sign;
    if (!metadata_int(meta, "UpAxis", &up) || !metadata_int(meta, "UpAxisSign", &up_sign) ||
        !metadata_int(meta, "FrontAxis", &front) || !metadata_int(meta, "FrontAxisSign", &front_sign) ||
        !metadata_int(meta, "CoordAxis", &coord) || !metadata_int(meta, "CoordAxisSign", &coord_sign))
        return;
    if (up < 0 || up > 2 || front < 0 || front > 2 || coord < 0 || coord > 2 || up == front || up == coord ||
        front == coord) {
        raw_model_warn(c->model,
                       "the file's axis settings (up %d, front %d, coord %d) are inconsistent; axes left as they are",
                       up, front, coord);
        return;
    }
    double unit_cm = 1.0;
    if (!metadata_real(meta, "UnitScaleFactor", &unit_cm) || !(unit_cm > 0.0) || !isfinite(unit_cm))
        unit_cm = 1.0;
    float scale = (float)(unit_cm / 100.0);
    /* new x = coord axis, new y = up axis, new z = front axis */
    sinew_mat4 conv = {{0}};
    conv.m[coord * 4 + 0] = (float)(coord_sign < 0 ? -1 : 1) * scale;
    conv.m[up * 4 + 1] = (float)(up_sign < 0 ? -1 : 1) * scale;
    conv.m[front * 4 + 2] = (float)(front_sign < 0 ? -1 : 1) * scale;
    conv.m[15] = 1.0f;

    bool identity = true;
    for (int i = 0; i < 16; i++)
        identity &= fabsf(conv.m[i] - ((i % 5 == 0) ? 1.0f : 0.0f)) < 1e-7f;
    if (identity)
        return;
    sinew_mat4 root, converted;
    sinew_transform_to_mat4(&c->model->node_rest[0], &root);
    glm_mat4_mul((vec4 *)conv.m, (vec4 *)root.m, (vec4 *)converted.m);
    sinew_mat4_decompose(&converted, &c->model->node_rest[0]);
}

/* ---- materials ---------------------------------------------------------------------------- */

static char *find_texture(context *c, const char *texture);

/* The image Assimp holds for a texture reference: "*N" (glTF, FBX, 3MF, ...) or a name
 * that one of the scene's embedded textures carries; NULL when the file does not embed it. */
static const struct aiTexture *embedded_texture(const struct aiScene *s, const char *texture)
{
    if (texture[0] == '*') {
        char *end;
        unsigned long i = strtoul(texture + 1, &end, 10);
        return *end == 0 && i < s->mNumTextures ? s->mTextures[i] : NULL;
    }
    for (unsigned i = 0; i < s->mNumTextures; i++)
        if (s->mTextures[i] && s->mTextures[i]->mFilename.length &&
            strcmp(s->mTextures[i]->mFilename.data, texture) == 0)
            return s->mTextures[i];
    return NULL;
}

/* The material's texture: an image the file embeds (its encoded bytes), else the file it
 * names, found beside the model when the stored path fails. */
static sinew_result resolve_texture(context *c, const char *texture, raw_texture *out)
{
    const struct aiTexture *t = embedded_texture(c->scene, texture);
    if (t) {
        /* mHeight 0: mWidth bytes of a compressed image (PNG, JPEG, ...); else raw texels */
        if (t->mHeight != 0 || !t->pcData || t->mWidth == 0 || t->mWidth > (1u << 28))
            return raw_model_warn(c->model,
                                  "embedded texture \"%s\" is stored as %ux%u raw texels, which sinew does not "
                                  "carry; the material keeps its colour",
                                  texture, t->mWidth, t->mHeight)
                       ? SINEW_OK
                       : oom(c);
        if (!(out->image = malloc(t->mWidth)))
            return oom(c);
        memcpy(out->image, t->pcData, t->mWidth);
        out->image_size = t->mWidth;
        return SINEW_OK;
    }
    if (texture[0] == '*')
        return raw_model_warn(c->model, "texture \"%s\" names an embedded image the file does not have", texture)
                   ? SINEW_OK
                   : oom(c);
    out->path = find_texture(c, texture);
    return SINEW_OK;
}

static char *find_texture(context *c, const char *texture)
{
    char looked[8192];
    char *path = import_find_texture(c->path, texture, false, looked, sizeof looked);
    if (!path)
        raw_model_warn(c->model, "texture \"%s\" not found (looked for %s)", texture, looked);
    return path;
}

static sinew_result read_materials(context *c)
{
    raw_model *m = c->model;
    const struct aiScene *s = c->scene;
    if (s->mNumMaterials == 0)
        return SINEW_OK;
    if (!(m->materials = calloc(s->mNumMaterials, sizeof *m->materials)))
        return oom(c);
    m->material_count = s->mNumMaterials;
    for (unsigned i = 0; i < s->mNumMaterials; i++) {
        const struct aiMaterial *mat = s->mMaterials[i];
        raw_material *out = &m->materials[i];
        struct aiString name = {0};
        char fallback[32];
        snprintf(fallback, sizeof fallback, "material %u", i);
        out->name = raw_strdup(aiGetMaterialString(mat, AI_MATKEY_NAME, &name) == AI_SUCCESS && name.length ? name.data
                                                                                                            : fallback);
        if (!out->name)
            return oom(c);
        struct aiColor4D color = {0.8f, 0.8f, 0.8f, 1.0f};
        if (aiGetMaterialColor(mat, AI_MATKEY_BASE_COLOR, &color) != AI_SUCCESS)
            aiGetMaterialColor(mat, AI_MATKEY_COLOR_DIFFUSE, &color);
        float opacity = 1.0f;
        if (aiGetMaterialFloatArray(mat, AI_MATKEY_OPACITY, &opacity, NULL) == AI_SUCCESS && opacity >= 0.0f &&
            opacity <= 1.0f)
            color.a *= opacity;
        float rgba[4] = {color.r, color.g, color.b, color.a};
        for (int k = 0; k < 4; k++)
            out->base_color[k] = isfinite(rgba[k]) ? rgba[k] : 1.0f;
        ai_real value = 0;
        bool metallic = aiGetMaterialFloatArray(mat, AI_MATKEY_METALLIC_FACTOR, &value, NULL) == AI_SUCCESS;
        out->metallic = metallic ? (float)value : 0.0f;
        bool roughness = aiGetMaterialFloatArray(mat, AI_MATKEY_ROUGHNESS_FACTOR, &value, NULL) == AI_SUCCESS;
        if (roughness)
            out->roughness = (float)value;
        else if (aiGetMaterialFloatArray(mat, AI_MATKEY_SHININESS, &value, NULL) == AI_SUCCESS)
            out->roughness = import_roughness_of_shininess(value);
        out->metallic_roughness = metallic || roughness;
        struct aiColor4D emissive = {0, 0, 0, 1};
        if (aiGetMaterialColor(mat, AI_MATKEY_COLOR_EMISSIVE, &emissive) == AI_SUCCESS) {
            out->emissive[0] = emissive.r, out->emissive[1] = emissive.g, out->emissive[2] = emissive.b;
        }
        /* the maps sinew shades with, each from the first texture type that has one */
        static const enum aiTextureType types[][2] = {
            [SINEW_MAP_BASE_COLOR] = {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR},
            [SINEW_MAP_METALLIC_ROUGHNESS] = {aiTextureType_UNKNOWN, aiTextureType_UNKNOWN}, /* glTF's packing */
            [SINEW_MAP_NORMAL] = {aiTextureType_NORMALS, aiTextureType_NORMAL_CAMERA},
            [SINEW_MAP_OCCLUSION] = {aiTextureType_AMBIENT_OCCLUSION, aiTextureType_LIGHTMAP},
            [SINEW_MAP_EMISSIVE] = {aiTextureType_EMISSIVE, aiTextureType_EMISSION_COLOR}};
        for (int k = 0; k < SINEW_MAP_COUNT; k++) {
            if (k == SINEW_MAP_METALLIC_ROUGHNESS && !out->metallic_roughness)
                continue; /* an "unknown" texture means glTF's packing only beside PBR factors */
            for (int t = 0; t < 2; t++) {
                struct aiString texture = {0};
                if (aiGetMaterialTexture(mat, types[k][t], 0, &texture, NULL, NULL, NULL, NULL, NULL, NULL) !=
                        AI_SUCCESS ||
                    !texture.length)
                    continue;
                sinew_result r = resolve_texture(c, texture.data, &out->maps[k]);
                if (r)
                    return r;
                break;
            }
        }
    }
    return SINEW_OK;
}

/* ---- meshes ------------------------------------------------------------------------------- */

/* Assimp's SkeletonMeshBuilder adds a mesh that draws the bones of skeleton-only files
 * (BVH, animation-only COLLADA); it uses this material name. */
static bool is_dummy_skeleton_mesh(const struct aiScene *s, const struct aiMesh *mesh)
{
    struct aiString name = {0};
    if (mesh->mMaterialIndex >= s->mNumMaterials)
        return false;
    return aiGetMaterialString(s->mMaterials[mesh->mMaterialIndex], AI_MATKEY_NAME, &name) == AI_SUCCESS &&
           strcmp(name.data, "SkeletonMaterial") == 0 && s->mNumMeshes == 1;
}

/* Marks the nodes that bones name as joints: unambiguous names first, then names shared
 * by several nodes, resolved with what is known (a few passes, since each choice can
 * settle the next). */
static void mark_joints(context *c)
{
    const struct aiScene *s = c->scene;
    for (int pass = 0; pass < 4; pass++) {
        for (unsigned m = 0; m < s->mNumMeshes; m++) {
            for (unsigned b = 0; b < s->mMeshes[m]->mNumBones; b++) {
                bool ambiguous = false;
                int32_t node = find_node(c, s->mMeshes[m]->mBones[b]->mName.data, pass ? c->joints : NULL, &ambiguous);
                if (node >= 0 && (pass > 0 || !ambiguous))
                    c->joints[node] = true;
            }
        }
    }
}

/* True when a node of this name holds one of the scene's cameras or lights. */
static bool names_camera_or_light(const struct aiScene *s, const char *name)
{
    for (unsigned i = 0; i < s->mNumCameras; i++)
        if (strcmp(s->mCameras[i]->mName.data, name) == 0)
            return true;
    for (unsigned i = 0; i < s->mNumLights; i++)
        if (strcmp(s->mLights[i]->mName.data, name) == 0)
            return true;
    return false;
}

static bool is_animated(const struct aiScene *s, const char *name)
{
    for (unsigned a = 0; a < s->mNumAnimations; a++)
        for (unsigned k = 0; k < s->mAnimations[a]->mNumChannels; k++)
            if (strcmp(s->mAnimations[a]->mChannels[k]->mNodeName.data, name) == 0)
                return true;
    return false;
}

/* True when a clip moves this node or a node below it. */
static bool moves_subtree(const struct aiScene *s, const struct aiNode *node)
{
    if (is_animated(s, node->mName.data))
        return true;
    for (unsigned i = 0; i < node->mNumChildren; i++)
        if (moves_subtree(s, node->mChildren[i]))
            return true;
    return false;
}

/* Whether a bone of Assimp's generated skeleton mesh (one bone a node) is part of the
 * skeleton: not a camera or light, and, when the file has clips, moved by one of them
 * (itself or below it) or hanging from a moved node (BVH end sites), which leaves out
 * helpers such as 3ds Max's sky light and camera targets. */
static bool in_generated_skeleton(const context *c, const char *name, int32_t node)
{
    if (names_camera_or_light(c->scene, name))
        return false;
    if (c->scene->mNumAnimations == 0 || node < 0)
        return true;
    const struct aiNode *n = c->nodes[node];
    return moves_subtree(c->scene, n) || (n->mParent && is_animated(c->scene, n->mParent->mName.data));
}

/* A skin from a mesh's bone list: each bone's node, and Assimp's offset matrix (mesh space
 * to bone space at bind time, with COLLADA's bind-shape matrix already multiplied in) used
 * once, as the inverse bind matrix. joint_of_bone gets each bone's joint index, or -1 for
 * a bone that names no node (its weights are dropped). `skeleton_only`: the mesh is
 * Assimp's generated bone mesh, whose bones are every node, cameras and lights included;
 * only the skeleton's nodes are kept (in_generated_skeleton). */
static sinew_result add_skin(context *c, const struct aiMesh *in, const char *mesh_name, bool skeleton_only,
                             int32_t *joint_of_bone, int32_t *skin_index)
{
    raw_model *m = c->model;
    raw_skin *grown = realloc(m->skins, (m->skin_count + 1) * sizeof *grown);
    if (!grown)
        return oom(c);
    m->skins = grown;
    raw_skin *skin = &m->skins[m->skin_count];
    *skin = (raw_skin){0};
    *skin_index = (int32_t)m->skin_count++;
    skin->joints = calloc(in->mNumBones, sizeof *skin->joints);
    skin->inverse_bind = calloc(in->mNumBones, sizeof *skin->inverse_bind);
    if (!skin->joints || !skin->inverse_bind)
        return oom(c);
    for (unsigned b = 0; b < in->mNumBones; b++) {
        const struct aiBone *bone = in->mBones[b];
        bool ambiguous = false;
        int32_t node = find_node(c, bone->mName.data, c->joints, &ambiguous);
        joint_of_bone[b] = -1;
        if (skeleton_only && !in_generated_skeleton(c, bone->mName.data, node))
            continue;
        if (node < 0) {
            raw_model_warn(m, "mesh \"%s\": bone \"%s\" names no node; its weights are dropped", mesh_name,
                           bone->mName.data);
            continue;
        }
        if (ambiguous)
            raw_model_warn(m, "mesh \"%s\": bone \"%s\" names several nodes; the first was taken", mesh_name,
                           bone->mName.data);
        joint_of_bone[b] = (int32_t)skin->joint_count;
        skin->joints[skin->joint_count] = (uint32_t)node;
        to_mat4(&bone->mOffsetMatrix, &skin->inverse_bind[skin->joint_count]);
        skin->joint_count++;
    }
    return SINEW_OK;
}

/* Per-vertex influence slots from the bones' weight lists; empty slots hold UINT32_MAX. */
static sinew_result read_influences(context *c, const struct aiMesh *in, const int32_t *joint_of_bone, raw_mesh *out)
{
    uint32_t *counts = calloc(in->mNumVertices ? in->mNumVertices : 1, sizeof *counts);
    if (!counts)
        return oom(c);
    uint32_t most = 0;
    for (unsigned b = 0; b < in->mNumBones; b++) {
        const struct aiBone *bone = in->mBones[b];
        for (unsigned w = 0; w < bone->mNumWeights; w++) {
            unsigned v = bone->mWeights[w].mVertexId;
            if (v >= in->mNumVertices) {
                free(counts);
                return sinew_fail(c->error, SINEW_ERROR_DATA, "%s: mesh \"%s\": bone \"%s\" weights vertex %u of %u",
                                  c->path, out->name, bone->mName.data, v, in->mNumVertices);
            }
            if (joint_of_bone[b] >= 0 && ++counts[v] > most)
                most = counts[v];
        }
    }
    out->influence_count = most ? most : 1;
    size_t slots = (size_t)in->mNumVertices * out->influence_count;
    out->joints = malloc((slots ? slots : 1) * sizeof *out->joints);
    out->weights = calloc(slots ? slots : 1, sizeof *out->weights);
    if (!out->joints || !out->weights) {
        free(counts);
        return oom(c);
    }
    for (size_t i = 0; i < slots; i++)
        out->joints[i] = UINT32_MAX;
    memset(counts, 0, in->mNumVertices * sizeof *counts);
    for (unsigned b = 0; b < in->mNumBones; b++) {
        if (joint_of_bone[b] < 0)
            continue;
        const struct aiBone *bone = in->mBones[b];
        for (unsigned w = 0; w < bone->mNumWeights; w++) {
            unsigned v = bone->mWeights[w].mVertexId;
            size_t slot = (size_t)v * out->influence_count + counts[v]++;
            out->joints[slot] = (uint32_t)joint_of_bone[b];
            out->weights[slot] = bone->mWeights[w].mWeight;
        }
    }
    free(counts);
    return SINEW_OK;
}

static sinew_result read_skin(context *c, const struct aiMesh *in, raw_mesh *out)
{
    int32_t *joint_of_bone = calloc(in->mNumBones, sizeof *joint_of_bone);
    if (!joint_of_bone)
        return oom(c);
    sinew_result r = add_skin(c, in, out->name, false, joint_of_bone, &out->skin);
    if (!r)
        r = read_influences(c, in, joint_of_bone, out);
    free(joint_of_bone);
    return r;
}

static sinew_result read_mesh(context *c, const struct aiMesh *in, uint32_t index, raw_mesh *out)
{
    char fallback[32];
    snprintf(fallback, sizeof fallback, "mesh %u", index);
    if (!(out->name = raw_strdup(in->mName.length ? in->mName.data : fallback)))
        return oom(c);
    uint32_t v = in->mNumVertices;
    out->vertex_count = v;
    out->material = in->mMaterialIndex < c->scene->mNumMaterials ? (int32_t)in->mMaterialIndex : -1;
    out->skin = -1;
    out->positions = malloc((v ? v : 1) * 3 * sizeof(float));
    if (!out->positions)
        return oom(c);
    for (uint32_t i = 0; i < v; i++)
        memcpy(&out->positions[i * 3], &in->mVertices[i], 3 * sizeof(float));
    if (in->mNormals) {
        if (!(out->normals = malloc((v ? v : 1) * 3 * sizeof(float))))
            return oom(c);
        for (uint32_t i = 0; i < v; i++)
            memcpy(&out->normals[i * 3], &in->mNormals[i], 3 * sizeof(float));
    }
    if (in->mTextureCoords[0]) {
        if (!(out->uvs = malloc((v ? v : 1) * 2 * sizeof(float))))
            return oom(c);
        for (uint32_t i = 0; i < v; i++) {
            out->uvs[i * 2] = in->mTextureCoords[0][i].x;
            out->uvs[i * 2 + 1] = in->mTextureCoords[0][i].y;
        }
    }
    if (in->mColors[0]) { /* sRGB, as painting tools write them */
        if (!(out->colors = malloc((v ? v : 1) * 4 * sizeof(float))))
            return oom(c);
        raw_colors_from_srgb(&in->mColors[0][0].r, 4, v, out->colors);
    }
    /* Tangents as the file has them (no aiProcess_CalcTangentSpace); handedness from the
     * bitangent, which Assimp keeps along +v. */
    if (in->mTangents && in->mBitangents && in->mNormals) {
        if (!(out->tangents = malloc((v ? v : 1) * 4 * sizeof(float))))
            return oom(c);
        for (uint32_t i = 0; i < v; i++) {
            const struct aiVector3D *n = &in->mNormals[i], *t = &in->mTangents[i], *b = &in->mBitangents[i];
            float x = n->y * t->z - n->z * t->y, y = n->z * t->x - n->x * t->z, z = n->x * t->y - n->y * t->x;
            float len = sqrtf(t->x * t->x + t->y * t->y + t->z * t->z);
            float inv = len > 0.0f ? 1.0f / len : 0.0f;
            out->tangents[i * 4] = t->x * inv, out->tangents[i * 4 + 1] = t->y * inv;
            out->tangents[i * 4 + 2] = t->z * inv;
            out->tangents[i * 4 + 3] = x * b->x + y * b->y + z * b->z < 0.0f ? -1.0f : 1.0f;
        }
    }
    uint32_t triangles = 0, other = 0;
    for (unsigned f = 0; f < in->mNumFaces; f++)
        in->mFaces[f].mNumIndices == 3 ? triangles++ : other++;
    if (other)
        raw_model_warn(c->model, "mesh \"%s\": %u line or point primitives are not drawn", out->name, other);
    if (!(out->indices = malloc((triangles ? triangles : 1) * 3 * sizeof(uint32_t))))
        return oom(c);
    for (unsigned f = 0; f < in->mNumFaces; f++) {
        const struct aiFace *face = &in->mFaces[f];
        if (face->mNumIndices != 3)
            continue;
        memcpy(&out->indices[out->index_count], face->mIndices, 3 * sizeof(uint32_t));
        out->index_count += 3;
    }
    return in->mNumBones ? read_skin(c, in, out) : SINEW_OK;
}

/* A mesh's anim meshes as morph targets: each one's vertices (and normals, tangents) less the
 * mesh's own, whatever the morphing method (COLLADA's NORMALIZED and RELATIVE blends are
 * both the base plus the weighted differences); a channel each, of the anim mesh's weight. */
static sinew_result read_targets(context *c, const struct aiMesh *in, uint32_t index, raw_mesh *out)
{
    raw_model *m = c->model;
    uint32_t n = in->mNumAnimMeshes, v = in->mNumVertices;
    if (n == 0 || !in->mAnimMeshes)
        return SINEW_OK;
    raw_morph_channel *channels = realloc(m->morph_channels, (m->morph_channel_count + n) * sizeof *channels);
    if (!channels)
        return oom(c);
    m->morph_channels = channels;
    if (!(out->targets = calloc(n, sizeof *out->targets)))
        return oom(c);
    c->morph_first[index] = (int32_t)m->morph_channel_count;
    for (uint32_t t = 0; t < n; t++) {
        const struct aiAnimMesh *am = in->mAnimMeshes[t];
        raw_morph_target *rt = &out->targets[out->target_count++];
        char fallback[32];
        snprintf(fallback, sizeof fallback, "target %u", t);
        const char *name = am && am->mName.length ? am->mName.data : fallback;
        if (!(rt->name = raw_strdup(name)))
            return oom(c);
        if (!am || !am->mVertices || am->mNumVertices != v)
            return sinew_fail(c->error, SINEW_ERROR_DATA,
                              "%s: mesh \"%s\": morph target \"%s\" has %u vertices, the mesh %u (they must have as "
                              "many)",
                              c->path, out->name, name, am ? am->mNumVertices : 0, v);
        rt->channel = t;
        rt->full_weight = 1.0f;
        rt->delta_count = v;
        rt->vertices = malloc((v ? v : 1) * sizeof *rt->vertices);
        rt->positions = malloc((v ? v : 1) * 3 * sizeof *rt->positions);
        bool normals = am->mNormals && in->mNormals, tangents = am->mTangents && in->mTangents;
        rt->normals = normals ? malloc((v ? v : 1) * 3 * sizeof *rt->normals) : NULL;
        rt->tangents = tangents ? malloc((v ? v : 1) * 3 * sizeof *rt->tangents) : NULL;
        if (!rt->vertices || !rt->positions || (normals && !rt->normals) || (tangents && !rt->tangents))
            return oom(c);
        for (uint32_t i = 0; i < v; i++) {
            rt->vertices[i] = i;
            const float *a = &am->mVertices[i].x, *b = &in->mVertices[i].x;
            for (int k = 0; k < 3; k++)
                rt->positions[i * 3 + k] = a[k] - b[k];
            for (int k = 0; normals && k < 3; k++)
                rt->normals[i * 3 + k] = (&am->mNormals[i].x)[k] - (&in->mNormals[i].x)[k];
            for (int k = 0; tangents && k < 3; k++)
                rt->tangents[i * 3 + k] = (&am->mTangents[i].x)[k] - (&in->mTangents[i].x)[k];
        }
        raw_morph_channel *ch = &m->morph_channels[m->morph_channel_count];
        ch->default_weight = isfinite(am->mWeight) ? am->mWeight : 0.0f;
        if (!(ch->name = raw_strdup(name)))
            return oom(c);
        m->morph_channel_count++;
    }
    return SINEW_OK;
}

static sinew_result read_instances(context *c, const uint32_t *mesh_map)
{
    raw_model *m = c->model;
    uint32_t count = 0;
    for (uint32_t n = 0; n < m->node_count; n++)
        count += c->nodes[n]->mNumMeshes;
    if (!(m->instances = calloc(count ? count : 1, sizeof *m->instances)))
        return oom(c);
    bool *used = calloc(m->mesh_count ? m->mesh_count : 1, sizeof *used);
    if (!used)
        return oom(c);
    for (uint32_t n = 0; n < m->node_count; n++) {
        for (unsigned k = 0; k < c->nodes[n]->mNumMeshes; k++) {
            unsigned src = c->nodes[n]->mMeshes[k];
            if (src >= c->scene->mNumMeshes || mesh_map[src] == UINT32_MAX)
                continue;
            int32_t first = c->morph_first[mesh_map[src]];
            m->instances[m->instance_count++] = (sinew_instance){mesh_map[src], n, first >= 0 ? (uint32_t)first : 0};
            used[mesh_map[src]] = true;
        }
    }
    for (uint32_t i = 0; i < m->mesh_count; i++)
        if (!used[i])
            raw_model_warn(m, "mesh \"%s\" is not placed at any node; it is not drawn", m->meshes[i].name);
    free(used);
    return SINEW_OK;
}

static sinew_result read_meshes(context *c)
{
    raw_model *m = c->model;
    const struct aiScene *s = c->scene;
    uint32_t *mesh_map = malloc((s->mNumMeshes ? s->mNumMeshes : 1) * sizeof *mesh_map);
    m->meshes = calloc(s->mNumMeshes ? s->mNumMeshes : 1, sizeof *m->meshes);
    c->morph_first = malloc((s->mNumMeshes ? s->mNumMeshes : 1) * sizeof *c->morph_first);
    if (!mesh_map || !m->meshes || !c->morph_first) {
        free(mesh_map);
        return oom(c);
    }
    for (unsigned i = 0; i < s->mNumMeshes; i++)
        c->morph_first[i] = -1;
    sinew_result result = SINEW_OK;
    for (unsigned i = 0; i < s->mNumMeshes; i++)
        mesh_map[i] = UINT32_MAX;
    mark_joints(c);
    for (unsigned i = 0; i < s->mNumMeshes && !result; i++) {
        const struct aiMesh *in = s->mMeshes[i];
        if (is_dummy_skeleton_mesh(s, in)) {
            /* Keep the skeleton it names as a skin with no mesh, so the joints stay joints. */
            int32_t *joint_of_bone = calloc(in->mNumBones ? in->mNumBones : 1, sizeof *joint_of_bone);
            int32_t skin;
            result = joint_of_bone ? add_skin(c, in, "skeleton", true, joint_of_bone, &skin) : oom(c);
            free(joint_of_bone);
            if (!result)
                raw_model_warn(m,
                               "skeleton-only file: Assimp's generated bone mesh was dropped; its %u joints are kept",
                               m->skins[skin].joint_count);
            continue;
        }
        if (!(in->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
            raw_model_warn(m, "mesh \"%s\" has only lines or points; it is not drawn", in->mName.data);
            continue;
        }
        mesh_map[i] = m->mesh_count++;
        result = read_mesh(c, in, i, &m->meshes[mesh_map[i]]);
        if (!result)
            result = read_targets(c, in, mesh_map[i], &m->meshes[mesh_map[i]]);
    }
    if (!result)
        result = read_instances(c, mesh_map);
    c->mesh_of = mesh_map;
    return result;
}

/* ---- clips -------------------------------------------------------------------------------- */

static sinew_result read_vector_keys(context *c, const struct aiVectorKey *keys, unsigned count, double tps,
                                     raw_channel *out)
{
    out->interp = SINEW_INTERP_LINEAR;
    out->count = count;
    out->times = malloc((count ? count : 1) * sizeof(float));
    out->values = malloc((count ? count : 1) * 3 * sizeof(float));
    if (!out->times || !out->values)
        return oom(c);
    for (unsigned k = 0; k < count; k++) {
        out->times[k] = (float)(keys[k].mTime / tps);
        memcpy(&out->values[k * 3], &keys[k].mValue, 3 * sizeof(float));
    }
    return SINEW_OK;
}

static sinew_result read_rotation_keys(context *c, const struct aiQuatKey *keys, unsigned count, double tps,
                                       raw_channel *out)
{
    out->interp = SINEW_INTERP_LINEAR;
    out->count = count;
    out->times = malloc((count ? count : 1) * sizeof(float));
    out->values = malloc((count ? count : 1) * 4 * sizeof(float));
    if (!out->times || !out->values)
        return oom(c);
    for (unsigned k = 0; k < count; k++) {
        out->times[k] = (float)(keys[k].mTime / tps);
        const struct aiQuaternion *q = &keys[k].mValue; /* Assimp stores w, x, y, z */
        float *v = &out->values[k * 4];
        v[0] = q->x, v[1] = q->y, v[2] = q->z, v[3] = q->w;
    }
    return SINEW_OK;
}

/* The raw mesh a mesh-morph channel animates: the one it names, or the one at the node it
 * names (Assimp names either), with targets; -1 when none. */
static int32_t morph_mesh(const context *c, const char *name)
{
    const raw_model *m = c->model;
    for (uint32_t i = 0; i < m->mesh_count; i++)
        if (m->meshes[i].target_count && strcmp(m->meshes[i].name, name) == 0)
            return (int32_t)i;
    for (uint32_t i = 0; i < m->instance_count; i++) {
        const raw_mesh *mesh = &m->meshes[m->instances[i].mesh];
        if (mesh->target_count && strcmp(m->node_names[m->instances[i].node], name) == 0)
            return (int32_t)m->instances[i].mesh;
    }
    return -1;
}

/* A mesh-morph channel: at each key, the weights of the targets it lists (0 for the rest),
 * as one linear weight track a target. */
static sinew_result read_morph_keys(context *c, const struct aiMeshMorphAnim *ch, double tps, raw_clip *out)
{
    raw_model *m = c->model;
    int32_t mesh = morph_mesh(c, ch->mName.data);
    if (mesh < 0)
        return raw_model_warn(m, "clip \"%s\": morph channel \"%s\" names no mesh with morph targets; skipped",
                              out->name, ch->mName.data)
                   ? SINEW_OK
                   : oom(c);
    uint32_t n = m->meshes[mesh].target_count, keys = ch->mNumKeys;
    raw_weight_track *grown = realloc(out->weight_tracks, (out->weight_track_count + n) * sizeof *grown);
    if (!grown)
        return oom(c);
    out->weight_tracks = grown;
    for (uint32_t t = 0; t < n; t++) {
        raw_weight_track *tr = &out->weight_tracks[out->weight_track_count++];
        memset(tr, 0, sizeof *tr);
        tr->channel = (uint32_t)c->morph_first[mesh] + t;
        tr->keys.interp = SINEW_INTERP_LINEAR;
        tr->keys.count = keys;
        tr->keys.times = malloc((keys ? keys : 1) * sizeof(float));
        tr->keys.values = calloc(keys ? keys : 1, sizeof(float));
        if (!tr->keys.times || !tr->keys.values)
            return oom(c);
        for (uint32_t k = 0; k < keys; k++) {
            const struct aiMeshMorphKey *key = &ch->mKeys[k];
            tr->keys.times[k] = (float)(key->mTime / tps);
            for (unsigned j = 0; j < key->mNumValuesAndWeights; j++)
                if (key->mValues[j] == t)
                    tr->keys.values[k] = (float)key->mWeights[j];
        }
    }
    return SINEW_OK;
}

static sinew_result read_clip(context *c, const struct aiAnimation *anim, uint32_t index, raw_clip *out)
{
    raw_model *m = c->model;
    char fallback[32];
    snprintf(fallback, sizeof fallback, "clip %u", index);
    if (!(out->name = raw_strdup(anim->mName.length ? anim->mName.data : fallback)))
        return oom(c);
    double tps = anim->mTicksPerSecond;
    if (!(tps > 0.0) || !isfinite(tps)) {
        raw_model_warn(m, "clip \"%s\" gives no ticks per second; using %g, the rate Assimp's own viewer assumes",
                       out->name, FALLBACK_TICKS_PER_SECOND);
        tps = FALLBACK_TICKS_PER_SECOND;
    }
    out->duration = (float)(anim->mDuration / tps);
    if (anim->mNumMeshChannels)
        raw_model_warn(m, "clip \"%s\": %u mesh channels (whole-mesh swaps) are not supported and were skipped",
                       out->name, anim->mNumMeshChannels);
    for (unsigned i = 0; i < anim->mNumMorphMeshChannels; i++) {
        sinew_result r = read_morph_keys(c, anim->mMorphMeshChannels[i], tps, out);
        if (r)
            return r;
    }
    if (!(out->tracks = calloc(anim->mNumChannels ? anim->mNumChannels : 1, sizeof *out->tracks)))
        return oom(c);
    for (unsigned i = 0; i < anim->mNumChannels; i++) {
        const struct aiNodeAnim *ch = anim->mChannels[i];
        bool ambiguous = false;
        int32_t node = find_node(c, ch->mNodeName.data, c->joints, &ambiguous);
        if (ambiguous)
            raw_model_warn(m, "clip \"%s\": channel for \"%s\" names several nodes; the first was taken", out->name,
                           ch->mNodeName.data);
        if (node < 0) {
            raw_model_warn(m, "clip \"%s\": channel for \"%s\" names no node and was skipped", out->name,
                           ch->mNodeName.data);
            continue;
        }
        raw_track *track = &out->tracks[out->track_count++];
        track->node = (uint32_t)node;
        sinew_result r;
        if ((r = read_vector_keys(c, ch->mPositionKeys, ch->mNumPositionKeys, tps,
                                  &track->channels[SINEW_CHANNEL_TRANSLATION])) ||
            (r = read_rotation_keys(c, ch->mRotationKeys, ch->mNumRotationKeys, tps,
                                    &track->channels[SINEW_CHANNEL_ROTATION])) ||
            (r = read_vector_keys(c, ch->mScalingKeys, ch->mNumScalingKeys, tps,
                                  &track->channels[SINEW_CHANNEL_SCALE])))
            return r;
    }
    if (out->track_count && out->tracks[0].node == 0 && c->model->node_count > 0)
        raw_model_warn(m,
                       "clip \"%s\" animates the root node; its rest transform (with any axis conversion) is replaced",
                       out->name);
    return SINEW_OK;
}

static sinew_result read_clips(context *c)
{
    raw_model *m = c->model;
    const struct aiScene *s = c->scene;
    if (s->mNumAnimations == 0)
        return SINEW_OK;
    if (!(m->clips = calloc(s->mNumAnimations, sizeof *m->clips)))
        return oom(c);
    for (unsigned i = 0; i < s->mNumAnimations; i++) {
        sinew_result r = read_clip(c, s->mAnimations[i], i, &m->clips[m->clip_count++]);
        if (r)
            return r;
    }
    return SINEW_OK;
}

/* ---- entry -------------------------------------------------------------------------------- */

static char *format_name(const char *path)
{
    const char *dot = strrchr(path, '.');
    const char *slash = strrchr(path, '/');
    char name[32] = "unknown";
    if (dot && (!slash || dot > slash) && dot[1]) {
        size_t n = 0;
        for (const char *p = dot + 1; *p && n + 1 < sizeof name; p++)
            name[n++] = (char)tolower((unsigned char)*p);
        name[n] = '\0';
    }
    return raw_strdup(name);
}

/* A COLLADA file in UTF-16 (legal XML, written by some Windows exporters) as UTF-8, or
 * NULL when it is not UTF-16 or cannot be converted. Assimp 5.2.5 reads only 8-bit XML
 * ("malformed XML" on cube_UTF16LE.dae); its XML reader takes an 8-bit buffer as UTF-8
 * whatever the declaration says. */
static char *utf16_collada_as_utf8(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    unsigned char bom[2] = {0};
    bool utf16 = fread(bom, 1, 2, f) == 2 && ((bom[0] == 0xff && bom[1] == 0xfe) || (bom[0] == 0xfe && bom[1] == 0xff));
    fclose(f);
    unsigned char *in = NULL;
    size_t n = 0;
    if (!utf16 || !import_read_file(path, &in, &n))
        return NULL;
    char *out = NULL;
    iconv_t cd = iconv_open("UTF-8", "UTF-16"); /* the BOM tells the byte order */
    if (cd != (iconv_t)-1) {
        size_t in_left = n, cap = n * 2 + 16, out_left = cap;
        char *src = (char *)in, *dst = out = malloc(cap);
        if (out && iconv(cd, &src, &in_left, &dst, &out_left) != (size_t)-1 && in_left == 0) {
            *size = cap - out_left;
        } else {
            free(out);
            out = NULL;
        }
        iconv_close(cd);
    }
    free(in);
    return out;
}

static const struct aiScene *import_scene(const char *path, const char *format, const struct aiPropertyStore *props)
{
    if (strcmp(format, "dae") == 0) {
        size_t size = 0;
        char *utf8 = utf16_collada_as_utf8(path, &size);
        if (utf8 && size <= UINT32_MAX) {
            const struct aiScene *scene =
                aiImportFileFromMemoryWithProperties(utf8, (unsigned)size, IMPORT_FLAGS, "dae", props);
            free(utf8);
            return scene;
        }
        free(utf8);
    }
    return aiImportFileExWithProperties(path, IMPORT_FLAGS, NULL, props);
}

sinew_result raw_model_from_assimp(const char *path, raw_model *model, sinew_error *error)
{
    memset(model, 0, sizeof *model);
    if (!(model->source = raw_strdup(path)) || !(model->format = format_name(path))) {
        raw_model_free(model);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory while importing", path);
    }
    struct aiPropertyStore *props = aiCreatePropertyStore();
    const struct aiScene *scene = import_scene(path, model->format, props);
    aiReleasePropertyStore(props);
    if (!scene || !scene->mRootNode) {
        const char *why = aiGetErrorString();
        sinew_result r = sinew_fail(error, SINEW_ERROR_IMPORTER, "%s: the importer (Assimp) failed: %s", path,
                                    why && *why ? why : "no reason given");
        if (scene)
            aiReleaseImport(scene);
        raw_model_free(model);
        return r;
    }
    context c = {.path = path, .scene = scene, .model = model, .error = error};
    if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) && scene->mNumMeshes == 0 && scene->mNumAnimations == 0)
        raw_model_warn(model, "Assimp marked the scene incomplete and it has no meshes and no clips");
    sinew_result result = read_nodes(&c);
    if (!result) {
        axis_conversion(&c);
        result = read_materials(&c);
    }
    if (!result)
        result = read_meshes(&c);
    if (!result)
        result = read_clips(&c);
    if (!result && strcmp(model->format, "dae") == 0)
        collada_split_clips(path, model);
    free(c.nodes);
    free(c.mesh_of);
    free(c.morph_first);
    free(c.joints);
    aiReleaseImport(scene);
    if (result)
        raw_model_free(model);
    return result;
}
