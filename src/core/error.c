/* Result names and the one helper that fills a sinew_error. */
#include <stdio.h>

#include "internal.h"
#include "sinew/version.h"

const char *sinew_result_string(sinew_result result)
{
    switch (result) {
    case SINEW_OK:
        return "ok";
    case SINEW_ERROR_INVALID_ARGUMENT:
        return "invalid argument";
    case SINEW_ERROR_IO:
        return "i/o error";
    case SINEW_ERROR_FORMAT:
        return "format error";
    case SINEW_ERROR_IMPORTER:
        return "importer error";
    case SINEW_ERROR_DATA:
        return "invalid data";
    case SINEW_ERROR_LIMIT:
        return "over a limit";
    case SINEW_ERROR_OUT_OF_MEMORY:
        return "out of memory";
    case SINEW_ERROR_GRAPHICS:
        return "graphics error";
    case SINEW_ERROR_CANCELLED:
        return "cancelled";
    case SINEW_ERROR_UNSUPPORTED:
        return "not supported";
    case SINEW_ERROR_LIMIT_TIME:
        return "over the time limit";
    case SINEW_ERROR_LIMIT_MEMORY:
        return "over the memory limit";
    case SINEW_ERROR_INTERNAL:
        return "internal error";
    }
    return "unknown error";
}

const char *sinew_result_name(sinew_result result)
{
    static const char *const names[] = {
        "ok",           "invalid_argument", "io",       "format",    "importer",    "data",
        "limit",        "out_of_memory",    "graphics", "cancelled", "unsupported", "limit_time",
        "limit_memory", "internal"};
    _Static_assert(sizeof names / sizeof *names == SINEW_RESULT_LAST + 1, "a name for every kind");
    return (unsigned)result <= SINEW_RESULT_LAST ? names[result] : "unknown";
}

static void fill(sinew_error *error, sinew_result kind, const char *file, int64_t offset, uint32_t line,
                 const char *format, va_list args)
{
    error->kind = kind;
    vsnprintf(error->message, sizeof error->message, format, args);
    snprintf(error->file, sizeof error->file, "%s", file ? file : "");
    error->offset = offset;
    error->line = line;
}

sinew_result sinew_fail(sinew_error *error, sinew_result kind, const char *format, ...)
{
    if (error) {
        va_list args;
        va_start(args, format);
        fill(error, kind, NULL, -1, 0, format, args);
        va_end(args);
    }
    return kind;
}

sinew_result sinew_fail_at(sinew_error *error, sinew_result kind, const char *file, int64_t offset, uint32_t line,
                           const char *format, ...)
{
    if (error) {
        va_list args;
        va_start(args, format);
        fill(error, kind, file, offset, line, format, args);
        va_end(args);
    }
    return kind;
}

const char *sinew_version(void)
{
    return SINEW_VERSION_STRING;
}
