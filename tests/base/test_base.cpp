// The ground floor at one rank: phases, the atomic writer, the output
// folder's lock, manifest and replacement, exit statuses, PETSc handles, the
// byte serialiser, the cell grid.
#include "lem/base/byte_stream.hpp"
#include "lem/base/cell_grid.hpp"
#include "lem/sample/cemented_sample.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/base/petsc_handle.hpp"
#include "lem/base/phase.hpp"
#include "lem/base/summary.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <string>

using namespace lem;
namespace fs = std::filesystem;

TEST(Phases, NamesParseBackToTheirCodes) {
  for (int k = 0; k < kPhaseCount; ++k) {
    const Phase phase = static_cast<Phase>(k);
    ASSERT_TRUE(parse_phase(phase_name(phase)).has_value());
    EXPECT_EQ(*parse_phase(phase_name(phase)), phase);
  }
  EXPECT_STREQ(phase_name(Phase::pm), "pm");
  EXPECT_FALSE(parse_phase("mp").has_value());
  EXPECT_FALSE(parse_phase("").has_value());
}

TEST(Phases, TableDefaultsAreThePaperRatios) {
  const PhaseTable t;
  const auto at = [](Phase p) { return static_cast<int>(p); };
  EXPECT_EQ(t.modulus, kDefaultPhaseModulus);
  EXPECT_EQ(t.strength, kDefaultPhaseStrength);
  EXPECT_DOUBLE_EQ(t.modulus[at(Phase::p)], 3 * t.modulus[at(Phase::m)]);
  EXPECT_DOUBLE_EQ(t.modulus[at(Phase::pm)], t.modulus[at(Phase::m)]);
  EXPECT_DOUBLE_EQ(t.strength[at(Phase::p)], t.strength[at(Phase::m)]);
  EXPECT_EQ(t.strength[at(Phase::pp)], 0.0);
}

namespace {

class Files : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lem_files_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static std::string read(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  fs::path dir_;
};

}  // namespace

TEST_F(Files, TextReplacesTheFileWholeAndLeavesNoTemporary) {
  write_text_file_atomically(path("a.csv"), "x,y\n1,2\n");
  write_text_file_atomically(path("a.csv"), "x\n");
  EXPECT_EQ(read(path("a.csv")), "x\n");
  write_text_file_atomically(path("empty"), "");
  EXPECT_EQ(read(path("empty")), "");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 2);
}

TEST_F(Files, UnwritableTextNamesTheFile) {
  const std::string bad = path("no_such_dir/a.csv");
  try {
    write_text_file_atomically(bad, "x");
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
}

TEST_F(Files, MoveIntoPlacePublishesAndNamesBothFilesOnFailure) {
  { std::ofstream(path("log.part")) << "line\n"; }
  move_into_place(path("log.part"), path("log.csv"));
  EXPECT_EQ(read(path("log.csv")), "line\n");
  EXPECT_FALSE(fs::exists(path("log.part")));
  try {
    move_into_place(path("missing.part"), path("out.csv"));
    ADD_FAILURE() << "no error";
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("missing.part"), std::string::npos) << what;
    EXPECT_NE(what.find("out.csv"), std::string::npos) << what;
  }
}

TEST_F(Files, ASecondLockOnTheOutputDirectoryIsRefused) {
  const std::string dir = path("out");
  {
    const OutputLock first(MPI_COMM_SELF, dir);
    EXPECT_TRUE(fs::is_directory(dir));
    try {
      const OutputLock second(MPI_COMM_SELF, dir);
      ADD_FAILURE() << "a second lock was granted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("in use by another run"), std::string::npos) << e.what();
    }
  }
  const OutputLock again(MPI_COMM_SELF, dir);  // released with its holder
}

