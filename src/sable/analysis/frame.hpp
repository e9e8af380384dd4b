// Samples seen from a frame rotating about an axis: for averages attached to a rotating body
// (Guillard et al. 2015 average their stress fields in the frame turning with the cylinder).
//
// At time t the frame has turned by theta = omega (t - t0) about the axis through `point`
// along `axis` (right-handed). Every position is rotated by -theta about the axis, every
// vector (forces, normals, lever arms, accelerations) by the same rotation, and velocities
// become velocities relative to the frame: v' = R v - Omega x (x' - point), w' = R w - Omega.
// Accelerations are only rotated (no fictitious forces are added): tensors built from forces
// and positions are then those of the lab frame, turned with the body. In 2D the axis is z.
#pragma once

#include <Eigen/Dense>

#include "sable/analysis/sample.hpp"

namespace sable {

struct RotatingFrame {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // normalised on use
  double omega = 0.0;                               // rad/s
  double t0 = 0.0;                                  // time at which the frames coincide (s)
};

// Throws InputError for a zero axis, or (2D) an axis that is not along z.
template <int D>
Sample<D> to_rotating_frame(const Sample<D>& s, const RotatingFrame& frame);

}  // namespace sable
