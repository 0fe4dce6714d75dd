/* sinew_import: checks the path, reads a .sinew file directly, or picks the reader (sinew's
 * own for FBX, glTF, COLLADA, IQM and BVH, Assimp for the rest) and runs it: sinew's own in this
 * process under the import's byte limit and deadline (or in the import helper when the desc
 * asks to isolate it), Assimp always in the helper (isolate.c), which libsinew never links;
 * then turns the blob made into a runtime model.
 */
#define _GNU_SOURCE /* realpath, mkostemp */
#include <errno.h>
#include <libgen.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "xml.h" /* libxml2, loaded on first use */

#include "../core/internal.h"
#include "fbx_internal.h"
#include "internal.h"
#include "sinew/import.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

/* A file's first bytes and its size, read once for the questions below: is it a .sinew file,
 * which reader reads it, how much memory may its import take. */
typedef struct file_head {
    unsigned char bytes[1024];
    size_t size;        /* of bytes[] read: fewer when the file is shorter, 0 when it cannot be read */
    uint64_t file_size; /* 0 where not known */
} file_head;

/* The file at `path` opened once: SINEW_OK with its head, else why it cannot be imported (not
 * there, not readable, a directory or other file that is not regular, empty). */
static sinew_result check_path(const char *path, file_head *head, sinew_error *error)
{
    head->size = 0;
    head->file_size = 0;
    uint64_t file_size;
    int fd = sinew_open_regular(path, &file_size);
    if (fd < 0) { /* what it is, only now that it cannot be read */
        int why = errno;
        struct stat st;
        if (stat(path, &st) != 0)
            return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
        if (S_ISDIR(st.st_mode))
            return sinew_fail(error, SINEW_ERROR_IO, "%s: is a directory, not a model file", path);
        if (!S_ISREG(st.st_mode))
            return sinew_fail(error, SINEW_ERROR_IO, "%s: not a regular file", path);
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot read: %s", path, strerror(why));
    }
    sinew_result result = SINEW_OK;
    if (file_size == 0) {
        result = sinew_fail(error, SINEW_ERROR_FORMAT, "%s: the file is empty", path);
    } else {
        head->size = sinew_read_fully(fd, head->bytes, sizeof head->bytes);
        head->file_size = file_size;
    }
    close(fd);
    return result;
}

/* The head of a file not checked (a session's, which may come through the caller's read_file):
 * nothing read where check_path() would refuse it. */
static file_head head_of(const char *path)
{
    file_head h;
    check_path(path, &h, NULL);
    return h;
}

/* A .sinew file, by its magic (whatever its name): read by sinew_model_load(), not Assimp. */
static bool is_sinew_file(const file_head *h)
{
    return h->size >= sizeof BLOB_MAGIC - 1 && memcmp(h->bytes, BLOB_MAGIC, sizeof BLOB_MAGIC - 1) == 0;
}

/* The file callback of the import running on this thread (sinew_import_desc.read_file), if any:
 * the readers' external parts go through it. */
static _Thread_local const sinew_import_desc *reading_for;

bool import_read_file(const char *path, unsigned char **bytes, size_t *size)
{
    if (reading_for && reading_for->read_file) {
        void *got = NULL;
        size_t n = 0;
        if (!reading_for->read_file(path, &got, &n, reading_for->read_user)) {
            errno = ENOENT;
            return false;
        }
        /* the readers want a NUL after the bytes (text formats) */
        unsigned char *buf = realloc(got, n + 1);
        if (!buf) {
            free(got);
            errno = ENOMEM;
            return false;
        }
        buf[n] = 0;
        *bytes = buf;
        *size = n;
        return true;
    }
    uint64_t file_size;
    int fd = sinew_open_regular(path, &file_size); /* EINVAL: a FIFO or device would block or never end */
    if (fd < 0)
        return false;
    bool ok = file_size < SIZE_MAX;
    size_t n = ok ? (size_t)file_size : 0;
    /* A large file's pages in one call, not a fault a page; in 2 MB pages from IMPORT_PAGES_MIN. (Not the
     * file mapped: a file truncated while mapped ends the process with SIGBUS, and sinew-view --watch
     * reads files being rewritten.) */
    unsigned char *buf = ok ? import_large_alloc(n + 1, IMPORT_PAGES_MIN) : NULL;
    bool starved = ok && !buf;
    errno = 0;
    size_t got = buf ? sinew_read_fully(fd, buf, n) : 0;
    ok = buf && got == n;
    /* what failed, not what close() leaves: a file cut short while read reads as an I/O error */
    int why = starved ? ENOMEM : !ok && errno == 0 ? (buf ? EIO : EINVAL) : errno;
    close(fd);
    if (!ok) {
        free(buf);
        errno = why;
        return false;
    }
    buf[n] = 0;
    *bytes = buf;
    *size = (size_t)n;
    return true;
}

