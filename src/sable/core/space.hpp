// Dimension traits: Sable is written once for 2D disks and 3D spheres.
//
// Every dimension-dependent piece of the engine is a template on `int D` and reaches vectors,
// rotations and cross products only through `Space<D>`. In 2D a rotation rate or torque is a
// scalar (about z); in 3D it is a vector. Nothing in the engine stores a 3D vector for a 2D run.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>

namespace sable {

template <int D>
struct Space;

template <>
struct Space<3> {
  static constexpr int dim = 3;
  using Vec = Eigen::Vector3d;
  using Rot = Eigen::Vector3d;  // angular velocity, torque, rotation vector
  using Orientation = Eigen::Quaterniond;
  using Matrix = Eigen::Matrix3d;

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
    const Rot a = w * h;  // rotation vector of the step
    const double a2 = a.squaredNorm();
    if (a2 == 0.0) return q;
    double c, s;  // cos(|a|/2) and sin(|a|/2) / |a|
    if (a2 < 1e-8) {
      // |a| < 1e-4 rad (every step of a sane run): Taylor series, exact to round-off here,
      // instead of sin, cos and a division; multiplied by the reciprocals (a division by 48
      // is not turned into a multiplication by the compiler: it would round differently).
      c = 1.0 - a2 * (1.0 / 8.0) + a2 * a2 * (1.0 / 384.0);
      s = 0.5 - a2 * (1.0 / 48.0) + a2 * a2 * (1.0 / 3840.0);
    } else {
      const double angle = std::sqrt(a2);
      c = std::cos(0.5 * angle);
      s = std::sin(0.5 * angle) / angle;
    }
    const Orientation dq(c, s * a.x(), s * a.y(), s * a.z());
    const Orientation r = dq * q;
    // dq and q are unit, so |r|^2 = 1 + e with e a few round-offs: one Newton step for
    // 1/|r|, 1 - e/2, brings |r| back to 1 within round-off, without the square root and four
    // divisions of normalized(). A quaternion far from unit (read from a file) is normalized.
    const double n2 = r.squaredNorm();
    if (std::abs(n2 - 1.0) > 1e-8) return r.normalized();
    return Orientation(r.coeffs() * (1.5 - 0.5 * n2));
  }
  // The rotation matrix of an orientation, and the angle (rad, in [0, pi]) of the rotation
  // that takes b to a: what a turning wall's rebuild test bounds its surface's motion by.
  static Matrix matrix(const Orientation& q) { return q.toRotationMatrix(); }
  static double angle_between(const Orientation& a, const Orientation& b) {
    const Orientation r = a * b.conjugate();
    return 2.0 * std::atan2(r.vec().norm(), std::abs(r.w()));
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
  using Matrix = Eigen::Matrix2d;

  static Vec zero() { return Vec::Zero(); }
  static Rot zero_rot() { return 0.0; }
  static Vec spin_velocity(Rot w, const Vec& r) { return {-w * r.y(), w * r.x()}; }
  static Rot moment(const Vec& r, const Vec& f) { return r.x() * f.y() - r.y() * f.x(); }
  static double rot_norm2(Rot w) { return w * w; }
  static Orientation identity() { return 0.0; }
  static Orientation rotate(Orientation a, Rot w, double h) { return a + w * h; }
  static Matrix matrix(Orientation a) {
    const double c = std::cos(a), s = std::sin(a);
    Matrix m;
    m << c, -s, s, c;
    return m;
  }
  static double angle_between(Orientation a, Orientation b) { return std::abs(a - b); }
  static Vec from_array(const std::array<double, 3>& a) { return {a[0], a[1]}; }
  static std::array<double, 3> to_array(const Vec& v) { return {v.x(), v.y(), 0.0}; }
  static std::array<double, 3> rot_to_array(Rot w) { return {0.0, 0.0, w}; }
  static Rot rot_from_array(const std::array<double, 3>& a) { return a[2]; }
};

}  // namespace sable
