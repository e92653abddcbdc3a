/* tl_volume_sign, the exact sign of a closed surface's enclosed volume, on
 * tetrahedra so flat that their volume is lost in the rounding of the sum:
 * integer corners near 2^40 (exact doubles) with the fourth corner within one
 * unit of the plane of the other three, against an __int128 oracle; a
 * coplanar tetrahedron (volume exactly 0), a flat pillow of two triangles
 * back to back, and both orientations of a unit tetrahedron and a cube. */
#include <stdint.h>
#include "talus.h"
#include "tl_predicates.h"
#include "tl_test.h"

typedef struct {
  TlVec3 x[8];
  int tri[12][3];
  size_t n;
} Surface;

static void corners(const void *ctx, size_t t, TlVec3 c[3])
{
  const Surface *s = ctx;
  for (int k = 0; k < 3; ++k) c[k] = s->x[s->tri[t][k]];
}

/* The four faces of tetrahedron (a, b, c, d), outward when
 * det(b - a, c - a, d - a) > 0; flip reverses every face. */
static Surface tetrahedron(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, int flip)
{
  Surface s = {{a, b, c, d}, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}, 4};
  if (flip)
    for (int t = 0; t < 4; ++t) {
      int k = s.tri[t][1];
      s.tri[t][1] = s.tri[t][2], s.tri[t][2] = k;
    }
  return s;
}

static int naive_sign(const Surface *s)
{
  double v = 0.0;
  for (size_t t = 0; t < s->n; ++t) {
    TlVec3 c[3];
    corners(s, t, c);
    v += tl_v3_dot(c[0], tl_v3_cross(c[1], c[2]));
  }
  return (v > 0) - (v < 0);
}

static uint64_t rng(uint64_t *s)
{
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return *s >> 33;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  const TlVec3 o = tl_v3(0, 0, 0), ex = tl_v3(1, 0, 0), ey = tl_v3(0, 1, 0), ez = tl_v3(0, 0, 1);
  Surface s = tetrahedron(o, ex, ey, ez, 0);
  TL_TEST_ASSERT(tl_volume_sign(s.n, corners, &s) == 1, "unit tetrahedron, normals out: sign %d", tl_volume_sign(s.n, corners, &s));
  s = tetrahedron(o, ex, ey, ez, 1);
  TL_TEST_ASSERT(tl_volume_sign(s.n, corners, &s) == -1, "unit tetrahedron inside out: sign %d", tl_volume_sign(s.n, corners, &s));
  s = tetrahedron(o, ex, ey, tl_v3(0.25, 0.25, 0), 0);
  TL_TEST_ASSERT(tl_volume_sign(s.n, corners, &s) == 0, "coplanar tetrahedron: sign %d", tl_volume_sign(s.n, corners, &s));
  s = tetrahedron(o, ex, ey, tl_v3(0.25, 0.25, 0x1p-60), 0);
  TL_TEST_ASSERT(tl_volume_sign(s.n, corners, &s) == 1, "tetrahedron of height 2^-60: sign %d", tl_volume_sign(s.n, corners, &s));
  Surface pillow = {{o, ex, ey}, {{0, 1, 2}, {0, 2, 1}}, 2};
  TL_TEST_ASSERT(tl_volume_sign(pillow.n, corners, &pillow) == 0, "pillow: sign %d", tl_volume_sign(pillow.n, corners, &pillow));
  /* the unit cube at an offset of 1e6, twelve triangles */
  Surface cube = {{{0}}, {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                          {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}}, 12};
  for (int i = 0; i < 8; ++i) cube.x[i] = tl_v3(1e6 + ((i & 1) ^ ((i >> 1) & 1)), 1e6 + ((i >> 1) & 1), 1e6 + (i >> 2));
  TL_TEST_ASSERT(tl_volume_sign(cube.n, corners, &cube) == 1, "offset cube: sign %d", tl_volume_sign(cube.n, corners, &cube));

  /* flat tetrahedra near 2^40 */
  uint64_t seed = 2026;
  int wrong = 0, naive_wrong = 0, zero = 0, trials = 20000;
  const double base = 0x1p40;
  for (int k = 0; k < trials; ++k) {
    int64_t p[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) p[i][j] = (int64_t)(rng(&seed) % (1u << 20));
    /* d = a + (b - a) + (c - a) nudged by -1, 0 or 1 along z: the volume is
     * that nudge times the area's z component */
    int64_t d[3];
    for (int j = 0; j < 3; ++j) d[j] = p[1][j] + p[2][j] - p[0][j];
    d[2] += (int64_t)(rng(&seed) % 3) - 1;
    __int128 u[3], v[3], w[3];
    for (int j = 0; j < 3; ++j) u[j] = p[1][j] - p[0][j], v[j] = p[2][j] - p[0][j], w[j] = d[j] - p[0][j];
    __int128 det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
    const int truth = (det > 0) - (det < 0);
    zero += truth == 0;
    TlVec3 q[4];
    for (int i = 0; i < 3; ++i) q[i] = tl_v3(base + (double)p[i][0], base + (double)p[i][1], base + (double)p[i][2]);
    q[3] = tl_v3(base + (double)d[0], base + (double)d[1], base + (double)d[2]);
    Surface t = tetrahedron(q[0], q[1], q[2], q[3], 0);
    wrong += tl_volume_sign(t.n, corners, &t) != truth;
    naive_wrong += naive_sign(&t) != truth;
  }
  printf("flat tetrahedra near 2^40: %d of %d exactly flat; exact sign wrong on %d, the naive sum on %d\n", zero, trials,
         wrong, naive_wrong);
  TL_TEST_ASSERT(wrong == 0, "tl_volume_sign wrong on %d of %d flat tetrahedra", wrong, trials);
  TL_TEST_ASSERT(naive_wrong > trials / 10, "the naive sum errs on only %d of %d: the cases are not hard", naive_wrong, trials);
  return tl_test_report();
}
