// The files of a packing (lem_pack): a table of spheres and its sidecar.
#pragma once

#include "lem/packing/packing.hpp"
#include "lem/base/provenance.hpp"

#include <string>

namespace lem {

/// "x,y,z,radius" and one row per sphere (17 digits).
std::string spheres_csv(const CubeSample& cube);

/// The sidecar of a spheres table (<name>.json): what it holds (`what`, the
/// table's `file`) and how it was made.
std::string spheres_json(const CubeSample& cube, const Packing& packing, const PackingSpec& spec,
                         const Provenance& prov, const std::string& what, const std::string& file);

}  // namespace lem
