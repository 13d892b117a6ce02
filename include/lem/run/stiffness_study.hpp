// Effective Young's modulus of cemented samples against the matrix volume
// fraction (Affes et al. 2012, sect. 3, figs. 5 and 11, appendix D), the work
// of lem_stiffness (stiffness_program, programs.hpp).
//
// One packing and one lattice are built; for each matrix fraction the
// bridges are recalibrated and the sample is pulled elastically twice: with
// bare contacts (particle-particle bonds carry nothing, E^pp = 0) and with
// adhesive ones (E^pp = E^pm).  E_eff is normalised by E^[p], the modulus of
// a homogeneous lattice of the same nodes and bonds made of particle bonds,
// and compared with the appendix-D estimates.
#pragma once

#include "lem/base/line_fit.hpp"
#include "lem/base/provenance.hpp"
#include "lem/base/summary.hpp"
#include "lem/run/result_folder.hpp"
#include "lem/sample/cemented_sample.hpp"
#include "lem/system/elastic_system.hpp"

#include <mpi.h>

#include <vector>

namespace lem {

struct StiffnessStudy {
  CementedSampleSpec spec;
  PhaseTable table;
  std::vector<double> fractions;  // the matrix fractions rho^m
  bool halved_faces = false;      // -lattice_face_bonds halved
  ResultFolder::Request request;  // -output_dir, -output_overwrite
};

/// The study's options (-stiffness_fractions and those of the sample,
/// the phases and the output), checked.  Collective.
StiffnessStudy read_stiffness_study(MPI_Comm comm);

/// Build the sample, pull it at every fraction, write stiffness.csv,
/// fits.csv and the summary in request.dir.  Collective.
void run_stiffness_study(MPI_Comm comm, StiffnessStudy study, const SolverOptions& solver,
                         const Provenance& provenance);

/// What the summary reports: the homogeneous lattice and the fits against
/// rho^m of E_bare/E^[p], E_adhesive/E^[p] and S^pm/S^p.
struct StiffnessFindings {
  double e_p = 0, e_m = 0, poisson = 0;  // E^[p], E^[m] (E^phi units), nu of the lattice
  bool halved_faces = false;
  LineFit bare, adhesive, coverage;
  double bare_over_em_at_highest = 0, adhesive_over_em_at_highest = 0;
};
/// lem_stiffness's summary entries, in their order.
const std::vector<SummaryField>& stiffness_summary_fields();
/// Its summary, before the provenance.
Summary stiffness_summary(const StiffnessFindings& findings);

}  // namespace lem
