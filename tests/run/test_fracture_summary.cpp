// Every program's summary is written from a table of entries, each with its
// name, unit, meaning and value (lem/run/programs.hpp lists them): names
// are unique and described, an entry without a value for a run is left
// out, an entry that no table describes is refused when the summary is
// written, each program's summary holds exactly its table's entries, and
// each table is the one of docs/reference/outputs.md (lem_fracture's: of
// docs/reference/fracture-outputs.md; LEM_WRITE_DOCS=1 rewrites the pages'
// tables from the code).  lem_fracture's table is
// src/run/fracture_summary.cpp, with the fields of the registered break
// rules and relaxation schemes after "relaxation".
#include "lem/base/summary.hpp"
#include "lem/packing/packing_file.hpp"
#include "lem/report/sample_summary.hpp"
#include "lem/report/tension_summary.hpp"
#include "lem/run/convergence_study.hpp"
#include "lem/run/fracture_summary.hpp"
#include "lem/run/programs.hpp"
#include "lem/run/stiffness_study.hpp"

#include "lem/protocol/registry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

using namespace lem;

namespace {

const std::string kEnd = "<!-- end -->";

// The marker line above the generated table of `what` in its page.
std::string begin_marker(const std::string& what) {
  return "<!-- begin: summary table of " + what +
         "; LEM_WRITE_DOCS=1 build/tests/test_fracture_summary rewrites it -->";
}

// The page of docs/reference/ that shows the summary table of `what`:
// lem_fracture's files have a page of their own, the others are on outputs.md.
std::string page_of(const std::string& what) {
  return what == "lem_fracture" ? "fracture-outputs.md" : "outputs.md";
}

std::string markdown_table(const std::vector<SummaryField>& fields) {
  std::string t = "| entry | meaning |\n|---|---|\n";
  for (const SummaryField& f : fields) {
    const std::string unit = *f.unit ? std::string("[") + f.unit + "]" : "";
    t += "| `" + std::string(f.name) + unit + "` | " + f.meaning + " |\n";
  }
  return t;
}

// Every table the page shows: the programs' and the provenance.
std::vector<ProgramSummary> page_tables() {
  auto tables = program_summaries();
  tables.push_back({"the provenance", provenance_summary_fields()});
  return tables;
}

std::vector<std::string> names_of(const std::vector<SummaryField>& fields,
                                  const std::set<std::string>& left_out = {}) {
  std::vector<std::string> names;
  for (const SummaryField& f : fields)
    if (!left_out.count(f.name)) names.push_back(f.name);
  return names;
}

}  // namespace

TEST(FractureSummary, FieldsAreUniqueAndDescribed) {
  for (const ProgramSummary& p : page_tables()) {
    std::set<std::string> names;
    for (const SummaryField& f : p.fields) {
      EXPECT_TRUE(names.insert(f.name).second) << p.program << ": " << f.name << " twice";
      EXPECT_GT(std::string(f.meaning).size(), 3u) << p.program << ": " << f.name;
    }
  }
}

TEST(FractureSummary, SchemesBringTheirFields) {
  // The local scheme's counts come from its registry entry, after
  // "relaxation", in the entry's order.
  const std::vector<SummaryField> fields = fracture_summary_fields();
  std::vector<std::string> names;
  for (const SummaryField& f : fields) names.emplace_back(f.name);
  const auto relaxation = std::find(names.begin(), names.end(), "relaxation");
  ASSERT_NE(relaxation, names.end());
  const std::vector<SummaryField>& local = relaxation_named("local").summary;
  ASSERT_EQ(local.size(), 6u);
  for (std::size_t k = 0; k < local.size(); ++k)
    EXPECT_EQ(relaxation[static_cast<std::ptrdiff_t>(k) + 1], local[k].name);
}

TEST(FractureSummary, AFieldOfAnotherEntryIsRefused) {
  BreakRuleEntry rule{"counting", "a rule that counts", make_all_critical_rule};
  rule.summary = {{"patch_solves", "", "the local scheme's name"}};
  const std::size_t rules = break_rules().size();
  EXPECT_THROW(register_break_rule(rule), std::invalid_argument);
  EXPECT_EQ(break_rules().size(), rules);
}

// An entry is written with its table's unit, and left out when its value
// function gives nothing for this record.
TEST(FractureSummary, EntriesAreValuedFromTheRecord) {
  struct Record {
    double x;
    bool has_y;
  };
  const SummaryTable<Record> table = {
      {"x", "s", "a number", [](const Record& r) { return r.x; }},
      {"y", "", "sometimes",
       [](const Record& r) -> std::optional<Summary::Value> {
         if (!r.has_y) return std::nullopt;
         return summary_count(2);
       }},
      {"z", "", "a word", [](const Record&) { return std::string("w"); }},
  };
  Summary with, without;
  with.add_from(table, Record{1.5, true});
  without.add_from(table, Record{1.5, false});
  EXPECT_EQ(with.csv(), "x[s],y,z\n1.5,2,w\n");
  EXPECT_EQ(without.csv(), "x[s],z\n1.5,w\n");
  EXPECT_TRUE(with.undescribed().empty());
  EXPECT_EQ(described_fields(table).size(), 3u);
}

