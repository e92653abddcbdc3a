/* Particle snapshots: HDF5 round trip compared exactly, optional arrays,
 * extra fields, the XDMF series listing every step, empty sets, bad input,
 * and a restart (writer checkpoint) that continues the same series. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "talus.h"
#include "tl_io.h"
#include "tl_test.h"

enum { N = 97 };

static TlVec3 pos[N], vel[N], omega[N], force[N];
static double radius[N], stress[6 * N], overlap[N];
static int species[N];

static double lcg(unsigned long *s)
{
  *s = *s * 6364136223846793005UL + 1442695040888963407UL;
  return ((double)(*s >> 11) / 9007199254740992.0 - 0.5) * 1e3;
}

static void fill(unsigned long seed)
{
  for (int i = 0; i < N; ++i) {
    pos[i] = tl_v3(lcg(&seed), lcg(&seed), lcg(&seed) * 1e-300);
    vel[i] = tl_v3(lcg(&seed), -0.0, 1.0 / 3.0);
    omega[i] = tl_v3(lcg(&seed), lcg(&seed), lcg(&seed));
    force[i] = tl_v3(lcg(&seed) * 1e200, lcg(&seed), 5e-324);
    radius[i] = 1e-3 * (1.0 + 0.1 * i);
    species[i] = i % 3 - 1;
    overlap[i] = lcg(&seed);
    for (int k = 0; k < 6; ++k) stress[6 * i + k] = lcg(&seed);
  }
}

static TlParticleView full_view(const TlField *fields)
{
  return (TlParticleView){.n = N, .position = pos, .radius = radius, .velocity = vel, .angular_velocity = omega,
                          .force = force, .species = species, .n_fields = 2, .fields = fields};
}

static void test_round_trip(void)
{
  TlField fields[2] = {{"overlap", 1, overlap}, {"stress", 6, stress}};
  TlParticleWriter *w;
  TL_TEST_STATUS(tl_particle_writer_create("out/sub", "grains", &w), TL_OK);
  if (!w) return;
  for (int k = 0; k < 3; ++k) {
    fill(100 + k);
    TlParticleView v = full_view(fields);
    TL_TEST_STATUS(tl_particle_writer_write(w, 1000 * k, 0.5 * k + 0.1, &v), TL_OK);
  }
  TL_TEST_ASSERT(tl_particle_writer_count(w) == 3, "count %zu", tl_particle_writer_count(w));
  TL_TEST_ASSERT(strcmp(tl_particle_writer_last_path(w), "out/sub/grains_000002.h5") == 0, "last path %s",
                 tl_particle_writer_last_path(w));

  /* the last snapshot holds exactly what was written */
  TlParticleSnapshot s;
  TL_TEST_STATUS(tl_particle_snapshot_read("out/sub/grains_000002.h5", &s), TL_OK);
  TL_TEST_ASSERT(s.n == N, "n %zu", s.n);
  TL_TEST_ASSERT(s.time == 0.5 * 2 + 0.1 && s.step == 2000, "time %.17g step %lld", s.time, (long long)s.step);
  if (s.n == N) {
    TL_TEST_ASSERT(memcmp(s.position, pos, sizeof pos) == 0, "positions differ");
    TL_TEST_ASSERT(memcmp(s.velocity, vel, sizeof vel) == 0, "velocities differ");
    TL_TEST_ASSERT(memcmp(s.angular_velocity, omega, sizeof omega) == 0, "angular velocities differ");
    TL_TEST_ASSERT(memcmp(s.force, force, sizeof force) == 0, "forces differ");
    TL_TEST_ASSERT(memcmp(s.radius, radius, sizeof radius) == 0, "radii differ");
    TL_TEST_ASSERT(memcmp(s.species, species, sizeof species) == 0, "species differ");
    TL_TEST_ASSERT(s.torque == NULL, "torque was not written, must read back as NULL");
    TL_TEST_ASSERT(s.n_fields == 2, "%zu fields", s.n_fields);
    if (s.n_fields == 2) {
      TL_TEST_ASSERT(strcmp(s.field_names[0], "overlap") == 0 && s.field_components[0] == 1, "field 0");
      TL_TEST_ASSERT(strcmp(s.field_names[1], "stress") == 0 && s.field_components[1] == 6, "field 1");
      TL_TEST_ASSERT(memcmp(s.field_data[0], overlap, sizeof overlap) == 0, "overlap differs");
      TL_TEST_ASSERT(memcmp(s.field_data[1], stress, sizeof stress) == 0, "stress differs");
    }
  }
  tl_particle_snapshot_free(&s);
  TL_TEST_ASSERT(s.position == NULL, "free must clear");

  /* the first file still holds the first step */
  TL_TEST_STATUS(tl_particle_snapshot_read("out/sub/grains_000000.h5", &s), TL_OK);
  TL_TEST_ASSERT(s.step == 0 && s.time == 0.1, "first file step %lld time %g", (long long)s.step, s.time);
  tl_particle_snapshot_free(&s);

  /* the series lists all three steps with their times and relative file names */
  char *xmf = tl_test_read_file("out/sub/grains.xmf");
  TL_TEST_ASSERT(xmf != NULL, "no grains.xmf");
  if (xmf) {
    TL_TEST_ASSERT(tl_test_count(xmf, "<Grid Name=\"step_") == 3, "%d step grids", tl_test_count(xmf, "<Grid Name=\"step_"));
    TL_TEST_ASSERT(strstr(xmf, "CollectionType=\"Temporal\"") != NULL, "not a temporal collection");
    TL_TEST_ASSERT(strstr(xmf, "<Time Value=\"1.1000000000000001\"/>") != NULL, "time of step 2 missing");
    TL_TEST_ASSERT(strstr(xmf, ">grains_000001.h5:/particles/position<") != NULL, "relative file reference missing");
    TL_TEST_ASSERT(tl_test_count(xmf, "TopologyType=\"Polyvertex\" NumberOfElements=\"97\"") == 3, "topology");
    TL_TEST_ASSERT(tl_test_count(xmf, "<Attribute Name=\"radius\" AttributeType=\"Scalar\" Center=\"Node\">") == 3, "radius");
    TL_TEST_ASSERT(tl_test_count(xmf, "<Attribute Name=\"stress\" AttributeType=\"Tensor6\"") == 3, "stress attribute");
    TL_TEST_ASSERT(tl_test_count(xmf, "Name=\"torque\"") == 0, "torque listed though absent");
  }
  free(xmf);
  TL_TEST_ASSERT(access("out/sub/grains_000003.h5", F_OK) != 0, "a fourth file exists");
  tl_particle_writer_destroy(&w);
  TL_TEST_ASSERT(w == NULL, "destroy must null");
}

