#include "sable/generation/generate.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "sable/core/error.hpp"
#include "sable/core/rng.hpp"
#include "sable/generation/numpy_pcg64.hpp"

namespace sable {
namespace {

// Lattice sites outside the region skipped before the lattice gives up, besides 64 per grain
// asked for: about a tenth of a second of skipping.
constexpr std::size_t kMaxSkippedSites = std::size_t{1} << 24;

// A count of sites or cells computed in floating point, as a long: a tiny grain in a huge
// region gives more than a long holds (a cast would be undefined), and no loop or array of
// 2^62 sites is ever made, so larger counts stop there.
long count_cast(double x) {
  constexpr double kMost = 4.0e18;
  return x >= kMost ? static_cast<long>(kMost) : x > 0.0 ? static_cast<long>(x) : 0L;
}

class RadiusSampler {
 public:
  RadiusSampler(const RadiusConfig& c, Rng& rng) : c_(c), rng_(rng) {}
  double next() {
    switch (c_.kind) {
      case RadiusConfig::Kind::kMono:
        return c_.value;
      case RadiusConfig::Kind::kUniform:
        return c_.value * (1.0 + c_.spread * (2.0 * rng_.uniform() - 1.0));
      case RadiusConfig::Kind::kList:
        return c_.values[k_++ % c_.values.size()];
    }
    return c_.value;
  }
  double max() const {
    switch (c_.kind) {
      case RadiusConfig::Kind::kMono:
        return c_.value;
      case RadiusConfig::Kind::kUniform:
        return c_.value * (1.0 + c_.spread);
      case RadiusConfig::Kind::kList:
        return *std::max_element(c_.values.begin(), c_.values.end());
    }
    return c_.value;
  }

