#include "spectrum_probe.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/base/log.hpp"
#include "lem/base/petsc_handle.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <numeric>
#include <string>
#include <vector>

namespace lem {
namespace {

constexpr int kMaxIterations = 2000;

// Eigenpairs of the symmetric tridiagonal matrix with diagonal d and
// off-diagonal e (e[k] couples k and k+1) by the implicit QL method with
// Wilkinson-like shifts; returns the eigenvalues ascending in d and the
// eigenvectors as the columns of y (y[row * n + column]).
void tridiagonal_eigen(std::vector<double>& d, std::vector<double> e, std::vector<double>& y) {
  const int n = static_cast<int>(d.size());
  y.assign(static_cast<std::size_t>(n) * n, 0.0);
  for (int i = 0; i < n; ++i) y[static_cast<std::size_t>(i) * n + i] = 1.0;
  e.resize(n, 0.0);
  e[n - 1] = 0.0;
  for (int l = 0; l < n; ++l) {
    for (int sweep = 0;; ++sweep) {
      int m = l;
      for (; m < n - 1; ++m)
        if (std::abs(e[m]) <= 1e-15 * (std::abs(d[m]) + std::abs(d[m + 1]))) break;
      if (m == l) break;
      if (sweep > 60) throw NumericalError("spectrum probe: the tridiagonal QL did not converge");
      double g = (d[l + 1] - d[l]) / (2.0 * e[l]);
      double r = std::hypot(g, 1.0);
      g = d[m] - d[l] + e[l] / (g + std::copysign(r, g));
      double s = 1.0, c = 1.0, p = 0.0;
      int i = m - 1;
      for (; i >= l; --i) {
        const double f = s * e[i], b = c * e[i];
        r = std::hypot(f, g);
        e[i + 1] = r;
        if (r == 0.0) {
          d[i + 1] -= p;
          e[m] = 0.0;
          break;
        }
        s = f / r;
        c = g / r;
        g = d[i + 1] - p;
        r = (d[i] - g) * s + 2.0 * c * b;
        p = s * r;
        d[i + 1] = g + p;
        g = c * r - b;
        for (int k = 0; k < n; ++k) {
          double* row = &y[static_cast<std::size_t>(k) * n];
          const double t = row[i + 1];
          row[i + 1] = s * row[i] + c * t;
          row[i] = c * row[i] - s * t;
        }
      }
      if (r == 0.0 && i >= l) continue;
      d[l] -= p;
      e[l] = g;
      e[m] = 0.0;
    }
  }
  // Ascending order, the columns with them.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return d[a] < d[b]; });
  std::vector<double> ds(n), ys(y.size());
  for (int j = 0; j < n; ++j) {
    ds[j] = d[order[j]];
    for (int k = 0; k < n; ++k)
      ys[static_cast<std::size_t>(k) * n + j] = y[static_cast<std::size_t>(k) * n + order[j]];
  }
  d.swap(ds);
  y.swap(ys);
}

// (i, j, k) of every intact bond, on rank 0 (empty elsewhere).
std::vector<double> gather_bonds(const DistributedLattice& l) {
  std::vector<double> mine;  // (i, j, k) per intact bond with an owned first end
  for (int b = 0; b < l.local_bonds(); ++b) {
    const auto [p, q] = l.bond_ends[b];
    if (p >= l.owned || l.bond_stiffness[b] <= 0) continue;
    mine.insert(mine.end(), {static_cast<double>(l.global_index[p]),
                             static_cast<double>(l.global_index[q]), l.bond_stiffness[b]});
  }
  int rank = 0, size = 1;
  MPI_Comm_rank(l.comm, &rank);
  MPI_Comm_size(l.comm, &size);
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(size), offsets(size, 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, l.comm);
  std::partial_sum(counts.begin(), counts.end() - 1, offsets.begin() + 1);
  std::vector<double> all(rank == 0 ? offsets.back() + counts.back() : 0);
  MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE,
              0, l.comm);
  return all;
}

// A text file written whole or not at all: a failed write (a full disk)
// removes what was written and throws.
void write_text(const std::string& path, const std::function<void(FILE*)>& fill) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw IoError("cannot create " + path + ": " + std::strerror(errno));
  fill(f);
  const bool failed = std::ferror(f) != 0;
  const int saved = errno;
  if (std::fclose(f) != 0 || failed) {
    std::remove(path.c_str());
    throw IoError("writing " + path + " failed: " + std::strerror(failed ? saved : errno));
  }
}

