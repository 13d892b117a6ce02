// The Ritz pairs of a CG solve from its own coefficients: what the spectrum
// probe (-solver_spectrum_solves) and the Ritz-vector deflation share.
#pragma once

#include <vector>

namespace lem {

/// Eigenpairs of the Lanczos tridiagonal of CG from its step lengths
/// alpha_0..alpha_{m-1} and ratios beta_1..beta_{m-1} (beta_k = rho_k /
/// rho_{k-1}): the Ritz values ascending in `theta`, the eigenvectors as the
/// columns of `y` (y[row * m + column]).
void lanczos_eigenpairs(const std::vector<double>& alpha, const std::vector<double>& beta,
                        std::vector<double>& theta, std::vector<double>& y);

}  // namespace lem
