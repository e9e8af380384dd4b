// Walls: rigid boundaries with a prescribed motion and their own material.
//
// A wall is a shape (geometry/wall_shapes.hpp: plane, inside of a cylinder, triangle mesh)
// and what every shape shares: a pose (a point and an orientation), a prescribed motion (a
// translation velocity and a spin about a pivot), the total force and torque the grains
// exert on it. The shape answers the contact kernel's one question: for a grain centre x and
// one of the shape's list elements, the nearest feature's normal, distance and id
// (WallFeature). That is the geometry a grain pair produces too, so one kernel serves both.
//
// The wall interface, what a new shape provides (one file plus a row in WallShape):
//   kName, kBounded            its scenario name; whether its elements are binned in the
//                              grains' cells (a mesh) or tested against every grain (planes)
//   elements()                 how many list elements (1 unless a mesh)
//   element_box(), element_distance()   the broad phase of a bounded shape
//   contact(point, x, e)       the feature element e answers for at x
//   distance(point, x, n)      the nearest surface point overall (checks outside the loop)
//   place(R, point)            the pose changed: R from the starting orientation, the point
// Motion, velocity at a point, the rebuild bound, snapshots (the pose) and outputs are the
// Wall's, the same for every shape.
#pragma once

#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include "sable/core/material.hpp"
#include "sable/core/space.hpp"
#include "sable/geometry/wall_shapes.hpp"

namespace sable {

template <int D>
struct Wall {
  using S = Space<D>;
  using Vec = typename S::Vec;
  using Rot = typename S::Rot;
  std::string name;
  WallShape<D> shape = PlaneShape<D>();
  MaterialIndex material = 0;
  // The pose: the body frame's origin (a plane: a point on it; a cylinder: a point on its
  // axis; a mesh: the centre of its starting bounding box) and its rotation from the start.
  Vec point = Vec::Zero();
  typename S::Orientation orientation = S::identity();
  Vec velocity = Vec::Zero();  // prescribed translation velocity (m/s)
  Rot spin = S::zero_rot();    // prescribed angular velocity (rad/s) about `pivot`
  // The point the wall turns about and its torque is taken about; it moves with the wall
  // once a rotation was given (`pivoted`). The origin for a wall never given a rotation.
  Vec pivot = Vec::Zero();
  bool pivoted = false;
  // Over the last force evaluation, force and torque (about pivot) exerted BY the grains ON
  // the wall (a mesh's force per element: world/element_forces.hpp).
  Vec force = Vec::Zero();
  Rot torque = S::zero_rot();

  // Shorthands for code that builds walls by hand (tests, benchmarks).
  void set_plane(const Vec& unit_normal) { shape = PlaneShape<D>(unit_normal); }
  void set_cylinder(double radius) { shape = CylinderShape<D>(radius); }
  // A mesh placed as given: the wall's point becomes its body origin (MeshShape).
  void set_mesh(SurfaceMesh<D> surface) {
    Vec origin;
    shape = MeshShape<D>(std::move(surface), origin);
    point = origin;
  }
  // Turn at `rate` (3D: about `axis`, any length) about `p`; rate 0 stops the turning and
  // keeps the pivot (the torque is still taken about it).
  void set_rotation(const Vec& p, const Vec& axis, double rate) {
    pivot = p;
    pivoted = true;
    if constexpr (D == 3)
      spin = rate * axis.normalized();
    else
      spin = rate;
    (void)axis;
  }

  bool turning() const { return S::rot_norm2(spin) > 0.0; }
  // Given a rotation at some time: its orientation, spin and pivot are state.
  bool moves_about() const { return pivoted || turning() || turned(); }
  bool turned() const {
    if constexpr (D == 3)
      return orientation.coeffs() != S::identity().coeffs();
    else
      return orientation != S::identity();
  }
  bool is_mesh() const { return std::holds_alternative<MeshShape<D>>(shape); }
  const PlaneShape<D>* plane() const { return std::get_if<PlaneShape<D>>(&shape); }
  const MeshShape<D>* mesh() const { return std::get_if<MeshShape<D>>(&shape); }
  const char* type_name() const {
    return std::visit([](const auto& s) { return std::decay_t<decltype(s)>::kName; }, shape);
  }
  std::uint32_t elements() const {
    return std::visit([](const auto& s) { return s.elements(); }, shape);
  }
  // A plane's unit normal into the grains; zero for another shape.
  Vec normal() const {
    const auto* p = plane();
    return p ? p->normal : Vec(Vec::Zero());
  }

  // Signed distance (planes, cylinders; unsigned for a mesh) from the surface to x and the
  // unit normal there towards x.
  double distance(const Vec& x, Vec& n) const {
    return std::visit([&](const auto& s) { return s.distance(point, x, n); }, shape);
  }
  WallFeature<D> contact(const Vec& x, std::uint32_t element) const {
    return std::visit([&](const auto& s) { return s.contact(point, x, element); }, shape);
  }
  // The wall's velocity at x: v + omega x (x - pivot).
  Vec velocity_at(const Vec& x) const {
    if (!turning()) return velocity;
    return velocity + S::spin_velocity(spin, x - pivot);
  }

  // One time step h of the prescribed motion: turn by spin * h about the pivot, then
  // translate by velocity * h (the pivot with it). A shape whose world data follow its pose
  // (a mesh's vertices; a turned plane's normal) is placed again.
  void advance(double h) {
    if (turning()) {
      const typename S::Matrix step = S::matrix(S::rotate(S::identity(), spin, h));
      point = pivot + step * (point - pivot);
      orientation = S::rotate(orientation, spin, h);
    }
    point += h * velocity;
    if (pivoted) pivot += h * velocity;
    if (turning() || (is_mesh() && velocity != Vec::Zero())) place();
  }
  // Re-derive the shape's world data from the pose (after advance, or a snapshot's pose).
  void place() {
    const typename S::Matrix r = S::matrix(orientation);
    std::visit([&](auto& s) { s.place(r, point); }, shape);
  }

  // How far any point of the surface that grains in lo..hi can reach moved between the pose
  // (ref_point, ref_orientation) and now: |dpoint| + angle * lever, lever the largest
  // distance from the body origin to that surface.
  double moved_since(const Vec& ref_point, const typename S::Orientation& ref_orientation,
                     const Vec& lo, const Vec& hi) const {
    const double shift = (point - ref_point).norm();
    const double angle = S::angle_between(orientation, ref_orientation);
    if (angle == 0.0) return shift;
    const auto* m = mesh();
    double lever = 0.0;
    if (m) {
      lever = m->extent();
    } else {  // planes and cylinders: their part inside the grains' domain
      lever = ((point - lo).cwiseAbs().cwiseMax((point - hi).cwiseAbs())).norm();
      if (const auto* c = std::get_if<CylinderShape<D>>(&shape)) lever += c->radius;
    }
    return shift + angle * lever;
  }

  // The coordinate axis a plane wall faces (its normal is +-e_axis), or -1 for another shape
  // or a tilted plane: the walls that bound a box sample and that a servo can drive.
  int facing_axis() const {
    const auto* p = plane();
    if (!p) return -1;
    for (int d = 0; d < D; ++d)
      if (std::abs(std::abs(p->normal[d]) - 1.0) < 1e-12) return d;
    return -1;
  }
};

}  // namespace sable
