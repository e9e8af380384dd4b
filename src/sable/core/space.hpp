// Dimension traits: Sable is written once for 2D disks and 3D spheres.
//
// Every dimension-dependent piece of the engine is a template on `int D` and reaches vectors,
// rotations and cross products only through `Space<D>`. In 2D a rotation rate or torque is a
// scalar (about z); in 3D it is a vector. Nothing in the engine stores a 3D vector for a 2D run.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

namespace sable {

template <int D>
struct Space;

template <>
struct Space<3> {
  static constexpr int dim = 3;
  using Vec = Eigen::Vector3d;
  using Rot = Eigen::Vector3d;  // angular velocity, torque, rotation vector
  using Orientation = Eigen::Quaterniond;

  static Vec zero() { return Vec::Zero(); }
  static Rot zero_rot() { return Rot::Zero(); }
  // Velocity of the point at lever arm r on a body spinning at w: w x r.
  static Vec spin_velocity(const Rot& w, const Vec& r) { return w.cross(r); }
  // Moment of force f applied at lever arm r: r x f.
  static Rot moment(const Vec& r, const Vec& f) { return r.cross(f); }
  static double rot_norm2(const Rot& w) { return w.squaredNorm(); }
  static Orientation identity() { return Orientation::Identity(); }
  // Advance an orientation by the rotation vector w*h (exact exponential map).
  static Orientation rotate(const Orientation& q, const Rot& w, double h) {
    const double angle = w.norm() * h;
    if (angle == 0.0) return q;
    Orientation dq(Eigen::AngleAxisd(angle, w.normalized()));
    return (dq * q).normalized();
  }
  static Vec from_array(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }
  static std::array<double, 3> to_array(const Vec& v) { return {v.x(), v.y(), v.z()}; }
  static std::array<double, 3> rot_to_array(const Rot& w) { return {w.x(), w.y(), w.z()}; }
  static Rot rot_from_array(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }
};

template <>
struct Space<2> {
  static constexpr int dim = 2;
  using Vec = Eigen::Vector2d;
  using Rot = double;          // rotation about z
  using Orientation = double;  // angle about z (rad)

  static Vec zero() { return Vec::Zero(); }
  static Rot zero_rot() { return 0.0; }
  static Vec spin_velocity(Rot w, const Vec& r) { return {-w * r.y(), w * r.x()}; }
  static Rot moment(const Vec& r, const Vec& f) { return r.x() * f.y() - r.y() * f.x(); }
  static double rot_norm2(Rot w) { return w * w; }
  static Orientation identity() { return 0.0; }
  static Orientation rotate(Orientation a, Rot w, double h) { return a + w * h; }
  static Vec from_array(const std::array<double, 3>& a) { return {a[0], a[1]}; }
  static std::array<double, 3> to_array(const Vec& v) { return {v.x(), v.y(), 0.0}; }
  static std::array<double, 3> rot_to_array(Rot w) { return {0.0, 0.0, w}; }
  static Rot rot_from_array(const std::array<double, 3>& a) { return a[2]; }
};

}  // namespace sable
