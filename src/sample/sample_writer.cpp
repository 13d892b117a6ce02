// Writing the cemented sample file (lem/sample/sample_writer.hpp): serial HDF5 with
// compressed chunks made in memory (write_sample), or every rank its rows
// through parallel HDF5 (write_sample_block); and its XDMF description.
#include "lem/sample/sample_writer.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/io/hdf5_util.hpp"
#include "lem/io/parallel_hdf5.hpp"

#include "sample_layout.hpp"

#include <hdf5.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace lem {
namespace {

namespace fs = std::filesystem;
using h5::Handle;
using namespace sample_layout;

// ---------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------

bool write_point_attribute(hid_t location, const std::string& name, const Point& value) {
  const hsize_t three = 3;
  Handle space(H5Screate_simple(1, &three, nullptr), H5Sclose);
  Handle attribute(space.valid() ? H5Acreate2(location, name.c_str(), H5T_IEEE_F64LE, space.get(),
                                              H5P_DEFAULT, H5P_DEFAULT)
                                 : H5I_INVALID_HID,
                   H5Aclose);
  return attribute.valid() && H5Awrite(attribute.get(), H5T_NATIVE_DOUBLE, value.data()) >= 0 &&
         attribute.close();
}

// The serial writer: one rank writes the whole file.
class SampleWriter {
 public:
  // The file is made in memory and written out by write_file_atomically: an
  // I/O error then never reaches HDF5, whose file object a failed close
  // leaves behind (and crashes on when MPI ends).
  SampleWriter(const std::string& path, const std::string& label) : label_(label) {
    const Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    check(access.valid() && H5Pset_fapl_core(access.get(), kImageIncrement, false) >= 0,
          "set up the file in memory");
    file_ = Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose);
    check(file_.valid(), "create the file");
    // Shipped samples should be small; fall back to plain storage if this
    // HDF5 build lacks zlib.
    unsigned config = 0;
    compress_ = H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0 &&
                H5Zget_filter_info(H5Z_FILTER_DEFLATE, &config) >= 0 &&
                (config & H5Z_FILTER_CONFIG_ENCODE_ENABLED) != 0;
  }

  hid_t file() const { return file_.get(); }

