// The batched Hertz-Mindlin law (contact/contact_lanes.hpp) against the scalar one
// (contact_force in contact/contact_model.hpp): the same bits, lane for lane, for every copy
// (instruction set) this machine can run and every option of the law. The DEM's dry pass in
// 3D runs the batched law, its wall contacts the scalar one: a state hash is the same on every
// machine, whichever copy it runs, only if this holds exactly, so the tolerance is zero: bits,
// not values.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <random>

#include "sable/contact/contact_lanes.hpp"

namespace {

using Vec = Eigen::Vector3d;

struct Contact {
  Vec d, dv, wa, wb, shear;
  double ra, rb, inv_mass_a, inv_mass_b;
  sable::PairParams p;
};

// The scalar law as PairPass::touch() (dem/dem_solver_impl.hpp) sets it up: the force on a, the
// spring after the step, n x F, the overlap and the two lever arms.
struct Result {
  Vec f, shear, m;
  double delta, lever_a, lever_b;
};

Result scalar(const Contact& c, const sable::ContactModel& model, double dt) {
  const double rsum = c.ra + c.rb;
  const double dist = std::sqrt(c.d.squaredNorm());
  sable::ContactGeometry<3> g;
  g.n = c.d * (1.0 / dist);
  g.delta = rsum - dist;
  const double lever_a = c.ra - 0.5 * g.delta, lever_b = c.rb - 0.5 * g.delta;
  g.vrel = c.dv - (lever_a * c.wa + lever_b * c.wb).cross(g.n);
  g.r_eff = c.ra * c.rb / rsum;
  g.m_eff = 1.0 / (c.inv_mass_a + c.inv_mass_b);
  Result r;
  r.shear = c.shear;
  r.f = sable::contact_force<3, sable::HertzNormal>(g, c.p, model, dt, r.shear);
  r.m = g.n.cross(r.f);
  r.delta = g.delta;
  r.lever_a = lever_a;
  r.lever_b = lever_b;
  return r;
}

void fill(sable::ContactLanes& lanes, int l, const Contact& c) {
  lanes.dx[l] = c.d.x();
  lanes.dy[l] = c.d.y();
  lanes.dz[l] = c.d.z();
  lanes.dist2[l] = c.d.squaredNorm();
  lanes.rsum[l] = c.ra + c.rb;
  lanes.ra[l] = c.ra;
  lanes.rb[l] = c.rb;
  lanes.inv_mass_a[l] = c.inv_mass_a;
  lanes.inv_mass_b[l] = c.inv_mass_b;
  lanes.dvx[l] = c.dv.x();
  lanes.dvy[l] = c.dv.y();
  lanes.dvz[l] = c.dv.z();
  lanes.wax[l] = c.wa.x();
  lanes.way[l] = c.wa.y();
  lanes.waz[l] = c.wa.z();
  lanes.wbx[l] = c.wb.x();
  lanes.wby[l] = c.wb.y();
  lanes.wbz[l] = c.wb.z();
  lanes.set_params(l, c.p);
  lanes.sx[l] = c.shear.x();
  lanes.sy[l] = c.shear.y();
  lanes.sz[l] = c.shear.z();
}

// Contacts of 1.5 mm glass-like grains as in a dense bed: overlaps up to 2 % of R, speeds up
// to 0.1 m/s and 100 rad/s; springs zero (a new contact), small (sticking) or long (sliding);
// some frictionless pairs and some fixed second grains (1/m = 0).
Contact random_contact(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.0, 1.0);
  Contact c;
  c.ra = 0.75e-3 * (1.0 + 0.2 * u(rng));
  c.rb = 0.75e-3 * (1.0 + 0.2 * u(rng));
  Vec dir(u(rng), u(rng), u(rng));
  dir.normalize();
  c.d = (c.ra + c.rb) * (1.0 - 0.02 * pos(rng) * std::min(c.ra, c.rb) / (c.ra + c.rb)) * dir;
  c.dv = 0.1 * Vec(u(rng), u(rng), u(rng));
  c.wa = 100.0 * Vec(u(rng), u(rng), u(rng));
  c.wb = 100.0 * Vec(u(rng), u(rng), u(rng));
  c.inv_mass_a = 1.0 / (2500.0 * 4.18879 * c.ra * c.ra * c.ra);
  c.inv_mass_b = pos(rng) < 0.1 ? 0.0 : 1.0 / (2500.0 * 4.18879 * c.rb * c.rb * c.rb);
  const double kind = pos(rng);
  const double length = kind < 0.2 ? 0.0 : (kind < 0.6 ? 1e-8 : 1e-5);
  c.shear = length * Vec(u(rng), u(rng), u(rng));
  c.p.y_star = 2.8e6 * (1.0 + 0.1 * u(rng));
  c.p.g_star = 1.0e6 * (1.0 + 0.1 * u(rng));
  c.p.beta = -0.16 * (1.0 + 0.1 * u(rng));
  c.p.st_over_sn_sqrt = std::sqrt(4.0 * c.p.g_star / c.p.y_star);
  c.p.friction = pos(rng) < 0.1 ? 0.0 : 0.5 * (1.0 + 0.5 * u(rng));
  return c;
}

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

