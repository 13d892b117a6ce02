#include "lem/protocol/checkpoint.hpp"

#include "lem/byte_stream.hpp"
#include "lem/collective.hpp"
#include "lem/driver.hpp"
#include "lem/error.hpp"
#include "lem/files.hpp"
#include "lem/hdf5_writer.hpp"
#include "lem/write_watch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <unistd.h>

namespace lem {

namespace {

// Version 3: the check field of a decided field follows the displacement
// (version 2 had none, version 1 another state layout).
constexpr char kCheckpointMagic[8] = {'L', 'E', 'M', 'C', 'K', 'P', 'T', '3'};

void put(ByteWriter& w, const DamageHistory& h) {
  w.vec(h.bond_events), w.vec(h.bond_batches), w.vec(h.node_events), w.vec(h.node_batches);
  w.vec(h.build_batches);
}

void get(ByteReader& r, DamageHistory& h) {
  r.vec(h.bond_events), r.vec(h.bond_batches), r.vec(h.node_events), r.vec(h.node_batches);
  r.vec(h.build_batches);
}

}  // namespace

void write_checkpoint_file(const std::string& path, const Checkpoint& c) {
  ByteWriter w;
  w.raw(kCheckpointMagic, sizeof(kCheckpointMagic));
  w.pod(static_cast<std::uint64_t>(sizeof(FractureState)));
  w.pod(c.state);
  w.str(c.fingerprint);
  put(w, c.damage);
  w.vec(c.displacement);
  w.vec(c.check_displacement);
  w.pod(fnv1a(w.bytes.data(), w.bytes.size()));
  write_text_file_atomically(path, std::string(w.bytes.begin(), w.bytes.end()));
}

namespace {

// Beyond the checksum, which a crafted file passes: sizes and ids must fit
// the run the fingerprint describes (the fingerprint itself is compared
// with this run's by CheckpointStore::load; bond ids by the ledger's replay).
void check_checkpoint_values(const Checkpoint& c, const std::string& bad) {
  const auto refuse = [&](const std::string& what) {
    throw InputError(bad + what + "); remove it or pass -checkpoint_resume false");
  };
  std::int64_t nodes = -1;
  std::istringstream lines(c.fingerprint);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("nodes=", 0) == 0) std::istringstream(line.substr(6)) >> nodes;
  if (nodes < 0) refuse("no node count in its fingerprint");
  if (c.displacement.size() != 3 * static_cast<std::uint64_t>(nodes))
    refuse(std::to_string(c.displacement.size()) + " displacement values for " +
           std::to_string(nodes) + " nodes");
  if (!c.check_displacement.empty() && c.check_displacement.size() != c.displacement.size())
    refuse(std::to_string(c.check_displacement.size()) + " check field values for " +
           std::to_string(nodes) + " nodes");
  for (const auto* field : {&c.displacement, &c.check_displacement})
    for (std::size_t i = 0; i < field->size(); ++i)
      if (!std::isfinite((*field)[i]))
        refuse(std::string(field == &c.displacement ? "displacement " : "check field value ") +
               std::to_string(i) + " is not finite");
  const FractureState& s = c.state;
  const FractureTally& t = s.tally;
  for (const std::int64_t count : {t.steps, t.visited_steps, t.solves, t.iterations,
                                   t.preconditioner_builds, t.rupture_steps, s.batches,
                                   s.files.curve_bytes, s.files.broken_bytes})
    if (count < 0) refuse("a negative count in its state");
  const DamageHistory& h = c.damage;
  // Batches are numbered 1, 2, ... in order; builds follow batch 0 (the
  // intact system) or a later one.
  const auto check_batches = [&](const std::vector<std::int64_t>& batches, std::int64_t lowest,
                                 const char* what) {
    for (std::size_t k = 0; k < batches.size(); ++k)
      if (batches[k] < lowest || batches[k] > s.batches || (k > 0 && batches[k] < batches[k - 1]))
        refuse(std::string(what) + " " + std::to_string(k) + " is in batch " +
               std::to_string(batches[k]) + ", out of order or beyond the " +
               std::to_string(s.batches) + " batches of its state");
  };
  check_batches(h.bond_batches, 1, "bond event");
  check_batches(h.node_batches, 1, "node event");
  check_batches(h.build_batches, 0, "preconditioner build");
  for (std::size_t k = 0; k < h.node_events.size(); ++k)
    if (h.node_events[k] < 0 || h.node_events[k] >= nodes)
      refuse("node event " + std::to_string(k) + " pins node " +
             std::to_string(h.node_events[k]) + ", not one of the " + std::to_string(nodes) +
             " nodes");
  std::vector<std::int64_t> bonds = h.bond_events;
  std::sort(bonds.begin(), bonds.end());
  if (!bonds.empty() && bonds.front() < 0)
    refuse("a bond event breaks bond " + std::to_string(bonds.front()));
  const auto twice = std::adjacent_find(bonds.begin(), bonds.end());
  if (twice != bonds.end()) refuse("bond " + std::to_string(*twice) + " is broken twice");
}

}  // namespace

