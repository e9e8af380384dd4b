// Wall geometry, stable particle ids and material mixing: the small pieces every contact and
// every snapshot relies on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sable/core/ids.hpp"
#include "sable/core/material.hpp"
#include "sable/geometry/walls.hpp"

namespace {

using sable::IdRegistry;
using sable::Material;
using sable::MaterialTable;
using sable::ParticleId;
using sable::Wall;

// ---------------------------------------------------------------- walls

// Guards the signed distance to a tilted plane in 3D: (x - p) . n, positive on the grains'
// side, negative behind, independent of the in-plane offset; the normal returned is the
// plane's. 1e-14 absolute: a few roundings of O(1) products.
TEST(WallsDistance, TiltedPlane3D) {
  Wall<3> w;
  w.point = Eigen::Vector3d(1.0, 2.0, 3.0);
  w.set_plane(Eigen::Vector3d(1.0, -2.0, 2.0) / 3.0);          // unit
  const Eigen::Vector3d t1(2.0, 1.0, 0.0), t2(0.0, 1.0, 1.0);  // both orthogonal to the normal
  Eigen::Vector3d n;
  for (double h : {0.7, -0.25, 0.0}) {
    const Eigen::Vector3d x = w.point + h * w.normal() + 0.3 * t1 - 1.1 * t2;
    EXPECT_NEAR(w.distance(x, n), h, 1e-14);
    EXPECT_NEAR((n - w.normal()).norm(), 0.0, 1e-15);
  }
}

// Guards the inside of a cylinder (axis z through `point`): distance = R - rho, independent of
// z, negative outside; the normal is horizontal, unit, and points to the axis; on the axis it
// is a deterministic unit vector. 1e-14 absolute: rounding of rho and of cos/sin products.
TEST(WallsDistance, CylinderInside) {
  Wall<3> w;
  w.point = Eigen::Vector3d(1.0, -2.0, 5.0);
  w.set_cylinder(3.0);
  Eigen::Vector3d n;
  for (double rho : {0.5, 2.9, 3.0, 3.4}) {
    for (double a : {0.0, 0.9, 2.5, -1.7}) {
      for (double z : {-4.0, 5.0, 11.0}) {
        const Eigen::Vector3d x(1.0 + rho * std::cos(a), -2.0 + rho * std::sin(a), z);
        EXPECT_NEAR(w.distance(x, n), 3.0 - rho, 1e-14) << rho << " " << a << " " << z;
        EXPECT_NEAR(n.x(), -std::cos(a), 1e-14);
        EXPECT_NEAR(n.y(), -std::sin(a), 1e-14);
        EXPECT_EQ(n.z(), 0.0);
      }
    }
  }
  EXPECT_EQ(w.distance(Eigen::Vector3d(1.0, -2.0, 0.0), n), 3.0);
  EXPECT_EQ(n.norm(), 1.0);
}

// Guards the 2D plane (a line): (x - p) . n with sign and the normal returned. 1e-14
// absolute: a few roundings of O(1) products.
TEST(WallsDistance, Plane2D) {
  Wall<2> w;
  w.point = Eigen::Vector2d(0.5, -1.0);
  w.set_plane(Eigen::Vector2d(-3.0, 4.0) / 5.0);
  const Eigen::Vector2d t(4.0, 3.0);  // along the line
  Eigen::Vector2d n;
  for (double h : {1.5, -0.4}) {
    EXPECT_NEAR(w.distance(w.point + h * w.normal() + 0.2 * t, n), h, 1e-14);
    EXPECT_NEAR((n - w.normal()).norm(), 0.0, 1e-15);
  }
  EXPECT_NEAR(w.distance(Eigen::Vector2d(0.0, 0.0), n), (-0.5 * -3.0 + 1.0 * 4.0) / 5.0, 1e-15);
}

// ---------------------------------------------------------------- ids

// Guards id bookkeeping: create maps ids to slots, destroy invalidates, and a destroyed id
// stays invalid after its index is reused (the generation differs). Exact: integers.
TEST(IdsRegistry, CreateDestroyReuse) {
  IdRegistry reg;
  const ParticleId a = reg.create(10), b = reg.create(11), c = reg.create(12);
  EXPECT_EQ(a.index, 0u);
  EXPECT_EQ(b.index, 1u);
  EXPECT_EQ(c.index, 2u);
  for (const auto& id : {a, b, c}) EXPECT_TRUE(reg.valid(id));
  EXPECT_EQ(reg.slot(a), 10u);
  EXPECT_EQ(reg.slot(b), 11u);
  EXPECT_EQ(reg.slot(c), 12u);

  reg.destroy(b);
  EXPECT_FALSE(reg.valid(b));
  EXPECT_EQ(reg.slot(b), IdRegistry::kNoSlot);
  EXPECT_TRUE(reg.valid(a));
  EXPECT_TRUE(reg.valid(c));

  const ParticleId d = reg.create(20);  // reuses index 1 with a new generation
  EXPECT_EQ(d.index, b.index);
  EXPECT_NE(d.generation, b.generation);
  EXPECT_FALSE(reg.valid(b));
  EXPECT_EQ(reg.slot(b), IdRegistry::kNoSlot);
  EXPECT_TRUE(reg.valid(d));
  EXPECT_EQ(reg.slot(d), 20u);
  EXPECT_FALSE(d == b);

  // A second round of reuse: both older ids stay invalid.
  reg.destroy(d);
  const ParticleId e = reg.create(30);
  EXPECT_EQ(e.index, b.index);
  EXPECT_FALSE(reg.valid(b));
  EXPECT_FALSE(reg.valid(d));
  EXPECT_TRUE(reg.valid(e));
  EXPECT_EQ(reg.slot(e), 30u);

  // Slots follow moves; ids never issued are invalid.
  reg.move(a, 7);
  EXPECT_EQ(reg.slot(a), 7u);
  EXPECT_EQ(reg.id_at_index(0), a);
  EXPECT_FALSE(reg.valid(ParticleId{}));
  EXPECT_FALSE(reg.valid(ParticleId{3, 0}));
  EXPECT_EQ(reg.slot(ParticleId{3, 0}), IdRegistry::kNoSlot);
}

// ---------------------------------------------------------------- materials

Material glass() {
  Material m;
  m.name = "glass";
  m.density = 2500.0;
  m.young = 5.0e6;
  m.poisson = 0.45;
  m.restitution = 0.6;
  m.friction = 0.5;
  return m;
}

Material steel() {
  Material m;
  m.name = "steel";
  m.density = 7800.0;
  m.young = 2.1e11;
  m.poisson = 0.3;
  m.restitution = 0.9;
  m.friction = 0.3;
  return m;
}

// Guards the mixing of two different materials against docs/contact-laws.md:
// Y* = 1 / ((1 - nu_i^2)/Y_i + (1 - nu_j^2)/Y_j), G* = 1 / (2(2 - nu_i)(1 + nu_i)/Y_i + ...),
// restitution sqrt(e_i e_j), friction min, symmetric. 1e-14 relative: a few roundings.
TEST(MaterialTable, MixTwoMaterials) {
  const Material a = glass(), b = steel();
  const double y_star = 1.0 / ((1.0 - 0.45 * 0.45) / 5.0e6 + (1.0 - 0.3 * 0.3) / 2.1e11);
  const double g_star =
      1.0 / (2.0 * (2.0 - 0.45) * (1.0 + 0.45) / 5.0e6 + 2.0 * (2.0 - 0.3) * (1.0 + 0.3) / 2.1e11);
  const double e = std::sqrt(0.6 * 0.9);
  for (const auto& p : {MaterialTable::mix(a, b), MaterialTable::mix(b, a)}) {
    EXPECT_NEAR(p.y_star, y_star, 1e-14 * y_star);
    EXPECT_NEAR(p.g_star, g_star, 1e-14 * g_star);
    EXPECT_NEAR(p.restitution, e, 1e-15);
    EXPECT_EQ(p.friction, 0.3);
    EXPECT_NEAR(p.beta, MaterialTable::beta_from_restitution(e), 1e-15);
  }
  // Sanity of the formulas as typed here (hand values to 6 digits): Y* = 6.26942e6 Pa,
  // G* = 1.11232e6 Pa.
  EXPECT_NEAR(y_star, 6.26942e6, 10.0);
  EXPECT_NEAR(g_star, 1.11232e6, 10.0);
}

// Guards rigid materials: a rigid partner adds no compliance, so Y* and G* are those of the
// deformable grain alone, even with no Young's modulus given (no division by zero). 1e-14
// relative: a few roundings.
TEST(MaterialTable, RigidContributesNoCompliance) {
  Material wall;
  wall.name = "rigid";
  wall.rigid = true;  // young = 0: must not be read
  wall.restitution = 0.6;
  wall.friction = 0.5;
  const Material g = glass();
  const auto p = MaterialTable::mix(g, wall);
  const double y_star = 5.0e6 / (1.0 - 0.45 * 0.45);
  const double g_star = 5.0e6 / (2.0 * (2.0 - 0.45) * (1.0 + 0.45));
  EXPECT_NEAR(p.y_star, y_star, 1e-14 * y_star);
  EXPECT_NEAR(p.g_star, g_star, 1e-14 * g_star);
  EXPECT_TRUE(std::isfinite(p.y_star) && std::isfinite(p.g_star));
  const auto q = MaterialTable::mix(wall, g);
  EXPECT_NEAR(q.y_star, y_star, 1e-14 * y_star);
  EXPECT_NEAR(q.g_star, g_star, 1e-14 * g_star);
}

// Guards pair overrides: they apply to (a, b) and (b, a) alike, re-derive beta from the
// overridden restitution, and leave every other pair at its mixed value. Exact for copied
// values; 1e-15 for beta (same formula).
TEST(MaterialTable, OverridesApplySymmetrically) {
  MaterialTable t;
  const auto ga = t.add(glass());
  const auto st = t.add(steel());
  Material rubber = glass();
  rubber.name = "rubber";
  rubber.young = 1.0e7;
  const auto ru = t.add(rubber);
  sable::PairOverride o;
  o.a = st;
  o.b = ga;
  o.friction = 0.8;
  o.restitution = 0.4;
  o.young_star = 1.0e9;
  t.add_override(o);
  t.finalize();
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t.find("steel"), st);
  EXPECT_FALSE(t.find("wood").has_value());
  for (const auto& p : {t.pair(ga, st), t.pair(st, ga)}) {
    EXPECT_EQ(p.friction, 0.8);
    EXPECT_EQ(p.restitution, 0.4);
    EXPECT_NEAR(p.beta, MaterialTable::beta_from_restitution(0.4), 1e-15);
    EXPECT_EQ(p.y_star, 1.0e9);
    EXPECT_EQ(p.g_star, MaterialTable::mix(glass(), steel()).g_star);  // not overridden
  }
  // Untouched pairs keep the mixed values.
  const auto mixed = MaterialTable::mix(glass(), rubber);
  for (const auto& p : {t.pair(ga, ru), t.pair(ru, ga)}) {
    EXPECT_EQ(p.friction, mixed.friction);
    EXPECT_EQ(p.restitution, mixed.restitution);
    EXPECT_EQ(p.y_star, mixed.y_star);
  }
  EXPECT_EQ(t.pair(ga, ga).friction, 0.5);
  EXPECT_EQ(t.pair(st, st).friction, 0.3);
  EXPECT_EQ(t.pair(st, ru).restitution, MaterialTable::mix(steel(), rubber).restitution);
}

// Guards beta = ln e / sqrt(ln^2 e + pi^2): exactly 0 for e = 1 (no damping), the formula for
// e = 0.6 (1e-15: the same few operations), negative and decreasing with e below 1.
TEST(MaterialTable, BetaFromRestitution) {
  EXPECT_EQ(MaterialTable::beta_from_restitution(1.0), 0.0);
  const double l = std::log(0.6);
  const double expected = l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
  EXPECT_NEAR(MaterialTable::beta_from_restitution(0.6), expected, 1e-15);
  EXPECT_NEAR(expected, -0.160493, 1e-6);  // hand value
  EXPECT_LT(MaterialTable::beta_from_restitution(0.3), MaterialTable::beta_from_restitution(0.6));
  EXPECT_LT(MaterialTable::beta_from_restitution(0.99), 0.0);
}

}  // namespace
