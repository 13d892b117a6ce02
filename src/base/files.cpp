#include "lem/files.hpp"

#include "lem/error.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
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
    throw InputError("cannot write file '" + path + "': " + why);
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
    throw InputError("cannot move '" + from + "' to '" + to + "': " + what + ": " + why);
  };
  if (!sync_path(from, false)) fail("syncing failed");
  if (std::rename(from.c_str(), to.c_str()) != 0) fail("renaming failed");
  // The rename itself is durable once the directory is synced.
  if (!sync_path(directory_of(to), true))
    throw InputError("cannot sync directory '" + directory_of(to) + "' after writing '" + to +
                     "': " + last_error());
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

}  // namespace lem
