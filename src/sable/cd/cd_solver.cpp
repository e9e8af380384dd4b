#include "sable/cd/cd_solver.hpp"

#include "sable/cd/fc_newton.hpp"
#include "sable/cd/grain_delassus.hpp"

#include <fmt/format.h>

#include <cmath>

#include "sable/core/error.hpp"
#include "sable/core/parallel.hpp"
#include "sable/world/guards.hpp"

namespace sable {

// The grain problem seen by NLGS: U_a = frame_a^T (relative velocity at the contact point),
// computed from the grains' and walls' current velocities, which apply() keeps consistent with
// the impulses. Nothing is assembled beyond the diagonal blocks: memory O(contacts).
template <int D>
class CdSolver<D>::Problem {
 public:
  Problem(Contacts& c, ParticleStore<D>& p, std::vector<Wall<D>>& walls, std::vector<WallDof>& dofs,
          double h, double recovery, const cd::SweepColouring& colouring, AngularResponse turn)
      : c_(c),
        p_(p),
        walls_(walls),
        dofs_(dofs),
        inv_h_(1.0 / h),
        recovery_(recovery),
        colouring_(colouring),
        turn_(turn) {}
  const cd::SweepColouring& colouring() const { return colouring_; }
  std::size_t size() const { return c_.size(); }
  const LMat& W(std::size_t a) const { return c_.W[a]; }
  double mu(std::size_t a) const { return c_.mu[a]; }
  LVec& r(std::size_t a) { return c_.r[a]; }
  double q_norm() const { return q_norm_; }
  void set_q_norm(double q) { q_norm_ = q; }

  LVec velocity(std::size_t a) const {
    using S = Space<D>;
    const std::uint32_t i = c_.i[a], j = c_.partner[a];
    Vec vrel = p_.v[i] + S::spin_velocity(p_.omega[i], c_.arm_i[a]);
    if (c_.wall[a]) {
      // The wall's velocity at the contact point (its translation velocity unless it turns).
      const Wall<D>& wall = walls_[j];
      vrel -= wall.turning() ? wall.velocity_at(p_.x[i] + c_.arm_i[a]) : wall.velocity;
    } else {
      vrel -= p_.v[j] + S::spin_velocity(p_.omega[j], c_.arm_j[a]);
    }
    LVec u = c_.frame[a].transpose() * vrel;
    // An open gap may close; a share of an overlap is removed (CdSettings::overlap_recovery;
    // with none, the same bits as max(gap, 0) / h).
    const double g = c_.gap[a];
    u[0] += (g >= 0.0 ? g : recovery_ > 0.0 ? recovery_ * g : 0.0) * inv_h_;
    return u;
  }

  void apply(std::size_t a, const LVec& dr) {
    using S = Space<D>;
    c_.r[a] += dr;
    const Vec impulse = c_.frame[a] * dr;
    const std::uint32_t i = c_.i[a], j = c_.partner[a];
    // A fixed grain is not written: the coloured sweep lets contacts of one colour share it
    // (an update by zero leaves a finite velocity as it is).
    if (!p_.fixed(i)) {
      p_.v[i] += p_.inv_mass[i] * impulse;
      p_.omega[i] += turn_(i, S::moment(c_.arm_i[a], impulse));
    }
    if (!c_.wall[a]) {
      if (!p_.fixed(j)) {
        p_.v[j] -= p_.inv_mass[j] * impulse;
        p_.omega[j] -= turn_(j, S::moment(c_.arm_j[a], impulse));
      }
    } else if (j < dofs_.size() && dofs_[j].inv_mass > 0.0) {
      // A wall body takes the opposite impulse along its normal (its one degree of freedom;
      // the friction impulses, tangent to a plane wall, have no component there). The speed
      // cap makes W_aa (which counts 1/M) inexact while the wall is held at its cap, but not
      // the solution: a contact is solved when its local solve returns dr = 0 from the U it
      // sees, whatever W_aa; W_aa only sets how fast the sweeps get there.
      Wall<D>& wall = walls_[j];
      dofs_[j].impulse -= impulse.dot(wall.normal());
      wall.velocity = dofs_[j].speed() * wall.normal();
    }
  }

