/* Biovision Hierarchy (.bvh) motion capture files, read by sinew (CMU's motion library and what
 * MotionBuilder, Blender and most capture systems export).
 *
 * What a file holds: HIERARCHY, then one or more ROOTs, each a tree of JOINTs in braces; a joint
 * has an OFFSET (x y z, its position in its parent) and CHANNELS (a count, then that many of
 * Xposition Yposition Zposition Xrotation Yrotation Zrotation, in any order; some exporters add
 * Xscale Yscale Zscale); a leaf may hold an "End Site" with an OFFSET only (where the last bone
 * ends). Then MOTION, "Frames: N", "Frame Time: seconds", and N frames of numbers: every joint's
 * channels, in the order the joints and their channels were declared.
 *
 * How sinew takes it:
 * - every ROOT, JOINT and End Site is a node, all of them the skeleton's joints (a skin with no
 *   mesh); an End Site is named "EndSite_" and its joint's name (as Assimp names it; a joint's
 *   second End Site "EndSite_NAME_2"), so that the last bone of each chain has its length. Names
 *   are the rest of the ROOT or JOINT line (spaces kept). The rest pose is the OFFSETs, unrotated.
 * - the frames are one clip, "Motion", a linear key a frame at `Frame Time` apart (its frame
 *   rate the inverse, as written). A joint's rotation channels are
 *   Euler angles in degrees applied in the order written: "Zrotation Xrotation Yrotation" is
 *   Rz * Rx * Ry (intrinsic Z, then X, then Y), as every reader takes them. Its position
 *   channels give its position in its parent, in place of the OFFSET's coordinates they name
 *   (as Blender and Assimp read them; three.js adds them to the OFFSET, which is the same for
 *   CMU's roots, whose OFFSETs are zero). Scale channels are the joint's scale. A channel that
 *   does not change is one key.
 * - the file's units and axes are kept (BVH has no unit; nearly every file is Y up).
 * - keywords are read in any case; numbers may be written as C writes them ("+1", ".5", "1.").
 *   A file that ends before its last frame keeps the whole frames it has, with a warning.
 *
 * Bad input: a clear error naming the file and line (unbalanced braces, an unknown keyword or
 * channel, a number that is not one or not finite, a hierarchy with no joint, no MOTION).
 */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "../core/internal.h" /* sinew_channel_width */
#include "decimal.h"
#include "internal.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

#define MAX_DEPTH 1024u          /* nested joints: deeper is a hostile file, not a skeleton */
#define MAX_CHANNELS_A_JOINT 64u /* 6 in practice; a count past this is not a BVH file */

/* A channel's kind: CH_* / 3 is its SINEW_CHANNEL_* (translation, rotation, scale), CH_* % 3 its axis. */
enum { CH_XPOS, CH_YPOS, CH_ZPOS, CH_XROT, CH_YROT, CH_ZROT, CH_XSCALE, CH_YSCALE, CH_ZSCALE, CH_KINDS };
_Static_assert(CH_XPOS / 3 == SINEW_CHANNEL_TRANSLATION && CH_XROT / 3 == SINEW_CHANNEL_ROTATION &&
                   CH_XSCALE / 3 == SINEW_CHANNEL_SCALE,
               "CH_* / 3 is the SINEW_CHANNEL_* kind");

typedef struct bvh_joint {
    uint32_t first_channel, channel_count; /* into bvh.channels */
    bool end_site;
    bool has[SINEW_CHANNEL_COUNT]; /* a channel of each kind (translation, rotation, scale) */
    uint32_t end_sites;            /* End Sites below it so far (the second is named "EndSite_NAME_2") */
} bvh_joint;

typedef struct bvh {
    const char *path;
    const char *p, *end; /* the text; *end is a NUL */
    uint32_t line;       /* of p, 1 first */
    raw_model *m;
    sinew_error *error;
    bvh_joint *joints;
    uint32_t joint_capacity;
    uint8_t *channels; /* CH_*, every joint's in order */
    uint32_t channel_count, channel_capacity;
} bvh;

