/* sinew/result.h — result codes and the caller-owned error record.
 *
 * What: every libsinew call that can fail returns a sinew_result and, when given
 * a non-NULL sinew_error, fills it with the kind and a message that names the file
 * (where there is one) and what is wrong.
 * What not: no global "last error", no printing, no abort or exit.
 * Memory: sinew_error is a plain value with a fixed-size message; nothing to free.
 */
#ifndef SINEW_RESULT_H
#define SINEW_RESULT_H

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
    SINEW_ERROR_OUT_OF_MEMORY,
    SINEW_ERROR_GRAPHICS, /* no EGL display or GL 3.3 core context, a shader or framebuffer GL refused */
    SINEW_ERROR_CANCELLED /* the caller asked to stop (sinew_import_desc.progress returned false) */
} sinew_result;

#define SINEW_ERROR_MESSAGE_SIZE 512

typedef struct sinew_error {
    sinew_result kind;
    char message[SINEW_ERROR_MESSAGE_SIZE];
} sinew_error;

/* A short constant name for a result code ("ok", "i/o error", ...). */
const char *sinew_result_string(sinew_result result);

/* Fills `error` (when not NULL) with kind and a printf-style message and returns kind: how the
 * library reports every failure, and how code around it (the sinew apps, an engine's loaders)
 * can report its own in the same record. */
sinew_result sinew_fail(sinew_error *error, sinew_result kind, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* The version of the library linked ("0.1.0"); SINEW_VERSION_STRING (sinew/version.h) is the
 * version of the headers compiled against. */
const char *sinew_version(void);

#ifdef __cplusplus
}
#endif
#endif
