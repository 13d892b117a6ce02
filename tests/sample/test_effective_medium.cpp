// Appendix-D estimates: the Hashin-Shtrikman formula against the classical
// bounds and limiting cases.
#include "lem/sample/effective_medium.hpp"

#include <gtest/gtest.h>

using namespace lem;

TEST(HashinShtrikman, OnePhaseIsItself) {
  const Isotropic a = Isotropic::from_young(2.5, 0.23);
  const double f[1] = {1.0};
  const Isotropic r = hashin_shtrikman(f, &a, 1, Isotropic::from_young(7, 0.3));
  EXPECT_NEAR(r.bulk, a.bulk, 1e-12);
  EXPECT_NEAR(r.shear, a.shear, 1e-12);
  EXPECT_NEAR(r.young(), 2.5, 1e-12);
  EXPECT_NEAR(r.poisson(), 0.23, 1e-12);
}

TEST(HashinShtrikman, StiffestReferenceGivesTheUpperBound) {
  // Classical two-phase HS upper bound (phase 1 the stiffer, Hashin &
  // Shtrikman 1963): kappa = k1 + f2 / (1/(k2-k1) + 3 f1/(3 k1 + 4 m1)),
  // mu = m1 + f2 / (1/(m2-m1) + 6 f1 (k1 + 2 m1) / (5 m1 (3 k1 + 4 m1))).
  const Isotropic one = Isotropic::from_young(3, 0.25), two = Isotropic::from_young(1, 0.2);
  for (double f1 : {0.1, 0.5, 0.64}) {
    const double f2 = 1 - f1, k1 = one.bulk, m1 = one.shear, k2 = two.bulk, m2 = two.shear;
    const double f[2] = {f1, f2};
    const Isotropic phases[2] = {one, two};
    const Isotropic r = hashin_shtrikman(f, phases, 2, one);
    EXPECT_NEAR(r.bulk, k1 + f2 / (1 / (k2 - k1) + 3 * f1 / (3 * k1 + 4 * m1)), 1e-12);
    EXPECT_NEAR(r.shear,
                m1 + f2 / (1 / (m2 - m1) + 6 * f1 * (k1 + 2 * m1) / (5 * m1 * (3 * k1 + 4 * m1))),
                1e-12);
    // and lies between the Reuss and Voigt bounds
    EXPECT_LT(r.young(), f1 * 3 + f2 * 1);
    EXPECT_GT(r.young(), 1 / (f1 / 3 + f2 / 1));
  }
}

TEST(AppendixD, LimitsAndOrdering) {
  // No pores, no contacts, particles as stiff as the matrix: homogeneous.
  CompositeFractions f{0.64, 0.36, 0.0, 0.0};
  auto e = appendix_d_estimates(f, 1, 1, 1, 0.23);
  EXPECT_NEAR(e.bare, 1, 1e-12);
  EXPECT_NEAR(e.adhesive, 1, 1e-12);
  // The paper's material: adhesive contacts are stiffer, and both grow with
  // the matrix filling the pores.
  double last_bare = 0, last_adhesive = 0;
  for (double rho_m : {0.06, 0.13, 0.2, 0.28}) {
    f = {0.64, rho_m, 0.36 - rho_m - 0.02, 0.02};
    e = appendix_d_estimates(f, 3, 1, 1, 0.23);
    EXPECT_GT(e.adhesive, e.bare);
    EXPECT_GT(e.bare, last_bare);
    EXPECT_GT(e.adhesive, last_adhesive);
    EXPECT_LT(e.adhesive, 3.0);
    last_bare = e.bare;
    last_adhesive = e.adhesive;
  }
}
