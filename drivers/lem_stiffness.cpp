// Effective Young's modulus of cemented samples against the matrix volume
// fraction (Affes et al. 2012, sect. 3, figs. 5 and 11, appendix D).
//
// One packing and one lattice are built; for each matrix fraction the
// bridges are recalibrated and the sample is pulled elastically twice: with
// bare contacts (particle-particle bonds carry nothing, E^pp = 0) and with
// adhesive ones (E^pp = E^pm).  E_eff is normalised by E^[p], the modulus of
// a homogeneous lattice of the same nodes and bonds made of particle bonds,
// and compared with the appendix-D estimates.
//
//   mpirun -n 2 lem_stiffness -output_dir results/stiffness
//   /usr/bin/python3 tools/plot_stiffness.py results/stiffness
#include "lem/cemented_sample.hpp"
#include "lem/driver.hpp"
#include "lem/effective_medium.hpp"
#include "lem/elastic_system.hpp"
#include "lem/error.hpp"
#include "lem/files.hpp"
#include "lem/hdf5_writer.hpp"
#include "lem/line_fit.hpp"
#include "lem/result_folder.hpp"
#include "lem/options.hpp"
#include "lem/sample_options.hpp"
#include "lem/setup.hpp"
#include "lem/summary.hpp"
#include "lem/tension_output.hpp"

#include <sstream>

static const char help[] =
    "E_eff/E^[p] of cemented samples against the matrix fraction, bare and adhesive\n"
    "contacts, with the Hashin-Shtrikman estimates of appendix D (paper figs. 5, 11).\n";

namespace {

struct Elastic {
  double young = 0, poisson = 0;
  int iterations = 0;
};

// Uniaxial tension of the lattice `make()` builds on rank 0.
Elastic pull(MPI_Comm comm, const lem::SolverOptions& solver, bool halved_faces,
             const std::function<lem::Lattice()>& make) {
  lem::SetupReport setup;
  auto lattice = lem::setup_tension_lattice(
      comm,
      [&](lem::SampleInfo& info) {
        lem::Lattice l = make();
        info.stats = lem::lattice_stats(l);
        if (halved_faces) lem::halve_face_bonds(l);
        return l;
      },
      setup);
  lem::ElasticSystem system(lattice, solver);
  lem::check_unused_options(lem::SolverStage::created);
  system.assemble();
  const auto solve = system.solve(3e-4 * lattice.mean_bond_length);
  const auto response = system.response();
  return {response.young_modulus, response.poisson_ratio, solve.iterations};
}

std::string fit_row(const char* name, const lem::LineFit& f) {
  std::ostringstream s;
  s.precision(8);
  s << name << "," << f.intercept << "," << f.slope << "," << f.max_residual << "\n";
  return s.str();
}

}  // namespace