sinew_result import_write_file(const char *path, const void *bytes, size_t size, sinew_error *error)
{
    struct stat st;
    bool in_place = stat(path, &st) == 0 && !S_ISREG(st.st_mode); /* /dev/stdout, a FIFO */
    if (in_place && S_ISDIR(st.st_mode))
        return sinew_fail(error, SINEW_ERROR_IO, "%s: is a folder, not a file", path);
    size_t n = strlen(path) + 16;
    char *temp = malloc(n);
    if (!temp)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    int fd = -1;
    if (in_place) {
        snprintf(temp, n, "%s", path);
        fd = open(path, O_WRONLY | O_CLOEXEC);
    } else {
        /* beside the target, renamed over it once whole: a failed write leaves no half file */
        snprintf(temp, n, "%s.XXXXXX", path);
        fd = mkostemp(temp, O_CLOEXEC);
        if (fd >= 0) {
            mode_t mask = umask(0);
            umask(mask);
            fchmod(fd, 0666 & ~mask);
        }
    }
    if (fd < 0) {
        sinew_result r = sinew_fail(error, SINEW_ERROR_IO, "%s: cannot write: %s", path, strerror(errno));
        free(temp);
        return r;
    }
    const char *p = bytes;
    size_t left = size;
    int failure = 0;
    while (left > 0 && !failure) {
        ssize_t w = write(fd, p, left);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            failure = w < 0 ? errno : EIO;
        else
            p += w, left -= (size_t)w;
    }
    if (close(fd) != 0 && !failure)
        failure = errno;
    if (!failure && !in_place && rename(temp, path) != 0)
        failure = errno;
    if (failure && !in_place)
        unlink(temp);
    free(temp);
    if (failure)
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot write: %s; nothing was written", path, strerror(failure));
    return SINEW_OK;
}

void import_uri_decode(const char *uri, char *out, size_t size)
{
    size_t n = 0;
    for (const char *p = uri; *p && n + 1 < size; p++) {
        unsigned hi, lo;
        if (p[0] == '%' && p[1] && p[2] && sscanf(p + 1, "%1x%1x", &hi, &lo) == 2) {
            out[n++] = (char)(hi * 16 + lo);
            p += 2;
        } else {
            out[n++] = *p;
        }
    }
    out[n] = 0;
}

static int base64_value(int c)
{
    if (c >= 'A' && c <= 'Z')
        return c - 'A';
    if (c >= 'a' && c <= 'z')
        return c - 'a' + 26;
    if (c >= '0' && c <= '9')
        return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
}

size_t import_base64_decode(const char *text, size_t len, unsigned char *out)
{
    uint32_t acc = 0;
    int bits = 0;
    size_t n = 0;
    for (size_t i = 0; i < len; i++) {
        unsigned char c = (unsigned char)text[i];
        if (c == '=') { /* padding: the group ends */
            acc = 0, bits = 0;
            continue;
        }
        if (c == '\n' || c == '\r')
            continue;
        int v = base64_value(c);
        if (v < 0)
            return SIZE_MAX;
        acc = acc << 6 | (uint32_t)v;
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out[n++] = (unsigned char)(acc >> bits);
        }
    }
    return n;
}

