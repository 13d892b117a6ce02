#include "lem/protocol/checkpoint.hpp"

#include "lem/base/byte_stream.hpp"
#include "lem/base/collective.hpp"
#include "lem/base/log.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/base/fingerprint.hpp"
#include "lem/protocol/registry.hpp"
#include "lem/system/elastic_system.hpp"
#include "lem/io/write_watch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <sstream>
#include <unistd.h>

namespace lem {

namespace {

// Version 6: the learnt space and the checksums of the logs (version 5 had
// neither; 4 was written collectively by id, 3 through rank 0 whole, 2 had no
// check field, 1 another state layout).
constexpr char kCheckpointMagic[8] = {'L', 'E', 'M', 'C', 'K', 'P', 'T', '6'};

void put(ByteWriter& w, const DamageHistory& h) {
  w.vec(h.bond_events), w.vec(h.bond_batches), w.vec(h.node_events), w.vec(h.node_batches);
  w.vec(h.build_batches);
}

void get(ByteReader& r, DamageHistory& h) {
  r.vec(h.bond_events), r.vec(h.bond_batches), r.vec(h.node_events), r.vec(h.node_batches);
  r.vec(h.build_batches);
}

// The layout: the head (magic, its length, the state, the fingerprint, the
// damage history, the value count of the displacement and the check field,
// the columns of the learnt space, an FNV-1a checksum of all that), then the
// fields by node id (3 doubles per node: the displacement, the check field
// if any, each column of the learnt space), then an order-free checksum of
// the field values (each rank sums the terms of its own nodes).
struct Head {
  std::uint64_t bytes = 0;  // where the fields start
  std::uint64_t displacement_values = 0, check_values = 0, learnt_columns = 0;
  std::uint64_t field_checksum = 0;  // the last 8 bytes of the file
  std::uint64_t file_bytes() const {
    return bytes + 8 * ((1 + learnt_columns) * displacement_values + check_values) + 8;
  }
};

// The fields in the order of the file (the check field only if `checked`).
std::vector<const std::vector<double>*> file_fields(const Checkpoint& c, bool checked) {
  std::vector<const std::vector<double>*> fields{&c.displacement};
  if (checked) fields.push_back(&c.check_displacement);
  for (const std::vector<double>& column : c.learnt_space) fields.push_back(&column);
  return fields;
}

// How a message names value `index` of field `field` (file order).
std::string value_name(std::size_t field, bool checked, std::uint64_t index) {
  const std::string at = std::to_string(index);
  if (field == 0) return "displacement " + at;
  if (checked && field == 1) return "check field value " + at;
  return "learnt deflation vector " + std::to_string(field - (checked ? 2 : 1)) + " value " + at;
}

std::uint64_t value_term(std::uint64_t index, double value) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, 8);
  return mix64(mix64(index) ^ bits);
}

std::vector<char> head_bytes(const Checkpoint& c, std::uint64_t displacement_values,
                             std::uint64_t check_values, std::uint64_t learnt_columns) {
  ByteWriter body;
  body.pod(static_cast<std::uint64_t>(sizeof(FractureState)));
  body.pod(c.state);
  body.str(c.fingerprint);
  body.str(c.relaxation_state);
  put(body, c.damage);
  body.pod(displacement_values);
  body.pod(check_values);
  body.pod(learnt_columns);
  ByteWriter w;
  w.raw(kCheckpointMagic, sizeof(kCheckpointMagic));
  w.pod(static_cast<std::uint64_t>(body.bytes.size()));
  w.raw(body.bytes.data(), body.bytes.size());
  w.pod(fnv1a(w.bytes.data(), w.bytes.size()));
  return w.bytes;
}

