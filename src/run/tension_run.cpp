// lem_tension: elastic uniaxial tension of a lattice sample.
#include "lem/solver/levers.hpp"
#include "lem/base/driver.hpp"
#include "lem/base/log.hpp"
#include "lem/base/options.hpp"
#include "lem/base/phase.hpp"
#include "lem/fields/tension_output.hpp"
#include "lem/protocol/fingerprint.hpp"
#include "lem/report/tension_summary.hpp"
#include "lem/run/programs.hpp"
#include "lem/run/result_folder.hpp"
#include "lem/setup/setup.hpp"
#include "lem/setup/units.hpp"

namespace lem {

namespace {

struct TensionOptions {
  SampleOptions sample;
  double delta = 0;  // -load_displacement, in units of a
  ResultFolder::Request request;
  bool fields = true;
  SolverOptions solver;
};

TensionOptions read_tension_options(MPI_Comm comm) {
  TensionOptions o;
  o.sample = read_sample_options(comm);
  {
    OptionGroup g(comm, "Loading and output");
    o.delta = g.real("-load_displacement",
                     "Top displacement Delta in units of the mean bond "
                     "length a",
                     3e-4, 0.0, 0.1, true);
    o.request = ResultFolder::read_request(g, "results/tension");
    o.fields = g.flag("-output_fields", "Write nodes and bonds to HDF5/XDMF", true);
  }
  register_solver_levers();
  o.solver = read_solver_options(comm);
  check_option_names(comm);
  return o;
}

// The lines a run prints after its solve.
void say_tension_result(const SampleOptions& sample, const SetupReport& setup,
                        const StressUnit& unit, const TensionResponse& response,
                        const SolveReport& solve, const PeakMemory& memory) {
  const double e_p = sample.phases.modulus[static_cast<int>(Phase::p)];
  const bool from_file = !sample.sample_file.empty();
  if (from_file) {
    const auto& c = setup.sample.cemented;
    say("sample %s: %lld particles, rho_p %.4f, rho_m %.4f, rho_v %.4f; E^p %g, E^m %g, "
        "E^pp %g, E^pm %g\n",
        sample.sample_file.c_str(), (long long)c.particles, c.rho_p, c.rho_m, c.rho_v, e_p,
        sample.phases.modulus[1], sample.phases.modulus[3], sample.phases.modulus[4]);
  }
  say("solve: %d CG iterations, PC setup %.2f s, solve %.2f s; peak memory per rank "
      "%.0f MB (largest), %.0f MB (mean)\n",
      solve.iterations, solve.setup_seconds, solve.solve_seconds, memory.max_mb, memory.mean_mb);
  const double e_eff = unit.of(response.young_modulus),
               e_aff = unit.of(setup.sample.affine.young_z);
  if (from_file)
    say("E_eff = %.6g (units of E^phase) = %.6g E^p   (affine estimate %.6g E^p)\n", e_eff,
        e_eff / e_p, e_aff / e_p);
  else
    say("E_eff = %.6g k/a   (affine estimate %.6g, appendix B 0.8485)\n", e_eff, e_aff);
  say("nu    = %.6g       (affine estimate %.6g)\n", response.poisson_ratio,
      setup.sample.affine.poisson_z);
  say("energy 1/2 u.Ku = %.10g, work 1/2 F Delta = %.10g\n", response.stored_energy,
      response.external_work);
}

void run_tension(MPI_Comm comm, TensionOptions o) {
  const auto provenance = collect_provenance(comm, "lem_tension");
  SetupReport setup;
  auto lattice = setup_sample_lattice(comm, o.sample, setup);
  // Only once the sample is read and checked: bad input keeps older results.
  o.request.fingerprint = options_fingerprint(comm, lattice_fingerprint(lattice));
  const ResultFolder folder(comm, tension_layout(), o.request);
  if (!folder.begin()) return;
  say("lattice: %lld nodes, %lld bonds (%lld in the system), a = %.4g, L_n = %.4g, "
      "coordination %.2f\n",
      (long long)setup.sample.stats.nodes, (long long)setup.sample.stats.bonds,
      (long long)setup.active_bonds, lattice.mean_bond_length, setup.sample.stats.mesh_density,
      setup.sample.stats.mean_coordination);
  ElasticSystem system(lattice, o.solver);
  check_unused_options(SolverStage::created);
  system.assemble();
  const auto solve = system.solve(o.delta * lattice.mean_bond_length);
  check_unused_options();
  const auto response = system.response();
  const PeakMemory memory = peak_memory(comm);
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  auto summary =
      tension_summary(o.sample, setup, lattice.mean_bond_length, response, solve, ranks, memory);
  say_tension_result(o.sample, setup, stress_unit(o.sample, lattice.mean_bond_length), response,
                     solve, memory);
  if (o.fields)
    write_tension_fields(folder.work_dir() + "/fields", lattice, system, provenance, summary);
  summary.add_provenance(provenance);
  folder.commit(summary, {});
  folder.install();
}

}  // namespace

int tension_program(int argc, char** argv, const char* help) {
  return run_driver(argc, argv, help,
                    [](MPI_Comm comm) { run_tension(comm, read_tension_options(comm)); });
}

}  // namespace lem
