// Hashin-Shtrikman-type estimates of the effective Young's modulus of a
// porous cemented granular composite (Affes et al. 2012, appendix D).
//
// Two scale transitions: (1) an "interphase" made of the matrix (with the
// particle-matrix interface counted in it) and the particle-particle
// interface, mixed by the Voigt bound; (2) a three-phase composite of
// spherical particles, spherical pores and that interphase, randomly
// distributed, estimated with the Hashin-Shtrikman formula (D.1) for a
// reference medium C^0.  Every phase is isotropic.
#pragma once

namespace lem {

/// Isotropic elastic moduli: bulk kappa and shear mu.
struct Isotropic {
  double bulk = 0, shear = 0;
  static Isotropic from_young(double young, double poisson);
  double young() const;    // 9 kappa mu / (3 kappa + mu)
  double poisson() const;  // (3 kappa - 2 mu) / (2 (3 kappa + mu))
};

/// Hashin-Shtrikman estimate (D.1) for phases of volume fractions `fraction`
/// (summing to 1) and moduli `phase`, around the reference medium `reference`.
/// The influence tensor is Hill's for a spherical inclusion in C^0:
///   C* = 3 kappa* J + 2 mu* K,  kappa* = 4 mu0 / 3,
///   mu* = mu0 (9 kappa0 + 8 mu0) / (6 (kappa0 + 2 mu0)).
/// (The printed K coefficient of the paper has kappa0 + mu0 in the
/// denominator, a misprint: with kappa0 + 2 mu0 the estimate reduces to the
/// Hashin-Shtrikman bounds when C^0 is the stiffest or softest phase.)
Isotropic hashin_shtrikman(const double* fraction, const Isotropic* phase, int phases,
                           const Isotropic& reference);

/// Volume fractions of the cemented composite (each on the lattice).
struct CompositeFractions {
  double particle = 0, matrix = 0, void_ = 0, contact = 0;  // p, m (+pm), v, pp
};

/// Appendix-D estimates of E_eff: bare contacts (C^pp = 0, C^0 = C^iph) and
/// adhesive contacts (C^pp = C^pm, C^0 = C^p).  The phase moduli are those of
/// homogeneous lattices (E^[phi]); all phases share the lattice's Poisson ratio.
struct CompositeEstimate {
  double bare = 0, adhesive = 0;
};
CompositeEstimate appendix_d_estimates(const CompositeFractions& f, double young_p, double young_m,
                                       double young_pm, double poisson);

}  // namespace lem