bool same_bits(const Vec& a, const Vec& b) {
  return same_bits(a.x(), b.x()) && same_bits(a.y(), b.y()) && same_bits(a.z(), b.z());
}

// Every copy the machine runs, every combination of the law's options, 1,000 contacts each
// in batches of 64 and a last partial batch; each field bit for bit. The contacts must cover
// the law's branches (sliding, sticking, a new spring, no friction), or the test proves less.
TEST(ContactLanes, BatchedLawGivesTheScalarLawsBits) {
  const double dt = 1.8e-5;
  std::vector<sable::SimdLevel> levels{sable::SimdLevel::kBaseline};
  if (sable::best_simd_level() >= sable::SimdLevel::kAvx2)
    levels.push_back(sable::SimdLevel::kAvx2);
  if (sable::best_simd_level() >= sable::SimdLevel::kAvx512)
    levels.push_back(sable::SimdLevel::kAvx512);
  for (const auto level : levels) {
    for (int options = 0; options < 8; ++options) {
      sable::ContactModel model;
      model.attractive_damping = (options & 1) != 0;
      model.keep_spring_length = (options & 2) != 0;
      model.tangential =
          (options & 4) != 0 ? sable::TangentialModel::kNone : sable::TangentialModel::kHistory;
      std::mt19937_64 rng(7 + static_cast<unsigned>(options));
      int sliding = 0, sticking = 0, fresh = 0, frictionless = 0, pulling = 0;
      for (int done = 0; done < 1000;) {
        const int n = std::min(sable::ContactLanes::kWidth, 1000 - done);
        sable::ContactLanes lanes;
        std::vector<Contact> contacts;
        for (int l = 0; l < n; ++l) {
          contacts.push_back(random_contact(rng));
          fill(lanes, l, contacts.back());
        }
        sable::contact_lanes_hertz(level, lanes, n, model, dt);
        for (int l = 0; l < n; ++l) {
          const Contact& c = contacts[static_cast<std::size_t>(l)];
          const Result r = scalar(c, model, dt);
          const std::string where = fmt::format("{} options {} contact {}",
                                                sable::simd_level_name(level), options, done + l);
          EXPECT_TRUE(same_bits(r.f, Vec(lanes.fx[l], lanes.fy[l], lanes.fz[l]))) << where;
          EXPECT_TRUE(same_bits(r.shear, Vec(lanes.sx[l], lanes.sy[l], lanes.sz[l]))) << where;
          EXPECT_TRUE(same_bits(r.m, Vec(lanes.mx[l], lanes.my[l], lanes.mz[l]))) << where;
          EXPECT_TRUE(same_bits(r.delta, lanes.delta[l])) << where;
          EXPECT_TRUE(same_bits(r.lever_a, lanes.lever_a[l])) << where;
          EXPECT_TRUE(same_bits(r.lever_b, lanes.lever_b[l])) << where;
          // Which branch the scalar law took: sliding holds the spring at the Coulomb limit,
          // |k_t s| = mu |F_n| (to round-off, 1e-9 relative).
          const Vec n_hat = c.d.normalized();
          const double fn = r.f.dot(n_hat);
          const double kt =
              sable::HertzNormal::coeffs(c.p, model, r.delta, c.ra * c.rb / (c.ra + c.rb), 1.0).kt;
          if (c.p.friction == 0.0 || (options & 4) != 0)
            ++frictionless;
          else if (c.shear.squaredNorm() == 0.0)
            ++fresh;
          else if (kt * r.shear.norm() >= c.p.friction * std::abs(fn) * (1.0 - 1e-9))
            ++sliding;
          else
            ++sticking;
          if (fn < -1e-9 * r.f.norm()) ++pulling;
        }
        done += n;
      }
      if ((options & 4) == 0) {
        EXPECT_GT(sliding, 100) << "options " << options;
        EXPECT_GT(sticking, 100) << "options " << options;
        EXPECT_GT(fresh, 50) << "options " << options;
      }
      EXPECT_GT(frictionless, 50) << "options " << options;
      // Attractive damping: some contacts pull (a separating pair); clipped, none does.
      if ((options & 1) != 0)
        EXPECT_GT(pulling, 0) << "options " << options;
      else
        EXPECT_EQ(pulling, 0) << "options " << options;
    }
  }
}

}  // namespace
