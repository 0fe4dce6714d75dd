/* The library's JSON (json.h): numbers read exactly as strtod reads them (the fast path and the
 * rest), what RFC 8259 does not call a number refused, and documents whose commas and colons
 * are wrong. */
#include <locale.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "import/decimal.h"
#include "import/json.h"

/* The number in "[text]" (jsmn, strict, wants an array or object at the top). */
static double parse_one(const char *number, bool *ok)
{
    char text[96];
    snprintf(text, sizeof text, "[%s]", number);
    json_doc doc = {0};
    size_t at = 0;
    const char *why = NULL;
    *ok = json_parse(text, strlen(text), false, &doc, &at, &why) == SINEW_OK && doc.root->count == 1 &&
          doc.root[1].type == JSON_NUMBER;
    double v = *ok ? doc.root[1].number : 0.0;
    json_free(&doc);
    return v;
}

static void test_numbers_as_strtod(void **state)
{
    (void)state;
    static const char *const numbers[] = {"0",
                                          "-0",
                                          "1",
                                          "-1",
                                          "0.5",
                                          "3.14159265358979",
                                          "1e10",
                                          "1E-10",
                                          "2.5e+3",
                                          "-7.25e-2",
                                          "0.1",
                                          "0.2",
                                          "0.30000000000000004",
                                          "123456789012345",
                                          "1234567890123456",
                                          "12345678901234567890",
                                          "0.000000000000000000000001",
                                          "1e22",
                                          "1e23",
                                          "1e-22",
                                          "1e-23",
                                          "9007199254740993",
                                          "4.9e-324",
                                          "1.7976931348623157e308",
                                          "2.2250738585072014e-308",
                                          "0.1000000000000000055511151231257827",
                                          "100000000000000000000000",
                                          "0.00001",
                                          "-0.0000000123",
                                          "5e-1",
                                          "1.000000000000000000000001",
                                          "0.7071067811865476",
                                          "-0.7071067811865475",
                                          "1.0",
                                          "10.0e0",
                                          "123.456e-5"};
    for (size_t i = 0; i < sizeof numbers / sizeof numbers[0]; i++) {
        bool ok;
        double v = parse_one(numbers[i], &ok), want = strtod(numbers[i], NULL);
        if (!ok || memcmp(&v, &want, sizeof v) != 0)
            fail_msg("\"%s\": read %.17g, strtod %.17g", numbers[i], v, want);
    }
    /* many generated decimals of up to 17 digits: every one bit-exact */
    uint64_t seed = 12345;
    char text[64];
    for (int i = 0; i < 200000; i++) {
        seed = seed * 6364136223846793005u + 1442695040888963407u;
        int digits = 1 + (int)((seed >> 33) % 17), point = (int)((seed >> 40) % (unsigned)(digits + 1));
        int exponent = (int)((seed >> 45) % 61) - 30;
        int n = 0;
        if (seed & 1)
            text[n++] = '-';
        uint64_t r = seed;
        for (int d = 0; d < digits; d++) {
            if (d == point && d > 0)
                text[n++] = '.';
            r = r * 6364136223846793005u + 1;
            text[n++] = (char)('0' + (d == 0 && point > 1 ? 1 + (r >> 60) % 9 : (r >> 60) % 10));
        }
        if ((seed >> 20) & 1)
            n += snprintf(text + n, sizeof text - (size_t)n, "e%d", exponent);
        text[n] = 0;
        if (text[seed & 1] == '0' && text[(seed & 1) + 1] >= '0' && text[(seed & 1) + 1] <= '9')
            continue; /* a leading zero: not JSON */
        bool ok;
        double v = parse_one(text, &ok), want = strtod(text, NULL);
        if (!ok || memcmp(&v, &want, sizeof v) != 0)
            fail_msg("\"%s\": read %.17g (%s), strtod %.17g", text, v, ok ? "ok" : "refused", want);
    }
}

