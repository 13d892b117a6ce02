// Reading the cemented sample file (lem/sample/sample_reader.hpp), whole on one rank
// or by blocks of rows on every rank, with checks of everything it loads so
// that a wrong or damaged file is one clear message.
#include "lem/sample/sample_reader.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/io/hdf5_util.hpp"
#include "lem/base/redistribute.hpp"

#include "sample_checks.hpp"
#include "sample_layout.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <system_error>
#include <type_traits>

namespace lem {
namespace {

namespace fs = std::filesystem;
using h5::Handle;
using namespace sample_layout;

// ---------------------------------------------------------------------------
// Reading
// ---------------------------------------------------------------------------

class SampleReader {
 public:
  /// With `comm`, every rank of it opens the file (collective) through MPI-IO.
  explicit SampleReader(const std::string& path, MPI_Comm comm = MPI_COMM_NULL) : path_(path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) throw InputError("sample file '" + path + "' does not exist");
    if (fs::is_directory(path, ec))
      throw InputError("sample file '" + path + "' is a directory, not a file");
    if (H5Fis_hdf5(path.c_str()) <= 0)
      throw InputError("sample file '" + path + "' is not a readable HDF5 file");
    Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (comm != MPI_COMM_NULL && H5Pset_fapl_mpio(access.get(), comm, MPI_INFO_NULL) < 0)
      throw InputError("sample file '" + path + "' cannot be opened through MPI-IO");
    file_ = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, access.get()), H5Fclose);
    if (!file_.valid())
      throw InputError("sample file '" + path +
                       "' is not a readable HDF5 file (damaged or "
                       "truncated?)");
  }

  [[noreturn]] void corrupt(const std::string& what) const {
    throw InputError("sample file '" + path_ + "' is corrupt: " + what);
  }

  bool has_attribute(const char* name) const { return H5Aexists(file_.get(), name) > 0; }

  std::string text(const std::string& name) const {
    Handle attribute(H5Aopen(file_.get(), name.c_str(), H5P_DEFAULT), H5Aclose);
    if (!attribute.valid()) corrupt("attribute '" + name + "' is missing");
    Handle stored(H5Aget_type(attribute.get()), H5Tclose);
    if (!stored.valid() || H5Tget_class(stored.get()) != H5T_STRING ||
        H5Tis_variable_str(stored.get()) <= 0)
      corrupt("attribute '" + name + "' is not a string");
    // Read with the stored type: HDF5 does not convert between character sets.
    char* value = nullptr;
    if (H5Aread(attribute.get(), stored.get(), &value) < 0)
      corrupt("attribute '" + name + "' cannot be read");
    std::string out = value != nullptr ? value : "";
    H5free_memory(value);
    return out;
  }

  /// A numeric attribute with `count` values.
  template <class T>
  void numbers(const std::string& name, T* out, hssize_t count = 1) const {
    Handle attribute(H5Aopen(file_.get(), name.c_str(), H5P_DEFAULT), H5Aclose);
    if (!attribute.valid()) corrupt("attribute '" + name + "' is missing");
    Handle space(H5Aget_space(attribute.get()), H5Sclose);
    Handle stored(H5Aget_type(attribute.get()), H5Tclose);
    const H5T_class_t cls = stored.valid() ? H5Tget_class(stored.get()) : H5T_NO_CLASS;
    if (!space.valid() || H5Sget_simple_extent_npoints(space.get()) != count ||
        (cls != H5T_INTEGER && cls != H5T_FLOAT))
      corrupt("attribute '" + name + "' is not " + std::to_string(count) + " number(s)");
    if (H5Aread(attribute.get(), hdf5_types<T>().second, out) < 0)
      corrupt("attribute '" + name + "' cannot be read");
  }

  /// A dataset of `columns` values per row (0: 1-D) and of `rows` rows, or
  /// of any row count (rows < 0), which is then stored in `rows`.
  template <class T>
  std::vector<T> dataset(const std::string& name, std::int64_t& rows, hsize_t columns = 0) const {
    Handle set = checked<T>(name, rows, columns);
    std::vector<T> values(static_cast<std::size_t>(rows) * (columns == 0 ? 1 : columns));
    if (!values.empty() && H5Dread(set.get(), hdf5_types<T>().second, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                                   values.data()) < 0)
      corrupt("dataset " + name + " cannot be read (truncated file?)");
    return values;
  }

  /// Rows [begin, begin + count) of a dataset of `total` rows (checked) and
  /// `columns` values per row (0: 1-D).
  template <class T>
  std::vector<T> rows(const std::string& name, std::int64_t total, hsize_t columns,
                      std::int64_t begin, std::int64_t count) const {
    Handle set = checked<T>(name, total, columns);
    const hsize_t width = columns == 0 ? 1 : columns;
    std::vector<T> values(static_cast<std::size_t>(count) * width);
    Handle file_space(H5Dget_space(set.get()), H5Sclose);
    const hsize_t start[2] = {static_cast<hsize_t>(begin), 0};
    const hsize_t counts[2] = {static_cast<hsize_t>(count), width};
    const int rank = columns == 0 ? 1 : 2;
    Handle memory_space(H5Screate_simple(rank, counts, nullptr), H5Sclose);
    bool ok = file_space.valid() && memory_space.valid();
    if (ok && count == 0) {
      ok = H5Sselect_none(file_space.get()) >= 0 && H5Sselect_none(memory_space.get()) >= 0;
    } else if (ok) {
      ok = H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, counts, nullptr) >=
           0;
    }
    T dummy{};  // never written: the selection is empty
    if (!ok || H5Dread(set.get(), hdf5_types<T>().second, memory_space.get(), file_space.get(),
                       H5P_DEFAULT, values.empty() ? &dummy : values.data()) < 0)
      corrupt("dataset " + name + " rows " + std::to_string(begin) + " to " +
              std::to_string(begin + count) + " cannot be read (truncated file?)");
    return values;
  }

 private:
  /// The open dataset, its dimensions checked (see dataset()).
  template <class T>
  Handle checked(const std::string& name, std::int64_t& rows, hsize_t columns) const {
    Handle set(H5Dopen2(file_.get(), name.c_str(), H5P_DEFAULT), H5Dclose);
    if (!set.valid()) corrupt("dataset " + name + " is missing");
    Handle space(H5Dget_space(set.get()), H5Sclose);
    Handle stored(H5Dget_type(set.get()), H5Tclose);
    const int rank = columns == 0 ? 1 : 2;
    hsize_t dims[2] = {0, 0};
    if (!space.valid() || !stored.valid() || H5Sget_simple_extent_ndims(space.get()) != rank)
      corrupt("dataset " + name + " should have " + std::to_string(rank) + " dimension(s)");
    H5Sget_simple_extent_dims(space.get(), dims, nullptr);
    const bool want_float = std::is_floating_point_v<T>;
    if (H5Tget_class(stored.get()) != (want_float ? H5T_FLOAT : H5T_INTEGER))
      corrupt("dataset " + name + " should hold " + (want_float ? "reals" : "integers"));
    // Reals narrower than T would be widened on reading, their rounding
    // kept: nodes moved off the box faces read as a disconnected sample.
    if (want_float && H5Tget_size(stored.get()) < sizeof(T))
      corrupt("dataset " + name + " holds " + std::to_string(H5Tget_size(stored.get())) +
              "-byte reals; a sample stores " + std::to_string(sizeof(T)) +
              "-byte ones (lem_sample writes them; a copy converted to single precision has "
              "lost the nodes' places)");
    if (rank == 2 && dims[1] != columns)
      corrupt("dataset " + name + " has " + std::to_string(dims[1]) + " columns, expected " +
              std::to_string(columns));
    const auto found = static_cast<std::int64_t>(dims[0]);
    if (rows >= 0 && found != rows)
      corrupt("dataset " + name + " has " + std::to_string(found) + " rows, expected " +
              std::to_string(rows));
    rows = found;
    return set;
  }

  std::string path_;
  Handle file_;
};

