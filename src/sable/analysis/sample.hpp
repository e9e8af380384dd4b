// What every analysis reads: one instant of a run, as flat arrays, independent of the solver.
//
// A Sample is made from a World (a live run, or a snapshot loaded through its scenario:
// scenario/snapshot_sample.hpp). It holds the grains (positions, velocities, accelerations,
// sizes, masses), the walls, and one record per force-carrying contact. DEM and CD snapshots give
// the same kind of Sample: DEM stores its contact forces, CD its impulses divided by the step, in
// the same slots.
//
// Conventions (docs/analysis.md):
//  - n points from grain i towards its partner (grain j, or into the wall);
//  - force is the force ON grain i (the partner feels -force);
//  - fn = -force . n is the normal force, positive in compression, negative in tension;
//  - ft = force + fn n is the tangential force (perpendicular to n);
//  - arm_i = contact point - x_i, arm_j = contact point - x_j (zero for walls); for an
//    overlapping pair both arms reach the same point, the middle of the overlap, which is
//    where the DEM solver applies the force (the torques it integrates use these arms);
//    for polyhedral grains both reach the point the solver stored: DEM's centre of pressure,
//    CD's centre of the manifold points weighted by their normal impulses;
//  - branch = x_j - x_i for grain pairs, arm_i for wall contacts;
//  - stresses are positive in compression (soil-mechanics sign; Dumont-Fortin-Ouafik write
//    theirs positive in tension: their tensor is minus ours).
//
// Accelerations are those the solver integrated at the snapshot's instant: a = f / m + g with
// f the contact force sum (DEM: forces at the stored positions; CD: impulses / h of the last
// step), and alpha = I^-1 torque (a polyhedron: Euler's equations, see Sample::polyhedra). Fixed
// grains have a = 0, alpha = 0.
//
// Contact dynamics computes a step's impulses in the configuration at the START of the step
// and then moves the grains (x_end = x_start + h v_end). A CD sample therefore places the
// grains and walls where the impulses were computed, x = x_end - h v_end, with the end
// velocities, and its arms end on the grains' surfaces (r n), as the CD solver's do: every
// grain's momentum balance then holds exactly in the sample, as it does in the solver.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sable/core/space.hpp"
#include "sable/geometry/walls.hpp"

namespace sable {

template <int D>
struct World;

// A contact's motion and damping, what the dissipation analysis needs (dissipation.hpp).
template <int D>
struct ContactMotion {
  typename Space<D>::Vec vrel = Space<D>::Vec::Zero();  // i's contact point less the partner's
  double damping_n = 0.0, damping_t = 0.0;  // the law's gamma_n, gamma_t at this overlap (N s/m)
  double spring = 0.0;  // the tangential spring's force k_t |xi| (N; DEM): mu f_n when sliding
};

// One record per contact carrying a non-zero force, as parallel arrays.
template <int D>
struct ContactSet {
  using Vec = typename Space<D>::Vec;
  std::vector<std::uint32_t> i;    // grain slot
  std::vector<std::uint32_t> j;    // partner: grain slot, or wall index when wall[k] != 0
  std::vector<std::uint8_t> wall;  // 1 for a grain-wall contact
  std::vector<Vec> n;              // unit normal from i towards the partner
  std::vector<Vec> force;          // force on i (N; per thickness in 2D)
  std::vector<double> fn;          // normal force, > 0 compressive
  std::vector<Vec> ft;             // tangential force on i
  std::vector<Vec> arm_i, arm_j;   // contact point relative to x_i, x_j
  std::vector<Vec> branch;         // x_j - x_i (pairs), arm_i (walls)
  std::vector<double> overlap;     // > 0 overlapping, < 0 open gap (m)
  std::vector<double> friction;    // Coulomb coefficient of the pair's materials
  // ContactMotion's fields, as arrays: the velocity of i's contact point less the partner's
  // there (a wall's: its translation and spin at the point); the normal law's damping
  // coefficients at the overlap and the tangential spring's force k_t |xi| (DEM; zero for
  // contact dynamics, whose contacts have neither dashpot nor spring).
  std::vector<Vec> vrel;
  std::vector<double> damping_n, damping_t, spring;

