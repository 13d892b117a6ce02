// OptionGroup: parsing and checks of every value type, the registry behind
// -help and the provenance, and the option-name checks.
#include "lem/base/error.hpp"
#include "lem/base/options.hpp"

#include <gtest/gtest.h>
#include <petscksp.h>

#include <cstdint>
#include <limits>
#include <string>

namespace {

using lem::InputError;
using lem::OptionGroup;

// Sets an option for one test and removes it afterwards.
class Given {
 public:
  Given(const char* name, const char* value) : name_(name) {
    PetscOptionsSetValue(nullptr, name, value);
  }
  ~Given() { PetscOptionsClearValue(nullptr, name_); }

 private:
  const char* name_;
};

// The InputError message of f(), or "" if it does not throw one.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(Options, IntegersAreParsedStrictlyAndNeverWrap) {
  OptionGroup g(PETSC_COMM_WORLD, "Test integers");
  auto read = [&] { return g.integer("-lem_t_int", "an integer", 7, -10, 2'000'000'000); };
  EXPECT_EQ(read(), 7);
  {
    Given v("-lem_t_int", "-5");
    EXPECT_EQ(read(), -5);
  }
  {
    Given v("-lem_t_int", "1e6");
    EXPECT_EQ(read(), 1'000'000);
  }
  {
    Given v("-lem_t_int", "abc");
    const std::string e = error_of(read);
    EXPECT_TRUE(contains(e, "-lem_t_int = 'abc' is not a number")) << e;
  }
  {
    Given v("-lem_t_int", "1e20");
    EXPECT_TRUE(contains(error_of(read), "-lem_t_int = 1e20 is out of range"));
  }
  {
    Given v("-lem_t_int", "99999999999999999999");  // beyond int64: no wrap either
    EXPECT_TRUE(contains(error_of(read), "is out of range"));
  }
  {
    Given v("-lem_t_int", "1.5");
    EXPECT_TRUE(contains(error_of(read), "-lem_t_int = '1.5' is not an integer"));
  }
  {
    Given v("-lem_t_int", "-11");
    EXPECT_TRUE(contains(error_of(read), "-lem_t_int = -11 is out of range: allowed [-10, "));
  }
}

TEST(Options, RealsFlagsAndLists) {
  OptionGroup g(PETSC_COMM_WORLD, "Test values");
  {
    Given v("-lem_t_real", "2.5e-3");
    EXPECT_DOUBLE_EQ(g.real("-lem_t_real", "a real", 1.0, 0.0, 1.0), 2.5e-3);
  }
  {
    Given v("-lem_t_real", "x1");
    EXPECT_TRUE(contains(error_of([&] { g.real("-lem_t_real", "a real", 1.0, 0.0, 1.0); }),
                         "-lem_t_real = 'x1' is not a number"));
  }
  {
    Given v("-lem_t_real", "0");
    EXPECT_TRUE(contains(error_of([&] { g.real("-lem_t_real", "a real", 1.0, 0.0, 1.0, true); }),
                         "-lem_t_real = 0 is out of range: allowed (0, 1]"));
  }
  auto flag = [&] { return g.flag("-lem_t_flag", "a flag", false); };
  EXPECT_FALSE(flag());
  {
    Given v("-lem_t_flag", nullptr);  // the bare name
    EXPECT_TRUE(flag());
  }
  {
    Given v("-lem_t_flag", "No");
    EXPECT_FALSE(flag());
  }
  {
    Given v("-lem_t_flag", "maybe");
    EXPECT_TRUE(contains(error_of(flag), "-lem_t_flag = 'maybe' is not a boolean"));
  }
  auto list = [&] { return g.positive_reals("-lem_t_list", "reals", {1.0, 2.0, 3.0}); };
  {
    Given v("-lem_t_list", "1,0.5,2");
    EXPECT_EQ(list(), (std::vector<double>{1.0, 0.5, 2.0}));
  }
  {
    Given v("-lem_t_list", "1,abc,2");
    EXPECT_TRUE(contains(error_of(list), "'abc' is not a number"));
  }
  {
    Given v("-lem_t_list", "1,2");
    EXPECT_TRUE(contains(error_of(list), "takes 3 comma-separated values, got 2"));
  }
}

TEST(Options, NumbersAreWholeDecimalTexts) {
  OptionGroup g(PETSC_COMM_WORLD, "Test strict numbers");
  auto read = [&] { return g.integer("-lem_t_strict", "an integer", 7, -10, 1000); };
  for (const char* bad : {"0x10", "+-5", "5 ", "5x", "--5", "1e", ""}) {
    Given v("-lem_t_strict", bad);
    EXPECT_FALSE(error_of(read).empty()) << "accepted '" << bad << "'";
  }
  {
    Given v("-lem_t_strict", "+12");
    EXPECT_EQ(read(), 12);
  }
  // The whole int64 range, and not one past it (2^63 cannot be converted).
  const std::int64_t top = std::numeric_limits<std::int64_t>::max();
  auto wide = [&] { return g.integer("-lem_t_wide", "a wide integer", 0, 0, top); };
  {
    Given v("-lem_t_wide", "9223372036854775807");
    EXPECT_EQ(wide(), top);
  }
  for (const char* beyond : {"9223372036854775808", "9.3e18", "1e300"}) {
    Given v("-lem_t_wide", beyond);
    EXPECT_TRUE(contains(error_of(wide), "is out of range")) << beyond;
  }
  auto real = [&] { return g.real("-lem_t_strict_real", "a real", 1.0, 0.0, 10.0); };
  for (const char* bad : {"0x1p2", "1.5.2", "nan", "inf", "1e400"}) {
    Given v("-lem_t_strict_real", bad);
    EXPECT_FALSE(error_of(real).empty()) << "accepted '" << bad << "'";
  }
}

TEST(Options, AValueMustFollowEveryOptionButAFlag) {
  OptionGroup g(PETSC_COMM_WORLD, "Test missing values");
  const char* name = "-lem_t_missing";
  const std::string expected = "option -lem_t_missing is given without a value (help)";
  for (const char* value : {static_cast<const char*>(nullptr), ""}) {
    Given v(name, value);
    EXPECT_EQ(error_of([&] { g.integer(name, "help", 1, 0, 9); }), expected);
    EXPECT_EQ(error_of([&] { g.real(name, "help", 1, 0, 9); }), expected);
    EXPECT_EQ(error_of([&] { g.string(name, "help", "x"); }), expected);
    EXPECT_EQ(error_of([&] { g.positive_reals(name, "help", {1.0}); }), expected);
    EXPECT_TRUE(contains(error_of([&] {
                           g.choice<int>(name, "help", {{"a", 0}, {"b", 1}}, 0);
                         }),
                         "option -lem_t_missing is given without a value (help (a|b))"));
  }
}

TEST(Options, ValuesPetscRejectsNameTheirOption) {
  Given v("-lem_t_ksp_rtol", "abc");
  const std::string e = error_of([] {
    lem::read_petsc_options([] {
      PetscReal value = 0;
      PetscBool set = PETSC_FALSE;
      lem::take_over_petsc_errors();  // keeps PETSc's message for the PetscFailure
      const PetscErrorCode ierr =
          PetscOptionsGetReal(nullptr, nullptr, "-lem_t_ksp_rtol", &value, &set);
      PetscPopErrorHandler();
      LEM_PETSC(ierr);
    });
  });
  EXPECT_TRUE(contains(e, "option -lem_t_ksp_rtol = 'abc' is rejected by PETSc")) << e;
}

enum class Shape { round, square };

TEST(Options, ChoicesBecomeEnums) {
  OptionGroup g(PETSC_COMM_WORLD, "Test choices");
  auto read = [&] {
    return g.choice<Shape>("-lem_t_shape", "a shape",
                           {{"round", Shape::round}, {"square", Shape::square}}, Shape::round);
  };
  EXPECT_EQ(read(), Shape::round);
  {
    Given v("-lem_t_shape", "square");
    EXPECT_EQ(read(), Shape::square);
  }
  {
    Given v("-lem_t_shape", "oval");
    EXPECT_TRUE(contains(error_of(read), "-lem_t_shape = 'oval' is not one of: round|square"));
  }
}

TEST(Options, RegistryRecordsEveryOptionOnce) {
  {
    Given v("-lem_t_reg", "5");
    OptionGroup g(PETSC_COMM_WORLD, "Test registry");
    g.integer("-lem_t_reg", "registered", 3, 0, 10);
    g.integer("-lem_t_reg", "registered", 3, 0, 10);  // read twice: one entry
    g.petsc_default("-lem_t_ksp_default", "a solver default", "cg");
  }
  int count = 0;
  for (const auto& r : lem::registered_options()) {
    if (r.name != "-lem_t_reg") continue;
    ++count;
    EXPECT_EQ(r.group, "Test registry");
    EXPECT_EQ(r.help, "registered");
    EXPECT_EQ(r.default_value, "3");
    EXPECT_EQ(r.value, "5");
    EXPECT_TRUE(r.given);
  }
  EXPECT_EQ(count, 1);
  // The provenance lists the solver default while no option overrides it.
  EXPECT_TRUE(contains(lem::options_as_text(), "-lem_t_ksp_default cg"));
}

TEST(Options, UnknownNamesAreReportedWithTheNearestOne) {
  {
    OptionGroup g(PETSC_COMM_WORLD, "Test names");
    g.integer("-lem_t_nodes", "nodes", 1, 0, 10);
  }
  {
    Given v("-lem_t_ndoes", "3");
    const std::string e = error_of([] { lem::check_option_names(PETSC_COMM_WORLD); });
    EXPECT_TRUE(contains(e, "unknown option(s): -lem_t_ndoes (did you mean -lem_t_nodes?)")) << e;
  }
  {
    Given v("-ksp_type", "cgg");
    LEM_PETSC(KSPInitializePackage());
    const std::string e = error_of([] { lem::check_type_option("-ksp_type", KSPList, "KSP"); });
    EXPECT_TRUE(contains(e, "-ksp_type = 'cgg' is not a KSP type known to PETSc (did you "
                            "mean cg?)"))
        << e;
  }
  EXPECT_EQ(error_of([] { lem::check_option_names(PETSC_COMM_WORLD); }), "");
}

TEST(Options, UnusedSolverOptionsAreCheckedInTwoStages) {
  using lem::SolverStage;
  {
    Given v("-ksp_rtoll", "1e-3");
    EXPECT_TRUE(contains(error_of([] { lem::check_unused_options(SolverStage::created); }),
                         "never used (misspelt, or not valid for the chosen solver): -ksp_rtoll"));
  }
  {
    // Read only when the preconditioner is set up: left for the later check.
    Given v("-mg_levels_ksp_typo", "1");
    Given w("-pc_mg_typo", "1");
    EXPECT_EQ(error_of([] { lem::check_unused_options(SolverStage::created); }), "");
    const std::string e = error_of([] { lem::check_unused_options(SolverStage::solved); });
    EXPECT_TRUE(contains(e, "-mg_levels_ksp_typo") && contains(e, "-pc_mg_typo")) << e;
  }
}

}  // namespace
