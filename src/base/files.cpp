#include "lem/base/files.hpp"

#include "lem/base/error.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

namespace lem {

namespace fs = std::filesystem;

namespace {

constexpr char kManifestName[] = "manifest.txt";
constexpr char kLockName[] = ".lock";

std::string last_error() { return std::strerror(errno); }

/// fsync an existing file or directory; false (errno set) on failure.
bool sync_path(const std::string& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? O_RDONLY | O_DIRECTORY : O_RDONLY);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  const int saved = errno;
  ::close(fd);
  errno = saved;
  return ok;
}

std::string directory_of(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

// Create the output folder `dir` (and its parents); InputError naming it if
// that fails.  A dangling symbolic link is named as such: creating the folder
// fails there with a bare "File exists".
void create_output_dir(const std::string& dir) {
  std::error_code ec;
  const auto link = fs::symlink_status(dir, ec);
  if (fs::is_symlink(link) && !fs::exists(fs::status(dir, ec)))
    throw InputError("output directory '" + dir + "' is a dangling symbolic link (to '" +
                     fs::read_symlink(dir, ec).string() +
                     "', which does not exist): create "
                     "the folder it points to, or choose another -output_dir");
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw InputError("output directory '" + dir + "' cannot be created: " +
                     (ec ? ec.message() : std::string("a file of that name is in the way")));
}

}  // namespace

std::string not_a_regular_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return "";
  if (S_ISFIFO(st.st_mode)) return "a pipe (FIFO)";
  if (S_ISCHR(st.st_mode)) return "a character device";
  if (S_ISBLK(st.st_mode)) return "a block device";
  if (S_ISSOCK(st.st_mode)) return "a socket";
  if (S_ISDIR(st.st_mode)) return "a directory";
  return "not a regular file";
}

void write_text_file_atomically(const std::string& path, const std::string& text) {
  write_file_atomically(path, text.data(), text.size());
}

std::string unwritable_file(const std::string& path) {
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return "cannot create '" + tmp + "': " + last_error();
  ::close(fd);
  std::error_code ec;
  fs::remove(tmp, ec);
  if (const std::string what = not_a_regular_file(path); !what.empty()) return "it is " + what;
  return "";
}

void write_file_atomically(const std::string& path, const void* data, std::size_t size) {
  const std::string tmp = path + ".tmp";
  const auto fail = [&](const std::string& why) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw IoError("cannot write file '" + path + "': " + why);
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("cannot create '" + tmp + "': " + last_error());
  const char* bytes = static_cast<const char*>(data);
  std::size_t written = 0;
  while (written < size) {
    const ssize_t n = ::write(fd, bytes + written, size - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string why = last_error();
      ::close(fd);
      fail("writing '" + tmp + "' failed: " + why);
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const std::string why = last_error();
    ::close(fd);
    fail("syncing '" + tmp + "' failed: " + why);
  }
  if (::close(fd) != 0) fail("closing '" + tmp + "' failed: " + last_error());
  move_into_place(tmp, path);
}

void move_into_place(const std::string& from, const std::string& to) {
  const auto fail = [&](const std::string& what) {
    const std::string why = last_error();
    std::error_code ec;
    fs::remove(from, ec);
    throw IoError("cannot move '" + from + "' to '" + to + "': " + what + ": " + why);
  };
  if (!sync_path(from, false)) fail("syncing failed");
  if (std::rename(from.c_str(), to.c_str()) != 0) fail("renaming failed");
  // The rename itself is durable once the directory is synced.
  sync_directory(directory_of(to));
}

void sync_directory(const std::string& dir) {
  if (!sync_path(dir, true)) throw IoError("cannot sync directory '" + dir + "': " + last_error());
}

void prepare_output_dir(MPI_Comm comm, const std::string& dir,
                        const std::vector<std::string>& result_files) {
  run_on_root(comm, [&] {
    create_output_dir(dir);
    std::error_code ec;
    for (const auto& f : result_files) fs::remove(dir + "/" + f, ec);
  });
}

OutputLock::OutputLock(MPI_Comm comm, const std::string& dir) {
  run_on_root(comm, [&] {
    // The lock file is never removed while it can be in use: removing it
    // would let a second run lock a new file while the first still holds the
    // old one.  Only install_result swaps it away, with its folder, while it
    // holds both; the check after flock lets go of a file swapped away
    // between our open and our lock, and takes the one now at the path.
    const std::string path = dir + "/" + kLockName;
    for (int attempt = 0;; ++attempt) {
      create_output_dir(dir);
      fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
      if (fd_ < 0)
        throw InputError("output directory '" + dir + "': cannot open its lock file '" + path +
                         "': " + last_error());
      if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
        const int saved = errno;
        ::close(fd_);
        fd_ = -1;
        if (saved == EWOULDBLOCK)
          throw InputError("output directory '" + dir +
                           "' is in use by another run (it holds "
                           "the lock on '" +
                           path +
                           "'); wait for it to end or choose another "
                           "-output_dir");
        errno = saved;
        throw InputError("output directory '" + dir + "': cannot lock '" + path +
                         "': " + last_error());
      }
      struct stat held {
      }, now{};
      if (::fstat(fd_, &held) == 0 && ::stat(path.c_str(), &now) == 0 &&
          held.st_dev == now.st_dev && held.st_ino == now.st_ino)
        return;
      ::close(fd_);
      fd_ = -1;
      if (attempt == 100)
        throw InputError("output directory '" + dir + "': its lock file '" + path +
                         "' keeps being replaced");
    }
  });
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

namespace {

// Eight tables of the reflected polynomial 0xEDB88320: eight bytes a step
// ("slicing by 8"), about 1 byte per cycle.
struct Crc32Tables {
  std::uint32_t t[8][256];
  Crc32Tables() {
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[0][i] = c;
    }
    for (int k = 1; k < 8; ++k)
      for (std::uint32_t i = 0; i < 256; ++i)
        t[k][i] = (t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xff];
  }
};

}  // namespace

