#include "lem/base/stop.hpp"

#include <signal.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>

namespace lem {

namespace {

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void note_stop_signal(int signal) {
  if (g_stop_signal == 0) g_stop_signal = signal;
}

// The pass count of `point` if LEM_FAULT_PAUSE asks to pause at this pass.
int pause_pass(const char* point) {
  const char* wanted = std::getenv("LEM_FAULT_PAUSE");
  if (!wanted) return 0;
  const std::size_t length = std::strlen(point);
  if (std::strncmp(wanted, point, length) != 0 || (wanted[length] != '\0' && wanted[length] != ':'))
    return 0;
  const int at = wanted[length] == ':' ? std::atoi(wanted + length + 1) : 1;
  static std::map<std::string, int> passes;
  const int pass = ++passes[point];
  return pass == at ? pass : 0;
}

}  // namespace

void install_stop_handler() {
  struct sigaction action {};
  action.sa_handler = note_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGUSR1, &action, nullptr);
}

int stop_signal_received() { return g_stop_signal; }

int stop_requested(MPI_Comm comm, const char* point) {
  fault_pause(comm, point);
  int mine = g_stop_signal, any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm);
  return any;
}

std::string signal_name(int signal) {
  if (signal == SIGTERM) return "SIGTERM";
  if (signal == SIGUSR1) return "SIGUSR1";
  return "signal " + std::to_string(signal);
}

void fault_pause(MPI_Comm comm, const char* point, const std::string& detail) {
  const int pass = pause_pass(point);
  if (pass == 0) return;  // the same on every rank: they pass the same points
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::fprintf(stderr, "test hook: rank %d (pid %d) paused at %s (pass %d%s%s)\n", rank,
               static_cast<int>(::getpid()), point, pass, detail.empty() ? "" : "; ",
               detail.c_str());
  std::fflush(stderr);
  const double start = MPI_Wtime();
  for (;;) {
    // Leave together: when some rank got a signal, or on rank 0's clock.
    int state[2] = {g_stop_signal, rank == 0 && MPI_Wtime() - start > 120}, any[2] = {0, 0};
    MPI_Allreduce(state, any, 2, MPI_INT, MPI_MAX, comm);
    if (any[0] != 0 || any[1] != 0) break;
    ::usleep(10000);
  }
}

}  // namespace lem
