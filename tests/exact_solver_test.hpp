// Fixture of MPI tests that compare numbers at the 1e-6 level: a tight
// solver tolerance, and the exact lattice without the regularising ground
// springs (pass `exact` to ElasticSystem).
#pragma once

#include "lem/system/elastic_system.hpp"

#include <gtest/gtest.h>
#include <petscsys.h>

/// The exact lattice: no ground springs.
inline lem::SolverOptions exact_solver_options() {
  lem::SolverOptions o;
  o.ground_stiffness = 0.0;
  return o;
}

class ExactSolverTest : public ::testing::Test {
 protected:
  void SetUp() override { PetscOptionsSetValue(nullptr, "-ksp_rtol", "1e-12"); }
  void TearDown() override { PetscOptionsClearValue(nullptr, "-ksp_rtol"); }
  const lem::SolverOptions exact = exact_solver_options();
};
