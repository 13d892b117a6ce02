#include "lem/sample/effective_medium.hpp"

#include "lem/base/error.hpp"

#include <cmath>

namespace lem {

Isotropic Isotropic::from_young(double young, double poisson) {
  return {young / (3 * (1 - 2 * poisson)), young / (2 * (1 + poisson))};
}

double Isotropic::young() const {
  const double d = 3 * bulk + shear;
  return d > 0 ? 9 * bulk * shear / d : 0.0;
}

double Isotropic::poisson() const { return (3 * bulk - 2 * shear) / (2 * (3 * bulk + shear)); }

Isotropic hashin_shtrikman(const double* fraction, const Isotropic* phase, int phases,
                           const Isotropic& reference) {
  const double k0 = reference.bulk, m0 = reference.shear;
  if (!(k0 > 0 && m0 > 0))
    throw NumericalError("Hashin-Shtrikman estimate: reference medium has no stiffness");
  const double k_star = 4 * m0 / 3;
  const double m_star = m0 * (9 * k0 + 8 * m0) / (6 * (k0 + 2 * m0));
  // (C_eff + C*)^-1 = sum_r f_r (C_r + C*)^-1, separately on the spherical
  // (J) and deviatoric (K) parts of isotropic tensors.
  double j = 0, k = 0;
  for (int r = 0; r < phases; ++r) {
    j += fraction[r] / (phase[r].bulk + k_star);
    k += fraction[r] / (phase[r].shear + m_star);
  }
  return {1 / j - k_star, 1 / k - m_star};
}

CompositeEstimate appendix_d_estimates(const CompositeFractions& f, double young_p, double young_m,
                                       double young_pm, double poisson) {
  const Isotropic p = Isotropic::from_young(young_p, poisson);
  const Isotropic m = Isotropic::from_young(young_m, poisson);
  const double interphase = f.matrix + f.contact;
  // Voigt mix of matrix and particle-particle interface (first transition).
  auto voigt = [&](const Isotropic& contact) {
    return Isotropic{(f.matrix * m.bulk + f.contact * contact.bulk) / interphase,
                     (f.matrix * m.shear + f.contact * contact.shear) / interphase};
  };
  // The interphase fills what particles and pores leave.
  const double fractions[3] = {f.particle, 1 - f.particle - f.void_, f.void_};
  CompositeEstimate e;
  const Isotropic bare_iph = voigt(Isotropic{0, 0});
  const Isotropic bare[3] = {p, bare_iph, Isotropic{0, 0}};
  e.bare = hashin_shtrikman(fractions, bare, 3, bare_iph).young();
  const Isotropic adhesive_iph = voigt(Isotropic::from_young(young_pm, poisson));
  const Isotropic adhesive[3] = {p, adhesive_iph, Isotropic{0, 0}};
  e.adhesive = hashin_shtrikman(fractions, adhesive, 3, p).young();
  return e;
}

}  // namespace lem