// Each check names the dataset and its first bad row (rows counted from
// `first_row`, the file row of values[0]).
template <class T>
void check_range(const SampleReader& r, const std::vector<T>& values, std::int64_t lo,
                 std::int64_t hi, const std::string& dataset, std::size_t columns = 1,
                 std::int64_t first_row = 0) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    const auto v = static_cast<std::int64_t>(values[k]);
    if (v < lo || v > hi)
      r.corrupt(dataset + " row " +
                std::to_string(first_row + static_cast<std::int64_t>(k / columns)) + " holds " +
                std::to_string(v) + ", out of range [" + std::to_string(lo) + ", " +
                std::to_string(hi) + "]");
  }
}

// Everything but the node and bond rows: the format, the attributes, the
// provenance, the particles and the bridges (checked).
SampleFile read_description(const SampleReader& r, const std::string& path) {
  if (!r.has_attribute("format") || r.text("format") != kSampleFormat)
    throw InputError("'" + path + "' is not a lem cemented-sample file (no format attribute '" +
                     std::string(kSampleFormat) + "'; make one with lem_sample)");
  std::int64_t version = 0;
  r.numbers("format_version", &version);
  if (version != kSampleFormatVersion)
    throw InputError("sample file '" + path + "' has format_version " + std::to_string(version) +
                     "; this program reads version " + std::to_string(kSampleFormatVersion) +
                     " (rebuild the sample with this lem_sample)");

  SampleFile f;
  CementedSample& s = f.sample;
  visit_structure(s.stats, f.spec,
                  [&](const std::string& name, auto& value) { r.numbers(name, &value); });
  visit_statistics(s.stats, [&](const std::string& name, auto& value) {
    if (r.has_attribute(name.c_str())) r.numbers(name, &value);
  });
  const std::string distribution = r.text("packing_distribution");
  const std::string law = r.text("packing_law");
  if (distribution != distribution_name(SizeDistribution::uniform_diameter) &&
      distribution != distribution_name(SizeDistribution::uniform_volume))
    r.corrupt("unknown packing_distribution '" + distribution + "'");
  f.spec.packing.distribution = distribution == "uniform_volume"
                                    ? SizeDistribution::uniform_volume
                                    : SizeDistribution::uniform_diameter;
  if (law != law_name(ContactLaw::linear) && law != law_name(ContactLaw::hertz))
    r.corrupt("unknown packing_law '" + law + "'");
  f.spec.packing.law = law == law_name(ContactLaw::hertz) ? ContactLaw::hertz : ContactLaw::linear;
  // Files written before the rule was a choice used any_end.
  if (r.has_attribute("void_bonds")) {
    const std::string rule = r.text("void_bonds");
    if (rule != void_rule_name(VoidRule::any_end) && rule != void_rule_name(VoidRule::both_ends))
      r.corrupt("unknown void_bonds '" + rule + "'");
    f.spec.bridges.void_bonds =
        rule == void_rule_name(VoidRule::both_ends) ? VoidRule::both_ends : VoidRule::any_end;
  }
  // Files written before the cells generator: serial.
  if (r.has_attribute("lattice_generator")) {
    const std::string generator = r.text("lattice_generator");
    if (generator != generator_name(LatticeGenerator::serial) &&
        generator != generator_name(LatticeGenerator::cells))
      r.corrupt("unknown lattice_generator '" + generator + "'");
    f.spec.generator = generator == generator_name(LatticeGenerator::cells)
                           ? LatticeGenerator::cells
                           : LatticeGenerator::serial;
  }
  r.numbers("box_lo", s.lattice.box.lo.data(), 3);
  r.numbers("box_hi", s.lattice.box.hi.data(), 3);
  f.spec.lattice.box = s.lattice.box;
  const std::string box_problem = first_box_problem(s.lattice.box);
  if (!box_problem.empty()) r.corrupt(box_problem);

  Provenance& prov = f.provenance;
  prov.program = r.text("program");
  prov.version = r.text("version");
  prov.git_hash = r.text("git_hash");
  prov.options = r.text("options");
  prov.start_time = r.text("start_time");
  std::int64_t ranks = 0;
  r.numbers("ranks", &ranks);
  prov.ranks = static_cast<int>(ranks);

  std::int64_t p = -1;
  const auto centres = r.dataset<double>("/particles/centres", p, 3);
  if (p != s.stats.particles)
    r.corrupt(std::to_string(p) +
              " particle rows but attribute particles = " + std::to_string(s.stats.particles));
  const auto radii = r.dataset<double>("/particles/radii", p);
  s.particles.resize(static_cast<std::size_t>(p));
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    std::copy(&centres[3 * i], &centres[3 * i] + 3, s.particles[i].centre.begin());
    s.particles[i].radius = radii[i];
    if (!(std::isfinite(radii[i]) && radii[i] > 0))
      r.corrupt("/particles/radii row " + std::to_string(i) + " = " + value_text(radii[i]) +
                " is not a finite positive radius");
  }

  std::int64_t nb = -1;
  const auto pairs = r.dataset<std::int32_t>("/bridges/particles", nb, 2);
  const auto lambda = r.dataset<double>("/bridges/lambda", nb);
  check_range(r, pairs, 0, p - 1, "/bridges/particles", 2);
  s.bridges.resize(static_cast<std::size_t>(nb));
  for (std::size_t k = 0; k < s.bridges.size(); ++k)
    s.bridges[k] = {pairs[2 * k], pairs[2 * k + 1], lambda[k]};
  const std::string problem = first_description_problem(s);
  if (!problem.empty()) r.corrupt(problem);
  return f;
}

