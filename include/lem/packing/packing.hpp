// Packing stage: a dense random packing of polydisperse rigid spheres, and a
// cubic sample cut out of it (Affes et al. 2012, sect. 2.2-2.3: 516 spheres,
// d uniform in [d_min, 1.25 d_min], rho^p ~ 0.64).
//
// The packing is made by isotropic compaction of frictionless soft spheres in
// a periodic cubic box, driven to the jamming point: random centres at a
// volume fraction above jamming are relaxed (FIRE energy minimisation) into a
// jammed state; the box is then expanded in steps, each relaxed again from
// the last jammed state, and the step is halved whenever the packing unjams
// (its overlaps relax to zero), until the step is below a tolerance in volume
// fraction.  The result is a mechanically stable packing whose overlaps are
// ~1e-6 d: effectively rigid spheres in contact.  Everything is serial and
// deterministic: the same spec (seed) gives bit-identical spheres on the same
// build (the random numbers do not depend on the standard library).
//
// Lengths are in the units of d_min (d_min = 1 gives the paper's units).
#pragma once

#include "lem/base/geometry.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace lem {

/// Diameter distribution.  The paper's is uniform in diameter; uniform in
/// volume (d^3 uniform in [d_min^3, d_max^3]) puts more weight on large
/// particles, which are then a larger share of the solid volume.
enum class SizeDistribution { uniform_diameter, uniform_volume };

/// Soft repulsion used only to find the jammed state (the final overlaps are
/// ~1e-6 d, so the law does not show in the result beyond the protocol):
/// linear f = k delta (harmonic energy, faster to relax) or Hertz
/// f = k delta^(3/2).
enum class ContactLaw { linear, hertz };

struct PackingSpec {
  std::int64_t count = 1000;  // spheres in the periodic box
  double d_min = 1.0;
  double d_max = 1.25;
  SizeDistribution distribution = SizeDistribution::uniform_diameter;
  ContactLaw law = ContactLaw::linear;
  std::uint64_t seed = 1;
  /// Volume fraction of the random (overlapping) start, and the first step
  /// of the decompression.  Starting above jamming is an instant quench (no
  /// time to order, random close packing) and avoids relaxing an unjammed
  /// state into a jammed one near the jamming point, which is very slow for
  /// large counts.  A start below jamming is compressed in steps of
  /// `initial_step` until it jams, then decompressed as usual.
  double initial_fraction = 0.66;
  double initial_step = 0.01;
  /// Stop when the last unjammed and the final jammed volume fractions differ
  /// by at most this.
  double fraction_tolerance = 1e-5;
  /// Two spheres are in contact when their gap is below contact_gap times
  /// the mean diameter (coordination statistics only).
  double contact_gap = 1e-3;
  /// A relaxation stops as jammed when the largest net force on a sphere is
  /// below force_tolerance times the mean contact force.  Near the jamming
  /// point relaxation is slow (it grows fast with the count); 1e-3 gives
  /// nearly isostatic packings (z = 5.99 on the loaded contacts) where 1e-2,
  /// three times cheaper, sometimes calls jammed a state that is slowly
  /// unjamming (rho_p then ~5e-4 lower; overlaps stay ~1e-6 d either way).
  double force_tolerance = 1e-3;
  /// Relaxation budget of one jamming attempt (FIRE steps); a state still
  /// overlapping after it counts as jammed (reported as not settled).
  std::int64_t max_relaxation_steps = 200000;
};

/// Throw InputError (naming the field, the value and what is allowed) if the
/// spec cannot be packed.
void validate(const PackingSpec& spec);

struct Sphere {
  Point centre;
  double radius;
};

struct PackingStats {
  std::int64_t particles = 0;
  double volume_fraction = 0;  // sum of sphere volumes / box volume
  double mean_diameter = 0;
  /// Contacts: pairs with gap < contact_gap * mean diameter (overlaps count).
  std::int64_t contacts = 0;
  double mean_coordination = 0;  // 2 contacts / particles
  /// Rattlers (fewer than 4 contacts, removed recursively) carry no load in a
  /// frictionless packing; the rest should be isostatic, z = 6.
  double rattler_fraction = 0;
  double backbone_coordination = 0;
  /// The same with only the overlapping pairs (the contacts that carry
  /// force): a jammed frictionless packing is isostatic, 6 up to O(1/N).
  double loaded_coordination = 0;
  /// Overlap delta_ij = r_i + r_j - |x_i - x_j| over the pair's mean
  /// diameter (r_i + r_j): mean over overlapping pairs, and maximum.
  std::int64_t overlapping_pairs = 0;
  double mean_overlap = 0;
  double max_overlap = 0;
  /// Pressure (1/3V) sum f_ij . r_ij with the soft law of unit stiffness,
  /// in units of k / d_min (linear) — ~0 at the jamming point.
  double pressure = 0;
  int attempts = 0;            // jamming attempts (relaxations)
  int unsettled_attempts = 0;  // attempts stopped by max_relaxation_steps
  std::int64_t relaxation_steps = 0;
  std::int64_t neighbour_builds = 0;
  double seconds = 0;  // wall time of make_packing
};