TEST(FractureSummary, UnitsGoToTheCsvHeader) {
  const SampleOptions sample;
  const FractureOptions options;
  const FractureOutput units;
  const Calibration calibration;
  const SetupReport setup;
  const FractureResult result;
  const FractureRecord record{sample, options, units, calibration, setup, result, 1, 0, {}, {}, 1};
  Summary s;
  s.add_from(fracture_summary_table(), record);
  EXPECT_EQ(s.names(), names_of(fracture_summary_fields()));
  EXPECT_NE(s.csv().find(",sigma_unit[stress],E_unit[stress],"), std::string::npos);
  EXPECT_NE(s.csv().find(",seconds[s],peak_memory_mb[MB],"), std::string::npos);
}

// lem_pack's packing.json: its table's entries, then the provenance.
TEST(FractureSummary, PackingSidecarWritesItsTable) {
  Packing packing;
  packing.box_side = 4;
  CubeSample cube;
  cube.side = 2;
  Provenance provenance;
  provenance.program = "lem_pack";
  const std::string json =
      spheres_json(cube, packing, PackingSpec{}, provenance, "cubic sample", "packing.csv");
  std::vector<std::string> keys;
  std::istringstream lines(json);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("  \"", 0) == 0) keys.push_back(line.substr(3, line.find('"', 3) - 3));
  std::vector<std::string> expected = names_of(packing_summary_fields());
  for (const std::string& name : names_of(provenance_summary_fields())) expected.push_back(name);
  EXPECT_EQ(keys, expected);
  EXPECT_NE(json.find("\"file\": \"packing.csv\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"box_side\": 4,"), std::string::npos) << json;
}

// A summary file holds described entries only: one added beside its table
// is refused before anything is written.
TEST(FractureSummary, AnEntryOfNoTableIsNotWritten) {
  Summary s = convergence_summary(SampleOptions{});
  Provenance provenance;
  provenance.program = "lem_convergence";
  s.add_provenance(provenance);
  EXPECT_TRUE(s.undescribed().empty());
  s.add("extra", 1.0);
  EXPECT_EQ(s.undescribed(), std::vector<std::string>{"extra"});
  const auto stem = std::filesystem::temp_directory_path() / "lem_undescribed_summary";
  for (const char* ext : {".json", ".csv"}) std::filesystem::remove(stem.string() + ext);
  try {
    s.write(stem.string());
    ADD_FAILURE() << "a summary with an undescribed entry was written";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("'extra'"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(stem.string() + ".json"));
  EXPECT_FALSE(std::filesystem::exists(stem.string() + ".csv"));
}

// Each program's summary holds its table's entries, in order, and no other.
TEST(FractureSummary, TensionWritesItsTable) {
  SampleOptions generated;
  SetupReport setup;
  TensionResponse response;
  response.young_modulus = 2;
  const Summary s = tension_summary(generated, setup, 0.5, response, SolveReport{}, 2, {});
  const std::set<std::string> file_only = {"sample_file", "rho_p", "rho_m",
                                           "rho_v",       "E_p",   "E_eff_over_E_p"};
  EXPECT_EQ(s.names(), names_of(tension_summary_fields(), file_only));
  SampleOptions file = generated;
  file.sample_file = "x.h5";
  const Summary f = tension_summary(file, setup, 0.5, response, SolveReport{}, 2, {});
  EXPECT_EQ(f.names(), names_of(tension_summary_fields()));
  EXPECT_TRUE(f.undescribed().empty());
}

TEST(FractureSummary, SampleStiffnessConvergenceWriteTheirTables) {
  EXPECT_EQ(sample_summary(CementedSampleStats{}, CementedSampleSpec{}, "x.h5", {}).names(),
            names_of(sample_summary_fields()));
  EXPECT_EQ(stiffness_summary(StiffnessFindings{}).names(), names_of(stiffness_summary_fields()));
  EXPECT_EQ(convergence_summary(SampleOptions{}).names(), names_of(convergence_summary_fields()));
}

TEST(FractureSummary, OutputsPagesListTheTables) {
  const bool rewrite = std::getenv("LEM_WRITE_DOCS") != nullptr;
  for (const char* name : {"outputs.md", "fracture-outputs.md"}) {
    const std::string path = std::string(LEM_SOURCE_DIR) + "/docs/reference/" + name;
    std::ifstream in(path);
    ASSERT_TRUE(in) << "cannot read " << path;
    std::stringstream buffer;
    buffer << in.rdbuf();
    std::string page = buffer.str();
    for (const ProgramSummary& p : page_tables()) {
      if (page_of(p.program) != name) continue;
      const std::size_t begin = page.find(begin_marker(p.program));
      ASSERT_NE(begin, std::string::npos)
          << path << " has no generated summary table of " << p.program;
      const std::size_t body = page.find('\n', begin) + 1;
      const std::size_t end = page.find(kEnd, body);
      ASSERT_NE(end, std::string::npos);
      const std::string expected = markdown_table(p.fields);
      if (rewrite) {
        page.replace(body, end - body, expected);
        continue;
      }
      EXPECT_EQ(page.substr(body, end - body), expected)
          << path << ": the summary table of " << p.program << " differs from the code: run "
          << "LEM_WRITE_DOCS=1 test_fracture_summary to rewrite it";
    }
    if (rewrite) std::ofstream(path) << page;
  }
}