  std::size_t size() const { return i.size(); }
  bool is_wall(std::size_t k) const { return wall[k] != 0; }
  Vec point(std::size_t k, const std::vector<Vec>& x) const { return x[i[k]] + arm_i[k]; }
  void clear();
  void push(std::uint32_t gi, std::uint32_t partner, bool at_wall, const Vec& normal, const Vec& f,
            const Vec& a_i, const Vec& a_j, const Vec& l, double delta, double mu,
            const ContactMotion<D>& motion = {});
  ContactMotion<D> motion(std::size_t k) const {
    return {vrel[k], damping_n[k], damping_t[k], spring[k]};
  }
};

struct SampleWall {
  std::string name;
  bool plane = true;
  std::array<double, 3> point{}, normal{}, force{};  // force ON the wall by the grains
  double radius = 0.0;                               // cylinder
  std::string type = "plane";                        // "plane", "cylinder" or "mesh"
  // Torque ON the wall by the grains about `pivot` (the origin for a wall never given a
  // rotation); 2D: about z, in torque[2].
  std::array<double, 3> torque{}, pivot{};
  bool mesh() const { return type == "mesh"; }
};

// How the solver that produced the forces places them (see above).
enum class ForceGeometry { kSoft, kContactDynamics };

template <int D>
struct Sample {
  using S = Space<D>;
  using Vec = typename S::Vec;
  using Rot = typename S::Rot;

  // Grains, by slot.
  std::vector<Vec> x, v, a;                           // position, velocity, acceleration (m/s^2)
  std::vector<Rot> omega, alpha;                      // angular velocity and acceleration
  std::vector<double> radius, mass, volume, inertia;  // volume: per 2D thickness times it
  std::vector<std::uint8_t> fixed;
  std::vector<std::uint32_t> id;  // stable id index (for following grains across snapshots)
  ContactSet<D> contacts;
  std::vector<SampleWall> walls;

  Vec gravity = Vec::Zero();
  double thickness = 1.0;  // 2D out-of-plane depth (m): volumes and stresses use it
  double time = 0.0;
  std::uint64_t step = 0;
  std::string source;  // the snapshot file (or "live"), for messages
  ForceGeometry geometry = ForceGeometry::kSoft;
  // The grains are convex polyhedra (3D): `radius` is then each one's bounding sphere, not its
  // size; `volume` its own; `inertia` its mean principal moment; `alpha` from Euler's
  // equations with its world-frame inertia tensor; contacts carry the normal and point the
  // solver stored (world/contact_geometry.hpp). Analyses that need a round grain's geometry refuse
  // such a sample (refuse_polyhedra()).
  bool polyhedra = false;
  // Polyhedra only (else empty): each grain's second moment of mass about its centroid in the
  // world frame, int rho r r^T (kg m^2), for the mean stress's inertial part.
  std::vector<Eigen::Matrix<double, D, D>> second_moment;

  std::size_t size() const { return x.size(); }
  double total_mass() const;
};

// The Sample of a World at its current state.
template <int D>
Sample<D> make_sample(const World<D>& world, ForceGeometry geometry = ForceGeometry::kSoft);

// Reads a snapshot into a Sample. A snapshot needs its World rebuilt (materials, walls and the
// contact law, from the scenario stored inside it) before its state can be read: that is the
// scenario layer's work (scenario/snapshot_sample.hpp gives these loaders), so the analyses
// take the loaders from their caller rather than reach up for them.
struct SampleLoaders {
  std::function<Sample<2>(const std::string&)> load2;
  std::function<Sample<3>(const std::string&)> load3;
  template <int D>
  Sample<D> load(const std::string& snapshot_path) const {
    if constexpr (D == 2)
      return load2(snapshot_path);
    else
      return load3(snapshot_path);
  }
};

// Throws InputError (naming s.source) if a contact names a grain the sample does not hold:
// analyses that index grains by contact call it once before they start.
template <int D>
void check_contact_indices(const Sample<D>& s);

// Throws InputError naming `analysis` and `why` if the sample holds polyhedral grains.
template <int D>
void refuse_polyhedra(const Sample<D>& s, const std::string& analysis, const std::string& why);

// The dimension of a snapshot (2 or 3), read from its header.
int snapshot_dimension(const std::string& snapshot_path);

// Axis-aligned box; the default (empty) region means "everything".
template <int D>
struct Region {
  using Vec = typename Space<D>::Vec;
  Vec lo = Vec::Constant(-1e300), hi = Vec::Constant(1e300);
  bool contains(const Vec& p) const {
    return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
  }
  bool bounded() const { return (lo.array() > -1e299).all() && (hi.array() < 1e299).all(); }
  // Volume (area times thickness in 2D).
  double volume(double thickness) const;
};

// The smallest box holding every grain entirely (x +- r).
template <int D>
Region<D> grain_bounds(const Sample<D>& s);

}  // namespace sable