  // Rolling resistance, the rigid limit of contact/rolling.hpp: the couple m on grain i (an
  // impulse: couple times h) holds the relative rolling velocity at zero while
  // |m| <= mu_r R* r_N, and otherwise sits at that cap, against the rolling. Exact for one
  // contact: a round grain's inertia is isotropic, so the rolling velocity answers m along m
  // alone, with 1/I_i + 1/I_j. Called by NLGS after each update of the contact's impulse.
  void solve_extra(std::size_t a) {
    if (c_.m.empty()) return;
    const double compliance = rolling_compliance(a);
    if (compliance == 0.0) return;
    Rot m = c_.m[a] - rolling_velocity(a) / compliance;
    project_roll(m, c_.roll_mu[a] * c_.roll_r[a] * std::max(c_.r[a][0], 0.0));
    apply_couple(a, m - c_.m[a]);
  }

  // The couples' share of the natural-map residual (natural_map_error), in the impulses'
  // units: with the couple over the lever, m / R* (an impulse), and the rolling velocity times
  // it, R* omega_r (a velocity), the law reads F = m / R* - P(m / R* - R* omega_r) onto
  // |.| <= mu_r r_N, zero iff solved, as Coulomb's law reads r - P_K(r - U). Without it NLGS
  // could stop on converged impulses while couples still move.
  void extra_residual(std::size_t a, double& f2, double& r2, double& u2) const {
    using S = Space<D>;
    if (c_.m.empty()) return;
    const double lever = c_.roll_r[a];
    const Rot m = c_.m[a] / lever, u = rolling_velocity(a) * lever;
    Rot p = m - u;
    project_roll(p, c_.roll_mu[a] * std::max(c_.r[a][0], 0.0));
    f2 += S::rot_norm2(Rot(m - p));
    r2 += S::rot_norm2(m);
    u2 += S::rot_norm2(u);
  }

  // 1/I_i + 1/I_j (1/I_i against a wall): how the rolling velocity answers a couple.
  double rolling_compliance(std::size_t a) const {
    const std::uint32_t i = c_.i[a], j = c_.partner[a];
    return p_.inv_inertia[i] + (c_.wall[a] ? 0.0 : p_.inv_inertia[j]);
  }

  // The relative rolling velocity omega_i - omega_j (against a wall omega_i, less the wall's
  // spin if it turns), twist removed in 3D.
  Rot rolling_velocity(std::size_t a) const {
    const std::uint32_t i = c_.i[a], j = c_.partner[a];
    Rot spin_rel = p_.omega[i];
    if (!c_.wall[a])
      spin_rel -= p_.omega[j];
    else if (walls_[j].turning())
      spin_rel -= walls_[j].spin;
    if constexpr (D == 3) spin_rel -= spin_rel.dot(c_.frame[a].col(0)) * c_.frame[a].col(0);
    return spin_rel;
  }

  // m onto the disk |m| <= cap.
  static void project_roll(Rot& m, double cap) {
    const double m2 = Space<D>::rot_norm2(m);
    if (m2 > cap * cap) m *= cap / std::sqrt(m2);
  }

  // m_a += dm, and the grains' spins with it.
  void apply_couple(std::size_t a, const Rot& dm) {
    const std::uint32_t i = c_.i[a], j = c_.partner[a];
    c_.m[a] += dm;
    if (!p_.fixed(i)) p_.omega[i] += p_.inv_inertia[i] * dm;
    if (!c_.wall[a] && !p_.fixed(j)) p_.omega[j] -= p_.inv_inertia[j] * dm;
  }

