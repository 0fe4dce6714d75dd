/* The demo humanoid: a mannequin of 24 joints made of overlapping ellipsoids (15,000
 * vertices, smooth weights of up to 4 joints), a staff held in the right hand (a rigid mesh
 * on its own node), and two clips: "walk", a 1 s cycle in place, and "wave", 2 s. Y up,
 * metres, facing +z; keys 30 a second on every animated joint. Made from code here, so that
 * sinew's demo content is its own. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/internal.h"
#include "internal.h"
#include "sinew/import.h"
#include "sinew/muscle_file.h"

#define PI 3.14159265f
#define RINGS 24
#define SIDES 24

typedef struct joint_spec {
    const char *name;
    int parent;
    float offset[3]; /* rest translation from the parent */
} joint_spec;

/* Left side is +x. */
/* clang-format off: one row per pair of joints */
static const joint_spec joints[] = {
    {"Hips", -1, {0.0f, 0.95f, 0.0f}},
    {"Spine", 0, {0.0f, 0.10f, 0.0f}},
    {"Chest", 1, {0.0f, 0.15f, 0.0f}},
    {"UpperChest", 2, {0.0f, 0.15f, 0.0f}},
    {"Neck", 3, {0.0f, 0.13f, 0.0f}},
    {"Head", 4, {0.0f, 0.09f, 0.0f}},
    {"LeftShoulder", 3, {0.03f, 0.08f, 0.0f}},
    {"LeftUpperArm", 6, {0.15f, 0.0f, 0.0f}},
    {"LeftLowerArm", 7, {0.28f, 0.0f, 0.0f}},
    {"LeftHand", 8, {0.25f, 0.0f, 0.0f}},
    {"LeftFingers", 9, {0.09f, 0.0f, 0.0f}},
    {"RightShoulder", 3, {-0.03f, 0.08f, 0.0f}},
    {"RightUpperArm", 11, {-0.15f, 0.0f, 0.0f}},
    {"RightLowerArm", 12, {-0.28f, 0.0f, 0.0f}},
    {"RightHand", 13, {-0.25f, 0.0f, 0.0f}},
    {"RightFingers", 14, {-0.09f, 0.0f, 0.0f}},
    {"LeftUpperLeg", 0, {0.10f, -0.06f, 0.0f}},
    {"LeftLowerLeg", 16, {0.0f, -0.42f, 0.0f}},
    {"LeftFoot", 17, {0.0f, -0.40f, 0.0f}},
    {"LeftToes", 18, {0.0f, -0.05f, 0.13f}},
    {"RightUpperLeg", 0, {-0.10f, -0.06f, 0.0f}},
    {"RightLowerLeg", 20, {0.0f, -0.42f, 0.0f}},
    {"RightFoot", 21, {0.0f, -0.40f, 0.0f}},
    {"RightToes", 22, {0.0f, -0.05f, 0.13f}},
};
/* clang-format on */
#define JOINTS ((uint32_t)(sizeof joints / sizeof joints[0]))
#define RIGHT_HAND 14

/* One body part: an ellipsoid from joint `from` towards `to` (a joint, or -1 with `end`
 * giving the far point in from's space), radii across (x-ish, z-ish). */
typedef struct part {
    int from, to;
    float end[3];
    float radius[2];
} part;

