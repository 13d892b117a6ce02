// The parts of the fracture protocol that need no solver: the break rule's
// arithmetic, the preconditioner rebuild rule, threshold disorder, the
// time-left estimate, fingerprints and the checkpoint file format (the
// byte serialiser under it is tested in test_base).
#include "lem/base/error.hpp"
#include "lem/protocol/break_rule.hpp"
#include "lem/base/fingerprint.hpp"
#include "lem/protocol/checkpoint.hpp"
#include "lem/protocol/disorder.hpp"
#include "lem/protocol/preconditioner_policy.hpp"
#include "lem/protocol/progress.hpp"

#include <gtest/gtest.h>
#include <petscsys.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <unistd.h>

using namespace lem;

TEST(BreakRule, CriticalOnlyStrictlyAboveThresholdAndFloor) {
  EXPECT_TRUE(is_critical(1.0 + 1e-12, 1.0, 1e-6));
  EXPECT_FALSE(is_critical(1.0, 1.0, 1e-6));   // equal is not above
  EXPECT_FALSE(is_critical(-5.0, 1.0, 1e-6));  // never in compression
  // A zero threshold (bare contact) breaks only above the noise floor.
  EXPECT_FALSE(is_critical(1e-7, 0.0, 1e-6));
  EXPECT_TRUE(is_critical(2e-6, 0.0, 1e-6));
}

TEST(BreakRule, MostCriticalIsLargestRatioThenSmallestId) {
  Rupture a{}, b{}, c{};
  a.id = 7, a.ratio = 1.5;
  b.id = 3, b.ratio = 1.5;
  c.id = 1, c.ratio = 1.2;
  EXPECT_TRUE(more_critical(b, a));
  EXPECT_FALSE(more_critical(a, b));
  EXPECT_TRUE(more_critical(a, c));
}

TEST(BreakRule, FirstBreakingStepIsTheFirstStepAboveTheThreshold) {
  // Tension t at step n grows as m t / n: the returned m is the first step
  // with m t / n > f, for many (n, t, f).
  for (std::int64_t n : {1, 3, 17, 250}) {
    for (double t : {0.013, 0.5, 2.0, 7.25}) {
      for (double f : {0.01, 0.3, 1.0, 40.0}) {
        const double m = first_breaking_step(n, t, f, 0.0);
        EXPECT_GT(m * t / static_cast<double>(n), f) << n << " " << t << " " << f;
        EXPECT_LE((m - 1) * t / static_cast<double>(n), f) << n << " " << t << " " << f;
      }
    }
  }
  // The floor replaces a zero threshold.
  EXPECT_EQ(first_breaking_step(10, 1.0, 0.0, 0.25), 3.0);
}

TEST(BreakRule, DoubtBandAroundTheLevel) {
  // Within the band of a threshold, on either side.
  EXPECT_TRUE(in_doubt(1.0 + 5e-4, 1.0, 1e-3));
  EXPECT_TRUE(in_doubt(1.0 - 5e-4, 1.0, 1e-3));
  EXPECT_FALSE(in_doubt(1.0 + 2e-3, 1.0, 1e-3));  // certainly critical
  EXPECT_FALSE(in_doubt(1.0 - 2e-3, 1.0, 1e-3));  // certainly not
  EXPECT_FALSE(in_doubt(1.0, 1.0, 0.0));          // no band, no doubt
  // At a floor narrower than the band, the band stops at half the floor:
  // a force that is noise around zero is never in doubt.
  EXPECT_DOUBLE_EQ(doubt_edge(1e-6, 1e-5), 0.5e-6);
  EXPECT_FALSE(in_doubt(0.4e-6, 1e-6, 1e-5));
  EXPECT_FALSE(in_doubt(-0.4e-6, 1e-6, 1e-5));
  EXPECT_TRUE(in_doubt(0.6e-6, 1e-6, 1e-5));
  EXPECT_TRUE(in_doubt(1.05e-5, 1e-6, 1e-5));
  EXPECT_FALSE(in_doubt(1.2e-5, 1e-6, 1e-5));
  // Without a band the edge is the level, so the predicted step is the
  // first breaking step; with one, the step at which the band is entered.
  EXPECT_EQ(doubt_edge(0.3, 0.0), 0.3);
  EXPECT_EQ(first_breaking_step(10, 1.0, doubt_edge(0.25, 0.0), 0.0), 3.0);
  EXPECT_EQ(first_breaking_step(100, 1.0, doubt_edge(0.25, 0.01), 0.0), 25.0);
}

