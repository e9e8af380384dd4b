// DEM with convex polyhedral grains (3D): the DEM solver's step when the World holds
// polyhedra (DemSolver delegates to it; dem/dem_solver_impl.hpp).
//
// The contact law. Two polyhedra (or a polyhedron and a plane wall) overlap at the points of
// their contact manifold (geometry/polyhedron_contact.hpp, polyhedron_plane.hpp): up to 4,
// each with its depth delta_p along the manifold's normal n. Each point is a linear spring
// with a dashpot along n: f_p = k_n delta_p - g v_n,p (contact.normal = "linear", the
// scenario's contact.kn; v_n,p the normal relative velocity at the point; f_p >= 0 unless
// contact.attractive_damping), so a face resting on a face carries its load shared by the
// depths of its corners: a cube at rest on a plane, its four corners equally deep, puts
// m g / 4 on each. The c points' dashpots share the one that gives the material's restitution
// exactly to c springs in parallel, g = 2 |beta| sqrt(c k_n m*) / c: a face landing flat
// (c = 4) or a vertex landing under the centroid (c = 1) rebounds with e, and the rocking of a
// face on its corners is damped too (each corner's dashpot resists its own motion). The
// tangential force is one spring per list entry, as for spheres, of stiffness c k_t, advanced
// by the relative velocity at the normal forces' centre of pressure x_N (where their moments
// cancel) and capped at mu times their sum; the whole force acts at x_N.
//
// Limits: the normal law is the linear one (a Hertz law needs a curvature, which a polyhedron's
// corners and edges do not have); walls are planes; no rolling resistance (faces resist
// rolling), no cohesion; every grain a polyhedron; one process (no MPI). Each is refused with
// a message at initialize(), or at the first step of a resumed run (which steps without it).
//
// The step is velocity Verlet for rigid bodies: half kick (v by the force, the angular
// velocity by the world-frame inverse inertia times the torque), drift (x by v; the
// orientation by the free rotation of core/rigid_rotation.hpp, which keeps the angular
// momentum), the forces at the new state, half kick. Forces are found per list entry in
// parallel and summed into the grains in the list's order: the same bits on any number of
// threads.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "sable/core/phase_timer.hpp"
#include "sable/world/reorder.hpp"
#include "sable/world/solver.hpp"
#include "sable/world/wall_totals.hpp"
#include "sable/world/world.hpp"

namespace sable {

class PolyhedralDem {
 public:
  PolyhedralDem(World<3>& world, PhaseTimers& timers, StepDiagnostics& diag)
      : w_(world), timers_(timers), diag_(diag) {}
  // The lists and the forces at the current state (no grain moves).
  void initialize();
  void step();

  using Vec = Eigen::Vector3d;
  // One list entry's contact this step: its force on grain i and where it acts.
  struct EntryForce {
    Vec force = Vec::Zero();
    Vec at = Vec::Zero();
    double depth = 0.0;        // the deepest point's overlap (0: apart)
    Vec normal = Vec::Zero();  // unit, from grain i towards its partner (zero: apart)
  };

 private:
  void check_world();  // throws what the header lists; sets checked_
  void kick(double h);
  void drift(double h);
  void compute_forces();
  EntryForce pair_force(std::size_t k);
  EntryForce wall_force(std::size_t k);
  void sum_forces();

  World<3>& w_;
  PhaseTimers& timers_;
  StepDiagnostics& diag_;
  GrainReorder<3> reorder_;
  WallTotals<3> wall_totals_;
  std::vector<EntryForce> pair_out_, wall_out_;
  bool checked_ = false;  // check_world() has passed: a World keeps its kinds through a run
};

}  // namespace sable