// Beyond the checksum, which a crafted file passes: sizes and ids must fit
// the run the fingerprint describes (the fingerprint itself is compared
// with this run's by CheckpointStore::load; bond ids by the ledger's replay).
void check_head_values(const Checkpoint& c, const Head& head, const std::string& bad) {
  const auto refuse = [&](const std::string& what) {
    throw InputError(bad + what + "); remove it or pass -checkpoint_resume false");
  };
  std::int64_t nodes = -1;
  std::istringstream lines(c.fingerprint);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("nodes=", 0) == 0) std::istringstream(line.substr(6)) >> nodes;
  if (nodes < 0) refuse("no node count in its fingerprint");
  if (head.displacement_values != 3 * static_cast<std::uint64_t>(nodes))
    refuse(std::to_string(head.displacement_values) + " displacement values for " +
           std::to_string(nodes) + " nodes");
  if (head.check_values != 0 && head.check_values != head.displacement_values)
    refuse(std::to_string(head.check_values) + " check field values for " + std::to_string(nodes) +
           " nodes");
  if (head.learnt_columns > kMostRitzColumns)
    refuse(std::to_string(head.learnt_columns) + " learnt deflation vectors, more than the " +
           std::to_string(kMostRitzColumns) + " -solver_ritz_deflation keeps");
  const FractureState& s = c.state;
  const FractureTally& t = s.tally;
  for (const std::int64_t count :
       {t.steps, t.visited_steps, t.solves, t.iterations, t.preconditioner_builds, t.rupture_steps,
        s.batches, s.files.curve_bytes, s.files.broken_bytes})
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
      refuse("node event " + std::to_string(k) + " pins node " + std::to_string(h.node_events[k]) +
             ", not one of the " + std::to_string(nodes) + " nodes");
  std::vector<std::int64_t> bonds = h.bond_events;
  std::sort(bonds.begin(), bonds.end());
  if (!bonds.empty() && bonds.front() < 0)
    refuse("a bond event breaks bond " + std::to_string(bonds.front()));
  const auto twice = std::adjacent_find(bonds.begin(), bonds.end());
  if (twice != bonds.end()) refuse("bond " + std::to_string(*twice) + " is broken twice");
}

// Rank 0: the head of the file (magic to head checksum) and its trailing
// field checksum, checked against the file's size.
std::vector<char> read_head(const std::string& path, const std::string& bad, Head& head) {
  if (const std::string what = not_a_regular_file(path); !what.empty())
    throw InputError(bad + what +
                     ", not a checkpoint lem wrote); remove it or pass "
                     "-checkpoint_resume false");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError("cannot open the checkpoint '" + path + "'");
  const auto read_at = [&](std::uint64_t offset, void* to, std::size_t n) {
    return std::fseek(f, static_cast<long>(offset), SEEK_SET) == 0 && std::fread(to, 1, n, f) == n;
  };
  std::vector<char> bytes(sizeof(kCheckpointMagic) + 8);
  std::uint64_t body = 0;
  bool ok = read_at(0, bytes.data(), bytes.size()) &&
            std::memcmp(bytes.data(), kCheckpointMagic, sizeof(kCheckpointMagic)) == 0;
  if (ok) std::memcpy(&body, bytes.data() + sizeof(kCheckpointMagic), 8);
  std::fseek(f, 0, SEEK_END);
  const auto size = static_cast<std::uint64_t>(std::ftell(f));
  if (!ok || body > size) {
    std::fclose(f);
    throw InputError(bad + "wrong header or another version of the code); remove it or pass "
                           "-checkpoint_resume false");
  }
  bytes.resize(bytes.size() + body + 8);
  ok = read_at(0, bytes.data(), bytes.size());
  std::uint64_t stored = 0;
  if (ok) std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  if (!ok || fnv1a(bytes.data(), bytes.size() - 8) != stored) {
    std::fclose(f);
    throw InputError(bad + "checksum mismatch: truncated or corrupt); remove it or pass "
                           "-checkpoint_resume false");
  }
  head.bytes = bytes.size();
  std::memcpy(&head.displacement_values, bytes.data() + bytes.size() - 32, 8);
  std::memcpy(&head.check_values, bytes.data() + bytes.size() - 24, 8);
  std::memcpy(&head.learnt_columns, bytes.data() + bytes.size() - 16, 8);
  const bool sized = head.displacement_values < size && head.check_values < size &&
                     head.learnt_columns < size && head.file_bytes() == size;
  ok = sized && read_at(size - 8, &head.field_checksum, 8);
  std::fclose(f);
  if (!ok)
    throw InputError(bad + std::to_string(size) + " bytes where its head announces " +
                     std::to_string(head.file_bytes()) +
                     ": truncated or corrupt); remove it "
                     "or pass -checkpoint_resume false");
  return bytes;
}