  std::string group(const char* name) {
    Handle g(H5Gcreate2(file_.get(), name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    check(g.valid() && g.close(), std::string("create group /") + name);
    return std::string("/") + name + "/";
  }
  template <class T>
  void whole(const std::string& group, const char* name, const T* data, std::size_t rows,
             hsize_t columns = 0) {
    dataset(group + name, data, rows, columns);
  }

  /// rows x columns values (columns 0: a 1-D dataset).
  template <class T>
  void dataset(const std::string& path, const T* data, std::size_t rows, hsize_t columns = 0) {
    const auto [file_type, memory_type] = hdf5_types<T>();
    const int rank = columns == 0 ? 1 : 2;
    const hsize_t dims[2] = {static_cast<hsize_t>(rows), columns};
    Handle space(H5Screate_simple(rank, dims, nullptr), H5Sclose);
    Handle create(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    check(space.valid() && create.valid(), "describe dataset " + path);
    if (compress_ && rows > 0) {
      // Chunks of at most 64k rows; shuffling the bytes first makes integers
      // and nearby doubles compress far better.
      const hsize_t chunk[2] = {std::min<hsize_t>(rows, 65536), columns};
      check(H5Pset_chunk(create.get(), rank, chunk) >= 0 && H5Pset_shuffle(create.get()) >= 0 &&
                H5Pset_deflate(create.get(), 6) >= 0,
            "set up compression of " + path);
    }
    Handle set(H5Dcreate2(file_.get(), path.c_str(), file_type, space.get(), H5P_DEFAULT,
                          create.get(), H5P_DEFAULT),
               H5Dclose);
    check(set.valid(), "create dataset " + path);
    if (rows > 0)
      check(H5Dwrite(set.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0,
            "write dataset " + path);
    check(set.close(), "close dataset " + path);
  }

  template <class T>
  void number(const std::string& name, const T& value) {
    const auto [file_type, memory_type] = hdf5_types<T>();
    check(h5::write_numeric_attribute(file_.get(), name, file_type, memory_type, &value),
          "write attribute " + name);
  }

  void text(const std::string& name, const std::string& value) {
    check(h5::write_string_attribute(file_.get(), name, value), "write attribute " + name);
  }

  void vector3(const std::string& name, const Point& value) {
    check(write_point_attribute(file_.get(), name, value), "write attribute " + name);
  }

  /// The whole file, closed.
  std::vector<char> close() {
    check(H5Fflush(file_.get(), H5F_SCOPE_GLOBAL) >= 0, "flush the file");
    const ssize_t size = H5Fget_file_image(file_.get(), nullptr, 0);
    check(size > 0, "measure the file");
    std::vector<char> image(static_cast<std::size_t>(size));
    check(H5Fget_file_image(file_.get(), image.data(), image.size()) == size, "copy the file");
    check(file_.close(), "close the file");
    return image;
  }

 private:
  static constexpr std::size_t kImageIncrement = std::size_t(1) << 20;
  void check(bool ok, const std::string& what) const {
    if (!ok) throw IoError("cannot write sample file " + label_ + ": HDF5 could not " + what);
  }
  std::string label_;
  Handle file_;
  bool compress_ = false;
};

/// /particles and /bridges, which every writer writes whole, through its
/// group() and whole().
template <class Writer>
void write_particles_and_bridges(Writer& w, const CementedSample& s) {
  const std::size_t p = s.particles.size();
  std::vector<double> centres(3 * p), radii(p);
  for (std::size_t i = 0; i < p; ++i) {
    std::copy(s.particles[i].centre.begin(), s.particles[i].centre.end(), &centres[3 * i]);
    radii[i] = s.particles[i].radius;
  }
  const auto particles = w.group("particles");
  w.whole(particles, "centres", centres.data(), p, 3);
  w.whole(particles, "radii", radii.data(), p);
  const auto particle_rows = h5::XdmfText::vertex_rows(0, static_cast<std::int64_t>(p));
  w.whole(particles, "vertices", particle_rows.data(), p, 1);

  const std::size_t nb = s.bridges.size();
  std::vector<std::int32_t> pairs(2 * nb);
  std::vector<double> lambda(nb);
  for (std::size_t k = 0; k < nb; ++k) {
    pairs[2 * k] = s.bridges[k].i;
    pairs[2 * k + 1] = s.bridges[k].j;
    lambda[k] = s.bridges[k].lambda;
  }
  const auto bridges = w.group("bridges");
  w.whole(bridges, "particles", pairs.data(), nb, 2);
  w.whole(bridges, "lambda", lambda.data(), nb);
}

/// The box, the statistics and the recipe, through a writer's number(),
/// text() and vector3().
template <class Writer>
void write_recipe_attributes(Writer& w, const CementedSample& s, const CementedSampleSpec& spec) {
  w.vector3("box_lo", s.lattice.box.lo);
  w.vector3("box_hi", s.lattice.box.hi);
  CementedSampleStats stats = s.stats;
  CementedSampleSpec copy = spec;
  const auto write = [&](const std::string& name, auto& value) { w.number(name, value); };
  visit_structure(stats, copy, write);
  visit_statistics(stats, write);
  w.text("packing_distribution", distribution_name(spec.packing.distribution));
  w.text("packing_law", law_name(spec.packing.law));
  w.text("void_bonds", void_rule_name(spec.bridges.void_bonds));
  w.text("lattice_generator", generator_name(spec.generator));
}

void check_sizes(const CementedSample& s) {
  const std::size_t n = s.lattice.node_count(), m = s.lattice.bond_count();
  if (s.node_volume.size() != n || s.node_phases.particle.size() != n ||
      s.node_phases.matrix.size() != n || s.bond_phase.size() != m ||
      s.lattice.stiffness.size() != m)
    throw std::invalid_argument("write_sample: the sample's per-node or per-bond arrays do not "
                                "match its lattice (" +
                                std::to_string(n) + " nodes, " + std::to_string(m) + " bonds)");
}

std::vector<char> write_hdf5(const std::string& path, const std::string& label,
                             const CementedSample& s, const CementedSampleSpec& spec,
                             const Provenance& provenance) {
  SampleWriter w(path, label);
  w.text("format", kSampleFormat);
  w.number("format_version", static_cast<std::int64_t>(kSampleFormatVersion));

  const std::size_t n = s.lattice.node_count(), m = s.lattice.bond_count();
  w.group("nodes");
  w.dataset("/nodes/coordinates", s.lattice.nodes.data()->data(), n, 3);
  w.dataset("/nodes/volume", s.node_volume.data(), n);
  w.dataset("/nodes/particle", s.node_phases.particle.data(), n);
  std::vector<std::uint8_t> codes(n);
  for (std::size_t i = 0; i < n; ++i) codes[i] = node_phase_code(s.node_phases, i);
  w.dataset("/nodes/phase", codes.data(), n);
  // The vertex connectivity of the XDMF node grid (readers show no cells without it).
  const auto node_rows = h5::XdmfText::vertex_rows(0, static_cast<std::int64_t>(n));
  w.dataset("/nodes/vertices", node_rows.data(), n, 1);

  w.group("bonds");
  std::vector<std::int64_t> ends(2 * m);
  for (std::size_t b = 0; b < m; ++b) {
    ends[2 * b] = s.lattice.bonds[b].i;
    ends[2 * b + 1] = s.lattice.bonds[b].j;
  }
  w.dataset("/bonds/connectivity", ends.data(), m, 2);
  codes.resize(m);
  for (std::size_t b = 0; b < m; ++b) codes[b] = static_cast<std::uint8_t>(s.bond_phase[b]);
  w.dataset("/bonds/phase", codes.data(), m);
  w.dataset("/bonds/stiffness", s.lattice.stiffness.data(), m);

  write_particles_and_bridges(w, s);

  write_recipe_attributes(w, s, spec);
  if (!h5::write_provenance_attributes(w.file(), provenance))
    throw InputError("cannot write sample file " + label +
                     ": HDF5 could not write the "
                     "provenance attributes");
  return w.close();
}

// One grid per XDMF file (meshio reads no more): <stem>.xmf the bonds with
// the node data on their ends, <stem>_nodes.xmf the nodes, and
// <stem>_particles.xmf the particles as vertices.
struct SampleXdmf {
  std::string bonds, nodes, particles;
};

SampleXdmf sample_xdmf(const std::string& h5_name, std::int64_t n, std::int64_t m, std::int64_t p) {
  const h5::XdmfArray node_arrays[] = {{"phase", "/nodes/phase", 1, "UChar", 1},
                                       {"particle", "/nodes/particle", 1, "Int", 4},
                                       {"volume", "/nodes/volume", 1, "Float", 8}};
  SampleXdmf out;
  h5::XdmfText bonds(h5_name);
  bonds.begin_polylines("bonds", m, "/bonds/connectivity", n, "/nodes/coordinates");
  for (const auto& a : node_arrays) bonds.attribute(a, "Node", n);
  bonds.attribute({"phase", "/bonds/phase", 1, "UChar", 1}, "Cell", m);
  bonds.attribute({"stiffness", "/bonds/stiffness", 1, "Float", 8}, "Cell", m);
  bonds.end_grid();
  out.bonds = bonds.text();
  h5::XdmfText nodes(h5_name);
  nodes.begin_points("nodes", n, "/nodes/coordinates", "/nodes/vertices");
  for (const auto& a : node_arrays) nodes.attribute(a, "Node", n);
  nodes.end_grid();
  out.nodes = nodes.text();
  h5::XdmfText particles(h5_name);
  particles.begin_points("particles", p, "/particles/centres", "/particles/vertices");
  particles.attribute({"radius", "/particles/radii", 1, "Float", 8}, "Node", p);
  particles.end_grid();
  out.particles = particles.text();
  return out;
}

/// <stem>.xmf, <stem>_nodes.xmf and <stem>_particles.xmf beside <stem>.h5.
void write_sample_xdmf(const std::string& stem, std::int64_t nodes, std::int64_t bonds,
                       std::int64_t particles) {
  const SampleXdmf xdmf =
      sample_xdmf(fs::path(stem + ".h5").filename().string(), nodes, bonds, particles);
  write_text_file_atomically(stem + ".xmf", xdmf.bonds);
  write_text_file_atomically(stem + "_nodes.xmf", xdmf.nodes);
  write_text_file_atomically(stem + "_particles.xmf", xdmf.particles);
}

// The parallel writer: every rank writes its rows (the particles and the
// bridges are rank 0's), through ParallelHdf5File.
class SampleBlockWriter {
 public:
  SampleBlockWriter(MPI_Comm comm, const std::string& path) : file_(comm, path) {
    MPI_Comm_rank(comm, &rank_);
  }
  struct Group {
    hid_t id;
    std::string name;
  };
  Group group(const char* name) { return {file_.group(name), name}; }
  template <class T>
  void dataset(const Group& group, const std::string& name, const T* data, const Slab& rows) {
    const auto [file_type, memory_type] = hdf5_types<T>();
    file_.dataset(group.id, "/" + group.name + "/" + name, name, file_type, memory_type, rows,
                  data);
  }
  /// Rows that every rank holds whole: written by rank 0.
  template <class T>
  void whole(const Group& group, const std::string& name, const T* data, std::size_t rows,
             hsize_t columns = 0) {
    dataset(group, name, data, Slab{rows, 0, rank_ == 0 ? rows : 0, columns});
  }
  template <class T>
  void number(const std::string& name, const T& value) {
    const auto [file_type, memory_type] = hdf5_types<T>();
    file_.attribute(name, [&](hid_t root) {
      return h5::write_numeric_attribute(root, name, file_type, memory_type, &value);
    });
  }
  void text(const std::string& name, const std::string& value) {
    file_.attribute(name,
                    [&](hid_t root) { return h5::write_string_attribute(root, name, value); });
  }
  void vector3(const std::string& name, const Point& value) {
    file_.attribute(name, [&](hid_t root) { return write_point_attribute(root, name, value); });
  }
  ParallelHdf5File& file() { return file_; }

 private:
  ParallelHdf5File file_;
  int rank_ = 0;
};

void write_block_hdf5(MPI_Comm comm, const std::string& path, const SampleBlock& b) {
  const CementedSample& s = b.description.sample;
  const CementedSampleSpec& spec = b.description.spec;
  SampleBlockWriter w(comm, path);
  w.text("format", kSampleFormat);
  w.number("format_version", static_cast<std::int64_t>(kSampleFormatVersion));

  const auto h = [](auto v) { return static_cast<hsize_t>(v); };
  const Slab node_rows{h(b.nodes), h(b.node_begin), h(b.coords.size()), 0};
  const Slab bond_rows{h(b.bonds), h(b.bond_begin), h(b.ends.size()), 0};
  const auto nodes = w.group("nodes");
  w.dataset(nodes, "coordinates", b.coords.data()->data(), node_rows.with_columns(3));
  w.dataset(nodes, "volume", b.volume.data(), node_rows);
  w.dataset(nodes, "particle", b.particle.data(), node_rows);
  std::vector<std::uint8_t> codes(b.coords.size());
  for (std::size_t n = 0; n < codes.size(); ++n)
    codes[n] = b.particle[n] >= 0 ? 0 : (b.matrix[n] ? 1 : 2);
  w.dataset(nodes, "phase", codes.data(), node_rows);
  const auto vertices =
      h5::XdmfText::vertex_rows(b.node_begin, static_cast<std::int64_t>(b.coords.size()));
  w.dataset(nodes, "vertices", vertices.data(), node_rows.with_columns(1));

  const auto bonds = w.group("bonds");
  w.dataset(bonds, "connectivity", b.ends.data()->data(), bond_rows.with_columns(2));
  codes.resize(b.ends.size());
  for (std::size_t k = 0; k < codes.size(); ++k)
    codes[k] = static_cast<std::uint8_t>(b.bond_phase[k]);
  w.dataset(bonds, "phase", codes.data(), bond_rows);
  const std::vector<double> stiffness(b.ends.size(), spec.lattice.stiffness);
  w.dataset(bonds, "stiffness", stiffness.data(), bond_rows);

  write_particles_and_bridges(w, s);

  write_recipe_attributes(w, s, spec);
  w.file().provenance(b.description.provenance);
  w.file().close();
}

}  // namespace

void write_sample(const std::string& stem, const CementedSample& sample,
                  const CementedSampleSpec& spec, const Provenance& provenance) {
  check_sizes(sample);
  if (stem.empty() || fs::path(stem).filename().empty())
    throw InputError("write_sample: output stem '" + stem +
                     "' must name a file (e.g. meshes/tiny), not be empty or end in '/'");
  const std::string h5_path = stem + ".h5";
  const std::string memory_name = h5_path + ".tmp";  // never on disk
  std::vector<char> image;
  {
    const h5::QuietErrors quiet;
    image = write_hdf5(memory_name, "'" + h5_path + "'", sample, spec, provenance);
  }
  write_file_atomically(h5_path, image.data(), image.size());
  write_sample_xdmf(stem, static_cast<std::int64_t>(sample.lattice.node_count()),
                    static_cast<std::int64_t>(sample.lattice.bond_count()),
                    static_cast<std::int64_t>(sample.particles.size()));
}

void write_sample_block(MPI_Comm comm, const std::string& stem, const SampleBlock& b) {
  if (stem.empty() || fs::path(stem).filename().empty())
    throw InputError("write_sample_block: output stem '" + stem +
                     "' must name a file (e.g. meshes/tiny), not be empty or end in '/'");
  run_collectively(comm, [&] {
    const std::size_t n = b.coords.size(), m = b.ends.size();
    if (b.volume.size() != n || b.particle.size() != n || b.matrix.size() != n ||
        b.end_coords.size() != m || b.bond_phase.size() != m)
      throw std::invalid_argument("write_sample_block: the block's per-node or per-bond arrays "
                                  "differ in length");
  });
  write_hdf5_into_place(
      comm, stem + ".h5",
      [&](const std::string& temporary) { write_block_hdf5(comm, temporary, b); },
      [&] {
        write_sample_xdmf(stem, b.nodes, b.bonds,
                          static_cast<std::int64_t>(b.description.sample.particles.size()));
      });
}

}  // namespace lem
