// lem_pack: a dense packing of polydisperse spheres and the cubic sample cut
// out of it.  The packing is serial: rank 0 builds it, other ranks only take
// part in the option handling and the error report.
#include "lem/base/driver.hpp"
#include "lem/base/error.hpp"
#include "lem/base/files.hpp"
#include "lem/base/log.hpp"
#include "lem/base/options.hpp"
#include "lem/packing/packing.hpp"
#include "lem/packing/packing_file.hpp"
#include "lem/run/programs.hpp"
#include "lem/run/result_folder.hpp"
#include "lem/setup/sample_options.hpp"

#include <string>

namespace lem {

namespace {

struct PackOptions {
  PackingSpec spec;
  std::int64_t sample = 0;  // -pack_sample_particles
  CubeCut cut = CubeCut::centres_inside;
  bool write_box = false;
  ResultFolder::Request request;
};

PackOptions read_pack_options(MPI_Comm comm) {
  PackOptions o;
  o.spec = read_packing_spec(comm);
  {
    OptionGroup g(comm, "Cubic sample and output");
    o.sample = g.integer("-pack_sample_particles",
                         "Sphere centres in the cubic sample (at most -pack_particles)", 516, 1,
                         50'000'000);
    if (o.spec.count == 0) o.spec.count = auto_packing_count(o.sample);
    o.cut = g.choice<CubeCut>("-pack_cut",
                              "Spheres of the cube: centres inside it, or also those reaching "
                              "in from outside",
                              {{"centres", CubeCut::centres_inside},
                               {"reaching", CubeCut::reaching_in}},
                              CubeCut::centres_inside);
    o.write_box = g.flag("-pack_write_box",
                         "Also write the whole periodic packing "
                         "(packing_box.csv)",
                         false);
    o.request = ResultFolder::read_request(g, "results/packing");
  }
  check_option_names(comm);
  validate(o.spec);
  if (o.sample > o.spec.count)
    throw InputError(
        "option -pack_sample_particles = " + std::to_string(o.sample) +
        " is out of range: allowed 1 to -pack_particles = " + std::to_string(o.spec.count));
  return o;
}

void say_packing(const PackingSpec& spec, const Packing& packing) {
  const auto& st = packing.stats;
  say("box: side %.6g, %lld spheres, rho_p %.6f, %d attempts (%d stopped by the step "
      "limit, marked *), %lld FIRE steps, %lld list builds, %.2f s\n",
      packing.box_side, (long long)st.particles, st.volume_fraction, st.attempts,
      st.unsettled_attempts, (long long)st.relaxation_steps, (long long)st.neighbour_builds,
      st.seconds);
  say("contacts (gap < %g d_mean): z = %.3f; rattlers %.1f%%, z without rattlers %.3f "
      "(overlapping contacts only: %.3f)\n",
      spec.contact_gap, st.mean_coordination, 100 * st.rattler_fraction, st.backbone_coordination,
      st.loaded_coordination);
  say("overlap / d: mean %.3e, max %.3e (%lld overlapping pairs); pressure %.3e k/d_min\n",
      st.mean_overlap, st.max_overlap, (long long)st.overlapping_pairs, st.pressure);
}

// Rank 0: the packing, its cube and their files in `dir`.
void write_packing(const PackOptions& o, const Provenance& provenance, const std::string& dir) {
  const PackingSpec& spec = o.spec;
  say("packing %lld spheres, d in [%g, %g], seed %llu\n", (long long)spec.count, spec.d_min,
      spec.d_max, (unsigned long long)spec.seed);
  const auto packing = make_packing(spec, [](const JammingAttempt& a) {
    say("attempt %3d  rho_p %.6f  %-8s  step %.1e  overlap mean %.2e max %.2e  "
        "relaxation %7lld steps  %8.2f s\n",
        a.attempt, a.volume_fraction, a.jammed ? (a.settled ? "jammed" : "jammed*") : "free",
        a.step, a.mean_overlap, a.max_overlap, (long long)a.relaxation_steps, a.seconds);
  });
  say_packing(spec, packing);
  const auto cube = cut_cube(packing, o.sample, o.cut);
  say("cube: side %.6g, %lld centres inside, %zu spheres, rho_p %.6f (counting every "
      "sphere reaching in %.6f)\n",
      cube.side, (long long)cube.centres_inside, cube.spheres.size(), cube.volume_fraction,
      cube.region_volume_fraction);
  write_text_file_atomically(dir + "/packing.csv", spheres_csv(cube));
  write_text_file_atomically(dir + "/packing.json", spheres_json(cube, packing, spec, provenance,
                                                                 "cubic sample", "packing.csv"));
  if (!o.write_box) return;
  CubeSample whole;
  whole.side = packing.box_side;
  whole.spheres = packing.spheres;
  whole.centres_inside = static_cast<std::int64_t>(whole.spheres.size());
  whole.volume_fraction = whole.region_volume_fraction = packing.stats.volume_fraction;
  write_text_file_atomically(dir + "/packing_box.csv", spheres_csv(whole));
  write_text_file_atomically(dir + "/packing_box.json",
                             spheres_json(whole, packing, spec, provenance, "periodic box",
                                          "packing_box.csv"));
}

void run_pack(MPI_Comm comm, PackOptions o) {
  const auto provenance = collect_provenance(comm, "lem_pack");
  o.request.fingerprint = options_fingerprint(comm);
  const ResultFolder folder(comm, packing_layout(), o.request);
  if (!folder.begin()) return;
  run_on_root(comm, [&] { write_packing(o, provenance, folder.work_dir()); });
  folder.commit(Summary{}, {});
  folder.install();
}

}  // namespace

int pack_program(int argc, char** argv, const char* help) {
  return run_driver(argc, argv, help,
                    [](MPI_Comm comm) { run_pack(comm, read_pack_options(comm)); });
}

}  // namespace lem
