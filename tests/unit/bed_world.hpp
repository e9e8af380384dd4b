// A small bed of grains on a floor, built by hand, for the snapshot tests (test_io.cpp,
// test_snapshot_hash.cpp).
#pragma once

#include "sable/world/world.hpp"

namespace sable::test {

// Drop the last grain as a future removal would: free its id (bumping the generation).
template <int D>
void remove_last(ParticleStore<D>& p) {
  p.ids.destroy(p.id.back());
  p.for_each_array([](auto& array) { array.pop_back(); });
}

inline constexpr double kBedR = 0.005;  // grain radius (m)

template <int D>
void add_walls(World<D>& w) {
  using Vec = typename Space<D>::Vec;
  Wall<D> floor;
  floor.name = "floor";
  floor.material = 1;
  floor.set_plane(Vec::Unit(D - 1));
  w.walls.push_back(floor);
  Wall<D> ramp;  // tilted and moving: exercises wall_ref and the clipping code
  ramp.name = "ramp";
  ramp.material = 1;
  ramp.point = Vec::Constant(0.0);
  ramp.point[0] = 0.12;
  Vec ramp_normal = Vec::Constant(0.3);
  ramp_normal[0] = -1.0;
  ramp.set_plane(ramp_normal.normalized());
  ramp.velocity = Vec::Zero();
  ramp.velocity[0] = -0.05;
  w.walls.push_back(ramp);
  if constexpr (D == 3) {
    Wall<D> drum;
    drum.name = "drum";
    drum.material = 1;
    drum.point = Vec(0.05, 0.05, 0.0);
    drum.set_cylinder(0.08);
    w.walls.push_back(drum);
  }
}

// The test beds' materials: soft glass grains (0) and stiff steel walls (1), rolling friction
// `mu_r` on both. Returns the glass.
inline Material add_glass_and_steel(MaterialTable& table, double mu_r = 0.0) {
  Material glass;
  glass.name = "glass";
  glass.density = 2500.0;
  glass.young = 5.0e6;
  glass.poisson = 0.25;
  glass.restitution = 0.6;
  glass.friction = 0.4;
  glass.rolling_friction = mu_r;
  Material steel = glass;
  steel.name = "steel";
  steel.young = 2.0e8;
  table.add(glass);
  table.add(steel);
  table.finalize();
  return glass;
}

// A small, jittered, slightly overlapping packing on a floor, with gravity, a fixed grain,
// a moving tilted wall, (3D) a drum, and a non-empty id free list. `with_grains = false`
// gives the world a resumed run builds from its scenario before loading a snapshot;
// `rolling`, rolling resistance (mu_r = 0.1, the lists carrying springs).
template <int D>
World<D> make_world(bool with_grains = true, bool rolling = false) {
  using Vec = typename Space<D>::Vec;
  World<D> w;
  const Material glass = add_glass_and_steel(w.materials, rolling ? 0.1 : 0.0);
  if (rolling) {
    w.model.rolling = RollingModel::kEpsd;
    w.neighbors.rolling = true;
  }
  w.dt = 1.0e-5;
  w.gravity[D - 1] = -9.81;
  w.rng.reseed(42);
  add_walls(w);
  w.neighbors.skin = 0.04 * kBedR;
  w.neighbors.domain_lo = Vec::Constant(-0.03);
  w.neighbors.domain_lo[D - 1] = 0.0;
  w.neighbors.domain_hi = Vec::Constant(0.13);
  w.neighbors.domain_hi[D - 1] = 0.1;
  if (!with_grains) return w;
  const int layers = D == 3 ? 3 : 4, nx = D == 3 ? 4 : 6;
  const int ny = D == 3 ? 4 : 1;
  for (int l = 0; l < layers; ++l) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        Vec x = Vec::Constant(0.03 + 1.98 * kBedR * j);
        x[0] = 0.03 + 1.98 * kBedR * i + w.rng.uniform(-1e-5, 1e-5);
        x[D - 1] = 0.98 * kBedR + 1.98 * kBedR * l;
        const double r = kBedR * (1.0 + w.rng.uniform(-0.01, 0.01));
        const auto id = w.particles.add(x, r, glass.density, 0, w.thickness);
        const auto k = w.particles.ids.slot(id);
        for (int d = 0; d < D; ++d) w.particles.v[k][d] = w.rng.uniform(-0.01, 0.01);
      }
    }
  }
  Vec side = Vec::Constant(0.03);
  side[0] = 0.03 - 1.98 * kBedR;
  side[D - 1] = 0.98 * kBedR;
  w.particles.add(side, kBedR, glass.density, 0, w.thickness, /*is_fixed=*/true);
  // Two grains removed again, then one added: a reused id of generation 1 and a free entry.
  Vec top = Vec::Constant(0.05);
  top[D - 1] = 0.09;
  w.particles.add(top, kBedR, glass.density, 0, w.thickness);
  w.particles.add(top + Vec::Constant(3 * kBedR), kBedR, glass.density, 0, w.thickness);
  remove_last(w.particles);
  remove_last(w.particles);
  w.particles.add(top, kBedR, glass.density, 0, w.thickness);
  return w;
}

}  // namespace sable::test
