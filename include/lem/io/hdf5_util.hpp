// HDF5 and XDMF pieces shared by the writers in src/io (lattice fields,
// sample files).  Private to the io module: it exposes HDF5 types.
#pragma once

#include "lem/base/provenance.hpp"

#include <hdf5.h>

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace lem::h5 {

/// Owns an HDF5 identifier and closes it with the matching H5?close.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);

  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  ~Handle() { close(); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept : id_(other.id_), closer_(other.closer_) {
    other.id_ = H5I_INVALID_HID;
  }
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      close();
      id_ = other.id_;
      closer_ = other.closer_;
      other.id_ = H5I_INVALID_HID;
    }
    return *this;
  }

  [[nodiscard]] hid_t get() const { return id_; }
  [[nodiscard]] bool valid() const { return id_ >= 0; }

  /// Close now; returns false if HDF5 reported an error.
  bool close() {
    herr_t status = 0;
    if (id_ >= 0 && closer_ != nullptr) status = closer_(id_);
    id_ = H5I_INVALID_HID;
    return status >= 0;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer closer_ = nullptr;
};

/// The innermost message of HDF5's current error stack ("" if none).
std::string error_text();

/// HDF5 prints no error stack while this lives (the caller reports errors).
class QuietErrors {
 public:
  QuietErrors();
  ~QuietErrors();
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  H5E_auto2_t function_ = nullptr;
  void* data_ = nullptr;
};

/// Scalar attributes of `location`; false if HDF5 reported an error.
bool write_string_attribute(hid_t location, const std::string& name, const std::string& value);
bool write_numeric_attribute(hid_t location, const std::string& name, hid_t file_type,
                             hid_t memory_type, const void* value);

/// The provenance strings and the rank count as attributes of `location`.
bool write_provenance_attributes(hid_t location, const Provenance& provenance);

/// Names of the provenance attributes (reserved for nothing else).
extern const char* const kProvenanceNames[6];

/// One HDF5 dataset shown as an XDMF attribute.
struct XdmfArray {
  std::string name;                   // as ParaView shows it
  std::string dataset;                // e.g. "/nodes/phase"
  int components = 1;                 // 1 (scalar) or 3 (vector)
  const char* number_type = "Float";  // XDMF NumberType: Float, Int, UChar, ...
  int precision = 8;                  // bytes per value
};

/// An XDMF 3 document over one HDF5 file holding one grid (meshio reads no
/// more): points (Polyvertex) or two-node polylines.
class XdmfText {
 public:
  explicit XdmfText(std::string h5_name);
  /// `vertices`: the dataset of the rows 0..points-1 (points x 1), the
  /// connectivity without which readers show no cells.
  void begin_points(const std::string& grid, std::int64_t points, const std::string& coordinates,
                    const std::string& vertices);
  /// Polylines whose ends are rows of `coordinates` (`points` rows).
  void begin_polylines(const std::string& grid, std::int64_t lines, const std::string& connectivity,
                       std::int64_t points, const std::string& coordinates);
  /// center: "Node" (one value per point) or "Cell" (one per polyline).
  void attribute(const XdmfArray& array, const char* center, std::int64_t rows);
  void end_grid();
  /// The whole document (closes the domain).
  std::string text() const;
  /// What every lem XDMF document opens (up to the domain) and closes with.
  static std::string document_head();
  static std::string document_tail();
  /// The row numbers first .. first+n-1, for (a slice of) a `vertices` dataset.
  static std::vector<std::int64_t> vertex_rows(std::int64_t first, std::int64_t n);

 private:
  void data_item(std::int64_t rows, int columns, const char* number_type, int precision,
                 const std::string& dataset);
  void data_item(const std::string& dims, const char* number_type, int precision,
                 const std::string& dataset);
  void geometry(std::int64_t points, const std::string& coordinates);
  std::string h5_name_;
  std::ostringstream out_;
};

}  // namespace lem::h5

namespace lem {

/// Rank 0: `path`, an XDMF temporal collection of the grids of `grid_files`
/// (<stem>.xmf files of write_lattice_fields in the folder of `path`), in
/// the order given, each at the time held by the root attribute
/// `time_attribute` of its <stem>.h5 (a scalar).  ParaView plays it; meshio
/// reads it with its TimeSeriesReader.  (The single files carry no time:
/// meshio.read refuses a grid with one.)
void write_xdmf_series(const std::string& path, const std::vector<std::string>& grid_files,
                       const std::string& time_attribute);

}  // namespace lem
