/* FBX documents, binary and ASCII 7.x, as a tree of nodes (fbx_internal.h).
 *
 *   budget ............ every allocation counted against a limit set by the file size, and made
 *                       in the document's arena (a few large chunks, freed together)
 *   binary ............ records (32-bit offsets before 7.5, 64-bit from 7.5), typed values,
 *                       arrays raw or zlib-compressed
 *   ascii ............. a tokenizer and a recursive reader of `Name: values { children }`
 *   lookups ........... fbx_child, fbx_num, fbx_array, ...
 *
 * Binary records give their end offset: each must lie after its own header and inside its
 * parent, so a record can never point back into itself and nesting always ends. Nesting is
 * also limited to FBX_MAX_DEPTH levels in both forms.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libdeflate.h>

#include "../core/internal.h"
#include "decimal.h"
#include "fbx_internal.h"
#include "alloc.h" /* last: the readers' allocations are the import's (alloc.h) */

#define FBX_MAX_DEPTH 64
#define FBX_BINARY_MAGIC "Kaydara FBX Binary  \0\x1a"
#define FBX_BINARY_MAGIC_SIZE 23u
#define FBX_BINARY_HEADER_SIZE 27u

typedef struct parser {
    fbx_doc *doc; /* whose arena holds what is read */
    const unsigned char *bytes;
    size_t size, pos;
    const char *path;
    sinew_error *error;
    bool wide;                                /* 64-bit record offsets (FBX 7.5 and later) */
    struct libdeflate_decompressor *inflater; /* made at the first compressed array */
    size_t budget;
    int depth;
    /* ASCII: one token of lookahead */
    int tok;
    const char *tok_text;
    size_t tok_len;
    size_t line;
} parser;

/* ---- budget ------------------------------------------------------------------------ */

/* A file may decode to at most this many bytes: zlib's largest ratio (about 1032:1) over the
 * whole file, plus room for the tree of a small file. */
static size_t budget_for(size_t size)
{
    return size > (SIZE_MAX - (64u << 20)) / 1100u ? SIZE_MAX : size * 1100u + (64u << 20);
}

static sinew_result fail_limit(parser *ps)
{
    return sinew_fail(ps->error, SINEW_ERROR_LIMIT,
                      "%s: the FBX document decodes to more than %zu bytes (the limit for a file of %zu bytes)",
                      ps->path, budget_for(ps->size), ps->size);
}

static sinew_result out_of_memory(parser *ps)
{
    return sinew_fail(ps->error, SINEW_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the FBX document", ps->path);
}

static void *take(parser *ps, size_t count, size_t elem, sinew_result *result)
{
    if (count == 0)
        return NULL;
    if (count > ps->budget / elem) {
        *result = fail_limit(ps);
        return NULL;
    }
    void *p = import_arena_take(&ps->doc->arena, count * elem);
    if (!p) {
        *result = out_of_memory(ps);
        return NULL;
    }
    ps->budget -= count * elem;
    return p;
}

void fbx_doc_free(fbx_doc *doc)
{
    if (!doc)
        return;
    import_arena_free(&doc->arena);
    memset(doc, 0, sizeof *doc);
}

/* Room for one more element after `count` in a growing array charged to the budget: the
 * capacity doubles (from `first` when empty), the elements moved to a larger block of the arena
 * (the old one is left: at most as much again). */
static sinew_result grow_array(parser *ps, void **array, uint32_t count, uint32_t *capacity, uint32_t first,
                               size_t elem)
{
    if (count < *capacity)
        return SINEW_OK;
    uint32_t grown = *capacity ? *capacity * 2 : first;
    if (grown <= *capacity || (size_t)grown > ps->budget / elem)
        return fail_limit(ps);
    void *p = import_arena_take(&ps->doc->arena, (size_t)grown * elem);
    if (!p)
        return out_of_memory(ps);
    if (count)
        memcpy(p, *array, (size_t)count * elem);
    ps->budget -= (size_t)grown * elem;
    *array = p;
    *capacity = grown;
    return SINEW_OK;
}

/* Appends a node to a growing child list. */
static fbx_node *push_child(parser *ps, fbx_node *parent, uint32_t *capacity, sinew_result *result)
{
    if ((*result = grow_array(ps, (void **)&parent->children, parent->child_count, capacity, 4, sizeof(fbx_node))))
        return NULL;
    return &parent->children[parent->child_count++]; /* zeroed: fresh from the arena */
}

/* ---- binary ------------------------------------------------------------------------ */

static sinew_result bad(parser *ps, size_t at, const char *what)
{
    return sinew_fail_at(ps->error, SINEW_ERROR_FORMAT, ps->path, (int64_t)at, 0, "%s: byte %zu: %s", ps->path, at,
                         what);
}

static uint64_t read_le(const unsigned char *p, int bytes)
{
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    if (bytes == 4) {
        uint32_t v;
        memcpy(&v, p, 4);
        return v;
    }
    if (bytes == 8) {
        uint64_t v;
        memcpy(&v, p, 8);
        return v;
    }
#endif
    uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; i--)
        v = (v << 8) | p[i];
    return v;
}

