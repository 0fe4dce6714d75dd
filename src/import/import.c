/* sinew_import: checks the path, reads a .sinew file directly or runs Assimp (in a child
 * process by default) and turns the blob it hands back into a runtime model.
 *
 * The child writes one message to the pipe: a reply header (status, error kind, payload
 * size) and then either the model blob or the error text. A child that dies on a signal
 * (Assimp crashing on a malformed file) or exits without a whole reply becomes an
 * SINEW_ERROR_IMPORTER naming the file and the signal.
 */
#define _GNU_SOURCE /* pipe2 */
#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <libxml/parser.h>

#include "../core/internal.h"
#include "fbx_internal.h"
#include "internal.h"
#include "sinew/import.h"

typedef struct reply_header {
    uint32_t magic;
    uint32_t kind; /* sinew_result */
    uint64_t size; /* bytes that follow */
} reply_header;

#define REPLY_MAGIC 0x53524550u /* "PERS" */

static sinew_result check_path(const char *path, sinew_error *error)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (S_ISDIR(st.st_mode))
        return sinew_fail(error, SINEW_ERROR_IO, "%s: is a directory, not a model file", path);
    if (!S_ISREG(st.st_mode))
        return sinew_fail(error, SINEW_ERROR_IO, "%s: not a regular file", path);
    FILE *f = fopen(path, "rb");
    if (!f)
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot read: %s", path, strerror(errno));
    fclose(f);
    if (st.st_size == 0)
        return sinew_fail(error, SINEW_ERROR_FORMAT, "%s: the file is empty", path);
    return SINEW_OK;
}

/* The first bytes of a file (fewer when it is shorter; 0 when it cannot be read). */
static size_t read_head(const char *path, unsigned char *head, size_t size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return 0;
    size_t n = fread(head, 1, size, f);
    fclose(f);
    return n;
}

/* A .sinew file, by its magic (whatever its name): read by sinew_model_load(), not Assimp. */
static bool is_sinew_file(const char *path)
{
    unsigned char magic[8];
    return read_head(path, magic, sizeof magic) == sizeof magic && memcmp(magic, BLOB_MAGIC, sizeof magic) == 0;
}

bool import_read_file(const char *path, unsigned char **bytes, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return false;
    bool ok = fseek(f, 0, SEEK_END) == 0;
    long n = ok ? ftell(f) : -1;
    ok = n >= 0 && fseek(f, 0, SEEK_SET) == 0;
    unsigned char *buf = ok ? malloc((size_t)n + 1) : NULL;
    ok = buf && fread(buf, 1, (size_t)n, f) == (size_t)n;
    fclose(f);
    if (!ok) {
        free(buf);
        return false;
    }
    buf[n] = 0;
    *bytes = buf;
    *size = (size_t)n;
    return true;
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

char *import_find_texture(const char *model_path, const char *reference, bool by_name, char *looked,
                          size_t looked_size)
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

static void quiet(void *context, const char *format, ...)
{
    (void)context;
    (void)format;
}

struct _xmlDoc *import_xml_parse(const char *path, const unsigned char *bytes, size_t size)
{
    /* libxml2 reports encoding errors through its generic handler, which prints to stderr
     * whatever the parse options say; the library never prints, so it is quieted for the
     * parse (the error itself comes back from xmlGetLastError) */
    xmlGenericErrorFunc printer = xmlGenericError;
    void *printer_context = xmlGenericErrorContext;
    xmlSetGenericErrorFunc(NULL, quiet);
    xmlDoc *doc = xmlReadMemory((const char *)bytes, (int)size, path, NULL,
                                XML_PARSE_NONET | XML_PARSE_NOWARNING | XML_PARSE_NOERROR | XML_PARSE_HUGE);
    xmlSetGenericErrorFunc(printer_context, printer);
    return doc;
}

static bool has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    return n > e && strcasecmp(path + n - e, ext) == 0;
}

typedef sinew_result (*native_reader)(const char *path, const unsigned char *bytes, size_t size, raw_model *model,
                                      sinew_error *error);

/* sinew's own readers for the formats it reads itself (FBX, glTF, COLLADA), Assimp for the rest. A
 * file that looks like one of them, or is named so, is never handed to Assimp. */
static sinew_result raw_model_read(const char *path, bool assimp, raw_model *raw, sinew_error *error)
{
    if (assimp)
        return raw_model_from_assimp(path, raw, error);
    unsigned char head[1024];
    size_t head_size = read_head(path, head, sizeof head);
    bool fbx = fbx_sniff(head, head_size);
    if (!fbx && has_extension(path, ".fbx"))
        return sinew_fail(error, SINEW_ERROR_FORMAT,
                          "%s: not an FBX file (no binary FBX header and no ASCII FBX header)", path);
    if (!gltf_sniff(head, head_size) && has_extension(path, ".glb"))
        return sinew_fail(error, SINEW_ERROR_FORMAT, "%s: not a binary glTF file (it does not start with \"glTF\")",
                          path);
    native_reader reader = fbx                                                           ? raw_model_from_fbx
                           : gltf_sniff(head, head_size) || has_extension(path, ".gltf") ? raw_model_from_gltf
                           : collada_sniff(head, head_size) || has_extension(path, ".dae") ? raw_model_from_collada
                                                                                          : NULL;
    if (!reader)
        return raw_model_from_assimp(path, raw, error);
    unsigned char *bytes = NULL;
    size_t size = 0;
    if (!import_read_file(path, &bytes, &size))
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot read: %s", path, strerror(errno));
    sinew_result result = reader(path, bytes, size, raw, error);
    free(bytes);
    return result;
}

