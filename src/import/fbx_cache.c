/* Geometry cache files that FBX vertex cache deformers name: Maya's (an .xml description and
 * .mc / .mcx data, one file or one a frame) and 3ds Max's point caches (.pc2).
 *
 *   Maya ........ read_description (the XML: cache type, format, channels), then the data in
 *                 IFF chunks: "FOR4" groups with 4-byte sizes (.mc) or "FOR8" groups with
 *                 8-byte sizes (.mcx), each frame a MYCH group of TIME (ticks, 6000 a second),
 *                 then for each channel CHNM (its name), SIZE (vectors) and FVCA / DVCA
 *                 (big-endian float / double xyz)
 *   3ds Max ..... "POINTCACHE2", version, points, start frame, frames a sample, samples, then
 *                 little-endian float xyz, sample after sample
 *
 * Only the positions of one channel are kept, as seconds and xyz frames. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "xml.h" /* libxml2, loaded on first use */

#include "fbx_scene.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

#define MAYA_TICKS_PER_SECOND 6000.0
#define MAX_FRAMES 1000000u

typedef struct reader {
    const char *path;
    char *why;
    size_t why_size;
    fbx_cache_data *out;
    uint32_t capacity;
} reader;

static sinew_result fail(reader *r, sinew_result kind, const char *what)
{
    snprintf(r->why, r->why_size, "%s: %s", r->path, what);
    return kind;
}

/* ---- frames ------------------------------------------------------------------------------ */

/* Appends a frame of `points` xyz (doubles or floats, big- or little-endian). */
static sinew_result add_frame(reader *r, double seconds, const unsigned char *data, uint32_t points, int size,
                              bool big_endian)
{
    fbx_cache_data *c = r->out;
    if (c->frame_count == 0)
        c->point_count = points;
    if (points != c->point_count)
        return fail(r, SINEW_ERROR_DATA, "its frames have different numbers of points");
    if (c->frame_count == MAX_FRAMES)
        return fail(r, SINEW_ERROR_DATA, "it has more than a million frames");
    if (c->frame_count == r->capacity) {
        uint32_t cap = r->capacity ? r->capacity * 2 : 16;
        float *times = realloc(c->times, cap * sizeof *times);
        if (times)
            c->times = times;
        float *pos = realloc(c->positions, (size_t)cap * (points ? points : 1) * 3 * sizeof *pos);
        if (pos)
            c->positions = pos;
        if (!times || !pos)
            return SINEW_ERROR_OUT_OF_MEMORY;
        r->capacity = cap;
    }
    float *out = c->positions + (size_t)c->frame_count * points * 3;
    for (size_t i = 0; i < (size_t)points * 3; i++) {
        const unsigned char *b = data + i * (size_t)size;
        unsigned char v[8];
        for (int k = 0; k < size; k++)
            v[k] = big_endian ? b[size - 1 - k] : b[k];
        double x;
        if (size == 8) {
            memcpy(&x, v, 8);
        } else {
            float f;
            memcpy(&f, v, 4);
            x = f;
        }
        if (!isfinite(x))
            return fail(r, SINEW_ERROR_DATA, "it has a position that is not finite");
        out[i] = (float)x;
    }
    c->times[c->frame_count++] = (float)seconds;
    return SINEW_OK;
}

/* ---- Maya's IFF chunks ------------------------------------------------------------------ */

typedef struct chunk {
    char tag[5];
    const unsigned char *data;
    uint64_t size;
} chunk;

static uint64_t be(const unsigned char *b, int n)
{
    uint64_t v = 0;
    for (int i = 0; i < n; i++)
        v = v << 8 | b[i];
    return v;
}

/* The chunk at *at within [*, end): FOR4 layout (tag, 4-byte size, padded to 4) or FOR8 (tag,
 * 4 unused bytes, 8-byte size, padded to 8; groups to 4). False at the end or on a chunk that overruns. */