static inline double array_element(const unsigned char *p, char type)
{
    switch (type) {
    case 'f': {
        float f;
        memcpy(&f, p, 4);
        return f;
    }
    case 'd': {
        double d;
        memcpy(&d, p, 8);
        return d;
    }
    case 'l':
        return (double)(int64_t)read_le(p, 8);
    case 'i':
        return (double)(int32_t)read_le(p, 4);
    default: /* 'b' */
        return p[0] ? 1.0 : 0.0;
    }
}

/* count elements of `elem` bytes and `type` at src as doubles. */
__attribute__((always_inline)) static inline void convert_array(double *out, const unsigned char *src, uint32_t count,
                                                                size_t elem, char type)
{
    for (uint32_t i = 0; i < count; i++)
        out[i] = array_element(src + (size_t)i * elem, type);
}

static sinew_result read_array(parser *ps, char type, size_t end, fbx_value *v)
{
    size_t at = ps->pos;
    if (end - ps->pos < 12)
        return bad(ps, at, "array header runs past its record");
    uint32_t count = (uint32_t)read_le(ps->bytes + ps->pos, 4);
    uint32_t encoding = (uint32_t)read_le(ps->bytes + ps->pos + 4, 4);
    uint32_t stored = (uint32_t)read_le(ps->bytes + ps->pos + 8, 4);
    ps->pos += 12;
    size_t elem = type == 'd' || type == 'l' ? 8 : type == 'b' ? 1 : 4;
    if (stored > end - ps->pos)
        return bad(ps, at, "array data runs past its record");
    if ((uint64_t)count * elem > UINT32_MAX)
        return bad(ps, at, "array is larger than 4 GiB");
    size_t raw_size = (size_t)count * elem;
    const unsigned char *src = ps->bytes + ps->pos;
    unsigned char *inflated = NULL;
    sinew_result result = SINEW_OK;
    if (raw_size > ps->budget)
        return sinew_fail(ps->error, SINEW_ERROR_LIMIT,
                          "%s: byte %zu: an array of %u elements is larger than a file of %zu bytes may decode to",
                          ps->path, at, count, ps->size);
    if (encoding == 1) {
        inflated = malloc(raw_size ? raw_size : 1);
        if (!inflated)
            return out_of_memory(ps);
        if (!ps->inflater && !(ps->inflater = libdeflate_alloc_decompressor())) {
            free(inflated);
            return out_of_memory(ps);
        }
        /* a zlib stream (its Adler-32 checked), decoded whole: libdeflate, 2-3x zlib's inflate */
        size_t got = 0;
        enum libdeflate_result z = libdeflate_zlib_decompress(ps->inflater, src, stored, inflated, raw_size, &got);
        if (z != LIBDEFLATE_SUCCESS || got != raw_size) {
            free(inflated);
            return bad(ps, at,
                       z == LIBDEFLATE_BAD_DATA ? "compressed array is corrupt"
                                                : "compressed array has the wrong length");
        }
        src = inflated;
    } else if (encoding != 0) {
        return bad(ps, at, "array has an unknown encoding");
    } else if (stored != raw_size) {
        return bad(ps, at, "array size does not match its count");
    }
    ps->pos += stored;
    v->type = FBX_ARRAY;
    v->count = count;
    v->a = take(ps, count, sizeof(double), &result);
    if (count && !v->a) {
        free(inflated);
        return result;
    }
    switch (type) { /* one loop a type (convert_array inlined with the type known): a switch an
                     * element cost a tenth of a mesh's import */
    case 'f':
        convert_array(v->a, src, count, 4, 'f');
        break;
    case 'd':
        convert_array(v->a, src, count, 8, 'd');
        break;
    case 'i':
        convert_array(v->a, src, count, 4, 'i');
        break;
    case 'l':
        convert_array(v->a, src, count, 8, 'l');
        break;
    default:
        convert_array(v->a, src, count, elem, type);
        break;
    }
    free(inflated);
    return SINEW_OK;
}

