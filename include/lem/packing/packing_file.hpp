// The files of a packing (lem_pack): a table of spheres and its sidecar.
#pragma once

#include "lem/packing/packing.hpp"
#include "lem/base/provenance.hpp"
#include "lem/base/summary.hpp"

#include <string>
#include <vector>

namespace lem {

/// "x,y,z,radius" and one row per sphere (17 digits).
std::string spheres_csv(const CubeSample& cube);

/// The sidecar of a spheres table (<name>.json): what it holds (`what`, the
/// table's `file`) and how it was made, written from the table of entries
/// that packing_summary_fields() describes, then the provenance.
std::string spheres_json(const CubeSample& cube, const Packing& packing, const PackingSpec& spec,
                         const Provenance& prov, const std::string& what, const std::string& file);

/// The entries of that sidecar, in their order (for the documentation).
const std::vector<SummaryField>& packing_summary_fields();

}  // namespace lem
