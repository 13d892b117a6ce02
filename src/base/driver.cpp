#include "lem/base/driver.hpp"

#include "lem/base/error.hpp"
#include "lem/base/options.hpp"
#include "lem/base/provenance.hpp"
#include "lem/base/stop.hpp"

#include <petscsys.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace lem {

int run_driver(int argc, char** argv, const char* help, const std::function<void(MPI_Comm)>& body,
               StopHandling stops) {
  // -version answers and runs nothing (PETSc's own -version would print
  // only PETSc's and go on with the job).
  if (version_requested(argc, argv)) {
    MPI_Init(&argc, &argv);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0)
      std::printf("%s", version_text(std::filesystem::path(argv[0]).filename().string()).c_str());
    MPI_Finalize();
    return 0;
  }
  const bool handle_stops = stops == StopHandling::save_and_exit;
  if (handle_stops) install_stop_handler();  // MPI start-up can take a while
  // PETSc cannot start on a missing options file and drops stray words:
  // say which, once.
  std::string unreadable = stray_command_line_word(argc, argv);
  if (unreadable.empty()) unreadable = unreadable_options_file(argc, argv);
  if (!unreadable.empty()) {
    MPI_Init(&argc, &argv);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0) std::fprintf(stderr, "%s: %s\n", status_label(1), unreadable.c_str());
    MPI_Finalize();
    return 1;
  }
  if (PetscInitialize(&argc, &argv, nullptr, help)) return 3;
  if (handle_stops) install_stop_handler();  // in case PETSc took the signals
  take_over_petsc_errors();
  int status = 0;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  {
    RankEnds ends(PETSC_COMM_WORLD);
    std::string message;
    try {
      body(PETSC_COMM_WORLD);
      // A request that came after the body's last stop point.
      if (handle_stops)
        if (const int signal = stop_requested(PETSC_COMM_WORLD, "driver_end"))
          throw Interrupted(signal_name(signal) + " came after the work was complete: nothing "
                                                  "to resume");
    } catch (const HelpShown& e) {
      if (rank == 0) std::printf("\n%s\n", e.what());
    } catch (const std::exception& e) {
      status = exit_status(e);
      message = e.what();
    } catch (...) {
      status = 3;
      message = "an exception of unknown type";
    }
    status = ends.finish(status, message);
  }
  PetscFinalize();
  if (handle_stops) {
    install_stop_handler();  // PETSc may have restored the default actions
    // Past the last collective: this rank alone reports it.
    if (status == 0 && stop_signal_received() != 0) {
      std::fprintf(stderr,
                   "interrupted: %s came while the run was ending; its work is "
                   "complete\n",
                   signal_name(stop_signal_received()).c_str());
      status = 4;
    }
  }
  return status;
}

std::vector<double> peak_memory_per_rank_mb(MPI_Comm comm) {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double mine = static_cast<double>(usage.ru_maxrss) / 1024.0;  // kB on Linux
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  std::vector<double> all(static_cast<std::size_t>(ranks));
  MPI_Allgather(&mine, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, comm);
  return all;
}

PeakMemory peak_memory(MPI_Comm comm) {
  const std::vector<double> all = peak_memory_per_rank_mb(comm);
  PeakMemory m;
  m.max_mb = *std::max_element(all.begin(), all.end());
  for (const double mb : all) m.mean_mb += mb / static_cast<double>(all.size());
  return m;
}

namespace {
// MemAvailable of this machine in bytes (0 if unknown).
double available_memory() {
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  double kb = 0;
  while (in >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024.0;
  return 0;
}
}  // namespace

MachineMemory tightest_machine(MPI_Comm comm, double bytes) {
  int rank = 0, machine_rank = 0;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm machine = MPI_COMM_NULL;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &machine);
  MachineMemory m;
  MPI_Comm_size(machine, &m.ranks);
  MPI_Comm_rank(machine, &machine_rank);
  MPI_Allreduce(&bytes, &m.need, 1, MPI_DOUBLE, MPI_SUM, machine);
  m.available = machine_rank == 0 ? available_memory() : 0;
  MPI_Bcast(&m.available, 1, MPI_DOUBLE, 0, machine);
  MPI_Comm_free(&machine);
  struct {
    double share;
    int rank;
  } mine{m.available > 0 ? m.need / m.available : 0.0, rank}, worst{};
  MPI_Allreduce(&mine, &worst, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm);
  double values[3] = {m.need, m.available, static_cast<double>(m.ranks)};
  MPI_Bcast(values, 3, MPI_DOUBLE, worst.rank, comm);
  return {values[0], values[1], static_cast<int>(values[2])};
}

}  // namespace lem