static sinew_result read_value(parser *ps, size_t end, fbx_value *v)
{
    size_t at = ps->pos;
    char type = (char)ps->bytes[ps->pos++];
    static const struct {
        char type;
        int bytes;
    } scalars[] = {{'Y', 2}, {'C', 1}, {'I', 4}, {'L', 8}, {'F', 4}, {'D', 8}};
    for (size_t k = 0; k < sizeof scalars / sizeof scalars[0]; k++) {
        if (scalars[k].type != type)
            continue;
        int n = scalars[k].bytes;
        if (end - ps->pos < (size_t)n)
            return bad(ps, at, "value runs past its record");
        const unsigned char *p = ps->bytes + ps->pos;
        ps->pos += (size_t)n;
        if (type == 'F' || type == 'D') {
            v->type = FBX_REAL;
            v->d = type == 'F' ? array_element(p, 'f') : array_element(p, 'd');
            v->i = v->d > -9.2e18 && v->d < 9.2e18 ? (int64_t)v->d : 0;
        } else {
            uint64_t u = read_le(p, n);
            v->type = FBX_INT;
            v->i = n == 8 ? (int64_t)u : n == 4 ? (int32_t)u : n == 2 ? (int16_t)u : (int64_t)u;
            v->d = (double)v->i;
        }
        return SINEW_OK;
    }
    if (type == 'S' || type == 'R') {
        if (end - ps->pos < 4)
            return bad(ps, at, "string length runs past its record");
        uint32_t len = (uint32_t)read_le(ps->bytes + ps->pos, 4);
        ps->pos += 4;
        if (len > end - ps->pos)
            return bad(ps, at, "string runs past its record");
        v->type = FBX_STRING;
        v->s = (const char *)ps->bytes + ps->pos;
        v->count = len;
        ps->pos += len;
        return SINEW_OK;
    }
    if (strchr("fdlib", type) && type)
        return read_array(ps, type, end, v);
    return bad(ps, at, "value of an unknown type");
}

static sinew_result read_record(parser *ps, size_t limit, fbx_node *out, bool *null_record);

/* How many records follow `pos` before a null record or `end`, by their headers' end offsets
 * alone (it stops at the first header that does not fit: read_record says what is wrong). */
static uint32_t count_records(const parser *ps, size_t pos, size_t end)
{
    const size_t header = ps->wide ? 25 : 13;
    const int w = ps->wide ? 8 : 4;
    uint32_t n = 0;
    while (end - pos >= header && n < UINT32_MAX) {
        uint64_t next = read_le(ps->bytes + pos, w);
        if (next <= pos || next > end) /* the null record (0), or one read_record refuses */
            break;
        n++;
        pos = (size_t)next;
    }
    return n;
}

/* Children of a record: records until a null record or the record's end. */
static sinew_result read_children(parser *ps, size_t end, fbx_node *parent)
{
    uint32_t capacity = 0;
    sinew_result result = SINEW_OK;
    const size_t header = ps->wide ? 25 : 13;
    /* The list made at its final size: grown by doubling, it left the smaller lists behind in
     * the arena (walk.fbx: half of 1.1 MB of node lists) */
    uint32_t expected = ps->pos < end ? count_records(ps, ps->pos, end) : 0;
    if (expected) {
        if (!(parent->children = take(ps, expected, sizeof(fbx_node), &result)))
            return result;
        capacity = expected;
    }
    while (ps->pos < end) {
        if (end - ps->pos < header)
            return bad(ps, ps->pos, "record header runs past its parent");
        fbx_node child = {0};
        bool null_record = false;
        if ((result = read_record(ps, end, &child, &null_record))) {
            return result;
        }
        if (null_record)
            break;
        fbx_node *slot = push_child(ps, parent, &capacity, &result);
        if (!slot) {
            return result;
        }
        *slot = child;
    }
    return SINEW_OK;
}

