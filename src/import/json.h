/* JSON for the library's readers (glTF, muscle files, name maps): jsmn's flat tokenizer (the one
 * cgltf uses), then one pass that turns its tokens into one array of nodes: strings unescaped in
 * place and NUL-terminated, numbers read exactly (Clinger's fast path, else strtod in the C
 * locale), each node knowing how many nodes its subtree holds, so that an object's members and an
 * array's elements are found by stepping over subtrees: no allocation a value, no pointers to chase.
 *
 * Stricter than jsmn alone: a member without a value, a literal other than true, false or null,
 * a number outside RFC 8259's grammar (01, 1., .5, +1, 0x10, inf), more than one top-level value
 * and a control character in a string are refused with the byte offset; in text written by hand
 * (json_parse's by_hand), a comma or colon missing, doubled or out of place too. */
#ifndef SINEW_IMPORT_JSON_H
#define SINEW_IMPORT_JSON_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sinew/model.h"

typedef enum json_type {
    JSON_NULL,
    JSON_FALSE,
    JSON_TRUE,
    JSON_NUMBER,
    JSON_STRING,
    JSON_ARRAY,
    JSON_OBJECT
} json_type;

/* A value. An object's members follow it as key (a string), value, key, value, ...; an array's
 * elements follow it; each child's subtree is `span` nodes long. */
typedef struct json_node {
    uint8_t type;    /* json_type */
    uint32_t span;   /* nodes in its subtree, itself included */
    uint32_t count;  /* an array's elements, an object's members, a string's bytes; 0 otherwise */
    uint32_t offset; /* where it starts in the text (bytes) */
    union {
        double number;
        const char *string; /* unescaped, NUL-terminated (it may hold a NUL of its own: \u0000) */
    };
} json_node;

typedef struct json_doc {
    json_node *root; /* NULL until parsed */
    char *text;      /* the copy the strings point into */
} json_doc;

/* Parses `size` bytes of JSON. SINEW_ERROR_FORMAT with *error_offset (bytes into the text) and
 * `why` when it is not JSON, SINEW_ERROR_OUT_OF_MEMORY, else SINEW_OK. Free with json_free().
 * by_hand: text people write (muscle files, name maps), whose commas and colons are checked too,
 * where jsmn reads [1 2] as [1, 2] and lets [1,,2] and [1,] pass. A program's output (glTF) is
 * left to jsmn, as cgltf leaves it: the check cost 3-5% of a glTF file's import, for files that
 * read as their writer meant. */
sinew_result json_parse(const char *text, size_t size, bool by_hand, json_doc *doc, size_t *error_offset,
                        const char **why);
void json_free(json_doc *doc);
/* json_parse() of text a person writes (by_hand), named `name` in errors: a broken document is
 * SINEW_ERROR_FORMAT "NAME:LINE:COLUMN: not valid JSON here: WHY", no memory "NAME: out of memory". */
sinew_result json_parse_named(const char *text, size_t size, const char *name, json_doc *doc, sinew_error *error);
/* The line and column (each from 1; a column counts bytes) of byte `offset` of `text`. */
void json_line_column(const char *text, size_t offset, int *line, int *column);

/* An object's member by key (the first of that name), NULL when absent or not an object. */
const json_node *json_get(const json_node *object, const char *key);

/* A key for json_pick: JSON_KEY("count") gives its length with it. */
typedef struct json_key {
    const char *name;
    uint32_t length;
} json_key;
#define JSON_KEY(literal)                                                                                              \
    {                                                                                                                  \
        literal, sizeof(literal) - 1                                                                                   \
    }

/* Several members of an object in one pass over it: out[k] is the first member named keys[k],
 * or NULL (all NULL when `object` is not an object). Names are told apart by their lengths
 * first. What an object read whole uses instead of a json_get() a key, each a walk of the
 * members (a glTF accessor has up to nine, and a file thousands of accessors). */
void json_pick(const json_node *object, const json_key *keys, int n, const json_node **out);
/* An array's element i (walks), NULL past the end. */
const json_node *json_item(const json_node *array, int i);
/* The first element (array) or member value (object), and the one after `child`; NULL at the end. */
static inline const json_node *json_first(const json_node *parent)
{
    if (!parent || parent->count == 0)
        return NULL;
    return parent->type == JSON_OBJECT ? parent + 2 : parent->type == JSON_ARRAY ? parent + 1 : NULL;
}
static inline const json_node *json_after(const json_node *parent, const json_node *child)
{
    const json_node *next = child + child->span, *end = parent + parent->span;
    if (parent->type == JSON_OBJECT)
        next++; /* over the key */
    return next < end ? next : NULL;
}
#define JSON_FOR_EACH(value, parent)                                                                                   \
    for ((value) = json_first(parent); (value); (value) = json_after((parent), (value)))

static inline int json_size(const json_node *n)
{
    return n && (n->type == JSON_ARRAY || n->type == JSON_OBJECT) ? (int)n->count : 0;
}
static inline bool json_is_number(const json_node *n)
{
    return n && n->type == JSON_NUMBER;
}
static inline bool json_is_string(const json_node *n)
{
    return n && n->type == JSON_STRING;
}
static inline bool json_is_array(const json_node *n)
{
    return n && n->type == JSON_ARRAY;
}
static inline bool json_is_object(const json_node *n)
{
    return n && n->type == JSON_OBJECT;
}
static inline bool json_is_true(const json_node *n)
{
    return n && n->type == JSON_TRUE;
}

#endif
