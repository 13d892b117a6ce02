#include "lem/setup/sample_options.hpp"

#include "lem/base/error.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace lem {
namespace {

// Paper sect. 2.3: 1.3e6 bonds for 516 sphere centres.
constexpr std::int64_t kBondsPerSampleParticle = 2520;

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

}  // namespace

bool read_random_lattice_options(OptionGroup& g, RandomLatticeSpec& spec) {
  spec.nodes = g.integer("-lattice_nodes",
                         "Number of nodes of the random lattice (0: use "
                         "-lattice_bonds or -lattice_Ln)",
                         0, 0, 200'000'000);
  spec.bonds = g.integer("-lattice_bonds",
                         "Approximate number of bonds M (0: use "
                         "-lattice_nodes or -lattice_Ln)",
                         0, 0, 2'000'000'000);
  spec.mesh_density =
      g.real("-lattice_Ln", "Mesh density L_n = M^(-1/3) (0: unused)", 0.0, 0.0, 0.5);
  spec.min_separation = g.real("-lattice_min_separation",
                               "Minimum node distance as a "
                               "fraction of the mean spacing",
                               0.5, 0.0, 0.8);
  spec.seed = static_cast<std::uint64_t>(
      g.integer("-lattice_seed", "Random seed of the node positions", 1, 0, PETSC_MAX_INT));
  // One size: the generator would take the first and drop the others silently.
  std::vector<std::string> sizes;
  if (spec.nodes != 0) sizes.push_back("-lattice_nodes " + std::to_string(spec.nodes));
  if (spec.bonds != 0) sizes.push_back("-lattice_bonds " + std::to_string(spec.bonds));
  if (spec.mesh_density != 0) sizes.push_back("-lattice_Ln " + std::to_string(spec.mesh_density));
  if (sizes.size() > 1) {
    std::string given;
    for (const auto& s : sizes) given += (given.empty() ? "" : ", ") + s;
    throw InputError("options " + given +
                     " each set the size of the random lattice: give "
                     "one of -lattice_nodes, -lattice_bonds, -lattice_Ln");
  }
  return !sizes.empty();
}

LatticeGenerator read_lattice_generator(OptionGroup& g) {
  return g.choice<LatticeGenerator>(
      "-lattice_generator",
      "How a random lattice is made: serial (on rank 0: the lattices of "
      "earlier versions) or cells (every rank its cells of a grid, the same lattice on any rank "
      "count: no rank holds all of it; lem_sample then builds the whole sample in parallel)",
      {{"serial", LatticeGenerator::serial}, {"cells", LatticeGenerator::cells}},
      LatticeGenerator::serial);
}

bool read_face_bond_option(OptionGroup& g) {
  return g.choice<bool>(
      "-lattice_face_bonds",
      "Bonds lying in a box face: whole = full stiffness and strength "
      "(a stiffer skin, the default and every published figure), halved = 1/2 per face they "
      "lie in, as the box-clipped Voronoi cells of their nodes (docs/model/theory.md)",
      {{"whole", false}, {"halved", true}}, false);
}

std::int64_t auto_packing_count(std::int64_t sample_particles) {
  const std::int64_t rounded = (2 * sample_particles + 50) / 100 * 100;
  return std::max<std::int64_t>(100, rounded);
}

PackingSpec read_packing_spec(MPI_Comm comm) {
  PackingSpec spec;
  OptionGroup g(comm, "Packing (periodic box of jammed spheres; lengths in units of d_min)");
  spec.count = g.integer("-pack_particles",
                         "Spheres in the periodic box (0: auto, twice the "
                         "sample's sphere count rounded to a hundred, at least 100)",
                         0, 0, 50'000'000);
  if (spec.count != 0 && spec.count < 20)
    throw InputError("option -pack_particles = " + std::to_string(spec.count) +
                     " is out of range: allowed 0 (auto) or 20 to 50000000");
  spec.d_min = g.real("-pack_dmin", "Smallest diameter", 1.0, 0.0, 1e6, true);
  spec.d_max =
      g.real("-pack_dmax", "Largest diameter (>= d_min, <= 4 d_min)", 1.25, 0.0, 1e6, true);
  if (!(spec.d_max >= spec.d_min && spec.d_max <= 4 * spec.d_min))
    throw InputError("option -pack_dmax = " + number(spec.d_max) +
                     " is out of range: allowed "
                     "-pack_dmin = " +
                     number(spec.d_min) + " to 4 -pack_dmin = " + number(4 * spec.d_min));
  spec.seed = static_cast<std::uint64_t>(
      g.integer("-pack_seed", "Seed of the random diameters and start positions", 1, 0,
                2147483647));
  spec.distribution =
      g.choice<SizeDistribution>("-pack_distribution", "Diameter distribution",
                                 {{"uniform_diameter", SizeDistribution::uniform_diameter},
                                  {"uniform_volume", SizeDistribution::uniform_volume}},
                                 SizeDistribution::uniform_diameter);
  spec.law = g.choice<ContactLaw>("-pack_law", "Soft repulsion used to find the jammed state",
                                  {{"linear", ContactLaw::linear}, {"hertz", ContactLaw::hertz}},
                                  ContactLaw::linear);
  spec.fraction_tolerance = g.real("-pack_tolerance",
                                   "Stop when jammed and unjammed volume fractions differ by "
                                   "less than this",
                                   1e-5, 1e-9, 1e-2);
  spec.initial_fraction = g.real("-pack_initial_fraction",
                                 "Volume fraction of the random "
                                 "start",
                                 spec.initial_fraction, 0.05, 0.72);
  spec.initial_step = g.real("-pack_initial_step",
                             "First change of volume fraction between "
                             "jamming attempts",
                             spec.initial_step, 0.0, 0.1, true);
  spec.force_tolerance = g.real("-pack_force_tolerance",
                                "A relaxation ends jammed when "
                                "the largest net force is below this times the mean "
                                "contact force",
                                spec.force_tolerance, 0.0, 0.1, true);
  spec.contact_gap = g.real("-pack_contact_gap",
                            "Contact if the gap is below this times "
                            "the mean diameter",
                            1e-3, 0.0, 0.5);
  return spec;
}

CementedSampleSpec read_cemented_sample_spec(MPI_Comm comm) {
  CementedSampleSpec spec;
  spec.packing = read_packing_spec(comm);
  OptionGroup g(comm, "Cemented sample (paper sect. 2.2-2.3; without a lattice size: 2520 "
                      "bonds per sample particle, the paper's 1.3e6 for 516)");
  spec.sample_particles = g.integer("-sample_particles",
                                    "Sphere centres inside the cubic sample (the paper: 516); the "
                                    "spheres reaching in from outside are kept too",
                                    516, kMinSampleParticles, 50'000'000);
  if (spec.packing.count == 0) {
    spec.packing.count = auto_packing_count(spec.sample_particles);
  } else if (spec.packing.count < spec.sample_particles) {
    throw InputError("option -pack_particles = " + std::to_string(spec.packing.count) +
                     " is too small: the cube needs -sample_particles = " +
                     std::to_string(spec.sample_particles) + " of the packing's spheres");
  }
  if (!read_random_lattice_options(g, spec.lattice))
    spec.lattice.bonds = kBondsPerSampleParticle * spec.sample_particles;
  spec.generator = read_lattice_generator(g);
  // The bridge options are in units of d_min; the geometry works in lengths.
  spec.bridges.matrix_fraction =
      g.real("-matrix_fraction",
             "Requested matrix volume fraction rho^m (calibrated on the lattice "
             "to 1e-3; the paper varies it up to the pore space)",
             spec.bridges.matrix_fraction, 0.0, 0.36, true);
  spec.bridges.max_gap =
      spec.packing.d_min *
      g.real(
          "-matrix_max_gap",
          "Pairs of particles whose surfaces are at most this far apart "
          "(in units of d_min) receive a matrix bridge; the paper states d_min, its ~9 bridges per "
          "particle need less",
          spec.bridges.max_gap, 0.0, 10.0);
  spec.bridges.max_lambda =
      g.real("-matrix_max_lambda", "Widest bridge: frustum radius / particle radius at the centres",
             spec.bridges.max_lambda, 0.0, 10.0, true);
  spec.bridges.void_bonds = g.choice<VoidRule>(
      "-sample_void_bonds",
      "Bonds the pores make void (the paper states only f^v = 0): "
      "any_end = every bond with an end in a pore; both_ends = only bonds with both ends in "
      "pores, a bond from a particle or matrix node into a pore taking that node's phase",
      {{"any_end", VoidRule::any_end}, {"both_ends", VoidRule::both_ends}}, VoidRule::any_end);
  return spec;
}

PhaseTable read_phase_table(MPI_Comm comm) {
  PhaseTable t;
  OptionGroup g(comm, "Bond properties per phase (paper sect. 2.2: E = k/a, sigma = f/a^2)");
  // -phase_E_<name> and -phase_sigma_<name> for every phase but the void.
  struct Entry {
    Phase phase;
    const char *modulus_help, *strength_help;
  };
  static const Entry entries[] = {
      {Phase::p, "Modulus E^p = k^p/a of bonds inside a particle (paper: 3 E^m)",
       "Breaking stress sigma^p = f^p/a^2 of particle bonds"},
      {Phase::m, "Modulus E^m = k^m/a of matrix bonds",
       "Breaking stress sigma^m = f^m/a^2 of matrix bonds (paper: sigma^p)"},
      {Phase::pp,
       "Modulus E^pp = k^pp/a of bonds joining two particles "
       "(0: bare contacts carry nothing and are left out)",
       "Breaking stress sigma^pp = f^pp/a^2 of particle-particle bonds (paper: 0)"},
      {Phase::pm, "Modulus E^pm = k^pm/a of particle-matrix interface bonds (paper: E^m)",
       "Breaking stress sigma^pm = f^pm/a^2 of particle-matrix interface bonds"},
  };
  for (const Entry& e : entries) {
    const int k = static_cast<int>(e.phase);
    const std::string modulus = std::string("-phase_E_") + phase_name(e.phase);
    const std::string strength = std::string("-phase_sigma_") + phase_name(e.phase);
    t.modulus[k] =
        g.real(modulus.c_str(), e.modulus_help, t.modulus[k], 0.0, 1e12, e.phase != Phase::pp);
    t.strength[k] = g.real(strength.c_str(), e.strength_help, t.strength[k], 0.0, 1e12);
  }
  return t;
}

}  // namespace lem