static sinew_result read_record(parser *ps, size_t limit, fbx_node *out, bool *null_record)
{
    const size_t at = ps->pos, header = ps->wide ? 25 : 13;
    const int w = ps->wide ? 8 : 4;
    const unsigned char *p = ps->bytes + at;
    uint64_t end = read_le(p, w), value_count = read_le(p + w, w), value_bytes = read_le(p + 2 * w, w);
    uint8_t name_len = p[3 * w];
    if (end == 0 && value_count == 0 && value_bytes == 0 && name_len == 0) {
        ps->pos += header;
        *null_record = true;
        return SINEW_OK;
    }
    if (end > ps->size && end < at + (1u << 30))
        return sinew_fail_at(
            ps->error, SINEW_ERROR_FORMAT, ps->path, (int64_t)at, 0,
            "%s: the file ends at byte %zu inside a record that runs to byte %llu (it seems cut short)", ps->path,
            ps->size, (unsigned long long)end);
    if (end > limit || end < at + header + name_len || value_bytes > end - (at + header + name_len))
        return bad(ps, at, "record's end lies outside its parent");
    if (value_count > value_bytes)
        return bad(ps, at, "record claims more values than it has bytes");
    if (ps->depth >= FBX_MAX_DEPTH)
        return bad(ps, at, "records nested deeper than 64 levels");
    out->name = (const char *)p + header;
    out->name_len = name_len;
    ps->pos = at + header + name_len;
    size_t values_end = ps->pos + value_bytes;
    sinew_result result = SINEW_OK;
    out->values = take(ps, value_count, sizeof(fbx_value), &result);
    if (value_count && !out->values)
        return result;
    for (uint64_t k = 0; k < value_count; k++) {
        if (ps->pos >= values_end)
            return bad(ps, ps->pos, "record's values run past their length");
        out->value_count++;
        if ((result = read_value(ps, values_end, &out->values[k])))
            return result;
    }
    if (ps->pos != values_end)
        return bad(ps, ps->pos, "record's values do not fill their length");
    ps->depth++;
    result = read_children(ps, (size_t)end, out);
    ps->depth--;
    ps->pos = (size_t)end;
    return result;
}

static sinew_result parse_binary(parser *ps, fbx_doc *doc)
{
    doc->binary = true;
    doc->version = (uint32_t)read_le(ps->bytes + FBX_BINARY_MAGIC_SIZE, 4);
    ps->wide = doc->version >= 7500;
    ps->pos = FBX_BINARY_HEADER_SIZE;
    /* The top level ends with a null record, then a footer. */
    uint32_t capacity = 0;
    sinew_result result = SINEW_OK;
    const size_t header = ps->wide ? 25 : 13;
    while (ps->size - ps->pos >= header) {
        fbx_node child = {0};
        bool null_record = false;
        if ((result = read_record(ps, ps->size, &child, &null_record))) {
            return result;
        }
        if (null_record)
            return SINEW_OK;
        fbx_node *slot = push_child(ps, &doc->root, &capacity, &result);
        if (!slot) {
            return result;
        }
        *slot = child;
    }
    if (doc->root.child_count == 0)
        return bad(ps, ps->pos, "the file ends before its first record");
    /* Every writer ends the top level with a null record: without one the file was cut short
     * between two records. */
    return sinew_fail_at(ps->error, SINEW_ERROR_FORMAT, ps->path, (int64_t)ps->size, 0,
                         "%s: the file ends at byte %zu, between two records, before the end of its top level "
                         "(it seems cut short)",
                         ps->path, ps->size);
}

/* ---- ASCII ------------------------------------------------------------------------- */

enum { T_END, T_KEY, T_STRING, T_NUMBER, T_WORD, T_OPEN, T_CLOSE, T_COMMA, T_STAR, T_BAD };

static sinew_result bad_line(parser *ps, const char *what)
{
    return sinew_fail_at(ps->error, SINEW_ERROR_FORMAT, ps->path, -1, (uint32_t)ps->line, "%s: line %zu: %s", ps->path,
                         ps->line, what);
}

/* The bytes of a bare word or number: letters, digits and _ | - . + (a table: the tokenizer asks
 * once a byte). */
