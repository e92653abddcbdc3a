#include "tl_memory.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

TlStatus tl_calloc(void *p, size_t n, size_t size)
{
  void **pp = (void **)p;
  *pp = NULL;
  if (n == 0 || size == 0) return TL_OK;
  if (n > SIZE_MAX / size)
    TL_ERROR(TL_ERR_MEM, "allocation of %zu x %zu bytes overflows", n, size);
  *pp = calloc(n, size);
  if (!*pp) TL_ERROR(TL_ERR_MEM, "cannot allocate %zu bytes", n * size);
  return TL_OK;
}

TlStatus tl_realloc(void *p, size_t n, size_t size)
{
  void **pp = (void **)p;
  if (n == 0 || size == 0) {
    free(*pp);
    *pp = NULL;
    return TL_OK;
  }
  if (n > SIZE_MAX / size)
    TL_ERROR(TL_ERR_MEM, "allocation of %zu x %zu bytes overflows", n, size);
  void *q = realloc(*pp, n * size);
  if (!q) TL_ERROR(TL_ERR_MEM, "cannot allocate %zu bytes", n * size);
  *pp = q;
  return TL_OK;
}

TlStatus tl_strdup(const char *s, char **out)
{
  size_t n = strlen(s);
  TL_CHECK(tl_calloc(out, n + 1, 1));
  memcpy(*out, s, n);
  return TL_OK;
}

void tl_free(void *p)
{
  void **pp = (void **)p;
  free(*pp);
  *pp = NULL;
}

TlStatus tl_array_reserve(void *p, size_t *capacity, size_t need, size_t size)
{
  if (need <= *capacity) return TL_OK;
  size_t cap = *capacity ? *capacity : 16;
  while (cap < need) cap *= 2;
  void **pp = (void **)p;
  size_t old = *capacity;
  TL_CHECK(tl_realloc(pp, cap, size));
  memset((char *)*pp + old * size, 0, (cap - old) * size);
  *capacity = cap;
  return TL_OK;
}
