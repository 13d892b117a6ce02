// Dense packing of polydisperse spheres and the cubic sample cut out of it.
//
//   lem_pack -pack_particles 4000 -pack_sample_particles 516 -output_dir results/packing
//
// -pack_particles defaults to "auto" (twice the cube's count, rounded to a
// hundred: 1000 for the default 516).
//
// The packing is serial: rank 0 builds it, other ranks only take part in the
// option handling and the error report.
#include "lem/base/driver.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/io/hdf5_writer.hpp"
#include "lem/base/options.hpp"
#include "lem/packing/packing.hpp"
#include "lem/packing/packing_file.hpp"
#include "lem/run/result_folder.hpp"
#include "lem/setup/sample_options.hpp"
#include "lem/base/summary.hpp"

#include <cstdio>
#include <string>

static const char help[] =
    "Jammed packing of polydisperse frictionless spheres (isotropic compaction in a periodic\n"
    "box) and a cubic sample of it, as in Affes et al., EPJE 35 (2012), sect. 2.2-2.3.\n";


int main(int argc, char** argv) {
  return lem::run_driver(argc, argv, help, [](MPI_Comm comm) {
    lem::PackingSpec spec = lem::read_packing_spec(comm);
    std::int64_t sample = 0;
    lem::ResultFolder::Request request;
    bool write_box = false;
    lem::CubeCut cut = lem::CubeCut::centres_inside;
    {
      lem::OptionGroup g(comm, "Cubic sample and output");
      sample = g.integer("-pack_sample_particles",
                         "Sphere centres in the cubic sample (at most -pack_particles)", 516, 1,
                         50'000'000);
      if (spec.count == 0) spec.count = lem::auto_packing_count(sample);
      cut = g.choice<lem::CubeCut>(
          "-pack_cut",
          "Spheres of the cube: centres inside it, or also those reaching in from "
          "outside",
          {{"centres", lem::CubeCut::centres_inside}, {"reaching", lem::CubeCut::reaching_in}},
          lem::CubeCut::centres_inside);
      write_box = g.flag("-pack_write_box",
                         "Also write the whole periodic packing "
                         "(packing_box.csv)",
                         false);
      request = lem::ResultFolder::read_request(g, "results/packing");
    }
    lem::check_option_names(comm);
    lem::validate(spec);
    if (sample > spec.count)
      throw lem::InputError(
          "option -pack_sample_particles = " + std::to_string(sample) +
          " is out of range: allowed 1 to -pack_particles = " + std::to_string(spec.count));
    const auto provenance = lem::collect_provenance(comm, "lem_pack");
    request.fingerprint = lem::options_fingerprint(comm);
    const lem::ResultFolder folder(comm, lem::packing_layout(), request);
    if (!folder.begin()) return;
    const std::string& dir = folder.work_dir();

    lem::run_on_root(comm, [&] {
      lem::say("packing %lld spheres, d in [%g, %g], seed %llu\n", (long long)spec.count,
               spec.d_min, spec.d_max, (unsigned long long)spec.seed);
      const auto packing = lem::make_packing(spec, [](const lem::JammingAttempt& a) {
        lem::say("attempt %3d  rho_p %.6f  %-8s  step %.1e  overlap mean %.2e max %.2e  "
                 "relaxation %7lld steps  %8.2f s\n",
                 a.attempt, a.volume_fraction,
                 a.jammed ? (a.settled ? "jammed" : "jammed*") : "free", a.step, a.mean_overlap,
                 a.max_overlap, (long long)a.relaxation_steps, a.seconds);
      });
      const auto& st = packing.stats;
      lem::say("box: side %.6g, %lld spheres, rho_p %.6f, %d attempts (%d stopped by the step "
               "limit, marked *), %lld FIRE steps, %lld list builds, %.2f s\n",
               packing.box_side, (long long)st.particles, st.volume_fraction, st.attempts,
               st.unsettled_attempts, (long long)st.relaxation_steps,
               (long long)st.neighbour_builds, st.seconds);
      lem::say("contacts (gap < %g d_mean): z = %.3f; rattlers %.1f%%, z without rattlers %.3f "
               "(overlapping contacts only: %.3f)\n",
               spec.contact_gap, st.mean_coordination, 100 * st.rattler_fraction,
               st.backbone_coordination, st.loaded_coordination);
      lem::say("overlap / d: mean %.3e, max %.3e (%lld overlapping pairs); pressure %.3e k/d_min\n",
               st.mean_overlap, st.max_overlap, (long long)st.overlapping_pairs, st.pressure);

      const auto cube = lem::cut_cube(packing, sample, cut);
      lem::say("cube: side %.6g, %lld centres inside, %zu spheres, rho_p %.6f (counting every "
               "sphere reaching in %.6f)\n",
               cube.side, (long long)cube.centres_inside, cube.spheres.size(), cube.volume_fraction,
               cube.region_volume_fraction);
      lem::write_text_file_atomically(dir + "/packing.csv", lem::spheres_csv(cube));
      lem::write_text_file_atomically(dir + "/packing.json",
                                      lem::spheres_json(cube, packing, spec, provenance,
                                                        "cubic sample", "packing.csv"));
      if (write_box) {
        lem::CubeSample whole;
        whole.side = packing.box_side;
        whole.spheres = packing.spheres;
        whole.centres_inside = static_cast<std::int64_t>(whole.spheres.size());
        whole.volume_fraction = whole.region_volume_fraction = st.volume_fraction;
        lem::write_text_file_atomically(dir + "/packing_box.csv", lem::spheres_csv(whole));
        lem::write_text_file_atomically(dir + "/packing_box.json",
                                        lem::spheres_json(whole, packing, spec, provenance,
                                                          "periodic box", "packing_box.csv"));
      }
    });
    folder.commit(lem::Summary{}, {});
    folder.install();
  });
}
