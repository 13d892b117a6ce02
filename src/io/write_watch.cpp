#include "lem/io/write_watch.hpp"

#include "lem/base/error.hpp"
#include "lem/base/stop.hpp"

#include <sys/statvfs.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

namespace lem {

namespace {

using Clock = std::chrono::steady_clock;

std::atomic<double> g_stop_grace{60};

}  // namespace

struct WriteWatch::State {
  std::string file, temporary;
  int rank = 0;
  std::mutex mutex;
  std::condition_variable wake;
  bool done = false;
  std::string error;  // this rank's first I/O error
  Clock::time_point failed_at;
  std::thread thread;

  [[noreturn]] void end_job(int status, const std::string& message) {
    std::remove(temporary.c_str());  // any rank may: nothing of it must stay
    std::fprintf(stderr, "%s on rank %d (%s; ending the job): %s\n", status_label(status), rank,
                 status == 3 ? "the ranks cannot finish the write together" : "a write goes on",
                 message.c_str());
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, status);
    std::_Exit(status);
  }

  void watch() {
    std::unique_lock<std::mutex> lock(mutex);
    std::optional<Clock::time_point> stop_seen;
    const auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
    while (!done) {
      wake.wait_for(lock, std::chrono::milliseconds(50));
      if (done) break;
      const auto now = Clock::now();
      // Rank 0 first, so that one message is printed as a rule.
      const double later = rank > 0 ? 2 : 0;
      if (!error.empty() && seconds(now - failed_at) > kErrorGraceSeconds + later)
        end_job(3, "cannot write '" + file + "': " + error + "; nothing of it is in place");
      if (!stop_seen && stop_signal_received() != 0) stop_seen = now;
      const double grace = g_stop_grace.load();
      if (stop_seen && seconds(now - *stop_seen) > grace + later) {
        char after[32];
        std::snprintf(after, sizeof after, "%g", grace);
        end_job(4, "stopped by " + signal_name(stop_signal_received()) + " while writing '" + file +
                       "', which had not ended " + after +
                       " s later "
                       "(-output_write_grace): abandoned, nothing of it is in place; run the "
                       "same command again to resume from the last checkpoint");
      }
    }
  }
};

namespace {

// The watch of the write in progress on this rank (writes do not nest).
std::atomic<WriteWatch::State*> g_active{nullptr};

void record(WriteWatch::State& s, const std::string& why) {
  const std::lock_guard<std::mutex> lock(s.mutex);
  if (!s.error.empty()) return;
  s.error = why;
  s.failed_at = Clock::now();
  s.wake.notify_one();
}

std::string mpi_error_text(int code) {
  char text[MPI_MAX_ERROR_STRING] = {};
  int length = 0;
  MPI_Error_string(code, text, &length);
  return text;
}

// MPI-IO's errors, as they arise inside the HDF5 library: the library may
// never return to us after one.
extern "C" void note_file_error(MPI_File*, int* code, ...) {
  if (WriteWatch::State* s = g_active.load()) record(*s, "MPI-IO: " + mpi_error_text(*code));
}

// A write that MPI-IO cut short: ompio reports a full disk to HDF5 as a
// write of fewer items than asked, with MPI_SUCCESS, and HDF5 may then hold
// the ranks in different collective calls before it returns.
void check_write(const char* call, int code, int count, MPI_Datatype type, const MPI_Status* status,
                 int error_number) {
  if (g_active.load() == nullptr) return;
  int written = 0;
  if (code == MPI_SUCCESS &&
      (PMPI_Get_count(status, type, &written) != MPI_SUCCESS || written == count))
    return;
  std::string why = call;
  if (code != MPI_SUCCESS) {
    why += " failed: " + mpi_error_text(code);
  } else {
    why += written == MPI_UNDEFINED
               ? std::string(" wrote only part of its data")
               : " wrote " + std::to_string(written) + " of " + std::to_string(count) + " items";
  }
  if (error_number != 0) why += std::string(" (") + std::strerror(error_number) + ")";
  WriteWatch::note_error("MPI-IO: " + why + WriteWatch::space_left());
}

void install_file_error_handler() {
  static const bool installed = [] {
    MPI_Errhandler handler = MPI_ERRHANDLER_NULL;
    // The handler of MPI_FILE_NULL is the one every file opened later gets;
    // it returns, so the failing call still returns its error code.
    return MPI_File_create_errhandler(note_file_error, &handler) == MPI_SUCCESS &&
           MPI_File_set_errhandler(MPI_FILE_NULL, handler) == MPI_SUCCESS;
  }();
  (void)installed;
}

}  // namespace