TEST_F(Files, ManifestListsTheCommittedFilesAndIsWithdrawnFirst) {
  { std::ofstream(path("curve.csv")) << "a,b\n1,2\n"; }
  { std::ofstream(path("summary.json")) << "{}"; }
  EXPECT_FALSE(read_manifest(dir_.string()).has_value());
  commit_results(dir_.string(), "prog", "x=1\ny=2\n", {"curve.csv", "summary.json"});
  const auto m = read_manifest(dir_.string());
  ASSERT_TRUE(m.has_value());
  EXPECT_EQ(m->program, "prog");
  EXPECT_EQ(m->fingerprint, "x=1\ny=2\n");
  ASSERT_EQ(m->files.size(), 2u);
  EXPECT_EQ(m->files[0], (std::pair<std::string, std::int64_t>{"curve.csv", 8}));
  EXPECT_EQ(manifest_mismatch(dir_.string(), *m), "");
  { std::ofstream(path("curve.csv"), std::ios::app) << "3,4\n"; }
  EXPECT_NE(manifest_mismatch(dir_.string(), *m).find("curve.csv has 12 bytes"), std::string::npos);
  // A manifest cut short is refused, not half believed.
  const std::string text = read(path("manifest.txt"));
  { std::ofstream(path("manifest.txt")) << text.substr(0, text.find("end")); }
  EXPECT_THROW(read_manifest(dir_.string()), InputError);
  withdraw_results(dir_.string(), {"curve.csv"});
  EXPECT_FALSE(fs::exists(path("manifest.txt")));
  EXPECT_FALSE(fs::exists(path("curve.csv")));
  EXPECT_TRUE(fs::exists(path("summary.json")));
}

namespace {

// A folder holding a committed result whose curve.csv is `curve`.
void committed(const std::string& dir, const std::string& curve) {
  fs::create_directories(dir);
  { std::ofstream(dir + "/curve.csv") << curve; }
  commit_results(dir, "prog", "x=1\n", {"curve.csv"});
}

bool own_names(const std::string& name) { return name == "curve.csv" || name == "plot.png"; }

}  // namespace

TEST_F(Files, StagingFolderIsOursOnlyWhenStampedOrBare) {
  const std::string dir = path("out"), staging = path("out.overwrite");
  EXPECT_EQ(staging_dir(dir + "/"), staging);
  EXPECT_EQ(staging_state(dir), StagingState::none);
  fs::create_directories(staging);
  { std::ofstream(staging + "/.lock"); }
  EXPECT_EQ(staging_state(dir), StagingState::ours);  // made by a run killed at once
  { std::ofstream(staging + "/notes.txt") << "mine"; }
  EXPECT_EQ(staging_state(dir), StagingState::foreign);
  fs::create_directories(dir);
  prepare_staging(dir);  // stamps it
  EXPECT_EQ(staging_state(dir), StagingState::ours);
  EXPECT_TRUE(clear_staging(dir));
  EXPECT_FALSE(fs::exists(staging + "/notes.txt"));
  EXPECT_EQ(staging_state(dir), StagingState::ours);
}

TEST_F(Files, InstallResultReplacesTheFolderAndKeepsWhatIsNotTheResults) {
  for (const bool one_rename : {true, false}) {
    const std::string dir = path(one_rename ? "a" : "b");
    committed(dir, "old\n");
    { std::ofstream(dir + "/run.json") << "{}"; }   // a study's: kept
    { std::ofstream(dir + "/plot.png") << "old"; }  // drawn from the old result: not
    fs::create_directories(staging_dir(dir));
    const bool exchange = prepare_staging(dir) && one_rename;
    committed(staging_dir(dir), "new\n");
    install_result(dir, exchange, own_names);
    EXPECT_EQ(read(dir + "/curve.csv"), "new\n");
    EXPECT_EQ(manifest_mismatch(dir, *read_manifest(dir)), "");
    EXPECT_TRUE(fs::exists(dir + "/run.json"));
    for (const char* gone : {"/plot.png", "/.overwrite_of", "/.superseded", "/.replaced"})
      EXPECT_FALSE(fs::exists(dir + gone)) << gone;
    EXPECT_FALSE(fs::exists(staging_dir(dir)));
    EXPECT_EQ(finish_replacement(dir, own_names), "");
  }
}

TEST_F(Files, ReplacementCutBetweenItsTwoRenamesIsFinished) {
  const std::string dir = path("out"), staging = staging_dir(dir);
  committed(dir, "old\n");
  { std::ofstream(dir + "/run.json") << "{}"; }
  fs::create_directories(staging);
  prepare_staging(dir);
  committed(staging, "new\n");
  fs::rename(dir, staging + "/.replaced");    // the first rename; then killed
  const OutputLock lock(MPI_COMM_SELF, dir);  // the next run makes the folder again
  EXPECT_NE(finish_replacement(dir, own_names).find("in place"), std::string::npos);
  EXPECT_EQ(read(dir + "/curve.csv"), "new\n");
  EXPECT_TRUE(fs::exists(dir + "/run.json"));
  EXPECT_FALSE(fs::exists(dir + "/.replaced"));
  EXPECT_FALSE(fs::exists(staging));
}

