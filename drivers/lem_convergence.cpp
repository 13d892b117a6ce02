// Convergence of the effective Young's modulus with the mesh density
// L_n = M^(-1/3) (paper sect. 3, fig. 6): a matrix with 20% stiff spherical
// inclusions (10x) and with 20% spherical pores, each normalised by the
// homogeneous lattice of the same nodes, fitted linearly in L_n.
//
//   mpirun -n 2 lem_convergence -convergence_Ln 0.05,0.04,0.03,0.02 -output_dir results/convergence
//   /usr/bin/python3 tools/plot_convergence.py results/convergence
#include "lem/base/driver.hpp"
#include "lem/system/elastic_system.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/io/hdf5_writer.hpp"
#include "lem/base/line_fit.hpp"
#include "lem/base/options.hpp"
#include "lem/run/result_folder.hpp"
#include "lem/setup/setup.hpp"
#include "lem/base/summary.hpp"
#include "lem/fields/tension_output.hpp"

#include <cmath>
#include <sstream>

static const char help[] =
    "Mesh-density convergence of E_eff for stiff inclusions and pores (paper fig. 6).\n";

namespace {

// E_eff of one sample, in units of k/a, and the CG iteration count.
std::pair<double, int> young_modulus(MPI_Comm comm, lem::SampleOptions sample,
                                     const lem::SolverOptions& solver,
                                     lem::InclusionType inclusions, lem::SetupReport& setup) {
  sample.inclusion_type = inclusions;
  auto lattice = lem::setup_sample_lattice(comm, sample, setup);
  lem::ElasticSystem system(lattice, solver);
  lem::check_unused_options(lem::SolverStage::created);
  system.assemble();
  const auto solve = system.solve(3e-4 * lattice.mean_bond_length);
  const double unit = sample.random.stiffness / lattice.mean_bond_length;
  return {system.response().young_modulus / unit, solve.iterations};
}

}  // namespace

int main(int argc, char** argv) {
  return lem::run_driver(argc, argv, help, [](MPI_Comm comm) {
    lem::SampleOptions sample = lem::read_sample_options(comm);
    std::vector<double> densities;
    lem::ResultFolder::Request request;
    {
      lem::OptionGroup g(comm, "Convergence study");
      densities = g.positive_reals("-convergence_Ln", "Mesh densities L_n = M^(-1/3) to run",
                                   {0.05, 0.04, 0.03, 0.025, 0.02}, true);
      request = lem::ResultFolder::read_request(g, "results/convergence");
    }
    for (double ln : densities)
      if (ln > 0.2)
        throw lem::InputError("option -convergence_Ln: L_n = " + std::to_string(ln) +
                              " is too coarse (allowed: <= 0.2)");
    const lem::SolverOptions solver = lem::read_solver_options(comm);
    lem::check_option_names(comm);
    if (sample.lattice_type != lem::LatticeType::random)
      throw lem::InputError("lem_convergence needs -lattice_type random");
    const auto provenance = lem::collect_provenance(comm, "lem_convergence");
    request.fingerprint = lem::options_fingerprint(comm);
    const lem::ResultFolder folder(comm, lem::convergence_layout(), request);
    if (!folder.begin()) return;
    const std::string& dir = folder.work_dir();

    std::ostringstream table;
    // E_eff/E^[m] against L_n (paper fig. 6), E^[m] in units of k/a; the
    // inclusions and the provenance are in summary.json.
    table << "Ln,bonds,nodes,E_matrix,E_stiff_over_matrix,E_pore_over_matrix,its_matrix,"
             "its_stiff,its_pore\n";
    std::vector<double> ln, stiff, pore;
    bool first_solve = true;
    lem::say("%8s %9s %10s %10s %10s %6s\n", "L_n", "bonds", "E^[m]", "E_stiff", "E_pore", "its");
    for (double density : densities) {
      sample.random.nodes = 0;
      sample.random.bonds = 0;
      sample.random.mesh_density = density;
      lem::SetupReport setup;
      const auto [em, im] = young_modulus(comm, sample, solver, lem::InclusionType::none, setup);
      if (first_solve) lem::check_unused_options();
      first_solve = false;
      lem::SetupReport ss, sp;
      const auto [es, is] = young_modulus(comm, sample, solver, lem::InclusionType::stiff, ss);
      const auto [ep, ip] = young_modulus(comm, sample, solver, lem::InclusionType::pore, sp);
      const double m = static_cast<double>(setup.sample.stats.bonds);
      ln.push_back(std::pow(m, -1.0 / 3.0));  // the L_n actually reached
      stiff.push_back(es / em);
      pore.push_back(ep / em);
      table << ln.back() << "," << setup.sample.stats.bonds << "," << setup.sample.stats.nodes
            << "," << em << "," << stiff.back() << "," << pore.back() << "," << im << "," << is
            << "," << ip << "\n";
      lem::say("%8.4f %9lld %10.5f %10.5f %10.5f %6d\n", ln.back(),
               (long long)setup.sample.stats.bonds, em, stiff.back(), pore.back(), im);
    }
    std::ostringstream fit;
    fit << "case,extrapolated_E_over_Em,alpha_E\n";
    if (ln.size() >= 2) {
      const auto s = lem::fit_line(ln, stiff), p = lem::fit_line(ln, pore);
      const double s0 = s.intercept, sa = s.slope, p0 = p.intercept, pa = p.slope;
      fit << "stiff," << s0 << "," << sa << "\npore," << p0 << "," << pa << "\n";
      lem::say("linear fits E/E^[m] = E0 + alpha_E L_n:\n  stiff inclusions: E0 = %.4f, "
               "alpha_E = %.3f\n  pores:            E0 = %.4f, alpha_E = %.3f\n",
               s0, sa, p0, pa);
    }
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    lem::Summary summary;
    summary.add("inclusion_volume_fraction", sample.inclusions.volume_fraction);
    summary.add("inclusion_radius", sample.inclusions.radius, "smallest box side");
    summary.add("inclusion_stiffness_ratio", sample.inclusion_stiffness_ratio);
    summary.add_provenance(provenance);
    if (rank == 0) {
      lem::write_text_file_atomically(dir + "/fit.csv", fit.str());
      lem::write_text_file_atomically(dir + "/convergence.csv", table.str());
    }
    folder.commit(summary, {});
    folder.install();
    lem::say("plot: /usr/bin/python3 tools/plot_convergence.py %s\n", request.dir.c_str());
  });
}