static const part parts[] = {
    {0, 1, {0}, {0.15f, 0.11f}},
    {1, 2, {0}, {0.14f, 0.10f}},
    {2, 3, {0}, {0.16f, 0.11f}},
    {3, 4, {0}, {0.17f, 0.11f}},
    {4, 5, {0}, {0.05f, 0.05f}},
    {5, -1, {0, 0.24f, 0.02f}, {0.10f, 0.11f}},
    {6, 7, {0}, {0.05f, 0.05f}},
    {7, 8, {0}, {0.055f, 0.055f}},
    {8, 9, {0}, {0.045f, 0.045f}},
    {9, 10, {0}, {0.045f, 0.02f}},
    {10, -1, {0.08f, 0, 0}, {0.04f, 0.012f}},
    {11, 12, {0}, {0.05f, 0.05f}},
    {12, 13, {0}, {0.055f, 0.055f}},
    {13, 14, {0}, {0.045f, 0.045f}},
    {14, 15, {0}, {0.045f, 0.02f}},
    {15, -1, {-0.08f, 0, 0}, {0.04f, 0.012f}},
    {16, 17, {0}, {0.085f, 0.085f}},
    {17, 18, {0}, {0.06f, 0.06f}},
    {18, 19, {0}, {0.05f, 0.035f}},
    {19, -1, {0, 0, 0.07f}, {0.045f, 0.02f}},
    {20, 21, {0}, {0.085f, 0.085f}},
    {21, 22, {0}, {0.06f, 0.06f}},
    {22, 23, {0}, {0.05f, 0.035f}},
    {23, -1, {0, 0, 0.07f}, {0.045f, 0.02f}},
};
#define PARTS ((uint32_t)(sizeof parts / sizeof parts[0]))

static void rest_world(uint32_t j, float out[3])
{
    out[0] = out[1] = out[2] = 0.0f;
    for (int k = (int)j; k >= 0; k = joints[k].parent)
        for (int i = 0; i < 3; i++)
            out[i] += joints[k].offset[i];
}

static void normalize3(float v[3])
{
    float n = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; n > 0.0f && i < 3; i++)
        v[i] /= n;
}

