#include "lem/report/calibration.hpp"

#include "lem/base/byte_stream.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/base/log.hpp"
#include "lem/base/collective.hpp"
#include "lem/base/fingerprint.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace lem {

namespace {

constexpr const char* kFingerprintLine = "# fingerprint:";
constexpr const char* kWarningLine = "warning=";
// The last line: the CRC-32 of every line before it.
constexpr const char* kChecksumLine = "checksum=";

std::string text_checksum(const std::string& text) {
  char hex[16];
  std::snprintf(hex, sizeof(hex), "crc32:%08x", crc32(text.data(), text.size()));
  return hex;
}

}  // namespace

std::string calibration_key(const std::string& fingerprint) {
  const std::string text = key_text(fingerprint);
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx",
                static_cast<unsigned long long>(fnv1a(text.data(), text.size())));
  return hex;
}

std::optional<Calibration> read_calibration(MPI_Comm comm, const std::string& path,
                                            const std::string& fingerprint) {
  int found = 0;
  Calibration c;
  run_on_root(comm, [&] {
    if (const std::string what = not_a_regular_file(path); !what.empty())
      throw InputError("the calibration file '" + path + "' is " + what +
                       ", not a file "
                       "lem wrote; remove it, or pass another -fracture_calibration_file");
    std::ifstream in(path);
    if (!in) return;
    std::string stored, line, written_by, content, checksum;
    bool have_sigma = false, have_e = false;
    while (std::getline(in, line)) {
      if (line.rfind(kChecksumLine, 0) == 0) {
        checksum = line.substr(std::string(kChecksumLine).size());
        continue;
      }
      content += line + "\n";
      if (line.rfind(kFingerprintLine, 0) == 0) {
        stored += line.substr(std::string(kFingerprintLine).size() + 1) + "\n";
      } else if (line.rfind("# written by ", 0) == 0) {
        written_by = line.substr(2);
      } else if (line.rfind("sigma_hom=", 0) == 0) {
        have_sigma = std::sscanf(line.c_str() + 10, "%lf", &c.sigma_hom) == 1;
      } else if (line.rfind("E_hom=", 0) == 0) {
        have_e = std::sscanf(line.c_str() + 6, "%lf", &c.e_hom) == 1;
      } else if (line.rfind(kWarningLine, 0) == 0) {
        c.warnings.push_back(line.substr(std::string(kWarningLine).size()));
      }
    }
    if (!have_sigma || !have_e || !(c.sigma_hom > 0) || !(c.e_hom > 0))
      throw InputError("the calibration file '" + path +
                       "' is damaged (no positive sigma_hom "
                       "and E_hom); remove it to calibrate again");
    // A value edited by hand would change every normalised stress silently.
    const std::string actual = text_checksum(content);
    if (checksum != actual) {
      std::ostringstream values;
      values.precision(17);
      values << "sigma_hom=" << c.sigma_hom << ", E_hom=" << c.e_hom;
      throw InputError("the calibration file '" + path + "' is not as it was written: " +
                       (checksum.empty() ? "it has no checksum line (" + actual + " now)"
                                         : "its content (" + values.str() +
                                               ") has the "
                                               "checksum " +
                                               actual + ", the file says " + checksum) +
                       "; remove it to calibrate again (the next run computes and stores "
                       "sigma^[p] and E^[p] anew)");
    }
    const std::string differs =
        compare_fingerprints(stored, without_ranks(fingerprint), "file").differs;
    if (!differs.empty())
      throw InputError("the calibration file '" + path +
                       "' was made for another lattice or "
                       "other options:" +
                       differs +
                       "\npass the calibration file of this sample, "
                       "or remove it to calibrate again");
    found = 1;
    // The code that made it is not part of the key: say which it was.
    say("calibration: reusing the values %s\n", written_by.c_str());
  });
  MPI_Bcast(&found, 1, MPI_INT, 0, comm);
  if (!found) return std::nullopt;
  double values[2] = {c.sigma_hom, c.e_hom};
  MPI_Bcast(values, 2, MPI_DOUBLE, 0, comm);
  c.sigma_hom = values[0], c.e_hom = values[1];
  std::string words;
  for (const auto& w : c.warnings) words += w + "\n";
  std::istringstream lines(broadcast_string(comm, words));
  c.warnings.clear();
  for (std::string w; std::getline(lines, w);) c.warnings.push_back(w);
  return c;
}

void write_calibration(MPI_Comm comm, const std::string& path, const std::string& fingerprint,
                       const Calibration& c, const Provenance& provenance) {
  run_on_root(comm, [&] {
    std::ostringstream out;
    out.precision(17);
    out << "# sigma^[p] and E^[p] of the homogeneous lattice (paper sect. 3), E^phase units;\n"
        << "# written by " << provenance.program << " " << provenance.version << " ("
        << provenance.git_hash << ") on " << provenance.ranks
        << (provenance.ranks == 1 ? " rank, " : " ranks, ") << iso8601_utc_now() << "\n"
        << "sigma_hom=" << c.sigma_hom << "\nE_hom=" << c.e_hom << "\n";
    for (const auto& w : c.warnings) out << kWarningLine << w << "\n";
    std::istringstream in(without_ranks(fingerprint));
    for (std::string line; std::getline(in, line);) out << kFingerprintLine << " " << line << "\n";
    const std::string checksum = text_checksum(out.str());
    out << kChecksumLine << checksum << "\n";
    write_text_file_atomically(path, out.str());
  });
}

}  // namespace lem