static sinew_result oom(bvh *b)
{
    return sinew_fail(b->error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the BVH file", b->path);
}

/* A FORMAT error at the current line. */
static sinew_result bad(bvh *b, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static sinew_result bad(bvh *b, const char *format, ...)
{
    char what[192];
    va_list args;
    va_start(args, format);
    vsnprintf(what, sizeof what, format, args);
    va_end(args);
    return sinew_fail_at(b->error, SINEW_ERROR_FORMAT, b->path, -1, b->line, "%s: line %u: %s", b->path, b->line, what);
}

/* A token's length as quoted in a message: at most 40 bytes of it. */
static int quoted(size_t n)
{
    return (int)(n < 40 ? n : 40);
}

static bool space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

/* Past the white space at b->p, counting its lines. */
static void skip_space(bvh *b)
{
    const char *p = b->p;
    for (; p < b->end && space(*p); p++)
        b->line += *p == '\n';
    b->p = p;
}

/* A UTF-8 byte order mark's length at the start of `text`: 3 or 0. */
static size_t bom_length(const unsigned char *text, size_t size)
{
    return size >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
}

/* The next token (a run of bytes that are not white space): its start and length; 0 at the end. */
static size_t token(bvh *b, const char **start)
{
    skip_space(b);
    const char *p = b->p, *s = p;
    while (p < b->end && !space(*p) && *p)
        p++;
    b->p = p;
    *start = s;
    return (size_t)(p - s);
}

static bool is(const char *t, size_t n, const char *word)
{
    return n == strlen(word) && strncasecmp(t, word, n) == 0;
}

/* The token t (n bytes) as a double; an error when it is not a number in a float's range. */
static sinew_result number_of(bvh *b, const char *t, size_t n, double *out)
{
    const char *stop;
    if (decimal_scan_within(t, b->end, &stop, out) != 1 || stop != t + n) {
        char *e;
        *out = strtod(t, &e); /* the wider grammar: "+1", ".5", "1.", more digits; the text ends in a NUL */
        if (e != t + n)
            return bad(b, "\"%.*s\" is not a number", quoted(n), t);
    }
    if (!(fabs(*out) <= FLT_MAX))
        return bad(b, "\"%.*s\" is not a finite number a float holds", quoted(n), t);
    return SINEW_OK;
}

/* The next number of a frame, read where it starts (no token found first: a frame's numbers are
 * most of a file); *ended when the text has ended instead. */
static sinew_result frame_number(bvh *b, double *out, bool *ended)
{
    skip_space(b);
    const char *p = b->p;
    *ended = p == b->end || !*p;
    if (*ended)
        return SINEW_OK;
    const char *stop;
    if (decimal_scan_within(p, b->end, &stop, out) == 1 && (stop == b->end || !*stop || space(*stop)) &&
        fabs(*out) <= FLT_MAX) {
        b->p = stop;
        return SINEW_OK;
    }
    const char *t;
    size_t n = token(b, &t);
    return number_of(b, t, n, out);
}

static sinew_result number(bvh *b, double *out)
{
    const char *t;
    size_t n = token(b, &t);
    return n ? number_of(b, t, n, out) : bad(b, "the file ends where a number should be");
}

/* A joint's name: the rest of its line, white space around it (and a '{' after it) left out;
 * `empty` is the error when there is none. */
static sinew_result name_of(bvh *b, const char *empty, char **out)
{
    const char *p = b->p;
    while (p < b->end && (*p == ' ' || *p == '\t'))
        p++;
    const char *s = p;
    while (p < b->end && *p != '\n' && *p != '\r' && *p != '{' && *p)
        p++;
    const char *e = p;
    while (e > s && space(e[-1]))
        e--;
    b->p = p;
    if (e == s)
        return bad(b, "%s", empty);
    if (!(*out = malloc((size_t)(e - s) + 1)))
        return oom(b);
    memcpy(*out, s, (size_t)(e - s));
    (*out)[e - s] = 0;
    return SINEW_OK;
}

/* A new node (and its joint record) below `parent` (-1: a root), named `name` (taken). */
static sinew_result add_node(bvh *b, int32_t parent, char *name, bool end_site)
{
    raw_model *m = b->m;
    if (m->node_count == b->joint_capacity) {
        uint32_t cap = b->joint_capacity ? b->joint_capacity * 2 : 64;
        bool grown = raw_model_grow_nodes(m, cap);
        bvh_joint *joints = realloc(b->joints, cap * sizeof *joints);
        if (joints)
            b->joints = joints;
        if (!grown || !joints) {
            free(name);
            return oom(b);
        }
        b->joint_capacity = cap;
    }
    uint32_t n = m->node_count++;
    m->node_names[n] = name;
    m->node_parents[n] = parent;
    m->node_rest[n] = (sinew_transform){.rotation = {0, 0, 0, 1}, .scale = {1, 1, 1}};
    b->joints[n] = (bvh_joint){.first_channel = b->channel_count, .end_site = end_site};
    return SINEW_OK;
}

/* An End Site's name ("End" read): the rest of the line is "Site" (its '{' may follow at once). */
static sinew_result end_site_name(bvh *b, int32_t top, char **out)
{
    char *site;
    sinew_result r = name_of(b, "\"End\" where \"End Site\" should be", &site);
    if (r)
        return r;
    if (strcasecmp(site, "Site") != 0)
        r = bad(b, "\"End %.40s\" where \"End Site\" should be", site);
    free(site);
    if (r)
        return r;
    if (top < 0)
        return bad(b, "an End Site outside every joint");
    const char *joint = b->m->node_names[top];
    size_t size = strlen(joint) + 20;
    if (!(*out = malloc(size)))
        return oom(b);
    if (b->joints[top].end_sites++ == 0)
        snprintf(*out, size, "EndSite_%s", joint);
    else /* a second End Site of one joint: a name of its own */
        snprintf(*out, size, "EndSite_%s_%u", joint, b->joints[top].end_sites);
    return SINEW_OK;
}

static sinew_result expect_brace(bvh *b)
{
    const char *t;
    size_t n = token(b, &t);
    if (n == 1 && *t == '{')
        return SINEW_OK;
    return n ? bad(b, "\"%.*s\" where a '{' should open the joint", quoted(n), t)
             : bad(b, "the file ends where a '{' should open the joint");
}

static sinew_result read_channels(bvh *b, uint32_t node)
{
    bvh_joint *j = &b->joints[node];
    double count;
    sinew_result r = number(b, &count);
    if (r)
        return r;
    if (j->channel_count || j->end_site)
        return bad(b, "CHANNELS given twice, or in an End Site");
    if (count != floor(count) || count < 0 || count > MAX_CHANNELS_A_JOINT)
        return bad(b, "a CHANNELS count that is not a whole number from 0 to 64");
    static const char *const NAMES[CH_KINDS] = {"Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation",
                                                "Zrotation", "Xscale",    "Yscale",    "Zscale"};
    for (uint32_t c = 0; c < (uint32_t)count; c++) {
        const char *t;
        size_t n = token(b, &t);
        int kind = -1;
        for (int k = 0; k < CH_KINDS && kind < 0; k++)
            kind = is(t, n, NAMES[k]) ? k : -1;
        if (kind < 0)
            return n ? bad(b, "\"%.*s\" is not a BVH channel (Xposition ... Zrotation, Xscale ... Zscale)", quoted(n),
                           t)
                     : bad(b, "the file ends in a CHANNELS list");
        if (b->channel_count == b->channel_capacity) {
            uint32_t cap = b->channel_capacity ? b->channel_capacity * 2 : 256;
            uint8_t *grown = realloc(b->channels, cap);
            if (!grown)
                return oom(b);
            b->channels = grown;
            b->channel_capacity = cap;
        }
        b->channels[b->channel_count++] = (uint8_t)kind;
        j->channel_count++;
        j->has[kind / 3] = true;
    }
    return SINEW_OK;
}

/* HIERARCHY up to MOTION: the nodes, their OFFSETs and channels. */
static sinew_result read_hierarchy(bvh *b)
{
    const char *t;
    size_t n = token(b, &t);
    if (!is(t, n, "HIERARCHY"))
        return bad(b, "\"%.*s\": a BVH file starts with HIERARCHY", quoted(n), t);
    int32_t *stack = malloc(MAX_DEPTH * sizeof *stack);
    if (!stack)
        return oom(b);
    uint32_t depth = 0;
    sinew_result r = SINEW_OK;
    while (!r) {
        n = token(b, &t);
        int32_t top = depth ? stack[depth - 1] : -1;
        if (n == 0) {
            r = bad(b, "the file ends in its HIERARCHY (no MOTION)");
        } else if (is(t, n, "ROOT") || is(t, n, "JOINT") || is(t, n, "End")) {
            bool end_site = is(t, n, "End");
            char *name = NULL;
            if (end_site) {
                r = end_site_name(b, top, &name);
            } else if (is(t, n, "JOINT") && top < 0) {
                r = bad(b, "a JOINT outside every ROOT");
            } else if (is(t, n, "ROOT") && top >= 0) {
                r = bad(b, "a ROOT inside a joint (a '}' is missing before it)");
            } else {
                r = name_of(b, is(t, n, "ROOT") ? "ROOT without a name" : "JOINT without a name", &name);
            }
            if (!r && depth == MAX_DEPTH) {
                free(name);
                r = bad(b, "joints nested more than 1024 deep");
            }
            if (!r && !(r = add_node(b, top, name, end_site)))
                stack[depth++] = (int32_t)(b->m->node_count - 1);
            if (!r)
                r = expect_brace(b);
        } else if (is(t, n, "OFFSET")) {
            double v[3] = {0};
            for (int i = 0; i < 3 && !r; i++)
                r = number(b, &v[i]);
            if (!r && top < 0)
                r = bad(b, "an OFFSET outside every joint");
            for (int i = 0; i < 3 && !r; i++)
                b->m->node_rest[top].translation[i] = (float)v[i];
        } else if (is(t, n, "CHANNELS")) {
            r = top < 0 ? bad(b, "CHANNELS outside every joint") : read_channels(b, (uint32_t)top);
        } else if (n == 1 && *t == '}') {
            if (depth == 0)
                r = bad(b, "a '}' that closes no joint");
            else
                depth--;
        } else if (is(t, n, "MOTION")) {
            if (depth)
                r = bad(b, "MOTION before the joint \"%.40s\" is closed (a '}' is missing)", b->m->node_names[top]);
            else if (b->m->node_count == 0)
                r = bad(b, "a HIERARCHY with no joint");
            break;
        } else {
            r = bad(b, "\"%.*s\" in the HIERARCHY (ROOT, JOINT, End Site, OFFSET, CHANNELS or '}' should be)",
                    quoted(n), t);
        }
    }
    free(stack);
    return r;
}

/* "Frames: N" and "Frame Time: seconds" (the colon may stand apart). */
static sinew_result read_motion_header(bvh *b, double *frames, double *frame_time)
{
    const char *t;
    size_t n = token(b, &t);
    if (!(is(t, n, "Frames:") || (is(t, n, "Frames") && (n = token(b, &t)) == 1 && *t == ':')))
        return bad(b, "\"%.*s\" where \"Frames:\" should follow MOTION", quoted(n), t);
    sinew_result r = number(b, frames);
    if (r)
        return r;
    if (*frames < 0 || *frames != floor(*frames) || *frames > 1e9)
        return bad(b, "\"Frames:\" is not a whole number of frames");
    n = token(b, &t);
    if (!is(t, n, "Frame"))
        return bad(b, "\"%.*s\" where \"Frame Time:\" should be", quoted(n), t);
    n = token(b, &t);
    if (!(is(t, n, "Time:") || (is(t, n, "Time") && (n = token(b, &t)) == 1 && *t == ':')))
        return bad(b, "\"Frame %.*s\" where \"Frame Time:\" should be", quoted(n), t);
    return number(b, frame_time);
}

/* q = q * (rotation of `degrees` about axis `axis`), x y z w in doubles. */
static void turn(double q[4], int axis, double degrees)
{
    double half = degrees * (M_PI / 360.0), s = sin(half), c = cos(half);
    double a[3] = {0, 0, 0};
    a[axis] = s;
    double x = q[3] * a[0] + q[0] * c + q[1] * a[2] - q[2] * a[1];
    double y = q[3] * a[1] + q[1] * c + q[2] * a[0] - q[0] * a[2];
    double z = q[3] * a[2] + q[2] * c + q[0] * a[1] - q[1] * a[0];
    double w = q[3] * c - q[0] * a[0] - q[1] * a[1] - q[2] * a[2];
    q[0] = x, q[1] = y, q[2] = z, q[3] = w;
}

/* A channel of `kind` with `keys` keys a frame apart, times filled in, values left for the caller. */
static bool even_channel(raw_channel *c, int kind, uint32_t keys, double frame_time)
{
    *c = (raw_channel){.interp = SINEW_INTERP_LINEAR, .count = keys, .finite = true};
    c->times = malloc(((size_t)keys + 1) * sizeof *c->times);
    c->values = malloc(((size_t)keys + 1) * sinew_channel_width(kind) * sizeof *c->values);
    if (!c->times || !c->values)
        return false;
    for (uint32_t k = 0; k < keys; k++)
        c->times[k] = (float)(k * frame_time);
    return true;
}

/* A channel of `kind` whose keys are all the same becomes one key. */
static void one_key_if_constant(raw_channel *c, int kind)
{
    uint32_t width = sinew_channel_width(kind);
    for (uint32_t k = 1; k < c->count; k++)
        if (memcmp(c->values + (size_t)k * width, c->values, width * sizeof(float)) != 0)
            return;
    c->count = c->count ? 1 : 0;
}

/* The frames: `declared` of them, of which the rest of the text can hold at most `frames`. */
static sinew_result read_frames(bvh *b, uint32_t declared, uint32_t frames, double frame_time)
{
    raw_model *m = b->m;
    uint32_t animated = 0;
    for (uint32_t j = 0; j < m->node_count; j++)
        animated += b->joints[j].channel_count > 0;
    m->clips = calloc(1, sizeof *m->clips);
    if (!m->clips)
        return oom(b);
    m->clip_count = 1;
    raw_clip *clip = &m->clips[0];
    clip->name = strdup("Motion");
    clip->tracks = calloc(animated ? animated : 1, sizeof *clip->tracks);
    double *row = malloc(((size_t)b->channel_count + 1) * sizeof *row);
    uint32_t *track_of = malloc(((size_t)m->node_count + 1) * sizeof *track_of);
    sinew_result r = !clip->name || !clip->tracks || !row || !track_of ? oom(b) : SINEW_OK;
    for (uint32_t j = 0; j < m->node_count && !r; j++) {
        const bvh_joint *joint = &b->joints[j];
        if (!joint->channel_count)
            continue;
        track_of[j] = clip->track_count;
        raw_track *track = &clip->tracks[clip->track_count++];
        track->node = j;
        for (int k = 0; k < SINEW_CHANNEL_COUNT && !r; k++)
            if (joint->has[k] && !even_channel(&track->channels[k], k, frames, frame_time))
                r = oom(b);
    }
    uint32_t read = 0;
    for (; read < frames && !r; read++) {
        if ((read & 255) == 255 && import_late())
            r = oom(b); /* the import reports its deadline */
        uint32_t c = 0;
        bool ended = false;
        for (; c < b->channel_count && !r && !ended; c++)
            r = frame_number(b, &row[c], &ended);
        c -= ended; /* the file ends inside this frame */
        if (r || c < b->channel_count)
            break;
        for (uint32_t j = 0; j < m->node_count; j++) {
            const bvh_joint *joint = &b->joints[j];
            if (!joint->channel_count)
                continue;
            raw_track *track = &clip->tracks[track_of[j]];
            const float *rest = m->node_rest[j].translation;
            double value[SINEW_CHANNEL_COUNT][4] = {{rest[0], rest[1], rest[2]}, {0, 0, 0, 1}, {1, 1, 1}};
            for (uint32_t i = 0; i < joint->channel_count; i++) {
                int kind = b->channels[joint->first_channel + i];
                double v = row[joint->first_channel + i];
                if (kind / 3 == SINEW_CHANNEL_ROTATION)
                    turn(value[SINEW_CHANNEL_ROTATION], kind % 3, v);
                else /* a position replaces the OFFSET's coordinate; a scale, 1 */
                    value[kind / 3][kind % 3] = v;
            }
            for (int k = 0; k < SINEW_CHANNEL_COUNT; k++) {
                uint32_t width = sinew_channel_width(k);
                for (uint32_t i = 0; joint->has[k] && i < width; i++)
                    track->channels[k].values[(size_t)read * width + i] = (float)value[k][i];
            }
        }
    }
    if (!r && read < declared) {
        if (!raw_model_warn(m, "%s: the file ends after %u of its %u frames (the %u whole ones are kept)", b->path,
                            read, declared, read))
            r = oom(b);
        for (uint32_t i = 0; i < clip->track_count; i++)
            for (int k = 0; k < SINEW_CHANNEL_COUNT; k++)
                if (clip->tracks[i].channels[k].count)
                    clip->tracks[i].channels[k].count = read;
    }
    const char *t;
    if (!r && read == declared && token(b, &t) &&
        !raw_model_warn(m, "%s: line %u: numbers after the last of the %u frames are left out", b->path, b->line,
                        frames))
        r = oom(b);
    for (uint32_t i = 0; i < clip->track_count && !r; i++) {
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++)
            one_key_if_constant(&clip->tracks[i].channels[k], k);
    }
    clip->duration = read ? (float)((read - 1) * frame_time) : 0.0f;
    if (!r && read == 0) { /* no whole frame: no clip */
        raw_clip_free(clip);
        m->clip_count = 0;
    }
    /* the rate as written, not rounded (CMU's 0.0083333 s is 120.0005 a second): sampling at the
     * clip's frame rate then lands on its keys, the last included, where 120 would drift off them
     * (by 1% of a frame at 01_01.bvh's end) and miss the last */
    clip->frame_rate = (float)(1.0 / frame_time);
    free(row);
    free(track_of);
    return r;
}

bool bvh_sniff(const unsigned char *head, size_t size)
{
    size_t i = bom_length(head, size);
    while (i < size && space((char)head[i]))
        i++;
    return size - i >= 9 && strncasecmp((const char *)head + i, "HIERARCHY", 9) == 0 &&
           (size - i == 9 || space((char)head[i + 9]));
}

sinew_result raw_model_from_bvh(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                sinew_error *error)
{
    memset(model, 0, sizeof *model);
    bvh b = {.path = path, .line = 1, .m = model, .error = error};
    /* The scanners stop at a NUL: a file's bytes have one after them (import_read_file); bytes
     * from memory that end inside a token are copied to have one. */
    char *copy = NULL;
    if (size && bytes[size - 1] && !space((char)bytes[size - 1])) {
        if (!(copy = malloc(size + 1)))
            return oom(&b);
        memcpy(copy, bytes, size);
        copy[size] = 0;
    }
    const char *text = copy ? copy : (const char *)bytes;
    b.p = text + bom_length((const unsigned char *)text, size);
    b.end = text + size;
    model->source = strdup(path);
    model->format = strdup("bvh");
    sinew_result r = !model->source || !model->format ? oom(&b) : read_hierarchy(&b);
    double frames = 0, frame_time = 0;
    if (!r)
        r = read_motion_header(&b, &frames, &frame_time);
    if (!r && !(frame_time > 0) && frames > 0) {
        if (!raw_model_warn(model, "%s: \"Frame Time: %g\": played at 30 frames a second", path, frame_time))
            r = oom(&b);
        frame_time = 1.0 / 30.0;
    }
    if (!r && frames > 0 && b.channel_count) { /* (no channel: a skeleton and no clip) */
        /* a value takes two bytes or more (a digit, then a space): frames that the rest of the
         * text cannot hold are not allocated */
        size_t room = ((size_t)(b.end - b.p) / 2 + 1) / b.channel_count;
        uint32_t can = frames < (double)room ? (uint32_t)frames : (uint32_t)room;
        if (can > 1 && (can - 1) * frame_time > 1e6)
            r = bad(&b, "%u frames %g s apart: more than a million seconds", can, frame_time);
        else
            r = read_frames(&b, (uint32_t)frames, can, frame_time);
    }
    if (!r && !raw_model_joints_from(model, 0)) /* every node is a joint: a skeleton with no mesh bound to it */
        r = oom(&b);
    free(copy);
    free(b.joints);
    free(b.channels);
    if (r)
        raw_model_free(model);
    return r;
}
