/* Clips of one skeleton on another (sinew_retarget, sinew/import.h).
 *
 * Joints are matched, for each node of the target: by a name map the caller gives (JSON,
 * source name -> target name), else by the same name once prefixes such as "mixamorig:" or
 * "Armature|" and case, spaces, dots, dashes and underscores are set aside, else through a
 * built-in humanoid naming (Mixamo, CMU's BVH, Unity's humanoid as the demo names its bones)
 * mapped to one canonical set. A matched joint turns in world space as its source turns away
 * from the source's rest pose: W_t(t) = W_s(t) * inv(W_s(rest)) * W_t(rest), so skeletons
 * whose rest poses differ in their joint frames still move alike; the local rotation is taken
 * through the target's parent. The root joint (the topmost matched one, the hips) also moves:
 * the source's motion from its rest position, scaled by the ratio of the legs' lengths (the
 * hips' heights when there are no legs). Other joints keep their rest. Each source clip is
 * baked at `frame_rate` keys a second into the new model, before the target's own clips.
 */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cglm/cglm.h>

#include "internal.h"
#include "json.h"
#include "sinew/anim.h"

#define CANONICAL_LEN 32

/* A naming family: its names (normalised) -> canonical ids; "L" names are mirrored to "R". */
typedef struct alias {
    const char *name, *canonical;
} alias;

static const alias UNITY[] = {{"hips", "hips"},
                              {"spine", "spine"},
                              {"chest", "chest"},
                              {"upperchest", "upperchest"},
                              {"neck", "neck"},
                              {"head", "head"},
                              {"leftshoulder", "lshoulder"},
                              {"leftupperarm", "lupperarm"},
                              {"leftlowerarm", "llowerarm"},
                              {"lefthand", "lhand"},
                              {"leftupperleg", "lupperleg"},
                              {"leftlowerleg", "llowerleg"},
                              {"leftfoot", "lfoot"},
                              {"lefttoes", "ltoes"},
                              {NULL, NULL}};
/* Mixamo's and CMU's BVH limbs share their names; their backs differ */
static const alias MIXAMO_LIMBS[] = {{"hips", "hips"},         {"neck", "neck"},
                                     {"head", "head"},         {"leftshoulder", "lshoulder"},
                                     {"leftarm", "lupperarm"}, {"leftforearm", "llowerarm"},
                                     {"lefthand", "lhand"},    {"leftupleg", "lupperleg"},
                                     {"leftleg", "llowerleg"}, {"leftfoot", "lfoot"},
                                     {"lefttoebase", "ltoes"}, {NULL, NULL}};
static const alias MIXAMO_BACK[] = {{"spine", "spine"}, {"spine1", "chest"}, {"spine2", "upperchest"}, {NULL, NULL}};
/* CMU's BVH (01_01.bvh): LowerBack, Spine, Spine1 up the back; LHipJoint and friends stay unmatched */
static const alias CMU_BACK[] = {{"lowerback", "spine"}, {"spine", "chest"}, {"spine1", "upperchest"}, {NULL, NULL}};

/* A naming: its back, then the rest (NULL for none). */
typedef struct family {
    const alias *back, *rest;
} family;

static const family UNITY_NAMES = {UNITY, NULL}, MIXAMO_NAMES = {MIXAMO_BACK, MIXAMO_LIMBS},
                    CMU_NAMES = {CMU_BACK, MIXAMO_LIMBS};

/* The name without a namespace prefix ("mixamorig:", "Armature|"), in lower case, without
 * spaces, dots, dashes and underscores. */
static void normalise(const char *name, char *out, size_t size)
{
    const char *at = name;
    for (const char *p = name; *p; p++)
        if (*p == ':' || *p == '|')
            at = p + 1;
    size_t n = 0;
    for (; *at && n + 1 < size; at++)
        if (!strchr(" ._-", *at))
            out[n++] = (char)tolower((unsigned char)*at);
    out[n] = 0;
}

static bool has_name(const sinew_model *m, const char *normalised)
{
    char buf[256];
    for (uint32_t i = 0; i < m->node_count; i++) {
        normalise(m->node_names[i], buf, sizeof buf);
        if (strcmp(buf, normalised) == 0)
            return true;
    }
    return false;
}

static const family *family_of(const sinew_model *m)
{
    if (has_name(m, "lowerback"))
        return &CMU_NAMES;
    if (has_name(m, "leftupleg"))
        return &MIXAMO_NAMES;
    if (has_name(m, "leftupperleg"))
        return &UNITY_NAMES;
    return NULL;
}