char *import_find_texture(const char *model_path, const char *reference, bool by_name, char *looked, size_t looked_size)
{
    char name[4096], folder[4096], path[8192];
    snprintf(name, sizeof name, "%s", reference);
    for (char *c = name; *c; c++)
        if (*c == '\\')
            *c = '/';
    snprintf(folder, sizeof folder, "%s", model_path);
    const char *dir = dirname(folder);
    if (by_name)
        snprintf(path, sizeof path, "%s/%s", dir, strrchr(name, '/') ? strrchr(name, '/') + 1 : name);
    else if (name[0] == '/')
        snprintf(path, sizeof path, "%s", name);
    else
        snprintf(path, sizeof path, "%s/%s", dir, name);
    snprintf(looked, looked_size, "%s", path);
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode))
        return NULL;
    char resolved[PATH_MAX];
    return raw_strdup(realpath(path, resolved) ? resolved : path);
}

bool import_material_texture(raw_model *model, const char *model_path, const char *material, const char *reference,
                             char **out)
{
    char looked[8192];
    bool drive = reference[0] && reference[1] == ':';
    *out = drive ? NULL : import_find_texture(model_path, reference, false, looked, sizeof looked);
    if (!*out)
        *out = import_find_texture(model_path, reference, true, looked, sizeof looked);
    return *out || raw_model_warn(model, "%s: material \"%s\": texture \"%s\" not found (looked for %s)", model_path,
                                  material, reference, looked);
}

float import_roughness_of_shininess(double exponent)
{
    if (!isfinite(exponent) || exponent < 0.0)
        return 0.5f;
    if (exponent < 1.0)
        exponent *= 128.0;
    return (float)pow(2.0 / (exponent + 2.0), 0.25);
}

static void quiet(void *context, const char *format, ...)
{
    (void)context;
    (void)format;
}

/* The first error of a parse (libxml2's last one is often a consequence: "premature end"). */
static void first_error(void *context, const xmlError *e)
{
    import_xml_error *first = context;
    if (first->line || !e || e->level < XML_ERR_ERROR)
        return;
    first->line = e->line > 0 ? e->line : 1;
    snprintf(first->message, sizeof first->message, "%s", e->message ? e->message : "no reason given");
    char *nl = strchr(first->message, '\n');
    if (nl)
        *nl = '\0';
}

struct _xmlDoc *import_xml_parse(const char *path, const unsigned char *bytes, size_t size, import_xml_error *first)
{
    /* libxml2 reports errors through its generic and structured handlers, which print to stderr
     * whatever the parse options say; the library never prints, so both are taken for the parse:
     * the first error is kept for the caller's message */
    import_xml_error ignored = {0};
    if (!first)
        first = &ignored;
    memset(first, 0, sizeof *first);
    if (!import_xml_load(first->message, sizeof first->message)) {
        first->unavailable = true;
        return NULL;
    }
    xmlGenericErrorFunc printer = xmlGenericError;
    void *printer_context = xmlGenericErrorContext;
    xmlStructuredErrorFunc structured = xmlStructuredError;
    void *structured_context = xmlStructuredErrorContext;
    xmlSetGenericErrorFunc(NULL, quiet);
    xmlSetStructuredErrorFunc(first, (xmlStructuredErrorFunc)first_error);
    /* NOBLANKS: no text nodes for the white space between elements (in a pretty-printed
     * COLLADA file, every other node); COMPACT: short texts kept in their node. Neither
     * changes what the readers see, and robot_walk.dae's import faults in 90 fewer pages. */
    xmlDoc *doc = xmlReadMemory((const char *)bytes, (int)size, path, NULL,
                                XML_PARSE_NONET | XML_PARSE_NOWARNING | XML_PARSE_NOERROR | XML_PARSE_HUGE |
                                    XML_PARSE_NOBLANKS | XML_PARSE_COMPACT);
    xmlSetGenericErrorFunc(printer_context, printer);
    xmlSetStructuredErrorFunc(structured_context, structured);
    if (!doc && !first->line)
        snprintf(first->message, sizeof first->message, "no reason given");
    return doc;
}

static bool has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    return n > e && strcasecmp(path + n - e, ext) == 0;
}

typedef sinew_result (*file_reader)(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                    sinew_error *error);

/* sinew's own readers for the formats it reads itself (FBX, glTF, COLLADA, IQM, BVH), Assimp for the
 * rest. A file that looks like one of them, or is named so, is never handed to Assimp. A NULL
 * reader with a refusal: the name promises a format the bytes are not. */