 private:
  Contacts& c_;
  ParticleStore<D>& p_;
  std::vector<Wall<D>>& walls_;
  std::vector<WallDof>& dofs_;
  double inv_h_;
  double recovery_;
  const cd::SweepColouring& colouring_;
  AngularResponse turn_;
  double q_norm_ = 0.0;
};

template <int D>
void CdSolver<D>::Contacts::resize(std::size_t n, bool rolling) {
  i.resize(n);
  partner.resize(n);
  wall.resize(n);
  source.resize(n);
  frame.resize(n);
  arm_i.resize(n);
  arm_j.resize(n);
  W.resize(n);
  mu.resize(n);
  gap.resize(n);
  r.resize(n);
  roll_mu.resize(rolling ? n : 0);
  roll_r.resize(rolling ? n : 0);
  m.resize(rolling ? n : 0);
}

namespace {

// An orthonormal frame [n, t1 (, t2)] chosen deterministically from n alone.
template <int D>
cd::LMat<D> contact_frame(const typename Space<D>::Vec& n) {
  cd::LMat<D> f;
  f.col(0) = n;
  if constexpr (D == 2) {
    f.col(1) = Eigen::Vector2d(-n.y(), n.x());
  } else {
    int k = 0;  // the axis least aligned with n gives the best-conditioned cross product
    for (int a = 1; a < 3; ++a)
      if (std::abs(n[a]) < std::abs(n[k])) k = a;
    const Eigen::Vector3d t1 = n.cross(Eigen::Vector3d::Unit(k)).normalized();
    f.col(1) = t1;
    f.col(2) = n.cross(t1);
  }
  return f;
}

}  // namespace

template <int D>
void CdSolver<D>::initialize() {
  // The lists carry rolling couples exactly when the law has rolling resistance.
  world_.neighbors.rolling = world_.model.rolling != RollingModel::kNone;
  check_polyhedra_once();
  // The builds sort the grains into cell order when due (world/reorder.hpp), as in the DEM
  // solver. The contacts, and so the NLGS sweep, follow the list's order: a sort changes the
  // sweep's order, and with it the iterates, not the problem (the same contacts, impulses
  // carried with their pairs). The step keeps no per-grain state of its own to move.
  reorder_.build_lists(world_);
}

// One Moreau-Jean step:
//   free velocity   v_free = v + h M^-1 [(1 - theta) f(t) + theta f(t + h)]  (gravity here;
//                   a wall body's applied force: start_wall_bodies)
//   contacts        every candidate of the neighbour lists, frame and Delassus block at x(t)
//   impulses        NLGS: find r with U = W r + q satisfying Signorini-Coulomb, where the
//                   normal velocity is U_N + max(gap, 0) / h (a grain may close an open gap
//                   within the step, never cross it), warm-started from the last step
//   positions       x(t + h) = x(t) + h v(t + h), from the new velocities (walls alike)
template <int D>
void CdSolver<D>::step() {
  using S = Space<D>;
  const double h = world_.dt;
  auto& p = world_.particles;
  check_polyhedra_once();  // a resumed run steps without initialize()
  {
    auto scope = timers_.time(Phase::kIntegrate);
    // Gravity is constant, so the theta weighting of smooth forces leaves h g.
    for (std::size_t k = 0; k < p.size(); ++k)
      if (p.inv_mass[k] != 0.0) p.v[k] += h * world_.gravity;
    start_wall_bodies();
  }
  {
    auto scope = timers_.time(Phase::kNeighbors);
    // Contacts that can close during this step must be candidates now.
    if (world_.neighbors.needs_rebuild(p, world_.walls, 2.0 * h * max_speed()))
      reorder_.build_lists(world_);
  }
  {
    auto scope = timers_.time(Phase::kContactBuild);
    turn_ = angular_response();
    build_contacts();
    if (s_.nlgs.order == cd::SweepOrder::kColoured) build_colouring();
  }
  {
    auto scope = timers_.time(Phase::kNlgsSolve);
    Problem problem(c_, p, world_.walls, dofs_, h, s_.overlap_recovery, colouring_, turn_);
    double q2 = 0.0;
    q_.resize(c_.size());
    for (std::size_t a = 0; a < c_.size(); ++a) {
      q_[a] = problem.velocity(a);
      q2 += q_[a].squaredNorm();
    }
    problem.set_q_norm(std::sqrt(q2));
    // Warm start: the impulses found at build (last step's, in the new frames) act at once.
    for (std::size_t a = 0; a < c_.size(); ++a) {
      const LVec r0 = c_.r[a];
      c_.r[a].setZero();
      if (r0.squaredNorm() > 0.0) problem.apply(a, r0);
    }
    for (std::size_t a = 0; a < c_.m.size(); ++a) {
      const Rot m0 = c_.m[a];
      c_.m[a] = S::zero_rot();
      problem.apply_couple(a, m0);
    }
    // Without the fallback nothing takes over at a stagnation: the sweeps go on to their cap,
    // as they always did (the same bits).
    cd::NlgsSettings nlgs = s_.nlgs;
    if (!newton_applies()) nlgs.stagnation_window = 0;
    result_ = cd::solve_nlgs<D>(problem, nlgs, world_.rng);
    newton_iterations_ = 0;
    if (!result_.converged && std::isfinite(result_.residual) && newton_applies())
      newton_fallback(problem);
  }
  if (!std::isfinite(result_.residual)) {
    check_grain_states(world_);  // names the first grain the non-finite impulses reached
    throw SimulationError(fmt::format(
        "step {}: the contact solver's residual is {} after {} sweeps: a contact's data is not "
        "finite (two grains at one position, or a mass, radius or position that is not a "
        "usable number)",
        world_.step, result_.residual, result_.iterations));
  }
  store_impulses();
  if (!world_.shapes.empty()) store_polyhedral_geometry();
  {
    auto scope = timers_.time(Phase::kIntegrate);
    drift(h);
    for (auto& wall : world_.walls) wall.advance(h);
  }
  world_.time += h;
  ++world_.step;
  diag_.iterations = result_.iterations;
  diag_.residual = result_.residual;
  diag_.converged = result_.converged;
  check_grain_states(world_);
}

// Positions from the end-of-step velocities. A polyhedral grain turns freely over the step
// (core/rigid_rotation.hpp: its angular momentum kept, its angular velocity turning with it),
// whatever track_orientation says: its orientation enters its contacts.
template <int D>
void CdSolver<D>::drift(double h) {
  using S = Space<D>;
  auto& p = world_.particles;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (p.inv_mass[k] == 0.0) continue;
    p.x[k] += h * p.v[k];
    if constexpr (D == 3) {
      if (p.polyhedron(k)) {
        free_rotation(p.q[k], p.omega[k], world_.shapes[p.shape_index[k]].moments(p.mass[k]), h);
        continue;
      }
    }
    if (world_.track_orientation) p.q[k] = S::rotate(p.q[k], p.omega[k], h);
  }
}

