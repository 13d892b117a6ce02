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

std::string spheres_json(const CubeSample& cube, const Packing& packing, const PackingSpec& spec,
                         const Provenance& prov, const std::string& what, const std::string& file) {
  Summary s;
  s.add("file", file);
  s.add("description", "lem_pack " + what +
                           ": sphere centres x, y, z and radii, lengths in "
                           "the units of d_min");
  s.add("seed", static_cast<long long>(spec.seed));
  s.add("d_min", spec.d_min);
  s.add("d_max", spec.d_max);
  s.add("distribution",
        std::string(spec.distribution == SizeDistribution::uniform_volume ? "uniform_volume"
                                                                          : "uniform_diameter"));
  s.add("box_side", packing.box_side, "d_min");
  s.add("box_spheres", static_cast<long long>(packing.spheres.size()));
  s.add("box_volume_fraction", packing.stats.volume_fraction);
  s.add("cube_side", cube.side, "d_min");
  s.add("spheres", static_cast<long long>(cube.spheres.size()));
  // The first centres_inside rows have their centres in the cube; the
  // others reach in from outside.
  s.add("centres_inside", static_cast<long long>(cube.centres_inside));
  s.add("volume_fraction", cube.volume_fraction);
  s.add("region_volume_fraction", cube.region_volume_fraction);
  s.add_provenance(prov);
  return s.json();
}

}  // namespace lem
