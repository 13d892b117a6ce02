// Effective Young's modulus of cemented samples against the matrix volume
// fraction (Affes et al. 2012, sect. 3, figs. 5 and 11, appendix D;
// lem/run/stiffness_study.hpp).
//
//   mpirun -n 2 lem_stiffness -output_dir results/stiffness
//   /usr/bin/python3 tools/plot_stiffness.py results/stiffness
#include "lem/base/driver.hpp"
#include "lem/base/error.hpp"
#include "lem/base/options.hpp"
#include "lem/setup/sample_options.hpp"
#include "lem/setup/setup.hpp"
#include "lem/run/stiffness_study.hpp"

#include <string>

static const char help[] =
    "E_eff/E^[p] of cemented samples against the matrix fraction, bare and adhesive\n"
    "contacts, with the Hashin-Shtrikman estimates of appendix D (paper figs. 5, 11).\n";

int main(int argc, char** argv) {
  return lem::run_driver(argc, argv, help, [](MPI_Comm comm) {
    lem::StiffnessStudy study;
    study.spec = lem::read_cemented_sample_spec(comm);
    study.table = lem::read_phase_table(comm);
    {
      lem::OptionGroup g(comm, "Stiffness against matrix fraction");
      study.fractions = g.positive_reals("-stiffness_fractions",
                                         "Matrix fractions rho^m to run "
                                         "(the paper's eight by default; -matrix_fraction has "
                                         "no use here and is refused)",
                                         {0.06, 0.1, 0.13, 0.17, 0.2, 0.22, 0.24, 0.28}, true);
      if (g.given("-matrix_fraction"))
        throw lem::InputError("option -matrix_fraction has no use in lem_stiffness, which makes "
                              "a sample at each of -stiffness_fractions: give it there");
      study.request = lem::ResultFolder::read_request(g, "results/stiffness");
      study.halved_faces = lem::read_face_bond_option(g);
    }
    for (double f : study.fractions)
      if (f > 0.36)
        throw lem::InputError("option -stiffness_fractions: " + std::to_string(f) +
                              " is out of range (allowed: (0, 0.36], the pore space of a "
                              "dense packing)");
    if (study.fractions.size() < 2)
      throw lem::InputError(
          "option -stiffness_fractions: give at least two fractions for the fits");
    if (study.spec.generator != lem::LatticeGenerator::serial)
      throw lem::InputError("option -lattice_generator cells: lem_stiffness builds its samples "
                            "on one rank, with -lattice_generator serial only");
    const lem::SolverOptions solver = lem::read_solver_options(comm);
    lem::check_option_names(comm);
    const auto provenance = lem::collect_provenance(comm, "lem_stiffness");
    lem::run_stiffness_study(comm, study, solver, provenance);
  });
}