std::uint32_t crc32(const void* data, std::size_t n, std::uint32_t crc) {
  static const Crc32Tables tables;
  const auto& t = tables.t;
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint32_t c = ~crc;
  for (; n >= 8; n -= 8, p += 8) {
    const std::uint32_t lo = c ^ (std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 |
                                  std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24);
    c = t[7][lo & 0xff] ^ t[6][(lo >> 8) & 0xff] ^ t[5][(lo >> 16) & 0xff] ^ t[4][lo >> 24] ^
        t[3][p[4]] ^ t[2][p[5]] ^ t[1][p[6]] ^ t[0][p[7]];
  }
  for (; n > 0; --n, ++p) c = t[0][(c ^ *p) & 0xff] ^ (c >> 8);
  return ~c;
}

std::uint32_t file_prefix_crc32(const std::string& path, std::uint64_t bytes) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw IoError("cannot read '" + path + "' for its checksum: " + last_error());
  std::vector<char> buffer(std::size_t(1) << 20);
  std::uint32_t crc = 0;
  while (bytes > 0) {
    const ssize_t n = ::read(fd, buffer.data(), std::min<std::uint64_t>(buffer.size(), bytes));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string why = last_error();
      ::close(fd);
      throw IoError("cannot read '" + path + "' for its checksum: " + why);
    }
    if (n == 0) break;
    crc = crc32(buffer.data(), static_cast<std::size_t>(n), crc);
    bytes -= static_cast<std::uint64_t>(n);
  }
  ::close(fd);
  return crc;
}

std::string crc32_text(std::uint32_t crc) {
  char text[16];
  std::snprintf(text, sizeof text, "crc32:%08x", crc);
  return text;
}

std::string file_checksum(const std::string& path) {
  return crc32_text(file_prefix_crc32(path, UINT64_MAX));
}

namespace {
constexpr char kFileKey[] = "file=";
constexpr char kChecksumKey[] = "checksum=";
constexpr char kWarningKey[] = "warning=";
constexpr char kProgramKey[] = "program=";
constexpr char kFingerprintKey[] = "fingerprint ";

// The checksum the manifest lists for `name`, or null.
const std::string* checksum_of(const Manifest& m, const std::string& name) {
  for (const auto& [file, sum] : m.checksums)
    if (file == name) return &sum;
  return nullptr;
}
}  // namespace

bool has_manifest(const std::string& dir) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(dir + "/" + kManifestName, ec));
}

