#include "lem/packing/packing_file.hpp"

#include "lem/base/summary.hpp"

#include <cstdio>

namespace lem {

std::string spheres_csv(const CubeSample& cube) {
  std::string text = "x,y,z,radius\n";
  char line[128];
  for (const auto& s : cube.spheres) {
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g\n", s.centre[0], s.centre[1],
                  s.centre[2], s.radius);
    text += line;
  }
  return text;
}

namespace {

// What the sidecar of a spheres table is written from.
struct SpheresRecord {
  const CubeSample& cube;
  const Packing& packing;
  const PackingSpec& spec;
  const std::string& what;  // "cubic sample" or "periodic box"
  const std::string& file;  // the table it describes
};

using R = SpheresRecord;

const SummaryTable<R>& spheres_table() {
  static const SummaryTable<R> table = {
      {"file", "", "the spheres table it describes (`packing.csv`)",
       [](const R& r) { return r.file; }},
      {"description", "", "what the table holds and in which units",
       [](const R& r) {
         return "lem_pack " + r.what +
                ": sphere centres x, y, z and radii, lengths in the units of d_min";
       }},
      {"seed", "", "`-pack_seed`",
       [](const R& r) { return summary_count(static_cast<long long>(r.spec.seed)); }},
      {"d_min", "", "the smallest sphere diameter (`-pack_dmin`)",
       [](const R& r) { return r.spec.d_min; }},
      {"d_max", "", "the largest sphere diameter (`-pack_dmax`)",
       [](const R& r) { return r.spec.d_max; }},
      {"distribution", "", "`uniform_volume` or `uniform_diameter` (`-pack_distribution`)",
       [](const R& r) {
         return std::string(r.spec.distribution == SizeDistribution::uniform_volume
                                ? "uniform_volume"
                                : "uniform_diameter");
       }},
      {"box_side", "d_min", "the side of the periodic box",
       [](const R& r) { return r.packing.box_side; }},
      {"box_spheres", "", "spheres of the periodic box",
       [](const R& r) { return summary_count(static_cast<long long>(r.packing.spheres.size())); }},
      {"box_volume_fraction", "", "ρ^p of the periodic box",
       [](const R& r) { return r.packing.stats.volume_fraction; }},
      {"cube_side", "d_min", "the side of the cube (of the box for `packing_box.json`)",
       [](const R& r) { return r.cube.side; }},
      {"spheres", "", "rows of the table",
       [](const R& r) { return summary_count(static_cast<long long>(r.cube.spheres.size())); }},
      // The first centres_inside rows have their centres in the cube; the
      // others reach in from outside.
      {"centres_inside", "", "the first rows, whose centres are in the cube",
       [](const R& r) { return summary_count(r.cube.centres_inside); }},
      {"volume_fraction", "", "ρ^p of the spheres with centres inside",
       [](const R& r) { return r.cube.volume_fraction; }},
      {"region_volume_fraction", "", "ρ^p counting every sphere reaching in",
       [](const R& r) { return r.cube.region_volume_fraction; }},
  };
  return table;
}

}  // namespace

const std::vector<SummaryField>& packing_summary_fields() {
  static const std::vector<SummaryField> fields = described_fields(spheres_table());
  return fields;
}

std::string spheres_json(const CubeSample& cube, const Packing& packing, const PackingSpec& spec,
                         const Provenance& prov, const std::string& what, const std::string& file) {
  Summary s;
  s.add_from(spheres_table(), R{cube, packing, spec, what, file});
  s.add_provenance(prov);
  return s.json();
}

}  // namespace lem
