// Checkpoints of a fracture run (the signals that ask for one: lem/base/stop.hpp).
//
// A checkpoint holds the state at the last equilibrium (counters, the damage
// history, displacements and what the solver learnt, by lattice node id) and
// a fingerprint of the sample and of the options that change the results.
// The file is binary: a head (a magic word, the state as bytes with its size,
// the rest length-prefixed, an FNV-1a checksum), then the fields by node id,
// then an order-free checksum of their values.  Every rank writes and reads
// the rows of its own nodes (MPI-IO), so no rank ever holds the whole field,
// and another rank count reads it by id; it is written whole or not at all.
#pragma once

#include "lem/base/petsc_handle.hpp"
#include "lem/system/distributed_lattice.hpp"
#include "lem/protocol/damage_ledger.hpp"
#include "lem/protocol/fingerprint.hpp"
#include "lem/protocol/options.hpp"
#include "lem/protocol/state.hpp"

#include <mpi.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace lem {

struct Checkpoint {
  FractureState state;
  std::string fingerprint;
  std::string relaxation_state;  // the scheme's own (Relaxation::saved_state)
  DamageHistory damage;
  // This rank's nodes (the `ids` of the file functions), 3 values each.
  std::vector<double> displacement;
  // The check field of a decided field (ElasticSystem::mark_check), as the
  // displacement; empty when the displacement is an equilibrium.
  std::vector<double> check_displacement;
  // What the solver learnt (ElasticSystem::learnt_space), each column as
  // the displacement.
  std::vector<std::vector<double>> learnt_space;
};

/// Collective: write `checkpoint` to `path` (through <path>.tmp).  Its fields
/// hold the values of the nodes `ids` of this rank; the ids of all ranks are
/// the lattice's 0 .. N-1, each once.  Rank 0's state, fingerprint and
/// history are written.  Throws IoError naming the file on every rank.
void write_checkpoint_file(MPI_Comm comm, const std::string& path, const Checkpoint& checkpoint,
                           const std::vector<std::int64_t>& ids);
/// Collective: read the checkpoint at `path`, each rank the fields of its
/// nodes `ids`.  `accept`, if given, sees the state, fingerprint and history
/// on rank 0 before any field is read, and may refuse them by throwing.
/// Throws InputError naming the file on every rank when it is not a valid
/// checkpoint of this version.
Checkpoint read_checkpoint_file(MPI_Comm comm, const std::string& path,
                                const std::vector<std::int64_t>& ids,
                                const std::function<void(const Checkpoint&)>& accept = {});

/// <output_dir>/checkpoint.bin.
std::string checkpoint_path(const std::string& output_dir);
/// Rank 0: delete the checkpoint of `output_dir` once its results are
/// committed (the removal is synced).
void remove_checkpoint(const std::string& output_dir);

/// The checkpoint file of one run directory: keeps the state of the last
/// equilibrium (hold) so that it can be written later (save), also after a
/// failed solve.  Collective except where noted.
class CheckpointStore {
 public:
  CheckpointStore(const DistributedLattice& lattice, std::string path, std::string fingerprint);

  bool exists() const;
  /// Read, check the fingerprint; each rank gets its own nodes' fields.  Throws InputError
  /// naming what differs, and naming `learning_option` (ElasticSystem::learning_option) when
  /// the rank count changed under it.  Otherwise says so when the rank count changed.
  Checkpoint load(const std::string& learning_option) const;
  /// Remember the state at this equilibrium (owned displacements, the
  /// solver's learnt space as shared columns).
  void hold(const FractureState& state, std::string relaxation_state, const DamageMark& damage,
            std::vector<double> owned_u, std::vector<double> owned_check,
            std::vector<VecHandle> learnt_space);
  /// Write the held state.
  void save(const DamageLedger& ledger) const;
  const FractureState& held_state() const { return held_.state; }
  const std::string& path() const { return path_; }

 private:
  std::vector<std::int64_t> owned_ids() const;

  const DistributedLattice& lattice_;
  std::string path_, fingerprint_;
  struct Held {
    FractureState state;
    std::string relaxation_state;
    DamageMark damage;
    std::vector<double> u, check;  // owned values (check: empty at an equilibrium)
    std::vector<VecHandle> learnt_space;
  } held_;
};

}  // namespace lem
