// Fixture of MPI tests that compare numbers at the 1e-6 level: a tight
// solver tolerance, and the exact lattice without the regularising ground
// springs (pass `exact` to ElasticSystem).
#pragma once

#include "lem/system/elastic_system.hpp"

#include <gtest/gtest.h>
#include <petscsys.h>

class ExactSolverTest : public ::testing::Test {
 protected:
  void SetUp() override { PetscOptionsSetValue(nullptr, "-ksp_rtol", "1e-12"); }
  void TearDown() override { PetscOptionsClearValue(nullptr, "-ksp_rtol"); }
  const lem::SolverOptions exact{0.0};
};
