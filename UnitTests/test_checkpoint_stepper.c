/* A time stepper's checkpoint with one value changed is refused on load with
 * a message naming the value (it used to run time backwards or step from a
 * NaN state): a negative time step, a NaN velocity, an infinite time, a
 * negative step count, a non-finite external work.  The unchanged file loads
 * and steps.  The scene: the S1 cantilever (hex8 1 x 4 x 1), Newmark. */
#include <math.h>
#include <string.h>

#include "talus.h"
#include "tl_cantilever.h"
#include "tl_checkpoint.h"
#include "tl_stepper.h"
#include "tl_test.h"
#include "tl_test_h5.h"

typedef struct {
  TlCantilever *beam;
  TlStepper *st;
} Scene;

static TlStatus build(Scene *sc)
{
  TlCantileverParams p;
  tl_cantilever_params_default(&p);
  p.nx = 1, p.ny = 4, p.nz = 1;
  TL_CHECK(tl_cantilever_create(&p, &sc->beam));
  sc->beam->load_scale = 1.0;
  TlStepperOptions o;
  tl_stepper_options_default(&o);
  TL_CHECK(tl_stepper_create("newmark", tl_solid_system(sc->beam->solid), &o, &sc->st));
  TL_CHECK(tl_stepper_set_state(sc->st, 0.0, NULL, NULL));
  return TL_OK;
}

static void destroy(Scene *sc)
{
  tl_stepper_destroy(&sc->st);
  tl_cantilever_destroy(&sc->beam);
}

static TlStatus load(const char *file)
{
  Scene sc = {0};
  TlCheckpoint *cp = NULL;
  TlStatus s = build(&sc);
  if (s == TL_OK) s = tl_checkpoint_create(&cp);
  if (s == TL_OK) s = tl_checkpoint_add(cp, "fem", &tl_stepper_checkpoint_ops, sc.st);
  if (s == TL_OK) s = tl_checkpoint_load(cp, file, NULL, NULL);
  if (s == TL_OK) s = tl_stepper_step(sc.st, 1e-3);
  tl_checkpoint_destroy(&cp);
  destroy(&sc);
  return s;
}

static void refused(const char *dataset, size_t k, double value, int is_int, const char *fragment)
{
  tl_test_h5_refused(load, dataset, k, value, is_int, fragment);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  Scene sc = {0};
  TL_TEST_STATUS(build(&sc), TL_OK);
  if (!sc.st) return tl_test_report();
  for (int k = 0; k < 3; ++k) TL_TEST_STATUS(tl_stepper_step(sc.st, 1e-3), TL_OK);
  TlCheckpoint *cp = NULL;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "fem", &tl_stepper_checkpoint_ops, sc.st), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_save(cp, "good.h5", sc.st->t, 3), TL_OK);
  tl_checkpoint_destroy(&cp);
  destroy(&sc);

  TL_TEST_STATUS(load("good.h5"), TL_OK);
  refused("/fem/dt", 0, -1e-3, 0, "fem/dt = -0.001 outside");
  refused("/fem/v", 2, NAN, 0, "fem/v[2] = nan is not a finite number");
  refused("/fem/t", 0, INFINITY, 0, "fem/t = inf");
  refused("/fem/steps", 0, -1, 1, "fem/steps = -1");
  refused("/fem/external_work", 0, NAN, 0, "fem/external_work[0] = nan");

  /* A flipped byte in stored data: the whole-file checksum refuses it; with
   * that checksum renewed, the dataset's Fletcher32 checksum does. */
  tl_test_copy_file("good.h5", "flipped.h5");
  int flipped = tl_test_flip_stored_byte("flipped.h5", "/fem/u");
  TL_TEST_ASSERT(flipped, "cannot locate the stored data of /fem/u (not chunked?)");
  if (flipped) {
    TlStatus s = load("flipped.h5");
    TL_TEST_ASSERT(s != TL_OK && strstr(tl_error_message(), "flipped.h5' is corrupted"),
                   "a flipped byte: status %d, message '%s'", (int)s, tl_error_message());
    TL_TEST_STATUS(tl_h5_seal("flipped.h5"), TL_OK);
    s = load("flipped.h5");
    TL_TEST_ASSERT(s != TL_OK && strstr(tl_error_message(), "fem/u") && strstr(tl_error_message(), "checksum"),
                   "a flipped byte, resealed: status %d, message '%s'", (int)s, tl_error_message());
  }
  return tl_test_report();
}