static bool next_chunk(const unsigned char **at, const unsigned char *end, bool wide, chunk *c)
{
    size_t head = wide ? 16 : 8, align = wide ? 8 : 4;
    if ((size_t)(end - *at) < head)
        return false;
    memcpy(c->tag, *at, 4);
    c->tag[4] = 0;
    c->size = wide ? be(*at + 8, 8) : be(*at + 4, 4);
    c->data = *at + head;
    if (c->size > (uint64_t)(end - c->data))
        return false;
    if (!memcmp(c->tag, "FOR", 3))
        align = 4; /* a group's size already covers its children's padding */
    uint64_t padded = (c->size + align - 1) / align * align;
    *at = padded > (uint64_t)(end - c->data) ? end : c->data + padded;
    return true;
}

/* One MYCH group: its TIME (or `time`, for a file of one frame) and the wanted channel. */
static sinew_result read_block(reader *r, const chunk *group, bool wide, const char *channel, double time, bool *found)
{
    const unsigned char *at = group->data + 4, *end = group->data + group->size;
    chunk c;
    bool mine = false;
    uint32_t size = 0;
    double seconds = time;
    while (next_chunk(&at, end, wide, &c)) {
        if (!strcmp(c.tag, "TIME") && c.size >= 4) {
            seconds = (double)(int32_t)be(c.data, 4) / MAYA_TICKS_PER_SECOND;
        } else if (!strcmp(c.tag, "CHNM")) {
            size_t n = strnlen((const char *)c.data, (size_t)c.size);
            mine = !channel || (n == strlen(channel) && memcmp(c.data, channel, n) == 0);
        } else if (!strcmp(c.tag, "SIZE") && c.size >= 4) {
            size = (uint32_t)be(c.data, 4);
        } else if (mine && (!strcmp(c.tag, "FVCA") || !strcmp(c.tag, "DVCA"))) {
            int bytes = c.tag[0] == 'F' ? 4 : 8;
            if ((uint64_t)size * 3 * (uint64_t)bytes > c.size)
                return fail(r, SINEW_ERROR_DATA, "a frame's data is shorter than its SIZE says");
            *found = true;
            return add_frame(r, seconds, c.data, size, bytes, true);
        }
    }
    return SINEW_OK;
}

/* A .mc / .mcx file: its CACH header (STIM: the time of a file of one frame) and its frames. */
static sinew_result read_maya_data(reader *r, const char *path, const char *channel, double time)
{
    unsigned char *bytes = NULL;
    size_t size = 0;
    const char *was = r->path;
    r->path = path;
    if (!import_read_file(path, &bytes, &size)) {
        sinew_result result = errno == ENOMEM ? fail(r, SINEW_ERROR_OUT_OF_MEMORY, "out of memory reading it")
                                              : fail(r, SINEW_ERROR_IO, "cannot be read");
        r->path = was;
        return result;
    }
    bool wide = size >= 4 && memcmp(bytes, "FOR8", 4) == 0;
    sinew_result result = SINEW_OK;
    if (!wide && !(size >= 4 && memcmp(bytes, "FOR4", 4) == 0))
        result = fail(r, SINEW_ERROR_FORMAT, "is not a Maya cache (no FOR4 or FOR8 chunk)");
    const unsigned char *at = bytes, *end = bytes + size;
    chunk group;
    bool found = false;
    while (!result && next_chunk(&at, end, wide, &group)) {
        if (group.size < 4 || (strcmp(group.tag, "FOR4") && strcmp(group.tag, "FOR8")))
            continue;
        if (!memcmp(group.data, "CACH", 4)) {
            const unsigned char *c_at = group.data + 4, *c_end = group.data + group.size;
            chunk c;
            while (next_chunk(&c_at, c_end, wide, &c))
                if (!strcmp(c.tag, "STIM") && c.size >= 4)
                    time = (double)(int32_t)be(c.data, 4) / MAYA_TICKS_PER_SECOND;
        } else if (!memcmp(group.data, "MYCH", 4)) {
            result = read_block(r, &group, wide, channel, time, &found);
        }
    }
    free(bytes);
    if (!result && !found)
        result = fail(r, SINEW_ERROR_DATA, "has no frame of the cache's positions channel");
    r->path = was;
    return result;
}

