#include "lem/files.hpp"

#include "lem/error.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

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

}  // namespace

void write_text_file_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  const auto fail = [&](const std::string& why) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw IoError("cannot write file '" + path + "': " + why);
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("cannot create '" + tmp + "': " + last_error());
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
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
  if (!sync_path(dir, true))
    throw IoError("cannot sync directory '" + dir + "': " + last_error());
}

void prepare_output_dir(MPI_Comm comm, const std::string& dir,
                        const std::vector<std::string>& result_files) {
  run_on_root(comm, [&] {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
      throw InputError("output directory '" + dir + "' cannot be created: " + ec.message());
    for (const auto& f : result_files) fs::remove(dir + "/" + f, ec);
  });
}

OutputLock::OutputLock(MPI_Comm comm, const std::string& dir) {
  run_on_root(comm, [&] {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
      throw InputError("output directory '" + dir + "' cannot be created: " + ec.message());
    // The lock file is never removed: removing it would let a second run
    // lock a new file while the first still holds the old one.
    const std::string path = dir + "/.lock";
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0)
      throw InputError("output directory '" + dir + "': cannot open its lock file '" + path +
                       "': " + last_error());
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int saved = errno;
      ::close(fd_);
      fd_ = -1;
      if (saved == EWOULDBLOCK)
        throw InputError("output directory '" + dir + "' is in use by another run (it holds "
                         "the lock on '" + path + "'); wait for it to end or choose another "
                         "-output_dir");
      errno = saved;
      throw InputError("output directory '" + dir + "': cannot lock '" + path + "': " +
                       last_error());
    }
  });
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

namespace {
constexpr char kManifestName[] = "manifest.txt";
constexpr char kFileKey[] = "file=";
constexpr char kProgramKey[] = "program=";
constexpr char kFingerprintKey[] = "fingerprint ";
}  // namespace

std::optional<Manifest> read_manifest(const std::string& dir) {
  const std::string path = dir + "/" + kManifestName;
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
    }
  }
  // Written atomically, so a manifest without its last line was not written
  // by lem: refuse it rather than guess.
  if (!end || m.program.empty())
    throw InputError("the manifest '" + path + "' is damaged (no program or no end line); "
                     "remove it, or pass -output_overwrite to compute the result again");
  return m;
}

std::string manifest_mismatch(const std::string& dir, const Manifest& m) {
  std::string why;
  for (const auto& [name, size] : m.files) {
    std::error_code ec;
    const auto actual = fs::file_size(dir + "/" + name, ec);
    if (ec)
      why += "\n  " + name + " is missing";
    else if (static_cast<std::int64_t>(actual) != size)
      why += "\n  " + name + " has " + std::to_string(actual) + " bytes, the manifest says " +
             std::to_string(size);
  }
  return why;
}

void commit_results(const std::string& dir, const std::string& program,
                    const std::string& fingerprint, const std::vector<std::string>& files) {
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

void fault_point(const char* point) {
  const char* wanted = std::getenv("LEM_FAULT_KILL");
  if (wanted && std::strcmp(wanted, point) == 0) ::kill(::getpid(), SIGKILL);
}

}  // namespace lem