// Node rows [begin, begin + count) into `b` (coordinates, volumes, particles
// and phase codes checked row by row).
void read_node_rows(const SampleReader& r, const SampleFile& f, std::int64_t begin,
                    std::int64_t count, SampleBlock& b) {
  const std::int64_t n = f.sample.stats.nodes;
  const auto particles = static_cast<std::int64_t>(f.sample.particles.size());
  const auto coords = r.rows<double>("/nodes/coordinates", n, 3, begin, count);
  b.coords.resize(static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < b.coords.size(); ++i)
    std::copy(&coords[3 * i], &coords[3 * i] + 3, b.coords[i].begin());
  b.volume = r.rows<double>("/nodes/volume", n, 0, begin, count);
  const std::string problem = first_node_problem(f.sample.lattice.box, b.coords, b.volume, begin);
  if (!problem.empty()) r.corrupt(problem);
  b.particle = r.rows<std::int32_t>("/nodes/particle", n, 0, begin, count);
  check_range(r, b.particle, -1, particles - 1, "/nodes/particle", 1, begin);
  const auto codes = r.rows<std::uint8_t>("/nodes/phase", n, 0, begin, count);
  check_range(r, codes, 0, 2, "/nodes/phase", 1, begin);
  b.matrix.resize(codes.size());
  for (std::size_t i = 0; i < codes.size(); ++i) {
    if ((codes[i] == 0) != (b.particle[i] >= 0))
      r.corrupt("/nodes/phase row " + std::to_string(begin + static_cast<std::int64_t>(i)) +
                " holds " + std::to_string(codes[i]) + " but /nodes/particle holds " +
                std::to_string(b.particle[i]) +
                " (0 is the phase of nodes in a particle, and "
                "only of them)");
    b.matrix[i] = codes[i] == 1 ? 1 : 0;
  }
}