static void test_minimal_and_errors(void)
{
  TlParticleWriter *w;
  TL_TEST_STATUS(tl_particle_writer_create("", "bare", &w), TL_OK);
  if (!w) return;
  TlParticleView v = {.n = N, .position = pos, .radius = radius};
  TL_TEST_STATUS(tl_particle_writer_write(w, 7, 0.0, &v), TL_OK);
  TlParticleView empty = {.n = 0};
  TL_TEST_STATUS(tl_particle_writer_write(w, 8, 1.0, &empty), TL_OK);
  TlParticleSnapshot s;
  TL_TEST_STATUS(tl_particle_snapshot_read("bare_000000.h5", &s), TL_OK);
  TL_TEST_ASSERT(s.n == N && !s.velocity && !s.force && !s.species && s.n_fields == 0, "optional arrays present");
  tl_particle_snapshot_free(&s);
  TL_TEST_STATUS(tl_particle_snapshot_read("bare_000001.h5", &s), TL_OK);
  TL_TEST_ASSERT(s.n == 0 && s.time == 1.0, "empty snapshot n %zu", s.n);
  tl_particle_snapshot_free(&s);

  /* bad input is refused before anything is written */
  TlParticleView no_radius = {.n = N, .position = pos};
  TL_TEST_STATUS(tl_particle_writer_write(w, 9, 2.0, &no_radius), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "radius") != NULL, "message: %s", tl_error_message());
  TlField reserved = {"velocity", 3, overlap};
  TlParticleView bad_field = {.n = N, .position = pos, .radius = radius, .n_fields = 1, .fields = &reserved};
  TL_TEST_STATUS(tl_particle_writer_write(w, 9, 2.0, &bad_field), TL_ERR_ARG);
  TlField zero = {"x", 0, overlap};
  bad_field.fields = &zero;
  TL_TEST_STATUS(tl_particle_writer_write(w, 9, 2.0, &bad_field), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "0 components") != NULL, "message: %s", tl_error_message());
  TlField spaced = {"a b", 1, overlap};
  bad_field.fields = &spaced;
  TL_TEST_STATUS(tl_particle_writer_write(w, 9, 2.0, &bad_field), TL_ERR_ARG);
  TL_TEST_ASSERT(tl_particle_writer_count(w) == 2, "count %zu after refused writes", tl_particle_writer_count(w));
  TL_TEST_ASSERT(access("bare_000002.h5", F_OK) != 0, "a refused write left a file");
  tl_particle_writer_destroy(&w);

  TL_TEST_STATUS(tl_particle_writer_create("", "a/b", &w), TL_ERR_ARG);
  TL_TEST_STATUS(tl_particle_snapshot_read("missing.h5", &s), TL_ERR_IO);
  /* a checkpoint file is not a particle snapshot */
  TlCheckpointWriter *cw;
  TL_TEST_STATUS(tl_checkpoint_writer_open("ck.h5", &cw), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_writer_commit(&cw), TL_OK);
  TL_TEST_STATUS(tl_particle_snapshot_read("ck.h5", &s), TL_ERR_NOT_FOUND);
}

