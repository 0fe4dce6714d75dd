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
#include <string.h>

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

/* The number of digits that start the 8 bytes of w (read little-endian from text), 0..8. A
 * byte is a digit when, XORed with '0', it is under 10: its high nibble clear before and after
 * adding 6. A carry out of a byte that is not a digit reaches only the bytes after it. */
static inline int decimal_run8(uint64_t w)
{
    uint64_t x = w ^ 0x3030303030303030u;
    uint64_t bad = (x | (x + 0x0606060606060606u)) & 0xF0F0F0F0F0F0F0F0u;
    return bad ? __builtin_ctzll(bad) / 8 : 8;
}

/* The value of the first n (1..8) digits of w: they are moved to the top bytes (zeros before
 * them) and paired, then the pairs paired, then the quads: three multiplications. */
static inline uint64_t decimal_value8(uint64_t w, int n)
{
    uint64_t v = (w - 0x3030303030303030u) << (8 * (8 - n));
    v = (v * 10 + (v >> 8)) & 0x00FF00FF00FF00FFu;
    v = (v * 100 + (v >> 16)) & 0x0000FFFF0000FFFFu;
    return (v * 10000 + (v >> 32)) & 0xFFFFFFFFu;
}

/* decimal_scan for text that can be read up to `limit` (its NUL, say): a number of at most 7
 * digits, a point and at most 8 (what exporters write: "-0.5161436") is read 8 bytes at a time,
 * with a branch a part instead of one a byte (COLLADA's number arrays: a third of the time they
 * took; ASCII FBX's numbers); anything else as decimal_scan reads it. The same results (test_json). */
static inline int decimal_scan_within(const char *p, const char *limit, const char **end, double *out)
{
    static const uint64_t SCALE[9] = {1, 10, 100, 1000, 10000, 100000, 1000000, 10000000, 100000000};
    static const double POW10[9] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8};
    if (limit - p >= 24) { /* the reads below stay within p + 18 */
        const char *s = p + (*p == '-');
        uint64_t w, f;
        memcpy(&w, s, sizeof w);
        int whole = decimal_run8(w), fraction = 0;
        if (whole >= 1 && whole <= 7 && !(s[0] == '0' && whole > 1)) {
            uint64_t mantissa = decimal_value8(w, whole);
            s += whole;
            if (*s == '.') {
                memcpy(&f, s + 1, sizeof f);
                fraction = decimal_run8(f);
                mantissa = fraction ? mantissa * SCALE[fraction] + decimal_value8(f, fraction) : 0;
                s += 1 + fraction;
            }
            bool plain = s[-1] != '.' && *s != '.' && *s != 'e' && *s != 'E' && !(*s >= '0' && *s <= '9');
            if (plain) {
                double v = (double)mantissa / POW10[fraction];
                *out = *p == '-' ? -v : v;
                *end = s;
                return 1;
            }
        }
    }
    return decimal_scan(p, end, out);
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
