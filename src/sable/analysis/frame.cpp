#include "sable/analysis/frame.hpp"

#include <fmt/format.h>

#include <cmath>

#include "sable/core/error.hpp"

namespace sable {

namespace {

template <int D>
struct Rotation;

template <>
struct Rotation<3> {
  Eigen::Matrix3d r;
  Eigen::Vector3d omega, point;
  Eigen::Vector3d vec(const Eigen::Vector3d& v) const { return r * v; }
  Eigen::Vector3d pos(const Eigen::Vector3d& x) const { return point + r * (x - point); }
  Eigen::Vector3d rot(const Eigen::Vector3d& w) const { return r * w; }
  Eigen::Vector3d frame_velocity(const Eigen::Vector3d& x) const { return omega.cross(x - point); }
};

template <>
struct Rotation<2> {
  Eigen::Matrix2d r;
  double omega = 0.0;
  Eigen::Vector2d point;
  Eigen::Vector2d vec(const Eigen::Vector2d& v) const { return r * v; }
  Eigen::Vector2d pos(const Eigen::Vector2d& x) const { return point + r * (x - point); }
  double rot(double w) const { return w; }
  Eigen::Vector2d frame_velocity(const Eigen::Vector2d& x) const {
    const Eigen::Vector2d d = x - point;
    return {-omega * d.y(), omega * d.x()};
  }
};

template <int D>
Rotation<D> make_rotation(const RotatingFrame& f, double time) {
  const double norm = f.axis.norm();
  if (!(norm > 0.0)) throw InputError("rotating frame: the axis is the zero vector");
  const Eigen::Vector3d u = f.axis / norm;
  const double theta = -f.omega * (time - f.t0);
  Rotation<D> rot;
  if constexpr (D == 3) {
    rot.r = Eigen::AngleAxisd(theta, u).toRotationMatrix();
    rot.omega = f.omega * u;
    rot.point = f.point;
  } else {
    if (std::abs(u.z()) < 1.0 - 1e-12)
      throw InputError(
          fmt::format("rotating frame: a 2D sample turns about z, not about ({}, {}, {})", u.x(),
                      u.y(), u.z()));
    const double angle = theta * u.z();
    rot.r << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    rot.omega = f.omega * u.z();
    rot.point = f.point.head<2>();
  }
  return rot;
}

}  // namespace

template <int D>
Sample<D> to_rotating_frame(const Sample<D>& s, const RotatingFrame& frame) {
  const Rotation<D> r = make_rotation<D>(frame, s.time);
  Sample<D> out = s;
  for (std::size_t g = 0; g < s.size(); ++g) {
    out.x[g] = r.pos(s.x[g]);
    out.v[g] = r.vec(s.v[g]) - r.frame_velocity(out.x[g]);
    out.a[g] = r.vec(s.a[g]);
    out.omega[g] = r.rot(s.omega[g]) - r.omega;
    out.alpha[g] = r.rot(s.alpha[g]);
  }
  auto& c = out.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    c.n[k] = r.vec(c.n[k]);
    c.force[k] = r.vec(c.force[k]);
    c.ft[k] = r.vec(c.ft[k]);
    c.arm_i[k] = r.vec(c.arm_i[k]);
    c.arm_j[k] = r.vec(c.arm_j[k]);
    c.branch[k] = r.vec(c.branch[k]);
    c.vrel[k] = r.vec(c.vrel[k]);  // a difference of velocities at one point: the frame's cancels
  }
  for (auto& w : out.walls) {
    typename Space<D>::Vec p, n, f, pivot;
    for (int d = 0; d < D; ++d) {
      p[d] = w.point[static_cast<std::size_t>(d)];
      n[d] = w.normal[static_cast<std::size_t>(d)];
      f[d] = w.force[static_cast<std::size_t>(d)];
      pivot[d] = w.pivot[static_cast<std::size_t>(d)];
    }
    w.point = Space<D>::to_array(r.pos(p));
    w.normal = Space<D>::to_array(r.vec(n));
    w.force = Space<D>::to_array(r.vec(f));
    w.pivot = Space<D>::to_array(r.pos(pivot));
    w.torque = Space<D>::rot_to_array(r.rot(Space<D>::rot_from_array(w.torque)));
  }
  out.gravity = r.vec(s.gravity);
  return out;
}

template Sample<2> to_rotating_frame(const Sample<2>&, const RotatingFrame&);
template Sample<3> to_rotating_frame(const Sample<3>&, const RotatingFrame&);

}  // namespace sable
