/* Allocation that reports failure through the status mechanism. */
#ifndef TL_MEMORY_H
#define TL_MEMORY_H

#include <stddef.h>
#include "tl_error.h"

/* *p = zeroed array of n elements of size bytes; error names what failed. */
TlStatus tl_calloc(void *p, size_t n, size_t size);
/* Resizes *p to n elements of size bytes, keeping the contents. */
TlStatus tl_realloc(void *p, size_t n, size_t size);
/* *out = a newly allocated copy of the string s. */
TlStatus tl_strdup(const char *s, char **out);
/* Frees *p and sets it to NULL. */
void tl_free(void *p);

/* Grows a dynamic array so that it holds at least `need` elements; capacity
 * doubles, so repeated pushes cost O(1) amortised and no allocation happens
 * once the array has reached its working size. */
TlStatus tl_array_reserve(void *p, size_t *capacity, size_t need, size_t size);

#define TL_NEW(ptr) tl_calloc(&(ptr), 1, sizeof *(ptr))

#endif