/* The canonical id of a normalised name in a table: "left..." names are also read as "right..." */
static bool canonical_in(const alias *table, const char *name, char *out)
{
    for (int i = 0; table && table[i].name; i++) {
        const char *a = table[i].name;
        char right[64];
        if (strcmp(a, name) == 0) {
            snprintf(out, CANONICAL_LEN, "%s", table[i].canonical);
            return true;
        }
        if (strncmp(a, "left", 4) == 0 && snprintf(right, sizeof right, "right%s", a + 4) > 0 &&
            strcmp(right, name) == 0) {
            snprintf(out, CANONICAL_LEN, "r%s", table[i].canonical + 1);
            return true;
        }
    }
    return false;
}

/* The canonical id of a normalised name in a naming ("" when it has none). */
static void canonical_of(const family *f, const char *name, char *out)
{
    out[0] = 0;
    if (f && !canonical_in(f->back, name, out))
        canonical_in(f->rest, name, out);
}

/* The name map file: {"source name": "target name", ...}; target node -> source node. Errors
 * name the file, and the line and column of a member that is wrong. */
static sinew_result read_name_map(const char *path, const sinew_model *target, const sinew_model *source,
                                  int32_t *match, sinew_error *error)
{
    size_t size = 0;
    unsigned char *text = NULL;
    if (!import_read_file(path, &text, &size))
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot read the name map", path);
    json_doc doc = {0};
    sinew_result r = json_parse_named((const char *)text, size, path, &doc, error);
    if (r == SINEW_OK && !json_is_object(doc.root))
        r = sinew_fail(error, SINEW_ERROR_FORMAT, "%s: a name map is a JSON object {\"source\": \"target\", ...}",
                       path);
    const json_node *members = r == SINEW_OK ? doc.root : NULL, *e;
    JSON_FOR_EACH(e, members)
    {
        const char *name = e[-1].string; /* the member's key */
        int32_t s = sinew_model_find_node(source, name);
        int32_t t = json_is_string(e) ? sinew_model_find_node(target, e->string) : -1;
        if (json_is_string(e) && s >= 0 && t >= 0) {
            match[t] = s;
            continue;
        }
        int line, column; /* counted only for the member refused: a walk from the text's start */
        json_line_column((const char *)text, e[-1].offset - 1, &line, &column); /* its opening quote */
        if (!json_is_string(e))
            r = sinew_fail(error, SINEW_ERROR_FORMAT, "%s:%d:%d: \"%s\": the target name is not a string", path, line,
                           column, name);
        else
            r = sinew_fail(error, SINEW_ERROR_DATA, "%s:%d:%d: \"%s\" -> \"%s\": %s has no node \"%s\"", path, line,
                           column, name, e->string, s < 0 ? source->source : target->source, s < 0 ? name : e->string);
        break;
    }
    json_free(&doc);
    import_free(text); /* import_read_file's */
    return r;
}

static bool is_joint(const sinew_model *m, uint32_t node)
{
    for (uint32_t k = 0; k < m->skin_count; k++)
        for (uint32_t j = 0; j < m->skins[k].joint_count; j++)
            if (m->skins[k].joints[j] == node)
                return true;
    return false;
}

/* The same hierarchy: as many nodes, each with the parent of the same index. */
static bool same_shape(const sinew_model *target, const sinew_model *source)
{
    if (target->node_count != source->node_count)
        return false;
    for (uint32_t i = 0; i < target->node_count; i++)
        if (target->node_parents[i] != source->node_parents[i])
            return false;
    return true;
}

/* True when every node matches the node of the same index in a hierarchy of the same shape:
 * the source's clips were made for this skeleton and are copied as they are. */
static bool matched_by_index(const sinew_model *target, const sinew_model *source, const int32_t *match)
{
    if (!same_shape(target, source))
        return false;
    for (uint32_t i = 0; i < target->node_count; i++)
        if (match[i] != (int32_t)i)
            return false;
    return true;
}

static uint32_t match_names(const sinew_model *target, const sinew_model *source, int32_t *match);

/* match[target node] = source node or -1: by name, or by index when no joint of the source
 * matches by name but the hierarchies have the same shape (an animation file whose joints
 * carry no names, such as IQM's, made for this skeleton: raylib's rule). */
