#include "lem/solver/levers.hpp"
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
#include "lem/run/programs.hpp"
#include "lem/setup/sample_options.hpp"

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

// The packing and lattice of the study, on rank 0 (the other ranks only solve).
CementedSample granular_sample(MPI_Comm comm, const CementedSampleSpec& spec) {
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
  return sample;
}

// stiffness.csv and the series the fits are made of (rank 0).
struct StiffnessTable {
  std::ostringstream csv;
  std::vector<double> rho, bare, adhesive, coverage;
};

// Pull the sample at every fraction, bare and adhesive; rows on rank 0.
void pull_fractions(MPI_Comm comm, const StiffnessStudy& study, const SolverOptions& solver,
                    CementedSample& sample, const Elastic& unit, StiffnessTable& t) {
  const PhaseTable& table = study.table;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const double Ep = unit.young * table.modulus[int(Phase::p)],
               Em = unit.young * table.modulus[int(Phase::m)],
               Epm = unit.young * table.modulus[int(Phase::pm)];
  t.csv.precision(8);
  // E_eff/E^[p] against rho^m (paper figs. 5, 11; appendix D); E^[p],
  // E^[m] and the lattice nu are in summary.json.
  t.csv << "rho_m_requested,rho_m,rho_p,rho_v,rho_pp,S_pm,bridges_per_particle,"
           "eligible_per_particle,bonds_p,bonds_m,bonds_v,bonds_pp,bonds_pm,"
           "E_bare,E_adhesive,HS_bare,HS_adhesive,nu_bare,nu_adhesive,its_bare,"
           "its_adhesive\n";
  say("%6s %7s %7s %7s %7s %7s %7s %8s %6s\n", "rho_m", "lattice", "E_bare", "HS_bare", "E_adh",
      "HS_adh", "S_pm", "bridges", "time");
  for (double fraction : study.fractions) {
    const double t0 = MPI_Wtime();
    PhaseTable bare_table = table, adhesive_table = table;
    bare_table.modulus[int(Phase::pp)] = 0;
    adhesive_table.modulus[int(Phase::pp)] = table.modulus[int(Phase::pm)];
    BridgeSpec bridges = study.spec.bridges;
    bridges.matrix_fraction = fraction;
    const Elastic b = pull(comm, solver, study.halved_faces, [&] {
      add_matrix(sample, bridges);
      return mechanical_lattice(sample, bare_table);
    });
    const Elastic a = pull(comm, solver, study.halved_faces,
                           [&] { return mechanical_lattice(sample, adhesive_table); });
    if (rank != 0) continue;  // the statistics are on rank 0
    const auto& st = sample.stats;
    const double rho_pp = st.bond_volume_fraction[int(Phase::pp)];
    const auto hs =
        appendix_d_estimates({st.rho_p, st.rho_m, st.rho_v, rho_pp}, Ep, Em, Epm, unit.poisson);
    t.rho.push_back(st.rho_m);
    t.bare.push_back(b.young / Ep);
    t.adhesive.push_back(a.young / Ep);
    t.coverage.push_back(st.interface_ratio);
    t.csv << fraction << "," << st.rho_m << "," << st.rho_p << "," << st.rho_v << "," << rho_pp
          << "," << st.interface_ratio << "," << st.bridges_per_particle << ","
          << st.eligible_per_particle;
    for (auto n : st.bonds_per_phase) t.csv << "," << n;
    t.csv << "," << t.bare.back() << "," << t.adhesive.back() << "," << hs.bare / Ep << ","
          << hs.adhesive / Ep << "," << b.poisson << "," << a.poisson << "," << b.iterations << ","
          << a.iterations << "\n";
    say("%6.3f %7.4f %7.4f %7.4f %7.4f %7.4f %7.4f %8.2f %5.1fs\n", fraction, st.rho_m,
        t.bare.back(), hs.bare / Ep, t.adhesive.back(), hs.adhesive / Ep, st.interface_ratio,
        st.bridges_per_particle, MPI_Wtime() - t0);
  }
}