Checkpoint parse_head(const std::vector<char>& bytes, const std::string& bad) {
  Checkpoint c;
  try {
    ByteReader r(bytes, bytes.size() - 8);
    char magic[8];
    r.raw(magic, 8);
    std::uint64_t body = 0, state_size = 0, values = 0;
    r.pod(body);
    r.pod(state_size);
    if (state_size != sizeof(FractureState)) throw std::runtime_error("version");
    r.pod(c.state);
    r.str(c.fingerprint);
    r.str(c.relaxation_state);
    get(r, c.damage);
    r.pod(values), r.pod(values), r.pod(values);
    const DamageHistory& h = c.damage;
    if (!r.at_end() || h.bond_events.size() != h.bond_batches.size() ||
        h.node_events.size() != h.node_batches.size())
      throw std::runtime_error("layout");
  } catch (const std::runtime_error& e) {
    throw InputError(bad + "written by another version of the code: " + e.what() + ")");
  }
  return c;
}

// This rank's nodes in id order, as an MPI-IO file view: 3 doubles per node
// at byte 24 * id of a field.
class NodeRows {
 public:
  explicit NodeRows(const std::vector<std::int64_t>& ids) : order_(ids.size()) {
    for (std::size_t k = 0; k < ids.size(); ++k) order_[k] = k;
    std::sort(order_.begin(), order_.end(), [&](auto a, auto b) { return ids[a] < ids[b]; });
    std::vector<MPI_Aint> at(ids.size());
    for (std::size_t k = 0; k < ids.size(); ++k) at[k] = 24 * static_cast<MPI_Aint>(ids[order_[k]]);
    // A rank without nodes still takes part in the collective transfers.
    if (ids.empty()) {
      MPI_Type_dup(MPI_DOUBLE, &view_);
    } else {
      MPI_Type_create_hindexed_block(static_cast<int>(ids.size()), 3, at.data(), MPI_DOUBLE,
                                     &view_);
    }
    MPI_Type_commit(&view_);
  }
  ~NodeRows() { MPI_Type_free(&view_); }
  NodeRows(const NodeRows&) = delete;
  NodeRows& operator=(const NodeRows&) = delete;

  MPI_Datatype view() const { return view_; }
  /// Values in the caller's order -> in id order, and back.
  std::vector<double> sorted(const std::vector<double>& values) const {
    std::vector<double> out(values.size());
    for (std::size_t k = 0; k < order_.size(); ++k)
      for (int a = 0; a < 3; ++a) out[3 * k + a] = values[3 * order_[k] + a];
    return out;
  }
  std::vector<double> unsorted(const std::vector<double>& values) const {
    std::vector<double> out(values.size());
    for (std::size_t k = 0; k < order_.size(); ++k)
      for (int a = 0; a < 3; ++a) out[3 * order_[k] + a] = values[3 * k + a];
    return out;
  }

 private:
  std::vector<std::size_t> order_;
  MPI_Datatype view_ = MPI_DATATYPE_NULL;
};

std::string mpi_error_text(int code) {
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  return std::string(text, static_cast<std::size_t>(length));
}

// Why an MPI-IO call failed ("" if it moved all `expected` values of
// `type`): on a full disk ompio reports a short write, not an error.
std::string transfer_error(int code, const MPI_Status& status, MPI_Datatype type,
                           std::size_t expected) {
  if (code != MPI_SUCCESS) return mpi_error_text(code);
  int count = 0;
  MPI_Get_count(&status, type, &count);
  if (count != static_cast<int>(expected))
    return "a short transfer (" + std::to_string(count) + " of " + std::to_string(expected) +
           " values)";
  return {};
}

std::string call_error(int code) {
  return code == MPI_SUCCESS ? std::string() : mpi_error_text(code);
}

// Run one MPI-IO step on every rank (it returns why it failed, "" if it did
// not); if it fails anywhere, every rank throws `Error(what: why)` of the
// lowest failing rank.
template <class Error>
void io_step(MPI_Comm comm, const std::string& what, const std::function<std::string()>& step) {
  run_collectively(comm, [&] {
    const std::string why = step();
    if (why.empty()) return;
    const std::string message = what + ": " + why + WriteWatch::space_left();
    WriteWatch::note_error(message);
    throw Error(message);
  });
}

