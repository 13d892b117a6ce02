#include "lem/system/partition.hpp"

#include "lem/base/error.hpp"

#include <metis.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <string>

namespace lem {
namespace {

// Spread the low 21 bits of x so that two zero bits separate each.
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

}  // namespace

std::uint64_t morton_code(const Point& p, const Box& box) {
  std::uint64_t code = 0;
  for (int a = 0; a < 3; ++a) {
    const double t = std::clamp((p[a] - box.lo[a]) / box.length(a), 0.0, 1.0);
    const auto q = static_cast<std::uint64_t>(t * 2097151.0);  // 2^21 - 1
    code |= spread_bits(q) << a;
  }
  return code;
}

Partition partition_lattice(const Lattice& lattice, const std::vector<char>& bond_active, int parts,
                            bool morton) {
  const std::size_t nodes = lattice.node_count();
  Partition p;
  p.parts = parts;
  p.owner.assign(nodes, 0);
  auto active = [&](std::size_t b) { return bond_active.empty() || bond_active[b]; };

  if (parts > 1) {
    std::uint64_t edges = 0;
    for (std::size_t b = 0; b < lattice.bond_count(); ++b) edges += active(b) ? 2 : 0;
    if (edges > static_cast<std::uint64_t>(std::numeric_limits<idx_t>::max()))
      throw InputError("the lattice has " + std::to_string(edges / 2) +
                       " bonds in the system: "
                       "more than the " +
                       std::to_string(std::numeric_limits<idx_t>::max() / 2) + " that METIS's " +
                       std::to_string(8 * sizeof(idx_t)) +
                       "-bit indices "
                       "can partition as one graph");
    // CSR adjacency of the active-bond graph.
    std::vector<idx_t> xadj(nodes + 1, 0);
    for (std::size_t b = 0; b < lattice.bond_count(); ++b)
      if (active(b)) {
        ++xadj[lattice.bonds[b].i + 1];
        ++xadj[lattice.bonds[b].j + 1];
      }
    for (std::size_t n = 0; n < nodes; ++n) xadj[n + 1] += xadj[n];
    std::vector<idx_t> adjncy(static_cast<std::size_t>(xadj[nodes]));
    std::vector<idx_t> fill(xadj.begin(), xadj.end() - 1);
    for (std::size_t b = 0; b < lattice.bond_count(); ++b)
      if (active(b)) {
        adjncy[fill[lattice.bonds[b].i]++] = lattice.bonds[b].j;
        adjncy[fill[lattice.bonds[b].j]++] = lattice.bonds[b].i;
      }
    idx_t nvtxs = static_cast<idx_t>(nodes), ncon = 1, nparts = parts, cut = 0;
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 12345;  // reproducible partitions
    std::vector<idx_t> part(nodes, 0);
    const int status =
        METIS_PartGraphKway(&nvtxs, &ncon, xadj.data(), adjncy.data(), nullptr, nullptr, nullptr,
                            &nparts, nullptr, nullptr, options, &cut, part.data());
    if (status != METIS_OK)
      throw std::runtime_error("METIS_PartGraphKway failed with status " + std::to_string(status));
    for (std::size_t n = 0; n < nodes; ++n) p.owner[n] = static_cast<int>(part[n]);
    p.edge_cut = cut;
  }

  // New numbering: by owner, then along the Morton curve (or kept order).
  std::vector<std::uint64_t> key(nodes, 0);
  if (morton)
    for (std::size_t n = 0; n < nodes; ++n) key[n] = morton_code(lattice.nodes[n], lattice.box);
  std::vector<std::int64_t> order(nodes);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) {
    if (p.owner[a] != p.owner[b]) return p.owner[a] < p.owner[b];
    if (key[a] != key[b]) return key[a] < key[b];
    return a < b;
  });
  p.new_index.assign(nodes, 0);
  for (std::size_t k = 0; k < nodes; ++k) p.new_index[order[k]] = static_cast<std::int64_t>(k);
  p.offsets.assign(parts + 1, 0);
  for (std::size_t n = 0; n < nodes; ++n) ++p.offsets[p.owner[n] + 1];
  for (int r = 0; r < parts; ++r) p.offsets[r + 1] += p.offsets[r];
  return p;
}

std::vector<int> partition_cells(const std::vector<std::int64_t>& weights,
                                 const std::vector<std::int64_t>& xadj,
                                 const std::vector<std::int64_t>& adjncy,
                                 const std::vector<std::int64_t>& adjwgt, int parts) {
  const std::size_t cells = weights.size();
  std::vector<int> out(cells, 0);
  if (parts <= 1 || cells == 0) return out;
  const auto fits = [](std::int64_t v) { return v <= std::numeric_limits<idx_t>::max(); };
  if (!fits(static_cast<std::int64_t>(cells)) || !fits(xadj.back()))
    throw InputError("the partition grid has " + std::to_string(cells) + " cells and " +
                     std::to_string(xadj.back() / 2) + " cell pairs: more than METIS's " +
                     std::to_string(8 * sizeof(idx_t)) + "-bit indices can partition");
  std::vector<idx_t> x(xadj.begin(), xadj.end()), a(adjncy.begin(), adjncy.end()),
      w(weights.size()), e(adjwgt.size());
  // Weights are summed by METIS over a part: they must stay in range.
  std::int64_t total = 0;
  for (std::size_t c = 0; c < cells; ++c) total += weights[c];
  const std::int64_t scale = total / std::numeric_limits<idx_t>::max() + 1;
  for (std::size_t c = 0; c < cells; ++c) w[c] = static_cast<idx_t>(weights[c] / scale);
  for (std::size_t k = 0; k < adjwgt.size(); ++k)
    e[k] = static_cast<idx_t>(
        std::min<std::int64_t>(adjwgt[k], std::numeric_limits<idx_t>::max() / 64));
  idx_t nvtxs = static_cast<idx_t>(cells), ncon = 1, nparts = parts, cut = 0;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = 12345;  // the same partition on every rank and run
  std::vector<idx_t> part(cells, 0);
  const int status =
      METIS_PartGraphKway(&nvtxs, &ncon, x.data(), a.data(), w.data(), nullptr, e.data(), &nparts,
                          nullptr, nullptr, options, &cut, part.data());
  if (status != METIS_OK)
    throw std::runtime_error("METIS_PartGraphKway failed on the cell graph with status " +
                             std::to_string(status));
  for (std::size_t c = 0; c < cells; ++c) out[c] = static_cast<int>(part[c]);
  return out;
}

}  // namespace lem
