/* Every allocation of sinew's readers and builder goes through the import's own accounting
 * (alloc.c): include this header last in a reader's source file, after every other include, and
 * malloc, calloc, realloc, strdup and free there become the import_* functions below.
 *
 * An import running on this thread (import_alloc_begin() .. import_alloc_end()) counts the bytes
 * its readers hold (malloc_usable_size, so memory freed by plain free() elsewhere, or given by a
 * caller's read_file callback, mixes safely), refuses an allocation past its byte limit, and can
 * be told to fail its k-th allocation (the allocation-failure sweep of the tests, as ufbx's
 * runner does). Outside an import these are malloc and friends. What libxml2 and Assimp allocate
 * themselves is not counted. When the sweep finds a failure, build alloc.c with
 * -DSINEW_ALLOC_TRACE -rdynamic: the failed allocation prints its call stack on stderr. */
#ifndef SINEW_IMPORT_ALLOC_H
#define SINEW_IMPORT_ALLOC_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void *import_malloc(size_t size);
void *import_calloc(size_t count, size_t size);
void *import_realloc(void *ptr, size_t size);
char *import_strdup(const char *text);
void import_free(void *ptr);

#define malloc(n) import_malloc(n)
#define calloc(n, s) import_calloc(n, s)
#define realloc(p, n) import_realloc(p, n)
#define strdup(t) import_strdup(t)
#define free(p) import_free(p)

#endif