 private:
  const RadiusConfig& c_;
  Rng& rng_;
  std::size_t k_ = 0;
};

// Bounding box of a region, and whether a grain of radius r at x lies wholly inside it.
void region_bounds(const RegionConfig& r, Vec3a& lo, Vec3a& hi) {
  if (r.kind == RegionConfig::Kind::kBox) {
    lo = r.lo;
    hi = r.hi;
  } else {
    lo = {r.center[0] - r.radius, r.center[1] - r.radius, r.zlo};
    hi = {r.center[0] + r.radius, r.center[1] + r.radius, r.zhi};
  }
}

// A grain exactly touching the boundary is inside: the tolerance (1e-9 of the region's size)
// absorbs the rounding of lattice sites computed as lo + (i + 1/2) s.
bool inside_region(const RegionConfig& r, const Vec3a& x, double rad, int dim) {
  if (r.kind == RegionConfig::Kind::kBox) {
    for (int d = 0; d < dim; ++d) {
      const double tol = 1e-9 * (r.hi[d] - r.lo[d]);
      if (x[d] - rad < r.lo[d] - tol || x[d] + rad > r.hi[d] + tol) return false;
    }
    return true;
  }
  const double tol = 1e-9 * std::max(r.radius, r.zhi - r.zlo);
  const double dx = x[0] - r.center[0], dy = x[1] - r.center[1];
  return std::sqrt(dx * dx + dy * dy) + rad <= r.radius + tol && x[2] - rad >= r.zlo - tol &&
         x[2] + rad <= r.zhi + tol;
}

std::vector<GrainSeed> lattice(const GrainsConfig& b, int dim, std::uint64_t seed,
                               const Blocked& blocked) {
  Rng rng(seed);
  RadiusSampler radii(b.radius, rng);
  const double s = b.spacing.value_or(2.0 * radii.max());
  Vec3a lo, hi;
  region_bounds(b.region, lo, hi);
  // Square: the same pitch s on every axis. Hexagonal: rows along x, sqrt(3)/2 s apart along
  // y, odd rows shifted by s/2 (in 3D such layers stack along z at pitch s).
  const bool hex = b.arrangement == "hexagonal";
  const std::array<double, 3> pitch{s, hex ? s * std::sqrt(3.0) / 2.0 : s, s};
  std::array<long, 3> n{1, 1, 1};
  for (int d = 0; d < dim; ++d)
    n[d] = count_cast(std::floor((hi[d] - lo[d] - s) / pitch[d] + 1.0 + 1e-9));
  // Jitter draws come in row-major (grain, axis) order, as numpy's uniform(size=(N, dim)).
  NumpyPcg64 pcg(seed);
  Rng jitter_rng(seed ^ 0x5bd1e995ULL);
  auto jitter = [&]() {
    if (b.jitter == 0.0) return 0.0;
    return b.jitter_rng == "numpy-pcg64" ? pcg.uniform(-b.jitter, b.jitter)
                                         : jitter_rng.uniform(-b.jitter, b.jitter);
  };
  std::vector<GrainSeed> out;
  // Sites outside the region (a cylinder's corners, rows shifted out, jitter) are skipped; so
  // many that the lattice would run for minutes means the region cannot take the grains.
  const std::size_t max_skipped = kMaxSkippedSites + 64 * b.count;
  std::size_t skipped = 0;
  for (long k = 0; k < n[2] && out.size() < b.count; ++k) {
    for (long j = 0; j < n[1] && out.size() < b.count; ++j) {
      const double shift = hex && (j % 2 == 1) ? 0.5 * s : 0.0;
      for (long i = 0; i < n[0] && out.size() < b.count; ++i) {
        const std::array<long, 3> idx{i, j, k};
        Vec3a x{0.0, 0.0, 0.0};
        for (int d = 0; d < dim; ++d)
          x[d] = lo[d] + 0.5 * s + static_cast<double>(idx[d]) * pitch[d];
        x[0] += shift;
        const double r = radii.next();
        for (int d = 0; d < dim; ++d) x[d] += jitter();
        if (!inside_region(b.region, x, r, dim) || (blocked && blocked(x, r))) {
          if (++skipped > max_skipped)
            throw InputError(fmt::format(
                "{}: grains: {} lattice sites lie outside the region or on a wall for {} grains "
                "placed of {} (is the jitter of {:g} m larger than the region?)",
                b.loc.str(), skipped, out.size(), b.count, b.jitter));
          continue;
        }
        out.push_back({x, r});
      }
    }
  }
  if (out.size() < b.count)
    throw InputError(fmt::format(
        "{}: grains: the lattice of spacing {:g} m holds only {} grains in the region, {} asked "
        "(enlarge the region or reduce spacing or count)",
        b.loc.str(), s, out.size(), b.count));
  return out;
}

// Uniform hash grid for overlap checks during random insertion.
class InsertionGrid {
 public:
  InsertionGrid(const Vec3a& lo, const Vec3a& hi, double cell, int dim, std::size_t expected)
      : lo_(lo), cell_(cell), dim_(dim) {
    for (int d = 0; d < 3; ++d)
      n_[d] = d < dim ? std::max(1L, count_cast((hi[d] - lo[d]) / cell) + 1) : 1;
    while (static_cast<double>(n_[0]) * static_cast<double>(n_[1]) * static_cast<double>(n_[2]) >
           8.0 * static_cast<double>(expected) + 64.0) {
      cell_ *= 1.5;
      for (int d = 0; d < dim; ++d) n_[d] = std::max(1L, count_cast((hi[d] - lo[d]) / cell_) + 1);
    }
    cells_.resize(static_cast<std::size_t>(n_[0] * n_[1] * n_[2]));
  }
  bool free(const Vec3a& x, double r, const std::vector<GrainSeed>& g) const {
    std::array<long, 3> c = index(x);
    std::array<long, 3> span{1, 1, 1};
    for (int d = 0; d < dim_; ++d) span[d] = static_cast<long>(std::ceil(2.0 * r_max_ / cell_)) + 1;
    for (long a = c[0] - span[0]; a <= c[0] + span[0]; ++a)
      for (long b = c[1] - span[1]; b <= c[1] + span[1]; ++b)
        for (long e = c[2] - (dim_ == 3 ? span[2] : 0); e <= c[2] + (dim_ == 3 ? span[2] : 0);
             ++e) {
          if (a < 0 || b < 0 || e < 0 || a >= n_[0] || b >= n_[1] || e >= n_[2]) continue;
          for (std::size_t k : cells_[static_cast<std::size_t>((e * n_[1] + b) * n_[0] + a)]) {
            double d2 = 0.0;
            for (int d = 0; d < dim_; ++d) d2 += (x[d] - g[k].x[d]) * (x[d] - g[k].x[d]);
            const double rs = r + g[k].radius;
            if (d2 < rs * rs) return false;
          }
        }
    return true;
  }
  void insert(std::size_t k, const GrainSeed& s) {
    const auto c = index(s.x);
    cells_[static_cast<std::size_t>((c[2] * n_[1] + c[1]) * n_[0] + c[0])].push_back(k);
    r_max_ = std::max(r_max_, s.radius);
  }

