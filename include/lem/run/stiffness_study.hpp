// Effective Young's modulus of cemented samples against the matrix volume
// fraction (Affes et al. 2012, sect. 3, figs. 5 and 11, appendix D), the work
// of lem_stiffness.
//
// One packing and one lattice are built; for each matrix fraction the
// bridges are recalibrated and the sample is pulled elastically twice: with
// bare contacts (particle-particle bonds carry nothing, E^pp = 0) and with
// adhesive ones (E^pp = E^pm).  E_eff is normalised by E^[p], the modulus of
// a homogeneous lattice of the same nodes and bonds made of particle bonds,
// and compared with the appendix-D estimates.
#pragma once

#include "lem/sample/cemented_sample.hpp"
#include "lem/system/elastic_system.hpp"
#include "lem/base/provenance.hpp"
#include "lem/run/result_folder.hpp"

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

/// Build the sample, pull it at every fraction, write stiffness.csv,
/// fits.csv and the summary in request.dir.  Collective.
void run_stiffness_study(MPI_Comm comm, StiffnessStudy study, const SolverOptions& solver,
                         const Provenance& provenance);

}  // namespace lem
