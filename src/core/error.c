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
    }
    return "unknown error";
}

sinew_result sinew_fail(sinew_error *error, sinew_result kind, const char *format, ...)
{
    if (error) {
        va_list args;
        va_start(args, format);
        error->kind = kind;
        vsnprintf(error->message, sizeof error->message, format, args);
        va_end(args);
    }
    return kind;
}

const char *sinew_version(void)
{
    return SINEW_VERSION_STRING;
}