// Rank 0: the fits, what they say, and fits.csv and stiffness.csv in `dir`.
StiffnessFindings fit_and_write(const StiffnessTable& t, const StiffnessFindings& lattice,
                                const std::string& dir) {
  StiffnessFindings f = lattice;
  f.bare = fit_line(t.rho, t.bare);
  f.adhesive = fit_line(t.rho, t.adhesive);
  f.coverage = fit_line(t.rho, t.coverage);
  f.bare_over_em_at_highest = t.bare.back() * f.e_p / f.e_m;
  f.adhesive_over_em_at_highest = t.adhesive.back() * f.e_p / f.e_m;
  say("linear fits against rho^m (intercept, slope, largest residual):\n"
      "  E_bare/E^[p]     %.4f %+.4f  %.1e\n  E_adhesive/E^[p] %.4f %+.4f  "
      "%.1e\n"
      "  S^pm/S^p         %.4f %+.4f  %.1e\n",
      f.bare.intercept, f.bare.slope, f.bare.max_residual, f.adhesive.intercept, f.adhesive.slope,
      f.adhesive.max_residual, f.coverage.intercept, f.coverage.slope, f.coverage.max_residual);
  say("at rho^m = %.3f: E_eff/E^[m] = %.3f bare, %.3f adhesive (paper at "
      "0.28: 1.6, 2.5)\n",
      t.rho.back(), f.bare_over_em_at_highest, f.adhesive_over_em_at_highest);
  write_text_file_atomically(dir + "/fits.csv", "quantity,intercept,slope,max_residual\n" +
                                                    fit_row("E_bare_over_Ep", f.bare) +
                                                    fit_row("E_adhesive_over_Ep", f.adhesive) +
                                                    fit_row("S_pm_over_S_p", f.coverage));
  write_text_file_atomically(dir + "/stiffness.csv", t.csv.str());
  return f;
}

}  // namespace

StiffnessStudy read_stiffness_study(MPI_Comm comm) {
  StiffnessStudy study;
  study.spec = read_cemented_sample_spec(comm);
  study.table = read_phase_table(comm);
  {
    OptionGroup g(comm, "Stiffness against matrix fraction");
    study.fractions = g.positive_reals("-stiffness_fractions",
                                       "Matrix fractions rho^m to run "
                                       "(the paper's eight by default; -matrix_fraction has "
                                       "no use here and is refused)",
                                       {0.06, 0.1, 0.13, 0.17, 0.2, 0.22, 0.24, 0.28}, true);
    if (g.given("-matrix_fraction"))
      throw InputError("option -matrix_fraction has no use in lem_stiffness, which makes "
                       "a sample at each of -stiffness_fractions: give it there");
    study.request = ResultFolder::read_request(g, "results/stiffness");
    study.halved_faces = read_face_bond_option(g);
  }
  for (double f : study.fractions)
    if (f > 0.36)
      throw InputError("option -stiffness_fractions: " + std::to_string(f) +
                       " is out of range (allowed: (0, 0.36], the pore space of a "
                       "dense packing)");
  if (study.fractions.size() < 2)
    throw InputError("option -stiffness_fractions: give at least two fractions for the fits");
  if (study.spec.generator != LatticeGenerator::serial)
    throw InputError("option -lattice_generator cells: lem_stiffness builds its samples "
                     "on one rank, with -lattice_generator serial only");
  return study;
}

