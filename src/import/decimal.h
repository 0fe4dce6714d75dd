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

/* The len bytes at p as a number in JSON's grammar (RFC 8259: -? int frac? exp?, nothing else):
 * 1 with *out when the fast path is exact, 0 when it is such a number but needs strtod (more
 * digits, a larger exponent), -1 when it is not one (a caller whose grammar is wider, as
 * xs:double's "+1", ".5" and "INF", asks strtod then). */
static inline int decimal_exact(const char *p, size_t len, double *out)
{
    static const double POW10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                     1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    size_t i = 0;
    int digits = 0, scale = 0;
    bool negative = i < len && p[i] == '-';
    uint64_t mantissa = 0;
    i += negative;
    if (i >= len || p[i] < '0' || p[i] > '9' || (p[i] == '0' && i + 1 < len && p[i + 1] >= '0' && p[i + 1] <= '9'))
        return -1;
    for (; i < len && p[i] >= '0' && p[i] <= '9'; i++)
        if (digits < 19 && (digits || p[i] != '0'))
            mantissa = mantissa * 10 + (uint64_t)(p[i] - '0'), digits++;
        else if (digits)
            scale++, digits++; /* past 19 digits: counted, not kept (strtod takes it) */
    if (i < len && p[i] == '.') {
        if (++i >= len || p[i] < '0' || p[i] > '9')
            return -1;
        for (; i < len && p[i] >= '0' && p[i] <= '9'; i++)
            if (digits < 19 && (digits || p[i] != '0'))
                mantissa = mantissa * 10 + (uint64_t)(p[i] - '0'), digits++, scale--;
            else if (digits)
                digits++;
            else
                scale--;
    }
    int exponent = 0;
    if (i < len && (p[i] == 'e' || p[i] == 'E')) {
        bool minus = ++i < len && p[i] == '-';
        i += i < len && (p[i] == '-' || p[i] == '+');
        if (i >= len || p[i] < '0' || p[i] > '9')
            return -1;
        for (; i < len && p[i] >= '0' && p[i] <= '9'; i++)
            exponent = exponent < 100000 ? exponent * 10 + (p[i] - '0') : exponent;
        exponent = minus ? -exponent : exponent;
    }
    if (i != len)
        return -1;
    int e = scale + exponent;
    if (digits > 15 || e < -22 || e > 22)
        return 0;
    double v = (double)mantissa;
    v = e < 0 ? v / POW10[-e] : v * POW10[e];
    *out = negative ? -v : v;
    return 1;
}

#endif
