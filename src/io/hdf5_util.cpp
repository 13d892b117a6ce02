// What lem's HDF5 writers share (lem/io/hdf5_util.hpp): attributes with the
// provenance, and XDMF 3 text over the HDF5 files — one-grid documents and a
// temporal collection of such grids.
#include "lem/io/hdf5_util.hpp"

#include <hdf5.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "lem/base/error.hpp"
#include "lem/base/files.hpp"

namespace lem {
namespace h5 {

const char* const kProvenanceNames[6] = {"program", "version",    "git_hash",
                                         "options", "start_time", "ranks"};

std::string error_text() {
  std::string text;
  // Upward: the most specific error first.
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned, const H5E_error2_t* error, void* data) -> herr_t {
        auto& found = *static_cast<std::string*>(data);
        if (found.empty() && error->desc && *error->desc) found = error->desc;
        return 0;
      },
      &text);
  return text;
}

QuietErrors::QuietErrors() {
  H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

QuietErrors::~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, function_, data_); }

bool write_string_attribute(hid_t location, const std::string& name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!type.valid()) return false;
  if (H5Tset_size(type.get(), H5T_VARIABLE) < 0) return false;
  if (H5Tset_cset(type.get(), H5T_CSET_UTF8) < 0) return false;
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  if (!space.valid()) return false;
  Handle attribute(H5Acreate2(location, name.c_str(), type.get(), space.get(), H5P_DEFAULT,
                              H5P_DEFAULT),
                   H5Aclose);
  if (!attribute.valid()) return false;
  const char* text = value.c_str();
  if (H5Awrite(attribute.get(), type.get(), &text) < 0) return false;
  return attribute.close();
}

bool write_numeric_attribute(hid_t location, const std::string& name, hid_t file_type,
                             hid_t memory_type, const void* value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  if (!space.valid()) return false;
  Handle attribute(H5Acreate2(location, name.c_str(), file_type, space.get(), H5P_DEFAULT,
                              H5P_DEFAULT),
                   H5Aclose);
  if (!attribute.valid()) return false;
  if (H5Awrite(attribute.get(), memory_type, value) < 0) return false;
  return attribute.close();
}

bool write_provenance_attributes(hid_t location, const Provenance& provenance) {
  const std::pair<const char*, const std::string*> strings[] = {
      {"program", &provenance.program},       {"version", &provenance.version},
      {"git_hash", &provenance.git_hash},     {"options", &provenance.options},
      {"start_time", &provenance.start_time},
  };
  for (const auto& entry : strings)
    if (!write_string_attribute(location, entry.first, *entry.second)) return false;
  const std::int64_t ranks = provenance.ranks;
  return write_numeric_attribute(location, "ranks", H5T_STD_I64LE, H5T_NATIVE_INT64, &ranks);
}