// The step's AngularResponse: the scalar inverse inertia, or with polyhedral grains each
// grain's tensor at its current orientation (a fixed grain's zero, a round one's isotropic).
template <int D>
typename CdSolver<D>::AngularResponse CdSolver<D>::angular_response() {
  const auto& p = world_.particles;
  AngularResponse r{p.inv_inertia.data(), nullptr};
  if constexpr (D == 3) {
    if (world_.shapes.empty()) return r;
    inv_tensor_.resize(p.size());
    for (std::size_t k = 0; k < p.size(); ++k) {
      if (p.inv_inertia[k] == 0.0 || !p.polyhedron(k)) {
        inv_tensor_[k] = p.inv_inertia[k] * Eigen::Matrix3d::Identity();
        continue;
      }
      const Eigen::Vector3d inv = world_.shapes[p.shape_index[k]].moments(p.mass[k]).cwiseInverse();
      inv_tensor_[k] = world_inverse_inertia(p.q[k], inv);
    }
    r.tensor = inv_tensor_.data();
  }
  return r;
}

// Where the NLGS stopped short (stagnating, or its sweeps spent): the semismooth Newton on the
// assembled problem, from r = 0 (from the NLGS's stalled iterate it tends to stall too:
// docs/contact-dynamics.md). Its answer replaces the NLGS's only if its residual, recomputed
// through the grains' velocities, is lower; the grains then carry its impulses.
template <int D>
bool CdSolver<D>::newton_applies() const {
  const bool bodies =
      std::any_of(dofs_.begin(), dofs_.end(), [](const WallDof& d) { return d.inv_mass > 0.0; });
  return s_.newton_iterations > 0 && !bodies && c_.m.empty() && world_.shapes.empty() &&
         s_.nlgs.criterion == cd::Criterion::kNatural;
}