static const bool word_chars[256] = {
    ['_'] = 1, ['|'] = 1, ['-'] = 1, ['.'] = 1, ['+'] = 1, ['0'] = 1, ['1'] = 1, ['2'] = 1, ['3'] = 1, ['4'] = 1,
    ['5'] = 1, ['6'] = 1, ['7'] = 1, ['8'] = 1, ['9'] = 1, ['a'] = 1, ['b'] = 1, ['c'] = 1, ['d'] = 1, ['e'] = 1,
    ['f'] = 1, ['g'] = 1, ['h'] = 1, ['i'] = 1, ['j'] = 1, ['k'] = 1, ['l'] = 1, ['m'] = 1, ['n'] = 1, ['o'] = 1,
    ['p'] = 1, ['q'] = 1, ['r'] = 1, ['s'] = 1, ['t'] = 1, ['u'] = 1, ['v'] = 1, ['w'] = 1, ['x'] = 1, ['y'] = 1,
    ['z'] = 1, ['A'] = 1, ['B'] = 1, ['C'] = 1, ['D'] = 1, ['E'] = 1, ['F'] = 1, ['G'] = 1, ['H'] = 1, ['I'] = 1,
    ['J'] = 1, ['K'] = 1, ['L'] = 1, ['M'] = 1, ['N'] = 1, ['O'] = 1, ['P'] = 1, ['Q'] = 1, ['R'] = 1, ['S'] = 1,
    ['T'] = 1, ['U'] = 1, ['V'] = 1, ['W'] = 1, ['X'] = 1, ['Y'] = 1, ['Z'] = 1};

static bool word_char(unsigned char c)
{
    return word_chars[c];
}