// Bond rows [begin, begin + count) into `b` (ends 0 <= i < j < N and phase
// codes checked row by row).
void read_bond_rows(const SampleReader& r, const SampleFile& f, std::int64_t begin,
                    std::int64_t count, SampleBlock& b) {
  const std::int64_t n = f.sample.stats.nodes, m = f.sample.stats.bonds;
  const auto ends = r.rows<std::int64_t>("/bonds/connectivity", m, 2, begin, count);
  b.ends.resize(static_cast<std::size_t>(count));
  for (std::size_t k = 0; k < b.ends.size(); ++k) {
    const std::int64_t i = ends[2 * k], j = ends[2 * k + 1];
    if (i < 0 || j >= n || i >= j)
      r.corrupt("/bonds/connectivity row " + std::to_string(begin + static_cast<std::int64_t>(k)) +
                " joins nodes " + std::to_string(i) + " and " + std::to_string(j) +
                " (needs 0 <= i < j < " + std::to_string(n) + ")");
    b.ends[k] = {i, j};
  }
  const auto codes = r.rows<std::uint8_t>("/bonds/phase", m, 0, begin, count);
  check_range(r, codes, 0, kPhaseCount - 1, "/bonds/phase", 1, begin);
  // Every bond of a sample holds the lattice's stiffness (the phases set a
  // run's stiffness): another value means an edited or foreign file.
  const auto stiffness = r.rows<double>("/bonds/stiffness", m, 0, begin, count);
  const double lattice_stiffness = f.spec.lattice.stiffness;
  for (std::size_t k = 0; k < stiffness.size(); ++k)
    if (!(stiffness[k] == lattice_stiffness))
      r.corrupt("/bonds/stiffness row " + std::to_string(begin + static_cast<std::int64_t>(k)) +
                " holds " + value_text(stiffness[k]) +
                "; every bond of a sample holds the attribute lattice_stiffness = " +
                value_text(lattice_stiffness));
  b.bond_phase.resize(codes.size());
  for (std::size_t k = 0; k < codes.size(); ++k) b.bond_phase[k] = static_cast<Phase>(codes[k]);
}