struct Packing {
  double box_side = 0;          // periodic box [0, box_side)^3
  std::vector<Sphere> spheres;  // centres wrapped into the box
  PackingStats stats;
};

/// One line of progress, reported after every jamming attempt.
struct JammingAttempt {
  int attempt = 0;
  double volume_fraction = 0;
  bool jammed = false;             // residual overlap after relaxation
  double step = 0;                 // current |change of volume fraction|
  double energy_per_particle = 0;  // in k d_min^2 (linear law)
  double mean_overlap = 0;         // as in PackingStats
  double max_overlap = 0;
  std::int64_t relaxation_steps = 0;
  bool settled = true;  // false: stopped by max_relaxation_steps
  double seconds = 0;   // since the start of make_packing
};
using JammingProgress = std::function<void(const JammingAttempt&)>;

/// Build a jammed periodic packing.  Throws InputError for a bad spec and
/// NumericalError if the compaction fails (does not jam in 400 attempts).
Packing make_packing(const PackingSpec& spec, const JammingProgress& progress = {});

/// Contact, rattler and overlap statistics of spheres in a periodic box
/// (timing and attempt counters are left at zero).  Throws InputError if the
/// box is narrower than 4 r_max + 2 gap (contacts with several images).
PackingStats measure_packing(const std::vector<Sphere>& spheres, double box_side,
                             double contact_gap);

/// Which spheres a cube cut keeps.  centres_inside: those whose centres lie
/// in the cube (the count is the target); the faces cut the ones near them,
/// but the parts of outside spheres that reach in are missing, so the
/// sample's volume fraction is below the packing's (~0.59-0.60 for 516
/// spheres at rho^p = 0.643).  reaching_in: also every periodic image of an
/// outside sphere that reaches into the cube (centre outside [0, side]^3):
/// the cube then holds exactly the packing's material (rho^p as the box).
enum class CubeCut { centres_inside, reaching_in };

/// A cubic sample [0, side]^3 cut out of a periodic packing.
struct CubeSample {
  double side = 0;
  Point centre_in_box{};  // where the cube's centre lies in the packing
  /// The spheres whose centres lie inside, shifted into [0, side)^3, in the
  /// packing's order; with CubeCut::reaching_in followed by the outside ones
  /// that reach in.
  std::vector<Sphere> spheres;
  std::int64_t centres_inside = 0;  // the first spheres, = the target count
  /// Volume of the parts of `spheres` inside the cube / side^3 (exact up to
  /// quadrature round-off, see sphere_box_volume).
  double volume_fraction = 0;
  /// The same counting every sphere that reaches in: the packing's own
  /// density in the cube (~ the box's rho^p), whatever the cut.
  double region_volume_fraction = 0;
};

/// Cut the cube centred at `centre` (default: the box centre) holding exactly
/// `target_count` sphere centres: the side is chosen halfway between the
/// target_count-th and the next sphere's distance (max-norm, periodic) from
/// the centre, so the side is about box_side * (target_count / N)^(1/3).
/// Throws InputError unless 1 <= target_count <= N.
CubeSample cut_cube(const Packing& packing, std::int64_t target_count,
                    CubeCut cut = CubeCut::centres_inside);
CubeSample cut_cube(const Packing& packing, std::int64_t target_count, const Point& centre,
                    CubeCut cut = CubeCut::centres_inside);

/// Volume of the part of a sphere inside a box: exact formula for a disc
/// clipped by two lines, integrated over the third axis by tanh-sinh
/// quadrature between the points where the integrand is not smooth
/// (relative error ~1e-12).
double sphere_box_volume(const Point& centre, double radius, const Box& box);

}  // namespace lem
