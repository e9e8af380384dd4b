// Materials and the per-pair contact parameters derived from them.
//
// A material carries the bulk properties a user knows (density, Young's modulus, Poisson ratio,
// restitution, friction). Contact laws never read materials directly: they read a PairParams,
// precomputed once for every (material, material) pair, so the hot loop does one table lookup.
// Pair overrides (friction, restitution) replace the mixed values for one pair only.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sable {

using MaterialIndex = std::uint16_t;

struct Material {
  std::string name;
  double density = 0.0;           // kg/m^3 (2D: mass per unit area is density * thickness)
  double young = 0.0;             // Pa
  double poisson = 0.0;           // [0, 0.5)
  double restitution = 1.0;       // (0, 1]
  double friction = 0.0;          // Coulomb coefficient, >= 0
  double rolling_friction = 0.0;  // mu_r of the rolling sub-model (contact/rolling.hpp), >= 0
  bool rigid = false;  // infinite stiffness (a wall that does not deform): zero compliance
};

struct PairOverride {
  MaterialIndex a = 0, b = 0;
  std::optional<double> friction;
  std::optional<double> restitution;
  std::optional<double> rolling_friction;
  std::optional<double> young_star;  // effective modulus Y* directly, Pa
};

// Parameters of one material pair, as the contact kernels read them.
struct PairParams {
  double y_star = 0.0;  // 1 / ((1-nu_i^2)/Y_i + (1-nu_j^2)/Y_j)
  double g_star = 0.0;  // 1 / (2(2-nu_i)(1+nu_i)/Y_i + 2(2-nu_j)(1+nu_j)/Y_j)
  double beta = 0.0;    // ln e / sqrt(ln^2 e + pi^2); 0 for e = 1
  double restitution = 1.0;
  double friction = 0.0;
  double rolling_friction = 0.0;  // mu_r: the rolling couple is at most mu_r R* F_n
  double st_over_sn_sqrt = 0.0;   // sqrt(4 G* / Y*): Hertz gamma_t / gamma_n, precomputed
};

// The pair table as plain pointer and size, for hot loops (dem/dem_solver_impl.hpp: a local copy
// cannot be aliased by the loop's stores, so the compiler keeps it in registers).
struct PairTableView {
  const PairParams* table;
  std::size_t n;
  const PairParams& operator()(MaterialIndex a, MaterialIndex b) const {
    return table[static_cast<std::size_t>(a) * n + b];
  }
};

class MaterialTable {
 public:
  MaterialIndex add(Material m);
  void add_override(const PairOverride& o);
  // Recompute the pair table; call after all materials and overrides are in.
  void finalize();

  std::size_t size() const { return materials_.size(); }
  const Material& operator[](MaterialIndex i) const { return materials_[i]; }
  std::optional<MaterialIndex> find(const std::string& name) const;
  const PairParams& pair(MaterialIndex a, MaterialIndex b) const { return pair_view()(a, b); }
  PairTableView pair_view() const { return {pairs_.data(), materials_.size()}; }
  const std::vector<Material>& materials() const { return materials_; }
  const std::vector<PairOverride>& overrides() const { return overrides_; }

  static PairParams mix(const Material& a, const Material& b);
  static double beta_from_restitution(double e);

 private:
  std::vector<Material> materials_;
  std::vector<PairOverride> overrides_;
  std::vector<PairParams> pairs_;
};

}  // namespace sable
