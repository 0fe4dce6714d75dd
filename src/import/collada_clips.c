/* COLLADA <animation_clip>s that Assimp 5.2.5 merges into one clip.
 *
 * A COLLADA file may cut its animations into named clips (<library_animation_clips>, each
 * <animation_clip start end> instancing some <animation>s). Assimp hands back one clip
 * with every key on one timeline. sinew reads the clip list with libxml2 and cuts Assimp's
 * clip into the file's clips: each keeps the tracks of the nodes its animations target
 * (all tracks when that cannot be told) and the keys inside [start, end], with keys
 * sampled at both ends, shifted to start at 0.
 *
 * Index:
 *   reading the file ..... collect (clips, animations' target nodes, node ids -> names)
 *   cutting .............. slice_channel, cut_clip
 *   collada_split_clips
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libxml/parser.h>
#include <libxml/tree.h>

#include "../core/internal.h"
#include "internal.h"
#include "sinew/anim.h"

#define MAX_CLIP_ANIMATIONS 256

typedef struct file_clip {
    char name[256];
    double start, end;
    bool has_end;
    int animation_count;
    xmlChar *animations[MAX_CLIP_ANIMATIONS]; /* ids, without '#' */
} file_clip;

typedef struct collected {
    file_clip *clips;
    int clip_count;
    xmlNode *root;
} collected;

static bool named(const xmlNode *n, const char *name)
{
    return n->type == XML_ELEMENT_NODE && strcmp((const char *)n->name, name) == 0;
}

static double attr_double(xmlNode *n, const char *key, bool *present)
{
    xmlChar *v = xmlGetProp(n, (const xmlChar *)key);
    *present = v != NULL;
    double d = v ? strtod((const char *)v, NULL) : 0.0;
    xmlFree(v);
    return isfinite(d) ? d : 0.0;
}

static bool read_clip(xmlNode *n, int index, file_clip *out)
{
    memset(out, 0, sizeof *out);
    bool has_start;
    out->start = attr_double(n, "start", &has_start);
    out->end = attr_double(n, "end", &out->has_end);
    xmlChar *name = xmlGetProp(n, (const xmlChar *)"name");
    if (!name)
        name = xmlGetProp(n, (const xmlChar *)"id");
    if (name)
        snprintf(out->name, sizeof out->name, "%s", (const char *)name);
    else
        snprintf(out->name, sizeof out->name, "clip %d", index);
    xmlFree(name);
    for (xmlNode *c = n->children; c; c = c->next) {
        if (!named(c, "instance_animation") || out->animation_count == MAX_CLIP_ANIMATIONS)
            continue;
        xmlChar *url = xmlGetProp(c, (const xmlChar *)"url");
        if (url && url[0] == '#')
            out->animations[out->animation_count++] = xmlStrdup(url + 1);
        xmlFree(url);
    }
    return true;
}

static void collect_clips(xmlNode *n, collected *c)
{
    for (; n; n = n->next) {
        if (named(n, "animation_clip")) {
            file_clip *grown = realloc(c->clips, (size_t)(c->clip_count + 1) * sizeof *grown);
            if (!grown)
                return;
            c->clips = grown;
            read_clip(n, c->clip_count, &c->clips[c->clip_count]);
            c->clip_count++;
        }
        collect_clips(n->children, c);
    }
}

static xmlNode *find_by_id(xmlNode *n, const char *element, const xmlChar *id)
{
    for (; n; n = n->next) {
        if (named(n, element)) {
            xmlChar *v = xmlGetProp(n, (const xmlChar *)"id");
            bool match = v && xmlStrEqual(v, id);
            xmlFree(v);
            if (match)
                return n;
        }
        xmlNode *found = find_by_id(n->children, element, id);
        if (found)
            return found;
    }
    return NULL;
}

/* Marks in `wanted` the sinew nodes that <channel target="NODE/..."> elements under
 * `animation` (nested ones too) drive. A node is named by its name attribute, or its id
 * when it has none, as Assimp names it. Returns how many channels were resolved. */
static int mark_targets(const collected *c, xmlNode *animation, const raw_model *m, bool *wanted)
{
    int resolved = 0;
    for (xmlNode *n = animation->children; n; n = n->next) {
        if (named(n, "animation")) {
            resolved += mark_targets(c, n, m, wanted);
            continue;
        }
        if (!named(n, "channel"))
            continue;
        xmlChar *target = xmlGetProp(n, (const xmlChar *)"target");
        if (!target)
            continue;
        size_t len = strcspn((const char *)target, "/(.");
        xmlChar *id = xmlStrndup(target, (int)len);
        xmlNode *node = find_by_id(c->root, "node", id);
        xmlChar *name = node ? xmlGetProp(node, (const xmlChar *)"name") : NULL;
        const char *want = (const char *)(name ? name : id);
        for (uint32_t i = 0; i < m->node_count; i++)
            if (strcmp(m->node_names[i], want) == 0) {
                wanted[i] = true;
                resolved++;
                break;
            }
        xmlFree(name);
        xmlFree(id);
        xmlFree(target);
    }
    return resolved;
}

