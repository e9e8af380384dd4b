// Stress-controlled walls: a wall moves so that the normal stress the grains put on it tends
// to a target (isotropic compaction to a confining pressure, the lateral walls of a triaxial
// test). Two mechanisms, one per solver, with the same stress measure below:
// - DEM (servo_walls): a controller sets the wall velocities between steps, from the wall
//   forces of the last step.
// - Contact dynamics (wall_bodies): rigid grains give a velocity controller no stiffness to
//   act on, so, as in LMGC90, each wall becomes a body the solver moves (world/solver.hpp
//   WallBody, cd/cd_solver.hpp): one translational degree of freedom along its normal, a mass
//   M and an applied force F = target * A pushing into the grains (A the current area, as
//   below). Its velocity is an unknown of the contact problem, solved with the grains'
//   impulses, and the wall stops where the grains' reaction balances F: at rest, the measured
//   stress is the target (up to the last step's change of the wall's momentum, see the mass
//   below). servo_max_velocity caps the wall's speed (a wall crossing a loose packing would
//   otherwise ram it).
//
// The measured stress of a plane wall is sigma = -F . n / A (F: force of the grains on the
// wall, n: the wall's normal into the grains, compression positive); A is the wall's current
// area: the product of the sample's extents along the other axes, each taken between the
// facing plane walls on that axis (or the contact-detection domain where there are none),
// times the thickness in 2D. With contact dynamics F is the last step's impulse / h (its mean
// force over the step; cd_solver.hpp), so a wall body at rest measures exactly what balances
// its applied force. The DEM control law is proportional:
//   v = -n * clamp(g * (sigma - target), -v_max, v_max)
// (too much stress: the wall backs off; too little: it advances). A step moves the wall by
// v dt, which changes the force by K v dt + C v, K the wall's contact stiffness (the sum of
// the tangent normal stiffnesses of its contacts) and C their dashpots' sum (the dashpot
// answers the wall's velocity at once); the loop is stable only if g (K dt + C) / A < 1, and a
// stiff or damped packing makes a fixed gain oscillate from one step to the next. So the gain
// used is
//   g = min(gain, 0.5 A / (K dt + C))
// with `gain` the user's (default v_max / the largest target, or v_max / zero_target_scale when
// every target is 0: a sample released to p = 0, whose walls back off until they carry no
// force).
//
// The wall bodies' mass (contact dynamics): unless the user sets it (servo_wall_mass),
//   M = max(m_grains, 50 h^2 F / d),
// m_grains the movable grains' total mass, d their mean diameter, h the time step. The second
// term resolves the wall's response in time: from rest under F alone the wall takes
// sqrt(2 M d / F) >= 10 steps to travel one diameter. The first sets the scale: the wall's
// inertia is that of what it pushes. Lighter, it would rattle at each grain impact; heavier,
// it rams the packing and its measured stress gets noisier, since one step's impulse / h is
// F - M du / h and the NLGS leaves an error du in the wall's velocity as in the grains'. In a
// 3D triaxial compression like test_servo_cd.cpp's (sampled every 10 steps), the lateral
// stress strayed from its target by at most 1.6 % with M = m_grains, 3.7 % with 3.4 m_grains,
// 14 % with 15 m_grains, and with 75 m_grains the compaction did not settle in 10,000 steps. F,
// hence M, follows the area as the box shrinks; everything is recomputed from the world's state at
// each step, so a resumed run sees the same masses.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "sable/core/exact_sum.hpp"
#include "sable/world/domain.hpp"
#include "sable/world/solver.hpp"
#include "sable/world/world.hpp"

namespace sable {

struct ServoTarget {
  std::size_t wall = 0;
  double stress = 0.0;  // Pa, compression positive
};

struct ServoSettings {
  double gain = 0.0;          // m/s per Pa; 0: max_velocity / the largest target (see above)
  double max_velocity = 0.0;  // m/s, > 0
  // Pa: the stress a zero target is measured against (scenario key stress_scale): the default
  // gain when every target is 0, and servo_error's denominator for zero targets.
  double zero_target_scale = 0.0;
  double wall_mass = 0.0;  // kg, contact dynamics only; 0: the rule above
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
// The law's terms come from its row of the table (contact/law_table.hpp): tangent_stiffness()
// and the dashpot of coeffs(). Summed exactly (core/exact_sum.hpp) over the contacts of the
// grains this process steps (not its ghosts'), so that the sum over processes is the serial
// run's to the bit: sums[2 w] the stiffness and sums[2 w + 1] the damping of walls[w] for
// each w with want(w).
template <class Laws = NormalLaws, int D, class Want>
void add_wall_responses(const World<D>& w, ExactSum* sums, Want&& want) {
  Laws::visit(w.model.normal, [&]<class Law>() {
    const auto& p = w.particles;
    const auto& wl = w.neighbors.wall_pairs;
    for (std::size_t c = 0; c < wl.size(); ++c) {
      const std::uint32_t i = wl.i[c];
      if (!want(wl.wall[c]) || (p.flags[i] & kGhost)) continue;
      const Wall<D>& plane = w.walls[wl.wall[c]];
      typename Space<D>::Vec n;
      const double delta = p.radius[i] - plane.distance(p.x[i], n);
      if (delta <= 0.0) continue;
      const PairParams& pp = w.materials.pair(p.material[i], plane.material);
      sums[2 * wl.wall[c]].add(Law::tangent_stiffness(pp, w.model, delta, p.radius[i]));
      sums[2 * wl.wall[c] + 1].add(
          std::abs(Law::coeffs(pp, w.model, delta, p.radius[i], p.mass[i]).gn));
    }
  });
}

// One wall's response, in a serial run.
template <class Laws = NormalLaws, int D>
WallResponse wall_response(const World<D>& w, std::size_t wall) {
  std::vector<ExactSum> sums(2 * w.walls.size());
  add_wall_responses<Laws>(w, sums.data(), [wall](std::size_t k) { return k == wall; });
  return {sums[2 * wall].value(), sums[2 * wall + 1].value()};
}

// Set the velocity of every targeted wall from its measured stress. Throws InputError when
// every target is 0 and neither gain nor zero_target_scale is set (the walls could not move).
// Under MPI (`domain`) the walls' responses are summed over every process.
template <int D>
void servo_walls(World<D>& w, const std::vector<ServoTarget>& targets, const ServoSettings& s,
                 const Domain<D>* domain = nullptr);

// Contact dynamics: the targeted walls as bodies under F = target * A, with the mass of the
// rule above. Throws InputError for a wall without an area (wall_area) or a mass of 0 (no
// grains and no force: give wall_mass).
template <int D>
std::vector<WallBody> wall_bodies(const World<D>& w, const std::vector<ServoTarget>& targets,
                                  const ServoSettings& s);

// Largest relative error |sigma - target| / s over the targets (0 for none), with s the target,
// or zero_target_scale (Pa) for a zero target: a wall released to 0 Pa is within a tolerance
// tol once it carries less than tol * zero_target_scale. Throws InputError for a zero target
// when zero_target_scale <= 0.
template <int D>
double servo_error(const World<D>& w, const std::vector<ServoTarget>& targets,
                   double zero_target_scale = 0.0);

}  // namespace sable
