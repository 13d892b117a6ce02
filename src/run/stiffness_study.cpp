#include "lem/run/stiffness_study.hpp"

#include <functional>
#include <sstream>

#include "lem/base/driver.hpp"
#include "lem/sample/effective_medium.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/base/line_fit.hpp"
#include "lem/base/log.hpp"
#include "lem/base/options.hpp"
#include "lem/setup/setup.hpp"
#include "lem/base/summary.hpp"

namespace lem {

namespace {

struct Elastic {
  double young = 0, poisson = 0;
  int iterations = 0;
};

// Uniaxial tension of the lattice `make()` builds on rank 0.
Elastic pull(MPI_Comm comm, const SolverOptions& solver, bool halved_faces,
             const std::function<Lattice()>& make) {
  SetupReport setup;
  auto lattice = setup_tension_lattice(
      comm,
      [&](SampleInfo& info) {
        Lattice l = make();
        info.stats = lattice_stats(l);
        if (halved_faces) halve_face_bonds(l);
        return l;
      },
      setup);
  ElasticSystem system(lattice, solver);
  check_unused_options(SolverStage::created);
  system.assemble();
  const auto solve = system.solve(3e-4 * lattice.mean_bond_length);
  const auto response = system.response();
  return {response.young_modulus, response.poisson_ratio, solve.iterations};
}

std::string fit_row(const char* name, const LineFit& f) {
  std::ostringstream s;
  s.precision(8);
  s << name << "," << f.intercept << "," << f.slope << "," << f.max_residual << "\n";
  return s.str();
}

}  // namespace

void run_stiffness_study(MPI_Comm comm, StiffnessStudy study, const SolverOptions& solver,
                         const Provenance& provenance) {
  const CementedSampleSpec& spec = study.spec;
  const PhaseTable& table = study.table;
  const std::vector<double>& fractions = study.fractions;
  const bool halved_faces = study.halved_faces;
  ResultFolder::Request& request = study.request;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);

  // The granular sample lives on rank 0; the other ranks only solve.
  CementedSample sample;
  run_on_root(comm, [&] {
    sample = build_granular_sample(spec);
    const auto& st = sample.stats;
    say("sample: %lld particles (%lld spheres), side %.4g, %lld nodes, %lld "
        "bonds, "
        "%.0f nodes per particle; packing %.1f s, lattice %.1f s, Voronoi %.1f "
        "s\n",
        (long long)st.sample_particles, (long long)st.particles, st.side, (long long)st.nodes,
        (long long)st.bonds, st.nodes_per_particle, st.packing_seconds, st.lattice_seconds,
        st.voronoi_seconds);
  });

  // E^[phi] = c E^phi: a homogeneous lattice of bonds k = a (E = 1).
  const Elastic unit = pull(comm, solver, halved_faces, [&] {
    Lattice l = sample.lattice;
    const double a = lattice_stats(l).mean_length;
    l.stiffness.assign(l.bond_count(), a);
    return l;
  });
  check_unused_options();
  // Only once the sample and the solver options proved good: bad input
  // keeps older results.
  request.fingerprint = options_fingerprint(comm);
  const ResultFolder folder(comm, stiffness_layout(), request);
  if (!folder.begin()) return;
  const std::string& dir = folder.work_dir();
  auto lattice_modulus = [&](Phase p) { return unit.young * table.modulus[int(p)]; };
  const double Ep = lattice_modulus(Phase::p), Em = lattice_modulus(Phase::m),
               Epm = lattice_modulus(Phase::pm);
  say("homogeneous lattice: E = %.5f E^phi, nu = %.4f -> E^[p] = %.4f, E^[m] = "
      "%.4f, "
      "E^[pm] = %.4f (units k/a)\n",
      unit.young, unit.poisson, Ep, Em, Epm);