typedef struct reader_choice {
    file_reader read; /* NULL: Assimp (or the refusal) */
    const char *name;
    const char *refusal;
} reader_choice;

static reader_choice choose_reader(const char *path, const file_head *h, bool assimp)
{
    if (assimp)
        return (reader_choice){NULL, "Assimp", NULL};
    const unsigned char *head = h->bytes;
    size_t head_size = h->size;
    if (fbx_sniff(head, head_size))
        return (reader_choice){raw_model_from_fbx, "sinew's FBX reader", NULL};
    if (has_extension(path, ".fbx"))
        return (reader_choice){NULL, NULL, "not an FBX file (no binary FBX header and no ASCII FBX header)"};
    bool gltf = gltf_sniff(head, head_size);
    if (!gltf && has_extension(path, ".glb"))
        return (reader_choice){NULL, NULL, "not a binary glTF file (it does not start with \"glTF\")"};
    if (gltf || has_extension(path, ".gltf"))
        return (reader_choice){raw_model_from_gltf, "sinew's glTF reader", NULL};
    if (iqm_sniff(head, head_size))
        return (reader_choice){raw_model_from_iqm, "sinew's IQM reader", NULL};
    if (has_extension(path, ".iqm"))
        return (reader_choice){NULL, NULL, "not an IQM file (it does not start with \"INTERQUAKEMODEL\")"};
    if (collada_sniff(head, head_size) || has_extension(path, ".dae"))
        return (reader_choice){raw_model_from_collada, "sinew's COLLADA reader", NULL};
    if (bvh_sniff(head, head_size))
        return (reader_choice){raw_model_from_bvh, "sinew's BVH reader", NULL};
    if (has_extension(path, ".bvh"))
        return (reader_choice){NULL, NULL, "not a BVH file (it does not start with HIERARCHY)"};
    return (reader_choice){NULL, "Assimp", NULL};
}

/* An import's error names its file when the reader did not name another (an external part). */
static sinew_result named(sinew_result result, const char *path, sinew_error *error)
{
    if (result != SINEW_OK && error && !error->file[0] && path)
        snprintf(error->file, sizeof error->file, "%s", path);
    return result;
}

/* A reader for bytes in memory: by the format's name (its extension without the dot), else by
 * what the bytes look like. */
static reader_choice choose_memory_reader(const unsigned char *bytes, size_t size, const char *format)
{
    /* by name, and told from the bytes in this order (a .gltf's JSON has no mark of its own) */
    static const struct {
        const char *name;
        file_reader read;
        const char *reader;
        bool (*sniff)(const unsigned char *head, size_t size);
    } FORMATS[] = {{"fbx", raw_model_from_fbx, "sinew's FBX reader", fbx_sniff},
                   {"gltf", raw_model_from_gltf, "sinew's glTF reader", NULL},
                   {"glb", raw_model_from_gltf, "sinew's glTF reader", gltf_sniff},
                   {"iqm", raw_model_from_iqm, "sinew's IQM reader", iqm_sniff},
                   {"dae", raw_model_from_collada, "sinew's COLLADA reader", collada_sniff},
                   {"bvh", raw_model_from_bvh, "sinew's BVH reader", bvh_sniff}};
    const char *f = format && format[0] == '.' ? format + 1 : format;
    size_t head = size < 1024 ? size : 1024;
    for (size_t i = 0; i < sizeof FORMATS / sizeof *FORMATS; i++)
        if (f ? strcasecmp(f, FORMATS[i].name) == 0 : FORMATS[i].sniff && FORMATS[i].sniff(bytes, head))
            return (reader_choice){FORMATS[i].read, FORMATS[i].reader, NULL};
    return (reader_choice){NULL, NULL, NULL};
}

/* The byte limit of an import's own allocations: the desc's (UINT64_MAX: none), else the default
 * for a file of `size` bytes (in the helper too, under its process limit). */
static uint64_t own_limit(const sinew_import_desc *desc, uint64_t size)
{
    return desc && desc->memory_limit ? desc->memory_limit : import_default_memory_limit(size);
}

sinew_result (*import_assimp_reader)(const char *path, raw_model *model, sinew_error *error);