 private:
  std::array<long, 3> index(const Vec3a& x) const {
    std::array<long, 3> c{0, 0, 0};
    for (int d = 0; d < dim_; ++d)
      c[d] = std::clamp(static_cast<long>(std::floor((x[d] - lo_[d]) / cell_)), 0L, n_[d] - 1);
    return c;
  }
  Vec3a lo_;
  double cell_;
  int dim_;
  double r_max_ = 0.0;
  std::array<long, 3> n_{1, 1, 1};
  std::vector<std::vector<std::size_t>> cells_;
};

std::vector<GrainSeed> random_insertion(const GrainsConfig& b, int dim, std::uint64_t seed,
                                        const std::vector<GrainSeed>& existing,
                                        const Blocked& blocked) {
  Rng rng(seed);
  RadiusSampler radii(b.radius, rng);
  Vec3a lo, hi;
  region_bounds(b.region, lo, hi);
  // Existing grains (earlier blocks) are obstacles too.
  std::vector<GrainSeed> all = existing;
  InsertionGrid grid(lo, hi, 2.0 * radii.max(), dim, all.size() + b.count);
  for (std::size_t k = 0; k < all.size(); ++k) grid.insert(k, all[k]);
  for (std::size_t placed = 0; placed < b.count; ++placed) {
    const double r = radii.next();
    bool ok = false;
    for (std::size_t attempt = 0; attempt < b.max_attempts && !ok; ++attempt) {
      Vec3a x{0, 0, 0};
      for (int d = 0; d < dim; ++d) x[d] = rng.uniform(lo[d] + r, hi[d] - r);
      if (!inside_region(b.region, x, r, dim) || !grid.free(x, r, all)) continue;
      if (blocked && blocked(x, r)) continue;
      all.push_back({x, r});
      grid.insert(all.size() - 1, all.back());
      ok = true;
    }
    if (!ok)
      throw InputError(fmt::format(
          "{}: grains: random insertion placed only {} of {} grains after {} attempts for the "
          "next one (the region is too full: enlarge it, lower count, or raise max_attempts)",
          b.loc.str(), placed, b.count, b.max_attempts));
  }
  return {all.begin() + static_cast<std::ptrdiff_t>(existing.size()), all.end()};
}

}  // namespace

namespace {

// Parse a whole token as a number, or fail with the file and line.
template <class T>
T parse_number(const std::string& token, const std::string& path, std::size_t lineno,
               const char* what) {
  std::istringstream ts(token);
  T value{};
  if (!(ts >> value) || !ts.eof())
    throw InputError(
        fmt::format("{}:{}: expected {}, found '{}'", path, lineno, what, clip(token)));
  return value;
}

}  // namespace

std::vector<GrainSeed> read_lammps_data(const std::string& path, int dim) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open the grain data file", path));
  std::string line;
  std::getline(in, line);  // the first line is a free-text title, always skipped
  std::size_t lineno = 1, natoms = 0;
  bool in_atoms = false;
  std::map<std::uint64_t, GrainSeed> byid;
  while (std::getline(in, line)) {
    ++lineno;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream ls(line);
    std::vector<std::string> tok;
    for (std::string t; ls >> t;) tok.push_back(t);
    if (tok.empty()) continue;
    if (!in_atoms) {
      if (tok.size() == 2 && tok[1] == "atoms")
        natoms = parse_number<std::size_t>(tok[0], path, lineno, "the number of atoms");
      if (tok[0] == "Atoms") in_atoms = true;
      continue;
    }
    if (!std::isdigit(static_cast<unsigned char>(tok[0][0]))) break;  // the next section
    if (tok.size() < 7)
      throw InputError(
          fmt::format("{}:{}: expected `id type diameter density x y z`", path, lineno));
    const auto id = parse_number<std::uint64_t>(tok[0], path, lineno, "an atom id");
    const double diam = parse_number<double>(tok[2], path, lineno, "a diameter");
    if (!(diam > 0.0))
      throw InputError(fmt::format("{}:{}: diameter {} must be > 0", path, lineno, clip(tok[2])));
    const double x = parse_number<double>(tok[4], path, lineno, "a coordinate");
    const double y = parse_number<double>(tok[5], path, lineno, "a coordinate");
    const double z = parse_number<double>(tok[6], path, lineno, "a coordinate");
    byid[id] = GrainSeed{{x, y, dim == 3 ? z : 0.0}, 0.5 * diam};
  }
  if (!in_atoms || byid.size() != natoms)
    throw InputError(fmt::format("{}: expected an `Atoms` section with {} atoms, found {}", path,
                                 natoms, byid.size()));
  std::vector<GrainSeed> out;
  out.reserve(byid.size());
  for (auto& [id, g] : byid) out.push_back(g);
  return out;
}

std::vector<GrainSeed> generate_grains(const GrainsConfig& b, int dim, std::uint64_t seed,
                                       const std::vector<GrainSeed>& existing,
                                       const Blocked& blocked) {
  if (b.generator == "lattice") return lattice(b, dim, seed, blocked);
  if (b.generator == "random") return random_insertion(b, dim, seed, existing, blocked);
  if (b.generator == "file") return read_lammps_data(b.file, dim);
  // "list"
  std::vector<GrainSeed> out;
  Rng rng(seed);
  RadiusSampler radii(b.radius, rng);
  for (const auto& x : b.positions) out.push_back({x, radii.next()});
  return out;
}

}  // namespace sable
