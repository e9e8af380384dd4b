// The DEM's grain-wall contacts: each grain's in its closing (dem/grain_loops_impl.hpp),
// and each wall's total force and torque once every contact's force is final.
//
// A plane or a cylinder has one list entry per (grain, wall). A mesh has one per (grain,
// wall, element) within reach, and its contacts are resolved together (mesh_contacts): each
// entry answers for the feature its element owns (geometry/mesh_wall.hpp), and when a grain
// slides from one feature to the next (face to face across a flat edge, face to edge on a
// faceted cylinder) the tangential history of the contact that ended moves to the one that
// began, as it would stay on a smooth surface.
#pragma once

#include <algorithm>
#include <array>

#include "sable/dem/dem_solver.hpp"

namespace sable {

// Grains [g0, g1)'s wall contacts (their wall pairs are one run of the list, by wall and
// element within each grain).
template <int D, class Laws>
template <class Normal>
void DemSolver<D, Laws>::wall_contacts(std::uint32_t g0, std::uint32_t g1, double& max_ratio,
                                       std::size_t& touching) {
  const auto& wl = world_.neighbors.wall_pairs;
  const std::uint32_t* const wb = world_.neighbors.wall_begin.data();
  const std::uint32_t end = wb[g1];
  const EntryWalk walk = entry_walk();
  for (std::uint32_t k = walk.first(wb[g0]); k < end;) {
    const Wall<D>& wall = world_.walls[wl.wall[k]];
    if (!wall.is_mesh()) {
      const WallFeature<D> f = wall.contact(world_.particles.x[wl.i[k]], 0);
      wall_contact<Normal>(k, wall, f, max_ratio, touching);
      k = walk.next(k);
      continue;
    }
    std::uint32_t k1 = walk.next(k);
    while (k1 < end && wl.i[k1] == wl.i[k] && wl.wall[k1] == wl.wall[k]) k1 = walk.next(k1);
    mesh_contacts<Normal>(k, k1, wall, max_ratio, touching);
    k = k1;
  }
}

// A grain's entries [k0, k1) with one mesh: the features their elements answer for, the
// history handed from the contacts that ended to those that began, then each contact's force.
// A grain touches a mesh at a few features at once; the hand-over keeps the first
// kMaxHandOver ended contacts' histories (more would only be lost, not mixed up).
template <int D, class Laws>
template <class Normal>
void DemSolver<D, Laws>::mesh_contacts(std::uint32_t k0, std::uint32_t k1, const Wall<D>& wall,
                                       double& max_ratio, std::size_t& touching) {
  using Vec = typename Space<D>::Vec;
  using Rot = typename Space<D>::Rot;
  constexpr std::size_t kMaxHandOver = 8;
  auto& wl = world_.neighbors.wall_pairs;
  const auto& p = world_.particles;
  const std::uint32_t i = wl.i[k0];
  const bool rolling = with_rolling();
  std::array<Vec, kMaxHandOver> shear;
  std::array<Rot, kMaxHandOver> roll;
  std::size_t ended = 0, taken = 0;
  const MeshShape<D>& mesh = *wall.mesh();
  // Per entry: kTouches, its element holds a touching feature now; kBegins, that contact is
  // new (it takes an ended contact's history). Most entries are elements near a grain but
  // not under it: they cost the bounds test and, when they held nothing, no more.
  constexpr std::uint8_t kTouches = 1, kBegins = 2;
  const Vec x = p.x[i];
  const double r = p.radius[i];
  // The grain's distance from its place at the last remake, or -1 while the mesh moves.
  const double moved = mesh_still_[wl.wall[k0]] ? (x - mesh_x_ref_[i]).norm() : -1.0;
  // Round-off of the values at either place (sums of products of size |x| + r), and tol_.
  const double slack = mesh.tolerance() + 1e-13 * (3.0 * x.cwiseAbs().maxCoeff() + r);
  const EntryWalk walk = entry_walk();
  for (std::uint32_t k = k0; k < k1; k = walk.next(k)) {
    const WallFeature<D> f = mesh_feature(k, wall, x, r, moved, slack);
    const bool now = f.active && f.dist < r;
    if (!now && wall_delta_[k] == 0.0) {  // apart, and was
      hand_over_[k] = 0;
      continue;
    }
    if (now) feature_[k] = f;
    const bool had =
        wall_delta_[k] != 0.0 && (wl.force[k] != Vec::Zero() || wl.shear[k] != Vec::Zero());
    std::uint8_t flags = now ? kTouches : 0;
    if (had && (!now || wl.feature[k] != f.feature)) {
      if (ended < kMaxHandOver) {
        shear[ended] = wl.shear[k];
        roll[ended++] = rolling ? wl.roll[k] : Space<D>::zero_rot();
      }
      wl.shear[k].setZero();
      if (rolling) wl.roll[k] = Space<D>::zero_rot();
      wall_delta_[k] = -1.0;  // the force it still holds is cleared below unless it touches
      if (now) flags |= kBegins;
    } else if (now && !had) {
      flags |= kBegins;
    }
    if (now) wl.feature[k] = f.feature;
    hand_over_[k] = flags;
  }
  WallFeature<D> none;
  none.active = false;
  for (std::uint32_t k = k0; k < k1; k = walk.next(k)) {
    const std::uint8_t flags = hand_over_[k];
    if (!(flags & kTouches)) {
      if (wall_delta_[k] != 0.0) wall_contact<Normal>(k, wall, none, max_ratio, touching);
      continue;
    }
    if ((flags & kBegins) && taken < ended) {
      wl.shear[k] = shear[taken];
      if (rolling) wl.roll[k] = roll[taken];
      ++taken;
    }
    wall_contact<Normal>(k, wall, feature_[k], max_ratio, touching);
  }
}

// The mesh entries that cannot touch before the next remake, and the bounds of the others
// (mesh_reach_): made at each near-list remake, and again when a mesh has moved half the
// inner skin since (a driven mesh, whose bounds do not apply while it moves).
template <int D, class Laws>
void DemSolver<D, Laws>::update_mesh_reach(bool remade) {
  const auto& nl = world_.neighbors;
  const auto& wl = nl.wall_pairs;
  const auto& walls = world_.walls;
  // Per mesh, how far it moved since the last remake: 0 keeps its bounds, half the inner skin
  // makes the next remake due.
  bool due = remade || mesh_reach_.size() != wl.size() || mesh_reach_point_.size() != walls.size();
  mesh_still_.assign(walls.size(), 0);
  for (std::size_t w = 0; w < walls.size() && !due; ++w) {
    if (!walls[w].is_mesh()) continue;
    const double shift =
        walls[w].moved_since(mesh_reach_point_[w], mesh_reach_turn_[w], nl.domain_lo, nl.domain_hi);
    due = 2.0 * shift >= mesh_reach_skin_;
    mesh_still_[w] = shift == 0.0 ? 1 : 0;
  }
  if (due) {
    mesh_reach_skin_ = near_.skin;  // infinite in wet runs: every entry is tested
    mesh_reach_point_.resize(walls.size());
    mesh_reach_turn_.resize(walls.size());
    for (std::size_t w = 0; w < walls.size(); ++w) {
      mesh_reach_point_[w] = walls[w].point;
      mesh_reach_turn_[w] = walls[w].orientation;
    }
    const auto& p = world_.particles;
    mesh_x_ref_ = p.x;
    assign_ahead(mesh_reach_, wl.size(), kFar);
    mesh_near_ref_.clear();
    for (std::size_t k = 0; k < wl.size(); ++k) {
      const MeshShape<D>* mesh = walls[wl.wall[k]].mesh();
      const std::uint32_t i = wl.i[k];
      if (!mesh || !mesh->may_touch(p.x[i], p.radius[i] + mesh_reach_skin_, wl.element[k]))
        continue;
      mesh_reach_[k] = static_cast<std::uint32_t>(mesh_near_ref_.size());
      mesh_near_ref_.push_back({mesh->reach_values(p.x[i], wl.element[k]), p.x[i], -1.0});
    }
    mesh_still_.assign(walls.size(), 1);  // every pose is the reference now
    skip_far_entries();
  }
}

// wall_from_ for the entries update_mesh_reach() just sorted: the step's loops visit every
// plane, box and cylinder entry and every mesh entry within reach, and skip the far ones.
// A far entry cannot touch before the next remake; the apart state it is left in is the one
// mesh_contacts would have given it (an overlap unknown since a rebuild, -1, with no force
// and no history: cleared), so the bits are those of visiting it. A far entry that still
// holds a contact's force or history (it cannot, having been within r a step ago, unless the
// skin is below a step's motion) is visited, and its contact ends there as it would.
template <int D, class Laws>
void DemSolver<D, Laws>::skip_far_entries() {
  using S = Space<D>;
  const auto& wl = world_.neighbors.wall_pairs;
  const auto& walls = world_.walls;
  const auto n = static_cast<std::uint32_t>(wl.size());
  assign_ahead(wall_from_, n + 1, n);
  std::uint32_t next = n;
  for (std::uint32_t k = n; k-- > 0;) {
    const bool far = mesh_reach_[k] == kFar && walls[wl.wall[k]].is_mesh() &&
                     wall_delta_[k] <= 0.0 && wl.force[k] == S::zero() && wl.shear[k] == S::zero();
    if (far) end_wall_contact(k);  // cleared as mesh_contacts would have
    if (!far) next = k;
    wall_from_[k] = next;
  }
}

// The feature mesh entry k's element answers for at grain centre x (inactive where none):
// the exact test (may_touch, then the feature regions) unless, the mesh still since the
// last remake (`moved` >= 0: the grain's distance from its place then), the bound of the
// remake's values rejects the element, or the last inactive answer holds (x within its
// margin of where it was found). Both skip only what the exact test rejects.
template <int D, class Laws>
WallFeature<D> DemSolver<D, Laws>::mesh_feature(std::uint32_t k, const Wall<D>& wall,
                                                const typename Space<D>::Vec& x, double r,
                                                double moved, double slack) {
  const MeshShape<D>& mesh = *wall.mesh();
  const std::uint32_t e = world_.neighbors.wall_pairs.element[k];
  const std::uint32_t q = mesh_reach_[k];
  WallFeature<D> f;
  f.active = false;
  if (q == kFar || moved < 0.0) {
    if (mesh.may_touch(x, r, e)) f = mesh.contact(wall.point, x, e);
    return f;
  }
  MeshNearRef& ref = mesh_near_ref_[q];
  if (!MeshShape<D>::may_touch_within(ref.values, moved, r, slack)) return f;
  if (ref.margin > (x - ref.x).norm() + slack) return f;
  if (!mesh.may_touch(x, r, e)) return f;
  double margin = 0.0;
  f = mesh.contact(wall.point, x, e, margin);
  ref.x = x;
  ref.margin = f.active ? -1.0 : margin;
  return f;
}

// Wall pair k apart: a contact that held (overlap != 0) loses its force, history and rolling
// spring; one already apart is left alone.
template <int D, class Laws>
void DemSolver<D, Laws>::end_wall_contact(std::size_t k) {
  using S = Space<D>;
  auto& wl = world_.neighbors.wall_pairs;
  if (with_rolling() && wall_delta_[k] != 0.0) {
    wl.roll[k] = S::zero_rot();
    wall_roll_[k] = S::zero_rot();
  }
  dem_detail::forget_if_ended(wl.shear.data(), wl.force.data(), wall_moment_.data(),
                              wall_delta_.data(), k, S::zero_rot());
}

// Wall pair k's contact, at the feature f of its wall: its force on the grain, n x F and
// overlap stored in its slots (for the grain's sum), and its rolling couple; raises max_ratio
// to the overlap over the radius.
template <int D, class Laws>
template <class Normal>
void DemSolver<D, Laws>::wall_contact(std::size_t k, const Wall<D>& wall, const WallFeature<D>& f,
                                      double& max_ratio, std::size_t& touching) {
  using S = Space<D>;
  const auto& p = world_.particles;
  auto& wl = world_.neighbors.wall_pairs;
  const bool rolling = with_rolling();
  const std::uint32_t i = wl.i[k];
  ContactGeometry<D> g;
  g.n = f.n;
  g.delta = p.radius[i] - f.dist;
  if (!f.active || g.delta <= 0.0) {
    end_wall_contact(k);
    return;
  }
  // The lever arm is -(R_i - delta/2) n (see PairPass::touch); a turning wall's velocity is
  // taken at the contact point.
  const double arm = p.radius[i] - 0.5 * g.delta;
  const typename S::Vec v_wall =
      wall.turning() ? wall.velocity_at(p.x[i] - arm * g.n) : wall.velocity;
  g.vrel = p.v[i] - v_wall - S::spin_velocity(arm * p.omega[i], g.n);
  g.r_eff = p.radius[i];
  g.m_eff = p.mass[i];
  const PairParams& pp = world_.materials.pair(p.material[i], wall.material);
  const typename S::Vec force =
      contact_force<D, Normal>(g, pp, world_.model, world_.dt, wl.shear[k]);
  wl.force[k] = force;
  wall_moment_[k] = S::moment(g.n, force);
  wall_delta_[k] = g.delta;
  if (rolling)  // the relative spin: the grain's less the wall's
    wall_roll_[k] = rolling_couple<D, Normal>(
        g, pp, world_.model, world_.dt, force,
        wall.turning() ? typename S::Rot(p.omega[i] - wall.spin) : p.omega[i], roll_inv_ic_[i], 0.0,
        wl.roll[k]);
  max_ratio = std::max(max_ratio, g.delta / p.radius[i]);
  ++touching;
}

// Stage total_wall_forces (printed "closing"): each wall's total force and torque about its
// pivot, its contacts' forces summed exactly (world/wall_totals.hpp: the same bits in any
// order, on any number of threads or processes), once every contact's force is final (a
// mesh's force per element is derived from them when written: world/element_forces.hpp).
// Contact point x_c = x_i - (R_i - delta/2) n, so the torque of -F there is
// -(x_i - pivot) x F + (R_i - delta/2) n x F; with rolling resistance the wall also takes
// minus each rolling couple (as contact dynamics counts it).
template <int D, class Laws>
void DemSolver<D, Laws>::total_wall_forces() {
  using S = Space<D>;
  using Vec = typename S::Vec;
  using Rot = typename S::Rot;
  const auto& wl = world_.neighbors.wall_pairs;
  const auto& p = world_.particles;
  const bool rolling = with_rolling();
  const std::size_t walls = world_.walls.size();
  // The touching entries by wall (a counting sort; their order within a wall does not matter,
  // the sums being exact), so that each wall's sums run in registers (ExactRun).
  by_wall_begin_.assign(walls + 1, 0);
  const EntryWalk walk = entry_walk();
  const auto n = static_cast<std::uint32_t>(wl.size());
  // An entry apart holds no force (forget_if_ended clears it as its overlap turns 0).
  for (std::uint32_t k = walk.first(0); k < n; k = walk.next(k))
    if (wall_delta_[k] != 0.0) ++by_wall_begin_[wl.wall[k] + 1];
  for (std::size_t w = 0; w < walls; ++w) by_wall_begin_[w + 1] += by_wall_begin_[w];
  by_wall_.resize(by_wall_begin_[walls]);
  by_wall_fill_.assign(by_wall_begin_.begin(), by_wall_begin_.end() - 1);
  for (std::uint32_t k = walk.first(0); k < n; k = walk.next(k))
    if (wall_delta_[k] != 0.0) by_wall_[by_wall_fill_[wl.wall[k]]++] = k;

  // Each entry's torque about its wall's pivot, then each component of each wall's totals
  // in a loop of its own: one ExactRun at a time stays in registers.
  by_wall_torque_.resize(by_wall_.size());
  for (std::size_t w = 0; w < walls; ++w) {
    const Vec pivot = world_.walls[w].pivot;
    for (std::uint32_t e = by_wall_begin_[w]; e < by_wall_begin_[w + 1]; ++e) {
      const std::uint32_t k = by_wall_[e];
      const std::uint32_t i = wl.i[k];
      Rot t = S::zero_rot();  // an overlap unknown (-1) counts in the force only
      if (wall_delta_[k] > 0.0) {
        t = (p.radius[i] - 0.5 * wall_delta_[k]) * wall_moment_[k] -
            S::moment(p.x[i] - pivot, wl.force[k]);
        if (rolling) t -= wall_roll_[k];  // the reaction to the grain's rolling couple
      }
      by_wall_torque_[e] = t;
    }
  }
  wall_totals_.reset(walls);
  constexpr int kRot = WallTotals<D>::kRot;
  for (std::size_t w = 0; w < walls; ++w) {
    const std::uint32_t e0 = by_wall_begin_[w], e1 = by_wall_begin_[w + 1];
    for (int d = 0; d < D; ++d) {
      ExactRun run(wall_totals_.component(w, d));
      for (std::uint32_t e = e0; e < e1; ++e) run.add(-wl.force[by_wall_[e]][d]);
    }
    for (int c = 0; c < kRot; ++c) {
      ExactRun run(wall_totals_.component(w, D + c));
      for (std::uint32_t e = e0; e < e1; ++e) {
        if constexpr (D == 3) {
          run.add(by_wall_torque_[e][c]);
        } else {
          run.add(by_wall_torque_[e]);
        }
      }
    }
  }
  domain_->reduce(wall_totals_);  // MPI: every process's contacts (ghosts have none)
  wall_totals_.store(world_.walls);
}

}  // namespace sable