Checkpoint read_checkpoint_file(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError("cannot open the checkpoint '" + path + "'");
  std::vector<char> bytes;
  char buffer[1 << 16];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof(buffer), f)) > 0;)
    bytes.insert(bytes.end(), buffer, buffer + n);
  std::fclose(f);
  const std::string bad = "the checkpoint '" + path + "' is not a valid lem checkpoint (";
  if (bytes.size() < sizeof(kCheckpointMagic) + 16 ||
      std::memcmp(bytes.data(), kCheckpointMagic, sizeof(kCheckpointMagic)) != 0)
    throw InputError(bad + "wrong header or another version of the code); remove it or pass "
                     "-checkpoint_resume false");
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  if (fnv1a(bytes.data(), bytes.size() - 8) != stored)
    throw InputError(bad + "checksum mismatch: truncated or corrupt); remove it or pass "
                     "-checkpoint_resume false");
  Checkpoint c;
  try {
    ByteReader r(bytes, bytes.size() - 8);
    char magic[8];
    r.raw(magic, 8);
    std::uint64_t state_size = 0;
    r.pod(state_size);
    if (state_size != sizeof(FractureState)) throw std::runtime_error("version");
    r.pod(c.state);
    r.str(c.fingerprint);
    get(r, c.damage);
    r.vec(c.displacement);
    r.vec(c.check_displacement);
    const DamageHistory& h = c.damage;
    if (!r.at_end() || h.bond_events.size() != h.bond_batches.size() ||
        h.node_events.size() != h.node_batches.size())
      throw std::runtime_error("layout");
  } catch (const std::runtime_error& e) {
    throw InputError(bad + "written by another version of the code: " + e.what() + ")");
  }
  check_checkpoint_values(c, bad);
  return c;
}

std::string fracture_fingerprint(const DistributedLattice& l, const FractureOptions& o) {
  // The intact sample (ids, stiffnesses, thresholds after disorder), hashed
  // in an order-free way, and every option that changes the results.
  std::uint64_t sum = 0;
  for (int b = 0; b < l.local_bonds(); ++b) {
    if (!l.bond_reported[b]) continue;
    std::uint64_t k = 0, f = 0;
    std::memcpy(&k, &l.bond_stiffness[b], 8);
    if (!l.bond_strength.empty()) std::memcpy(&f, &l.bond_strength[b], 8);
    sum += mix64(static_cast<std::uint64_t>(l.bond_id[b]) ^ mix64(k ^ mix64(f)));
  }
  std::uint64_t total = 0;
  MPI_Allreduce(&sum, &total, 1, MPI_UINT64_T, MPI_SUM, l.comm);
  int ranks = 1;
  MPI_Comm_size(l.comm, &ranks);
  std::ostringstream s;
  s.precision(17);
  s << "ranks=" << ranks << "\nnodes=" << l.global_nodes << "\nbonds=" << l.global_bonds
    << "\nsample_checksum=" << total << "\nincrement=" << o.increment
    << "\nbreak_rule=" << name_of(o.break_rule) << "\nskip_idle=" << o.skip_idle
    << "\npc_rebuild_ruptures=" << o.rebuild_after_ruptures
    << "\npc_rebuild_growth=" << o.rebuild_iteration_growth
    << "\nrelaxation=" << name_of(o.relaxation);
  if (o.relaxation == RelaxationScheme::local)
    s << "\npatch_radius=" << o.patch_radius << "\npatch_margin=" << o.patch_margin
      << "\npatch_max_fraction=" << o.patch_max_fraction << "\npatch_rtol=" << o.patch_rtol;
  if (o.decision_safety > 0)
    s << "\ndecision_safety=" << o.decision_safety
      << "\ndecision_interval=" << o.decision_interval
      << "\ndecided_closing=" << o.decided_closing;
  // Only when changed, so that keys made before the rule existed still match.
  const FractureOptions defaults;
  if (o.tie_band != defaults.tie_band || o.tie_rtol != defaults.tie_rtol)
    s << "\ntie_band=" << o.tie_band << "\ntie_rtol=" << o.tie_rtol;
  s << "\n";
  // Solver options are left out on purpose: a run stopped by a failed solve
  // may be resumed with others (then equal to the tolerance, not bitwise).
  return s.str();
}

