// Non-smooth contact dynamics (Moreau-Jean time stepping, NLGS contact solver).
//
// Grains are rigid; at each step the contact impulses r (normal and friction) are the unknowns
// of a frictional contact problem in local form, solved by nonlinear Gauss-Seidel with a
// bi-potential (or exact) local solver. The solver advances the same World as DEM: grains,
// walls, materials and the neighbour lists, whose per-contact `force` slot holds impulse / h
// (so outputs and analyses read CD forces exactly like DEM forces, and the impulses of
// persisting contacts warm-start the next step and travel in snapshots).
//
// Walls of every shape are bodies of infinite mass with a prescribed motion: a wall entry's
// contact is at the feature its element answers for (Wall::contact; a mesh entry whose
// element holds no nearest feature stays out), and the wall's velocity there is its
// translation plus its spin about its pivot (Wall::velocity_at).
//
// Stress-controlled walls are bodies here (set_wall_bodies, as in LMGC90): a plane wall with
// one translational degree of freedom along its normal, a mass M and an applied force F. Its
// velocity is one more unknown of the NLGS: a grain-wall contact sees the wall's 1/M along n
// in its Delassus block and the wall's current velocity in U, and every impulse update moves
// the wall's velocity at once (see Problem::apply). The wall then moves with its end-of-step
// velocity. The step's only wall state is that velocity, which snapshots carry.
#pragma once

#include <algorithm>
#include <limits>
#include <vector>

#include "sable/cd/nlgs.hpp"
#include "sable/geometry/polyhedron_contact.hpp"
#include "sable/world/reorder.hpp"
#include "sable/world/solver.hpp"
#include "sable/world/wall_totals.hpp"
#include "sable/world/world.hpp"

namespace sable {

struct CdSettings {
  double theta = 0.5;  // weight of the end-of-step smooth forces in the free velocity
  // The grains' sweep keeps its order: it follows the neighbour list, sorted by cell, along
  // which a packing's impulses propagate; a shuffled sweep converges far worse there
  // (docs/BENCHMARKS.md, BM_CdStepOrder: 3-9 times slower at a fixed number of sweeps with
  // scrambled slots). With `newton_iterations` > 0, a stagnation (or the sweep budget spent)
  // hands over to the semismooth Newton of fc_newton.hpp on the assembled problem
  // (grain_delassus.hpp), at most that many steps, where the step has neither wall bodies
  // nor rolling couples and the criterion is the natural map's. Off by default: on the silo
  // it cuts the sweeps fivefold but costs more time than it saves (docs/contact-dynamics.md).
  cd::NlgsSettings nlgs = {.shuffle_on_stagnation = false, .stop_on_stagnation = true};
  // nlgs.order kColoured: contacts per block of the colouring (cd/colouring.hpp).
  std::size_t colour_block = 256;
  int newton_iterations = 0;
  bool warm_start = true;
  // The share beta of an overlap that a step removes (0: none). The normal unknown is
  // U_N + g / h for an open gap g (it may close within the step, never cross) and
  // U_N + beta g / h for an overlap (g < 0): a contact that overlaps by |g| separates at up to
  // beta |g| / h, which is the energy it injects. With beta = 0 an overlap made by a step's
  // first-order error (a corner's arc, an edge sliding over an edge) stays for good and the
  // errors of a long compaction add up; a share of them removed each step bounds the overlap
  // near (error per step) / beta (docs/contact-dynamics.md).
  double overlap_recovery = 0.0;
};

template <int D>
class CdSolver final : public Solver {
 public:
  using Vec = typename Space<D>::Vec;
  using Rot = typename Space<D>::Rot;
  using LVec = cd::LVec<D>;
  using LMat = cd::LMat<D>;

  CdSolver(World<D>& world, const CdSettings& settings) : world_(world), s_(settings) {}
  std::string_view name() const override { return "cd"; }
  void initialize() override;
  void step() override;
  const StepDiagnostics& diagnostics() const override { return diag_; }
  const PhaseTimers& timers() const override { return timers_; }
  std::vector<std::string> diagnostic_columns() const override;
  void diagnostic_values(std::vector<double>& row) const override;
  bool moves_wall_bodies() const override { return true; }
  void set_wall_bodies(const std::vector<WallBody>& bodies) override;
  const cd::NlgsResult& last_solve() const { return result_; }
  int last_newton_iterations() const { return newton_iterations_; }