SampleFile read_everything(const std::string& path) {
  const SampleReader r(path);
  SampleBlock b;
  b.description = read_description(r, path);
  SampleFile& f = b.description;
  CementedSample& s = f.sample;
  b.nodes = s.stats.nodes;
  b.bonds = s.stats.bonds;
  if (b.nodes > std::numeric_limits<std::int32_t>::max())
    r.corrupt("too many nodes for int32 bonds");
  read_node_rows(r, f, 0, b.nodes, b);
  read_bond_rows(r, f, 0, b.bonds, b);
  s.lattice.nodes = std::move(b.coords);
  s.node_volume = std::move(b.volume);
  s.node_phases.particle = std::move(b.particle);
  s.node_phases.matrix.assign(b.matrix.begin(), b.matrix.end());
  s.lattice.bonds.resize(b.ends.size());
  for (std::size_t k = 0; k < b.ends.size(); ++k)
    s.lattice.bonds[k] = {static_cast<std::int32_t>(b.ends[k][0]),
                          static_cast<std::int32_t>(b.ends[k][1])};
  s.bond_phase = std::move(b.bond_phase);
  // read_bond_rows checked that every row holds the lattice's stiffness.
  s.lattice.stiffness.assign(s.lattice.bonds.size(), f.spec.lattice.stiffness);
  const std::string problem = first_geometry_problem(s);
  if (!problem.empty()) r.corrupt(problem);
  return std::move(b.description);
}