// This rank's share of the field checksum: component a of node `id` is value
// first_index + 3 * id + a of the file's fields.
std::uint64_t field_terms(const std::vector<std::int64_t>& ids, const std::vector<double>& owned,
                          std::uint64_t first_index) {
  std::uint64_t sum = 0;
  for (std::size_t n = 0; n < ids.size(); ++n)
    for (int a = 0; a < 3; ++a)
      sum += value_term(first_index + 3 * static_cast<std::uint64_t>(ids[n]) + a, owned[3 * n + a]);
  return sum;
}

}  // namespace

void write_checkpoint_file(MPI_Comm comm, const std::string& path, const Checkpoint& c,
                           const std::vector<std::int64_t>& ids) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::int64_t mine = static_cast<std::int64_t>(ids.size()), nodes = 0;
  MPI_Allreduce(&mine, &nodes, 1, MPI_INT64_T, MPI_SUM, comm);
  const auto values = 3 * static_cast<std::uint64_t>(nodes);
  // A rank without nodes has no check field values: agree on whether there is one.
  int checked = !c.check_displacement.empty(), any_checked = 0;
  MPI_Allreduce(&checked, &any_checked, 1, MPI_INT, MPI_MAX, comm);
  const std::vector<const std::vector<double>*> fields = file_fields(c, any_checked);
  const std::vector<char> head =
      head_bytes(c, values, any_checked ? values : 0, c.learnt_space.size());
  std::uint64_t sum = 0, total = 0;
  for (std::size_t k = 0; k < fields.size(); ++k) sum += field_terms(ids, *fields[k], k * values);
  MPI_Allreduce(&sum, &total, 1, MPI_UINT64_T, MPI_SUM, comm);

  const std::string tmp = path + ".tmp";
  const std::string failed = "cannot write file '" + path + "'";
  // The other ranks wait for the slowest rank's write: a stop request
  // reaches them there too (write_watch.hpp).
  const WriteWatch watch(comm, path, tmp);
  if (rank == 0) std::remove(tmp.c_str());  // a shorter file must not keep an old tail
  MPI_File file = MPI_FILE_NULL;
  io_step<IoError>(comm, failed + ": cannot create '" + tmp + "'", [&] {
    return call_error(
        MPI_File_open(comm, tmp.c_str(), MPI_MODE_CREATE | MPI_MODE_WRONLY, MPI_INFO_NULL, &file));
  });
  try {
    io_step<IoError>(comm, failed + ": writing '" + tmp + "' failed", [&] {
      if (rank != 0) return std::string();
      const std::uint64_t end = head.size() + 8 * values * fields.size();
      MPI_Status status;
      std::string why =
          transfer_error(MPI_File_write_at(file, 0, head.data(), static_cast<int>(head.size()),
                                           MPI_BYTE, &status),
                         status, MPI_BYTE, head.size());
      if (why.empty())
        why = transfer_error(MPI_File_write_at(file, static_cast<MPI_Offset>(end), &total, 8,
                                               MPI_BYTE, &status),
                             status, MPI_BYTE, 8);
      return why;
    });
    const NodeRows rows(ids);
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const std::vector<double> sorted = rows.sorted(*fields[k]);
      io_step<IoError>(comm, failed + ": writing '" + tmp + "' failed", [&] {
        const auto start = static_cast<MPI_Offset>(head.size() + 8 * k * values);
        const int code =
            MPI_File_set_view(file, start, MPI_DOUBLE, rows.view(), "native", MPI_INFO_NULL);
        if (code != MPI_SUCCESS) return mpi_error_text(code);
        MPI_Status status;
        return transfer_error(MPI_File_write_all(file, sorted.data(),
                                                 static_cast<int>(sorted.size()), MPI_DOUBLE,
                                                 &status),
                              status, MPI_DOUBLE, sorted.size());
      });
    }
    io_step<IoError>(comm, failed + ": syncing '" + tmp + "' failed",
                     [&] { return call_error(MPI_File_sync(file)); });
    io_step<IoError>(comm, failed + ": closing '" + tmp + "' failed",
                     [&] { return call_error(MPI_File_close(&file)); });
  } catch (...) {
    if (file != MPI_FILE_NULL) MPI_File_close(&file);
    if (rank == 0) std::remove(tmp.c_str());
    throw;
  }
  run_on_root(comm, [&] { move_into_place(tmp, path); });
}