template <int D>
void CdSolver<D>::newton_fallback(Problem& problem) {
  cd::MatrixProblem<D> mp = cd::assemble_grain_problem<D>(c_, world_.particles, q_);
  const cd::NewtonResult nr = cd::solve_newton_ac<D>(
      mp, {.tolerance = s_.nlgs.tolerance, .max_iterations = s_.newton_iterations});
  newton_iterations_ = nr.iterations;
  if (!(nr.residual < result_.residual)) return;
  const std::vector<LVec> kept(c_.r.begin(), c_.r.end());
  for (std::size_t a = 0; a < c_.size(); ++a) problem.apply(a, mp.r(a) - c_.r[a]);
  const double e = cd::natural_map_error<D>(problem);
  if (!(e < result_.residual)) {  // round-off made it no better: back to the NLGS's
    for (std::size_t a = 0; a < c_.size(); ++a) problem.apply(a, kept[a] - c_.r[a]);
    return;
  }
  result_.residual = result_.error = e;
  result_.converged = e <= s_.nlgs.tolerance;
}

template <int D>
void CdSolver<D>::set_wall_bodies(const std::vector<WallBody>& bodies) {
  dofs_.assign(bodies.empty() ? 0 : world_.walls.size(), WallDof{});
  for (const WallBody& b : bodies) {
    if (b.wall >= world_.walls.size() || !world_.walls[b.wall].plane() || !(b.mass > 0.0))
      throw InputError(fmt::format(
          "wall body {}: a plane wall with a mass > 0 is needed (mass {} kg)", b.wall, b.mass));
    WallDof& d = dofs_[b.wall];
    d.inv_mass = 1.0 / b.mass;
    d.force = b.force;
    if (b.max_speed > 0.0) d.max_speed = b.max_speed;
  }
}

// The free velocity of each wall body, u(t) + h F / M (a constant force: theta drops out; the
// wall is weightless, so F alone sets its stress), and its velocity before any impulse. Only
// the normal component of a body's velocity survives: that is its degree of freedom.
template <int D>
void CdSolver<D>::start_wall_bodies() {
  for (std::size_t k = 0; k < dofs_.size(); ++k) {
    WallDof& d = dofs_[k];
    if (d.inv_mass == 0.0) continue;
    Wall<D>& wall = world_.walls[k];
    d.free_speed = wall.velocity.dot(wall.normal()) + world_.dt * d.force * d.inv_mass;
    d.impulse = 0.0;
    wall.velocity = d.speed() * wall.normal();
  }
}

template <int D>
double CdSolver<D>::max_speed() const {
  const auto& p = world_.particles;
  double vmax = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k)
    vmax = std::max(vmax, p.v[k].norm() + p.radius[k] * std::sqrt(Space<D>::rot_norm2(p.omega[k])));
  return vmax;
}