int main(int argc, char** argv) {
  return lem::run_driver(argc, argv, help, [](MPI_Comm comm) {
    const lem::CementedSampleSpec spec = lem::read_cemented_sample_spec(comm);
    const lem::PhaseTable table = lem::read_phase_table(comm);
    std::vector<double> fractions;
    lem::ResultFolder::Request request;
    bool halved_faces = false;
    {
      lem::OptionGroup g(comm, "Stiffness against matrix fraction");
      fractions = g.positive_reals("-stiffness_fractions", "Matrix fractions rho^m to run (the "
                                   "paper's eight by default; -matrix_fraction has no use "
                                   "here and is refused)",
                                   {0.06, 0.1, 0.13, 0.17, 0.2, 0.22, 0.24, 0.28}, true);
      if (g.given("-matrix_fraction"))
        throw lem::InputError("option -matrix_fraction has no use in lem_stiffness, which makes "
                              "a sample at each of -stiffness_fractions: give it there");
      request = lem::ResultFolder::read_request(g, "results/stiffness");
      halved_faces = lem::read_face_bond_option(g);
    }
    for (double f : fractions)
      if (f > 0.36)
        throw lem::InputError("option -stiffness_fractions: " + std::to_string(f) +
                              " is out of range (allowed: (0, 0.36], the pore space of a "
                              "dense packing)");
    if (fractions.size() < 2)
      throw lem::InputError("option -stiffness_fractions: give at least two fractions for the fits");
    if (spec.generator != lem::LatticeGenerator::serial)
      throw lem::InputError("option -lattice_generator cells: lem_stiffness builds its samples "
                            "on one rank, with -lattice_generator serial only");
    const lem::SolverOptions solver = lem::read_solver_options(comm);
    lem::check_option_names(comm);
    const auto provenance = lem::collect_provenance(comm, "lem_stiffness");
    int rank = 0;
    MPI_Comm_rank(comm, &rank);

    // The granular sample lives on rank 0; the other ranks only solve.
    lem::CementedSample sample;
    lem::run_on_root(comm, [&] {
      sample = lem::build_granular_sample(spec);
      const auto& st = sample.stats;
      lem::say("sample: %lld particles (%lld spheres), side %.4g, %lld nodes, %lld bonds, "
               "%.0f nodes per particle; packing %.1f s, lattice %.1f s, Voronoi %.1f s\n",
               (long long)st.sample_particles, (long long)st.particles, st.side,
               (long long)st.nodes, (long long)st.bonds, st.nodes_per_particle,
               st.packing_seconds, st.lattice_seconds, st.voronoi_seconds);
    });

    // E^[phi] = c E^phi: a homogeneous lattice of bonds k = a (E = 1).
    const Elastic unit = pull(comm, solver, halved_faces, [&] {
      lem::Lattice l = sample.lattice;
      const double a = lem::lattice_stats(l).mean_length;
      l.stiffness.assign(l.bond_count(), a);
      return l;
    });
    lem::check_unused_options();
    // Only once the sample and the solver options proved good: bad input
    // keeps older results.
    request.fingerprint = lem::options_fingerprint(comm, {});
    const lem::ResultFolder folder(comm, lem::stiffness_layout(), request);
    if (!folder.begin()) return;
    const std::string& dir = folder.work_dir();
    using lem::Phase;
    auto lattice_modulus = [&](Phase p) { return unit.young * table.modulus[int(p)]; };
    const double Ep = lattice_modulus(Phase::p), Em = lattice_modulus(Phase::m),
                 Epm = lattice_modulus(Phase::pm);
    lem::say("homogeneous lattice: E = %.5f E^phi, nu = %.4f -> E^[p] = %.4f, E^[m] = %.4f, "
             "E^[pm] = %.4f (units k/a)\n", unit.young, unit.poisson, Ep, Em, Epm);

    std::ostringstream csv;
    csv.precision(8);
    // E_eff/E^[p] against rho^m (paper figs. 5, 11; appendix D); E^[p],
    // E^[m] and the lattice nu are in summary.json.
    csv << "rho_m_requested,rho_m,rho_p,rho_v,rho_pp,S_pm,bridges_per_particle,"
           "eligible_per_particle,bonds_p,bonds_m,bonds_v,bonds_pp,bonds_pm,"
           "E_bare,E_adhesive,HS_bare,HS_adhesive,nu_bare,nu_adhesive,its_bare,its_adhesive\n";
    std::vector<double> rho, bare, adhesive, coverage;
    lem::say("%6s %7s %7s %7s %7s %7s %7s %8s %6s\n", "rho_m", "lattice", "E_bare", "HS_bare",
             "E_adh", "HS_adh", "S_pm", "bridges", "time");
    for (double fraction : fractions) {
      const double t0 = MPI_Wtime();
      lem::PhaseTable bare_table = table, adhesive_table = table;
      bare_table.modulus[int(Phase::pp)] = 0;
      adhesive_table.modulus[int(Phase::pp)] = table.modulus[int(Phase::pm)];
      lem::BridgeSpec bridges = spec.bridges;
      bridges.matrix_fraction = fraction;
      const Elastic b = pull(comm, solver, halved_faces, [&] {
        lem::add_matrix(sample, bridges);
        return lem::mechanical_lattice(sample, bare_table);
      });
      const Elastic a = pull(comm, solver, halved_faces,
                             [&] { return lem::mechanical_lattice(sample, adhesive_table); });
      if (rank != 0) continue;  // the statistics are on rank 0
      const auto& st = sample.stats;
      const double rho_pp = st.bond_volume_fraction[int(Phase::pp)];
      const auto hs = lem::appendix_d_estimates({st.rho_p, st.rho_m, st.rho_v, rho_pp}, Ep, Em,
                                                Epm, unit.poisson);
      rho.push_back(st.rho_m);
      bare.push_back(b.young / Ep);
      adhesive.push_back(a.young / Ep);
      coverage.push_back(st.interface_ratio);
      csv << fraction << "," << st.rho_m << "," << st.rho_p << "," << st.rho_v << "," << rho_pp
          << "," << st.interface_ratio << "," << st.bridges_per_particle << "," << st.eligible_per_particle;
      for (auto n : st.bonds_per_phase) csv << "," << n;
      csv << "," << bare.back() << "," << adhesive.back() << "," << hs.bare / Ep << ","
          << hs.adhesive / Ep << "," << b.poisson << "," << a.poisson << "," << b.iterations
          << "," << a.iterations << "\n";
      lem::say("%6.3f %7.4f %7.4f %7.4f %7.4f %7.4f %7.4f %8.2f %5.1fs\n", fraction, st.rho_m,
               bare.back(), hs.bare / Ep, adhesive.back(), hs.adhesive / Ep, st.interface_ratio,
               st.bridges_per_particle, MPI_Wtime() - t0);
    }
    lem::Summary summary;
    if (rank == 0) {
      const auto fb = lem::fit_line(rho, bare), fa = lem::fit_line(rho, adhesive),
                 fs = lem::fit_line(rho, coverage);
      lem::say("linear fits against rho^m (intercept, slope, largest residual):\n"
               "  E_bare/E^[p]     %.4f %+.4f  %.1e\n  E_adhesive/E^[p] %.4f %+.4f  %.1e\n"
               "  S^pm/S^p         %.4f %+.4f  %.1e\n",
               fb.intercept, fb.slope, fb.max_residual, fa.intercept, fa.slope, fa.max_residual,
               fs.intercept, fs.slope, fs.max_residual);
      lem::say("at rho^m = %.3f: E_eff/E^[m] = %.3f bare, %.3f adhesive (paper at 0.28: 1.6, 2.5)\n",
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
      lem::write_text_file_atomically(dir + "/fits.csv",
                                      "quantity,intercept,slope,max_residual\n" +
                                          fit_row("E_bare_over_Ep", fb) +
                                          fit_row("E_adhesive_over_Ep", fa) +
                                          fit_row("S_pm_over_S_p", fs));
      lem::write_text_file_atomically(dir + "/stiffness.csv", csv.str());
    }
    folder.commit(summary, {});
    folder.install();
    lem::say("plot: /usr/bin/python3 tools/plot_stiffness.py %s\n", request.dir.c_str());
  });
}