namespace {

// Every field of the file, each rank the values of its nodes `ids`.
void read_fields(MPI_Comm comm, const std::string& path, const Head& head,
                 const std::vector<std::int64_t>& ids, Checkpoint& c) {
  const std::uint64_t values = head.displacement_values;
  const NodeRows rows(ids);
  MPI_File file = MPI_FILE_NULL;
  const std::string failed = "cannot read the checkpoint '" + path + "'";
  io_step<InputError>(comm, failed, [&] {
    return call_error(MPI_File_open(comm, path.c_str(), MPI_MODE_RDONLY, MPI_INFO_NULL, &file));
  });
  const auto read_field = [&](std::uint64_t field) {
    std::vector<double> sorted(3 * ids.size());
    io_step<InputError>(comm, failed, [&] {
      const auto start = static_cast<MPI_Offset>(head.bytes + 8 * field * values);
      const int code =
          MPI_File_set_view(file, start, MPI_DOUBLE, rows.view(), "native", MPI_INFO_NULL);
      if (code != MPI_SUCCESS) return mpi_error_text(code);
      MPI_Status status;
      return transfer_error(MPI_File_read_all(file, sorted.data(), static_cast<int>(sorted.size()),
                                              MPI_DOUBLE, &status),
                            status, MPI_DOUBLE, sorted.size());
    });
    return rows.unsorted(sorted);
  };
  try {
    std::uint64_t field = 0;
    c.displacement = read_field(field++);
    if (head.check_values != 0) c.check_displacement = read_field(field++);
    for (std::uint64_t j = 0; j < head.learnt_columns; ++j)
      c.learnt_space.push_back(read_field(field++));
  } catch (...) {
    MPI_File_close(&file);
    throw;
  }
  MPI_File_close(&file);
}

// The field checksum (over every node once the ranks' terms are summed),
// then every value finite: InputError on every rank otherwise.
void check_fields(MPI_Comm comm, const Head& head, const std::vector<std::int64_t>& ids,
                  const Checkpoint& c, const std::string& bad) {
  const bool checked = head.check_values != 0;
  const std::vector<const std::vector<double>*> fields = file_fields(c, checked);
  const std::uint64_t values = head.displacement_values;
  std::uint64_t sum = 0, total = 0;
  for (std::size_t k = 0; k < fields.size(); ++k) sum += field_terms(ids, *fields[k], k * values);
  MPI_Allreduce(&sum, &total, 1, MPI_UINT64_T, MPI_SUM, comm);
  if (total != head.field_checksum)
    throw InputError(bad + "checksum mismatch: corrupt); remove it or pass "
                           "-checkpoint_resume false");
  // The lowest non-finite value of each field, by its index in the field.
  std::vector<std::uint64_t> lowest(fields.size(), UINT64_MAX), global(fields.size());
  for (std::size_t k = 0; k < fields.size(); ++k)
    for (std::size_t n = 0; n < ids.size(); ++n)
      for (int a = 0; a < 3; ++a)
        if (!std::isfinite((*fields[k])[3 * n + a]))
          lowest[k] = std::min(lowest[k], 3 * static_cast<std::uint64_t>(ids[n]) + a);
  MPI_Allreduce(lowest.data(), global.data(), static_cast<int>(fields.size()), MPI_UINT64_T,
                MPI_MIN, comm);
  for (std::size_t k = 0; k < fields.size(); ++k)
    if (global[k] != UINT64_MAX)
      throw InputError(bad + value_name(k, checked, global[k]) +
                       " is not finite); remove it or pass -checkpoint_resume false");
}

}  // namespace