TEST(PreconditionerRule, RebuildsAfterEnoughRuptures) {
  RebuildRule rule{100, 0.0};
  PreconditionerState s;
  EXPECT_FALSE(rule.after_new_ruptures(s, 60));
  EXPECT_TRUE(rule.after_new_ruptures(s, 40));
  // A build resets the count.
  EXPECT_FALSE(rule.after_solve(s, 12, true, false));
  EXPECT_EQ(s.ruptures_since_build, 0);
  EXPECT_FALSE(rule.after_new_ruptures(s, 99));
  RebuildRule never{0, 0.0};
  EXPECT_FALSE(never.after_new_ruptures(s, 1'000'000));
}

TEST(PreconditionerRule, RebuildsWhenRelaxationSolvesGrowPastTheBaseline) {
  RebuildRule rule{0, 2.5};
  PreconditionerState s;
  EXPECT_FALSE(rule.after_solve(s, 18, true, false));  // a load step: no baseline
  EXPECT_EQ(s.baseline_iterations, 0);
  EXPECT_FALSE(rule.after_solve(s, 20, false, true));  // first relaxation solve: baseline
  EXPECT_EQ(s.baseline_iterations, 20);
  EXPECT_FALSE(rule.after_solve(s, 50, false, true));  // 2.5 x 20 is not above
  EXPECT_TRUE(rule.after_solve(s, 51, false, true));
  EXPECT_FALSE(rule.after_solve(s, 80, true, true));  // the new build sets a new baseline
  EXPECT_EQ(s.baseline_iterations, 80);
}

TEST(ThresholdDisorder, FactorsHaveTheirLawAndDependOnlyOnSeedAndId) {
  FractureOptions o;
  EXPECT_EQ(threshold_factor(o, 12), 1.0);
  o.disorder = ThresholdDisorder::uniform;
  o.disorder_width = 0.2;
  double sum = 0;
  const int n = 200000;
  for (int id = 0; id < n; ++id) {
    const double f = threshold_factor(o, id);
    ASSERT_GE(f, 0.8);
    ASSERT_LE(f, 1.2);
    sum += f;
  }
  // Within 4 standard errors of the mean (the factor's sd is w / sqrt 3).
  EXPECT_NEAR(sum / n, 1.0, 4 * 0.2 / std::sqrt(3.0 * n));
  EXPECT_EQ(threshold_factor(o, 41), threshold_factor(o, 41));
  const double before = threshold_factor(o, 41);
  o.disorder_seed = 2;
  EXPECT_NE(threshold_factor(o, 41), before);

  o.disorder = ThresholdDisorder::weibull;
  o.weibull_modulus = 6.0;
  double s1 = 0, s2 = 0;
  for (int id = 0; id < n; ++id) {
    const double f = threshold_factor(o, id);
    s1 += f, s2 += f * f;
  }
  const double mean = s1 / n, var = s2 / n - mean * mean;
  // Mean one by construction; variance Gamma(1+2/m)/Gamma(1+1/m)^2 - 1.
  const double g1 = std::tgamma(1 + 1 / 6.0), g2 = std::tgamma(1 + 2 / 6.0);
  EXPECT_NEAR(mean, 1.0, 4 * std::sqrt(var / n));
  EXPECT_NEAR(var, g2 / (g1 * g1) - 1, 0.02 * var);
}

TEST(TimeLeft, LinearDeclineIsExtrapolatedExactly) {
  TimeLeftEstimate e;
  // Before the peak: no estimate.
  EXPECT_FALSE(e.update(0, 1.0, 0.01, 1.0, 0.05, 0).has_value());
  // After it the stress falls by 0.01 per second: from 0.8 at t = 20 to the
  // stop level 0.05 takes 75 s.
  for (int t = 1; t <= 20; ++t) {
    const auto left = e.update(t, 1.0 - 0.01 * t, 0.01, 1.0, 0.05, 0);
    if (t > 1) {
      ASSERT_TRUE(left.has_value());
      EXPECT_NEAR(*left, (1.0 - 0.01 * t - 0.05) / 0.01, 1e-9);
    }
  }
  // A strain bound that comes first wins: strain grows 1e-3 per second.
  TimeLeftEstimate s;
  s.update(0, 0.9, 0.010, 1.0, 0.05, 0.020);
  const auto left = s.update(10, 0.89, 0.011, 1.0, 0.05, 0.020);
  ASSERT_TRUE(left.has_value());
  EXPECT_NEAR(*left, 90.0, 1e-9);
}