/* decimal_scan_within (COLLADA's number arrays, ASCII FBX's numbers) gives decimal_scan's answer, end
 * and bits on numbers of every shape, followed by what ends a number and what does not. */
static void test_scan_within(void **state)
{
    (void)state;
    static const char *const after[] = {" ", "\n", "", ".", "e5", "E-2", "x", "5", ".5", "-"};
    char text[128];
    uint64_t seed = 777;
    for (int i = 0; i < 300000; i++) {
        seed = seed * 6364136223846793005u + 1442695040888963407u;
        int whole = (int)((seed >> 33) % 10), fraction = (int)((seed >> 37) % 11) - 1, n = 0;
        if (seed & 1)
            text[n++] = '-';
        uint64_t r = seed;
        for (int d = 0; d < whole; d++, r = r * 6364136223846793005u + 1)
            text[n++] = (char)('0' + (r >> 60) % 10);
        if (fraction >= 0)
            text[n++] = '.';
        for (int d = 0; d < fraction; d++, r = r * 6364136223846793005u + 1)
            text[n++] = (char)('0' + (r >> 60) % 10);
        n += snprintf(text + n, sizeof text - (size_t)n, "%s", after[(seed >> 41) % 10]);
        memset(text + n, (seed >> 45) & 1 ? ' ' : '7', sizeof text - (size_t)n - 1); /* readable beyond */
        text[sizeof text - 1] = 0;
        const char *end_a = NULL, *end_b = NULL;
        double a = 0, b = 0;
        int ra = decimal_scan_within(text, text + sizeof text - 1, &end_a, &a), rb = decimal_scan(text, &end_b, &b);
        if (ra != rb || (ra >= 0 && end_a != end_b) || (ra > 0 && memcmp(&a, &b, sizeof a) != 0))
            fail_msg("\"%.*s\": %d %.17g (%td) against %d %.17g (%td)", n, text, ra, a, end_a - text, rb, b,
                     end_b - text);
    }
}

static void test_not_numbers(void **state)
{
    (void)state;
    static const char *const bad[] = {"01", "-01", "1.", ".5",   "+1",  "0x10", "inf",   "-inf", "nan",
                                      "1e", "1e+", "-",  "1.e5", "- 1", "1f",   "0.5.5", "--1",  "1e5.5"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        bool ok;
        parse_one(bad[i], &ok);
        if (ok)
            fail_msg("\"%s\" was read as a number", bad[i]);
    }
}

/* Whole documents written by hand: what RFC 8259 allows is read, the rest refused at the byte
 * named (jsmn alone lets a missing comma, a doubled or trailing one and a stray colon pass). A
 * program's JSON (glTF) is read as jsmn reads it, except where that would misplace a value. */