std::optional<Manifest> read_manifest(const std::string& dir) {
  const std::string path = dir + "/" + kManifestName;
  if (const std::string what = not_a_regular_file(path); !what.empty())
    throw InputError("the manifest '" + path + "' is " + what +
                     ", not a file lem wrote; "
                     "remove it, or choose another -output_dir");
  std::ifstream in(path);
  if (!in) {
    if (!fs::exists(path)) return std::nullopt;
    throw InputError("cannot read the manifest '" + path + "': " + last_error());
  }
  Manifest m;
  bool end = false;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    if (line == "end") {
      end = true;
    } else if (line.rfind(kProgramKey, 0) == 0) {
      m.program = line.substr(sizeof(kProgramKey) - 1);
    } else if (line.rfind(kFingerprintKey, 0) == 0) {
      m.fingerprint += line.substr(sizeof(kFingerprintKey) - 1) + "\n";
    } else if (line.rfind(kFileKey, 0) == 0) {
      std::istringstream fields(line.substr(sizeof(kFileKey) - 1));
      std::string name;
      long long size = -1;
      if (!(fields >> name >> size) || size < 0)
        throw InputError("the manifest '" + path + "' is damaged (line '" + line + "')");
      m.files.emplace_back(name, size);
    } else if (line.rfind(kWarningKey, 0) == 0) {
      m.warnings.push_back(line.substr(sizeof(kWarningKey) - 1));
    } else if (line.rfind(kChecksumKey, 0) == 0) {
      std::istringstream fields(line.substr(sizeof(kChecksumKey) - 1));
      std::string name, sum;
      if (!(fields >> name >> sum))
        throw InputError("the manifest '" + path + "' is damaged (line '" + line + "')");
      m.checksums.emplace_back(name, sum);
    }
  }
  // Written atomically, so a manifest without its last line was not written
  // by lem: refuse it rather than guess.
  if (!end || m.program.empty())
    throw InputError("the manifest '" + path +
                     "' is damaged (no program or no end line); "
                     "remove it, or pass -output_overwrite to compute the result again");
  // Checksums are written for every file, or (before they existed) for
  // none: a line missing would let a changed file pass as committed.
  for (const auto& [name, size] : m.files)
    if (!m.checksums.empty() && !checksum_of(m, name))
      throw InputError("the manifest '" + path + "' is damaged (no checksum of " + name +
                       ", though it has those of the other files); remove it, or pass "
                       "-output_overwrite to compute the result again");
  return m;
}

std::string manifest_mismatch(const std::string& dir, const Manifest& m) {
  std::string why;
  for (const auto& [name, size] : m.files) {
    std::error_code ec;
    const auto actual = fs::file_size(dir + "/" + name, ec);
    if (ec) {
      why += "\n  " + name + " is missing";
      continue;
    }
    if (static_cast<std::int64_t>(actual) != size) {
      why += "\n  " + name + " has " + std::to_string(actual) + " bytes, the manifest says " +
             std::to_string(size);
      continue;
    }
    const std::string* listed = checksum_of(m, name);
    if (!listed) continue;  // a manifest written before checksums (read_manifest)
    const std::string sum = file_checksum(dir + "/" + name);
    if (sum != *listed)
      why += "\n  " + name + " has other content than was committed (checksum " + sum +
             ", the manifest says " + *listed + "), at the same size";
  }
  return why;
}

void commit_results(const std::string& dir, const std::string& program,
                    const std::string& fingerprint, const std::vector<std::string>& files,
                    const std::vector<std::string>& warnings) {
  std::ostringstream out;
  out << "# The result in this folder is complete: written last, after every file below\n"
      << "# was in place and synced.  Without this file the folder holds no finished result.\n"
      << kProgramKey << program << "\n";
  for (const auto& name : files) {
    const std::string path = dir + "/" + name;
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (ec) throw IoError("cannot commit the results: '" + path + "' is missing");
    if (!sync_path(path, false))
      throw IoError("cannot commit the results: syncing '" + path + "' failed: " + last_error());
    out << kFileKey << name << " " << size << "\n";
  }
  // Apart from the sizes, on lines of their own: older readers (the Python
  // tools before checksums) read "file=<name> <size>" lines only.
  for (const auto& name : files)
    out << kChecksumKey << name << " " << file_checksum(dir + "/" + name) << "\n";
  for (const auto& w : warnings) out << kWarningKey << w << "\n";
  std::istringstream in(fingerprint);
  for (std::string line; std::getline(in, line);) out << kFingerprintKey << line << "\n";
  out << "end\n";
  sync_directory(dir);
  write_text_file_atomically(dir + "/" + kManifestName, out.str());
}

void withdraw_results(const std::string& dir, const std::vector<std::string>& files) {
  std::error_code ec;
  if (fs::remove(dir + "/" + kManifestName, ec)) sync_directory(dir);
  if (ec) throw IoError("cannot remove '" + dir + "/" + kManifestName + "': " + ec.message());
  for (const auto& f : files) fs::remove(dir + "/" + f, ec);
}

// ---- Replacing a finished result ---------------------------------------