static uint32_t match_joints(const sinew_model *target, const sinew_model *source, int32_t *match)
{
    uint32_t matched = match_names(target, source, match);
    bool joint_matched = false;
    for (uint32_t t = 0; t < target->node_count && !joint_matched; t++)
        joint_matched = match[t] >= 0 && is_joint(source, (uint32_t)match[t]);
    if (joint_matched || !same_shape(target, source))
        return matched;
    for (uint32_t i = 0; i < target->node_count; i++)
        match[i] = (int32_t)i;
    return target->node_count;
}

static uint32_t match_names(const sinew_model *target, const sinew_model *source, int32_t *match)
{
    const family *tf = family_of(target), *sf = family_of(source);
    char tn[256], sn[256], tc[CANONICAL_LEN], sc[CANONICAL_LEN];
    uint32_t matched = 0;
    for (uint32_t t = 0; t < target->node_count; t++) {
        if (match[t] >= 0) {
            matched++;
            continue;
        }
        normalise(target->node_names[t], tn, sizeof tn);
        canonical_of(tf, tn, tc);
        int32_t by_canonical = -1;
        for (uint32_t s = 0; s < source->node_count && match[t] < 0; s++) {
            normalise(source->node_names[s], sn, sizeof sn);
            if (!*tn)
                break;
            if (strcmp(tn, sn) == 0 && (!tf || !sf || tf == sf || !*tc)) /* same naming, or names outside it */
                match[t] = (int32_t)s;
            canonical_of(sf, sn, sc);
            if (by_canonical < 0 && *tc && strcmp(tc, sc) == 0)
                by_canonical = (int32_t)s;
        }
        if (match[t] < 0 && *tc)
            match[t] = by_canonical;
        matched += match[t] >= 0;
    }
    return matched;
}

static void world_rotation(const sinew_mat4 *w, versor out)
{
    sinew_transform t;
    sinew_mat4_decompose(w, &t);
    glm_vec4_copy(t.rotation, out);
    glm_quat_normalize(out);
}

static float distance(const sinew_mat4 *a, const sinew_mat4 *b)
{
    return glm_vec3_distance((float *)a->m + 12, (float *)b->m + 12);
}

/* Leg length (upper + lower leg) of a model under its naming, or 0. */
static float leg_length(const sinew_model *m, const sinew_mat4 *rest)
{
    const family *f = family_of(m);
    int32_t at[3] = {-1, -1, -1};
    static const char *const parts[3] = {"lupperleg", "llowerleg", "lfoot"};
    char name[256], canonical[CANONICAL_LEN];
    for (uint32_t i = 0; i < m->node_count; i++) {
        normalise(m->node_names[i], name, sizeof name);
        canonical_of(f, name, canonical);
        for (int k = 0; k < 3; k++)
            if (strcmp(canonical, parts[k]) == 0)
                at[k] = (int32_t)i;
    }
    if (at[0] < 0 || at[1] < 0 || at[2] < 0)
        return 0.0f;
    return distance(&rest[at[0]], &rest[at[1]]) + distance(&rest[at[1]], &rest[at[2]]);
}

typedef struct retarget {
    const sinew_model *target, *source;
    const int32_t *match;
    int32_t roots[2]; /* target nodes whose translation moves (the topmost matched, the hips), or -1 */
    float scale;
    /* per matched target node, what its world rotation is the source's times:
     * inv(source rest) * align * target rest, align turning the target's rest bone onto the
     * source's (world); made once, used every frame */
    versor *base;
    sinew_mat4 *target_rest, *source_rest, *source_worlds;
    sinew_transform *source_locals;
    versor *target_world;   /* per target node, the frame being made */
    sinew_mat4 *target_now; /* the target's worlds as far as the frame is made */
} retarget;

