/* JSON through jsmn, into flat nodes (json.h). */
#define _GNU_SOURCE /* newlocale, strtod_l */
#include <locale.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#define JSMN_STATIC
#define JSMN_PARENT_LINKS /* a closing bracket finds its opener without walking back */
#define JSMN_STRICT
#include <jsmn.h>

#include "../core/internal.h"
#include "decimal.h"
#include "internal.h" /* import_large_alloc */
#include "json.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

static locale_t c_locale;
static pthread_once_t c_locale_once = PTHREAD_ONCE_INIT;

static void make_c_locale(void)
{
    c_locale = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0);
}

static int hex4(const char *p)
{
    int v = 0;
    for (int i = 0; i < 4; i++) {
        char c = p[i];
        int d = c >= '0' && c <= '9'   ? c - '0'
                : c >= 'a' && c <= 'f' ? c - 'a' + 10
                : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                       : -1;
        if (d < 0)
            return -1;
        v = v * 16 + d;
    }
    return v;
}

static char *put_utf8(char *out, unsigned cp)
{
    if (cp < 0x80) {
        *out++ = (char)cp;
    } else if (cp < 0x800) {
        *out++ = (char)(0xC0 | cp >> 6);
        *out++ = (char)(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
        *out++ = (char)(0xE0 | cp >> 12);
        *out++ = (char)(0x80 | (cp >> 6 & 0x3F));
        *out++ = (char)(0x80 | (cp & 0x3F));
    } else {
        *out++ = (char)(0xF0 | cp >> 18);
        *out++ = (char)(0x80 | (cp >> 12 & 0x3F));
        *out++ = (char)(0x80 | (cp >> 6 & 0x3F));
        *out++ = (char)(0x80 | (cp & 0x3F));
    }
    return out;
}

/* The bytes of a word (8 bytes of text, the first in the lowest) that are `c`, or below `n` (at most
 * 0x80), flagged in their high bits. A byte's borrow only runs upwards, so the lowest flag is
 * always a byte wanted (those above it may not be). */
static inline uint64_t bytes_equal(uint64_t w, unsigned char c)
{
    const uint64_t ones = 0x0101010101010101u, highs = 0x8080808080808080u;
    uint64_t x = w ^ (ones * c);
    return (x - ones) & ~x & highs;
}

static inline uint64_t bytes_below(uint64_t w, unsigned char n)
{
    const uint64_t ones = 0x0101010101010101u, highs = 0x8080808080808080u;
    return (w - ones * n) & ~w & highs;
}

/* The string text[start, end) unescaped in place and NUL-terminated (it only shrinks), its
 * length in *length; false with *bad at the offending byte. */
static bool unescape(char *text, int start, int end, int *bad, uint32_t *length)
{
    /* Most strings (keys, names) have no escape: nothing to move. Eight bytes at a time to the
     * first below 0x20 or a \; the last word reads past the string (its quote, the text's 8 bytes
     * of padding), where a flag means there is none. */
    int plain = start;
    for (; plain < end; plain += 8) {
        uint64_t w;
        memcpy(&w, text + plain, 8);
        uint64_t hit = bytes_below(w, 0x20) | bytes_equal(w, '\\');
        if (hit) {
            plain += __builtin_ctzll(hit) / 8;
            break;
        }
    }
    plain = plain < end ? plain : end;
    char *out = text + plain;
    for (int i = plain; i < end; i++) {
        unsigned char c = (unsigned char)text[i];
        if (c < 0x20) {
            *bad = i;
            return false;
        }
        if (c != '\\') {
            *out++ = (char)c;
            continue;
        }
        char e = text[++i]; /* jsmn has checked the escape's form */
        switch (e) {
        case 'b':
            *out++ = '\b';
            break;
        case 'f':
            *out++ = '\f';
            break;
        case 'n':
            *out++ = '\n';
            break;
        case 'r':
            *out++ = '\r';
            break;
        case 't':
            *out++ = '\t';
            break;
        case 'u': {
            int cp = hex4(text + i + 1);
            i += 4;
            if (cp >= 0xD800 && cp < 0xDC00 && i + 6 < end && text[i + 1] == '\\' && text[i + 2] == 'u') {
                int low = hex4(text + i + 3);
                if (low >= 0xDC00 && low < 0xE000) {
                    cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
                    i += 6;
                }
            }
            out = put_utf8(out, cp < 0 ? 0xFFFD : (unsigned)cp);
            break;
        }
        default:
            *out++ = e;
            break; /* \" \\ \/ */
        }
    }
    *out = '\0';
    *length = (uint32_t)(out - (text + start));
    return true;
}

/* Where a member's value should have been: after the key's closing quote and the colon. */
static size_t after_key(const char *text, size_t size, int key_end)
{
    size_t at = (size_t)key_end + 1;
    while (at < size && strchr(" \t\r\n:", text[at]))
        at++;
    return at;
}

static bool literal(const char *p, int n, json_node *node)
{
    static const struct {
        const char *word;
        json_type type;
    } WORDS[] = {{"true", JSON_TRUE}, {"false", JSON_FALSE}, {"null", JSON_NULL}};
    int w = p[0] == 't' ? 0 : p[0] == 'f' ? 1 : p[0] == 'n' ? 2 : -1; /* numbers: none */
    if (w >= 0 && (size_t)n == strlen(WORDS[w].word) && memcmp(p, WORDS[w].word, (size_t)n) == 0) {
        node->type = (uint8_t)WORDS[w].type;
        return true;
    }
    return false;
}

/* A JSON number (RFC 8259: -? int frac? exp?, nothing else) of len bytes at p: Clinger's fast
 * path where it is exact (decimal.h), else strtod in the C locale. */
static bool number(const char *p, int len, double *out)
{
    int r = decimal_exact(p, (size_t)len, out);
    if (r != 0)
        return r > 0;
    char *end = NULL;
    *out = strtod_l(p, &end, c_locale);
    return end == p + len;
}

/* The first comma or colon in text[from, to), else to: eight bytes at a time over the indents of
 * pretty-printed files, the last word read past `to` (at worst into the text's padding). */
static int next_separator(const char *text, int from, int to)
{
    for (; from < to; from += 8) {
        uint64_t w;
        memcpy(&w, text + from, 8);
        uint64_t hit = bytes_equal(w, ',') | bytes_equal(w, ':');
        if (hit) {
            from += __builtin_ctzll(hit) / 8;
            break;
        }
    }
    return from < to ? from : to;
}

/* A key (a string member of an object) that jsmn gave no value: what a gap without its colon or
 * a colon without its value means after one. */
static bool dangling_key(const jsmntok_t *tok, const jsmntok_t *t)
{
    return t->type == JSMN_STRING && t->size == 0 && t->parent >= 0 && tok[t->parent].type == JSMN_OBJECT;
}

/* The commas and colons jsmn does not check, in the gap before token i (i == n: after the last):
 * after an object's or array's opening bracket nothing, after a key one colon, after a sibling
 * one comma (closing brackets between), after the last token nothing; nothing inside an empty
 * object or array either. False with *bad and *why at the first that is missing, doubled or out
 * of place. (A string with a value that is not a key is convert()'s to refuse.) */
static bool gap_ok(const char *text, size_t size, const jsmntok_t *tok, int i, int n, size_t *bad, const char **why)
{
    const jsmntok_t *p = &tok[i - 1];
    int from, to = i < n ? tok[i].start - (tok[i].type == JSMN_STRING) : (int)size;
    char want = 0;
    if (i < n && tok[i].parent < 0) {
        *bad = (size_t)to;
        *why = "more than one value at the top level";
        return false;
    } else if (i < n && tok[i].parent == i - 1) { /* a key's value, or an object's or array's first child */
        if (p->type == JSMN_PRIMITIVE) {
            *bad = (size_t)p->end; /* jsmn took a colon after a value */
            *why = "a colon out of place";
            return false;
        }
        from = p->type == JSMN_STRING ? p->end + 1 : p->start + 1;
        want = p->type == JSMN_STRING ? ':' : 0;
    } else { /* after a value, its subtree and the brackets closing after it */
        if ((p->type == JSMN_OBJECT || p->type == JSMN_ARRAY) && p->size == 0) {
            int inside = next_separator(text, p->start + 1, p->end - 1);
            if (inside < p->end - 1) {
                *bad = (size_t)inside;
                *why = "a separator without a value";
                return false;
            }
        }
        from = p->type == JSMN_STRING ? p->end + 1 : p->end;
        want = i < n ? ',' : 0;
    }
    if (to - from == (want != 0) && (!want || text[from] == want))
        return true; /* most gaps: the separator alone, or nothing */
    int k = next_separator(text, from, to);
    if (k == to ? !want : text[k] == want && (k = next_separator(text, k + 1, to)) == to)
        return true; /* the separator wanted, and no other */
    if (dangling_key(tok, p)) {
        *bad = after_key(text, size, p->end);
        *why = "a member without a value";
    } else if (k == to) {
        *bad = (size_t)to;
        *why = want == ',' ? "a comma missing before this value" : "a colon missing before this value";
    } else {
        *bad = (size_t)k;
        *why = text[k] == ',' ? "a comma without a value" : "a colon out of place";
    }
    return false;
}

/* gap_ok() before every token and after the last. */
static bool separators(const char *text, size_t size, const jsmntok_t *tok, int n, size_t *bad, const char **why)
{
    for (int i = 1; i <= n; i++)
        if (!gap_ok(text, size, tok, i, n, bad, why))
            return false;
    return true;
}

/* The tokens as nodes; false with *bad and *why when a token is not JSON. */
static bool convert(char *text, size_t size, const jsmntok_t *tok, int n, json_node *nodes, size_t *bad,
                    const char **why)
{
    for (int i = 0; i < n; i++) {
        const jsmntok_t *t = &tok[i];
        json_node *node = &nodes[i];
        *node = (json_node){.span = 1, .offset = (uint32_t)t->start};
        if (t->type == JSMN_OBJECT || t->type == JSMN_ARRAY) {
            node->type = t->type == JSMN_OBJECT ? JSON_OBJECT : JSON_ARRAY;
            node->count = (uint32_t)t->size;
        } else if (t->type == JSMN_STRING) {
            bool key = t->parent >= 0 && tok[t->parent].type == JSMN_OBJECT;
            if (key && t->size != 1) { /* more than one: a comma missing (jsmn made the next member its value) */
                *bad = after_key(text, size, t->end);
                *why = "a member without a value";
                return false;
            }
            if (!key && t->size != 0) { /* ["a": 1] */
                *bad = (size_t)t->end + 1;
                *why = "a colon out of place";
                return false;
            }
            int at;
            if (!unescape(text, t->start, t->end, &at, &node->count)) {
                *bad = (size_t)at;
                *why = "a control character inside a string";
                return false;
            }
            node->type = JSON_STRING;
            node->string = text + t->start;
        } else {
            const char *p = text + t->start;
            int len = t->end - t->start;
            if (!literal(p, len, node)) {
                node->type = JSON_NUMBER;
                if (!number(p, len, &node->number)) {
                    *bad = (size_t)t->start;
                    *why = "not a number, true, false or null";
                    return false;
                }
            }
        }
    }
    for (int i = n - 1; i > 0; i--) /* children follow their parent: a subtree's size from its end */
        if (tok[i].parent >= 0)
            nodes[tok[i].parent].span += nodes[i].span;
    if (nodes[0].span != (uint32_t)n) {
        *bad = (size_t)tok[nodes[0].span].start;
        *why = "more than one value at the top level";
        return false;
    }
    return true;
}

sinew_result json_parse(const char *source, size_t size, bool by_hand, json_doc *doc, size_t *error_offset,
                        const char **why)
{
    *doc = (json_doc){0};
    *error_offset = 0;
    *why = "";
    pthread_once(&c_locale_once, make_c_locale);
    if (size > (size_t)INT32_MAX) {
        *why = "larger than 2 GB";
        return SINEW_ERROR_FORMAT;
    }
    if (!c_locale || !(doc->text = import_large_alloc(size + 8, IMPORT_PAGES_MIN)))
        return SINEW_ERROR_OUT_OF_MEMORY;
    memcpy(doc->text, source, size);
    memset(doc->text + size, 0, 8); /* a NUL, and bytes for the scans' last words to read */
    /* tokens: a guess from the size (glTF files run 6 to 8 bytes a token; pages not written are
     * never touched), doubled while jsmn asks for more (it goes on where it stopped) */
    jsmn_parser parser;
    jsmn_init(&parser);
    unsigned room = (unsigned)(size / 6 + 16);
    jsmntok_t *tokens = NULL;
    int n;
    for (;;) {
        jsmntok_t *more = realloc(tokens, (size_t)room * sizeof *tokens);
        if (!more) {
            free(tokens);
            json_free(doc);
            return SINEW_ERROR_OUT_OF_MEMORY;
        }
        tokens = more;
        n = jsmn_parse(&parser, doc->text, size, tokens, room);
        if (n != JSMN_ERROR_NOMEM)
            break;
        room = room > UINT32_MAX / 4 ? UINT32_MAX / 2 : room * 2;
    }
    sinew_result result = SINEW_OK;
    if (n <= 0) {
        *error_offset = parser.pos < size ? parser.pos : size;
        *why = n == 0 ? "no value" : n == JSMN_ERROR_PART ? "it ends inside a value" : "an unexpected character";
        result = SINEW_ERROR_FORMAT;
    } else if (!(doc->root = import_large_alloc((size_t)n * sizeof *doc->root, IMPORT_PAGES_MIN))) {
        result = SINEW_ERROR_OUT_OF_MEMORY;
    } else {
        if ((by_hand && !separators(doc->text, size, tokens, n, error_offset, why)) ||
            !convert(doc->text, size, tokens, n, doc->root, error_offset, why))
            result = SINEW_ERROR_FORMAT;
    }
    free(tokens);
    if (result != SINEW_OK)
        json_free(doc);
    return result;
}

void json_line_column(const char *text, size_t offset, int *line, int *column)
{
    *line = 1, *column = 1;
    for (size_t i = 0; i < offset; i++) {
        if (text[i] == '\n')
            (*line)++, *column = 1;
        else
            (*column)++;
    }
}

sinew_result json_parse_named(const char *text, size_t size, const char *name, json_doc *doc, sinew_error *error)
{
    size_t at = 0;
    const char *why = "";
    sinew_result result = json_parse(text, size, true, doc, &at, &why);
    if (result == SINEW_ERROR_OUT_OF_MEMORY)
        return sinew_fail(error, result, "%s: out of memory", name);
    if (result != SINEW_OK) {
        int line, column;
        json_line_column(text, at > size ? size : at, &line, &column);
        return sinew_fail(error, result, "%s:%d:%d: not valid JSON here: %s", name, line, column, why);
    }
    return SINEW_OK;
}

void json_free(json_doc *doc)
{
    free(doc->root);
    free(doc->text);
    *doc = (json_doc){0};
}

const json_node *json_get(const json_node *object, const char *key)
{
    if (!object || object->type != JSON_OBJECT)
        return NULL;
    const json_node *v;
    JSON_FOR_EACH(v, object)
    {
        if (v[-1].string[0] == key[0] && strcmp(v[-1].string, key) == 0)
            return v;
    }
    return NULL;
}

/* memcmp(a, b, n) == 0 for the few bytes of a key, without a call */
static inline bool same_bytes(const char *a, const char *b, uint32_t n)
{
    uint32_t i = 0;
    for (; i + 8 <= n; i += 8) { /* both have n bytes and a NUL */
        uint64_t x, y;
        memcpy(&x, a + i, 8);
        memcpy(&y, b + i, 8);
        if (x != y)
            return false;
    }
    while (i < n && a[i] == b[i])
        i++;
    return i == n;
}

void json_pick(const json_node *object, const json_key *keys, int n, const json_node **out)
{
    for (int k = 0; k < n; k++)
        out[k] = NULL;
    if (!object || object->type != JSON_OBJECT)
        return;
    const json_node *v;
    JSON_FOR_EACH(v, object)
    {
        const json_node *name = &v[-1];
        uint32_t length = name->count;
        if (length == 0)
            continue;
        for (int k = 0; k < n; k++) /* the length and the last byte tell most names apart without a call */
            if (length == keys[k].length && name->string[length - 1] == keys[k].name[length - 1] && !out[k] &&
                same_bytes(name->string, keys[k].name, length)) {
                out[k] = v;
                break;
            }
    }
}

const json_node *json_item(const json_node *array, int i)
{
    if (!array || array->type != JSON_ARRAY || i < 0 || (uint32_t)i >= array->count)
        return NULL;
    const json_node *v = json_first(array);
    while (i-- > 0)
        v = json_after(array, v);
    return v;
}