static void next_token(parser *ps)
{
    const unsigned char *b = ps->bytes;
    for (;;) {
        while (ps->pos < ps->size &&
               (b[ps->pos] == ' ' || b[ps->pos] == '\t' || b[ps->pos] == '\r' || b[ps->pos] == '\n')) {
            if (b[ps->pos] == '\n')
                ps->line++;
            ps->pos++;
        }
        if (ps->pos < ps->size && b[ps->pos] == ';') {
            while (ps->pos < ps->size && b[ps->pos] != '\n')
                ps->pos++;
            continue;
        }
        break;
    }
    ps->tok_text = (const char *)b + ps->pos;
    ps->tok_len = 1;
    if (ps->pos >= ps->size) {
        ps->tok = T_END;
        return;
    }
    unsigned char c = b[ps->pos];
    int single = c == '{' ? T_OPEN : c == '}' ? T_CLOSE : c == ',' ? T_COMMA : c == '*' ? T_STAR : T_END;
    if (single != T_END) {
        ps->tok = single;
        ps->pos++;
        return;
    }
    if (c == '"') {
        size_t start = ++ps->pos;
        while (ps->pos < ps->size && b[ps->pos] != '"') {
            if (b[ps->pos] == '\n')
                ps->line++;
            ps->pos++;
        }
        if (ps->pos >= ps->size) {
            ps->tok = T_BAD;
            return;
        }
        ps->tok = T_STRING;
        ps->tok_text = (const char *)b + start;
        ps->tok_len = ps->pos - start;
        ps->pos++;
        return;
    }
    if (!word_char(c)) {
        ps->tok = T_BAD;
        return;
    }
    size_t start = ps->pos;
    while (ps->pos < ps->size && word_char(b[ps->pos]))
        ps->pos++;
    ps->tok_len = ps->pos - start;
    if (ps->pos < ps->size && b[ps->pos] == ':') {
        ps->pos++;
        ps->tok = T_KEY;
        return;
    }
    ps->tok = (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' ? T_NUMBER : T_WORD;
}

/* The current token as a number: a whole number (no '.', 'e' or 'E') as FBX_INT, else
 * FBX_REAL; false when the token is not all one number. Whole numbers of up to 18 digits and the
 * decimals decimal_scan_within reads exactly (nearly all of an ASCII file's: read in place where
 * the file goes on for 24 bytes) take no strtoll or strtod, which were a third of
 * maya_slime_7500_ascii.fbx's import; the same values. */
static bool number_value(const parser *ps, fbx_value *v)
{
    const char *text = ps->tok_text, *limit = (const char *)ps->bytes + ps->size;
    size_t len = ps->tok_len;
    size_t sign = len && (text[0] == '-' || text[0] == '+'), digits = 0;
    bool point = false;
    for (size_t k = sign; k < len; k++) {
        digits += text[k] >= '0' && text[k] <= '9';
        point = point || text[k] == '.' || text[k] == 'e' || text[k] == 'E';
    }
    if (!point && digits == len - sign && digits >= 1 && digits <= 18) {
        int64_t whole = 0;
        for (size_t k = sign; k < len; k++)
            whole = whole * 10 + (text[k] - '0');
        v->type = FBX_INT;
        v->i = text[0] == '-' ? -whole : whole;
        v->d = (double)v->i;
        return true;
    }
    char buf[64];
    if (len >= sizeof buf)
        return false;
    const char *at = text, *stop = NULL;
    if (limit - text < 24 || text + len >= limit) { /* at the file's end: a copy that ends */
        memcpy(buf, text, len);
        buf[len] = 0;
        at = buf, limit = buf + len;
    }
    double d;
    if (point && decimal_scan_within(at, limit, &stop, &d) == 1 && stop == at + len) {
        v->type = FBX_REAL;
        v->d = d;
        v->i = d > -9.2e18 && d < 9.2e18 ? (int64_t)d : 0;
        return true;
    }
    memcpy(buf, text, len); /* strtod and strtoll want the token to end */
    buf[len] = 0;
    char *end = NULL;
    if (!strpbrk(buf, ".eE")) {
        v->type = FBX_INT;
        v->i = strtoll(buf, &end, 10);
        v->d = (double)v->i;
    } else {
        v->type = FBX_REAL;
        v->d = strtod(buf, &end);
        v->i = v->d > -9.2e18 && v->d < 9.2e18 ? (int64_t)v->d : 0;
    }
    return end && *end == 0;
}

/* `*N { a: x, y, ... }`: the star is already read. */
static sinew_result ascii_array(parser *ps, fbx_value *v)
{
    next_token(ps);
    fbx_value count = {0};
    if (ps->tok != T_NUMBER || !number_value(ps, &count) || count.type != FBX_INT || count.i < 0 ||
        count.i > UINT32_MAX)
        return bad_line(ps, "array count after '*' is not a whole number");
    next_token(ps);
    if (ps->tok != T_OPEN)
        return bad_line(ps, "array has no '{'");
    next_token(ps);
    if (ps->tok != T_KEY || ps->tok_len != 1 || ps->tok_text[0] != 'a')
        return bad_line(ps, "array has no 'a:'");
    /* Each number takes at least two bytes of the file; the count only sizes the first guess. */
    size_t remaining = (ps->size - ps->pos) / 2 + 1;
    uint32_t capacity = (size_t)count.i < remaining ? (uint32_t)count.i : (uint32_t)remaining;
    sinew_result result = SINEW_OK;
    v->type = FBX_ARRAY;
    v->a = take(ps, capacity ? capacity : 1, sizeof(double), &result);
    if (!v->a)
        return result;
    if (!capacity)
        capacity = 1;
    next_token(ps);
    while (ps->tok == T_NUMBER) {
        fbx_value n = {0};
        if (!number_value(ps, &n))
            return bad_line(ps, "array element is not a number");
        v->reals |= n.type == FBX_REAL;
        if ((result = grow_array(ps, (void **)&v->a, v->count, &capacity, 1, sizeof(double))))
            return result;
        v->a[v->count++] = n.d;
        next_token(ps);
        if (ps->tok == T_COMMA)
            next_token(ps);
    }
    if (ps->tok != T_CLOSE)
        return bad_line(ps, "array has something other than numbers");
    if ((uint64_t)v->count != (uint64_t)count.i)
        return bad_line(ps, "array has another number of elements than its count says");
    next_token(ps);
    return SINEW_OK;
}

static sinew_result ascii_nodes(parser *ps, fbx_node *parent, bool top);

/* One `Key: values [{ children }]`; the key is the current token. */
static sinew_result ascii_node(parser *ps, fbx_node *node)
{
    node->name = ps->tok_text;
    node->name_len = ps->tok_len > 255 ? 255 : (uint32_t)ps->tok_len;
    next_token(ps);
    if (ps->tok == T_COMMA) /* `Content: , "..."` */
        next_token(ps);
    uint32_t capacity = 0;
    sinew_result result = SINEW_OK;
    while (ps->tok == T_STRING || ps->tok == T_NUMBER || ps->tok == T_WORD || ps->tok == T_STAR) {
        if ((result = grow_array(ps, (void **)&node->values, node->value_count, &capacity, 4, sizeof(fbx_value))))
            return result;
        fbx_value *v = &node->values[node->value_count++];
        memset(v, 0, sizeof *v);
        if (ps->tok == T_STAR) {
            if ((result = ascii_array(ps, v)))
                return result;
        } else {
            if (ps->tok == T_NUMBER) {
                if (!number_value(ps, v))
                    return bad_line(ps, "value is not a number");
            } else {
                v->type = FBX_STRING;
                v->s = ps->tok_text;
                v->count = (uint32_t)ps->tok_len;
            }
            next_token(ps);
        }
        if (ps->tok != T_COMMA)
            break;
        next_token(ps);
    }
    if (ps->tok != T_OPEN) { /* `Name:` alone is a node without values (`CameraIndexName:`) */
        if (node->value_count == 0 && ps->tok == T_END)
            return bad_line(ps, "the file ends after a node's name (it may be cut short)");
        return ps->tok == T_KEY || ps->tok == T_CLOSE || node->value_count
                   ? SINEW_OK
                   : bad_line(ps, "a node has neither values nor a '{' block");
    }
    if (ps->depth >= FBX_MAX_DEPTH)
        return bad_line(ps, "nodes nested deeper than 64 levels");
    next_token(ps);
    ps->depth++;
    result = ascii_nodes(ps, node, false);
    ps->depth--;
    if (result)
        return result;
    next_token(ps); /* the '}' */
    return SINEW_OK;
}

static sinew_result ascii_nodes(parser *ps, fbx_node *parent, bool top)
{
    uint32_t capacity = 0;
    sinew_result result = SINEW_OK;
    for (;;) {
        if (ps->tok == T_END) {
            if (!top)
                return bad_line(ps, "the file ends inside a '{' block");
            return SINEW_OK;
        }
        if (ps->tok == T_CLOSE) {
            if (top)
                return bad_line(ps, "'}' without a '{'");
            return SINEW_OK;
        }
        if (ps->tok != T_KEY)
            return bad_line(ps, ps->tok == T_BAD ? "unexpected character (or a string without its closing quote)"
                                                 : "expected a node name followed by ':'");
        fbx_node *child = push_child(ps, parent, &capacity, &result);
        if (!child)
            return result;
        if ((result = ascii_node(ps, child)))
            return result;
    }
}

/* FBXHeaderExtension's FBXVersion, or 0. */
static uint32_t header_version(const fbx_doc *doc)
{
    const fbx_node *h = fbx_child(&doc->root, "FBXHeaderExtension");
    const fbx_node *v = h ? fbx_child(h, "FBXVersion") : NULL;
    int64_t version = v ? fbx_int(v, 0) : 0;
    return version > 0 && version < 100000 ? (uint32_t)version : 0;
}

static bool all_numbers(const fbx_node *n)
{
    for (uint32_t i = 0; i < n->value_count; i++)
        if (n->values[i].type != FBX_INT && n->values[i].type != FBX_REAL)
            return false;
    return true;
}

/* Before FBX 7.0 arrays are lists of values: each node of two numbers or more becomes one
 * array value (fbx_internal.h). */
static sinew_result collapse_lists(parser *ps, fbx_node *n)
{
    if (n->value_count >= 2 && all_numbers(n)) {
        sinew_result result = SINEW_OK;
        fbx_value array = {.type = FBX_ARRAY, .count = n->value_count};
        array.a = take(ps, n->value_count, sizeof(double), &result);
        if (!array.a)
            return result;
        for (uint32_t i = 0; i < n->value_count; i++) {
            array.a[i] = n->values[i].d;
            array.reals |= n->values[i].type == FBX_REAL;
        }
        n->values[0] = array;
        n->value_count = 1;
    }
    for (uint32_t i = 0; i < n->child_count; i++) {
        sinew_result result = collapse_lists(ps, &n->children[i]);
        if (result)
            return result;
    }
    return SINEW_OK;
}

static sinew_result parse_ascii(parser *ps, fbx_doc *doc)
{
    ps->line = 1;
    next_token(ps);
    sinew_result result = ascii_nodes(ps, &doc->root, true);
    if (result)
        return result;
    if (doc->root.child_count == 0)
        return sinew_fail(ps->error, SINEW_ERROR_FORMAT, "%s: no FBX nodes in the file", ps->path);
    return SINEW_OK;
}

/* ---- entry points and lookups -------------------------------------------------------- */

bool fbx_sniff(const unsigned char *bytes, size_t size)
{
    if (size >= FBX_BINARY_MAGIC_SIZE && memcmp(bytes, FBX_BINARY_MAGIC, FBX_BINARY_MAGIC_SIZE) == 0)
        return true;
    static const char *const starts[] = {"; FBX", "FBXHeaderExtension:"};
    size_t i = 0;
    while (i < size && (bytes[i] == ' ' || bytes[i] == '\t' || bytes[i] == '\r' || bytes[i] == '\n'))
        i++;
    if (size - i >= 3 && memcmp(bytes + i, "\xef\xbb\xbf", 3) == 0)
        i += 3;
    for (size_t k = 0; k < sizeof starts / sizeof starts[0]; k++)
        if (size - i >= strlen(starts[k]) && memcmp(bytes + i, starts[k], strlen(starts[k])) == 0)
            return true;
    return false;
}

sinew_result fbx_parse(const unsigned char *bytes, size_t size, const char *path, fbx_doc *doc, sinew_error *error)
{
    memset(doc, 0, sizeof *doc);
    import_arena_expect(&doc->arena, size <= SIZE_MAX / 2 ? size * 2 : size); /* walk.fbx (0.98 MB): 2.8 MB */
    parser ps = {.doc = doc, .bytes = bytes, .size = size, .path = path, .error = error, .budget = budget_for(size)};
    bool binary = size >= FBX_BINARY_MAGIC_SIZE && memcmp(bytes, FBX_BINARY_MAGIC, FBX_BINARY_MAGIC_SIZE) == 0;
    if (binary && size < FBX_BINARY_HEADER_SIZE)
        return bad(&ps, size, "the file ends inside the binary FBX header");
    sinew_result result = binary ? parse_binary(&ps, doc) : parse_ascii(&ps, doc);
    if (ps.inflater)
        libdeflate_free_decompressor(ps.inflater);
    if (!result && header_version(doc))
        doc->version = header_version(doc);
    if (!result && doc->version && doc->version < 7000)
        result = collapse_lists(&ps, &doc->root);
    if (result)
        fbx_doc_free(doc);
    return result;
}

bool fbx_named(const fbx_node *node, const char *name)
{
    size_t n = strlen(name);
    return node->name_len == n && memcmp(node->name, name, n) == 0;
}

const fbx_node *fbx_child(const fbx_node *node, const char *name)
{
    for (uint32_t i = 0; node && i < node->child_count; i++)
        if (fbx_named(&node->children[i], name))
            return &node->children[i];
    return NULL;
}

/* A node kept as one array (fbx_internal.h): its element k, else NULL. */
static const double *list_element(const fbx_node *node, uint32_t k)
{
    if (node && node->value_count == 1 && node->values[0].type == FBX_ARRAY && k < node->values[0].count)
        return &node->values[0].a[k];
    return NULL;
}

double fbx_num(const fbx_node *node, uint32_t k)
{
    const double *e = list_element(node, k);
    if (e)
        return *e;
    if (!node || k >= node->value_count)
        return 0.0;
    const fbx_value *v = &node->values[k];
    return v->type == FBX_INT || v->type == FBX_REAL ? v->d : 0.0;
}

int64_t fbx_int(const fbx_node *node, uint32_t k)
{
    const double *e = list_element(node, k);
    if (e)
        return *e > -9.2e18 && *e < 9.2e18 ? (int64_t)*e : 0;
    if (!node || k >= node->value_count)
        return 0;
    const fbx_value *v = &node->values[k];
    return v->type == FBX_INT || v->type == FBX_REAL ? v->i : 0;
}

bool fbx_str_is(const fbx_node *node, uint32_t k, const char *text)
{
    if (!node || k >= node->value_count || node->values[k].type != FBX_STRING)
        return false;
    size_t n = strlen(text);
    return node->values[k].count == n && memcmp(node->values[k].s, text, n) == 0;
}

const double *fbx_values(const fbx_node *c, uint32_t *count)
{
    *count = 0;
    if (!c || c->value_count == 0)
        return NULL;
    if (c->value_count == 1 && (c->values[0].type == FBX_INT || c->values[0].type == FBX_REAL)) {
        *count = 1;
        return &c->values[0].d;
    }
    if (c->values[0].type != FBX_ARRAY)
        return NULL;
    *count = c->values[0].count;
    return c->values[0].a;
}

const double *fbx_array(const fbx_node *node, const char *name, uint32_t *count)
{
    return fbx_values(fbx_child(node, name), count);
}

bool fbx_array_reals(const fbx_node *node, const char *name)
{
    const fbx_node *c = fbx_child(node, name);
    return c && c->value_count == 1 && c->values[0].type == FBX_ARRAY && c->values[0].reals;
}
