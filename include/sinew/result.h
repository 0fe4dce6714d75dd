/* sinew/result.h — result codes and the caller-owned error record.
 *
 * What: every libsinew call that can fail returns a sinew_result and, when given
 * a non-NULL sinew_error, fills it with the kind, the file (where there is one), the byte
 * offset or line in it when the reader knows them, and a message that names the file and says
 * what is wrong. Choose exit codes and texts from the kind, never from the message's words.
 * What not: no global "last error", no printing, no abort or exit.
 * Memory: sinew_error is a plain value with a fixed-size message; nothing to free.
 */
#ifndef SINEW_RESULT_H
#define SINEW_RESULT_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sinew_result {
    SINEW_OK = 0,
    SINEW_ERROR_INVALID_ARGUMENT, /* a caller bug: NULL pointer, span too small, bad option */
    SINEW_ERROR_IO,               /* missing file, directory, unreadable, short read */
    SINEW_ERROR_FORMAT,           /* unknown format, garbage, truncated or corrupted file */
    SINEW_ERROR_IMPORTER,         /* Assimp refused the file or crashed on it */
    SINEW_ERROR_DATA,             /* the file parsed, but its content is invalid (NaN, bad indices) */
    SINEW_ERROR_LIMIT,            /* over a documented limit (joints per skin, influences) */
    SINEW_ERROR_OUT_OF_MEMORY,    /* an allocation failed (or the allocator refused it) */
    SINEW_ERROR_GRAPHICS,         /* no EGL display or GL 3.3 core context, a shader or framebuffer GL refused */
    SINEW_ERROR_CANCELLED,        /* the caller asked to stop (sinew_import_desc.progress returned false) */
    SINEW_ERROR_UNSUPPORTED,      /* valid, but something sinew does not do (a format from memory Assimp reads) */
    SINEW_ERROR_LIMIT_TIME,       /* the import took longer than its deadline (sinew_import_desc.timeout) */
    SINEW_ERROR_LIMIT_MEMORY,     /* the import needed more than its memory limit (sinew_import_desc.memory_limit) */
    SINEW_ERROR_INTERNAL          /* a bug in sinew: please report it with the file */
} sinew_result;

/* The last kind: kinds run from SINEW_OK to it. */
#define SINEW_RESULT_LAST SINEW_ERROR_INTERNAL

#define SINEW_ERROR_MESSAGE_SIZE 512
#define SINEW_ERROR_FILE_SIZE 256

typedef struct sinew_error {
    sinew_result kind;
    char message[SINEW_ERROR_MESSAGE_SIZE]; /* one line that names the file and what is wrong */
    char file[SINEW_ERROR_FILE_SIZE];       /* the file it is about ("" when none or not known) */
    int64_t offset;                         /* byte offset in the file where it went wrong; -1: not known */
    uint32_t line;                          /* line in a text file (1 first); 0: not known */
} sinew_error;

/* A short constant name for a result code ("ok", "i/o error", ...). */
const char *sinew_result_string(sinew_result result);

/* A short constant identifier for a result code ("io", "format", "limit_time", ...): what the
 * Python binding and `sinew batch` manifests call the kinds. */
const char *sinew_result_name(sinew_result result);

/* Fills `error` (when not NULL) with kind and a printf-style message and returns kind: how the
 * library reports every failure, and how code around it (the sinew apps, an engine's loaders)
 * can report its own in the same record. */
sinew_result sinew_fail(sinew_error *error, sinew_result kind, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* The same, naming the file (copied into error->file; may be NULL), the byte offset (-1: not known)
 * and the line (0: not known) it is about. sinew_fail() leaves file empty, offset -1, line 0. */
sinew_result sinew_fail_at(sinew_error *error, sinew_result kind, const char *file, int64_t offset, uint32_t line,
                           const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 6, 7)))
#endif
    ;

/* The version of the library linked ("0.1.0"); SINEW_VERSION_STRING (sinew/version.h) is the
 * version of the headers compiled against. */
const char *sinew_version(void);

#ifdef __cplusplus
}
#endif
#endif