// A vector gathered on rank 0 (collective), for a write by rank 0 alone.
VecHandle on_root(Vec v) {
  VecScatter scatter = nullptr;
  VecHandle whole;
  LEM_PETSC(VecScatterCreateToZero(v, &scatter, whole.replace()));
  LEM_PETSC(VecScatterBegin(scatter, v, whole, INSERT_VALUES, SCATTER_FORWARD));
  LEM_PETSC(VecScatterEnd(scatter, v, whole, INSERT_VALUES, SCATTER_FORWARD));
  LEM_PETSC(VecScatterDestroy(&scatter));
  return whole;
}

}  // namespace

void lanczos_eigenpairs(const std::vector<double>& alpha, const std::vector<double>& beta,
                        std::vector<double>& theta, std::vector<double>& y) {
  const int m = static_cast<int>(alpha.size());
  theta.assign(m, 0.0);
  std::vector<double> e(m, 0.0);
  for (int k = 0; k < m; ++k) {
    theta[k] = 1.0 / alpha[k] + (k > 0 ? beta[k - 1] / alpha[k - 1] : 0.0);
    if (k + 1 < m) e[k] = -std::sqrt(beta[k]) / alpha[k];
  }
  if (m > 0) tridiagonal_eigen(theta, e, y);
}

RitzPairs lanczos_ritz(Mat K, PC pc, Vec b, Vec u0, double rtol, int vectors) {
  VecHandle x, r, z, p, q;
  LEM_PETSC(VecDuplicate(b, x.replace()));
  LEM_PETSC(VecCopy(u0, x));
  LEM_PETSC(VecDuplicate(b, r.replace()));
  LEM_PETSC(VecDuplicate(b, z.replace()));
  LEM_PETSC(VecDuplicate(b, p.replace()));
  LEM_PETSC(VecDuplicate(b, q.replace()));
  LEM_PETSC(MatMult(K, x, r));
  LEM_PETSC(VecAYPX(r, -1.0, b));  // r = b - K x
  // The norm of CG's default test: |M^-1 r| / |M^-1 b|.
  RitzPairs out;
  PetscReal bnorm = 0, rnorm = 0;
  LEM_PETSC(PCApply(pc, b, z));
  LEM_PETSC(VecNorm(z, NORM_2, &bnorm));
  LEM_PETSC(PCApply(pc, r, z));
  LEM_PETSC(VecNorm(z, NORM_2, &rnorm));
  out.history.push_back(bnorm > 0 ? rnorm / bnorm : 0.0);
  std::vector<double> alpha, beta, rho;
  std::vector<VecHandle> lanczos;  // v_k = z_k / sqrt(rho_k)
  PetscScalar rz = 0;
  LEM_PETSC(VecDot(r, z, &rz));
  rho.push_back(rz);
  LEM_PETSC(VecCopy(z, p));
  while (out.history.back() > rtol && rz > 0 && static_cast<int>(alpha.size()) < kMaxIterations) {
    lanczos.emplace_back();
    LEM_PETSC(VecDuplicate(z, lanczos.back().replace()));
    LEM_PETSC(VecCopy(z, lanczos.back()));
    LEM_PETSC(VecScale(lanczos.back(), 1.0 / std::sqrt(rho.back())));
    LEM_PETSC(MatMult(K, p, q));
    PetscScalar pq = 0;
    LEM_PETSC(VecDot(p, q, &pq));
    const double a = rho.back() / pq;
    alpha.push_back(a);
    LEM_PETSC(VecAXPY(x, a, p));
    LEM_PETSC(VecAXPY(r, -a, q));
    LEM_PETSC(PCApply(pc, r, z));
    LEM_PETSC(VecNorm(z, NORM_2, &rnorm));
    out.history.push_back(rnorm / bnorm);
    LEM_PETSC(VecDot(r, z, &rz));
    beta.push_back(rz / rho.back());
    rho.push_back(rz);
    LEM_PETSC(VecAYPX(p, beta.back(), z));  // p = z + beta p
  }
  const int m = static_cast<int>(alpha.size());
  if (m == 0) return out;

  std::vector<double> y;
  beta.resize(m - 1);
  lanczos_eigenpairs(alpha, beta, out.theta, y);

  // The slowest Ritz vectors V y (M-orthonormal while the Lanczos vectors
  // stay so).
  const int kept = std::min(vectors, m);
  out.vectors.resize(kept);
  std::vector<PetscScalar> column(m);
  std::vector<Vec> v(m);
  for (int k = 0; k < m; ++k) v[k] = lanczos[k];
  for (int j = 0; j < kept; ++j) {
    LEM_PETSC(VecDuplicate(b, out.vectors[j].replace()));
    LEM_PETSC(VecZeroEntries(out.vectors[j]));
    for (int k = 0; k < m; ++k) column[k] = y[static_cast<std::size_t>(k) * m + j];
    LEM_PETSC(VecMAXPY(out.vectors[j], m, column.data(), v.data()));
  }
  return out;
}