  std::ostringstream csv;
  csv.precision(8);
  // E_eff/E^[p] against rho^m (paper figs. 5, 11; appendix D); E^[p],
  // E^[m] and the lattice nu are in summary.json.
  csv << "rho_m_requested,rho_m,rho_p,rho_v,rho_pp,S_pm,bridges_per_particle,"
         "eligible_per_particle,bonds_p,bonds_m,bonds_v,bonds_pp,bonds_pm,"
         "E_bare,E_adhesive,HS_bare,HS_adhesive,nu_bare,nu_adhesive,its_bare,"
         "its_adhesive\n";
  std::vector<double> rho, bare, adhesive, coverage;
  say("%6s %7s %7s %7s %7s %7s %7s %8s %6s\n", "rho_m", "lattice", "E_bare", "HS_bare", "E_adh",
      "HS_adh", "S_pm", "bridges", "time");
  for (double fraction : fractions) {
    const double t0 = MPI_Wtime();
    PhaseTable bare_table = table, adhesive_table = table;
    bare_table.modulus[int(Phase::pp)] = 0;
    adhesive_table.modulus[int(Phase::pp)] = table.modulus[int(Phase::pm)];
    BridgeSpec bridges = spec.bridges;
    bridges.matrix_fraction = fraction;
    const Elastic b = pull(comm, solver, halved_faces, [&] {
      add_matrix(sample, bridges);
      return mechanical_lattice(sample, bare_table);
    });
    const Elastic a = pull(comm, solver, halved_faces,
                           [&] { return mechanical_lattice(sample, adhesive_table); });
    if (rank != 0) continue;  // the statistics are on rank 0
    const auto& st = sample.stats;
    const double rho_pp = st.bond_volume_fraction[int(Phase::pp)];
    const auto hs =
        appendix_d_estimates({st.rho_p, st.rho_m, st.rho_v, rho_pp}, Ep, Em, Epm, unit.poisson);
    rho.push_back(st.rho_m);
    bare.push_back(b.young / Ep);
    adhesive.push_back(a.young / Ep);
    coverage.push_back(st.interface_ratio);
    csv << fraction << "," << st.rho_m << "," << st.rho_p << "," << st.rho_v << "," << rho_pp << ","
        << st.interface_ratio << "," << st.bridges_per_particle << "," << st.eligible_per_particle;
    for (auto n : st.bonds_per_phase) csv << "," << n;
    csv << "," << bare.back() << "," << adhesive.back() << "," << hs.bare / Ep << ","
        << hs.adhesive / Ep << "," << b.poisson << "," << a.poisson << "," << b.iterations << ","
        << a.iterations << "\n";
    say("%6.3f %7.4f %7.4f %7.4f %7.4f %7.4f %7.4f %8.2f %5.1fs\n", fraction, st.rho_m, bare.back(),
        hs.bare / Ep, adhesive.back(), hs.adhesive / Ep, st.interface_ratio,
        st.bridges_per_particle, MPI_Wtime() - t0);
  }
  Summary summary;
  if (rank == 0) {
    const auto fb = fit_line(rho, bare), fa = fit_line(rho, adhesive), fs = fit_line(rho, coverage);
    say("linear fits against rho^m (intercept, slope, largest residual):\n"
        "  E_bare/E^[p]     %.4f %+.4f  %.1e\n  E_adhesive/E^[p] %.4f %+.4f  "
        "%.1e\n"
        "  S^pm/S^p         %.4f %+.4f  %.1e\n",
        fb.intercept, fb.slope, fb.max_residual, fa.intercept, fa.slope, fa.max_residual,
        fs.intercept, fs.slope, fs.max_residual);
    say("at rho^m = %.3f: E_eff/E^[m] = %.3f bare, %.3f adhesive (paper at "
        "0.28: 1.6, 2.5)\n",
        rho.back(), bare.back() * Ep / Em, adhesive.back() * Ep / Em);
    summary.add("E_p_lattice", Ep);
    summary.add("E_m_lattice", Em);
    summary.add("lattice_poisson", unit.poisson);
    summary.add("face_bonds", halved_faces ? "halved" : "whole");
    summary.add("bare_intercept", fb.intercept);
    summary.add("bare_slope", fb.slope);
    summary.add("adhesive_intercept", fa.intercept);
    summary.add("adhesive_slope", fa.slope);
    summary.add("coverage_intercept", fs.intercept);
    summary.add("coverage_slope", fs.slope);
    summary.add("bare_over_Em_at_highest", bare.back() * Ep / Em);
    summary.add("adhesive_over_Em_at_highest", adhesive.back() * Ep / Em);
    summary.add_provenance(provenance);
    write_text_file_atomically(dir + "/fits.csv", "quantity,intercept,slope,max_residual\n" +
                                                      fit_row("E_bare_over_Ep", fb) +
                                                      fit_row("E_adhesive_over_Ep", fa) +
                                                      fit_row("S_pm_over_S_p", fs));
    write_text_file_atomically(dir + "/stiffness.csv", csv.str());
  }
  folder.commit(summary, {});
  folder.install();
  say("plot: /usr/bin/python3 tools/plot_stiffness.py %s\n", request.dir.c_str());
}

}  // namespace lem
