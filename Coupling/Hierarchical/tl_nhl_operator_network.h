/* What the contact-network operators share (tl_nhl_operator_network.c):
 * the linearised contacts of a cell and the helpers that gather them, apply
 * one contact's linearisation and turn a stress increment into operator
 * entries.  PSTLO (tl_nhl_operator_pstlo.c) solves over the same network. */
#ifndef TL_NHL_OPERATOR_NETWORK_H
#define TL_NHL_OPERATOR_NETWORK_H

#include "tl_nhl_operator.h"

typedef struct {
  size_t i, j;
  TlVec3 n, b, f, ft;
  double l, ai, aj, fn, kn, kt;
  int sliding, lever_fixed;
} NetContact;

typedef struct {
  NetContact *c;
  size_t n, cap;
  TlDem *dem;
  TlStatus status;
  double V;
  int dim;
} Net;

/* The cell's contacts with their stiffnesses; N->c freed with tl_free. */
TlStatus tl_nhl_net_gather(const TlNhlOperatorInput *in, Net *N);
void tl_nhl_net_contact_linear(const NetContact *c, const double y[9], int springs, int geo, double out[9]);
void tl_nhl_net_add_stress(const NetContact *c, const double y[9], const double out[9], TlMat3 *ds);
TlMat3 tl_nhl_net_unit_G(int k, int l);
void tl_nhl_net_finish(double c[81], int k, int l, TlMat3 ds, double V, TlMat3 sigma, TlMat3 G);

extern const TlNhlOperatorOps tl_nhl_pstlo_ops;

#endif