void run_stiffness_study(MPI_Comm comm, StiffnessStudy study, const SolverOptions& solver,
                         const Provenance& provenance) {
  CementedSample sample = granular_sample(comm, study.spec);
  // E^[phi] = c E^phi: a homogeneous lattice of bonds k = a (E = 1).
  const Elastic unit = pull(comm, solver, study.halved_faces, [&] {
    Lattice l = sample.lattice;
    const double a = lattice_stats(l).mean_length;
    l.stiffness.assign(l.bond_count(), a);
    return l;
  });
  check_unused_options();
  // Only once the sample and the solver options proved good: bad input
  // keeps older results.
  study.request.fingerprint = options_fingerprint(comm);
  const ResultFolder folder(comm, stiffness_layout(), study.request);
  if (!folder.begin()) return;
  StiffnessFindings lattice;
  lattice.e_p = unit.young * study.table.modulus[int(Phase::p)];
  lattice.e_m = unit.young * study.table.modulus[int(Phase::m)];
  lattice.poisson = unit.poisson;
  lattice.halved_faces = study.halved_faces;
  say("homogeneous lattice: E = %.5f E^phi, nu = %.4f -> E^[p] = %.4f, E^[m] = "
      "%.4f, "
      "E^[pm] = %.4f (units k/a)\n",
      unit.young, unit.poisson, lattice.e_p, lattice.e_m,
      unit.young * study.table.modulus[int(Phase::pm)]);
  StiffnessTable table;
  pull_fractions(comm, study, solver, sample, unit, table);
  Summary summary;
  run_on_root(comm, [&] {
    summary = stiffness_summary(fit_and_write(table, lattice, folder.work_dir()));
    summary.add_provenance(provenance);
  });
  folder.commit(summary, {});
  folder.install();
  say("plot: /usr/bin/python3 tools/plot_stiffness.py %s\n", study.request.dir.c_str());
}

namespace {

const SummaryTable<StiffnessFindings>& stiffness_table() {
  static const SummaryTable<StiffnessFindings> table = {
      {"E_p_lattice", "", "E^[p] of the homogeneous lattice, in E^φ units",
       [](const StiffnessFindings& r) { return r.e_p; }},
      {"E_m_lattice", "", "E^[m] of the homogeneous lattice, in E^φ units",
       [](const StiffnessFindings& r) { return r.e_m; }},
      {"lattice_poisson", "", "ν of the homogeneous lattice",
       [](const StiffnessFindings& r) { return r.poisson; }},
      {"face_bonds", "", "`whole` or `halved` (`-lattice_face_bonds`)",
       [](const StiffnessFindings& r) { return std::string(r.halved_faces ? "halved" : "whole"); }},
      {"bare_intercept", "", "the fit of E_bare/E^[p] against ρ^m (`fits.csv`): intercept",
       [](const StiffnessFindings& r) { return r.bare.intercept; }},
      {"bare_slope", "", "the fit of E_bare/E^[p]: slope",
       [](const StiffnessFindings& r) { return r.bare.slope; }},
      {"adhesive_intercept", "", "the fit of E_adhesive/E^[p]: intercept",
       [](const StiffnessFindings& r) { return r.adhesive.intercept; }},
      {"adhesive_slope", "", "the fit of E_adhesive/E^[p]: slope",
       [](const StiffnessFindings& r) { return r.adhesive.slope; }},
      {"coverage_intercept", "", "the fit of S^pm/S^p: intercept",
       [](const StiffnessFindings& r) { return r.coverage.intercept; }},
      {"coverage_slope", "", "the fit of S^pm/S^p: slope",
       [](const StiffnessFindings& r) { return r.coverage.slope; }},
      {"bare_over_Em_at_highest", "", "E_eff/E^[m] with bare contacts at the largest fraction",
       [](const StiffnessFindings& r) { return r.bare_over_em_at_highest; }},
      {"adhesive_over_Em_at_highest", "", "E_eff/E^[m] with adhesive contacts there",
       [](const StiffnessFindings& r) { return r.adhesive_over_em_at_highest; }},
  };
  return table;
}

}  // namespace

const std::vector<SummaryField>& stiffness_summary_fields() {
  static const std::vector<SummaryField> fields = described_fields(stiffness_table());
  return fields;
}

Summary stiffness_summary(const StiffnessFindings& f) {
  Summary summary;
  summary.add_from(stiffness_table(), f);
  return summary;
}

int stiffness_program(int argc, char** argv, const char* help) {
  return run_driver(argc, argv, help, [](MPI_Comm comm) {
    const StiffnessStudy study = read_stiffness_study(comm);
    register_solver_levers();
    const SolverOptions solver = read_solver_options(comm);
    check_option_names(comm);
    const auto provenance = collect_provenance(comm, "lem_stiffness");
    run_stiffness_study(comm, study, solver, provenance);
  });
}

}  // namespace lem