/* ---- Maya's description ----------------------------------------------------------------- */

typedef struct description {
    bool per_frame;
    bool wide;               /* Format mcx */
    char channel[256];       /* the positions channel sinew reads */
    double start, end, step; /* ticks */
} description;

static bool attr_is(xmlNode *n, const char *name, const char *value)
{
    xmlChar *v = xmlGetProp(n, (const xmlChar *)name);
    bool same = v && strcmp((const char *)v, value) == 0;
    xmlFree(v);
    return same;
}

static double attr_num(xmlNode *n, const char *name, double fallback)
{
    xmlChar *v = xmlGetProp(n, (const xmlChar *)name);
    char *stop = NULL;
    double x = v ? strtod((const char *)v, &stop) : fallback;
    if (v && stop == (char *)v)
        x = fallback;
    xmlFree(v);
    return x;
}

static xmlNode *element(xmlNode *parent, const char *name)
{
    for (xmlNode *n = parent ? parent->children : NULL; n; n = n->next)
        if (n->type == XML_ELEMENT_NODE && !strcmp((const char *)n->name, name))
            return n;
    return NULL;
}

/* The cache's type and format, and the channel to read: `wanted` when it names a positions
 * channel, else the first positions channel. */
static sinew_result read_description(reader *r, const unsigned char *bytes, size_t size, const char *wanted,
                                     description *d)
{
    xmlDoc *doc = import_xml_parse(r->path, bytes, size, NULL);
    if (!doc)
        return fail(r, SINEW_ERROR_FORMAT, "is not well-formed XML");
    xmlNode *root = xmlDocGetRootElement(doc);
    sinew_result result = SINEW_OK;
    memset(d, 0, sizeof *d);
    if (!root || strcmp((const char *)root->name, "Autodesk_Cache_File")) {
        result = fail(r, SINEW_ERROR_FORMAT, "is not a Maya cache description (no Autodesk_Cache_File)");
    } else {
        xmlNode *type = element(root, "cacheType");
        d->per_frame = type && attr_is(type, "Type", "OneFilePerFrame");
        d->wide = type && attr_is(type, "Format", "mcx");
        xmlNode *per = element(root, "cacheTimePerFrame");
        d->step = per ? attr_num(per, "TimePerFrame", 250) : 250;
        for (xmlNode *ch = element(root, "Channels") ? element(root, "Channels")->children : NULL; ch; ch = ch->next) {
            if (ch->type != XML_ELEMENT_NODE || !attr_is(ch, "ChannelInterpretation", "positions"))
                continue;
            xmlChar *name = xmlGetProp(ch, (const xmlChar *)"ChannelName");
            bool is_wanted = name && wanted && !strcmp((const char *)name, wanted);
            if (name && (!d->channel[0] || is_wanted)) {
                snprintf(d->channel, sizeof d->channel, "%s", (const char *)name);
                d->start = attr_num(ch, "StartTime", 0);
                d->end = attr_num(ch, "EndTime", 0);
                d->step = attr_num(ch, "SamplingRate", d->step);
            }
            xmlFree(name);
            if (is_wanted)
                break;
        }
        if (!d->channel[0])
            result = fail(r, SINEW_ERROR_DATA, "describes no positions channel");
        else if (!(d->step > 0) || !(d->end >= d->start) || (d->end - d->start) / d->step > MAX_FRAMES)
            result = fail(r, SINEW_ERROR_DATA, "has a time range or sampling rate sinew cannot read");
    }
    xmlFreeDoc(doc);
    return result;
}