template <int D>
template <bool kWall>
void CdSolver<D>::set_contact(std::size_t a, std::uint32_t i, std::uint32_t partner,
                              std::uint32_t source, const Vec& n, double gap, const Vec& arm_i,
                              const Vec& arm_j, const PairParams& pp, const Vec& force,
                              const Rot& couple) {
  using S = Space<D>;
  const auto& p = world_.particles;
  const LMat frame = contact_frame<D>(n);
  // Delassus block, column by column: the relative velocity change per unit local impulse.
  LMat W;
  for (int c = 0; c < D; ++c) {
    const Vec P = frame.col(c);
    Vec dv = p.inv_mass[i] * P + S::spin_velocity(turn_(i, S::moment(arm_i, P)), arm_i);
    if constexpr (!kWall)
      dv += p.inv_mass[partner] * P + S::spin_velocity(turn_(partner, S::moment(arm_j, P)), arm_j);
    if constexpr (kWall) {
      if (is_body(partner)) {  // a wall body recoils along its normal only
        const Vec nw = world_.walls[partner].normal();
        dv += dofs_[partner].inv_mass * nw.dot(P) * nw;
      }
    }
    W.col(c) = frame.transpose() * dv;
  }
  c_.i[a] = i;
  c_.partner[a] = partner;
  c_.wall[a] = kWall ? 1 : 0;
  c_.source[a] = source;
  c_.frame[a] = frame;
  c_.arm_i[a] = arm_i;
  c_.arm_j[a] = arm_j;
  c_.W[a] = W;
  c_.mu[a] = pp.friction;
  c_.gap[a] = gap;
  c_.r[a] = s_.warm_start ? LVec(frame.transpose() * force * world_.dt) : LVec::Zero();
  if (world_.model.rolling == RollingModel::kNone) return;
  const double r_i = p.radius[i];
  const double r_eff = kWall ? r_i : r_i * p.radius[partner] / (r_i + p.radius[partner]);
  c_.roll_mu[a] = pp.rolling_friction;
  c_.roll_r[a] = r_eff;
  Rot m = s_.warm_start ? Rot(couple * world_.dt) : S::zero_rot();
  if constexpr (D == 3) m -= m.dot(n) * n;  // last step's couple, in the new tangent plane
  c_.m[a] = m;
}

// The problem holds the candidates whose gap can close within the step: gap <= 2 h v_max,
// v_max the largest grain speed (rotation included) after the free flight, doubled because
// impulses can speed grains up during the solve. Far-open candidates would only add
// unknowns that stay zero, and their large gap/h would dilute the convergence measures.
// Two passes over the lists' entries, each shared among the threads: which entries join
// (and the wall entries' features), then, after a prefix sum gives each joining entry its
// slot, the contacts themselves. The contacts follow the lists' order on any thread count.
template <int D>
void CdSolver<D>::build_contacts() {
  using S = Space<D>;
  const auto& p = world_.particles;
  auto& pl = world_.neighbors.pairs;
  auto& wl = world_.neighbors.wall_pairs;
  if constexpr (D == 3) {
    if (!world_.shapes.empty()) return build_polyhedral_contacts();
  }
  const double reach = 2.0 * world_.dt * max_speed();
  // Rolling resistance: the lists' `roll` slots (one per entry, kept by build() and
  // load_snapshot()) hold each contact's couple (N m) on its grain i, for the warm start and
  // the outputs (DEM keeps its rolling spring there).
  const bool rolling = world_.model.rolling != RollingModel::kNone;
  const auto np = static_cast<std::ptrdiff_t>(pl.size()),
             nw = static_cast<std::ptrdiff_t>(wl.size());
  slot_.resize(static_cast<std::size_t>(np + nw) + 1);
  features_.resize(static_cast<std::size_t>(nw));
#pragma omp parallel for schedule(static) if (np >= kMinParallelItems)
  for (std::ptrdiff_t k = 0; k < np; ++k) {
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    // Not (gap > reach): a non-finite gap joins, and the solve reports it.
    const bool joins = !((p.x[i] - p.x[j]).norm() - p.radius[i] - p.radius[j] > reach);
    slot_[k] = joins ? 1 : 0;
    if (joins) continue;
    pl.force[k].setZero();
    if (rolling) pl.roll[k] = S::zero_rot();
  }
  // A wall entry is (grain, wall, element): the feature its element answers for
  // (geometry/walls.hpp; for a plane or a cylinder, element 0 is the whole surface), skipped
  // when another element's entry holds the nearest feature.
#pragma omp parallel for schedule(static) if (nw >= kMinParallelItems)
  for (std::ptrdiff_t k = 0; k < nw; ++k) {
    const std::uint32_t i = wl.i[k];
    const WallFeature<D> f = world_.walls[wl.wall[k]].contact(p.x[i], wl.element[k]);
    const bool joins =
        f.active &&
        !(f.dist - p.radius[i] > reach + world_.dt * wall_speed(wl.wall[k], p.x[i], p.radius[i]));
    slot_[np + k] = joins ? 1 : 0;
    features_[k] = f;
    if (joins) {
      wl.feature[k] = f.feature;
      continue;
    }
    wl.force[k].setZero();
    if (rolling) wl.roll[k] = S::zero_rot();
  }
  c_.resize(first_contacts(), rolling);  // slot_[k]: the contact of entry k if it joins
#pragma omp parallel for schedule(static) if (np >= kMinParallelItems)
  for (std::ptrdiff_t k = 0; k < np; ++k) {
    if (slot_[k + 1] == slot_[k]) continue;
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    const Vec d = p.x[i] - p.x[j];
    const double dist = d.norm();
    const Vec n = d / dist;
    set_contact<false>(slot_[k], i, j, static_cast<std::uint32_t>(k), n,
                       dist - p.radius[i] - p.radius[j], -p.radius[i] * n, p.radius[j] * n,
                       world_.materials.pair(p.material[i], p.material[j]), pl.force[k],
                       rolling ? pl.roll[k] : S::zero_rot());
  }
#pragma omp parallel for schedule(static) if (nw >= kMinParallelItems)
  for (std::ptrdiff_t k = 0; k < nw; ++k) {
    if (slot_[np + k + 1] == slot_[np + k]) continue;
    const std::uint32_t i = wl.i[k];
    const WallFeature<D>& f = features_[k];
    set_contact<true>(slot_[np + k], i, wl.wall[k], static_cast<std::uint32_t>(k), f.n,
                      f.dist - p.radius[i], -p.radius[i] * f.n, Vec::Zero(),
                      world_.materials.pair(p.material[i], world_.walls[wl.wall[k]].material),
                      wl.force[k], rolling ? wl.roll[k] : S::zero_rot());
  }
}

