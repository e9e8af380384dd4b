// Stress-controlled walls: a wall moves so that the normal stress the grains put on it tends
// to a target (isotropic compaction to a confining pressure, the lateral walls of a triaxial
// test). The controller only sets wall velocities between steps, from the wall forces of the
// last step.
//
// The measured stress of a plane wall is sigma = -F . n / A (F: force of the grains on the
// wall, n: the wall's normal into the grains, compression positive); A is the wall's current
// area: the product of the sample's extents along the other axes, each taken between the
// facing plane walls on that axis (or the contact-detection domain where there are none),
// times the thickness in 2D. The control law is proportional:
//   v = -n * clamp(g * (sigma - target), -v_max, v_max)
// (too much stress: the wall backs off; too little: it advances). A step moves the wall by
// v dt, which changes the force by K v dt + C v, K the wall's contact stiffness (the sum of
// the tangent normal stiffnesses of its contacts) and C their dashpots' sum (the dashpot
// answers the wall's velocity at once); the loop is stable only if g (K dt + C) / A < 1, and a
// stiff or damped packing makes a fixed gain oscillate from one step to the next. So the gain
// used is
//   g = min(gain, 0.5 A / (K dt + C))
// with `gain` the user's (default v_max / the largest target). This needs stiffness: contact
// dynamics (rigid grains) is refused for now; it needs walls driven by a force (a wall body
// with a mass), not by a velocity.
#pragma once

#include <cstddef>
#include <vector>

#include "sable/world/world.hpp"

namespace sable {

struct ServoTarget {
  std::size_t wall = 0;
  double stress = 0.0;  // Pa, compression positive
};

struct ServoSettings {
  double gain = 0.0;          // m/s per Pa; 0: max_velocity / the largest target
  double max_velocity = 0.0;  // m/s, > 0
};

// Area (m^2; 2D: length times thickness) of an axis-aligned plane wall, as described above.
// Throws InputError for a cylinder or a tilted plane.
template <int D>
double wall_area(const World<D>& w, std::size_t wall);

// Measured normal stress on a plane wall (Pa, compression positive).
template <int D>
double wall_normal_stress(const World<D>& w, std::size_t wall);

// How the wall's force answers its motion: the sum of the tangent normal stiffnesses
// dF/d(delta) of its touching contacts (N/m) and of their dashpot coefficients (N s/m).
struct WallResponse {
  double stiffness = 0.0, damping = 0.0;
};
template <int D>
WallResponse wall_response(const World<D>& w, std::size_t wall);

// Set the velocity of every targeted wall from its measured stress.
template <int D>
void servo_walls(World<D>& w, const std::vector<ServoTarget>& targets, const ServoSettings& s);

// Largest |sigma - target| / target over the targets (0 for none).
template <int D>
double servo_error(const World<D>& w, const std::vector<ServoTarget>& targets);

}  // namespace sable
