/* Numbers from command lines and settings, strictly: all of the text, finite, in range. The one
 * number parser of both apps. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>

#include "app.h"

int app_parse_list(const char *text, double *out, int min, int max, double lo, double hi)
{
    if (!text)
        return -1;
    const char *p = text;
    int count = 0;
    for (;;) {
        if (count == max)
            return -1;
        char *end = NULL;
        errno = 0;
        double v = strtod(p, &end);
        /* strtod skips leading blanks and reads "nan", "inf", hex: only plain decimals pass */
        if (end == p || errno || !isfinite(v) || v < lo || v > hi || *p == ' ' || *p == '\t' || *p == '\n')
            return -1;
        out[count++] = v;
        if (*end == '\0')
            break;
        if (*end != ',')
            return -1;
        p = end + 1;
    }
    return count >= min ? count : -1;
}

bool app_parse_number(const char *text, double lo, double hi, double *out)
{
    double v;
    if (app_parse_list(text, &v, 1, 1, lo, hi) != 1)
        return false;
    *out = v;
    return true;
}

bool app_parse_integer(const char *text, long lo, long hi, long *out)
{
    if (!text)
        return false;
    char *end = NULL;
    errno = 0;
    long n = strtol(text, &end, 10);
    if (end == text || *end || errno || n < lo || n > hi || *text == ' ' || *text == '\t' || *text == '+')
        return false;
    *out = n;
    return true;
}

bool app_parse_size(const char *text, int lo, int hi, int *width, int *height)
{
    if (!text)
        return false;
    char part[32];
    const char *x = text;
    while (*x && *x != 'x' && *x != 'X')
        x++;
    size_t n = (size_t)(x - text);
    if (!*x || n == 0 || n >= sizeof part)
        return false;
    for (size_t i = 0; i < n; i++)
        part[i] = text[i];
    part[n] = '\0';
    long w, h;
    if (!app_parse_integer(part, lo, hi, &w) || !app_parse_integer(x + 1, lo, hi, &h))
        return false;
    *width = (int)w;
    *height = (int)h;
    return true;
}