/* A run interrupted after two snapshots and restarted from a checkpoint
 * writes the same third file name and the same series as an uninterrupted run. */
static void test_restart(void)
{
  TlParticleView v = {.n = N, .position = pos, .radius = radius};
  TlParticleWriter *a;
  TL_TEST_STATUS(tl_particle_writer_create("straight", "p", &a), TL_OK);
  if (!a) return;
  TL_TEST_STATUS(tl_particle_writer_write(a, 0, 0.0, &v), TL_OK);
  TL_TEST_STATUS(tl_particle_writer_write(a, 1, 0.25, &v), TL_OK);
  TL_TEST_STATUS(tl_particle_writer_write(a, 2, 0.5, &v), TL_OK);
  char *expected = tl_test_read_file("straight/p.xmf");

  TlParticleWriter *b;
  TL_TEST_STATUS(tl_particle_writer_create("restarted", "p", &b), TL_OK);
  TL_TEST_STATUS(tl_particle_writer_write(b, 0, 0.0, &v), TL_OK);
  TL_TEST_STATUS(tl_particle_writer_write(b, 1, 0.25, &v), TL_OK);
  TlCheckpoint *cp;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "particle_output", &tl_particle_writer_checkpoint_ops, b), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_save(cp, "restart.h5", 0.25, 1), TL_OK);
  tl_checkpoint_destroy(&cp);
  TL_TEST_STATUS(tl_particle_writer_write(b, 2, 0.5, &v), TL_OK); /* lost with the crash */
  tl_particle_writer_destroy(&b);

  TlParticleWriter *c;
  TL_TEST_STATUS(tl_particle_writer_create("restarted", "p", &c), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "particle_output", &tl_particle_writer_checkpoint_ops, c), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_load(cp, "restart.h5", NULL, NULL), TL_OK);
  TL_TEST_ASSERT(tl_particle_writer_count(c) == 2, "restored count %zu", tl_particle_writer_count(c));
  TL_TEST_STATUS(tl_particle_writer_write(c, 2, 0.5, &v), TL_OK);
  char *got = tl_test_read_file("restarted/p.xmf");
  TL_TEST_ASSERT(expected && got && strcmp(expected, got) == 0, "restarted series differs from the straight one");
  free(expected);
  free(got);
  tl_checkpoint_destroy(&cp);
  tl_particle_writer_destroy(&a);
  tl_particle_writer_destroy(&c);
}

int main(void)
{
  test_round_trip();
  test_minimal_and_errors();
  test_restart();
  return tl_test_report();
}
