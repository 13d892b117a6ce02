// Elastic uniaxial tension of a lattice sample: prints the effective Young's
// modulus and Poisson ratio and writes a summary and the fields.
//
//   mpirun -n 2 lem_tension -lattice_bonds 1300000 -output_dir results/tension
//   mpirun -n 2 lem_tension -sample_file meshes/demo.h5 -output_dir results/demo
#include "lem/base/driver.hpp"
#include "lem/base/options.hpp"
#include "lem/protocol/fingerprint.hpp"
#include "lem/run/result_folder.hpp"
#include "lem/setup/setup.hpp"
#include "lem/fields/tension_output.hpp"
#include "lem/report/tension_summary.hpp"

static const char help[] =
    "Elastic uniaxial tension of a spring lattice (Affes et al., EPJE 35, 2012).\n"
    "Bottom face u_z = 0, top face u_z = Delta, lateral faces free.\n"
    "The sample is a generated lattice (-lattice_*, -inclusion_*) or a cemented sample\n"
    "file from lem_sample (-sample_file, bond moduli -phase_E_*).\n";

int main(int argc, char** argv) {
  return lem::run_driver(argc, argv, help, [](MPI_Comm comm) {
    const lem::SampleOptions sample = lem::read_sample_options(comm);
    double delta = 0;
    lem::ResultFolder::Request request;
    bool fields = true;
    {
      lem::OptionGroup g(comm, "Loading and output");
      delta = g.real("-load_displacement",
                     "Top displacement Delta in units of the mean bond "
                     "length a",
                     3e-4, 0.0, 0.1, true);
      request = lem::ResultFolder::read_request(g, "results/tension");
      fields = g.flag("-output_fields", "Write nodes and bonds to HDF5/XDMF", true);
    }
    const lem::SolverOptions solver = lem::read_solver_options(comm);
    lem::check_option_names(comm);
    const auto provenance = lem::collect_provenance(comm, "lem_tension");

    lem::SetupReport setup;
    auto lattice = lem::setup_sample_lattice(comm, sample, setup);
    // Only once the sample is read and checked: bad input keeps older results.
    request.fingerprint = lem::options_fingerprint(comm, lem::lattice_fingerprint(lattice));
    const lem::ResultFolder folder(comm, lem::tension_layout(), request);
    if (!folder.begin()) return;
    const std::string& dir = folder.work_dir();
    lem::say("lattice: %lld nodes, %lld bonds (%lld in the system), a = %.4g, L_n = %.4g, "
             "coordination %.2f\n",
             (long long)setup.sample.stats.nodes, (long long)setup.sample.stats.bonds,
             (long long)setup.active_bonds, lattice.mean_bond_length,
             setup.sample.stats.mesh_density, setup.sample.stats.mean_coordination);

    lem::ElasticSystem system(lattice, solver);
    lem::check_unused_options(lem::SolverStage::created);
    system.assemble();
    const auto solve = system.solve(delta * lattice.mean_bond_length);
    lem::check_unused_options();
    const auto response = system.response();
    // Moduli in units of k/a.  A sample file's bonds have k = E^phase a_s and
    // f = sigma^phase a_s^2 in the sample's length unit, so its stresses and
    // moduli already come out in the units of E^phase: take k = a (unit 1).
    const bool from_file = !sample.sample_file.empty();
    const double bond_k = from_file ? lattice.mean_bond_length : sample.random.stiffness;
    auto summary = lem::tension_summary(setup, lattice, bond_k, response, solve);
    const double unit = bond_k / lattice.mean_bond_length;
    const double e_p = sample.phases.modulus[static_cast<int>(lem::Phase::p)];
    if (from_file) {
      const auto& c = setup.sample.cemented;
      lem::say("sample %s: %lld particles, rho_p %.4f, rho_m %.4f, rho_v %.4f; E^p %g, E^m %g, "
               "E^pp %g, E^pm %g\n",
               sample.sample_file.c_str(), (long long)c.particles, c.rho_p, c.rho_m, c.rho_v, e_p,
               sample.phases.modulus[1], sample.phases.modulus[3], sample.phases.modulus[4]);
      summary.add("sample_file", sample.sample_file);
      summary.add("rho_p", c.rho_p);
      summary.add("rho_m", c.rho_m);
      summary.add("rho_v", c.rho_v);
      summary.add("E_p", e_p, "stress");
      summary.add("E_eff_over_E_p", response.young_modulus / unit / e_p);
    }
    const lem::PeakMemory memory = lem::peak_memory(comm);
    summary.add("peak_memory_mb", memory.max_mb, "MB");
    summary.add("peak_memory_mean_mb", memory.mean_mb, "MB");
    lem::say("solve: %d CG iterations, PC setup %.2f s, solve %.2f s; peak memory per rank "
             "%.0f MB (largest), %.0f MB (mean)\n",
             solve.iterations, solve.setup_seconds, solve.solve_seconds, memory.max_mb,
             memory.mean_mb);
    if (from_file)
      lem::say("E_eff = %.6g (units of E^phase) = %.6g E^p   (affine estimate %.6g E^p)\n",
               response.young_modulus / unit, response.young_modulus / unit / e_p,
               setup.sample.affine.young_z / unit / e_p);
    else
      lem::say("E_eff = %.6g k/a   (affine estimate %.6g, appendix B 0.8485)\n",
               response.young_modulus / unit, setup.sample.affine.young_z / unit);
    lem::say("nu    = %.6g       (affine estimate %.6g)\n", response.poisson_ratio,
             setup.sample.affine.poisson_z);
    lem::say("energy 1/2 u.Ku = %.10g, work 1/2 F Delta = %.10g\n", response.stored_energy,
             response.external_work);

    if (fields) lem::write_tension_fields(dir + "/fields", lattice, system, provenance, summary);
    summary.add_provenance(provenance);
    folder.commit(summary, {});
    folder.install();
  });
}