// The first bond row that repeats an earlier one, found by the rank that
// read the rows of its lower end (read_sample_file's check, in parallel).
void check_repeated_bonds(MPI_Comm comm, const SampleBlock& block, const RowBlocks& node_rows,
                          const SampleReader& reader) {
  struct Row {
    std::int64_t i, j, row;
  };
  std::vector<Row> rows(block.ends.size());
  std::vector<int> to(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    rows[k] = {block.ends[k][0], block.ends[k][1], block.bond_begin + static_cast<std::int64_t>(k)};
    to[k] = node_rows.rank_of(rows[k].i);
  }
  std::vector<Row> mine = route(comm, rows, to);
  std::sort(mine.begin(), mine.end(), [](const Row& a, const Row& b) {
    return std::tie(a.i, a.j, a.row) < std::tie(b.i, b.j, b.row);
  });
  // (repeat, original, i, j) of this rank's first repeat; repeat = -1: none.
  std::int64_t found[4] = {std::numeric_limits<std::int64_t>::max(), 0, 0, 0};
  for (std::size_t k = 1; k < mine.size(); ++k) {
    if (mine[k].i != mine[k - 1].i || mine[k].j != mine[k - 1].j) continue;
    std::size_t first = k - 1;
    while (first > 0 && mine[first - 1].i == mine[k].i && mine[first - 1].j == mine[k].j) --first;
    if (first == k - 1 && mine[k].row < found[0])
      found[0] = mine[k].row, found[1] = mine[first].row, found[2] = mine[k].i,
      found[3] = mine[k].j;
  }
  const std::vector<std::int64_t> all =
      allgather(comm, std::vector<std::int64_t>(found, found + 4));
  std::size_t best = 0;
  for (std::size_t r = 4; r < all.size(); r += 4)
    if (all[r] < all[best]) best = r;
  if (all[best] != std::numeric_limits<std::int64_t>::max())
    reader.corrupt(repeated_bond_problem(all[best], all[best + 1], all[best + 2], all[best + 3]));
}

}  // namespace

SampleFile read_sample_file(const std::string& path) {
  const h5::QuietErrors quiet;
  return read_everything(path);
}

CementedSample read_sample(const std::string& path) { return read_sample_file(path).sample; }

SampleFile read_sample_description(const std::string& path) {
  const h5::QuietErrors quiet;
  const SampleReader r(path);
  return read_description(r, path);
}

SampleBlock read_sample_block(MPI_Comm comm, const std::string& path) {
  const h5::QuietErrors quiet;
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  SampleBlock b;
  // The file is opened and read by every rank; an error on some is the
  // lowest failing rank's on all (for the rows: the first bad row).
  std::unique_ptr<SampleReader> reader;
  run_collectively(comm, [&] {
    reader = std::make_unique<SampleReader>(path, comm);
    b.description = read_description(*reader, path);
  });
  const CementedSampleStats& st = b.description.sample.stats;
  b.nodes = st.nodes;
  b.bonds = st.bonds;
  const RowBlocks node_blocks(b.nodes, ranks), bond_blocks(b.bonds, ranks);
  b.node_begin = node_blocks.begin(rank);
  b.bond_begin = bond_blocks.begin(rank);
  run_collectively(comm, [&] {
    read_node_rows(*reader, b.description, b.node_begin, node_blocks.begin(rank + 1) - b.node_begin,
                   b);
    read_bond_rows(*reader, b.description, b.bond_begin, bond_blocks.begin(rank + 1) - b.bond_begin,
                   b);
  });
  double volume = 0, total = 0;
  for (const double v : b.volume) volume += v;
  MPI_Allreduce(&volume, &total, 1, MPI_DOUBLE, MPI_SUM, comm);
  const std::string problem = volume_sum_problem(b.description.sample.lattice.box, total);
  if (b.nodes > 0 && !problem.empty()) reader->corrupt(problem);

  // Where the ends of this block's bonds are: asked of the ranks that read
  // their node rows.
  std::vector<std::int64_t> ends;
  std::vector<int> to;
  for (const auto& e : b.ends)
    for (const std::int64_t n : e) ends.push_back(n), to.push_back(node_blocks.rank_of(n));
  const std::vector<Point> at = ask<Point>(comm, ends, to, [&](std::int64_t n) {
    return b.coords[static_cast<std::size_t>(n - b.node_begin)];
  });
  b.end_coords.resize(b.ends.size());
  run_collectively(comm, [&] {
    for (std::size_t k = 0; k < b.ends.size(); ++k) {
      b.end_coords[k] = {at[2 * k], at[2 * k + 1]};
      const std::string zero =
          zero_length_problem(b.description.sample.lattice.box,
                              b.bond_begin + static_cast<std::int64_t>(k), b.ends[k][0],
                              b.ends[k][1], at[2 * k], at[2 * k + 1]);
      if (!zero.empty()) reader->corrupt(zero);
    }
  });
  check_repeated_bonds(comm, b, node_blocks, *reader);
  return b;
}

}  // namespace lem