/* ---- cutting ------------------------------------------------------------------------------ */

/* Value of a raw channel at time t, through the runtime sampler. */
static void eval_raw(const raw_channel *ch, int kind, float t, float *out)
{
    sinew_clip view = {.times = ch->times, .values = ch->values, .time_count = ch->count};
    sinew_channel channel = {ch->count, ch->interp, 0, 0};
    sinew_channel_eval(&view, &channel, kind, t, NULL, out);
}

/* The keys of `in` inside [start, end], with keys sampled at both ends, shifted by -start. */
static bool slice_channel(const raw_channel *in, int kind, float start, float end, raw_channel *out)
{
    *out = (raw_channel){.interp = in->interp};
    if (in->count == 0)
        return true;
    uint32_t width = sinew_channel_width(kind);
    uint32_t stride = sinew_channel_stride(kind, in->interp);
    out->times = malloc(((size_t)in->count + 2) * sizeof(float));
    out->values = malloc(((size_t)in->count + 2) * stride * sizeof(float));
    if (!out->times || !out->values)
        return false;
    /* cubic keys carry tangents: the end keys get zero ones */
    uint32_t at = in->interp == SINEW_INTERP_CUBIC ? width : 0;
    memset(out->values, 0, ((size_t)in->count + 2) * stride * sizeof(float));
    out->times[0] = 0.0f;
    eval_raw(in, kind, start, &out->values[at]);
    uint32_t n = 1;
    for (uint32_t k = 0; k < in->count; k++)
        if (in->times[k] > start && in->times[k] < end) {
            out->times[n] = in->times[k] - start;
            memcpy(&out->values[(size_t)n * stride], &in->values[(size_t)k * stride], stride * sizeof(float));
            n++;
        }
    if (end > start) {
        out->times[n] = end - start;
        eval_raw(in, kind, end, &out->values[(size_t)n * stride + at]);
        n++;
    }
    out->count = n;
    return true;
}

static bool cut_clip(const raw_clip *whole, const file_clip *fc, const bool *wanted, raw_clip *out)
{
    memset(out, 0, sizeof *out);
    float start = (float)fmax(0.0, fc->start);
    float end = fc->has_end ? (float)fc->end : whole->duration;
    if (end < start)
        end = start;
    out->name = raw_strdup(fc->name);
    out->duration = end - start;
    out->tracks = calloc(whole->track_count ? whole->track_count : 1, sizeof *out->tracks);
    if (!out->name || !out->tracks)
        return false;
    for (uint32_t t = 0; t < whole->track_count; t++) {
        const raw_track *in = &whole->tracks[t];
        if (wanted && !wanted[in->node])
            continue;
        raw_track *track = &out->tracks[out->track_count++];
        track->node = in->node;
        for (int k = 0; k < SINEW_CHANNEL_COUNT; k++)
            if (!slice_channel(&in->channels[k], k, start, end, &track->channels[k]))
                return false;
    }
    return true;
}

static void free_collected(collected *c)
{
    for (int i = 0; i < c->clip_count; i++)
        for (int a = 0; a < c->clips[i].animation_count; a++)
            xmlFree(c->clips[i].animations[a]);
    free(c->clips);
}

void collada_split_clips(const char *path, raw_model *m)
{
    if (m->clip_count != 1)
        return;
    unsigned char *bytes = NULL;
    size_t size = 0;
    if (!import_read_file(path, &bytes, &size))
        return;
    xmlDocPtr doc = size <= INT32_MAX ? import_xml_parse(path, bytes, size) : NULL;
    free(bytes);
    if (!doc)
        return;
    collected c = {.root = xmlDocGetRootElement(doc)};
    collect_clips(c.root, &c);
    raw_clip *clips = c.clip_count ? calloc((size_t)c.clip_count, sizeof *clips) : NULL;
    bool *wanted = calloc(m->node_count ? m->node_count : 1, sizeof *wanted);
    bool ok = clips && wanted;
    for (int i = 0; ok && i < c.clip_count; i++) {
        memset(wanted, 0, (m->node_count ? m->node_count : 1) * sizeof *wanted);
        int resolved = 0;
        for (int a = 0; a < c.clips[i].animation_count; a++) {
            xmlNode *animation = find_by_id(c.root, "animation", c.clips[i].animations[a]);
            if (animation)
                resolved += mark_targets(&c, animation, m, wanted);
        }
        ok = cut_clip(&m->clips[0], &c.clips[i], resolved ? wanted : NULL, &clips[i]);
    }
    if (ok) {
        raw_clip_free(&m->clips[0]);
        free(m->clips);
        m->clips = clips;
        m->clip_count = (uint32_t)c.clip_count;
        raw_model_warn(m, "the file's %d <animation_clip>s were cut from the one clip Assimp makes of them",
                       c.clip_count);
    } else if (clips) {
        for (int i = 0; i < c.clip_count; i++)
            raw_clip_free(&clips[i]);
        free(clips);
    }
    free(wanted);
    free_collected(&c);
    xmlFreeDoc(doc);
}
