// The torque-free rotation of a body with three different principal moments
// (core/rigid_rotation.hpp): what the splitting promises, each against an independent
// reference or an exact invariant.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "sable/core/rigid_rotation.hpp"

namespace {

using Vec = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

// Principal moments of an asymmetric body (a box of sides 1, 2, 3 has I ~ (13, 10, 5) m/12;
// these are of that kind, every gap between them wide).
const Vec kInertia(1.0, 2.0, 3.0);

Vec momentum(const Quat& q, const Vec& omega) {
  return q * kInertia.cwiseProduct(q.conjugate() * omega);
}

struct Body {
  Quat q = Quat::Identity();
  Vec omega = Vec::Zero();  // world frame
};

// An independent reference: Euler's equations in the body frame and dq/dt = q (0, w_b) / 2,
// by classical Runge-Kutta (fourth order) at a step far below the splitting's.
Body reference(Body b, double t, int steps) {
  using State = Eigen::Matrix<double, 7, 1>;  // w_b (3), q (w, x, y, z)
  const auto rate = [](const State& s) {
    const Vec w = s.head<3>();
    const Vec l = kInertia.cwiseProduct(w);
    State d;
    d.head<3>() = l.cross(w).cwiseQuotient(kInertia);  // I dw/dt = (I w) x w
    const Quat q(s[3], s[4], s[5], s[6]);
    const Quat dq = q * Quat(0.0, w.x(), w.y(), w.z());
    d.tail<4>() << 0.5 * dq.w(), 0.5 * dq.x(), 0.5 * dq.y(), 0.5 * dq.z();
    return d;
  };
  State s;
  s.head<3>() = b.q.conjugate() * b.omega;
  s.tail<4>() << b.q.w(), b.q.x(), b.q.y(), b.q.z();
  const double h = t / steps;
  for (int k = 0; k < steps; ++k) {
    const State k1 = rate(s), k2 = rate(s + 0.5 * h * k1), k3 = rate(s + 0.5 * h * k2),
                k4 = rate(s + h * k3);
    s += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  b.q = Quat(s[3], s[4], s[5], s[6]).normalized();
  b.omega = b.q * Vec(s.head<3>());
  return b;
}

Body split(Body b, double t, int steps) {
  for (int k = 0; k < steps; ++k) sable::free_rotation(b.q, b.omega, kInertia, t / steps);
  return b;
}

// A start near no axis, turned away from the body frame: every term of the splitting works.
Body generic_start() {
  Body b;
  b.q = Quat(Eigen::AngleAxisd(0.7, Vec(1.0, -2.0, 0.5).normalized()));
  b.omega = b.q * Vec(0.6, -1.1, 0.9);
  return b;
}

// Angular momentum is each sub-flow's invariant: kept at every step to rounding. The bound
// allows ten roundings (2.2e-16 each) a step, adding up over 20,000 steps: 4.4e-11.
TEST(RigidRotation, AngularMomentumKeptToRounding) {
  Body b = generic_start();
  const Vec l0 = momentum(b.q, b.omega);
  double worst = 0.0;
  for (int k = 0; k < 20000; ++k) {
    sable::free_rotation(b.q, b.omega, kInertia, 1e-2);
    worst = std::max(worst, (momentum(b.q, b.omega) - l0).norm() / l0.norm());
  }
  EXPECT_LT(worst, 20000 * 10 * 2.2e-16);
}

// Second order: against the Runge-Kutta reference over a time of about two turns, halving
// the step quarters the error in the angular velocity and the orientation (ratio 4, within
// [3.5, 4.5]: the next term of the error is two orders of h below).
TEST(RigidRotation, SecondOrderAgainstRungeKutta) {
  const double t = 10.0;
  const Body ref = reference(generic_start(), t, 200000);
  double err[2];
  for (int level = 0; level < 2; ++level) {
    const Body b = split(generic_start(), t, 2000 << level);
    err[level] = (b.omega - ref.omega).norm() + b.q.angularDistance(ref.q);
  }
  EXPECT_LT(err[0], 1e-3) << "h = 5e-3 against the reference";
  RecordProperty("error_ratio", std::to_string(err[0] / err[1]));
  EXPECT_GT(err[0] / err[1], 3.5);
  EXPECT_LT(err[0] / err[1], 4.5);
}

// The energy error of a symplectic step stays bounded: over 100 times as long a run its
// largest relative error is within 1.5 times that of the first hundredth (no drift), and
// small, (h |omega|)^2 / 10 or so.
TEST(RigidRotation, EnergyErrorBoundedWithoutDrift) {
  Body b = generic_start();
  const auto energy = [](const Body& s) {
    return sable::rotational_energy(s.q, kInertia, s.omega);
  };
  const double e0 = energy(b), h = 2e-2;
  double early = 0.0, late = 0.0;
  for (int k = 0; k < 100000; ++k) {
    sable::free_rotation(b.q, b.omega, kInertia, h);
    const double e = std::abs(energy(b) - e0) / e0;
    (k < 1000 ? early : late) = std::max(k < 1000 ? early : late, e);
  }
  EXPECT_GT(early, 0.0);  // not conserved exactly: the bound below is the method's, not luck
  EXPECT_LT(early, 1e-3);
  EXPECT_LT(late, 1.5 * early);
}

// The tennis-racket theorem: a spin about the intermediate axis (I_2) with a small
// perturbation flips over (its component along that axis changes sign) within a few of its
// periods; about the smallest and largest axes it stays within a few % of its start.
TEST(RigidRotation, IntermediateAxisFlipsOthersStay) {
  const double spin = 2.0 * std::numbers::pi, eps = 1e-3 * spin;
  for (int axis = 0; axis < 3; ++axis) {
    Body b;
    Vec w = Vec::Constant(eps);
    w[axis] = spin;
    b.omega = w;
    double lowest = spin;              // the smallest body-frame component along `axis`
    for (int k = 0; k < 20000; ++k) {  // 20 turns at 1,000 steps a turn
      sable::free_rotation(b.q, b.omega, kInertia, 1e-3);
      lowest = std::min(lowest, (b.q.conjugate() * b.omega)[axis]);
    }
    if (axis == 1)
      EXPECT_LT(lowest, -0.9 * spin) << "the intermediate axis turns over";
    else
      EXPECT_GT(lowest, 0.97 * spin) << "axis " << axis << " is stable";
  }
}

// The world inverse inertia is the inverse of R diag(I) R^T, and the energy reads it.
TEST(RigidRotation, WorldInverseInertiaInvertsTheWorldTensor) {
  const Quat q = generic_start().q;
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const Eigen::Matrix3d tensor = R * kInertia.asDiagonal() * R.transpose();
  const Eigen::Matrix3d product = sable::world_inverse_inertia(q, kInertia.cwiseInverse()) * tensor;
  EXPECT_LT((product - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  const Vec w(0.3, -0.2, 0.5);
  EXPECT_NEAR(sable::rotational_energy(q, kInertia, w), 0.5 * w.dot(tensor * w), 1e-15);
}

}  // namespace