WriteWatch::WriteWatch(MPI_Comm comm, std::string file, std::string temporary)
    : state_(std::make_unique<State>()) {
  install_file_error_handler();
  state_->file = std::move(file);
  state_->temporary = std::move(temporary);
  MPI_Comm_rank(comm, &state_->rank);
  state_->thread = std::thread([s = state_.get()] { s->watch(); });
  g_active.store(state_.get());
}

WriteWatch::~WriteWatch() {
  g_active.store(nullptr);
  {
    const std::lock_guard<std::mutex> lock(state_->mutex);
    state_->done = true;
    state_->wake.notify_one();
  }
  state_->thread.join();
}

void WriteWatch::note_error(const std::string& why) {
  if (State* s = g_active.load()) record(*s, why);
}

std::string WriteWatch::first_error() {
  State* s = g_active.load();
  if (!s) return {};
  const std::lock_guard<std::mutex> lock(s->mutex);
  return s->error;
}

std::string WriteWatch::space_left() {
  State* s = g_active.load();
  if (!s) return {};
  const std::filesystem::path parent = std::filesystem::path(s->temporary).parent_path();
  const std::string folder = parent.empty() ? std::string(".") : parent.string();
  struct statvfs fs {};
  if (::statvfs(folder.c_str(), &fs) != 0) return {};
  const auto free = static_cast<unsigned long long>(fs.f_bavail) * fs.f_frsize;
  std::string text = "; ";
  text += std::to_string(free);
  text += " bytes free on the filesystem of '";
  text += folder;
  text += free < (1ull << 20) ? "' (full: no space left on device)" : "'";
  return text;
}

void fault_stall(MPI_Comm comm, const std::string& file) {
  const char* wanted = std::getenv("LEM_FAULT_STALL");
  if (!wanted || !*wanted || file.find(wanted) == std::string::npos) return;
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  if (rank != ranks - 1) return;
  std::fprintf(stderr, "test hook: rank %d (pid %d) stalls in the write of %s\n", rank,
               static_cast<int>(::getpid()), file.c_str());
  std::fflush(stderr);
  std::this_thread::sleep_for(std::chrono::seconds(120));
}

void set_write_stop_grace(double seconds) { g_stop_grace.store(seconds); }
double write_stop_grace() { return g_stop_grace.load(); }

}  // namespace lem

namespace lem {
namespace {

// `write(status)`, a call of MPI-IO, checked for a short write.
template <class Write>
int checked_write(const char* call, int count, MPI_Datatype type, MPI_Status* status, Write write) {
  MPI_Status own;
  if (status == MPI_STATUS_IGNORE) status = &own;
  errno = 0;
  const int code = write(status);
  check_write(call, code, count, type, status, errno);
  return code;
}

}  // namespace
}  // namespace lem

// MPI-IO's writes, as the HDF5 library calls them (it is linked against
// these names; the program's own definitions come first).
extern "C" int MPI_File_write_at(MPI_File file, MPI_Offset offset, const void* data, int count,
                                 MPI_Datatype type, MPI_Status* status) {
  return lem::checked_write("MPI_File_write_at", count, type, status, [&](MPI_Status* s) {
    return PMPI_File_write_at(file, offset, data, count, type, s);
  });
}

extern "C" int MPI_File_write_at_all(MPI_File file, MPI_Offset offset, const void* data, int count,
                                     MPI_Datatype type, MPI_Status* status) {
  return lem::checked_write("MPI_File_write_at_all", count, type, status, [&](MPI_Status* s) {
    return PMPI_File_write_at_all(file, offset, data, count, type, s);
  });
}
