// Contact dynamics with polyhedral grains: the contacts of a step from the grains' manifolds.
//
// A polyhedral pair touches at up to 4 points (geometry/polyhedron_contact.hpp: a vertex on a
// face 1, an edge on a face 2, a face on a face up to 4 from the clipped polygon), a grain on a
// plane wall likewise (geometry/polyhedron_plane.hpp); a pair also gets up to 4 look-ahead
// points, corners that close on a face within the step (ManifoldMotion). Each point is a
// contact of the frictional contact problem, as in LMGC90: its own frame (the manifold's
// normal, or a look-ahead point's face normal), gap, arms from both centroids and Delassus
// block with the grains' world-frame inertia tensors. The points of one list entry sit in a
// row among the contacts; their impulses are stored summed as the entry's force (what
// outputs, analyses and snapshots read), and that force, shared equally among the next
// step's points, is their warm start (a guess: the solution is the same whatever it is, only
// the sweeps needed change).
#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "sable/cd/cd_solver.hpp"
#include "sable/core/error.hpp"
#include "sable/core/parallel.hpp"
#include "sable/geometry/polyhedron_plane.hpp"

namespace sable {

template <>
void CdSolver<2>::build_polyhedral_contacts() {}  // a 2D world holds no polyhedra

template <>
void CdSolver<2>::check_polyhedral_world() const {}

template <>
void CdSolver<2>::store_polyhedral_geometry() {}

// What the solver does with polyhedra today: every grain a polyhedron, walls that are planes
// (wall bodies included), no rolling resistance (a polyhedron's faces resist rolling).
template <>
void CdSolver<3>::check_polyhedral_world() const {
  const auto& p = world_.particles;
  for (std::size_t k = 0; k < p.size(); ++k)
    if (!p.polyhedron(k))
      throw InputError(fmt::format(
          "contact dynamics: grain {} is a sphere in a world of polyhedral grains; a world "
          "holds one kind of grain",
          p.id[k].index));
  for (std::size_t w = 0; w < world_.walls.size(); ++w)
    if (world_.walls[w].plane() == nullptr)
      throw InputError(
          fmt::format("contact dynamics: wall {} is a {}; polyhedral grains touch plane walls only",
                      w, world_.walls[w].type_name()));
  if (world_.model.rolling != RollingModel::kNone)
    throw InputError(
        "contact dynamics: rolling resistance with polyhedral grains (their faces resist "
        "rolling: no rolling law is needed, and none is applied to them)");
}

// As build_contacts(): the entries whose bounding spheres can close within the step get their
// manifold (margin: how far the gap can close), each point a contact, in the lists' order on
// any thread count. A manifold with more than 4 points within the margin keeps the 4 that
// the grains' present motion brings closest within the step (ManifoldMotion).
template <>
void CdSolver<3>::build_polyhedral_contacts() {
  const auto& p = world_.particles;
  auto& pl = world_.neighbors.pairs;
  auto& wl = world_.neighbors.wall_pairs;
  const double reach = 2.0 * world_.dt * max_speed();
  // Not finite (a non-finite velocity): the points found at a zero margin; the solve reports.
  const double margin = std::isfinite(reach) ? reach : 0.0;
  const auto solid = [&](std::uint32_t g) -> const ConvexPolyhedron& {
    return world_.shapes[p.shape_index[g]].solid;
  };
  const auto np = static_cast<std::ptrdiff_t>(pl.size()),
             nw = static_cast<std::ptrdiff_t>(wl.size());
  slot_.resize(static_cast<std::size_t>(np + nw) + 1);
  manifold_.resize(static_cast<std::size_t>(np + nw));
#pragma omp parallel for schedule(static) if (np >= kMinParallelItems)
  for (std::ptrdiff_t k = 0; k < np; ++k) {
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    PolyhedronContact& m = manifold_[k];
    m.count = 0;
    if (!((p.x[i] - p.x[j]).norm() - p.radius[i] - p.radius[j] > margin))
      m = polyhedron_contact(solid(i), p.x[i], p.q[i], solid(j), p.x[j], p.q[j], margin,
                             {p.v[i], p.omega[i], p.x[i], p.v[j], p.omega[j], p.x[j], world_.dt});
    slot_[k] = static_cast<std::size_t>(m.total());
    if (m.total() == 0) pl.force[k].setZero();
  }
#pragma omp parallel for schedule(static) if (nw >= kMinParallelItems)
  for (std::ptrdiff_t k = 0; k < nw; ++k) {
    const std::uint32_t i = wl.i[k];
    const Wall<3>& wall = world_.walls[wl.wall[k]];
    const double reach_k = margin + world_.dt * wall_speed(wl.wall[k], p.x[i], p.radius[i]);
    const double wall_margin = std::isfinite(reach_k) ? reach_k : 0.0;
    PolyhedronContact& m = manifold_[np + k];
    m.count = 0;
    if (!(wall.normal().dot(p.x[i] - wall.point) - p.radius[i] > wall_margin))
      m = polyhedron_plane_contact(
          solid(i), p.x[i], p.q[i], wall.point, wall.normal(), wall_margin,
          {p.v[i], p.omega[i], p.x[i], wall.velocity, wall.spin, wall.pivot, world_.dt});
    slot_[np + k] = static_cast<std::size_t>(m.total());
    if (m.total() == 0) wl.force[k].setZero();
  }
  c_.resize(first_contacts(), false);  // slot_[k]: the first contact of entry k
#pragma omp parallel for schedule(static) if (np >= kMinParallelItems)
  for (std::ptrdiff_t k = 0; k < np; ++k) {
    const PolyhedronContact& m = manifold_[k];
    const std::uint32_t i = pl.i[k], j = pl.j[k];
    const PairParams pp = world_.materials.pair(p.material[i], p.material[j]);
    const Vec share = pl.force[k] / std::max(m.total(), 1);
    for (int t = 0; t < m.total(); ++t) {
      const Vec& x = m.points[t].position;  // the normal n runs from j to i, as for spheres
      set_contact<false>(slot_[k] + t, i, j, static_cast<std::uint32_t>(k), -m.normal_of(t),
                         m.points[t].gap, x - p.x[i], x - p.x[j], pp, share, Rot::Zero());
    }
  }
#pragma omp parallel for schedule(static) if (nw >= kMinParallelItems)
  for (std::ptrdiff_t k = 0; k < nw; ++k) {
    const PolyhedronContact& m = manifold_[np + k];
    const std::uint32_t i = wl.i[k];
    const PairParams pp = world_.materials.pair(p.material[i], world_.walls[wl.wall[k]].material);
    const Vec share = wl.force[k] / std::max(m.total(), 1);
    for (int t = 0; t < m.total(); ++t)
      set_contact<true>(slot_[np + k] + t, i, wl.wall[k], static_cast<std::uint32_t>(k),
                        -m.normal_of(t), m.points[t].gap, m.points[t].position - p.x[i],
                        Vec::Zero(), pp, share, Rot::Zero());
  }
}

// An entry's contact point is the centre of its points weighted by their normal impulses:
// the impulses are parallel (one normal per manifold), so their sum acting there has the
// moment of the points' normal impulses, which is what a particle stress needs. Without a
// normal impulse (the entry carries no force) the mean of the points stands in. The normal
// runs from grain i towards its partner, opposite to the contact frames' (from j to i).
template <>
void CdSolver<3>::store_polyhedral_geometry() {
  auto& g = world_.contact_geometry;
  const std::size_t np = world_.neighbors.pairs.size(), nw = world_.neighbors.wall_pairs.size();
  g.pairs.resize(np);
  g.wall_pairs.resize(nw);
  const auto n_all = static_cast<std::ptrdiff_t>(np + nw);
#pragma omp parallel for schedule(static) if (n_all >= kMinParallelItems)
  for (std::ptrdiff_t e = 0; e < n_all; ++e) {
    const auto k = static_cast<std::size_t>(e);
    EntryGeometry<3>& out = k < np ? g.pairs : g.wall_pairs;
    const std::size_t row = k < np ? k : k - np;
    const std::size_t first = slot_[k], end = slot_[k + 1];
    if (first == end) {
      out.set(row, Vec::Zero(), Vec::Zero(), 0.0);
      continue;
    }
    double weight = 0.0, depth = -std::numeric_limits<double>::infinity();
    Vec weighted = Vec::Zero(), mean = Vec::Zero();
    for (std::size_t a = first; a < end; ++a) {
      const double rn = c_.r[a][0];
      weighted += rn * c_.arm_i[a];
      weight += rn;
      mean += c_.arm_i[a];
      depth = std::max(depth, -c_.gap[a]);
    }
    const Vec arm =
        weight > 0.0 ? Vec(weighted / weight) : Vec(mean / static_cast<double>(end - first));
    out.set(row, Vec(-c_.frame[first].col(0)), arm, depth);
  }
}

}  // namespace sable