TEST(Checkpoint, FingerprintDifferencesNameTheLinesAndAllowOtherRankCounts) {
  const std::string ours = "ranks=2\nnodes=10\nincrement=0.0003\n";
  EXPECT_EQ(compare_fingerprints(ours, ours, "checkpoint").differs, "");
  EXPECT_EQ(compare_fingerprints(ours, ours, "checkpoint").other_ranks, 0);
  const auto one =
      compare_fingerprints("ranks=1\nnodes=10\nincrement=0.0003\n", ours, "checkpoint");
  EXPECT_EQ(one.differs, "");
  EXPECT_EQ(one.other_ranks, 1);
  const std::string d =
      compare_fingerprints("ranks=2\nnodes=10\nincrement=0.001\n", ours, "checkpoint").differs;
  EXPECT_NE(d.find("checkpoint: increment=0.001"), std::string::npos);
  EXPECT_NE(d.find("this run: increment=0.0003"), std::string::npos);
  EXPECT_NE(compare_fingerprints("ranks=2\n", ours, "checkpoint").differs, "");
}

// A removed option's unused value in a fingerprint written before the
// removal is no difference; another value of it is.
TEST(Checkpoint, FingerprintOfARemovedOptionAtItsUnusedValueAgrees) {
  const std::string ours = "nodes=10\n-solver_ritz_deflation=0\n";
  EXPECT_EQ(compare_fingerprints("nodes=10\n-solver_ritz_deflation=0\n"
                                 "-solver_soft_node_deflation=0\n",
                                 ours, "finished")
                .differs,
            "");
  const std::string d = compare_fingerprints("nodes=10\n-solver_ritz_deflation=0\n"
                                             "-solver_soft_node_deflation=0.3\n",
                                             ours, "finished")
                            .differs;
  EXPECT_NE(d.find("-solver_soft_node_deflation=0.3"), std::string::npos) << d;
}

// A line that only one side has is named, not "(a different option set)";
// the sums of a set-up on other ranks agree to 1e-10; solver options may
// differ where allowed (a checkpoint) and are named apart.
TEST(Checkpoint, FingerprintDifferencesNameAMissingOptionAndKeepSolverLinesApart) {
  const std::string ours = "nodes=10\nbond_length_mean=0.31427800000000001\n-ksp_rtol=1e-08\n"
                           "-lattice_ground_stiffness=0.001\n";
  const std::string theirs = "nodes=10\nbond_length_mean=0.31427800000000006\n-ksp_rtol=0.01\n";
  const auto d = compare_fingerprints(theirs, ours, "finished");
  EXPECT_NE(d.differs.find("finished: -lattice_ground_stiffness not set   this run: "
                           "-lattice_ground_stiffness=0.001"),
            std::string::npos)
      << d.differs;
  EXPECT_NE(d.differs.find("finished: -ksp_rtol=0.01   this run: -ksp_rtol=1e-08"),
            std::string::npos)
      << d.differs;
  EXPECT_EQ(d.differs.find("bond_length_mean"), std::string::npos) << d.differs;
  EXPECT_EQ(d.differs.find("different option set"), std::string::npos);
  const auto c = compare_fingerprints(theirs, ours, "checkpoint", true);
  EXPECT_EQ(c.differs.find("-ksp_rtol"), std::string::npos) << c.differs;
  EXPECT_NE(c.solver_changes.find("-ksp_rtol=0.01"), std::string::npos);
  EXPECT_NE(c.differs.find("-lattice_ground_stiffness"), std::string::npos);
  // A real change of the sums is a difference.
  EXPECT_NE(compare_fingerprints("bond_length_mean=0.30968\n", "bond_length_mean=0.314278\n",
                                 "file")
                .differs,
            "");
}