/* An import's deadline in process (a NULL desc: the default's). */
static double own_seconds(const sinew_import_desc *desc)
{
    return import_timeout_of(desc ? desc : &(sinew_import_desc){0});
}

/* What the import's allocations make of its result: one refused fails an import that went on
 * without it (out of memory), and one refused for the byte limit says so, whatever the reader said. */
static sinew_result allocation_outcome(sinew_result result, const import_alloc_result *used, const char *name,
                                       const sinew_import_desc *desc, sinew_error *error)
{
    if (used->cancelled)
        return sinew_fail(error, SINEW_ERROR_CANCELLED, "%s: the import was cancelled", name);
    if (used->late && result != SINEW_ERROR_CANCELLED)
        return sinew_fail(error, SINEW_ERROR_LIMIT_TIME,
                          "%s: the import took longer than its %.3g s deadline and was stopped (the file may make "
                          "the reader loop; sinew_import_desc.timeout sets the deadline)",
                          name, own_seconds(desc));
    if (result == SINEW_OK && (used->over_limit || used->refused)) /* a reader went on without what it could */
        result = sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY,      /* not allocate: no partial model */
                            "%s: out of memory while reading (part of the file was left out)", name);
    if (result == SINEW_OK || !used->over_limit)
        return result;
    char said[SINEW_ERROR_MESSAGE_SIZE] = "";
    if (error)
        snprintf(said, sizeof said, "%s", error->message);
    return sinew_fail(error, SINEW_ERROR_LIMIT_MEMORY,
                      "%s: the import needed more than its %.0f MiB memory limit and was stopped (%s; "
                      "sinew_import_desc.memory_limit sets another)%s%s",
                      name, (double)used->limit / (1 << 20),
                      desc && desc->memory_limit ? "the limit asked for"
                                                 : "the default for a file of its size: 256 MiB and 64 times the size",
                      *said ? "; the reader said: " : "", said);
}

static sinew_result import_bytes(const unsigned char *bytes, size_t size, const char *format, const char *name,
                                 const sinew_import_desc *desc, sinew_model **out, sinew_error *error)
{
    const sinew_allocator *allocator = desc ? desc->allocator : NULL;
    bool sinew_blob = size >= 8 && memcmp(bytes, BLOB_MAGIC, 8) == 0;
    if ((format && strcasecmp(format[0] == '.' ? format + 1 : format, "sinew") == 0) || (!format && sinew_blob))
        return sinew_model_from_blob(bytes, size, name, allocator, out, error);
    reader_choice choice = choose_memory_reader(bytes, size, format);
    if (!choice.read)
        return format
                   ? sinew_fail(
                         error, SINEW_ERROR_UNSUPPORTED,
                         "%s: from memory sinew reads fbx, gltf, glb, dae, iqm, bvh and sinew, not \"%s\" (Assimp's "
                         "formats are read from files: sinew_import())",
                         name, format)
                   : sinew_fail(error, SINEW_ERROR_UNSUPPORTED,
                                "%s: not FBX, glTF, COLLADA, IQM, BVH or .sinew bytes (Assimp's formats are read from "
                                "files: sinew_import())",
                                name);
    if (desc && desc->progress && !desc->progress(-1.0f, desc->progress_user))
        return sinew_fail(error, SINEW_ERROR_CANCELLED, "%s: the import was cancelled", name);
    const sinew_import_desc *was = reading_for;
    reading_for = desc;
    import_alloc_state state;
    import_alloc_result used;
    import_alloc_begin(&state, own_limit(desc, size), own_seconds(desc), desc ? desc->progress : NULL,
                       desc ? desc->progress_user : NULL);
    raw_model raw;
    sinew_result result = choice.read(name, bytes, size, &raw, error);
    reading_for = was;
    void *blob = NULL;
    size_t blob_size = 0;
    if (result == SINEW_OK) {
        raw.blob_in_pages = true; /* adopted below */
        result = raw_model_build(&raw, &blob, &blob_size, error);
        raw_model_free(&raw);
    }
    import_alloc_end(&state, &used);
    result = allocation_outcome(result, &used, name, desc, error);
    if (result == SINEW_OK) {
        result = sinew_model_adopt_blob(blob, blob_size, true, name, allocator, out, error);
        if (result == SINEW_OK && !allocator)
            blob = NULL;                                               /* the model's now */
        if (result != SINEW_OK && result != SINEW_ERROR_OUT_OF_MEMORY) /* the builder wrote what it cannot read */
            result = sinew_fail(error, SINEW_ERROR_INTERNAL, "%s: the model built from it does not read back (%s)",
                                name, error ? error->message : "");
    }
    free(blob);
    return result;
}

