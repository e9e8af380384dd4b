// The tangential spring as the contact turns (ContactModel::keep_spring_length): the spring is
// brought into the new tangent plane either turned with its length kept (default) or only
// projected, which shortens it by cos(theta) for a turn theta (LIGGGHTS 3.8's rule, used by the
// peer benchmark for a like-for-like bed).
#include <gtest/gtest.h>

#include <cmath>

#include "sable/contact/registry.hpp"
#include "sable/scenario/config.hpp"

namespace {

using Vec = Eigen::Vector3d;

// A contact with no relative velocity whose normal has turned by theta about y since the
// spring s0 (along x, tangent to the old normal z) was stored: the kernel's only change to
// the spring is bringing it into the new tangent plane. Friction is large, so the spring stays
// below the Coulomb limit and the tangential force is -k_t s exactly.
Vec turned_spring(bool keep_length, double theta, Vec* force = nullptr) {
  sable::ContactModel model;
  model.keep_spring_length = keep_length;
  sable::PairParams p;
  p.y_star = 1e7;
  p.g_star = 4e6;
  p.friction = 1e6;
  sable::ContactGeometry<3> g;
  g.n = Vec(std::sin(theta), 0.0, std::cos(theta));
  g.delta = 1e-6;
  g.vrel = Vec::Zero();
  g.r_eff = 1e-3;
  g.m_eff = 1e-5;
  Vec shear(2e-7, 0.0, 0.0);
  const Vec f = sable::contact_force<3, sable::HertzNormal>(g, p, model, 1e-6, shear);
  if (force) *force = f;
  return shear;
}

// Length kept: |s| unchanged and s perpendicular to the new normal, to round-off (1e-15
// relative: a few operations on numbers of order one).
TEST(ContactKernel, TurningContactKeepsTheSpringLength) {
  for (const double theta : {1e-6, 1e-3, 0.1, 0.5}) {
    const Vec n(std::sin(theta), 0.0, std::cos(theta));
    const Vec s = turned_spring(true, theta);
    EXPECT_NEAR(s.norm(), 2e-7, 2e-7 * 1e-15) << "theta " << theta;
    EXPECT_NEAR(s.dot(n), 0.0, 2e-7 * 1e-15) << "theta " << theta;
  }
}

// Projected only: |s| = |s0| cos(theta), perpendicular to the new normal (to round-off).
// The tangential force is -k_t s with k_t = 8 G* sqrt(R* delta): the shorter spring pushes less.
TEST(ContactKernel, ProjectedSpringShortensByTheCosine) {
  for (const double theta : {1e-3, 0.1, 0.5}) {
    const Vec n(std::sin(theta), 0.0, std::cos(theta));
    Vec f;
    const Vec s = turned_spring(false, theta, &f);
    EXPECT_NEAR(s.norm(), 2e-7 * std::cos(theta), 2e-7 * 1e-15) << "theta " << theta;
    EXPECT_NEAR(s.dot(n), 0.0, 2e-7 * 1e-15) << "theta " << theta;
    const double kt = 8.0 * 4e6 * std::sqrt(1e-3 * 1e-6);
    const Vec ft = f - f.dot(n) * n;
    EXPECT_NEAR((ft + kt * s).norm(), 0.0, kt * 2e-7 * 1e-12) << "theta " << theta;
  }
}

// The scenario key: default true, false accepted, a non-boolean refused naming the key.
TEST(ContactKernel, KeepSpringLengthScenarioKey) {
  const std::string head =
      "[simulation]\ndimension = 3\ndt = 1e-6\n[domain]\nlo = [0, 0, 0]\nhi = [1, 1, 1]\n"
      "[[material]]\nname = \"g\"\ndensity = 2500.0\nyoung = 1e7\npoisson = 0.3\n"
      "restitution = 0.5\nfriction = 0.5\n[[stage]]\nname = \"s\"\nsteps = 1\n";
  EXPECT_TRUE(sable::parse_scenario(head, "a.toml").contact.keep_spring_length);
  EXPECT_FALSE(sable::parse_scenario(head + "[contact]\nkeep_spring_length = false\n", "b.toml")
                   .contact.keep_spring_length);
  try {
    sable::parse_scenario(head + "[contact]\nkeep_spring_length = \"no\"\n", "c.toml");
    FAIL() << "a string for keep_spring_length was accepted";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("c.toml"), std::string::npos) << what;
    EXPECT_NE(what.find("keep_spring_length"), std::string::npos) << what;
  }
}

}  // namespace
