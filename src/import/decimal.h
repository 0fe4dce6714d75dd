/* Decimal numbers read exactly without strtod where that is easy (the JSON and COLLADA readers):
 * Clinger's fast path. A decimal of up to 15 significant digits with a power of ten within 10^22
 * (nearly every number an exporter writes) is one product or quotient of two exactly
 * representable doubles, so one correctly rounded operation gives strtod's result bit for bit
 * (test_json checks 200,000 generated decimals against strtod). */
#ifndef SINEW_IMPORT_DECIMAL_H
#define SINEW_IMPORT_DECIMAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The number in JSON's grammar (RFC 8259: -? int frac? exp?) that starts at p, in text that a
 * byte other than a digit, '.', 'e', 'E', '+' or '-' ends (a NUL terminator does): *end is
 * where it stops. 1 with *out when the fast path is exact; 0 when it is such a number but
 * needs strtod (more digits, a larger exponent); -1 when p starts no such number or it breaks
 * the grammar (01, 1., 1e); a caller whose grammar is wider, as xs:double's "+1", ".5" and
 * "INF", asks strtod then. */
static inline int decimal_scan(const char *p, const char **end, double *out)
{
    static const double POW10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                     1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const char *s = p;
    int digits = 0, scale = 0;
    bool negative = *s == '-';
    uint64_t mantissa = 0;
    s += negative;
    if (*s < '0' || *s > '9' || (s[0] == '0' && s[1] >= '0' && s[1] <= '9'))
        return -1;
    for (; *s >= '0' && *s <= '9'; s++)
        if (digits < 19 && (digits || *s != '0'))
            mantissa = mantissa * 10 + (uint64_t)(*s - '0'), digits++;
        else if (digits)
            scale++, digits++; /* past 19 digits: counted, not kept (strtod takes it) */
    if (*s == '.') {
        if (*++s < '0' || *s > '9')
            return -1;
        for (; *s >= '0' && *s <= '9'; s++)
            if (digits < 19 && (digits || *s != '0'))
                mantissa = mantissa * 10 + (uint64_t)(*s - '0'), digits++, scale--;
            else if (digits)
                digits++;
            else
                scale--;
    }
    int exponent = 0;
    if (*s == 'e' || *s == 'E') {
        bool minus = *++s == '-';
        s += *s == '-' || *s == '+';
        if (*s < '0' || *s > '9')
            return -1;
        for (; *s >= '0' && *s <= '9'; s++)
            exponent = exponent < 100000 ? exponent * 10 + (*s - '0') : exponent;
        exponent = minus ? -exponent : exponent;
    }
    *end = s;
    int e = scale + exponent;
    if (digits > 15 || e < -22 || e > 22)
        return 0;
    double v = (double)mantissa;
    v = e < 0 ? v / POW10[-e] : v * POW10[e];
    *out = negative ? -v : v;
    return 1;
}

/* The len bytes at p (inside NUL-terminated text) as one number in JSON's grammar: as
 * decimal_scan, and -1 when the number does not take exactly those bytes. */
static inline int decimal_exact(const char *p, size_t len, double *out)
{
    const char *end = p;
    int r = decimal_scan(p, &end, out);
    return r >= 0 && end == p + len ? r : -1;
}

#endif