sinew_result sinew_import_memory(const void *bytes, size_t size, const char *format, const sinew_import_desc *desc,
                                 sinew_model **out, sinew_error *error)
{
    if (!out || (!bytes && size))
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_import_memory: NULL bytes or output");
    *out = NULL;
    char fallback[64];
    const char *name = desc && desc->path ? desc->path : fallback;
    snprintf(fallback, sizeof fallback, "(memory).%s", format ? (format[0] == '.' ? format + 1 : format) : "model");
    if (size == 0)
        return named(sinew_fail(error, SINEW_ERROR_FORMAT, "%s: empty (0 bytes)", name), name, error);
    const char *dot = !format && desc && desc->path ? strrchr(desc->path, '.') : NULL;
    if (dot && choose_memory_reader(bytes, size, dot + 1).read) /* no format given: the name's extension */
        format = dot + 1;
    return named(import_bytes(bytes, size, format, name, desc, out, error), name, error);
}

const char *import_reader_name(const char *path, bool assimp)
{
    file_head head = {.size = 0, .file_size = 0};
    if (!assimp) /* Assimp's, whatever the file holds */
        head = head_of(path);
    reader_choice choice = choose_reader(path, &head, assimp);
    return choice.name ? choice.name : "the importer";
}

static sinew_result raw_model_read(const char *path, reader_choice choice, raw_model *raw, sinew_error *error)
{
    if (choice.refusal)
        return sinew_fail(error, SINEW_ERROR_FORMAT, "%s: %s", path, choice.refusal);
    if (!choice.read && !import_assimp_reader)
        return sinew_fail(error, SINEW_ERROR_INTERNAL, "%s: Assimp's formats are read by the import helper", path);
    if (!choice.read)
        return import_assimp_reader(path, raw, error);
    unsigned char *bytes = NULL;
    size_t size = 0;
    if (!import_read_file(path, &bytes, &size))
        return errno == ENOMEM
                   ? sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the file", path)
                   : sinew_fail(error, SINEW_ERROR_IO, "%s: cannot read: %s", path, strerror(errno));
    sinew_result result = choice.read(path, bytes, size, raw, error);
    free(bytes);
    return result;
}

static sinew_result blob_of(const sinew_import_desc *desc, reader_choice choice, uint64_t file_size, bool adopted,
                            void **bytes, size_t *size, sinew_error *error);

sinew_result sinew_import_blob_desc(const sinew_import_desc *desc, void **bytes, size_t *size, sinew_error *error)
{
    if (!desc || !desc->path || !bytes || !size)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_import_blob: NULL argument");
    *bytes = NULL;
    *size = 0;
    file_head head;
    sinew_result result = check_path(desc->path, &head, error);
    if (result)
        return result;
    return blob_of(desc, choose_reader(desc->path, &head, desc->assimp), head.file_size, false, bytes, size, error);
}

/* sinew_import_blob_desc() for a checked path, its reader and its size (check_path()); `adopted`:
 * the caller's model will own the bytes (then they may be in 2 MB pages, else malloc'd). */
static sinew_result blob_of(const sinew_import_desc *desc, reader_choice choice, uint64_t file_size, bool adopted,
                            void **bytes, size_t *size, sinew_error *error)
{
    if (!choice.read && !choice.refusal && !import_assimp_reader) /* Assimp: only the helper links it */
        return import_blob_in_helper(desc, bytes, size, error);
    sinew_result result;
    import_alloc_state state;
    import_alloc_result used;
    import_alloc_begin(&state, own_limit(desc, file_size), own_seconds(desc), desc->progress, desc->progress_user);
    raw_model raw;
    if ((result = raw_model_read(desc->path, choice, &raw, error)) == SINEW_OK) {
        raw.blob_in_pages = adopted;
        result = raw_model_build(&raw, bytes, size, error);
        raw_model_free(&raw);
    }
    import_alloc_end(&state, &used);
    result = allocation_outcome(result, &used, desc->path, desc, error);
    if (result != SINEW_OK && *bytes) {
        free(*bytes);
        *bytes = NULL;
        *size = 0;
    }
    return result;
}

