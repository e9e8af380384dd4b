// Particle storage: structure of arrays, one std::vector per field, indexed by slot.
//
// Hot fields (position, velocity, force, ...) are what the step touches every time; the id,
// material and flags are read when needed. Slots are dense [0, size()); a grain's stable
// ParticleId maps to its slot through the IdRegistry. No field is allocated per grain: adding
// grains grows each vector, and the step itself never allocates.
#pragma once

#include <cstdint>
#include <vector>

#include "sable/core/ids.hpp"
#include "sable/core/material.hpp"
#include "sable/core/space.hpp"

namespace sable {

enum ParticleFlags : std::uint8_t {
  kFixed = 1u << 0,  // never moves: infinite mass for contacts, skipped by integration
  // A copy of a grain another process steps (MPI, world/domain.hpp): in contacts like any
  // grain, but not kicked, drifted or checked here; its state comes from its owner.
  kGhost = 1u << 1,
};

// The shape of the grain: a disk (2D) or sphere (3D), or a convex polyhedron (3D) whose
// geometry, volume and principal inertia are row `shape_index` of the world's shape table
// (world/grain_shapes.hpp). Its `radius` is then its bounding sphere's, about its centroid
// (what the cell lists and the lists' gap tests need), and its `inv_inertia` the largest of its
// principal inverse moments (a bound, for what asks for one number: the body-frame tensor is
// the shape table's).
enum class ShapeKind : std::uint8_t { kRound = 0, kPolyhedron = 1 };

// A new per-grain field goes into for_each_array() (GrainReorder moves the grains' slots
// through it), add(), the snapshot (io/snapshot_write.cpp, read by io/snapshot.cpp) and the state
// hash (world/state_hash.hpp); the static_assert below the struct stops the build until the count
// there is raised.
template <int D>
struct ParticleStore {
  using S = Space<D>;
  using Vec = typename S::Vec;
  using Rot = typename S::Rot;

  // --- hot: touched every step
  std::vector<Vec> x;      // centre position (m)
  std::vector<Vec> v;      // velocity (m/s)
  std::vector<Rot> omega;  // angular velocity (rad/s)
  std::vector<Vec> f;      // force (N)
  std::vector<Rot> t;      // torque (N m)
  std::vector<double> radius;
  std::vector<double> inv_mass;     // 0 for fixed grains
  std::vector<double> inv_inertia;  // 0 for fixed grains
  std::vector<MaterialIndex> material;
  std::vector<std::uint8_t> flags;
  // --- warm: integrated, rarely read
  std::vector<typename S::Orientation> q;
  std::vector<double> mass;  // physical mass even for fixed grains (outputs, analysis)
  // --- cold
  std::vector<ParticleId> id;
  std::vector<ShapeKind> shape;
  std::vector<std::uint32_t> shape_index;  // a polyhedron's row of the shape table; 0 if round
  // The grain's place in the order of the slots: its cell at the last spatial reorder
  // (world/reorder.hpp; kUnsortedKey before the first), then its id's index. The slots always
  // follow (order_key, id.index); a process holding some of the grains (MPI) puts each one it
  // receives where this key says, so that every grain meets its partners in the same order
  // however the grains are split.
  std::vector<std::uint64_t> order_key;
  IdRegistry ids;

  std::size_t size() const { return x.size(); }

  // f(array) for every per-grain array (all but `ids`): what must move together when the
  // slots are permuted (world/reorder.cpp).
  template <class Visit>
  void for_each_array(Visit&& visit) {
    visit(x);
    visit(v);
    visit(omega);
    visit(f);
    visit(t);
    visit(radius);
    visit(inv_mass);
    visit(inv_inertia);
    visit(material);
    visit(flags);
    visit(q);
    visit(mass);
    visit(id);
    visit(shape);
    visit(shape_index);
    visit(order_key);
  }
  static constexpr std::size_t kArrays = 16;  // how many for_each_array() visits
  static constexpr std::uint64_t kUnsortedKey = ~std::uint64_t{0};  // order_key before a sort
  bool fixed(std::size_t i) const { return (flags[i] & kFixed) != 0; }
  bool polyhedron(std::size_t i) const { return shape[i] == ShapeKind::kPolyhedron; }