TEST(Errors, ExitStatusFollowsTheType) {
  EXPECT_EQ(exit_status(IoError("x")), 3);
  EXPECT_EQ(exit_status(InputError("x")), 1);
  EXPECT_EQ(exit_status(NumericalError("x")), 2);
  EXPECT_EQ(exit_status(PetscFailure("KSPSolve", 1)), 3);
  EXPECT_EQ(exit_status(std::runtime_error("x")), 3);
  EXPECT_EQ(exit_status(Interrupted("x")), 4);
  EXPECT_EQ(exit_status(HelpShown("x")), 0);
}

TEST(Summary, CsvHeaderKeepsOneColumnPerEntryWhateverTheUnitSays) {
  Summary s;
  s.add("peak_memory_mb", 12.5, "MB, largest rank");
  s.add("note", std::string("a, b"));
  const std::string csv = s.csv();
  const std::string head = csv.substr(0, csv.find('\n'));
  EXPECT_EQ(head, "peak_memory_mb[MB  largest rank],note");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), ','), 2);
}

TEST(PetscHandles, DestroyTheirObjectAndMoveOwnership) {
  VecHandle v;
  ASSERT_EQ(VecCreateSeq(PETSC_COMM_SELF, 4, v.replace()), 0);
  ASSERT_TRUE(v);
  // A second reference shows when the handle lets go of its own.
  Vec watcher = v;
  ASSERT_EQ(PetscObjectReference(reinterpret_cast<PetscObject>(watcher)), 0);
  PetscInt references = 0;
  PetscObjectGetReference(reinterpret_cast<PetscObject>(watcher), &references);
  EXPECT_EQ(references, 2);
  {
    VecHandle moved(std::move(v));
    EXPECT_FALSE(v);
    EXPECT_EQ(moved.get(), watcher);
  }
  PetscObjectGetReference(reinterpret_cast<PetscObject>(watcher), &references);
  EXPECT_EQ(references, 1);
  VecDestroy(&watcher);
}

TEST(ByteStream, RoundTripAndShortInput) {
  ByteWriter w;
  w.pod(std::int64_t{-7});
  w.vec(std::vector<double>{1.5, 2.5});
  w.str("pm");
  ByteReader r(w.bytes, w.bytes.size());
  std::int64_t i = 0;
  std::vector<double> v;
  std::string s;
  r.pod(i);
  r.vec(v);
  r.str(s);
  EXPECT_EQ(i, -7);
  EXPECT_EQ(v, (std::vector<double>{1.5, 2.5}));
  EXPECT_EQ(s, "pm");
  EXPECT_TRUE(r.at_end());
  ByteReader short_reader(w.bytes, 4);
  EXPECT_THROW(short_reader.pod(i), std::runtime_error);
}

TEST(CellGrid, FindsEveryPointWithinTheCellSide) {
  const Box box{{0.0, -1.0, 2.0}, {1.0, 0.5, 2.3}};  // thinner than a cell along z
  const double radius = 0.13;
  std::mt19937_64 g(4);
  std::uniform_real_distribution<double> u(-0.05, 1.05);  // some points outside the box
  std::vector<Point> points(400);
  for (Point& p : points)
    for (int a = 0; a < 3; ++a) p[a] = box.lo[a] + u(g) * box.length(a);
  const CellGrid grid(box, radius);
  std::vector<std::vector<int>> cells(grid.cell_count());
  for (std::size_t i = 0; i < points.size(); ++i)
    cells[grid.cell_of(points[i])].push_back(static_cast<int>(i));
  const auto close = [&](const Point& p, const Point& q) {
    const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return dx * dx + dy * dy + dz * dz < radius * radius;
  };
  for (const Point& p : points) {
    std::set<int> found, expected;
    grid.for_each_cell_near(p, [&](std::size_t cell) {
      for (int q : cells[cell])
        if (close(p, points[q])) found.insert(q);
      return true;
    });
    for (std::size_t q = 0; q < points.size(); ++q)
      if (close(p, points[q])) expected.insert(static_cast<int>(q));
    ASSERT_EQ(found, expected);
  }
  // A box registered in every cell it touches is found from any point inside.
  const Point lo{0.2, -0.4, 2.05}, hi{0.6, 0.1, 2.2};
  std::set<std::size_t> touched;
  grid.for_each_cell_touching(lo, hi, [&](std::size_t cell) { touched.insert(cell); });
  for (const Point& p : points) {
    bool inside = true;
    for (int a = 0; a < 3; ++a) inside = inside && p[a] >= lo[a] && p[a] <= hi[a];
    if (inside) {
      EXPECT_TRUE(touched.count(grid.cell_of(p)));
    }
  }
}