sinew_result sinew_import_blob(const char *path, void **bytes, size_t *size, sinew_error *error)
{
    return sinew_import_blob_desc(&(sinew_import_desc){.path = path}, bytes, size, error);
}

static sinew_result session_load(sinew_import_session *session, const char *path, sinew_model **out,
                                 sinew_error *error);

sinew_result sinew_import_session_load(sinew_import_session *session, const char *path, sinew_model **out,
                                       sinew_error *error)
{
    return named(session_load(session, path, out, error), path, error);
}

static sinew_result session_load(sinew_import_session *session, const char *path, sinew_model **out, sinew_error *error)
{
    if (!session || !path || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT,
                          "sinew_import_session_load: NULL session, path or output");
    *out = NULL;
    const sinew_import_desc *d = import_session_desc(session);
    sinew_import_desc one = *d;
    one.path = path;
    /* what the session's helper does not do: imports not isolated, .sinew files, Assimp's formats
     * (the lean helper execs another program for them: one helper for that file) */
    if (!d->isolate || d->assimp)
        return sinew_import(&one, out, error);
    file_head head = head_of(path);
    reader_choice choice = choose_reader(path, &head, false);
    if (is_sinew_file(&head) || (!choice.read && !choice.refusal))
        return sinew_import(&one, out, error);
    /* head_of() read it: opened again only to say why it could not be */
    sinew_result result = head.file_size ? SINEW_OK : check_path(path, &head, error);
    if (result)
        return result;
    if (d->progress && !d->progress(-1.0f, d->progress_user))
        return sinew_fail(error, SINEW_ERROR_CANCELLED, "%s: the import was cancelled", path);
    return import_in_session(session, path, out, error);
}

static sinew_result import_file(const sinew_import_desc *desc, sinew_model **out, sinew_error *error);

sinew_result sinew_import(const sinew_import_desc *desc, sinew_model **out, sinew_error *error)
{
    if (!desc || !desc->path || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_import: NULL path or output");
    return named(import_file(desc, out, error), desc->path, error);
}

static sinew_result import_file(const sinew_import_desc *desc, sinew_model **out, sinew_error *error)
{
    *out = NULL;
    if (desc->read_file) { /* the caller's files: read in this process, through its callback */
        unsigned char *bytes = NULL;
        size_t size = 0;
        reading_for = desc;
        bool read = import_read_file(desc->path, &bytes, &size);
        reading_for = NULL;
        if (!read)
            return sinew_fail(error, SINEW_ERROR_IO, "%s: the read_file callback could not read it", desc->path);
        const char *dot = strrchr(desc->path, '.');
        bool known = dot && choose_memory_reader(bytes, size, dot + 1).read;
        sinew_result result = import_bytes(bytes, size, known ? dot + 1 : NULL, desc->path, desc, out, error);
        free(bytes);
        return result;
    }
    file_head head;
    sinew_result result = check_path(desc->path, &head, error);
    if (result)
        return result;
    if (is_sinew_file(&head))
        return sinew_model_load(desc->path, desc->allocator, out, error);
    reader_choice choice = choose_reader(desc->path, &head, desc->assimp);
    if (desc->isolate || (!choice.read && !choice.refusal)) /* asked for, or Assimp's */
        return import_in_helper(desc, out, error);
    if (desc->progress && !desc->progress(-1.0f, desc->progress_user))
        return sinew_fail(error, SINEW_ERROR_CANCELLED, "%s: the import was cancelled", desc->path);
    void *bytes = NULL;
    size_t size = 0;
    if ((result = blob_of(desc, choice, head.file_size, true, &bytes, &size, error)))
        return result;
    /* built here: the helper's blobs, whose checksum says they came through whole, went above */
    result = sinew_model_adopt_blob(bytes, size, choice.read != NULL, desc->path, desc->allocator, out, error);
    if (result != SINEW_OK || desc->allocator) /* else the model's now */
        free(bytes);
    return result;
}
