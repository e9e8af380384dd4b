// Coarse-grained continuum fields (analysis/coarse_grain.hpp): the exact sphere-kernel
// weights, the normalisation of every kernel, the field integrals (mass, virial), the derived
// quantities, averaging, layouts, outputs and input errors.
#include "sable/analysis/coarse_grain.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "sable/core/error.hpp"

namespace fs = std::filesystem;
using namespace sable;

namespace {

constexpr double kPi = std::numbers::pi;
const CgKernel kAll[] = {CgKernel::Sphere, CgKernel::Gaussian, CgKernel::Lucy};

// Grains at rest at `x` with radii `r`, density 2500 kg/m^3 (2D: disks 0.01 m thick).
template <int D>
Sample<D> grains(const std::vector<typename Space<D>::Vec>& x, const std::vector<double>& r) {
  Sample<D> s;
  s.thickness = 0.01;
  s.x = x;
  s.radius = r;
  for (double ri : r) {
    const double vol = D == 3 ? 4.0 / 3.0 * kPi * ri * ri * ri : kPi * ri * ri * s.thickness;
    s.volume.push_back(vol);
    s.mass.push_back(2500.0 * vol);
  }
  s.v.assign(x.size(), Space<D>::Vec::Zero());
  s.a.assign(x.size(), Space<D>::Vec::Zero());
  return s;
}

template <int D>
FieldSpec<D> grid_spec(CgKernel k, double width, const typename Space<D>::Vec& lo,
                       const typename Space<D>::Vec& hi, double spacing) {
  FieldSpec<D> spec;
  spec.kernel = k;
  spec.width = width;
  spec.box.lo = lo;
  spec.box.hi = hi;
  spec.spacing = spacing;
  return spec;
}

template <int D>
FieldSpec<D> grid_spec(CgKernel k, double width, double lo, double hi, double spacing) {
  return grid_spec<D>(k, width, Space<D>::Vec::Constant(lo), Space<D>::Vec::Constant(hi), spacing);
}

// The exception message of f(), or "" if it does not throw InputError.
template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// Guards: kernel names round-trip; an unknown name is refused naming the key and the choices.
TEST(CoarseGrainKernel, Names) {
  for (CgKernel k : kAll) EXPECT_EQ(parse_cg_kernel(cg_kernel_name(k)), k);
  const std::string msg = input_error([] { parse_cg_kernel("tophat", "analysis.kernel"); });
  for (const char* word : {"analysis.kernel", "tophat", "\"sphere\"", "\"gaussian\"", "\"lucy\""})
    EXPECT_NE(msg.find(word), std::string::npos) << msg;
}

// Guards: Guillard et al. eq. (3), W = the fraction of the branch inside the ball, on cases
// known by hand; closed-form arithmetic, so 1e-12.
TEST(CoarseGrainKernel, SegmentFractionInBall) {
  using V3 = Eigen::Vector3d;
  using V2 = Eigen::Vector2d;
  const V3 c(1, 2, 3);
  const double R = 2.0;
  // Fully inside.
  EXPECT_NEAR(cg::segment_fraction_in_ball<3>(c, V3(0.5, 0.5, 0.5), c, R), 1.0, 1e-12);
  // From the centre to 2 R outwards: half inside.
  EXPECT_NEAR(cg::segment_fraction_in_ball<3>(c, V3(0, 0, 2 * R), c, R), 0.5, 1e-12);
  // Crossing the whole ball through its centre, from -2R to 2R: half inside.
  EXPECT_NEAR(cg::segment_fraction_in_ball<3>(c - V3(4, 0, 0), V3(8, 0, 0), c, R), 0.5, 1e-12);
  // A chord at distance 1 from the centre: length 2 sqrt(R^2 - 1) of 10.
  EXPECT_NEAR(cg::segment_fraction_in_ball<3>(c + V3(-5, 1, 0), V3(10, 0, 0), c, R),
              2.0 * std::sqrt(3.0) / 10.0, 1e-12);
  // Tangent and missing: 0.
  EXPECT_EQ(cg::segment_fraction_in_ball<3>(c + V3(-5, R, 0), V3(10, 0, 0), c, R), 0.0);
  EXPECT_EQ(cg::segment_fraction_in_ball<3>(c + V3(3, 0, 0), V3(1, 0, 0), c, R), 0.0);
  // Zero length: 1 inside, 0 outside.
  EXPECT_EQ(cg::segment_fraction_in_ball<3>(c, V3::Zero(), c, R), 1.0);
  EXPECT_EQ(cg::segment_fraction_in_ball<3>(c + V3(3, 0, 0), V3::Zero(), c, R), 0.0);
  // 2D: half inside, and a segment ending on the circle from inside.
  EXPECT_NEAR(cg::segment_fraction_in_ball<2>(V2(0, 0), V2(0, 2), V2(0, 0), 1.0), 0.5, 1e-12);
  EXPECT_NEAR(cg::segment_fraction_in_ball<2>(V2(0.5, 0), V2(0.5, 0), V2(0, 0), 1.0), 1.0, 1e-12);
}

// Guards: Guillard et al. eq. (4), the exact lens of two balls; 1e-12 relative (closed forms).
TEST(CoarseGrainKernel, BallIntersection) {
  const double r = 0.7;
  for (double d : {0.1, 0.5, 1.0, 1.3}) {
    // Two equal spheres: pi (4r + d)(2r - d)^2 / 12.
    const double lens3 = kPi * (4 * r + d) * (2 * r - d) * (2 * r - d) / 12.0;
    EXPECT_NEAR(cg::ball_intersection<3>(r, r, d), lens3, 1e-12 * lens3) << d;
    // Two equal disks: 2 r^2 acos(d / 2r) - (d / 2) sqrt(4 r^2 - d^2).
    const double lens2 =
        2 * r * r * std::acos(d / (2 * r)) - 0.5 * d * std::sqrt(4 * r * r - d * d);
    EXPECT_NEAR(cg::ball_intersection<2>(r, r, d), lens2, 1e-12 * lens2) << d;
  }
  // A grain entirely inside the ball (either order): its whole volume; disjoint: 0.
  EXPECT_NEAR(cg::ball_intersection<3>(2.0, 0.5, 1.2), 4.0 / 3.0 * kPi * 0.125, 1e-12);
  EXPECT_NEAR(cg::ball_intersection<3>(0.5, 2.0, 1.5), 4.0 / 3.0 * kPi * 0.125, 1e-12);
  EXPECT_NEAR(cg::ball_intersection<2>(2.0, 0.5, 1.2), kPi * 0.25, 1e-12);
  EXPECT_EQ(cg::ball_intersection<3>(1.0, 0.5, 1.5), 0.0);
  EXPECT_EQ(cg::ball_intersection<2>(1.0, 0.5, 1.6), 0.0);
  // Continuity at internal tangency (d = R - r): the lens formula meets the grain volume.
  EXPECT_NEAR(cg::ball_intersection<3>(2.0, 0.5, 1.5 + 1e-9), 4.0 / 3.0 * kPi * 0.125, 1e-8);
  EXPECT_NEAR(cg::ball_intersection<2>(2.0, 0.5, 1.5 + 1e-9), kPi * 0.25, 1e-8);
}

// Guards: each kernel's point weight integrates to exactly 1 over its support (radial
// Simpson rule with 20,000 intervals: error < 1e-9 for the smooth part; the truncated
// Gaussian's jump at 3w sits on the last node, so 1e-9 holds too). 2D weights carry 1/thickness.
TEST(CoarseGrainKernel, NormalisationIsOne) {
  for (CgKernel k : kAll) {
    for (int dim : {2, 3}) {
      const double w = 1.3e-3, thick = 0.02;
      double integral = 0.0;
      const int n = 20000;
      auto radial = [&](double r) {
        if (dim == 3) {
          const cg::Kernel<3> kern(k, w, thick);
          return r >= kern.reach() ? 0.0 : kern.point(r * r) * 4.0 * kPi * r * r;
        }
        const cg::Kernel<2> kern(k, w, thick);
        // Just inside the support for the last node: the left limit of the jump.
        return r >= kern.reach() ? 0.0 : kern.point(r * r) * 2.0 * kPi * r * thick;
      };
      const double reach = k == CgKernel::Gaussian ? 3 * w : w;
      const double h = reach / n;
      for (int q = 0; q <= n; ++q) {
        const double r = q == n ? reach * (1 - 1e-15) : q * h;
        const double c = (q == 0 || q == n) ? 1.0 : (q % 2 == 1 ? 4.0 : 2.0);
        integral += c * radial(r);
      }
      integral *= h / 3.0;
      EXPECT_NEAR(integral, 1.0, 1e-9) << cg_kernel_name(k) << " " << dim << "D";
    }
  }
}

// Guards: the Gaussian's analytic normalisation against its defining integral, and Lucy's
// constants (105 / 16 pi, 5 / pi), already covered above; here the closed forms themselves.
TEST(CoarseGrainKernel, GaussianNormClosedForm) {
  // Truncation at 3 sigma keeps 1 - e^{-9/2} of the 2D mass and 97.07 % of the 3D mass
  // (chi distribution with 3 dof at 3: 0.970709); tolerance 1e-6, the digits quoted.
  EXPECT_NEAR(cg::gaussian_norm<2>(1.0) / (2 * kPi), 1.0 - std::exp(-4.5), 1e-15);
  EXPECT_NEAR(cg::gaussian_norm<3>(1.0) / std::pow(2 * kPi, 1.5), 0.970709, 1e-6);
}

// Guards: one grain on a fine grid: the sum over nodes of rho times the cell volume is the
// grain's mass, and of phi times it the grain's volume. Grid spacing w/8 over the grain's
// support plus a cell: the midpoint rule errs by 1.1e-4 (sphere), 1.5e-4 (Gaussian, whose
// cut at 3w is a jump), 2e-5 (Lucy), measured; 1e-3 bounds all three in 2D and 3D.
template <int D>
void check_mass(CgKernel k) {
  using Vec = typename Space<D>::Vec;
  Vec x = Vec::Constant(0.0052);
  x[0] = 0.0101;
  const Sample<D> s = grains<D>({x}, {0.75e-3});
  const double w = 2e-3, h = w / 8;
  const double reach = cg::Kernel<D>(k, w, s.thickness).grain_reach(0.75e-3) + h;
  const Fields<D> f = coarse_grain(s, grid_spec<D>(k, w, x.array() - reach, x.array() + reach, h));
  EXPECT_NEAR(f.mass_on_grid() / s.mass[0], 1.0, 1e-3) << cg_kernel_name(k) << " " << D << "D";
  double vol = 0.0;
  for (double p : f.volume_fraction) vol += p * f.cell_volume();
  EXPECT_NEAR(vol / s.volume[0], 1.0, 1e-3) << cg_kernel_name(k) << " " << D << "D";
  EXPECT_EQ(f.mass, s.mass[0]);  // the exact total is the sample's own number
}

TEST(CoarseGrainFields, GridIntegralOfDensityIsMass) {
  for (CgKernel k : kAll) {
    check_mass<2>(k);
    check_mass<3>(k);
  }
}

namespace {

// Three grains, two pair contacts and a wall contact, with tangential parts: a virial with
// every component non-zero.
template <int D>
Sample<D> contact_sample() {
  using Vec = typename Space<D>::Vec;
  Vec a = Vec::Constant(0.004), b = a, c = a;
  b[0] += 1.9e-3;
  b[1] += 0.4e-3;
  c[D - 1] += 2.0e-3;
  Sample<D> s = grains<D>({a, b, c}, {1e-3, 1e-3, 1.1e-3});
  Vec f1 = Vec::Constant(0.3), f2 = Vec::Constant(-0.2), f3 = Vec::Constant(0.1);
  f1[0] = -2.0;      // i = a pushed away from b
  f2[D - 1] = -1.5;  // i = a pushed away from c
  f3[D - 1] = 0.8;   // the floor pushes c up
  Vec arm = Vec::Zero();
  arm[D - 1] = -1.1e-3;
  s.contacts.push(0, 1, false, (b - a).normalized(), f1, Vec::Zero(), Vec::Zero(), b - a, 1e-5,
                  0.5);
  s.contacts.push(0, 2, false, (c - a).normalized(), f2, Vec::Zero(), Vec::Zero(), c - a, 1e-5,
                  0.5);
  s.contacts.push(2, 0, true, -Vec::Unit(D - 1), f3, arm, Vec::Zero(), arm, 1e-5, 0.5);
  return s;
}

template <int D>
void check_virial(CgKernel k) {
  const Sample<D> s = contact_sample<D>();
  typename Fields<D>::Mat exact = Fields<D>::Mat::Zero();
  for (std::size_t c = 0; c < s.contacts.size(); ++c)
    exact -= s.contacts.force[c] * s.contacts.branch[c].transpose();
  // Grid spacing w/8 over the contacts' extent plus the kernel's reach and a cell.
  const double w = 1.5e-3, h = w / 8, reach = cg::Kernel<D>(k, w, s.thickness).reach() + h;
  const Fields<D> f = coarse_grain(s, grid_spec<D>(k, w, 0.004 - 1.1e-3 - reach, 0.006 + reach, h));
  // The exact sum is the sample's virial to round-off.
  EXPECT_LT((f.virial - exact).norm(), 1e-15 * exact.norm());
  // Midpoint rule at w/8. The sphere's weight (branch fraction in a ball) has kinks where
  // the ball meets the branch's ends: measured 2.9e-3 (2D), 3.1e-3 (3D), so 5e-3; the smooth
  // Gaussian and Lucy line integrals: measured 3.4e-5 and 4.7e-6, so 2e-4.
  const double tol = k == CgKernel::Sphere ? 5e-3 : 2e-4;
  EXPECT_LT((f.virial_on_grid() - exact).norm(), tol * exact.norm())
      << cg_kernel_name(k) << " " << D << "D\n"
      << f.virial_on_grid() << "\n"
      << exact;
}

}  // namespace

// Guards: the integral of the contact-stress field is the virial -sum f (x) l (walls
// included, with their branch x_i -> contact point), for every kernel, 2D and 3D.
TEST(CoarseGrainFields, GridIntegralOfContactStressIsVirial) {
  for (CgKernel k : kAll) {
    check_virial<2>(k);
    check_virial<3>(k);
  }
}

// Guards: sign convention: two grains pressed together give a positive (compressive) stress
// along their branch, and a sphere kernel wholly containing the branch gives exactly
// sigma = -f (x) l / V_R (1e-12: closed form).
TEST(CoarseGrainFields, CompressionIsPositive) {
  Sample<3> s = grains<3>({{0, 0, 0}, {1.9e-3, 0, 0}}, {1e-3, 1e-3});
  s.contacts.push(0, 1, false, {1, 0, 0}, {-3.0, 0, 0}, {0.95e-3, 0, 0}, {-0.95e-3, 0, 0},
                  {1.9e-3, 0, 0}, 1e-4, 0.5);
  FieldSpec<3> spec;
  spec.layout = FieldLayout::Line;
  spec.from = {0.95e-3, 0, 0};
  spec.points = 1;
  spec.kernel = CgKernel::Sphere;
  spec.width = 5e-3;
  const Fields<3> f = coarse_grain(s, spec);
  const double vr = 4.0 / 3.0 * kPi * 125e-9;
  EXPECT_NEAR(f.contact_stress[0](0, 0), 3.0 * 1.9e-3 / vr, 1e-12 * 3.0 * 1.9e-3 / vr);
  EXPECT_GT(f.pressure[0], 0.0);  // compression positive
  // Both grains lie inside the ball: rho = total mass / V_R, phi = total volume / V_R.
  EXPECT_NEAR(f.density[0], (s.mass[0] + s.mass[1]) / vr, 1e-12 * f.density[0]);
  EXPECT_NEAR(f.volume_fraction[0], (s.volume[0] + s.volume[1]) / vr, 1e-12);
}

// Guards: the kinetic stress is the fluctuation about the local mean velocity: a uniform
// translation gives none; two equal grains moving +-u around a drift V give rho v = rho V and
// sigma_k = rho u u (exactly, 1e-12 relative), positive like a gas pressure.
TEST(CoarseGrainFields, KineticStress) {
  Sample<2> s = grains<2>({{0, 0}, {1e-4, 0}}, {1e-3, 1e-3});
  const Eigen::Vector2d V(0.3, -0.1), u(0.2, 0.5);
  s.v = {V + u, V - u};
  FieldSpec<2> spec;
  spec.layout = FieldLayout::Line;
  spec.points = 1;
  spec.from = {5e-5, 0};  // equidistant: equal weights
  spec.kernel = CgKernel::Lucy;
  spec.width = 3e-3;
  Fields<2> f = coarse_grain(s, spec);
  const double rho = f.density[0];
  EXPECT_LT((f.velocity[0] - V).norm(), 1e-12 * V.norm());
  const Eigen::Matrix2d want = rho * u * u.transpose();
  EXPECT_LT((f.kinetic_stress[0] - want).norm(), 1e-12 * want.norm());
  s.v = {V, V};
  f = coarse_grain(s, spec);
  // Round-off of second_moment - rho v v with |m v v w| ~ rho |V|^2: 1e-12 of that.
  EXPECT_LT(f.kinetic_stress[0].norm(), 1e-12 * rho * V.squaredNorm());
}

// Guards: pressure, principal values (descending) and directions (signed: largest component
// positive), maximum shear, antisymmetry and the ellipsoid sigma / P of a known tensor.
TEST(CoarseGrainFields, DerivedQuantities) {
  Fields<3> f;
  f.nodes = {Eigen::Vector3d::Zero()};
  f.density = {0.0};
  f.volume_fraction = {0.0};
  f.momentum = {Eigen::Vector3d::Zero()};
  f.second_moment = {Eigen::Matrix3d::Zero()};
  // diag(5, 3, 1) rotated by 30 degrees about z, plus an antisymmetric part of norm sqrt 2 * 0.5.
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(kPi / 6, Eigen::Vector3d::UnitZ()).matrix();
  Eigen::Matrix3d sigma = rot * Eigen::Vector3d(5, 3, 1).asDiagonal() * rot.transpose();
  Eigen::Matrix3d skew = Eigen::Matrix3d::Zero();
  skew(0, 2) = 0.5;
  skew(2, 0) = -0.5;
  f.contact_stress = {sigma + skew};
  finish(f);
  // Eigen's symmetric solver: accurate to ~1e-15 relative on a 3 x 3; 1e-12 leaves room.
  EXPECT_NEAR(f.pressure[0], 3.0, 1e-12);
  EXPECT_NEAR(f.principal[0][0], 5.0, 1e-12);
  EXPECT_NEAR(f.principal[0][1], 3.0, 1e-12);
  EXPECT_NEAR(f.principal[0][2], 1.0, 1e-12);
  EXPECT_NEAR(f.deviator[0], 2.0, 1e-12);
  EXPECT_NEAR(f.antisymmetry[0], std::sqrt(0.5), 1e-12);
  const Eigen::Vector3d major = f.directions[0].col(0);
  EXPECT_LT((major - rot.col(0)).norm(), 1e-12);  // (cos 30, sin 30, 0): largest > 0
  EXPECT_LT((f.ellipsoid[0] - sigma / 3.0).norm(), 1e-12);
  EXPECT_LT((f.stress[0] - sigma - skew).norm(), 1e-15);  // no kinetic part at rho = 0
}

// Guards: averaging adds the linear sums and derives velocity after averaging:
// v = (p1 + p2) / (rho1 + rho2), not the mean of velocities; fields on other nodes refuse.
TEST(CoarseGrainFields, AccumulateAndAverage) {
  Sample<2> s1 = grains<2>({{0.001, 0.001}, {0.003, 0.001}}, {1e-3, 1e-3});
  Sample<2> s2 = s1;
  s1.v[0] = {1.0, 0.0};
  s2.x[1] = {0.0035, 0.0012};
  s2.v[1] = {0.0, 2.0};
  const FieldSpec<2> spec = grid_spec<2>(CgKernel::Gaussian, 1e-3, 0.0, 0.004, 5e-4);
  const Fields<2> f1 = coarse_grain(s1, spec), f2 = coarse_grain(s2, spec);
  Fields<2> avg;
  accumulate(avg, f1);
  accumulate(avg, f2);
  EXPECT_EQ(avg.snapshots, 2);
  average(avg);
  for (std::size_t k = 0; k < avg.size(); ++k) {
    // Sums of two terms, halved: exact up to one rounding each (1e-15 relative).
    const double rho = 0.5 * (f1.density[k] + f2.density[k]);
    EXPECT_NEAR(avg.density[k], rho, 1e-15 * rho);
    if (rho > 0) {
      const Eigen::Vector2d v = (f1.momentum[k] + f2.momentum[k]) / (2 * rho);
      EXPECT_LT((avg.velocity[k] - v).norm(), 1e-12 * (v.norm() + 1e-300));
    }
  }
  EXPECT_NEAR(avg.mass, s1.total_mass(), 1e-15 * s1.total_mass());
  FieldSpec<2> other = spec;
  other.box.hi = {0.005, 0.004};
  Fields<2> bad = coarse_grain(s1, other);
  EXPECT_NE(input_error([&] { accumulate(avg, bad); }).find("other nodes"), std::string::npos);
}

// Guards: a line through grid nodes gives the same values there (same weights, same order of
// summation: bit-identical), and its nodes run from `from` to `to`, both included.
TEST(CoarseGrainFields, LineMatchesGrid) {
  const Sample<3> s = contact_sample<3>();
  const Fields<3> g = coarse_grain(s, grid_spec<3>(CgKernel::Lucy, 2e-3, 0.0, 0.008, 1e-3));
  FieldSpec<3> line = g.spec;
  line.layout = FieldLayout::Line;
  line.from = g.nodes[3 + 8 * (4 + 8 * 0)];  // x index 3, y index 4, z from 0 to 7
  line.to = g.nodes[3 + 8 * (4 + 8 * 7)];
  line.points = 8;
  const Fields<3> l = coarse_grain(s, line);
  ASSERT_EQ(l.size(), 8u);
  for (std::size_t k = 0; k < 8; ++k) {
    const std::size_t node = 3 + 8 * (4 + 8 * k);
    EXPECT_LT((l.nodes[k] - g.nodes[node]).norm(), 1e-17);  // a few ulps of 8 mm
    EXPECT_NEAR(l.density[k], g.density[node], 1e-12 * g.density[node] + 1e-300);
    EXPECT_LT((l.contact_stress[k] - g.contact_stress[node]).norm(),
              1e-12 * g.contact_stress[node].norm() + 1e-300);
  }
  const Table t = field_table(l);
  EXPECT_EQ(t.names.front(), "s_m");
  EXPECT_EQ(t.rows(), 8u);
  EXPECT_NEAR(t.columns[0].back(), (line.to - line.from).norm(), 1e-18);
  for (const char* name :
       {"x_m", "z_m", "density_kg_m3", "volume_fraction", "vz_m_s", "sigma_zz_Pa", "sigma_xy_Pa",
        "pressure_Pa", "deviator_Pa", "sigma_1_Pa", "sigma_3_Pa", "major_z", "antisymmetry_Pa"})
    EXPECT_NE(std::find(t.names.begin(), t.names.end(), name), t.names.end()) << name;
}

// Guards: grid layout: cell-centred nodes; spacing mode grows the box to whole cells of
// exactly `spacing`; unbounded sides come from the grains. Positions: 1e-15 (arithmetic).
TEST(CoarseGrainFields, GridLayout) {
  const Sample<2> s = grains<2>({{0.0, 0.0}, {0.01, 0.004}}, {1e-3, 1e-3});
  FieldSpec<2> spec;
  spec.kernel = CgKernel::Sphere;
  spec.width = 1e-3;
  spec.cells = {4, 2};
  Fields<2> f = coarse_grain(s, spec);  // box = grain bounds: [-1, 11] x [-1, 5] mm
  ASSERT_EQ(f.size(), 8u);
  EXPECT_NEAR(f.nodes[0][0], -1e-3 + 1.5e-3, 1e-15);
  EXPECT_NEAR(f.nodes[0][1], -1e-3 + 1.5e-3, 1e-15);
  EXPECT_NEAR(f.nodes[7][0], 11e-3 - 1.5e-3, 1e-15);
  EXPECT_NEAR(f.nodes[4][1], 5e-3 - 1.5e-3, 1e-15);  // x fastest: node 4 is (0, 1)
  EXPECT_NEAR(f.cell_volume(), 3e-3 * 3e-3 * 0.01, 1e-20);
  spec.cells = {0, 0};
  spec.spacing = 5e-3;  // 12 mm -> 3 cells (15 mm), 6 mm -> 2 cells (10 mm)
  f = coarse_grain(s, spec);
  EXPECT_EQ(f.counts[0], 3);
  EXPECT_EQ(f.counts[1], 2);
  EXPECT_NEAR(f.spec.box.lo[0], -2.5e-3, 1e-15);
  EXPECT_NEAR(f.spec.box.hi[1], 7e-3, 1e-15);
  EXPECT_NEAR(f.cell[0], 5e-3, 1e-15);
}

// Guards: every bad spec is refused with the key named.
TEST(CoarseGrainFields, BadInput) {
  const Sample<3> s = grains<3>({{0, 0, 0}}, {1e-3});
  auto refuses = [&](const FieldSpec<3>& spec, const std::string& key) {
    const std::string msg = input_error([&] { coarse_grain(s, spec); });
    EXPECT_NE(msg.find(key), std::string::npos) << key << ": \"" << msg << "\"";
  };
  const FieldSpec<3> good = grid_spec<3>(CgKernel::Sphere, 1e-3, -0.01, 0.01, 1e-3);
  EXPECT_NO_THROW(coarse_grain(s, good));
  FieldSpec<3> bad = good;
  bad.width = 0.0;
  refuses(bad, "width");
  bad = good;
  bad.spacing = -1.0;
  refuses(bad, "spacing");
  bad = good;
  bad.spacing = 0.0;
  bad.cells = {10, 0, 40};
  refuses(bad, "cells");
  bad = good;
  bad.cells = {10, 10, 40};  // and spacing too
  refuses(bad, "either cells or spacing");
  bad = good;
  bad.box.hi[2] = bad.box.lo[2];
  refuses(bad, "box");
  bad = good;
  bad.layout = FieldLayout::Line;
  bad.points = 0;
  refuses(bad, "points");
  bad.points = 3;  // from == to
  refuses(bad, "from/to");
}

// Guards: the .vti file: extents, origin at the first node, spacing, every array with its
// component count and one tuple per point (2D: one z layer); replaced atomically (no
// temporary left); a line is refused.
TEST(CoarseGrainFields, WritesVti) {
  const Sample<2> s = contact_sample<2>();
  FieldSpec<2> spec = grid_spec<2>(CgKernel::Gaussian, 1e-3, 0.0, 0.01, 2.5e-3);
  const Fields<2> f = coarse_grain(s, spec);
  const fs::path dir = fs::temp_directory_path() / "sable_test_coarse_grain_vti";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "fields.vti").string();
  write_fields_vti(f, path, VtkEncoding::kAscii);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string t = text.str();
  EXPECT_NE(t.find("WholeExtent=\"0 3 0 3 0 0\""), std::string::npos);
  EXPECT_NE(t.find("Origin=\"0.00125 0.00125 0\""), std::string::npos);
  EXPECT_NE(t.find("Spacing=\"0.0025 0.0025 0.01\""), std::string::npos);
  for (const char* arr :
       {"\"density\" NumberOfComponents=\"1\"", "\"velocity\" NumberOfComponents=\"3\"",
        "\"stress\" NumberOfComponents=\"9\"", "\"kinetic_stress\" NumberOfComponents=\"9\"",
        "\"contact_stress\" NumberOfComponents=\"9\"", "\"pressure\" NumberOfComponents=\"1\"",
        "\"principal_stress\" NumberOfComponents=\"3\"",
        "\"major_direction\" NumberOfComponents=\"3\"", "\"ellipsoid\" NumberOfComponents=\"9\"",
        "\"volume_fraction\"", "\"deviator\""})
    EXPECT_NE(t.find(arr), std::string::npos) << arr;
  // 16 points: 16 lines of values (one tuple each) per array, 12 arrays.
  std::size_t lines = 0;
  std::istringstream ls(t);
  for (std::string line; std::getline(ls, line);)
    if (!line.empty() && line[0] != '<') ++lines;
  EXPECT_EQ(lines, 16u * 12u);
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename(), "fields.vti");  // no temporary left behind
  FieldSpec<2> line;
  line.layout = FieldLayout::Line;
  line.points = 2;
  line.to = {0.01, 0.0};
  line.width = 1e-3;
  const Fields<2> lf = coarse_grain(s, line);
  EXPECT_NE(input_error([&] { write_fields_vti(lf, path); }).find("line"), std::string::npos);
  const Summary sum = field_summary(f);
  EXPECT_NE(sum.json().find("\"virial_on_grid_J\""), std::string::npos);
  fs::remove_all(dir);
}
