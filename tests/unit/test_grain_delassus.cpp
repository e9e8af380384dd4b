// The grains' assembled Delassus matrix (cd/grain_delassus.hpp) against the rigid-body
// mechanics written out here: random grains (one fixed), random contacts between them and
// with walls, random frames, arms and impulses r; W r from the assembled blocks must equal
// the contact velocities the impulses produce when applied body by body (dv = m^-1 P,
// domega = I^-1 x P, u = F^T (v_i + omega_i x x_i - v_j - omega_j x x_j)), to 1e-12 relative:
// the same arithmetic in another order.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <vector>

#include "sable/cd/grain_delassus.hpp"
#include "sable/core/rng.hpp"

namespace {

using sable::Rng;

// 3D: v x w; 2D: the scalar z component, and the planar velocity of a spin w at arm x.
double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

template <int D>
void check_assembly(std::uint64_t seed) {
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  Rng rng(seed);
  const auto rvec = [&] {
    Vec v;
    for (int k = 0; k < D; ++k) v[k] = rng.uniform(-1.0, 1.0);
    return v;
  };
  sable::ParticleStore<D> p;
  const int grains = 8;
  for (int g = 0; g < grains; ++g) {
    p.add(rvec(), rng.uniform(0.5, 1.5), rng.uniform(1000.0, 3000.0), 0, 1.0);
    if (g == 3) {  // a fixed grain: it moves for nobody
      p.inv_mass[g] = 0.0;
      p.inv_inertia[g] = 0.0;
    }
  }
  typename sable::CdSolver<D>::Contacts c;
  const int contacts = 20;
  for (int a = 0; a < contacts; ++a) {
    const bool wall = a % 5 == 4;
    const auto i = static_cast<std::uint32_t>(rng.below(grains));
    auto j = static_cast<std::uint32_t>(rng.below(grains));
    if (!wall && j == i) j = (i + 1) % grains;
    Mat F;  // a random orthonormal frame (columns n, t...)
    if constexpr (D == 3) {
      F = Eigen::Quaterniond(Eigen::Vector4d(rng.uniform(-1, 1), rng.uniform(-1, 1),
                                             rng.uniform(-1, 1), rng.uniform(-1, 1))
                                 .normalized())
              .toRotationMatrix();
    } else {
      F = Eigen::Rotation2Dd(rng.uniform(0.0, 6.3)).toRotationMatrix();
    }
    c.i.push_back(i);
    c.partner.push_back(wall ? 0 : j);
    c.wall.push_back(wall ? 1 : 0);
    c.source.push_back(static_cast<std::uint32_t>(a));
    c.frame.push_back(F);
    c.arm_i.push_back(rvec());
    c.arm_j.push_back(rvec());
    c.W.push_back(Mat::Identity());
    c.mu.push_back(0.5);
    c.gap.push_back(0.0);
    c.r.push_back(Vec::Zero());
  }
  std::vector<Vec> q(contacts, Vec::Zero());
  sable::cd::MatrixProblem<D> mp = sable::cd::assemble_grain_problem<D>(c, p, q);
  std::vector<Vec> r(contacts);
  for (int a = 0; a < contacts; ++a) {
    r[a] = rvec();
    mp.apply(static_cast<std::size_t>(a), r[a]);
  }
  // Body by body.
  using Spin = std::conditional_t<D == 3, Eigen::Vector3d, double>;
  std::vector<Vec> dv(grains, Vec::Zero());
  std::vector<Spin> dw(grains);
  for (auto& w : dw) {
    if constexpr (D == 3)
      w.setZero();
    else
      w = 0.0;
  }
  const auto push = [&](std::uint32_t g, const Vec& P, const Vec& arm) {
    dv[g] += p.inv_mass[g] * P;
    if constexpr (D == 3)
      dw[g] += p.inv_inertia[g] * arm.cross(P);
    else
      dw[g] += p.inv_inertia[g] * cross2(arm, P);
  };
  const auto point_velocity = [&](std::uint32_t g, const Vec& arm) -> Vec {
    if constexpr (D == 3)
      return dv[g] + dw[g].cross(arm);
    else
      return dv[g] + dw[g] * Vec(-arm.y(), arm.x());
  };
  for (int a = 0; a < contacts; ++a) {
    const Vec P = c.frame[a] * r[a];
    push(c.i[a], P, c.arm_i[a]);
    if (!c.wall[a]) push(c.partner[a], -P, c.arm_j[a]);
  }
  double worst = 0.0, scale = 0.0;
  for (int a = 0; a < contacts; ++a) {
    Vec vrel = point_velocity(c.i[a], c.arm_i[a]);
    if (!c.wall[a]) vrel -= point_velocity(c.partner[a], c.arm_j[a]);
    const Vec u = c.frame[a].transpose() * vrel;
    worst = std::max(worst, (mp.velocity(static_cast<std::size_t>(a)) - u).cwiseAbs().maxCoeff());
    scale = std::max(scale, u.cwiseAbs().maxCoeff());
  }
  EXPECT_GT(scale, 0.0);
  EXPECT_LE(worst, 1e-12 * scale);
  // W is symmetric: the map of a conservative (Gram) form, H M^-1 H^T.
  for (std::size_t a = 0; a < mp.size(); ++a)
    for (std::size_t k = mp.row_ptr()[a]; k < mp.row_ptr()[a + 1]; ++k) {
      const std::size_t b = mp.cols()[k];
      for (std::size_t l = mp.row_ptr()[b]; l < mp.row_ptr()[b + 1]; ++l) {
        if (mp.cols()[l] != a) continue;
        EXPECT_LE((mp.blocks()[k] - mp.blocks()[l].transpose()).cwiseAbs().maxCoeff(),
                  1e-12 * mp.blocks()[k].cwiseAbs().maxCoeff() + 1e-300);
      }
    }
}

TEST(GrainDelassus, AssembledWMatchesBodyByBodyImpulses3D) {
  for (std::uint64_t seed : {1u, 2u, 3u}) check_assembly<3>(seed);
}

TEST(GrainDelassus, AssembledWMatchesBodyByBodyImpulses2D) {
  for (std::uint64_t seed : {1u, 2u, 3u}) check_assembly<2>(seed);
}

}  // namespace
