#include "lem/run/result_folder.hpp"

#include "lem/base/collective.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/base/fingerprint.hpp"
#include "lem/base/log.hpp"
#include "lem/base/options.hpp"
#include "lem/protocol/checkpoint.hpp"
#include "lem/base/stop.hpp"

#include <algorithm>
#include <filesystem>

namespace lem {

namespace fs = std::filesystem;

namespace {

bool listed(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// A file of the family `stem`, as the programs name them: <stem>.h5,
// <stem>.xmf, <stem>_nodes.xmf, and the same with a step after the stem
// (snapshot_0000120.h5); snapshots.xmf is the family "snapshots".  Nothing
// else: a user's fields_mine.h5 or snapshot_notes.h5 is not the program's.
bool of_family(const std::string& name, const std::string& stem) {
  if (name.rfind(stem, 0) != 0) return false;
  std::size_t at = stem.size();
  const auto digit = [&](std::size_t k) {
    return k < name.size() && name[k] >= '0' && name[k] <= '9';
  };
  if (at < name.size() && name[at] == '_' && digit(at + 1)) {
    ++at;
    while (digit(at)) ++at;
  }
  const std::string rest = name.substr(at);
  return rest == ".h5" || rest == ".xmf" || rest == "_nodes.xmf";
}

bool of_families(const std::string& name, const std::vector<std::string>& stems) {
  return std::any_of(stems.begin(), stems.end(),
                     [&](const std::string& stem) { return of_family(name, stem); });
}

// Rank 0: the files of `dir` that belong to the families `stems`.
std::vector<std::string> family_files(const std::string& dir,
                                      const std::vector<std::string>& stems) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (of_families(name, stems)) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

// Whether the staging folder of `dir` (<dir>.overwrite) is one of ours
// (rank 0 decides).
bool staging_is_ours(MPI_Comm comm, const std::string& dir) {
  bool ours = false;
  run_on_root(comm, [&] { ours = staging_state(dir) == StagingState::ours; });
  broadcast_value(comm, ours);
  return ours;
}

std::string joined(const std::vector<std::string>& words) {
  std::string text;
  for (const auto& w : words) text += (text.empty() ? "" : ", ") + w;
  return text;
}

}  // namespace

bool ResultLayout::owns(const std::string& name) const {
  // A file being written under a temporary name: one of the result's names
  // (or the manifest's) with .part or .tmp after it; a user's notes.tmp is not.
  const std::string ext = fs::path(name).extension().string();
  if (ext == ".part" || ext == ".tmp") {
    const std::string final_name = fs::path(name).stem().string();
    return final_name == "manifest.txt" || (!final_name.empty() && owns(final_name));
  }
  return listed(required, name) || listed(optional, name) || listed(extras, name) ||
         of_families(name, final_families) || of_families(name, running_families);
}

const ResultLayout& fracture_layout() {
  static const ResultLayout layout = {"lem_fracture",
                                      {"curve.csv", "broken.csv", "summary.csv", "summary.json"},
                                      {"curve.csv", "curve.json", "broken.csv"},
                                      {"fields"},
                                      {"elastic", "snapshot", "snapshots"},
                                      {"calibration", "checkpoint.bin", "fracture.png",
                                       "fracture.pdf", "stress.png", "stress.pdf", "stress.json",
                                       "crack.png", "crack.pdf"}};
  return layout;
}

const ResultLayout& tension_layout() {
  static const ResultLayout layout = {
      "lem_tension", {"summary.csv", "summary.json"}, {}, {"fields"}, {}, {"tension.png"}};
  return layout;
}

const ResultLayout& stiffness_layout() {
  static const ResultLayout layout = {"lem_stiffness",
                                      {"stiffness.csv", "fits.csv", "summary.csv", "summary.json"},
                                      {},
                                      {},
                                      {},
                                      {"stiffness.png", "stiffness.pdf", "interface.png",
                                       "interface.pdf"}};
  return layout;
}

const ResultLayout& convergence_layout() {
  static const ResultLayout layout = {"lem_convergence",
                                      {"convergence.csv", "fit.csv", "summary.csv", "summary.json"},
                                      {},
                                      {},
                                      {},
                                      {"convergence.png", "convergence.pdf"}};
  return layout;
}

const ResultLayout& packing_layout() {
  static const ResultLayout layout = {
      "lem_pack", {"packing.csv", "packing.json"}, {"packing_box.csv", "packing_box.json"}, {}, {},
      {}};
  return layout;
}

std::string options_fingerprint(MPI_Comm comm, const std::string& inputs) {
  std::string text;
  run_on_root(comm, [&] { text = option_lines(kAllOptionKinds) + inputs; });
  return text;
}

ResultFolder::Request ResultFolder::read_request(OptionGroup& g, const char* default_dir) {
  Request r;
  r.dir = g.string("-output_dir", "Directory of the results", default_dir);
  r.overwrite = g.flag("-output_overwrite",
                       "Compute the result again even if -output_dir "
                       "holds a finished one (its manifest.txt), in <output_dir>.overwrite/: "
                       "it replaces the old one only when complete; without it a finished "
                       "run of the same input and options is left as it is (exit 0)",
                       false);
  return r;
}

namespace {

// Rank 0: why the finished result `m` is not that of this run ("" if it is;
// the rank count may differ).
std::string other_run(const Manifest& m, const ResultLayout& layout,
                      const std::string& fingerprint) {
  if (m.program != layout.program) return "\n  written by " + m.program;
  return compare_fingerprints(m.fingerprint, fingerprint, "finished").differs;
}

// Rank 0: a finished result with warnings is an error under -fracture_strict
// (the warning options are not part of the fingerprint).
void refuse_if_strict(const std::string& dir, const Manifest& m, bool strict) {
  if (strict && !m.warnings.empty())
    throw NumericalError("output directory '" + dir +
                         "' holds a finished result with "
                         "warnings (" +
                         joined(m.warnings) +
                         "), an error under "
                         "-fracture_strict; pass -output_overwrite to compute it again");
}

// Rank 0 of a locked output directory: true if it holds the finished result
// of this very run (then there is nothing to do); InputError if it holds
// another one and -output_overwrite was not given.
bool already_finished(const ResultLayout& layout, const ResultFolder::Request& r) {
  if (r.overwrite) return false;  // a damaged manifest too
  const auto manifest = read_manifest(r.dir);
  if (!manifest) return false;
  const std::string differs = other_run(*manifest, layout, r.fingerprint);
  if (!differs.empty())
    throw InputError("output directory '" + r.dir +
                     "' holds the finished result of "
                     "another run:" +
                     differs +
                     "\npass -output_overwrite to replace it, "
                     "or choose another -output_dir");
  const std::string changed = manifest_mismatch(r.dir, *manifest);
  if (!changed.empty())
    throw InputError("output directory '" + r.dir +
                     "' holds a finished result changed "
                     "since it was written:" +
                     changed +
                     "\npass -output_overwrite to "
                     "compute it again");
  refuse_if_strict(r.dir, *manifest, r.strict);
  return true;
}

// Rank 0, -output_overwrite: what the staging folder of `dir` holds for this
// run.  True if it is this run's complete result, to be put in place (a run
// stopped while doing so); false if the run is to be computed there: resumed
// from its checkpoint, or started over once the folder is emptied.
bool staged_complete(const ResultLayout& layout, const ResultFolder::Request& r) {
  const std::string staging = staging_dir(r.dir);
  if (!r.resume) {
    if (clear_staging(r.dir))
      say("-output_overwrite: %s/ emptied (-checkpoint_resume false)\n", staging.c_str());
    return false;
  }
  if (const auto manifest = read_manifest(staging)) {
    const std::string differs =
        other_run(*manifest, layout, r.fingerprint) + manifest_mismatch(staging, *manifest);
    if (!differs.empty())
      throw InputError("'" + staging +
                       "' holds the finished result of another "
                       "-output_overwrite run of '" +
                       r.dir + "', not yet in place:" + differs +
                       "\nrun that command again to put it in place, or pass "
                       "-checkpoint_resume false to discard it");
    refuse_if_strict(staging, *manifest, r.strict);
    remove_checkpoint(staging);
    say("-output_overwrite: %s/ holds the complete result of this run, not yet in place "
        "(the run was stopped while it put it there): putting it in place\n",
        staging.c_str());
    return true;
  }
  if (fs::exists(checkpoint_path(staging)) ||
      fs::exists(checkpoint_path(staging + "/calibration"))) {
    say("-output_overwrite: resuming the run stopped in %s/\n", staging.c_str());
    return false;
  }
  if (clear_staging(r.dir))
    say("-output_overwrite: %s/ held a run stopped before its first checkpoint: "
        "starting over\n",
        staging.c_str());
  return false;
}

}  // namespace

ResultFolder::ResultFolder(MPI_Comm comm, const ResultLayout& layout, Request request)
    : comm_(comm), layout_(layout), request_(std::move(request)), work_(request_.dir) {
  const std::string& dir = request_.dir;
  const ResultNames own = [this](const std::string& name) { return layout_.owns(name); };
  lock_ = std::make_unique<OutputLock>(comm, dir);
  // A replacement of the result stopped halfway is finished first (the new
  // result put in place, or the replaced one removed).
  if (staging_is_ours(comm, dir))
    staging_lock_ = std::make_unique<OutputLock>(comm, staging_dir(dir));
  run_on_root(comm, [&] {
    const std::string done = finish_replacement(dir, own);
    if (!done.empty()) say("%s/: %s\n", dir.c_str(), done.c_str());
  });
  // Still there: an -output_overwrite run that did not end.
  const bool staged = staging_is_ours(comm, dir);
  if (staged && !request_.overwrite)
    say("note: %s/ holds an -output_overwrite run of %s/ that did not end, left as it "
        "is: run with -output_overwrite to finish it, or remove %s/\n",
        staging_dir(dir).c_str(), dir.c_str(), staging_dir(dir).c_str());
  bool finished = false;
  run_on_root(comm, [&] {
    finished = already_finished(layout_, request_);
    // A run killed between its commit and the checkpoint's removal.
    if (finished) remove_checkpoint(dir);
  });
  broadcast_value(comm, finished);
  finished_ = finished;
  if (finished_) {
    say("the result in %s/ is complete (manifest.txt): nothing to do; pass "
        "-output_overwrite to compute it again\n",
        dir.c_str());
    return;
  }
  // -output_overwrite on a finished result: the new one is computed in the
  // staging folder and takes the old one's place only when complete.
  bool staging = false;
  run_on_root(comm, [&] { staging = request_.overwrite && (staged || has_manifest(dir)); });
  broadcast_value(comm, staging);
  staging_ = staging;
  if (!staging_) {
    staging_lock_.reset();  // held only to finish or report what it holds
    return;
  }
  run_on_root(comm, [&] {
    check_replaceable(dir);
    if (staging_state(dir) == StagingState::foreign)
      throw InputError("-output_overwrite computes the new result of '" + dir + "' in '" +
                       staging_dir(dir) + "', which holds something else: move or remove it");
  });
  if (!staged) {  // made (again)
    staging_lock_.reset();
    staging_lock_ = std::make_unique<OutputLock>(comm, staging_dir(dir));
  }
  bool exchange = false, pending = false;
  run_on_root(comm, [&] {
    exchange = prepare_staging(dir);
    pending = staged_complete(layout_, request_);
  });
  broadcast_value(comm, exchange);
  broadcast_value(comm, pending);
  exchange_ = exchange;
  pending_ = pending;
  work_ = staging_dir(dir);
  if (!pending_)
    say("-output_overwrite: the new result is computed in %s/; the one in %s/ stays "
        "until it is complete\n",
        work_.c_str(), dir.c_str());
  if (!exchange_)
    say("-output_overwrite: this filesystem cannot swap two folders in one rename: "
        "the new result will take the old one's place by two, between which %s/ "
        "does not exist\n",
        dir.c_str());
}

ResultFolder::~ResultFolder() = default;

bool ResultFolder::resuming() const {
  bool found = false;
  run_on_root(comm_, [&] { found = request_.resume && fs::exists(checkpoint_path(work_)); });
  broadcast_value(comm_, found);
  return found;
}

bool ResultFolder::begin() const {
  if (finished_) return false;
  if (pending_) {
    install();
    return false;
  }
  const bool resumes = resuming();
  run_on_root(comm_, [&] {
    // A resumed run goes on from its logs, its first fields and snapshots.
    std::vector<std::string> stale;
    for (const auto& name : layout_.required)
      if (!resumes || !listed(layout_.optional, name)) stale.push_back(name);
    if (!resumes) stale.insert(stale.end(), layout_.optional.begin(), layout_.optional.end());
    for (const auto& name : layout_.extras)  // plots drawn from an earlier result
      if (fs::path(name).has_extension() && name != "checkpoint.bin") stale.push_back(name);
    std::vector<std::string> families = layout_.final_families;
    if (!resumes)
      families.insert(families.end(), layout_.running_families.begin(),
                      layout_.running_families.end());
    for (const auto& name : family_files(work_, families)) stale.push_back(name);
    withdraw_results(work_, stale);
  });
  return true;
}

void ResultFolder::commit(const Summary& summary, const std::vector<std::string>& warnings) const {
  run_on_root(comm_, [&] {
    if (listed(layout_.required, "summary.json")) summary.write(work_ + "/summary");
    std::vector<std::string> files = layout_.required;
    std::vector<std::string> present;
    for (const auto& name : layout_.optional)
      if (!listed(files, name) && fs::exists(work_ + "/" + name)) present.push_back(name);
    std::vector<std::string> families = layout_.final_families;
    families.insert(families.end(), layout_.running_families.begin(),
                    layout_.running_families.end());
    for (const auto& name : family_files(work_, families)) present.push_back(name);
    std::sort(present.begin(), present.end());
    files.insert(files.end(), present.begin(), present.end());
    fault_point("before_manifest");
    commit_results(work_, layout_.program, request_.fingerprint, files, warnings);
    fault_point("after_manifest");
    remove_checkpoint(work_);
  });
}

void ResultFolder::install() const {
  const std::string& dir = request_.dir;
  if (staging_) {
    const ResultNames own = [this](const std::string& name) { return layout_.owns(name); };
    run_on_root(comm_, [&] { install_result(dir, exchange_, own); });
  }
  say("results in %s/\n", dir.c_str());
  if (const int signal = stop_requested(comm_, "committed"))
    throw Interrupted("stopped by " + signal_name(signal) +
                      " while the results were written; "
                      "they are complete in " +
                      dir +
                      "/ (manifest.txt), so running the same "
                      "command again does nothing");
}

}  // namespace lem