Checkpoint read_checkpoint_file(MPI_Comm comm, const std::string& path,
                                const std::vector<std::int64_t>& ids,
                                const std::function<void(const Checkpoint&)>& accept) {
  const std::string bad = "the checkpoint '" + path + "' is not a valid lem checkpoint (";
  std::vector<char> bytes;
  Head head;
  run_on_root(comm, [&] {
    bytes = read_head(path, bad, head);
    const Checkpoint c = parse_head(bytes, bad);
    check_head_values(c, head, bad);
    if (accept) accept(c);
  });
  broadcast(comm, bytes);
  broadcast_value(comm, head);
  Checkpoint c = parse_head(bytes, bad);
  run_collectively(comm, [&] {
    for (const std::int64_t id : ids)
      if (id < 0 || 3 * static_cast<std::uint64_t>(id) >= head.displacement_values)
        throw InputError(bad + "it has no node " + std::to_string(id) + ")");
  });
  read_fields(comm, path, head, ids, c);
  check_fields(comm, head, ids, c, bad);
  return c;
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

Checkpoint CheckpointStore::load(const std::string& learning_option) const {
  const DistributedLattice& l = lattice_;
  int other_ranks = 0;  // rank count of a checkpoint written by another one
  int ranks = 1;
  MPI_Comm_size(l.comm, &ranks);
  // Everything in the checkpoint is by lattice id, so another partition can
  // take it over: the rank count may differ, unless an option learns from
  // the solves (what it learns depends on the rank count's rounding).
  std::string solver_changes;
  Checkpoint c = read_checkpoint_file(l.comm, path_, owned_ids(), [&](const Checkpoint& theirs) {
    const FingerprintDifference d =
        compare_fingerprints(theirs.fingerprint, fingerprint_, "checkpoint", true);
    if (!d.differs.empty())
      throw InputError("the checkpoint '" + path_ +
                       "' belongs to a different run "
                       "(sample or options):" +
                       d.differs +
                       "\nresume with the same command, or "
                       "pass -checkpoint_resume false to start over");
    if (d.other_ranks > 0 && !learning_option.empty())
      throw InputError("cannot resume the checkpoint '" + path_ + "', written on " +
                       std::to_string(d.other_ranks) + " ranks, on " + std::to_string(ranks) +
                       " under " + learning_option + ": the deflation space it learnt from the " +
                       std::to_string(d.other_ranks) +
                       "-rank solves is in the checkpoint, but only that rank count goes on "
                       "learning as the uninterrupted run; resume it on " +
                       std::to_string(d.other_ranks) +
                       " ranks, or pass -checkpoint_resume false to start over");
    other_ranks = d.other_ranks;
    solver_changes = d.solver_changes;
  });
  MPI_Bcast(&other_ranks, 1, MPI_INT, 0, l.comm);
  solver_changes = broadcast_string(l.comm, solver_changes);
  if (!solver_changes.empty())
    say("resuming a checkpoint written with other solver options:%s\nthe rest of the run is "
        "solved with this run's, so it agrees with an uninterrupted one to the solver "
        "tolerance, not bit for bit\n",
        solver_changes.c_str());
  if (other_ranks > 0) {
    say("resuming a checkpoint written on %d ranks on %d: the preconditioner differs, so the "
        "rest of the run agrees with an uninterrupted one to the solver tolerance, not bit for "
        "bit\n",
        other_ranks, ranks);
  }
  return c;
}

void CheckpointStore::hold(const FractureState& state, std::string relaxation_state,
                           const DamageMark& damage, std::vector<double> owned_u,
                           std::vector<double> owned_check, std::vector<VecHandle> learnt_space) {
  held_ = {state,
           std::move(relaxation_state),
           damage,
           std::move(owned_u),
           std::move(owned_check),
           std::move(learnt_space)};
}

void CheckpointStore::save(const DamageLedger& ledger) const {
  Checkpoint c;
  c.state = held_.state;
  c.fingerprint = fingerprint_;
  c.relaxation_state = held_.relaxation_state;
  c.damage = ledger.prefix(held_.damage);
  c.displacement = held_.u;
  c.check_displacement = held_.check;
  for (const VecHandle& column : held_.learnt_space) {
    PetscInt n = 0;
    const PetscScalar* w = nullptr;
    LEM_PETSC(VecGetLocalSize(column, &n));
    LEM_PETSC(VecGetArrayRead(column, &w));
    c.learnt_space.emplace_back(w, w + n);
    LEM_PETSC(VecRestoreArrayRead(column, &w));
  }
  write_checkpoint_file(lattice_.comm, path_, c, owned_ids());
}

std::vector<std::int64_t> CheckpointStore::owned_ids() const {
  return {lattice_.node_id.begin(), lattice_.node_id.begin() + lattice_.owned};
}

std::string checkpoint_path(const std::string& output_dir) {
  return output_dir + "/checkpoint.bin";
}

void remove_checkpoint(const std::string& output_dir) {
  if (std::remove(checkpoint_path(output_dir).c_str()) == 0) sync_directory(output_dir);
}

}  // namespace lem