  // The problem NLGS sees: one entry per candidate contact, velocities from the grains.
  // Public so the NLGS template can call it; not part of the user API.
  struct Contacts {
    std::vector<std::uint32_t> i;        // grain slot
    std::vector<std::uint32_t> partner;  // grain slot, or wall index when `wall` is set
    std::vector<std::uint8_t> wall;      // 1 for a grain-wall contact
    std::vector<std::uint32_t> source;   // index into the pair or wall-pair list
    std::vector<LMat> frame;             // columns n, t1 (, t2): local -> world
    std::vector<Vec> arm_i, arm_j;       // centre -> contact point
    std::vector<LMat> W;                 // Delassus diagonal block
    std::vector<double> mu;
    std::vector<double> gap;  // at the start of the step; max(gap, 0) / h joins U_N
    std::vector<LVec> r;      // impulse, local frame
    // Rolling resistance only (else empty): mu_r and R* (the couple's cap is mu_r R* r_N)
    // and the rolling impulse on grain i (a couple times h; its partner gets minus).
    std::vector<double> roll_mu;
    std::vector<double> roll_r;
    std::vector<Rot> m;
    std::size_t size() const { return i.size(); }
    void resize(std::size_t n, bool rolling);  // the rolling arrays to n, or empty
  };
  // A wall's degree of freedom during a step (inv_mass 0: the wall's velocity is prescribed).
  // Its speed along the normal is u = clamp(u_free + impulse / M, +-max_speed).
  struct WallDof {
    double inv_mass = 0.0;
    double force = 0.0;  // N, applied along the normal (into the grains)
    double max_speed = std::numeric_limits<double>::infinity();
    double free_speed = 0.0;  // u(t) + h F / M
    double impulse = 0.0;     // the contacts' impulses on the wall, along its normal
    double speed() const {
      return std::clamp(free_speed + inv_mass * impulse, -max_speed, max_speed);
    }
  };
  class Problem;

  // How a grain's angular velocity answers a moment: its scalar inverse inertia (disks,
  // spheres), or, in a world with polyhedral grains, its world-frame inverse inertia tensor
  // at the step's orientation (core/rigid_rotation.hpp), one per grain.
  struct AngularResponse {
    const double* inv_inertia = nullptr;
    const Eigen::Matrix3d* tensor = nullptr;  // null: every grain round
    Rot operator()(std::uint32_t g, const Rot& m) const {
      if constexpr (D == 3)
        if (tensor != nullptr) return tensor[g] * m;
      return inv_inertia[g] * m;
    }
  };

 private:
  void build_contacts();
  // The contacts of a world with polyhedral grains (cd/cd_polyhedra.cpp): each list entry
  // gives its manifold's points (up to 4) and look-ahead points (up to 4), each a contact.
  void build_polyhedral_contacts();
  void check_polyhedral_world() const;
  // Each list entry's normal, point and depth into World::contact_geometry, from its
  // manifold's contacts and their solved impulses (cd/cd_polyhedra.cpp).
  void store_polyhedral_geometry();
  // check_polyhedral_world() on the first call with polyhedra (initialize(), or a resumed
  // run's first step): a World's grains and walls keep their kinds through a run.
  void check_polyhedra_once() {
    if (polyhedra_checked_ || world_.shapes.empty()) return;
    check_polyhedral_world();
    polyhedra_checked_ = true;
  }
  AngularResponse angular_response();
  // slot_ holds each list entry's number of contacts (and a 0 at its end): turned into each
  // entry's first contact (an exclusive prefix sum); returns the total.
  std::size_t first_contacts();
  void drift(double h);
  void build_colouring();
  template <bool kWall>
  void set_contact(std::size_t a, std::uint32_t i, std::uint32_t partner, std::uint32_t source,
                   const Vec& n, double gap, const Vec& arm_i, const Vec& arm_j,
                   const PairParams& pp, const Vec& force, const Rot& couple);
  void store_impulses();
  bool newton_applies() const;
  void newton_fallback(Problem& problem);
  void start_wall_bodies();
  double max_speed() const;
  double wall_speed(std::uint32_t w, const Vec& x, double radius) const;
  bool is_body(std::size_t wall) const { return wall < dofs_.size() && dofs_[wall].inv_mass > 0.0; }

  World<D>& world_;
  CdSettings s_;
  StepDiagnostics diag_;
  PhaseTimers timers_;
  Contacts c_;
  std::vector<WallDof> dofs_;  // per wall once set_wall_bodies was called, else empty
  cd::NlgsResult result_;
  std::vector<LVec> q_;           // the contacts' free velocities (every impulse zero), per step
  cd::SweepColouring colouring_;  // kColoured: this step's blocks
  std::vector<std::uint32_t> body_i_, body_j_;  // scratch of build_colouring()
  std::vector<std::uint8_t> serial_;
  std::vector<std::size_t> slot_;            // scratch of build_contacts(): per list entry
  std::vector<WallFeature<D>> features_;     // and per wall entry
  std::vector<PolyhedronContact> manifold_;  // polyhedra: per list entry (pairs, then walls)
  std::vector<Eigen::Matrix3d> inv_tensor_;  // polyhedra: AngularResponse::tensor, per grain
  AngularResponse turn_;                     // this step's (angular_response())
  bool polyhedra_checked_ = false;           // check_polyhedra_once() has passed
  int newton_iterations_ = 0;                // the fallback's steps in the last step (0: not used)
  GrainReorder<D> reorder_;
  WallTotals<D> wall_totals_;  // store_impulses()' exact sums
};

template <>
void CdSolver<2>::build_polyhedral_contacts();
template <>
void CdSolver<3>::build_polyhedral_contacts();
template <>
void CdSolver<2>::store_polyhedral_geometry();
template <>
void CdSolver<3>::store_polyhedral_geometry();
template <>
void CdSolver<2>::check_polyhedral_world() const;
template <>
void CdSolver<3>::check_polyhedral_world() const;

}  // namespace sable