void probe_spectrum(const DistributedLattice& l, Mat K, PC pc, Vec b, Vec u0, double rtol,
                    const std::string& prefix, std::int64_t solve, int vectors) {
  const RitzPairs ritz = lanczos_ritz(K, pc, b, u0, rtol, vectors);
  const std::vector<double>& d = ritz.theta;
  const int m = static_cast<int>(d.size()), kept = static_cast<int>(ritz.vectors.size());
  // Rayleigh quotients x^T K x of the kept vectors: theta again while the
  // Lanczos vectors are still M-orthonormal (a check).
  std::vector<double> quotient(kept);
  VecHandle q;
  LEM_PETSC(VecDuplicate(b, q.replace()));
  for (int j = 0; j < kept; ++j) {
    LEM_PETSC(MatMult(K, ritz.vectors[j], q));
    PetscScalar xkx = 0;
    LEM_PETSC(VecDot(ritz.vectors[j], q, &xkx));
    quotient[j] = xkx;
  }
  const std::vector<double>& history = ritz.history;

  // Everything is gathered on rank 0 first (the collectives), then written
  // by rank 0 alone: a write that fails there (a full disk) leaves no rank
  // waiting, removes the probe's files and the run goes on.
  VecHandle coords;
  LEM_PETSC(VecDuplicate(b, coords.replace()));
  PetscScalar* c = nullptr;
  LEM_PETSC(VecGetArray(coords, &c));
  for (int node = 0; node < l.owned; ++node)
    for (int a = 0; a < 3; ++a) c[3 * node + a] = l.coords[node][a];
  LEM_PETSC(VecRestoreArray(coords, &c));
  std::vector<VecHandle> whole;
  whole.push_back(on_root(coords));
  for (const VecHandle& v : ritz.vectors) whole.push_back(on_root(v));
  const std::vector<double> bonds = gather_bonds(l);

  int rank = 0;
  MPI_Comm_rank(l.comm, &rank);
  const std::string base = prefix + "_" + std::to_string(solve);
  const std::vector<std::string> files = {base + ".txt", base + ".bin", base + ".bin.info",
                                          base + "_bonds.txt"};
  std::string failure;
  if (rank == 0) {
    try {
      write_text(files[0], [&](FILE* f) {
        std::fprintf(f, "# solve %lld, rtol %g, %d iterations\n", static_cast<long long>(solve),
                     rtol, m);
        std::fprintf(f, "# residual: iteration |M^-1 r|/|M^-1 b|\n");
        for (std::size_t k = 0; k < history.size(); ++k)
          std::fprintf(f, "residual %zu %.6e\n", k, history[k]);
        std::fprintf(f, "# ritz: index theta (ascending)  [x^T K x of the kept vectors]\n");
        for (int k = 0; k < m; ++k) {
          if (k < kept)
            std::fprintf(f, "ritz %d %.9e %.9e\n", k, d[k], quotient[k]);
          else
            std::fprintf(f, "ritz %d %.9e\n", k, d[k]);
        }
      });
      // Coordinates in the layout of K, then the kept Ritz vectors.
      PetscViewer viewer = nullptr;
      LEM_PETSC(PetscViewerBinaryOpen(PETSC_COMM_SELF, files[1].c_str(), FILE_MODE_WRITE, &viewer));
      PetscErrorCode written = 0;
      for (const VecHandle& v : whole)
        if (!written) written = VecView(v, viewer);
      if (PetscViewerDestroy(&viewer) || written) throw IoError("writing " + files[1] + " failed");
      write_text(files[3], [&](FILE* f) {
        std::fprintf(f, "# intact bonds: global node i, global node j, stiffness\n");
        for (std::size_t i = 0; i < bonds.size(); i += 3)
          std::fprintf(f, "%.0f %.0f %.17g\n", bonds[i], bonds[i + 1], bonds[i + 2]);
      });
    } catch (const std::exception& e) {
      failure = e.what();
      for (const std::string& file : files) std::remove(file.c_str());
    }
  }
  failure = broadcast_string(l.comm, failure);
  if (!failure.empty()) {
    say("spectrum probe at solve %lld: its files were not written (%s); the run goes on\n",
        static_cast<long long>(solve), failure.c_str());
    return;
  }
  say("spectrum probe at solve %lld: %d iterations, Ritz values %.3e .. %.3e, written to %s.*\n",
      static_cast<long long>(solve), m, m ? d[0] : 0.0, m ? d[m - 1] : 0.0, base.c_str());
}

}  // namespace lem