/* One frame of a source clip as target local rotations (and the root's translation). */
static bool retarget_frame(retarget *r, const sinew_clip *clip, float time, sinew_transform *out)
{
    const sinew_model *t = r->target, *s = r->source;
    sinew_sample_desc sd = {
        .model = s, .clip = clip, .time = time, .locals = r->source_locals, .local_count = s->node_count};
    if (sinew_sample(&sd, NULL) != SINEW_OK || sinew_local_to_world(s, r->source_locals, s->node_count, NULL,
                                                                    r->source_worlds, s->node_count, NULL) != SINEW_OK)
        return false;
    for (uint32_t j = 0; j < t->node_count; j++) {
        out[j] = t->node_rest[j];
        versor parent = GLM_QUAT_IDENTITY_INIT, local;
        int32_t p = t->node_parents[j];
        if (p >= 0)
            glm_vec4_copy(r->target_world[p], parent);
        memcpy(local, t->node_rest[j].rotation, sizeof local);
        glm_quat_normalize(local);
        if (r->match[j] < 0) {
            glm_quat_mul(parent, local, r->target_world[j]);
            continue;
        }
        versor now, inv_parent;
        world_rotation(&r->source_worlds[r->match[j]], now);
        glm_quat_mul(now, r->base[j], r->target_world[j]);
        glm_quat_normalize(r->target_world[j]);
        glm_quat_inv(parent, inv_parent);
        glm_quat_mul(inv_parent, r->target_world[j], local);
        glm_quat_normalize(local);
        glm_vec4_copy(local, out[j].rotation);
    }
    /* the moving roots: the source's motion from rest, scaled, under the parent as posed now */
    for (int k = 0; k < 2; k++) {
        int32_t root = r->roots[k];
        if (root < 0)
            continue;
        const float *now = r->source_worlds[r->match[root]].m + 12, *rest = r->source_rest[r->match[root]].m + 12;
        vec3 world;
        for (int c = 0; c < 3; c++)
            world[c] = r->target_rest[root].m[12 + c] + (now[c] - rest[c]) * r->scale;
        int32_t p = t->node_parents[root];
        if (p >= 0) {
            if (sinew_local_to_world(t, out, t->node_count, NULL, r->target_now, t->node_count, NULL) != SINEW_OK)
                return false;
            mat4 parent, inv;
            memcpy(parent, r->target_now[p].m, sizeof parent);
            glm_mat4_inv(parent, inv);
            glm_mat4_mulv3(inv, world, 1.0f, world);
        }
        glm_vec3_copy(world, out[root].translation);
    }
    return true;
}

/* The source's clips baked onto the target, appended to raw->clips (before the target's own). */
static sinew_result bake_clips(retarget *r, raw_model *raw, float rate, sinew_error *error)
{
    const sinew_model *t = r->target, *s = r->source;
    uint32_t old = raw->clip_count, add = s->clip_count;
    raw_clip *clips = calloc((size_t)old + add, sizeof *clips);
    sinew_transform *frame = malloc(t->node_count * sizeof *frame);
    if (!clips || !frame) {
        free(clips);
        free(frame);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory retargeting", t->source);
    }
    if (old) /* a skeleton without clips has no array */
        memcpy(clips + add, raw->clips, old * sizeof *clips);
    free(raw->clips);
    raw->clips = clips;
    raw->clip_count = old + add;
    uint32_t tracked = 0;
    for (uint32_t j = 0; j < t->node_count; j++)
        tracked += r->match[j] >= 0;
    for (uint32_t c = 0; c < add; c++) {
        const sinew_clip *src = &s->clips[c];
        raw_clip *dst = &clips[c];
        uint32_t keys = (uint32_t)ceilf(src->duration * rate - 1e-4f) + 1;
        keys = keys < 2 ? 2 : keys;
        dst->name = raw_strdup(src->name ? src->name : "clip");
        dst->duration = src->duration;
        dst->tracks = calloc(tracked ? tracked : 1, sizeof *dst->tracks);
        if (!dst->name || !dst->tracks)
            goto oom;
        dst->track_count = tracked;
        for (uint32_t j = 0, k = 0; j < t->node_count; j++) {
            if (r->match[j] < 0)
                continue;
            raw_track *track = &dst->tracks[k++];
            track->node = j;
            if (!raw_channel_even(&track->channels[SINEW_CHANNEL_ROTATION], SINEW_CHANNEL_ROTATION, src->duration,
                                  keys) ||
                (((int32_t)j == r->roots[0] || (int32_t)j == r->roots[1]) &&
                 !raw_channel_even(&track->channels[SINEW_CHANNEL_TRANSLATION], SINEW_CHANNEL_TRANSLATION,
                                   src->duration, keys)))
                goto oom;
        }
        for (uint32_t key = 0; key < keys; key++) {
            float time = src->duration * (float)key / (float)(keys - 1);
            if (!retarget_frame(r, src, time, frame)) {
                free(frame);
                return sinew_fail(error, SINEW_ERROR_DATA, "%s: clip \"%s\" cannot be sampled at %g s", s->source,
                                  src->name, (double)time);
            }
            for (uint32_t k = 0; k < dst->track_count; k++) {
                raw_track *track = &dst->tracks[k];
                memcpy(track->channels[SINEW_CHANNEL_ROTATION].values + key * 4, frame[track->node].rotation, 16);
                if (track->channels[SINEW_CHANNEL_TRANSLATION].count)
                    memcpy(track->channels[SINEW_CHANNEL_TRANSLATION].values + key * 3, frame[track->node].translation,
                           12);
            }
        }
    }
    free(frame);
    return SINEW_OK;
oom:
    free(frame);
    return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory retargeting", t->source);
}