  // Append a round grain. `thickness` is the out-of-plane depth of a 2D run (mass per
  // thickness); it is ignored in 3D.
  ParticleId add(const Vec& pos, double r, double density, MaterialIndex mat, double thickness,
                 bool is_fixed = false) {
    const auto slot = static_cast<std::uint32_t>(size());
    const double m = grain_mass(r, density, thickness);
    x.push_back(pos);
    v.push_back(S::zero());
    omega.push_back(S::zero_rot());
    f.push_back(S::zero());
    t.push_back(S::zero_rot());
    radius.push_back(r);
    mass.push_back(m);
    inv_mass.push_back(is_fixed ? 0.0 : 1.0 / m);
    inv_inertia.push_back(is_fixed ? 0.0 : 1.0 / (inertia_factor() * m * r * r));
    material.push_back(mat);
    flags.push_back(is_fixed ? kFixed : 0);
    q.push_back(S::identity());
    shape.push_back(ShapeKind::kRound);
    shape_index.push_back(0);
    // Grains are added in id order (a fresh registry gives index = slot), after any grain
    // already sorted: a key above every cell (reorder.cpp sets it at the next sort).
    order_key.push_back(kUnsortedKey);
    id.push_back(ids.create(slot));
    return id.back();
  }

  // Append a polyhedral grain (3D), its centroid at `pos`, its body frame turned by `orientation`:
  // `mass` and the principal moments `inertia` (kg m^2, along the body axes) come from its
  // shape, row `index` of the world's table (mass m), `bounding_radius` is the shape's radius about
  // its centroid (world/grain_shapes.hpp, add_polyhedral_grain(), fills these in).
  ParticleId add_polyhedron(const Vec& pos, const typename S::Orientation& orientation,
                            std::uint32_t index, double bounding_radius, double m,
                            const Vec& inertia, MaterialIndex mat,
                            bool is_fixed = false) requires(D == 3) {
    const ParticleId pid = add(pos, bounding_radius, 0.0, mat, 1.0, is_fixed);
    const std::size_t k = size() - 1;
    q[k] = orientation;
    mass[k] = m;
    inv_mass[k] = is_fixed ? 0.0 : 1.0 / m;
    inv_inertia[k] = is_fixed ? 0.0 : 1.0 / inertia.minCoeff();
    shape[k] = ShapeKind::kPolyhedron;
    shape_index[k] = index;
    return pid;
  }

  // I = c m r^2: c = 2/5 for a solid sphere, 1/2 for a disk (a cylinder about its axis).
  static constexpr double inertia_factor() { return D == 3 ? 0.4 : 0.5; }
  static double grain_mass(double r, double density, double thickness) {
    constexpr double pi = 3.14159265358979323846;
    return D == 3 ? density * 4.0 / 3.0 * pi * r * r * r : density * pi * r * r * thickness;
  }
};

// A per-grain array added to ParticleStore changes its size: this stops the build until the
// array is in for_each_array() (and add(), the snapshot, the state hash) and kArrays counts it.
static_assert(sizeof(ParticleStore<3>) ==
                  ParticleStore<3>::kArrays * sizeof(std::vector<double>) + sizeof(IdRegistry),
              "a new per-grain array: list it in ParticleStore::for_each_array() (see above)");
static_assert(sizeof(ParticleStore<2>) ==
                  ParticleStore<2>::kArrays * sizeof(std::vector<double>) + sizeof(IdRegistry),
              "a new per-grain array: list it in ParticleStore::for_each_array() (see above)");

}  // namespace sable
