// Quasi-static tensile test to complete failure (paper sect. 2.3, 3, 6):
// stress-strain curve, E_eff, sigma_eff, broken bonds by phase, fields.
//
//   mpirun -n 2 lem_fracture -sample_file meshes/demo.h5 -output_dir results/fracture
//   mpirun -n 2 lem_fracture -lattice_bonds 200000 -lattice_break_strain 1e-3
#include "lem/driver.hpp"
#include "lem/fracture_run.hpp"
#include "lem/options.hpp"

static const char help[] =
    "Quasi-static uniaxial tension to complete failure of an elastic-brittle spring lattice\n"
    "(Affes et al., EPJE 35, 2012).  The sample is a cemented sample file (-sample_file,\n"
    "phases -phase_*) or a generated lattice (-lattice_*, thresholds -lattice_break_strain).\n"
    "Stresses are normalised by sigma^[p], the strength of the homogeneous lattice of the\n"
    "same geometry made of particle bonds, calibrated first (-fracture_calibrate).\n";

int main(int argc, char** argv) {
  return lem::run_driver(argc, argv, help, [](MPI_Comm comm) {
    const lem::SampleOptions sample = lem::read_sample_options(comm);
    const lem::FractureOptions protocol = lem::read_fracture_options(comm);
    const lem::FractureRunOptions run = lem::read_fracture_run_options(comm);
    const lem::SolverOptions solver = lem::read_solver_options(comm);
    lem::check_option_names(comm);
    const auto provenance = lem::collect_provenance(comm, "lem_fracture");
    lem::run_fracture_job(comm, sample, protocol, run, solver, provenance);
  }, lem::StopHandling::save_and_exit);
}