sinew_result sinew_import_blob_desc(const sinew_import_desc *desc, void **bytes, size_t *size, sinew_error *error)
{
    if (!desc || !desc->path || !bytes || !size)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_import_blob: NULL argument");
    sinew_result result = check_path(desc->path, error);
    if (result)
        return result;
    raw_model raw;
    if ((result = raw_model_read(desc->path, desc->assimp, &raw, error)))
        return result;
    result = raw_model_build(&raw, bytes, size, error);
    raw_model_free(&raw);
    return result;
}

sinew_result sinew_import_blob(const char *path, void **bytes, size_t *size, sinew_error *error)
{
    return sinew_import_blob_desc(&(sinew_import_desc){.path = path}, bytes, size, error);
}

static bool write_all(int fd, const void *data, size_t size)
{
    const char *p = data;
    while (size > 0) {
        ssize_t n = write(fd, p, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return false;
        p += n;
        size -= (size_t)n;
    }
    return true;
}

/* In the child: import, reply, and leave without running atexit handlers. The caller's
 * signal handlers (a test runner's, a GUI's) are reset so that a crash in Assimp ends
 * the child with its signal, which the parent reports; its output goes to /dev/null. */
static void child_main(int fd, const sinew_import_desc *desc)
{
    static const int fatal[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS};
    for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; i++)
        signal(fatal[i], SIG_DFL);
    /* The library never prints: Assimp's own asserts and logs go nowhere. */
    int null = open("/dev/null", O_WRONLY);
    if (null >= 0) {
        dup2(null, STDOUT_FILENO);
        dup2(null, STDERR_FILENO);
        close(null);
    }
    sinew_error error = {0};
    void *bytes = NULL;
    size_t size = 0;
    sinew_result result = sinew_import_blob_desc(desc, &bytes, &size, &error);
    reply_header reply = {.magic = REPLY_MAGIC, .kind = result};
    const void *payload = bytes;
    if (result) {
        payload = error.message;
        size = strlen(error.message) + 1;
    }
    reply.size = size;
    bool ok = write_all(fd, &reply, sizeof reply) && write_all(fd, payload, size);
    close(fd);
    _exit(ok ? 0 : 3);
}

/* Reads everything until end of file into a malloc'd buffer. */
static bool read_all(int fd, unsigned char **out, size_t *out_size)
{
    size_t size = 0, cap = 1 << 16;
    unsigned char *buf = malloc(cap);
    if (!buf)
        return false;
    for (;;) {
        if (size == cap) {
            unsigned char *grown = realloc(buf, cap * 2);
            if (!grown) {
                free(buf);
                return false;
            }
            buf = grown;
            cap *= 2;
        }
        ssize_t n = read(fd, buf + size, cap - size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            free(buf);
            return false;
        }
        if (n == 0)
            break;
        size += (size_t)n;
    }
    *out = buf;
    *out_size = size;
    return true;
}

static sinew_result child_status(const char *path, int status, sinew_error *error)
{
    if (WIFSIGNALED(status)) {
        int sig = WTERMSIG(status);
        return sinew_fail(error, SINEW_ERROR_IMPORTER,
                          "%s: the importer (Assimp) crashed while reading this file (signal %d, %s); the file is "
                          "probably malformed",
                          path, sig, strsignal(sig));
    }
    return sinew_fail(error, SINEW_ERROR_IMPORTER, "%s: the import process failed (exit status %d)", path,
                      WIFEXITED(status) ? WEXITSTATUS(status) : -1);
}

static sinew_result import_in_child(const sinew_import_desc *desc, sinew_model **out, sinew_error *error)
{
    const char *path = desc->path;
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0)
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot start the import process: %s", path, strerror(errno));
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        return sinew_fail(error, SINEW_ERROR_IO, "%s: cannot start the import process: %s", path, strerror(errno));
    }
    if (pid == 0) {
        close(fds[0]);
        child_main(fds[1], desc);
    }
    close(fds[1]);
    unsigned char *buf = NULL;
    size_t size = 0;
    bool read_ok = read_all(fds[0], &buf, &size);
    close(fds[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (!read_ok)
        return sinew_fail(error, SINEW_ERROR_OUT_OF_MEMORY, "%s: cannot read the import process's reply", path);

    sinew_result result;
    reply_header reply;
    if (size >= sizeof reply)
        memcpy(&reply, buf, sizeof reply);
    if (size < sizeof reply || reply.magic != REPLY_MAGIC || reply.size != size - sizeof reply ||
        !(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
        result = child_status(path, status, error);
    } else if (reply.kind != SINEW_OK) {
        buf[size - 1] = '\0';
        result = sinew_fail(error, (sinew_result)reply.kind, "%s", (const char *)buf + sizeof reply);
    } else {
        result = sinew_model_from_blob(buf + sizeof reply, size - sizeof reply, path, desc->allocator, out, error);
    }
    free(buf);
    return result;
}

sinew_result sinew_import(const sinew_import_desc *desc, sinew_model **out, sinew_error *error)
{
    if (!desc || !desc->path || !out)
        return sinew_fail(error, SINEW_ERROR_INVALID_ARGUMENT, "sinew_import: NULL path or output");
    *out = NULL;
    sinew_result result = check_path(desc->path, error);
    if (result)
        return result;
    if (is_sinew_file(desc->path))
        return sinew_model_load(desc->path, desc->allocator, out, error);
    if (!desc->in_process)
        return import_in_child(desc, out, error);
    void *bytes = NULL;
    size_t size = 0;
    if ((result = sinew_import_blob_desc(desc, &bytes, &size, error)))
        return result;
    result = sinew_model_from_blob(bytes, size, desc->path, desc->allocator, out, error);
    free(bytes);
    return result;
}