namespace {

constexpr char kStagingSuffix[] = ".overwrite";
constexpr char kStampName[] = ".overwrite_of";     // a staging folder's stamp
constexpr char kSupersededName[] = ".superseded";  // a folder whose result was replaced
constexpr char kAsideName[] = ".replaced";         // the old folder, moved aside

std::string trimmed(const std::string& dir) {
  std::string d = dir;
  while (d.size() > 1 && d.back() == '/') d.pop_back();
  return d;
}

bool entry_exists(const std::string& path) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(path, ec));
}

// The names in `dir`, read before any is moved.
std::vector<std::string> entries_of(const std::string& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    names.push_back(entry.path().filename().string());
  if (ec) throw IoError("cannot list '" + dir + "': " + ec.message());
  return names;
}

void rename_or_throw(const std::string& from, const std::string& to, const std::string& what) {
  if (std::rename(from.c_str(), to.c_str()) != 0)
    throw IoError("cannot " + what + ": renaming '" + from + "' to '" + to +
                  "' failed: " + last_error());
}

// The replaced folder `old`: its entries that are not the result's go into
// `dir` (unless it has its own), then it is removed, manifest first, so that
// a folder half removed never looks finished.
void discard_replaced(const std::string& old, const std::string& dir, const ResultNames& own) {
  bool moved = false;
  for (const auto& name : entries_of(old)) {
    if (name == kLockName || name == kManifestName || name == kStampName ||
        name == kSupersededName || name == kAsideName || own(name) ||
        entry_exists(dir + "/" + name))
      continue;
    rename_or_throw(old + "/" + name, dir + "/" + name, "keep '" + name + "'");
    moved = true;
  }
  if (moved) sync_directory(dir);
  withdraw_results(old, {});
  fault_point("discarding");
  std::error_code ec;
  fs::remove_all(old, ec);
  if (ec) throw IoError("cannot remove the replaced result '" + old + "': " + ec.message());
  sync_directory(directory_of(old));
  if (fs::remove(dir + "/" + kStampName, ec)) sync_directory(dir);
}

}  // namespace

std::string staging_dir(const std::string& dir) { return trimmed(dir) + kStagingSuffix; }

StagingState staging_state(const std::string& dir) {
  const std::string staging = staging_dir(dir);
  std::error_code ec;
  const auto status = fs::symlink_status(staging, ec);
  if (!fs::exists(status)) return StagingState::none;
  if (!fs::is_directory(status)) return StagingState::foreign;
  if (entry_exists(staging + "/" + kStampName) || entry_exists(staging + "/" + kSupersededName))
    return StagingState::ours;
  // Made by a run killed before it stamped it: a lock at most.
  for (const auto& name : entries_of(staging))
    if (name != kLockName) return StagingState::foreign;
  return StagingState::ours;
}

void check_replaceable(const std::string& dir) {
  const std::string d = trimmed(dir);
  const std::string name = fs::path(d).filename().string();
  const auto refuse = [&](const std::string& why) {
    throw InputError("-output_overwrite: the result in '" + dir +
                     "' cannot be replaced by a "
                     "rename (" +
                     why +
                     "); remove its manifest.txt to compute it again in "
                     "place, or choose another -output_dir");
  };
  if (name.empty() || name == "." || name == "..") refuse("name the folder itself");
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(d, ec)))
    refuse("it is a symbolic link: pass the folder it points to");
  struct stat self {
  }, parent{};
  if (::stat(d.c_str(), &self) != 0 || ::stat(directory_of(d).c_str(), &parent) != 0)
    throw IoError("cannot read '" + d + "' or its parent: " + last_error());
  if (self.st_dev != parent.st_dev) refuse("it is a mount point");
}

std::string finish_replacement(const std::string& dir, const ResultNames& own) {
  const std::string d = trimmed(dir), staging = staging_dir(dir);
  const bool ours = staging_state(dir) == StagingState::ours;
  std::string done;
  // Two renames cut between them: the old folder is aside in the staging
  // folder, and `dir` is the empty folder this run's lock made again.
  if (ours && fs::is_directory(staging + "/" + kAsideName) && !has_manifest(d) &&
      entry_exists(staging + "/" + kManifestName)) {
    for (const auto& name : entries_of(d))
      if (name != kLockName)
        throw IoError("cannot finish replacing the result of '" + d + "' by the one in '" +
                      staging + "': '" + d + "/" + name + "' is in the way");
    std::error_code ec;
    fs::remove(d + "/" + kLockName, ec);  // the staging folder's lock, held, comes instead
    rename_or_throw(staging, d, "finish replacing the result of '" + d + "'");
    sync_directory(directory_of(d));
    done = "put the new result of an interrupted -output_overwrite in place";
  }
  if (fs::is_directory(d + "/" + kAsideName)) {
    discard_replaced(d + "/" + kAsideName, d, own);
    done += std::string(done.empty() ? "" : "; ") + "removed the result it replaced (" + d + "/" +
            kAsideName + ")";
  }
  if (ours && entry_exists(staging + "/" + kSupersededName)) {
    discard_replaced(staging, d, own);
    done += std::string(done.empty() ? "" : "; ") +
            "removed the result replaced by an interrupted -output_overwrite (" + staging + ")";
  }
  return done;
}

