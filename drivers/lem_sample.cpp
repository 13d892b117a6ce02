// Build a cemented granular sample and write it to a sample file that
// lem_tension (-sample_file) and the other mechanical drivers load.
//
//   lem_sample -sample_particles 516 -lattice_bonds 1300000 -matrix_fraction 0.13
//   lem_sample -sample_particles 64 -output_dir meshes -output_stem tiny
//
// With -lattice_generator serial (the default) the sample is built on rank 0;
// with cells every rank builds and writes its share (lem/sample/parallel_sample.hpp).
#include "lem/sample/cemented_sample.hpp"
#include "lem/base/driver.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/io/hdf5_writer.hpp"
#include "lem/base/options.hpp"
#include "lem/sample/parallel_sample.hpp"
#include "lem/sample/sample_writer.hpp"
#include "lem/setup/sample_options.hpp"
#include "lem/report/sample_summary.hpp"
#include "lem/base/summary.hpp"

#include <string>

static const char help[] =
    "Cemented granular sample (Affes et al., EPJE 35, 2012, sect. 2.2-2.3):\n"
    "  1. a jammed periodic packing of polydisperse spheres (-pack_*),\n"
    "  2. a cube holding -sample_particles sphere centres (spheres reaching in are kept),\n"
    "  3. a random Delaunay lattice in the cube (-lattice_*) and its clipped Voronoi volumes\n"
    "     (-lattice_generator cells: every rank builds and writes its share of steps 3-5),\n"
    "  4. matrix bridges between near particles (-matrix_*), calibrated so that the matrix\n"
    "     volume measured on the lattice is -matrix_fraction,\n"
    "  5. node phases (particle/matrix/void) and bond phases (p, m, v, pp, pm).\n"
    "Writes <output_dir>/<output_stem>.h5 and .xmf (open in ParaView) and a summary.\n";


int main(int argc, char** argv) {
  return lem::run_driver(argc, argv, help, [](MPI_Comm comm) {
    const lem::CementedSampleSpec spec = lem::read_cemented_sample_spec(comm);
    std::string dir, stem;
    {
      lem::OptionGroup g(comm, "Output");
      dir = g.string("-output_dir", "Directory of the results", "results/sample");
      stem = g.string("-output_stem",
                      "Name of the sample files in -output_dir (<stem>.h5, "
                      "<stem>.xmf; summaries summary.json/.csv for the default, else "
                      "<stem>_summary.json/.csv)",
                      "sample");
    }
    lem::check_option_names(comm);
    if (stem.empty() || stem.find('/') != std::string::npos)
      throw lem::InputError("option -output_stem = '" + stem +
                            "' must be a plain file name "
                            "(no '/'; the directory is -output_dir)");
    const std::string summary_stem = stem == "sample" ? "summary" : stem + "_summary";
    lem::validate(spec.packing);
    const auto provenance = lem::collect_provenance(comm, "lem_sample");

    lem::say("packing %lld spheres (seed %llu), cube of %lld centres, lattice seed %llu (%s "
             "generator), matrix fraction %g\n",
             (long long)spec.packing.count, (unsigned long long)spec.packing.seed,
             (long long)spec.sample_particles, (unsigned long long)spec.lattice.seed,
             spec.generator == lem::LatticeGenerator::cells ? "cells" : "serial",
             spec.bridges.matrix_fraction);
    const std::string path = dir + "/" + stem;
    const auto prepare = [&] {  // only once the sample is made: a failure keeps older results
      lem::prepare_output_dir(comm, dir,
                              {stem + ".h5", stem + ".xmf", stem + "_nodes.xmf",
                               stem + "_particles.xmf", summary_stem + ".json",
                               summary_stem + ".csv"});
    };
    lem::CementedSampleStats stats;
    if (spec.generator == lem::LatticeGenerator::cells) {
      lem::SampleBlock block = lem::build_cemented_sample_block(comm, spec);
      stats = block.description.sample.stats;
      lem::say_sample_report(stats, spec);
      prepare();
      block.description.provenance = provenance;
      lem::write_sample_block(comm, path, block);
    } else {
      lem::CementedSample sample;
      lem::run_on_root(comm, [&] {
        sample = lem::build_cemented_sample(spec);
        stats = sample.stats;
        lem::say_sample_report(stats, spec);
      });
      prepare();
      lem::run_on_root(comm, [&] { lem::write_sample(path, sample, spec, provenance); });
    }
    const lem::PeakMemory memory = lem::peak_memory(comm);
    lem::say("peak memory per rank %.0f MB (largest), %.0f MB (mean)\n", memory.max_mb,
             memory.mean_mb);
    lem::run_on_root(comm, [&] {
      lem::Summary summary = sample_summary(stats, spec, path + ".h5");
      summary.add("peak_memory_mb", memory.max_mb, "MB");
      summary.add("peak_memory_mean_mb", memory.mean_mb, "MB");
      summary.add_provenance(provenance);
      summary.write(dir + "/" + summary_stem);
    });
    lem::say("results in %s/: %s.h5, %s.xmf (ParaView), %s.json/.csv\n", dir.c_str(), stem.c_str(),
             stem.c_str(), summary_stem.c_str());
  });
}