/* The description's data: the file beside it with the data's extension, or one a frame
 * ("<name>Frame<n>.mc", "<name>Frame<n>Tick<t>.mc" between frames). */
static sinew_result read_maya(reader *r, const unsigned char *bytes, size_t size, const char *channel)
{
    description d;
    sinew_result result = read_description(r, bytes, size, channel, &d);
    if (result)
        return result;
    const char *ext = d.wide ? ".mcx" : ".mc";
    size_t base = strlen(r->path);
    const char *dot = strrchr(r->path, '.'), *slash = strrchr(r->path, '/');
    if (dot && (!slash || dot > slash))
        base = (size_t)(dot - r->path);
    char data[4096];
    if (!d.per_frame) {
        snprintf(data, sizeof data, "%.*s%s", (int)base, r->path, ext);
        return read_maya_data(r, data, d.channel, d.start / MAYA_TICKS_PER_SECOND);
    }
    for (double t = d.start; t <= d.end && !result; t += d.step) {
        long frame = (long)floor(t / d.step), tick = (long)llround(t - (double)frame * d.step);
        if (tick)
            snprintf(data, sizeof data, "%.*sFrame%ldTick%ld%s", (int)base, r->path, frame, tick, ext);
        else
            snprintf(data, sizeof data, "%.*sFrame%ld%s", (int)base, r->path, frame, ext);
        result = read_maya_data(r, data, d.channel, t / MAYA_TICKS_PER_SECOND);
    }
    return result;
}

/* ---- 3ds Max's point cache -------------------------------------------------------------- */

static uint32_t le32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static float lef(const unsigned char *b)
{
    uint32_t u = le32(b);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static sinew_result read_pc2(reader *r, const unsigned char *bytes, size_t size, double frame_rate)
{
    if (size < 32 || memcmp(bytes, "POINTCACHE2", 12) != 0)
        return fail(r, SINEW_ERROR_FORMAT, "is not a point cache (no POINTCACHE2 header)");
    uint32_t points = le32(bytes + 16), samples = le32(bytes + 28);
    float start = lef(bytes + 20), rate = lef(bytes + 24);
    if (!isfinite(start) || !isfinite(rate) || samples > MAX_FRAMES)
        return fail(r, SINEW_ERROR_DATA, "has a start, rate or sample count sinew cannot read");
    if ((uint64_t)points * 12 * samples > size - 32)
        return fail(r, SINEW_ERROR_DATA, "is shorter than its header says (it seems cut short)");
    double fps = frame_rate > 0 ? frame_rate : 30.0;
    for (uint32_t i = 0; i < samples; i++) {
        sinew_result result =
            add_frame(r, (start + (double)i * rate) / fps, bytes + 32 + (size_t)i * points * 12, points, 4, false);
        if (result)
            return result;
    }
    return SINEW_OK;
}

sinew_result fbx_cache_read(const char *path, const char *channel, double frame_rate, fbx_cache_data *out, char *why,
                            size_t why_size)
{
    memset(out, 0, sizeof *out);
    reader r = {.path = path, .why = why, .why_size = why_size, .out = out};
    unsigned char *bytes = NULL;
    size_t size = 0;
    if (!import_read_file(path, &bytes, &size))
        return errno == ENOMEM ? fail(&r, SINEW_ERROR_OUT_OF_MEMORY, "out of memory reading it")
                               : fail(&r, SINEW_ERROR_IO, "cannot be read");
    sinew_result result = size >= 11 && memcmp(bytes, "POINTCACHE2", 11) == 0 ? read_pc2(&r, bytes, size, frame_rate)
                                                                              : read_maya(&r, bytes, size, channel);
    free(bytes);
    if (!result && out->frame_count == 0)
        result = fail(&r, SINEW_ERROR_DATA, "has no frames");
    if (result)
        fbx_cache_free(out);
    return result;
}

void fbx_cache_free(fbx_cache_data *c)
{
    free(c->times);
    free(c->positions);
    memset(c, 0, sizeof *c);
}
