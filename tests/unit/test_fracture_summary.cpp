// lem_fracture's summary is written from one table of fields
// (src/run/fracture_summary.cpp, with the fields of the registered break
// rules and relaxation schemes after "relaxation"): names are unique and
// described, a summary written out of the table's order is refused, and the table of
// docs/reference/outputs.md is the table of the code (LEM_WRITE_DOCS=1
// rewrites it from the code).
#include "lem/run/fracture_summary.hpp"

#include "lem/protocol/registry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

using namespace lem;

namespace {

const std::string kBegin = "<!-- begin: generated from src/run/fracture_summary.cpp";
const std::string kEnd = "<!-- end -->";

std::string markdown_table() {
  std::string t = "| entry | meaning |\n|---|---|\n";
  for (const SummaryField& f : fracture_summary_fields()) {
    const std::string unit = *f.unit ? std::string("[") + f.unit + "]" : "";
    t += "| `" + std::string(f.name) + unit + "` | " + f.meaning + " |\n";
  }
  return t;
}

}  // namespace

TEST(FractureSummary, FieldsAreUniqueAndDescribed) {
  std::set<std::string> names;
  for (const SummaryField& f : fracture_summary_fields()) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name << " twice";
    EXPECT_GT(std::string(f.meaning).size(), 3u) << f.name << " has no meaning";
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

TEST(FractureSummary, EntriesFollowTheTable) {
  Summary s;
  const std::vector<SummaryField> fields = fracture_summary_fields();
  Summary::Described d(s, fields);
  d.put("sample_file", std::string("x.h5"));
  EXPECT_THROW(d.put("active_bonds", 1LL), std::logic_error);  // "nodes" comes first
  d.put("nodes", 1LL);
  EXPECT_THROW(d.done(), std::logic_error);  // the rest is missing
  EXPECT_NE(s.csv().find("sample_file,nodes"), std::string::npos);
}

TEST(FractureSummary, UnitsGoToTheCsvHeader) {
  Summary s;
  const std::vector<SummaryField> fields = fracture_summary_fields();
  Summary::Described d(s, fields);
  for (const SummaryField& f : fields) d.put(f.name, 0.0);
  d.done();
  EXPECT_NE(s.csv().find(",sigma_unit[stress],E_unit[stress],"), std::string::npos);
  EXPECT_NE(s.csv().find(",seconds[s],peak_memory_mb[MB],"), std::string::npos);
}

TEST(FractureSummary, OutputsPageListsTheTable) {
  const std::string path = std::string(LEM_SOURCE_DIR) + "/docs/reference/outputs.md";
  std::ifstream in(path);
  ASSERT_TRUE(in) << "cannot read " << path;
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string page = buffer.str();
  const std::size_t begin = page.find(kBegin);
  ASSERT_NE(begin, std::string::npos) << path << " has no generated summary table";
  const std::size_t body = page.find('\n', begin) + 1;
  const std::size_t end = page.find(kEnd, body);
  ASSERT_NE(end, std::string::npos);
  const std::string expected = markdown_table();
  if (std::getenv("LEM_WRITE_DOCS")) {
    page.replace(body, end - body, expected);
    std::ofstream(path) << page;
    return;
  }
  EXPECT_EQ(page.substr(body, end - body), expected)
      << path << " differs from src/run/fracture_summary.cpp: run LEM_WRITE_DOCS=1 "
      << "test_fracture_summary to rewrite it";
}