TEST(Fingerprint, OptionKinds) {
  EXPECT_EQ(option_kind("-lattice_ground_stiffness"), OptionKind::physics);
  EXPECT_EQ(option_kind("-ksp_rtol"), OptionKind::solver);
  EXPECT_EQ(option_kind("-pc_gamg_threshold"), OptionKind::solver);
  EXPECT_EQ(option_kind("-solver_operator"), OptionKind::solver);
  EXPECT_EQ(option_kind("-ksp_monitor"), OptionKind::outside);
  EXPECT_EQ(option_kind("-output_dir"), OptionKind::outside);
  EXPECT_EQ(option_kind("-output_fields"), OptionKind::physics);
  EXPECT_EQ(option_kind("-checkpoint_steps"), OptionKind::outside);
  EXPECT_EQ(option_kind("-sample_parallel"), OptionKind::outside);
  EXPECT_EQ(option_kind("-fracture_warn_energy"), OptionKind::outside);
  // A diagnostic that does not change the run does not identify it.
  EXPECT_EQ(option_kind("-solver_spectrum_solves"), OptionKind::outside);
  EXPECT_EQ(option_kind("-solver_spectrum_prefix"), OptionKind::outside);
  EXPECT_EQ(option_kind("-solver_cycle_precision"), OptionKind::solver);
}

namespace {
Checkpoint sample_checkpoint() {
  Checkpoint c;
  c.state.tally.steps = 1234;
  c.state.tally.broken = {5, 6, 0, 7, 8};
  c.state.tally.peak_stress = 0.125;
  c.state.batches = 3;
  c.state.files = {4096, 777};
  c.fingerprint = "ranks=2\nnodes=4\n";
  c.damage.bond_events = {11, 12, 40};
  c.damage.bond_batches = {1, 2, 3};
  c.damage.node_events = {2};
  c.damage.node_batches = {3};
  c.damage.build_batches = {0, 2};
  c.displacement = {0.0, 1e-3, -2e-3, 4.5, 0, 0, 1, 2, 3, 4, 5, 6};
  return c;
}

std::string temp_path(const char* name) {
  return (std::filesystem::temp_directory_path() /
          (std::string("lem_test_") + std::to_string(::getpid()) + name))
      .string();
}

// The nodes of sample_checkpoint's fields, in the order of its values.
const std::vector<std::int64_t> kIds = {2, 0, 3, 1};

void expect_refused(const std::string& path, const char* why) {
  try {
    read_checkpoint_file(PETSC_COMM_SELF, path, kIds);
    ADD_FAILURE() << "accepted a bad checkpoint (" << why << ")";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(Checkpoint, FileRoundTripsAndRefusesDamage) {
  const std::string path = temp_path("roundtrip.bin");
  const Checkpoint c = sample_checkpoint();
  write_checkpoint_file(PETSC_COMM_SELF, path, c, kIds);
  const Checkpoint r = read_checkpoint_file(PETSC_COMM_SELF, path, kIds);
  EXPECT_EQ(r.state.tally.steps, 1234);
  EXPECT_EQ(r.state.tally.broken, c.state.tally.broken);
  EXPECT_EQ(r.state.tally.peak_stress, 0.125);
  EXPECT_EQ(r.state.files.broken_bytes, 777);
  EXPECT_EQ(r.fingerprint, c.fingerprint);
  EXPECT_EQ(r.damage.bond_events, c.damage.bond_events);
  EXPECT_EQ(r.damage.node_batches, c.damage.node_batches);
  EXPECT_EQ(r.damage.build_batches, c.damage.build_batches);
  EXPECT_EQ(r.displacement, c.displacement);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));

  const auto size = std::filesystem::file_size(path);
  {  // one flipped byte in the middle
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2));
    f.put('\x5a');
  }
  expect_refused(path, "checksum mismatch");
  write_checkpoint_file(PETSC_COMM_SELF, path, c, kIds);
  std::filesystem::resize_file(path, size - 20);  // cut short
  expect_refused(path, "truncated or corrupt");
  // By id: another order of the same nodes reads the same values.
  write_checkpoint_file(PETSC_COMM_SELF, path, c, kIds);
  const Checkpoint sorted = read_checkpoint_file(PETSC_COMM_SELF, path, {0, 1, 2, 3});
  EXPECT_EQ(std::vector<double>(sorted.displacement.begin(), sorted.displacement.begin() + 3),
            std::vector<double>(c.displacement.begin() + 3, c.displacement.begin() + 6));
  {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f << "not a checkpoint at all, but long enough to have a header";
  }
  expect_refused(path, "wrong header");
  std::remove(path.c_str());
}
