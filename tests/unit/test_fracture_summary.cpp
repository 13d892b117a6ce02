// lem_fracture's summary is written from one table of fields
// (src/run/fracture_summary.cpp): names are unique and described, a summary
// written out of the table's order is refused, and the table of
// docs/reference/outputs.md is the table of the code (LEM_WRITE_DOCS=1
// rewrites it from the code).
#include "lem/run/fracture_summary.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

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

TEST(FractureSummary, EntriesFollowTheTable) {
  Summary s;
  Summary::Described d(s, fracture_summary_fields());
  d.put("sample_file", std::string("x.h5"));
  EXPECT_THROW(d.put("active_bonds", 1LL), std::logic_error);  // "nodes" comes first
  d.put("nodes", 1LL);
  EXPECT_THROW(d.done(), std::logic_error);  // the rest is missing
  EXPECT_NE(s.csv().find("sample_file,nodes"), std::string::npos);
}

TEST(FractureSummary, UnitsGoToTheCsvHeader) {
  Summary s;
  Summary::Described d(s, fracture_summary_fields());
  for (const SummaryField& f : fracture_summary_fields()) d.put(f.name, 0.0);
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
