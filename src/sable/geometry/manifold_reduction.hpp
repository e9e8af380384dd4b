// Internal to the geometry's narrow phases (polyhedron_contact.cpp, polyhedron_plane.cpp): the
// rule that keeps at most 4 points of a contact manifold, in one place so that a grain on a
// grain and a grain on a wall keep their points alike.
//
// Why 4: the contact law integrates a force per point, and a patch of contact is held flat
// (against rocking) by its corners; more points cost more without holding it better. Which 4,
// greedily, each chosen once: the deepest (the first of equals); the one farthest from it; the
// one making the largest triangle with those two; the one adding the most area outside one
// side of that triangle. Distances and areas are measured in the reference plane (the
// component along its normal n removed), so that the points spread over the patch however
// deep each lies. Fewer come back when the rest add nothing: all the candidates at one point
// give 1, on one line 2, inside the triangle 3.
//
// Points already touching (gap <= 0) come first: each of the three later choices is made among
// the touching candidates when one of them adds something, and among all only otherwise. A
// wide margin (contact dynamics takes the step's reach, up to a third of a grain's size) holds
// corners that cannot touch within the step beside those that already do, and a rule blind to
// the gaps would keep the far ones and leave a touching corner unconstrained, to sink on
// (docs/contact-dynamics.md). So at most 3 touching points are all kept; with none touching
// (or one), the rule is the plain one above.
//
// The candidates are read through callables, so that the caller keeps them where it has them
// (a clipped polygon, a grain's vertices posed on the fly) and nothing is copied: point(k) and
// gap(k) for k < count (the gap that ranks them: the present one, or the one predicted at the
// end of the step when the caller gives the motion, ManifoldMotion in polyhedron_contact.hpp,
// so that "touching" reads "touching by the step's end"), member(k) saying which k are candidates
// at all (the rest are skipped as if absent: the kept indices are those the rule keeps of the
// candidates alone). No allocation; 4 to 7 passes over the k < count: the deepest (member() and
// gap() per k), then for each later choice one over the touching candidates and, when none of them
// adds anything, one over all, calling point() once per candidate k.
//
// Invariants: deterministic (the first of equals at each step, in index order); reads nothing
// but the callables; the same floating-point operations whatever the callables, so that a
// caller's results are those of the rule written out on its own points.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace sable::detail {

// Twice the signed area of the triangle (p, q, r) seen along n.
inline double twice_area(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                         const Eigen::Vector3d& r, const Eigen::Vector3d& n) {
  return (q - p).cross(r - p).dot(n);
}

// The argmax of score(k) over k < count (the first of equals); -1 unless some score > 0.
template <typename Score>
int best_of(std::size_t count, Score&& score) {
  int best = -1;
  double top = 0.0;
  for (std::size_t k = 0; k < count; ++k)
    if (const double v = score(k); v > top) {
      top = v;
      best = static_cast<int>(k);
    }
  return best;
}

// The rule above, for more than 4 candidates among k < count (at least one; a caller with 4
// or fewer keeps them all). Returns how many are kept (1 to 4), their indices in `keep`, in
// the order chosen (the deepest first).
template <typename Point, typename Gap, typename Member>
int reduce_to_four(std::size_t count, const Point& point, const Gap& gap, const Member& member,
                   const Eigen::Vector3d& n, std::array<std::size_t, 4>& keep) {
  using Vec = Eigen::Vector3d;
  std::size_t i0 = 0;
  while (!member(i0)) ++i0;
  double g0 = gap(i0);
  for (std::size_t k = i0 + 1; k < count; ++k)
    if (member(k))
      if (const double g = gap(k); g < g0) {
        g0 = g;
        i0 = k;
      }
  // Written as in the rule's first home (an Eigen expression, not a vector): the same
  // operations, so the pair's results kept their bits when the rule moved here.
  const auto flat = [&](const Vec& v) { return v - n.dot(v) * n; };  // in the plane
  // Only candidates score (the touching ones first, see above); a score <= 0 is never chosen
  // (best_of).
  const auto pick = [&](auto of) {
    const int touching = best_of(
        count, [&](std::size_t k) { return member(k) && gap(k) <= 0.0 ? of(point(k)) : 0.0; });
    if (touching >= 0) return touching;
    return best_of(count, [&](std::size_t k) { return member(k) ? of(point(k)) : 0.0; });
  };
  keep[0] = i0;
  const Vec p0 = point(i0);
  const int i1 = pick([&](const Vec& x) { return flat(x - p0).squaredNorm(); });
  if (i1 < 0) return 1;
  keep[1] = static_cast<std::size_t>(i1);
  const Vec p1 = point(keep[1]);
  const int i2 = pick([&](const Vec& x) { return std::abs(twice_area(p0, p1, x, n)); });
  if (i2 < 0) return 2;
  keep[2] = static_cast<std::size_t>(i2);
  const Vec p2 = point(keep[2]);
  const double turn = twice_area(p0, p1, p2, n) > 0.0 ? 1.0 : -1.0;  // the triangle's winding
  const int i3 = pick([&](const Vec& x) {
    // Outside a side (q, r), x adds the triangle (q, r, x), wound against it.
    return std::max({-turn * twice_area(p0, p1, x, n), -turn * twice_area(p1, p2, x, n),
                     -turn * twice_area(p2, p0, x, n)});
  });
  if (i3 < 0) return 3;
  keep[3] = static_cast<std::size_t>(i3);
  return 4;
}

}  // namespace sable::detail
