// lem_convergence (convergence_study.hpp).
#include "lem/solver/levers.hpp"
#include "lem/run/convergence_study.hpp"

#include "lem/base/driver.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/base/line_fit.hpp"
#include "lem/base/log.hpp"
#include "lem/base/options.hpp"
#include "lem/run/programs.hpp"
#include "lem/run/result_folder.hpp"
#include "lem/setup/units.hpp"
#include "lem/system/elastic_system.hpp"

#include <cmath>
#include <sstream>
#include <string>

namespace lem {

namespace {

struct ConvergenceOptions {
  SampleOptions sample;
  std::vector<double> densities;  // -convergence_Ln
  ResultFolder::Request request;
  SolverOptions solver;
};

ConvergenceOptions read_convergence_options(MPI_Comm comm) {
  ConvergenceOptions o;
  o.sample = read_sample_options(comm);
  {
    OptionGroup g(comm, "Convergence study");
    o.densities = g.positive_reals("-convergence_Ln", "Mesh densities L_n = M^(-1/3) to run",
                                   {0.05, 0.04, 0.03, 0.025, 0.02}, true);
    o.request = ResultFolder::read_request(g, "results/convergence");
  }
  for (double ln : o.densities)
    if (ln > 0.2)
      throw InputError("option -convergence_Ln: L_n = " + std::to_string(ln) +
                       " is too coarse (allowed: <= 0.2)");
  register_solver_levers();
  o.solver = read_solver_options(comm);
  check_option_names(comm);
  if (o.sample.lattice_type != LatticeType::random)
    throw InputError("lem_convergence needs -lattice_type random");
  return o;
}

// E_eff of one sample, in the unit of setup/units.hpp (k/a), and the CG
// iteration count.
std::pair<double, int> young_modulus(MPI_Comm comm, SampleOptions sample,
                                     const SolverOptions& solver, InclusionType inclusions,
                                     SetupReport& setup) {
  sample.inclusion_type = inclusions;
  auto lattice = setup_sample_lattice(comm, sample, setup);
  ElasticSystem system(lattice, solver);
  check_unused_options(SolverStage::created);
  system.assemble();
  const auto solve = system.solve(3e-4 * lattice.mean_bond_length);
  const StressUnit unit = stress_unit(sample, lattice.mean_bond_length);
  return {unit.of(system.response().young_modulus), solve.iterations};
}

// The rows of convergence.csv and the series of the fit.
struct ConvergenceTable {
  std::ostringstream csv;
  std::vector<double> ln, stiff, pore;
};

void run_densities(MPI_Comm comm, ConvergenceOptions& o, ConvergenceTable& t) {
  // E_eff/E^[m] against L_n (paper fig. 6), E^[m] in units of k/a; the
  // inclusions and the provenance are in summary.json.
  t.csv << "Ln,bonds,nodes,E_matrix,E_stiff_over_matrix,E_pore_over_matrix,its_matrix,"
           "its_stiff,its_pore\n";
  bool first_solve = true;
  say("%8s %9s %10s %10s %10s %6s\n", "L_n", "bonds", "E^[m]", "E_stiff", "E_pore", "its");
  SampleOptions sample = o.sample;
  for (double density : o.densities) {
    sample.random.nodes = 0;
    sample.random.bonds = 0;
    sample.random.mesh_density = density;
    SetupReport setup;
    const auto [em, im] = young_modulus(comm, sample, o.solver, InclusionType::none, setup);
    if (first_solve) check_unused_options();
    first_solve = false;
    SetupReport ss, sp;
    const auto [es, is] = young_modulus(comm, sample, o.solver, InclusionType::stiff, ss);
    const auto [ep, ip] = young_modulus(comm, sample, o.solver, InclusionType::pore, sp);
    const double m = static_cast<double>(setup.sample.stats.bonds);
    t.ln.push_back(std::pow(m, -1.0 / 3.0));  // the L_n actually reached
    t.stiff.push_back(es / em);
    t.pore.push_back(ep / em);
    t.csv << t.ln.back() << "," << setup.sample.stats.bonds << "," << setup.sample.stats.nodes
          << "," << em << "," << t.stiff.back() << "," << t.pore.back() << "," << im << "," << is
          << "," << ip << "\n";
    say("%8.4f %9lld %10.5f %10.5f %10.5f %6d\n", t.ln.back(), (long long)setup.sample.stats.bonds,
        em, t.stiff.back(), t.pore.back(), im);
  }
}

// fit.csv: the straight lines E/E^[m] = E0 + alpha_E L_n (two densities or more).
std::string fit_csv(const ConvergenceTable& t) {
  std::ostringstream fit;
  fit << "case,extrapolated_E_over_Em,alpha_E\n";
  if (t.ln.size() >= 2) {
    const auto s = fit_line(t.ln, t.stiff), p = fit_line(t.ln, t.pore);
    const double s0 = s.intercept, sa = s.slope, p0 = p.intercept, pa = p.slope;
    fit << "stiff," << s0 << "," << sa << "\npore," << p0 << "," << pa << "\n";
    say("linear fits E/E^[m] = E0 + alpha_E L_n:\n  stiff inclusions: E0 = %.4f, "
        "alpha_E = %.3f\n  pores:            E0 = %.4f, alpha_E = %.3f\n",
        s0, sa, p0, pa);
  }
  return fit.str();
}

void run_convergence(MPI_Comm comm, ConvergenceOptions o) {
  const auto provenance = collect_provenance(comm, "lem_convergence");
  o.request.fingerprint = options_fingerprint(comm);
  const ResultFolder folder(comm, convergence_layout(), o.request);
  if (!folder.begin()) return;
  const std::string& dir = folder.work_dir();
  ConvergenceTable table;
  run_densities(comm, o, table);
  const std::string fit = fit_csv(table);
  Summary summary = convergence_summary(o.sample);
  summary.add_provenance(provenance);
  run_on_root(comm, [&] {
    write_text_file_atomically(dir + "/fit.csv", fit);
    write_text_file_atomically(dir + "/convergence.csv", table.csv.str());
  });
  folder.commit(summary, {});
  folder.install();
  say("plot: /usr/bin/python3 tools/plot_convergence.py %s\n", o.request.dir.c_str());
}

}  // namespace

namespace {

const SummaryTable<SampleOptions>& convergence_table() {
  static const SummaryTable<SampleOptions> table = {
      {"inclusion_volume_fraction", "", "volume fraction of the inclusions and of the pores",
       [](const SampleOptions& r) { return r.inclusions.volume_fraction; }},
      {"inclusion_radius", "smallest box side", "their radius",
       [](const SampleOptions& r) { return r.inclusions.radius; }},
      {"inclusion_stiffness_ratio", "", "the stiff inclusions' bond stiffness over the matrix's",
       [](const SampleOptions& r) { return r.inclusion_stiffness_ratio; }},
  };
  return table;
}

}  // namespace

const std::vector<SummaryField>& convergence_summary_fields() {
  static const std::vector<SummaryField> fields = described_fields(convergence_table());
  return fields;
}

Summary convergence_summary(const SampleOptions& sample) {
  Summary summary;
  summary.add_from(convergence_table(), sample);
  return summary;
}

int convergence_program(int argc, char** argv, const char* help) {
  return run_driver(argc, argv, help,
                    [](MPI_Comm comm) { run_convergence(comm, read_convergence_options(comm)); });
}

}  // namespace lem