static void cross3(const float a[3], const float b[3], float out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* Adds one weight to a vertex's slots (4), merging a joint already there. */
static void add_weight(uint32_t *js, float *ws, uint32_t joint, float w)
{
    for (int i = 0; i < 4; i++)
        if (ws[i] > 0.0f && js[i] == joint) {
            ws[i] += w;
            return;
        }
    for (int i = 0; i < 4; i++)
        if (ws[i] == 0.0f) {
            js[i] = joint;
            ws[i] = w;
            return;
        }
}

static float smooth(float x)
{
    x = x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
    return x * x * (3.0f - 2.0f * x);
}

static bool make_body(raw_mesh *mesh)
{
    uint32_t per = (RINGS + 1) * (SIDES + 1);
    mesh->name = raw_strdup("Body");
    mesh->vertex_count = PARTS * per;
    mesh->index_count = PARTS * RINGS * SIDES * 6;
    mesh->positions = malloc((size_t)mesh->vertex_count * 3 * sizeof(float));
    mesh->uvs = malloc((size_t)mesh->vertex_count * 2 * sizeof(float));
    mesh->indices = malloc((size_t)mesh->index_count * sizeof(uint32_t));
    mesh->influence_count = 4;
    mesh->joints = calloc((size_t)mesh->vertex_count * 4, sizeof(uint32_t));
    mesh->weights = calloc((size_t)mesh->vertex_count * 4, sizeof(float));
    mesh->skin = 0;
    mesh->material = 0;
    if (!mesh->name || !mesh->positions || !mesh->uvs || !mesh->indices || !mesh->joints || !mesh->weights)
        return false;
    uint32_t v = 0, ix = 0;
    for (uint32_t p = 0; p < PARTS; p++) {
        const part *pa = &parts[p];
        float a[3], b[3];
        rest_world((uint32_t)pa->from, a);
        if (pa->to >= 0) {
            rest_world((uint32_t)pa->to, b);
        } else {
            for (int i = 0; i < 3; i++)
                b[i] = a[i] + pa->end[i];
        }
        float axis[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float length = sqrtf(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
        normalize3(axis);
        /* across: e1 roughly x (or z for parts along x), e2 = axis x e1 */
        float ref[3] = {fabsf(axis[0]) > 0.7f ? 0.0f : 1.0f, 0.0f, fabsf(axis[0]) > 0.7f ? 1.0f : 0.0f};
        float e2[3], e1[3];
        cross3(axis, ref, e2);
        normalize3(e2);
        cross3(e2, axis, e1);
        normalize3(e1);
        /* the ellipsoid runs from a bit before the joint to a bit past the far end */
        float lo = -0.12f * length, hi = 1.1f * length, half = 0.5f * (hi - lo), mid = 0.5f * (hi + lo);
        uint32_t first = v;
        for (uint32_t r = 0; r <= RINGS; r++) {
            float ang = PI * (float)r / RINGS;
            float along = mid - half * cosf(ang), across = sinf(ang);
            float u = along / length; /* 0 at the joint, 1 at the far end */
            for (uint32_t s = 0; s <= SIDES; s++, v++) {
                float th = 2.0f * PI * (float)s / SIDES;
                float c = cosf(th) * pa->radius[0] * across, d = sinf(th) * pa->radius[1] * across;
                for (int i = 0; i < 3; i++)
                    mesh->positions[v * 3 + i] = a[i] + axis[i] * along + e1[i] * c + e2[i] * d;
                mesh->uvs[v * 2] = (float)s / SIDES;
                mesh->uvs[v * 2 + 1] = (float)r / RINGS;
                /* weights: the part's joint, blending into the far joint near it and into
                 * the parent near the start */
                uint32_t *js = &mesh->joints[v * 4];
                float *ws = &mesh->weights[v * 4];
                float to_far = pa->to >= 0 ? 0.5f * smooth((u - 0.72f) / 0.38f) : 0.0f;
                int parent = joints[pa->from].parent;
                float to_parent = parent >= 0 ? 0.5f * smooth((0.22f - u) / 0.34f) : 0.0f;
                add_weight(js, ws, (uint32_t)pa->from, 1.0f - to_far - to_parent);
                if (to_far > 0.0f)
                    add_weight(js, ws, (uint32_t)pa->to, to_far);
                if (to_parent > 0.0f)
                    add_weight(js, ws, (uint32_t)parent, to_parent);
                /* the shoulders and hips follow the chest and pelvis a little */
                if ((pa->from == 7 || pa->from == 12 || pa->from == 16 || pa->from == 20) && u < 0.05f)
                    add_weight(js, ws, pa->from >= 16 ? 0u : 3u, 0.1f);
                float sum = ws[0] + ws[1] + ws[2] + ws[3];
                for (int i = 0; i < 4; i++)
                    ws[i] /= sum;
            }
        }
        for (uint32_t r = 0; r < RINGS; r++)
            for (uint32_t s = 0; s < SIDES; s++) {
                uint32_t i0 = first + r * (SIDES + 1) + s, i1 = i0 + SIDES + 1;
                const uint32_t quad[6] = {i0, i1, i0 + 1, i0 + 1, i1, i1 + 1};
                memcpy(&mesh->indices[ix], quad, sizeof quad);
                ix += 6;
            }
    }
    return true;
}

/* A staff: a cylinder 1.2 m long through the right hand, along the hand node's z. */
static bool make_staff(raw_mesh *mesh)
{
    const uint32_t sides = 16, rings = 8;
    mesh->name = raw_strdup("StaffMesh");
    mesh->vertex_count = (rings + 1) * (sides + 1);
    mesh->index_count = rings * sides * 6;
    mesh->positions = malloc((size_t)mesh->vertex_count * 3 * sizeof(float));
    mesh->normals = malloc((size_t)mesh->vertex_count * 3 * sizeof(float));
    mesh->indices = malloc((size_t)mesh->index_count * sizeof(uint32_t));
    mesh->skin = -1;
    mesh->material = 1;
    if (!mesh->name || !mesh->positions || !mesh->normals || !mesh->indices)
        return false;
    uint32_t v = 0, ix = 0;
    for (uint32_t r = 0; r <= rings; r++)
        for (uint32_t s = 0; s <= sides; s++, v++) {
            float th = 2.0f * PI * (float)s / (float)sides, c = cosf(th), d = sinf(th);
            float radius = 0.018f + (r == 0 || r == rings ? 0.0f : 0.004f);
            float *p = &mesh->positions[v * 3], *n = &mesh->normals[v * 3];
            p[0] = c * radius, p[1] = d * radius, p[2] = -0.45f + 1.2f * (float)r / (float)rings;
            n[0] = c, n[1] = d, n[2] = 0.0f;
        }
    for (uint32_t r = 0; r < rings; r++)
        for (uint32_t s = 0; s < sides; s++) {
            uint32_t i0 = r * (sides + 1) + s, i1 = i0 + sides + 1;
            const uint32_t quad[6] = {i0, i0 + 1, i1, i0 + 1, i1 + 1, i1};
            memcpy(&mesh->indices[ix], quad, sizeof quad);
            ix += 6;
        }
    return true;
}

/* ---- clips --------------------------------------------------------------------------------- */

static void quat_axis(float x, float y, float z, float angle, float out[4])
{
    float s = sinf(0.5f * angle);
    out[0] = x * s, out[1] = y * s, out[2] = z * s, out[3] = cosf(0.5f * angle);
}

static void quat_mul(const float a[4], const float b[4], float out[4])
{
    float r[4] = {
        a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1], a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
        a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3], a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
    memcpy(out, r, sizeof r);
}

/* Rotation of a joint at phase (0..1 of the clip): X then Z angles (radians), applied as
 * qx * qz (lower/raise about z first, then swing about x). */
typedef void (*pose_fn)(uint32_t joint, float phase, float *x, float *z);

static void walk_pose(uint32_t j, float ph, float *x, float *z)
{
    float w = 2.0f * PI * ph, swing = sinf(w);
    const char *n = joints[j].name;
    bool left = strncmp(n, "Left", 4) == 0;
    float side = left ? 1.0f : -1.0f;
    const char *limb = left ? n + 4 : strncmp(n, "Right", 5) == 0 ? n + 5 : "";
    *x = *z = 0.0f;
    if (strcmp(limb, "UpperLeg") == 0)
        *x = -0.45f * swing * side;
    else if (strcmp(limb, "LowerLeg") == 0)
        *x = 0.35f + 0.35f * sinf(w + (left ? 0.0f : PI) - 1.2f);
    else if (strcmp(limb, "Foot") == 0)
        *x = -0.15f * swing * side;
    else if (strcmp(limb, "UpperArm") == 0)
        *z = -1.3f * side, *x = 0.35f * swing * side;
    else if (strcmp(limb, "LowerArm") == 0)
        *z = -0.25f * side;
    else if (strcmp(n, "Spine") == 0)
        *x = 0.05f, *z = 0.03f * swing;
    else if (strcmp(n, "Chest") == 0)
        *z = -0.04f * swing;
}

static void wave_pose(uint32_t j, float ph, float *x, float *z)
{
    float w = 2.0f * PI * ph;
    const char *n = joints[j].name;
    *x = *z = 0.0f;
    if (strcmp(n, "LeftUpperArm") == 0)
        *z = -1.3f;
    else if (strcmp(n, "LeftLowerArm") == 0)
        *z = -0.2f;
    else if (strcmp(n, "RightUpperArm") == 0)
        *z = -0.5f - 0.15f * sinf(w), *x = -0.2f;
    else if (strcmp(n, "RightLowerArm") == 0)
        *z = -1.2f + 0.45f * sinf(4.0f * w); /* the forearm up, waving side to side */
    else if (strcmp(n, "RightHand") == 0)
        *z = 0.25f * sinf(4.0f * w + 0.6f);
    else if (strcmp(n, "Head") == 0)
        *z = 0.12f * sinf(w), *x = -0.08f;
    else if (strcmp(n, "Spine") == 0)
        *z = 0.04f * sinf(w);
}

static bool make_clip(raw_clip *clip, const char *name, float duration, pose_fn pose, bool bob)
{
    const uint32_t keys = (uint32_t)lroundf(duration * 30.0f) + 1;
    clip->name = raw_strdup(name);
    clip->duration = duration;
    clip->tracks = calloc(JOINTS, sizeof *clip->tracks);
    if (!clip->name || !clip->tracks)
        return false;
    clip->track_count = JOINTS;
    for (uint32_t j = 0; j < JOINTS; j++) {
        raw_track *t = &clip->tracks[j];
        t->node = j + 1; /* node 0 is the scene root */
        raw_channel *r = &t->channels[SINEW_CHANNEL_ROTATION];
        if (!raw_channel_even(r, SINEW_CHANNEL_ROTATION, duration, keys))
            return false;
        for (uint32_t k = 0; k < keys; k++) {
            float ph = (float)k / (float)(keys - 1), ax, az, qx[4], qz[4];
            pose(j, ph, &ax, &az);
            quat_axis(1, 0, 0, ax, qx);
            quat_axis(0, 0, 1, az, qz);
            quat_mul(qx, qz, &r->values[k * 4]);
        }
        if (j == 0 && bob) { /* the hips rise and fall twice a step cycle */
            raw_channel *tr = &t->channels[SINEW_CHANNEL_TRANSLATION];
            if (!raw_channel_even(tr, SINEW_CHANNEL_TRANSLATION, duration, keys))
                return false;
            for (uint32_t k = 0; k < keys; k++) {
                float ph = (float)k / (float)(keys - 1);
                tr->values[k * 3] = 0.0f;
                tr->values[k * 3 + 1] = joints[0].offset[1] + 0.025f * cosf(4.0f * PI * ph);
                tr->values[k * 3 + 2] = 0.0f;
            }
        }
    }
    return true;
}

static bool make_humanoid(raw_model *m)
{
    uint32_t nodes = JOINTS + 2; /* root, joints, staff */
    m->node_count = nodes;
    m->node_names = calloc(nodes, sizeof(char *));
    m->node_parents = malloc(nodes * sizeof(int32_t));
    m->node_rest = calloc(nodes, sizeof(sinew_transform));
    if (!m->node_names || !m->node_parents || !m->node_rest)
        return false;
    for (uint32_t i = 0; i < nodes; i++) {
        m->node_rest[i].rotation[3] = 1.0f;
        m->node_rest[i].scale[0] = m->node_rest[i].scale[1] = m->node_rest[i].scale[2] = 1.0f;
    }
    m->node_names[0] = raw_strdup("Humanoid");
    m->node_parents[0] = -1;
    for (uint32_t j = 0; j < JOINTS; j++) {
        m->node_names[j + 1] = raw_strdup(joints[j].name);
        m->node_parents[j + 1] = joints[j].parent + 1;
        memcpy(m->node_rest[j + 1].translation, joints[j].offset, sizeof joints[j].offset);
    }
    uint32_t staff = JOINTS + 1;
    m->node_names[staff] = raw_strdup("Staff");
    m->node_parents[staff] = RIGHT_HAND + 1;
    m->node_rest[staff].translation[0] = -0.07f;
    m->node_rest[staff].translation[1] = -0.01f;
    for (uint32_t i = 0; i < nodes; i++)
        if (!m->node_names[i])
            return false;

    m->skin_count = 1;
    m->skins = calloc(1, sizeof *m->skins);
    if (!m->skins)
        return false;
    raw_skin *skin = &m->skins[0];
    skin->joint_count = JOINTS;
    skin->joints = malloc(JOINTS * sizeof(uint32_t));
    skin->inverse_bind = calloc(JOINTS, sizeof(sinew_mat4));
    if (!skin->joints || !skin->inverse_bind)
        return false;
    for (uint32_t j = 0; j < JOINTS; j++) {
        float w[3];
        rest_world(j, w);
        skin->joints[j] = j + 1;
        float *ibm = skin->inverse_bind[j].m;
        ibm[0] = ibm[5] = ibm[10] = ibm[15] = 1.0f;
        ibm[12] = -w[0], ibm[13] = -w[1], ibm[14] = -w[2];
    }

    m->mesh_count = 2;
    m->meshes = calloc(2, sizeof *m->meshes);
    m->instance_count = 2;
    m->instances = malloc(2 * sizeof *m->instances);
    m->material_count = 2;
    m->materials = calloc(2, sizeof *m->materials);
    m->clip_count = 2;
    m->clips = calloc(2, sizeof *m->clips);
    if (!m->meshes || !m->instances || !m->materials || !m->clips)
        return false;
    m->instances[0] = (sinew_instance){0, 0, 0};
    m->instances[1] = (sinew_instance){1, staff, 0};
    m->materials[0] = (raw_material){.name = raw_strdup("Mannequin"), .base_color = {0.78f, 0.66f, 0.55f, 1.0f}};
    m->materials[1] = (raw_material){.name = raw_strdup("Wood"), .base_color = {0.45f, 0.28f, 0.13f, 1.0f}};
    return m->materials[0].name && m->materials[1].name && make_body(&m->meshes[0]) && make_staff(&m->meshes[1]) &&
           make_clip(&m->clips[0], "walk", 1.0f, walk_pose, true) &&
           make_clip(&m->clips[1], "wave", 2.0f, wave_pose, false);
}

sinew_result sinew_demo_humanoid(sinew_model **out, sinew_error *error)
{
    if (!out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_demo_humanoid: no output");
    *out = NULL;
    raw_model raw = {.source = raw_strdup("demo humanoid"), .format = raw_strdup("generated")};
    if (!raw.source || !raw.format || !make_humanoid(&raw)) {
        raw_model_free(&raw);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "demo humanoid: out of memory");
    }
    /* its biceps travel with it, as a .sinew file's muscles do */
    const char *text = sinew_demo_humanoid_muscles();
    sinew_muscle_set *muscles = NULL;
    sinew_result result = sinew_muscle_set_parse(text, strlen(text), "demo humanoid muscles", &muscles, error);
    raw.muscles = muscles;
    void *bytes = NULL;
    size_t size = 0;
    if (result == SINEW_OK)
        result = raw_model_build(&raw, &bytes, &size, error);
    raw_model_free(&raw);
    sinew_muscle_set_free(muscles);
    if (result == SINEW_OK)
        result = sinew_model_from_blob(bytes, size, "demo humanoid", NULL, out, error);
    free(bytes);
    return result;
}

const char *sinew_demo_humanoid_muscles(void)
{
    /* A biceps on each arm: from the front of the upper arm near the shoulder to the
     * forearm just past the elbow, so it shortens as the elbow bends (the wave). */
    return "{\n"
           "  \"muscles\": [\n"
           "    {\n"
           "      \"name\": \"LeftBiceps\",\n"
           "      \"origin\": {\"joint\": \"LeftUpperArm\", \"offset\": [0.04, 0.0, 0.035]},\n"
           "      \"insertion\": {\"joint\": \"LeftLowerArm\", \"offset\": [0.05, 0.0, 0.03]},\n"
           "      \"radii\": [0.006, 0.012, 0.020, 0.027, 0.030, 0.028, 0.022, 0.014, 0.007],\n"
           "      \"coefficients\": [0.0, 0.25, 0.6, 0.9, 1.0, 0.9, 0.6, 0.25, 0.0],\n"
           "      \"segments\": 24,\n"
           "      \"color\": \"#b03a2e\"\n"
           "    },\n"
           "    {\n"
           "      \"name\": \"RightBiceps\",\n"
           "      \"origin\": {\"joint\": \"RightUpperArm\", \"offset\": [-0.04, 0.0, 0.035]},\n"
           "      \"insertion\": {\"joint\": \"RightLowerArm\", \"offset\": [-0.05, 0.0, 0.03]},\n"
           "      \"radii\": [0.006, 0.012, 0.020, 0.027, 0.030, 0.028, 0.022, 0.014, 0.007],\n"
           "      \"coefficients\": [0.0, 0.25, 0.6, 0.9, 1.0, 0.9, 0.6, 0.25, 0.0],\n"
           "      \"segments\": 24,\n"
           "      \"color\": \"#b03a2e\"\n"
           "    }\n"
           "  ]\n"
           "}\n";
}