bool prepare_staging(const std::string& dir) {
  const std::string d = trimmed(dir), staging = staging_dir(dir);
  struct stat a {
  }, b{};
  if (::stat(d.c_str(), &a) != 0 || ::stat(staging.c_str(), &b) != 0)
    throw IoError("cannot read '" + d + "' or '" + staging + "': " + last_error());
  if (a.st_dev != b.st_dev)
    throw InputError("-output_overwrite: '" + staging + "' is not on the filesystem of '" + d +
                     "', so the new result computed there could not take the old one's place "
                     "by a rename; remove it (or " +
                     d +
                     "/manifest.txt to compute the result "
                     "again in place)");
  if (!entry_exists(staging + "/" + kStampName))
    write_text_file_atomically(staging + "/" + kStampName,
                               "lem_fracture -output_overwrite computes the new result of '" + d +
                                   "' here; it takes the old one's place when complete\n");
  // Does the filesystem swap two folders in one rename?  Tried on two of
  // its own.
  const std::string a_dir = staging + "/.exchange_a", b_dir = staging + "/.exchange_b";
  std::error_code ec;
  for (const auto& p : {a_dir, b_dir}) {
    fs::remove_all(p, ec);
    if (!fs::create_directory(p, ec)) throw IoError("cannot create '" + p + "': " + ec.message());
  }
  bool swapped = false;
  int why = 0;  // 0: the test hook says it cannot
  if (std::getenv("LEM_FAULT_NO_EXCHANGE") == nullptr) {
    swapped = ::renameat2(AT_FDCWD, a_dir.c_str(), AT_FDCWD, b_dir.c_str(), RENAME_EXCHANGE) == 0;
    why = swapped ? 0 : errno;
  }
  for (const auto& p : {a_dir, b_dir}) fs::remove_all(p, ec);
  if (why != 0 && why != EINVAL && why != ENOSYS && why != EOPNOTSUPP)
    throw IoError("cannot exchange '" + a_dir + "' and '" + b_dir + "': " + std::strerror(why));
  return swapped;
}

bool clear_staging(const std::string& dir) {
  const std::string staging = staging_dir(dir);
  bool removed = false;
  for (const auto& name : entries_of(staging)) {
    if (name == kLockName || name == kStampName) continue;
    std::error_code ec;
    fs::remove_all(staging + "/" + name, ec);
    if (ec) throw IoError("cannot remove '" + staging + "/" + name + "': " + ec.message());
    removed = true;
  }
  if (removed) sync_directory(staging);
  return removed;
}

void install_result(const std::string& dir, bool exchange, const ResultNames& own) {
  const std::string d = trimmed(dir), staging = staging_dir(dir), parent = directory_of(d);
  if (exchange) {
    // Marked first, so that once swapped the old folder is known as such.
    write_text_file_atomically(d + "/" + kSupersededName,
                               "the result in this folder was replaced by -output_overwrite; "
                               "the folder is removed\n");
    fault_point("before_exchange");
    if (::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, d.c_str(), RENAME_EXCHANGE) != 0)
      throw IoError("cannot put the new result in place: exchanging '" + staging + "' and '" + d +
                    "' failed: " + last_error());
    sync_directory(parent);
    fault_point("after_exchange");
    discard_replaced(staging, d, own);
    return;
  }
  rename_or_throw(d, staging + "/" + kAsideName, "put the new result in place");
  sync_directory(staging);
  sync_directory(parent);
  fault_point("moved_aside");
  rename_or_throw(staging, d, "put the new result in place");
  sync_directory(parent);
  fault_point("after_install");
  discard_replaced(d + "/" + kAsideName, d, own);
}

void fault_point(const char* point) {
  const char* wanted = std::getenv("LEM_FAULT_KILL");
  if (wanted && std::strcmp(wanted, point) == 0) ::kill(::getpid(), SIGKILL);
}

}  // namespace lem