static void test_documents(void **state)
{
    (void)state;
    static const char *const good[] = {"[]",
                                       "{}",
                                       " [ 1 , 2 ] ",
                                       "{\"a\": [1, {\"b\": []}], \"c\": {}}",
                                       "[[], [[]], {}, \"x\", true]",
                                       "{\"a\":\"b\",\"c\":[1,2]}\n",
                                       "[\"a,b:c\", \"[\"]"};
    for (size_t i = 0; i < sizeof good / sizeof good[0]; i++) {
        json_doc doc = {0};
        size_t at = 0;
        const char *why = NULL;
        if (json_parse(good[i], strlen(good[i]), true, &doc, &at, &why) != SINEW_OK)
            fail_msg("'%s' refused at %zu: %s", good[i], at, why);
        json_free(&doc);
    }
    static const struct {
        const char *text;
        size_t at; /* where the message points */
    } bad[] = {
        {"[1 2]", 3},
        {"[1,,2]", 3},
        {"[1,2,]", 4},
        {"[,1]", 1},
        {"[,]", 1},
        {"{,}", 1},
        {"{\"a\":1,}", 6},
        {"{\"a\":1 \"b\":2}", 7},
        {"{\"a\"::1}", 5},
        {"[1:2]", 1},
        {"[\"a\":1]", 4},
        {"[[1],,[2]]", 5},
        {"{\"a\":[1,2,]}", 9},
        {"[[1] [2]]", 5},
        {"[1]]", 3},
        {"[1] [2]", 4},
        {"[1],[2]", 4},
        {"{\"a\" 1}", 5},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        json_doc doc = {0};
        size_t at = 0;
        const char *why = NULL;
        if (json_parse(bad[i].text, strlen(bad[i].text), true, &doc, &at, &why) == SINEW_OK)
            fail_msg("'%s' was read", bad[i].text);
        if (at != bad[i].at)
            fail_msg("'%s' refused at %zu (%s), expected %zu", bad[i].text, at, why, bad[i].at);
        assert_null(doc.root);
    }
    json_doc doc = {0};
    size_t at = 0;
    const char *why = NULL;
    assert_int_equal(json_parse("[1 2,]", 6, false, &doc, &at, &why), SINEW_OK);
    assert_int_equal(doc.root->count, 2);
    json_free(&doc);
    static const char *const misplaced[] = {"{\"a\":1 \"b\":2}", "[\"a\":1]", "{\"a\" 1}"};
    for (size_t i = 0; i < sizeof misplaced / sizeof misplaced[0]; i++)
        if (json_parse(misplaced[i], strlen(misplaced[i]), false, &doc, &at, &why) == SINEW_OK)
            fail_msg("'%s' was read", misplaced[i]);
}

/* Strings read eight bytes at a time: an escape or a control character at every place around a
 * word's edge, in strings of 0 to 19 bytes (the last word masked past the string's end). */
static void test_strings_around_words(void **state)
{
    (void)state;
    static const char *const escaped[] = {"\\n", "\\\"", "\\\\", "\\u00e9", "\\ud83d\\ude00", "x"};
    static const char *const meant[] = {"\n", "\"", "\\", "\xc3\xa9", "\xf0\x9f\x98\x80", "x"};
    for (int len = 0; len < 20; len++)
        for (int at = 0; at <= len; at++)
            for (int e = 0; e < 6; e++) {
                char plain[32] = {0}, doc[96], want[64];
                for (int i = 0; i < len; i++)
                    plain[i] = (char)('a' + i % 26);
                snprintf(doc, sizeof doc, "[\"%.*s%s%s\"]", at, plain, escaped[e], plain + at);
                snprintf(want, sizeof want, "%.*s%s%s", at, plain, meant[e], plain + at);
                json_doc d = {0};
                size_t off = 0;
                const char *why = NULL;
                if (json_parse(doc, strlen(doc), false, &d, &off, &why) != SINEW_OK)
                    fail_msg("'%s' refused at %zu: %s", doc, off, why);
                if (strcmp(d.root[1].string, want) != 0 || d.root[1].count != strlen(want))
                    fail_msg("'%s' read as '%s'", doc, d.root[1].string);
                json_free(&d);
            }
    for (int len = 1; len < 20; len++)
        for (int at = 0; at < len; at++) {
            char doc[32];
            int n = snprintf(doc, sizeof doc, "[\"%.*s\"]", len, "bbbbbbbbbbbbbbbbbbbb");
            doc[2 + at] = '\t';
            json_doc d = {0};
            size_t off = 0;
            const char *why = NULL;
            assert_int_equal(json_parse(doc, (size_t)n, false, &d, &off, &why), SINEW_ERROR_FORMAT);
            assert_int_equal(off, 2 + at);
        }
}

int main(void)
{
    setlocale(LC_ALL, "C");
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_numbers_as_strtod),    cmocka_unit_test(test_scan_within),
        cmocka_unit_test(test_not_numbers),          cmocka_unit_test(test_documents),
        cmocka_unit_test(test_strings_around_words),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