template <int D>
std::size_t CdSolver<D>::first_contacts() {
  slot_.back() = 0;
  std::size_t count = 0;
  for (std::size_t& s : slot_) {
    const std::size_t contacts = s;
    s = count;
    count += contacts;
  }
  return count;
}

// The bodies each contact updates: its grains unless fixed (walls take no update, but a wall
// body takes every impulse of its contacts: those run in the serial tail).
template <int D>
void CdSolver<D>::build_colouring() {
  const auto& p = world_.particles;
  constexpr std::uint32_t kNone = cd::SweepColouring::kNoBody;
  const std::size_t n = c_.size();
  body_i_.resize(n);
  body_j_.resize(n);
  serial_.resize(n);
  for (std::size_t a = 0; a < n; ++a) {
    const std::uint32_t i = c_.i[a], j = c_.partner[a];
    body_i_[a] = p.fixed(i) ? kNone : i;
    body_j_[a] = c_.wall[a] || p.fixed(j) ? kNone : j;
    serial_[a] = c_.wall[a] && is_body(j) ? 1 : 0;
  }
  colouring_.build(body_i_, body_j_, serial_, p.size(), s_.colour_block);
}

// How fast wall w's surface can move near a grain centre x during the step: a wall body's
// speed can change during the solve, up to its cap; a turning wall's, at the contact point of
// a grain of `radius` at x, is at most its speed at x plus the spin times the radius.
template <int D>
double CdSolver<D>::wall_speed(std::uint32_t w, const Vec& x, double radius) const {
  const Wall<D>& wall = world_.walls[w];
  if (is_body(w) && std::isfinite(dofs_[w].max_speed)) return dofs_[w].max_speed;
  if (!wall.turning()) return wall.velocity.norm();
  return wall.velocity_at(x).norm() + std::sqrt(Space<D>::rot_norm2(wall.spin)) * radius;
}

