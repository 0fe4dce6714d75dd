/* Cross-file internals of sinew's FBX reader (fbx_parse.c reads the document, fbx.c turns
 * it into a raw model). No promise to library users.
 *
 * The document is FBX's own tree: nodes with a name, a list of values and child nodes,
 * the same for binary and ASCII, FBX 5.x to 7.x. Integers (bool, char, int16/32/64) keep
 * their exact value in `i` and an approximate one in `d` (a binary 'C' value keeps its byte:
 * FBX 6.x keys write their interpolation as characters); every array is decoded to doubles
 * (int64 key times up to 2^53 ticks, 54 hours, stay exact). Strings point into the file's
 * bytes, which must outlive the document.
 *
 * FBX before 7.0 writes arrays as plain lists of values (`Vertices: 1,2,3,...` in ASCII, a
 * value each in binary): in a document of such a version a node whose two or more values
 * are all numbers is kept as one array, so fbx_array() reads both forms, and fbx_num() and
 * fbx_int() index into it. A node of one number is an array of one to fbx_array().
 */
#ifndef SINEW_IMPORT_FBX_INTERNAL_H
#define SINEW_IMPORT_FBX_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "internal.h" /* import_arena */
#include "sinew/result.h"

typedef enum fbx_type { FBX_INT = 'I', FBX_REAL = 'D', FBX_STRING = 'S', FBX_ARRAY = 'A' } fbx_type;

/* 24 bytes (48 before the integer, the string and the array shared their place): a document
 * holds tens of thousands, written once into fresh memory (walk.fbx's arena: 4.8 -> 3.7 MB). */
typedef struct fbx_value {
    char type;      /* fbx_type */
    bool reals;     /* FBX_ARRAY from ASCII: some element was written with a '.' or an exponent */
    uint32_t count; /* array elements or string bytes */
    union {
        int64_t i;     /* FBX_INT (FBX_REAL: truncated) */
        const char *s; /* FBX_STRING: not NUL-terminated */
        double *a;     /* FBX_ARRAY */
    };
    double d; /* FBX_INT and FBX_REAL (a node of one number gives it as an array of one) */
} fbx_value;
_Static_assert(sizeof(fbx_value) <= 24, "fbx_value grew");

typedef struct fbx_node {
    const char *name; /* not NUL-terminated */
    uint32_t name_len;
    uint32_t value_count;
    uint32_t child_count;
    fbx_value *values;
    struct fbx_node *children;
} fbx_node;

typedef struct fbx_doc {
    fbx_node root;      /* its children are the top-level nodes */
    import_arena arena; /* every node, value and array of the document */
    uint32_t version;   /* 7400 for FBX 7.4: FBXHeaderExtension's FBXVersion, else the binary header's */
    bool binary;
} fbx_doc;

/* True when the bytes start like an FBX file (binary magic, or ASCII FBX's comment header
 * or top-level node names). */
bool fbx_sniff(const unsigned char *bytes, size_t size);

/* Parses a whole FBX file. Every record, array and string is checked against the bytes;
 * decoded arrays and the tree together may not exceed a budget proportional to the file
 * size. Errors name `path` and the place (byte offset or line). */
sinew_result fbx_parse(const unsigned char *bytes, size_t size, const char *path, fbx_doc *doc, sinew_error *error);
void fbx_doc_free(fbx_doc *doc);

/* First child named `name`, or NULL. */
const fbx_node *fbx_child(const fbx_node *node, const char *name);
bool fbx_named(const fbx_node *node, const char *name);
/* Value `k` as a number / integer / string (0 / 0 / "" when absent or of another type); of
 * a node kept as one array, its element `k`. */
double fbx_num(const fbx_node *node, uint32_t k);
int64_t fbx_int(const fbx_node *node, uint32_t k);
bool fbx_str_is(const fbx_node *node, uint32_t k, const char *text);
/* The array of the first child named `name` (its first value, or its one number), with its
 * length; NULL and 0 when it has none. */
const double *fbx_array(const fbx_node *node, const char *name, uint32_t *count);
/* The same of a node itself. */
const double *fbx_values(const fbx_node *node, uint32_t *count);
/* Whether the array of the first child named `name` came from ASCII text with reals in it. */
bool fbx_array_reals(const fbx_node *node, const char *name);

#endif
