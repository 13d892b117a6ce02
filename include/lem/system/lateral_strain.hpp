// The lateral strains of a sample in uniaxial tension, measured from the
// displacements of its lateral faces without the rigid rotation about z that
// the boundary conditions leave to the three anchoring constraints
// (docs/model/theory.md, "Tension").
#pragma once

#include "lem/system/distributed_lattice.hpp"

namespace lem {

struct LateralStrain {
  double xx = 0, yy = 0;
};

/// eps_xx from the nodes on the two x faces (eps_yy likewise from the y
/// faces), pinned nodes left out: the least-squares fit of u_x over both
/// faces by c + eps_xx x + h_y y + h_z z, i.e. the difference of the two
/// faces' mean u_x after the linear trend along the faces (pooled over both
/// faces) is taken to a common point:
///
///   eps_xx = [(<u_x>+ - h.<t>+) - (<u_x>- - h.<t>-)] / Lx,   t = (y, z).
///
/// A displacement linear along the faces -- a rigid rotation about z, an
/// in-face shear -- changes the plain difference of face means by h times
/// the distance between the two faces' node centroids; here it changes
/// nothing, and an affine field gives its own eps_xx to round-off.  When
/// both faces have the same node centroid the result is the difference of
/// face means.  0 for an axis one of whose faces has no free node.
/// `u_owned`: 3 values per owned node.  Collective over lattice.comm.
LateralStrain lateral_strains(const DistributedLattice& lattice, const double* u_owned);

}  // namespace lem