// Forces = impulses / h, written where DEM writes its forces, so outputs are shared (a mesh's
// force per element among them: world/element_forces.hpp). Each wall's force and its torque
// about its pivot (the force -f at the contact point x_i + arm_i, x_i - R_i n, and the
// reaction to each rolling couple), summed exactly as the DEM's total_wall_forces() sums them.
template <int D>
void CdSolver<D>::store_impulses() {
  using S = Space<D>;
  auto& p = world_.particles;
  auto& nl = world_.neighbors;
  for (std::size_t k = 0; k < p.size(); ++k) {
    p.f[k].setZero();
    p.t[k] = S::zero_rot();
  }
  wall_totals_.reset(world_.walls.size());
  diag_.touching = 0;
  diag_.max_overlap_ratio = 0.0;
  for (std::size_t a = 0; a < c_.size(); ++a) {
    const Vec f = c_.frame[a] * c_.r[a] / world_.dt;
    const std::uint32_t i = c_.i[a], j = c_.partner[a];
    if (f.squaredNorm() > 0.0) ++diag_.touching;
    p.f[i] += f;
    p.t[i] += S::moment(c_.arm_i[a], f);
    // A polyhedral pair's manifold is several contacts of one list entry, in a row: the
    // entry's force is their sum (a round grain's entry has one).
    const bool first = a == 0 || c_.source[a - 1] != c_.source[a] || c_.wall[a - 1] != c_.wall[a];
    if (c_.wall[a]) {
      Vec& entry = nl.wall_pairs.force[c_.source[a]];
      entry = first ? f : Vec(entry + f);
      wall_totals_.add_force(j, -f);
      wall_totals_.add_torque(j, -S::moment(Vec(p.x[i] + c_.arm_i[a] - world_.walls[j].pivot), f));
    } else {
      Vec& entry = nl.pairs.force[c_.source[a]];
      entry = first ? f : Vec(entry + f);
      p.f[j] -= f;
      p.t[j] -= S::moment(c_.arm_j[a], f);
    }
    if (!c_.m.empty()) {
      const Rot couple = c_.m[a] / world_.dt;
      p.t[i] += couple;
      if (c_.wall[a]) {
        nl.wall_pairs.roll[c_.source[a]] = couple;
        wall_totals_.add_torque(j, -couple);
      } else {
        nl.pairs.roll[c_.source[a]] = couple;
        p.t[j] -= couple;
      }
    }
    const double r_min = c_.wall[a] ? p.radius[i] : std::min(p.radius[i], p.radius[j]);
    diag_.max_overlap_ratio = std::max(diag_.max_overlap_ratio, -c_.gap[a] / r_min);
  }
  wall_totals_.store(world_.walls);
}

template <int D>
std::vector<std::string> CdSolver<D>::diagnostic_columns() const {
  return {"nlgs_contacts", "nlgs_iterations", "nlgs_residual", "newton_iterations"};
}

template <int D>
void CdSolver<D>::diagnostic_values(std::vector<double>& row) const {
  row.push_back(static_cast<double>(c_.size()));
  row.push_back(static_cast<double>(result_.iterations));
  row.push_back(result_.residual);
  row.push_back(static_cast<double>(newton_iterations_));
}

template class CdSolver<2>;
template class CdSolver<3>;
// For cd_polyhedra.cpp, whose contacts are made by the same function.
template void CdSolver<3>::set_contact<false>(std::size_t, std::uint32_t, std::uint32_t,
                                              std::uint32_t, const Eigen::Vector3d&, double,
                                              const Eigen::Vector3d&, const Eigen::Vector3d&,
                                              const PairParams&, const Eigen::Vector3d&,
                                              const Eigen::Vector3d&);
template void CdSolver<3>::set_contact<true>(std::size_t, std::uint32_t, std::uint32_t,
                                             std::uint32_t, const Eigen::Vector3d&, double,
                                             const Eigen::Vector3d&, const Eigen::Vector3d&,
                                             const PairParams&, const Eigen::Vector3d&,
                                             const Eigen::Vector3d&);

}  // namespace sable
