// The batched contact law (see contact_lanes.hpp). This file is compiled with
// -fno-trapping-math, so that the compiler may compute both sides of a select (a division or
// square root whose result a lane then discards raises no trap that anyone reads; no value
// changes), and with -ffp-contract=off, so that each multiply and add is rounded on its own
// as in the scalar law, never fused into an AVX-512 multiply-add (CMakeLists.txt).
#include "sable/contact/contact_lanes.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace sable {

namespace {

// One loop over the lanes, every branch of contact_force() a select; the comments say which
// part of contact_force() (or of PairPass::touch() in dem/dem_solver_impl.hpp) each stretch
// repeats. Eigen's 3-vector dot products and norms sum left to right, ((x + y) + z).
template <class Normal>
[[gnu::always_inline]] inline void run(ContactLanes& L, int n, const ContactModel& law, double dt) {
  // A local copy: the lanes' stores cannot alias it, so its fields stay in registers.
  const ContactModel model = law;
  const bool clip = !model.attractive_damping;
  const bool tangential = model.tangential != TangentialModel::kNone;
  const bool keep_length = model.keep_spring_length;
#pragma omp simd
  for (int l = 0; l < n; ++l) {
    // PairPass::touch(): the geometry.
    const double dist = std::sqrt(L.dist2[l]);
    const double inv_dist = 1.0 / dist;
    const double nx = L.dx[l] * inv_dist, ny = L.dy[l] * inv_dist, nz = L.dz[l] * inv_dist;
    const double delta = L.rsum[l] - dist;
    const double lever_a = L.ra[l] - 0.5 * delta, lever_b = L.rb[l] - 0.5 * delta;
    const double ox = lever_a * L.wax[l] + lever_b * L.wbx[l];
    const double oy = lever_a * L.way[l] + lever_b * L.wby[l];
    const double oz = lever_a * L.waz[l] + lever_b * L.wbz[l];
    // vrel = v_i - v_j - (o x n)
    const double vrx = L.dvx[l] - (oy * nz - oz * ny);
    const double vry = L.dvy[l] - (oz * nx - ox * nz);
    const double vrz = L.dvz[l] - (ox * ny - oy * nx);
    const double r_eff = L.ra[l] * L.rb[l] / L.rsum[l];
    const double m_eff = 1.0 / (L.inv_mass_a[l] + L.inv_mass_b[l]);
    PairParams p;
    p.y_star = L.y_star[l];
    p.g_star = L.g_star[l];
    p.beta = L.beta[l];
    p.st_over_sn_sqrt = L.st_over_sn_sqrt[l];
    p.friction = L.friction[l];
    // contact_force(): the normal force.
    const NormalCoeffs c = Normal::coeffs(p, model, delta, r_eff, m_eff);
    const double vn = (vrx * nx + vry * ny) + vrz * nz;
    double fn = c.kn * delta - c.gn * vn;
    fn = (clip & (fn < 0.0)) ? 0.0 : fn;
    double fx = fn * nx, fy = fn * ny, fz = fn * nz;
    // The tangential spring: turned into the tangent plane when it is not zero (and brought
    // back to its length if the law keeps it), advanced by vt dt, held at the Coulomb limit.
    const double vtx = vrx - vn * nx, vty = vry - vn * ny, vtz = vrz - vn * nz;
    double sx = L.sx[l], sy = L.sy[l], sz = L.sz[l];
    const double s2 = (sx * sx + sy * sy) + sz * sz;
    const double s_n = (sx * nx + sy * ny) + sz * nz;
    const double px = sx - s_n * nx, py = sy - s_n * ny, pz = sz - s_n * nz;
    const double s2_new = (px * px + py * py) + pz * pz;
    const double stretch = std::sqrt(s2 / s2_new);
    const bool turn = s2 > 0.0;
    const bool rescale = turn & keep_length & (s2_new > 0.0);
    const double qx = rescale ? px * stretch : px, qy = rescale ? py * stretch : py,
                 qz = rescale ? pz * stretch : pz;
    sx = (turn ? qx : sx) + vtx * dt;
    sy = (turn ? qy : sy) + vty * dt;
    sz = (turn ? qz : sz) + vtz * dt;
    const double f_max = p.friction * std::abs(fn);
    const double f_spring2 = c.kt * c.kt * ((sx * sx + sy * sy) + sz * sz);
    const bool slide = f_spring2 > f_max * f_max;
    const double cap = f_max / std::sqrt(f_spring2);
    sx = slide ? sx * cap : sx;
    sy = slide ? sy * cap : sy;
    sz = slide ? sz * cap : sz;
    const double tx = slide ? c.kt * sx : c.kt * sx + c.gt * vtx;
    const double ty = slide ? c.kt * sy : c.kt * sy + c.gt * vty;
    const double tz = slide ? c.kt * sz : c.kt * sz + c.gt * vtz;
    // A frictionless contact (no tangential law, or mu = 0) has no spring.
    const bool friction = tangential & (p.friction != 0.0);
    fx = friction ? fx - tx : fx;
    fy = friction ? fy - ty : fy;
    fz = friction ? fz - tz : fz;
    L.sx[l] = friction ? sx : 0.0;
    L.sy[l] = friction ? sy : 0.0;
    L.sz[l] = friction ? sz : 0.0;
    L.fx[l] = fx;
    L.fy[l] = fy;
    L.fz[l] = fz;
    // n x F, for the torques
    L.mx[l] = ny * fz - nz * fy;
    L.my[l] = nz * fx - nx * fz;
    L.mz[l] = nx * fy - ny * fx;
    L.delta[l] = delta;
    L.lever_a[l] = lever_a;
    L.lever_b[l] = lever_b;
  }
}

// One copy per instruction set. None uses fused multiply-adds (see above), so every copy
// gives the same bits; contact_lanes_hertz() picks the widest this machine has, once.
[[gnu::target("avx512f")]] void hertz_avx512(ContactLanes& lanes, int n, const ContactModel& model,
                                             double dt) {
  run<HertzNormal>(lanes, n, model, dt);
}

[[gnu::target("avx2")]] void hertz_avx2(ContactLanes& lanes, int n, const ContactModel& model,
                                        double dt) {
  run<HertzNormal>(lanes, n, model, dt);
}

void hertz_baseline(ContactLanes& lanes, int n, const ContactModel& model, double dt) {
  run<HertzNormal>(lanes, n, model, dt);
}

using HertzLanes = void (*)(ContactLanes&, int, const ContactModel&, double);

HertzLanes hertz_for(SimdLevel level) {
  switch (level) {
    case SimdLevel::kAvx512:
      return hertz_avx512;
    case SimdLevel::kAvx2:
      return hertz_avx2;
    case SimdLevel::kBaseline:
      break;
  }
  return hertz_baseline;
}

}  // namespace

SimdLevel best_simd_level() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return SimdLevel::kAvx512;
  if (__builtin_cpu_supports("avx2")) return SimdLevel::kAvx2;
  return SimdLevel::kBaseline;
}

std::string_view simd_level_name(SimdLevel level) {
  switch (level) {
    case SimdLevel::kAvx512:
      return "avx512f";
    case SimdLevel::kAvx2:
      return "avx2";
    case SimdLevel::kBaseline:
      break;
  }
  return "baseline";
}

void contact_lanes_hertz(ContactLanes& lanes, int n, const ContactModel& model, double dt) {
  // Chosen once (a constant of the machine, not state): an indirect call per batch of 64.
  static const HertzLanes best = hertz_for(best_simd_level());
  best(lanes, n, model, dt);
}

void contact_lanes_hertz(SimdLevel level, ContactLanes& lanes, int n, const ContactModel& model,
                         double dt) {
  if (static_cast<int>(level) > static_cast<int>(best_simd_level()))
    throw std::invalid_argument(
        fmt::format("contact_lanes_hertz: this machine has no {}", simd_level_name(level)));
  hertz_for(level)(lanes, n, model, dt);
}

}  // namespace sable
