// The rotation of a rigid body whose inertia is not isotropic (a polyhedral grain): its
// inertia tensor in the world frame, and its torque-free motion over a time step.
//
// The body frame is the principal frame: the body's inertia there is diag(I1, I2, I3), and
// its orientation q turns body vectors into world ones. In the world frame the inertia is
// R diag(I) R^T (R the matrix of q), so a torque's or an impulse's moment m changes the
// angular velocity by R diag(1/I) R^T m, and a kick (a torque held over a time, or an
// impulse) is exact with the orientation it is applied at.
//
// Between kicks the body turns freely: the body-frame angular momentum pi = diag(I) R^T omega
// obeys Euler's equations d(pi)/dt = pi x diag(1/I) pi, which turn it about the body axes
// while the world-frame momentum L = R pi stays fixed. free_rotation() integrates them by
// the symmetric splitting of Dullweber, Leimkuhler & McLachlan (J. Chem. Phys. 107, 5840,
// 1997): the kinetic energy is the sum of pi_k^2 / (2 I_k) over the three axes, and the flow
// of each term alone is exact, a turn of the body about its axis k by the angle
// pi_k t / I_k (and of pi the other way, about the same axis). Composed as
// axis 1 (h/2), axis 2 (h/2), axis 3 (h), axis 2 (h/2), axis 1 (h/2), the step is
// symplectic, time-reversible and second order: L is kept to rounding at every step, the
// energy error stays bounded (no drift), of order (h |omega|)^2 relative, and the motion
// about the intermediate axis is unstable as it is in the exact flow (the tennis-racket
// flips). tests/unit/test_rigid_rotation.cpp measures all three.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace sable {

// R diag(inv_inertia) R^T: the world-frame inverse inertia of a body turned by q.
inline Eigen::Matrix3d world_inverse_inertia(const Eigen::Quaterniond& q,
                                             const Eigen::Vector3d& inv_inertia) {
  const Eigen::Matrix3d R = q.toRotationMatrix();
  return R * inv_inertia.asDiagonal() * R.transpose();
}

// The rotational kinetic energy 1/2 omega . I omega of a body turned by q (inertia: the
// principal moments).
inline double rotational_energy(const Eigen::Quaterniond& q, const Eigen::Vector3d& inertia,
                                const Eigen::Vector3d& omega) {
  const Eigen::Vector3d w = q.conjugate() * omega;
  return 0.5 * (inertia.array() * w.array().square()).sum();
}

// Advance the torque-free motion of a body with principal moments `inertia` over time h:
// q (body -> world, unit) and the world angular velocity omega at the end (see above).
inline void free_rotation(Eigen::Quaterniond& q, Eigen::Vector3d& omega,
                          const Eigen::Vector3d& inertia, double h) {
  Eigen::Vector3d pi = inertia.cwiseProduct(q.conjugate() * omega);
  const auto turn = [&](int k, double t) {
    const double a = 0.5 * pi[k] / inertia[k] * t;  // half the angle: a quaternion's
    Eigen::Quaterniond r(std::cos(a), 0.0, 0.0, 0.0);
    r.vec()[k] = std::sin(a);
    q = q * r;                // the body turns about its own axis k
    pi = r.conjugate() * pi;  // so its momentum, seen from the body, turns back
  };
  turn(0, 0.5 * h);
  turn(1, 0.5 * h);
  turn(2, h);
  turn(1, 0.5 * h);
  turn(0, 0.5 * h);
  // Rounding only: one Newton step back to |q| = 1 (as Space<3>::rotate does).
  q = Eigen::Quaterniond(q.coeffs() * (1.5 - 0.5 * q.squaredNorm()));
  omega = q * pi.cwiseQuotient(inertia);
}

}  // namespace sable