namespace {

std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace

XdmfText::XdmfText(std::string h5_name) : h5_name_(std::move(h5_name)) { out_ << document_head(); }

std::string XdmfText::document_head() {
  return "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n";
}

std::string XdmfText::document_tail() { return "  </Domain>\n</Xdmf>\n"; }

void XdmfText::data_item(std::int64_t rows, int columns, const char* number_type, int precision,
                         const std::string& dataset) {
  data_item(columns == 1 ? std::to_string(rows)
                         : std::to_string(rows) + " " + std::to_string(columns),
            number_type, precision, dataset);
}

void XdmfText::data_item(const std::string& dims, const char* number_type, int precision,
                         const std::string& dataset) {
  out_ << "        <DataItem Dimensions=\"" << dims << "\" NumberType=\"" << number_type
       << "\" Precision=\"" << precision << "\" Format=\"HDF\">" << xml_escape(h5_name_) << ':'
       << xml_escape(dataset) << "</DataItem>\n";
}

void XdmfText::geometry(std::int64_t points, const std::string& coordinates) {
  out_ << "      <Geometry GeometryType=\"XYZ\">\n";
  data_item(points, 3, "Float", 8, coordinates);
  out_ << "      </Geometry>\n";
}

void XdmfText::begin_points(const std::string& grid, std::int64_t points,
                            const std::string& coordinates, const std::string& vertices) {
  out_ << "    <Grid Name=\"" << xml_escape(grid) << "\" GridType=\"Uniform\">\n"
       << "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << points
       << "\" NodesPerElement=\"1\">\n";
  // N x 1, as a table of one-node cells (meshio's shape for vertices).
  data_item(std::to_string(points) + " 1", "Int", 8, vertices);
  out_ << "      </Topology>\n";
  geometry(points, coordinates);
}

std::vector<std::int64_t> XdmfText::vertex_rows(std::int64_t first, std::int64_t n) {
  std::vector<std::int64_t> rows(static_cast<std::size_t>(n));
  for (std::int64_t i = 0; i < n; ++i) rows[static_cast<std::size_t>(i)] = first + i;
  return rows;
}

void XdmfText::begin_polylines(const std::string& grid, std::int64_t lines,
                               const std::string& connectivity, std::int64_t points,
                               const std::string& coordinates) {
  out_ << "    <Grid Name=\"" << xml_escape(grid) << "\" GridType=\"Uniform\">\n"
       << "      <Topology TopologyType=\"Polyline\" NumberOfElements=\"" << lines
       << "\" NodesPerElement=\"2\">\n";
  data_item(lines, 2, "Int", 8, connectivity);
  out_ << "      </Topology>\n";
  geometry(points, coordinates);
}

void XdmfText::attribute(const XdmfArray& a, const char* center, std::int64_t rows) {
  out_ << "      <Attribute Name=\"" << xml_escape(a.name) << "\" AttributeType=\""
       << (a.components == 3   ? "Vector"
           : a.components == 6 ? "Tensor6"
                               : "Scalar")
       << "\" Center=\"" << center << "\">\n";
  data_item(rows, a.components, a.number_type, a.precision, a.dataset);
  out_ << "      </Attribute>\n";
}

void XdmfText::end_grid() { out_ << "    </Grid>\n"; }

std::string XdmfText::text() const { return out_.str() + document_tail(); }

}  // namespace h5

namespace fs = std::filesystem;

void write_xdmf_series(const std::string& path, const std::vector<std::string>& grid_files,
                       const std::string& time_attribute) {
  std::ostringstream out;
  out << h5::XdmfText::document_head() << "    <Grid Name=\"" << fs::path(path).stem().string()
      << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const std::string& file : grid_files) {
    std::ifstream in(file);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto from = text.find("    <Grid "), to = text.rfind("    </Grid>\n");
    const auto opened = text.find('\n', from);
    if (!in || from == std::string::npos || to == std::string::npos || to < opened)
      throw IoError("cannot read the grid of '" + file + "' for '" + path + "'");
    const std::string h5_path = fs::path(file).replace_extension(".h5").string();
    double time = 0;
    {
      const h5::Handle h5(H5Fopen(h5_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
      const h5::Handle attribute(h5.valid() ? H5Aopen(h5.get(), time_attribute.c_str(), H5P_DEFAULT)
                                            : H5I_INVALID_HID,
                                 H5Aclose);
      if (!attribute.valid() || H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &time) < 0)
        throw IoError("cannot read the attribute '" + time_attribute + "' of '" + h5_path +
                      "' for '" + path + "'");
    }
    // The grid, one level deeper, with its time after the opening line.
    std::string grid = text.substr(from, opened + 1 - from);
    char line[64];
    std::snprintf(line, sizeof line, "      <Time Value=\"%.17g\"/>\n", time);
    grid += line;
    grid += text.substr(opened + 1, to + 12 - (opened + 1));
    std::istringstream lines(grid);
    for (std::string l; std::getline(lines, l);) out << "  " << l << '\n';
  }
  out << "    </Grid>\n" << h5::XdmfText::document_tail();
  write_text_file_atomically(path, out.str());
}

}  // namespace lem