/* The source's clips copied key for key onto a target of the same skeleton (node i to node
 * i), before the target's own clips. */
static sinew_result copy_clips(const sinew_model *s, raw_model *raw, sinew_error *error)
{
    raw_model src = {0};
    raw_clip *clips = NULL;
    raw_key_pool *pools = NULL;
    if (!raw_model_from_model(s, &src) || !(clips = calloc((size_t)raw->clip_count + src.clip_count, sizeof *clips)) ||
        !(pools = calloc((size_t)raw->pool_count + src.pool_count + 1, sizeof *pools))) {
        free(clips);
        raw_model_free(&src);
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory copying clips", s->source);
    }
    for (uint32_t c = 0; c < src.clip_count; c++) /* their pools go after the target's */
        for (uint32_t t = 0; t < src.clips[c].track_count; t++)
            for (int k = 0; k < SINEW_CHANNEL_COUNT; k++)
                if (src.clips[c].tracks[t].channels[k].pool)
                    src.clips[c].tracks[t].channels[k].pool += raw->pool_count;
    if (src.clip_count)
        memcpy(clips, src.clips, src.clip_count * sizeof *clips);
    if (raw->clip_count)
        memcpy(clips + src.clip_count, raw->clips, raw->clip_count * sizeof *clips);
    if (raw->pool_count)
        memcpy(pools, raw->pools, raw->pool_count * sizeof *pools);
    if (src.pool_count)
        memcpy(pools + raw->pool_count, src.pools, src.pool_count * sizeof *pools);
    free(raw->clips);
    free(raw->pools);
    raw->clips = clips;
    raw->clip_count += src.clip_count;
    raw->pools = pools;
    raw->pool_count += src.pool_count;
    free(src.clips);
    free(src.pools);
    src.clips = NULL, src.clip_count = 0, src.pools = NULL, src.pool_count = 0;
    raw_model_free(&src);
    return SINEW_OK;
}