std::string fingerprint_differences(const std::string& theirs, const std::string& ours,
                                    int& other_ranks, const char* label) {
  auto lines = [](const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
  };
  const auto a = lines(theirs), b = lines(ours);
  other_ranks = 0;
  if (a.size() != b.size()) return "\n  (a different option set)";
  std::string differs;
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (a[i] == b[i]) continue;
    if (a[i].rfind("ranks=", 0) == 0 && b[i].rfind("ranks=", 0) == 0)
      other_ranks = std::stoi(a[i].substr(6));
    else
      differs += "\n  " + std::string(label) + ": " + a[i] + "   this run: " + b[i];
  }
  return differs;
}

CheckpointStore::CheckpointStore(const DistributedLattice& lattice, std::string path,
                                 std::string fingerprint)
    : lattice_(lattice), path_(std::move(path)), fingerprint_(std::move(fingerprint)) {}

bool CheckpointStore::exists() const {
  int rank = 0, found = 0;
  MPI_Comm_rank(lattice_.comm, &rank);
  if (rank == 0) found = ::access(path_.c_str(), F_OK) == 0;
  MPI_Bcast(&found, 1, MPI_INT, 0, lattice_.comm);
  return found != 0;
}

Checkpoint CheckpointStore::load() const {
  Checkpoint c;
  int other_ranks = 0;  // rank count of a checkpoint written by another one
  run_on_root(lattice_.comm, [&] {
    c = read_checkpoint_file(path_);
    // Everything in the checkpoint is by lattice id, so another partition
    // can take it over: the rank count may differ.
    const std::string differs = fingerprint_differences(c.fingerprint, fingerprint_, other_ranks);
    if (!differs.empty())
      throw InputError("the checkpoint '" + path_ + "' belongs to a different run "
                       "(sample or options):" + differs + "\nresume with the same command, or "
                       "pass -checkpoint_resume false to start over");
  });
  MPI_Bcast(&other_ranks, 1, MPI_INT, 0, lattice_.comm);
  if (other_ranks > 0) {
    int ranks = 1;
    MPI_Comm_size(lattice_.comm, &ranks);
    say("resuming a checkpoint written on %d ranks on %d: the preconditioner differs, so the "
        "rest of the run agrees with an uninterrupted one to the solver tolerance, not bit for "
        "bit\n", other_ranks, ranks);
  }
  broadcast_value(lattice_.comm, c.state);
  DamageHistory& h = c.damage;
  for (auto* v : {&h.bond_events, &h.bond_batches, &h.node_events, &h.node_batches,
                  &h.build_batches})
    broadcast(lattice_.comm, *v);
  broadcast(lattice_.comm, c.displacement);
  broadcast(lattice_.comm, c.check_displacement);
  return c;
}

void CheckpointStore::hold(const FractureState& state, const DamageMark& damage,
                           std::vector<double> owned_u, std::vector<double> owned_check) {
  held_ = {state, damage, std::move(owned_u), std::move(owned_check)};
}

void CheckpointStore::save(const DamageLedger& ledger) const {
  // Displacements by lattice node id.
  const DistributedLattice& l = lattice_;
  std::vector<std::int64_t> ids(l.node_id.begin(), l.node_id.begin() + l.owned);
  const auto all_ids = allgather(l.comm, ids);
  const auto all_u = allgather(l.comm, held_.u);
  const auto all_check = allgather(l.comm, held_.check);  // empty on every rank, or full
  // The other ranks wait for rank 0's write: a stop request reaches them
  // there too (write_watch.hpp).
  const WriteWatch watch(l.comm, path_, path_ + ".tmp");
  run_on_root(l.comm, [&] {
    Checkpoint c;
    c.state = held_.state;
    c.fingerprint = fingerprint_;
    c.damage = ledger.prefix(held_.damage);
    const auto by_id = [&](const std::vector<double>& owned, std::vector<double>& field) {
      field.assign(3 * static_cast<std::size_t>(l.global_nodes), 0.0);
      for (std::size_t i = 0; i < all_ids.size(); ++i)
        for (int a = 0; a < 3; ++a) field[3 * all_ids[i] + a] = owned[3 * i + a];
    };
    by_id(all_u, c.displacement);
    if (!all_check.empty()) by_id(all_check, c.check_displacement);
    write_checkpoint_file(path_, c);
  });
}

std::string checkpoint_path(const std::string& output_dir) {
  return output_dir + "/checkpoint.bin";
}

void remove_checkpoint(const std::string& output_dir) {
  if (std::remove(checkpoint_path(output_dir).c_str()) == 0) sync_directory(output_dir);
}

}  // namespace lem
