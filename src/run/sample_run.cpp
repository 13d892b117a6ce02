// lem_sample: a cemented granular sample built and written to a sample file
// that lem_tension (-sample_file) and the other mechanical programs load.
// With -lattice_generator serial (the default) the sample is built on rank
// 0; with cells every rank builds and writes its share
// (lem/sample/parallel_sample.hpp).  Each sample is one HDF5 file renamed
// into place: a folder may hold several, so there is no ResultFolder.
#include "lem/base/driver.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/base/log.hpp"
#include "lem/base/options.hpp"
#include "lem/report/sample_summary.hpp"
#include "lem/run/programs.hpp"
#include "lem/sample/cemented_sample.hpp"
#include "lem/sample/parallel_sample.hpp"
#include "lem/sample/sample_writer.hpp"
#include "lem/setup/sample_options.hpp"

#include <string>

namespace lem {

namespace {

struct SampleProgramOptions {
  CementedSampleSpec spec;
  std::string dir, stem;
  std::string summary_stem;  // summary for the default stem, else <stem>_summary
};

SampleProgramOptions read_sample_program_options(MPI_Comm comm) {
  SampleProgramOptions o;
  o.spec = read_cemented_sample_spec(comm);
  {
    OptionGroup g(comm, "Output");
    o.dir = g.string("-output_dir", "Directory of the results", "results/sample");
    o.stem = g.string("-output_stem",
                      "Name of the sample files in -output_dir (<stem>.h5, "
                      "<stem>.xmf; summaries summary.json/.csv for the default, else "
                      "<stem>_summary.json/.csv)",
                      "sample");
  }
  check_option_names(comm);
  if (o.stem.empty() || o.stem.find('/') != std::string::npos)
    throw InputError("option -output_stem = '" + o.stem +
                     "' must be a plain file name "
                     "(no '/'; the directory is -output_dir)");
  o.summary_stem = o.stem == "sample" ? "summary" : o.stem + "_summary";
  validate(o.spec.packing);
  return o;
}

// Build the sample and write it to <dir>/<stem>.h5; its statistics.
CementedSampleStats build_and_write(MPI_Comm comm, const SampleProgramOptions& o,
                                    const Provenance& provenance) {
  const CementedSampleSpec& spec = o.spec;
  const std::string path = o.dir + "/" + o.stem;
  const auto prepare = [&] {  // only once the sample is made: a failure keeps older results
    prepare_output_dir(comm, o.dir,
                       {o.stem + ".h5", o.stem + ".xmf", o.stem + "_nodes.xmf",
                        o.stem + "_particles.xmf", o.summary_stem + ".json",
                        o.summary_stem + ".csv"});
  };
  CementedSampleStats stats;
  if (spec.generator == LatticeGenerator::cells) {
    SampleBlock block = build_cemented_sample_block(comm, spec);
    stats = block.description.sample.stats;
    say_sample_report(stats, spec);
    prepare();
    block.description.provenance = provenance;
    write_sample_block(comm, path, block);
  } else {
    CementedSample sample;
    run_on_root(comm, [&] {
      sample = build_cemented_sample(spec);
      stats = sample.stats;
      say_sample_report(stats, spec);
    });
    prepare();
    run_on_root(comm, [&] { write_sample(path, sample, spec, provenance); });
  }
  return stats;
}

void run_sample(MPI_Comm comm, const SampleProgramOptions& o) {
  const CementedSampleSpec& spec = o.spec;
  const auto provenance = collect_provenance(comm, "lem_sample");
  say("packing %lld spheres (seed %llu), cube of %lld centres, lattice seed %llu (%s "
      "generator), matrix fraction %g\n",
      (long long)spec.packing.count, (unsigned long long)spec.packing.seed,
      (long long)spec.sample_particles, (unsigned long long)spec.lattice.seed,
      spec.generator == LatticeGenerator::cells ? "cells" : "serial", spec.bridges.matrix_fraction);
  const CementedSampleStats stats = build_and_write(comm, o, provenance);
  const PeakMemory memory = peak_memory(comm);
  say("peak memory per rank %.0f MB (largest), %.0f MB (mean)\n", memory.max_mb, memory.mean_mb);
  run_on_root(comm, [&] {
    Summary summary = sample_summary(stats, spec, o.dir + "/" + o.stem + ".h5", memory);
    summary.add_provenance(provenance);
    summary.write(o.dir + "/" + o.summary_stem);
  });
  say("results in %s/: %s.h5, %s.xmf (ParaView), %s.json/.csv\n", o.dir.c_str(), o.stem.c_str(),
      o.stem.c_str(), o.summary_stem.c_str());
}

}  // namespace

int sample_program(int argc, char** argv, const char* help) {
  return run_driver(argc, argv, help,
                    [](MPI_Comm comm) { run_sample(comm, read_sample_program_options(comm)); });
}

}  // namespace lem