sinew_result sinew_retarget(const sinew_retarget_desc *d, sinew_model **out, sinew_error *error)
{
    if (!d || !d->target || !d->source || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_retarget: missing target, source or output");
    *out = NULL;
    const sinew_model *t = d->target, *s = d->source;
    if (s->clip_count == 0)
        return sinew_fail(error, SINEW_ERROR_DATA, "%s: no clips to apply to %s", s->source, t->source);
    float rate = d->frame_rate > 0.0f && isfinite(d->frame_rate) ? d->frame_rate : 30.0f;
    retarget r = {.target = t, .source = s, .roots = {-1, -1}, .scale = 1.0f};
    int32_t *match = malloc((t->node_count + 1) * sizeof *match);
    r.target_rest = malloc((t->node_count + 1) * sizeof(sinew_mat4));
    r.source_rest = malloc((s->node_count + 1) * sizeof(sinew_mat4));
    r.source_worlds = malloc((s->node_count + 1) * sizeof(sinew_mat4));
    r.source_locals = malloc((s->node_count + 1) * sizeof(sinew_transform));
    r.target_world = malloc((t->node_count + 1) * sizeof(versor));
    r.target_now = malloc((t->node_count + 1) * sizeof(sinew_mat4));
    r.base = malloc((t->node_count + 1) * sizeof(versor));
    raw_model raw = {0};
    bool raw_made = false;
    sinew_result result = SINEW_OK;
    if (!match || !r.target_rest || !r.source_rest || !r.source_worlds || !r.source_locals || !r.target_world ||
        !r.target_now || !r.base) {
        result = sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory retargeting", t->source);
        goto out;
    }
    for (uint32_t i = 0; i < t->node_count; i++)
        match[i] = -1;
    r.match = match;
    if (d->name_map && (result = read_name_map(d->name_map, t, s, match, error)))
        goto out;
    uint32_t matched = match_joints(t, s, match);
    if (matched == 0) {
        result = sinew_fail(error, SINEW_ERROR_DATA,
                            "%s: no joint of %s matches by name (give a name map: {\"source\": \"target\", ...})",
                            s->source, t->source);
        goto out;
    }
    sinew_local_to_world(t, t->node_rest, t->node_count, NULL, r.target_rest, t->node_count, NULL);
    sinew_local_to_world(s, s->node_rest, s->node_count, NULL, r.source_rest, s->node_count, NULL);
    /* the roots that move: the topmost matched node, and the hips when they are another */
    uint32_t best = UINT32_MAX;
    const family *naming = family_of(t);
    for (uint32_t j = 0; j < t->node_count; j++) {
        if (match[j] < 0)
            continue;
        uint32_t depth = 0;
        for (int32_t p = t->node_parents[j]; p >= 0; p = t->node_parents[p])
            depth++;
        if (depth < best)
            best = depth, r.roots[0] = (int32_t)j;
        char name[256], canonical[CANONICAL_LEN];
        normalise(t->node_names[j], name, sizeof name);
        canonical_of(naming, name, canonical);
        if (strcmp(canonical, "hips") == 0)
            r.roots[1] = (int32_t)j;
    }
    if (r.roots[1] == r.roots[0])
        r.roots[1] = -1;
    /* rest shapes made alike: each matched joint's bone (to its first matched child) turned onto
     * the source's bone in the rest poses (an A-pose target under a T-pose source) */
    for (uint32_t j = 0; j < t->node_count; j++) {
        versor align = GLM_QUAT_IDENTITY_INIT;
        for (uint32_t c = j + 1; match[j] >= 0 && c < t->node_count; c++) {
            if (t->node_parents[c] != (int32_t)j || match[c] < 0)
                continue;
            vec3 bt, bs;
            glm_vec3_sub(r.target_rest[c].m + 12, r.target_rest[j].m + 12, bt);
            glm_vec3_sub(r.source_rest[match[c]].m + 12, r.source_rest[match[j]].m + 12, bs);
            if (glm_vec3_norm(bt) > 1e-6f && glm_vec3_norm(bs) > 1e-6f) {
                glm_vec3_normalize(bt);
                glm_vec3_normalize(bs);
                float c_angle = glm_vec3_dot(bt, bs);
                if (c_angle > -0.999f) { /* opposite bones: left as they are */
                    vec3 axis;
                    glm_vec3_cross(bt, bs, axis);
                    versor q = {axis[0], axis[1], axis[2], 1.0f + c_angle};
                    glm_quat_normalize_to(q, align);
                }
            }
            break;
        }
        if (match[j] < 0)
            continue;
        versor rest_s, rest_t, inv;
        world_rotation(&r.source_rest[match[j]], rest_s);
        world_rotation(&r.target_rest[j], rest_t);
        glm_quat_inv(rest_s, inv);
        glm_quat_mul(align, rest_t, rest_t);
        glm_quat_mul(inv, rest_t, r.base[j]);
    }
    float lt = leg_length(t, r.target_rest), ls = leg_length(s, r.source_rest);
    float ht = r.target_rest[r.roots[0]].m[13], hs = r.source_rest[match[r.roots[0]]].m[13];
    r.scale = lt > 0.0f && ls > 0.0f ? lt / ls : (ht > 0.0f && hs > 0.0f ? ht / hs : 1.0f);
    if (!raw_model_from_model(t, &raw)) {
        result = sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory retargeting", t->source);
        goto out;
    }
    raw_made = true;
    if ((result = matched_by_index(t, s, match) ? copy_clips(s, &raw, error) : bake_clips(&r, &raw, rate, error)))
        goto out;
    raw.muscles = t->muscles;
    void *bytes = NULL;
    size_t size = 0;
    if ((result = raw_model_build(&raw, &bytes, &size, error)) == SINEW_OK) {
        result = sinew_model_from_blob(bytes, size, t->source, NULL, out, error);
        free(bytes);
    }
out:
    if (raw_made)
        raw_model_free(&raw);
    free(match);
    free(r.target_rest);
    free(r.source_rest);
    free(r.source_worlds);
    free(r.source_locals);
    free(r.target_world);
    free(r.target_now);
    free(r.base);
    return result;
}

uint32_t sinew_retarget_matches(const sinew_model *target, const sinew_model *source, int32_t *match)
{
    for (uint32_t i = 0; i < target->node_count; i++)
        match[i] = -1;
    return match_joints(target, source, match);
}
