// Coarse-grained fields: node layout, the accumulation of grains and contacts on the nodes
// their kernel reaches, the derived quantities, averaging, and the outputs (table, summary,
// .vti). The weights themselves are in coarse_grain_kernels.cpp.
#include "sable/analysis/coarse_grain.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "sable/core/error.hpp"
#include "sable/io/vti.hpp"

namespace sable {

namespace {

// The nodes as a lattice: node(k) = origin + sum_a k_a h_a e_a, axes orthogonal. A grid has D
// axes along x, y(, z); a line has one axis along (to - from). This is what lets a grain or a
// contact find the nodes its kernel can reach without looking at the others.
template <int D>
struct Lattice {
  using Vec = typename Space<D>::Vec;
  int axes = 0;
  Vec origin = Vec::Zero();
  std::array<Vec, D> dir{};
  std::array<double, D> h{};
  std::array<int, D> n{};
  std::array<std::size_t, D> stride{};

  // Visit (in a fixed order) every node whose projection on each axis lies within `reach` of
  // the projections of the segment [p, q]: a superset of the nodes within `reach` of it.
  template <class F>
  void visit(const Vec& p, const Vec& q, double reach, F&& f) const {
    std::array<int, D> lo{}, hi{};
    for (int a = 0; a < axes; ++a) {
      const std::size_t ua = static_cast<std::size_t>(a);
      const double up = (p - origin).dot(dir[ua]), uq = (q - origin).dot(dir[ua]);
      // One node of margin each side: the weight itself decides at the edge of the support.
      const double kmin = std::ceil((std::min(up, uq) - reach) / h[ua]) - 1.0;
      const double kmax = std::floor((std::max(up, uq) + reach) / h[ua]) + 1.0;
      const double last = static_cast<double>(n[ua] - 1);
      if (!(kmax >= 0.0 && kmin <= last)) return;  // out of the grid (or not finite)
      lo[ua] = static_cast<int>(std::max(kmin, 0.0));
      hi[ua] = static_cast<int>(std::min(kmax, last));
    }
    std::array<int, D> k = lo;
    for (;;) {
      std::size_t node = 0;
      for (int a = 0; a < axes; ++a)
        node += static_cast<std::size_t>(k[static_cast<std::size_t>(a)]) *
                stride[static_cast<std::size_t>(a)];
      f(node);
      int a = 0;
      for (; a < axes; ++a) {
        const std::size_t ua = static_cast<std::size_t>(a);
        if (++k[ua] <= hi[ua]) break;
        k[ua] = lo[ua];
      }
      if (a == axes) return;
    }
  }
};

std::string key_err(const char* key, const std::string& what) {
  return fmt::format("coarse-graining: {}: {}", key, what);
}

// The grid box: the spec's bounded sides, the grains' bounds for the others.
template <int D>
Region<D> resolve_box(const Sample<D>& s, const FieldSpec<D>& spec) {
  Region<D> box = spec.box;
  bool open = false;
  for (int a = 0; a < D; ++a) open = open || box.lo[a] < -1e299 || box.hi[a] > 1e299;
  if (open) {
    const Region<D> g = grain_bounds(s);
    for (int a = 0; a < D; ++a) {
      if (box.lo[a] < -1e299) box.lo[a] = g.lo[a];
      if (box.hi[a] > 1e299) box.hi[a] = g.hi[a];
    }
  }
  for (int a = 0; a < D; ++a)
    if (!(box.hi[a] > box.lo[a]))
      throw InputError(key_err(
          "box", fmt::format("empty along axis {} (lo = {}, hi = {})", a, box.lo[a], box.hi[a])));
  return box;
}

// Nodes and lattice of a grid: cell centres of `cells` cells over the box.
template <int D>
Lattice<D> make_grid(const Sample<D>& s, Fields<D>& f) {
  FieldSpec<D>& spec = f.spec;
  Region<D> box = resolve_box(s, spec);
  if (spec.spacing > 0.0) {
    for (int a = 0; a < D; ++a) {
      const double len = box.hi[a] - box.lo[a];
      const double n = std::max(std::ceil(len / spec.spacing - 1e-9), 1.0);
      if (n > 1e6) throw InputError(key_err("spacing", "over a million cells on one axis"));
      spec.cells[static_cast<std::size_t>(a)] = static_cast<int>(n);
      const double grow = 0.5 * (n * spec.spacing - len);
      box.lo[a] -= grow;
      box.hi[a] += grow;
    }
    spec.spacing = 0.0;
  }
  spec.box = box;
  Lattice<D> lat;
  lat.axes = D;
  std::size_t total = 1;
  for (int a = 0; a < D; ++a) {
    const std::size_t ua = static_cast<std::size_t>(a);
    lat.n[ua] = spec.cells[ua];
    lat.h[ua] = (box.hi[a] - box.lo[a]) / spec.cells[ua];
    lat.dir[ua] = Space<D>::Vec::Unit(a);
    lat.stride[ua] = total;
    total *= static_cast<std::size_t>(lat.n[ua]);
    f.cell[a] = lat.h[ua];
  }
  lat.origin = box.lo + 0.5 * f.cell;
  f.counts = lat.n;
  f.nodes.resize(total);
  for (std::size_t node = 0; node < total; ++node) {
    typename Space<D>::Vec x = lat.origin;
    std::size_t rest = node;
    for (int a = 0; a < D; ++a) {
      const std::size_t ua = static_cast<std::size_t>(a);
      x[a] += static_cast<double>(rest % static_cast<std::size_t>(lat.n[ua])) * lat.h[ua];
      rest /= static_cast<std::size_t>(lat.n[ua]);
    }
    f.nodes[node] = x;
  }
  return lat;
}

template <int D>
Lattice<D> make_line(Fields<D>& f) {
  const FieldSpec<D>& spec = f.spec;
  Lattice<D> lat;
  lat.axes = 1;
  lat.origin = spec.from;
  const typename Space<D>::Vec span = spec.to - spec.from;
  const int n = spec.points;
  // One point: any positive step; the range clamp keeps the single node.
  lat.h[0] = n > 1 ? span.norm() / (n - 1) : 1.0;
  lat.dir[0] = n > 1 ? typename Space<D>::Vec(span.normalized()) : Space<D>::Vec::Unit(0);
  lat.n[0] = n;
  lat.stride[0] = 1;
  f.counts.fill(1);
  f.counts[0] = n;
  f.nodes.resize(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    f.nodes[static_cast<std::size_t>(k)] =
        n > 1 ? typename Space<D>::Vec(spec.from + span * (static_cast<double>(k) / (n - 1)))
              : spec.from;
  return lat;
}

template <int D>
void size_sums(Fields<D>& f) {
  using Mat = typename Fields<D>::Mat;
  const std::size_t n = f.nodes.size();
  f.density.assign(n, 0.0);
  f.volume_fraction.assign(n, 0.0);
  f.momentum.assign(n, Space<D>::Vec::Zero());
  f.second_moment.assign(n, Mat::Zero());
  f.contact_stress.assign(n, Mat::Zero());
}

// Grains: rho, phi, rho v and sum m v v w, each node in slot order.
template <int D>
void add_grains(const Sample<D>& s, const cg::Kernel<D>& kern, const Lattice<D>& lat,
                Fields<D>& f) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto& xi = s.x[i];
    const auto& vi = s.v[i];
    const double m = s.mass[i], vol = s.volume[i], r = s.radius[i];
    const typename Fields<D>::Mat mvv = m * vi * vi.transpose();
    lat.visit(xi, xi, kern.grain_reach(r), [&](std::size_t node) {
      const double w = kern.grain(f.nodes[node] - xi, r);
      if (w == 0.0) return;
      f.density[node] += m * w;
      f.volume_fraction[node] += vol * w;
      f.momentum[node] += (m * w) * vi;
      f.second_moment[node] += w * mvv;
    });
    f.mass += m;
  }
}

// Contacts: sigma_c = -f (x) l times the branch's share of each node.
template <int D>
void add_contacts(const Sample<D>& s, const cg::Kernel<D>& kern, const Lattice<D>& lat,
                  Fields<D>& f) {
  const ContactSet<D>& c = s.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const auto& p = s.x[c.i[k]];
    const auto& l = c.branch[k];
    const typename Fields<D>::Mat moment = -c.force[k] * l.transpose();
    const typename Space<D>::Vec q = p + l;
    lat.visit(p, q, kern.reach(), [&](std::size_t node) {
      const double w = kern.segment(f.nodes[node], p, l);
      if (w != 0.0) f.contact_stress[node] += w * moment;
    });
    f.virial += moment;
  }
}

// The symmetric eigenproblem of one node: values descending, directions signed.
template <int D>
void principal_of(const typename Fields<D>::Mat& sym, typename Space<D>::Vec& values,
                  typename Fields<D>::Mat& dirs) {
  using Mat = typename Fields<D>::Mat;
  Eigen::SelfAdjointEigenSolver<Mat> es(sym, Eigen::ComputeEigenvectors);
  for (int a = 0; a < D; ++a) {
    values[a] = es.eigenvalues()[D - 1 - a];
    typename Space<D>::Vec e = es.eigenvectors().col(D - 1 - a);
    Eigen::Index big = 0;
    e.cwiseAbs().maxCoeff(&big);
    if (e[big] < 0.0) e = -e;  // a sign fixed by the vector itself, not by the solver
    dirs.col(a) = e;
  }
}

}  // namespace

template <int D>
void validate(const FieldSpec<D>& spec) {
  if (!(spec.width > 0.0) || !std::isfinite(spec.width))
    throw InputError(
        key_err("width", fmt::format("must be a finite number > 0 (got {})", spec.width)));
  if (spec.layout == FieldLayout::Line) {
    if (spec.points < 1)
      throw InputError(key_err("points", fmt::format("must be >= 1 (got {})", spec.points)));
    if (spec.points > 1 && spec.from == spec.to)
      throw InputError(key_err("from/to", "the line's two ends coincide"));
    if (!spec.from.allFinite() || !spec.to.allFinite())
      throw InputError(key_err("from/to", "not finite"));
    return;
  }
  const bool any_cells =
      std::any_of(spec.cells.begin(), spec.cells.end(), [](int c) { return c != 0; });
  if (any_cells && spec.spacing != 0.0)
    throw InputError(key_err("cells", "give either cells or spacing, not both"));
  if (any_cells) {
    for (int a = 0; a < D; ++a)
      if (spec.cells[static_cast<std::size_t>(a)] < 1)
        throw InputError(key_err("cells", fmt::format("axis {} has {} cells (need >= 1)", a,
                                                      spec.cells[static_cast<std::size_t>(a)])));
  } else if (!(spec.spacing > 0.0) || !std::isfinite(spec.spacing)) {
    throw InputError(
        key_err("spacing", fmt::format("must be a finite number > 0 (got {})", spec.spacing)));
  }
  for (int a = 0; a < D; ++a)
    if (!(spec.box.hi[a] > spec.box.lo[a]))
      throw InputError(key_err("box", fmt::format("empty along axis {} (lo = {}, hi = {})", a,
                                                  spec.box.lo[a], spec.box.hi[a])));
}

template <int D>
Fields<D> coarse_grain(const Sample<D>& sample, const FieldSpec<D>& spec) {
  validate(spec);
  if (spec.kernel == CgKernel::Sphere)
    refuse_polyhedra(sample, "coarse-graining (fields)", kSphereKernelPolyhedra);
  Fields<D> f;
  f.spec = spec;
  f.thickness = D == 2 ? sample.thickness : 1.0;
  const Lattice<D> lat = spec.layout == FieldLayout::Grid ? make_grid(sample, f) : make_line(f);
  size_sums(f);
  const cg::Kernel<D> kern(spec.kernel, spec.width, f.thickness);
  add_grains(sample, kern, lat, f);
  add_contacts(sample, kern, lat, f);
  f.snapshots = 1;
  finish(f);
  return f;
}

template <int D>
void finish(Fields<D>& f) {
  using Vec = typename Space<D>::Vec;
  using Mat = typename Fields<D>::Mat;
  const std::size_t n = f.nodes.size();
  f.velocity.assign(n, Vec::Zero());
  f.kinetic_stress.assign(n, Mat::Zero());
  f.stress.assign(n, Mat::Zero());
  f.pressure.assign(n, 0.0);
  f.deviator.assign(n, 0.0);
  f.antisymmetry.assign(n, 0.0);
  f.principal.assign(n, Vec::Zero());
  f.directions.assign(n, Mat::Identity());
  f.ellipsoid.assign(n, Mat::Zero());
  for (std::size_t k = 0; k < n; ++k) {
    const double rho = f.density[k];
    if (rho > 0.0) {
      f.velocity[k] = f.momentum[k] / rho;
      // sum m (v_i - v)(v_i - v) w = sum m v_i v_i w - rho v v, since sum m v_i w = rho v.
      f.kinetic_stress[k] = f.second_moment[k] - rho * f.velocity[k] * f.velocity[k].transpose();
    }
    const Mat sigma = f.contact_stress[k] + f.kinetic_stress[k];
    f.stress[k] = sigma;
    const double p = sigma.trace() / D;
    f.pressure[k] = p;
    const Mat sym = 0.5 * (sigma + sigma.transpose());
    f.antisymmetry[k] = (0.5 * (sigma - sigma.transpose())).norm();
    principal_of<D>(sym, f.principal[k], f.directions[k]);
    f.deviator[k] = 0.5 * (f.principal[k][0] - f.principal[k][D - 1]);
    if (p != 0.0) f.ellipsoid[k] = sym / p;
  }
}

template <int D>
Fields<D>& accumulate(Fields<D>& sum, const Fields<D>& add) {
  if (sum.snapshots == 0 && sum.nodes.empty()) {
    sum = add;
    return sum;
  }
  const bool same = sum.nodes == add.nodes && sum.spec.kernel == add.spec.kernel &&
                    sum.spec.width == add.spec.width && sum.thickness == add.thickness &&
                    sum.spec.layout == add.spec.layout;
  if (!same)
    throw InputError(
        "coarse-graining: cannot add fields made on other nodes or with another kernel (to "
        "average over snapshots, give the grid an explicit box)");
  for (std::size_t k = 0; k < sum.nodes.size(); ++k) {
    sum.density[k] += add.density[k];
    sum.volume_fraction[k] += add.volume_fraction[k];
    sum.momentum[k] += add.momentum[k];
    sum.second_moment[k] += add.second_moment[k];
    sum.contact_stress[k] += add.contact_stress[k];
  }
  sum.mass += add.mass;
  sum.virial += add.virial;
  sum.snapshots += add.snapshots;
  return sum;
}

template <int D>
Fields<D>& scale(Fields<D>& f, double factor) {
  for (std::size_t k = 0; k < f.nodes.size(); ++k) {
    f.density[k] *= factor;
    f.volume_fraction[k] *= factor;
    f.momentum[k] *= factor;
    f.second_moment[k] *= factor;
    f.contact_stress[k] *= factor;
  }
  f.mass *= factor;
  f.virial *= factor;
  return f;
}

template <int D>
Fields<D>& average(Fields<D>& f) {
  if (f.snapshots > 1) {
    scale(f, 1.0 / f.snapshots);
    f.snapshots = 1;
  }
  finish(f);
  return f;
}

template <int D>
double Fields<D>::cell_volume() const {
  if (spec.layout != FieldLayout::Grid) return 0.0;
  return cell.prod() * (D == 2 ? thickness : 1.0);
}

template <int D>
double Fields<D>::mass_on_grid() const {
  double m = 0.0;
  for (double rho : density) m += rho;
  return m * cell_volume();
}

template <int D>
typename Fields<D>::Mat Fields<D>::virial_on_grid() const {
  Mat v = Mat::Zero();
  for (const Mat& s : contact_stress) v += s;
  return v * cell_volume();
}

namespace {

const char* axis_name(int a) {
  return a == 0 ? "x" : a == 1 ? "y" : "z";
}

// A D x D matrix as 9 row-major components of a 3 x 3 one (2D: zeros in z).
template <int D>
void push_tensor(std::vector<double>& out, const typename Fields<D>::Mat& m) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out.push_back(r < D && c < D ? m(r, c) : 0.0);
}

template <int D>
void push_vector(std::vector<double>& out, const typename Space<D>::Vec& v) {
  for (int a = 0; a < 3; ++a) out.push_back(a < D ? v[a] : 0.0);
}

template <int D>
std::vector<double> flat(const typename Fields<D>::Mat& m) {
  std::vector<double> out;
  for (int r = 0; r < D; ++r)
    for (int c = 0; c < D; ++c) out.push_back(m(r, c));
  return out;
}

template <int D>
std::vector<double> as_list(const typename Space<D>::Vec& v) {
  return std::vector<double>(v.data(), v.data() + D);
}

}  // namespace

template <int D>
Table field_table(const Fields<D>& f) {
  const std::size_t n = f.size();
  Table t;
  auto column = [&](const std::string& name, auto get) {
    std::vector<double> c(n);
    for (std::size_t k = 0; k < n; ++k) c[k] = get(k);
    t.add(name, std::move(c));
  };
  if (f.spec.layout == FieldLayout::Line)
    column("s_m", [&](std::size_t k) { return (f.nodes[k] - f.spec.from).norm(); });
  for (int a = 0; a < D; ++a)
    column(fmt::format("{}_m", axis_name(a)), [&](std::size_t k) { return f.nodes[k][a]; });
  column("density_kg_m3", [&](std::size_t k) { return f.density[k]; });
  column("volume_fraction", [&](std::size_t k) { return f.volume_fraction[k]; });
  for (int a = 0; a < D; ++a)
    column(fmt::format("v{}_m_s", axis_name(a)), [&](std::size_t k) { return f.velocity[k][a]; });
  for (int r = 0; r < D; ++r)
    for (int c = 0; c < D; ++c)
      column(fmt::format("sigma_{}{}_Pa", axis_name(r), axis_name(c)),
             [&](std::size_t k) { return f.stress[k](r, c); });
  column("contact_pressure_Pa", [&](std::size_t k) { return f.contact_stress[k].trace() / D; });
  column("kinetic_pressure_Pa", [&](std::size_t k) { return f.kinetic_stress[k].trace() / D; });
  column("pressure_Pa", [&](std::size_t k) { return f.pressure[k]; });
  column("deviator_Pa", [&](std::size_t k) { return f.deviator[k]; });
  column("antisymmetry_Pa", [&](std::size_t k) { return f.antisymmetry[k]; });
  for (int a = 0; a < D; ++a)
    column(fmt::format("sigma_{}_Pa", a + 1), [&](std::size_t k) { return f.principal[k][a]; });
  for (int a = 0; a < D; ++a)
    column(fmt::format("major_{}", axis_name(a)),
           [&](std::size_t k) { return f.directions[k](a, 0); });
  return t;
}

template <int D>
Summary field_summary(const Fields<D>& f) {
  const FieldSpec<D>& s = f.spec;
  Summary spec;
  spec.add("dimension", D);
  spec.add("layout", s.layout == FieldLayout::Grid ? "grid" : "line");
  if (s.layout == FieldLayout::Grid) {
    spec.add("cells", std::vector<double>(f.counts.begin(), f.counts.end()));
    spec.add("box_lo_m", as_list<D>(s.box.lo));
    spec.add("box_hi_m", as_list<D>(s.box.hi));
    spec.add("cell_m", as_list<D>(f.cell));
    spec.add("nodes", "cell centres");
  } else {
    spec.add("points", s.points);
    spec.add("from_m", as_list<D>(s.from));
    spec.add("to_m", as_list<D>(s.to));
  }
  spec.add("kernel", cg_kernel_name(s.kernel));
  spec.add("width_m", s.width);
  spec.add("reach_m", cg::Kernel<D>(s.kernel, s.width, f.thickness).reach());
  if (D == 2) spec.add("thickness_m", f.thickness);
  Summary totals;
  totals.add("mass_kg", f.mass);
  totals.add("virial_J", flat<D>(f.virial));
  if (s.layout == FieldLayout::Grid) {
    totals.add("mass_on_grid_kg", f.mass_on_grid());
    totals.add("virial_on_grid_J", flat<D>(f.virial_on_grid()));
  }
  double pmax = 0.0;
  for (double p : f.pressure) pmax = std::max(pmax, p);
  Summary out;
  out.add("spec", spec);
  out.add("snapshots", f.snapshots);
  out.add("totals", totals);
  out.add("max_pressure_Pa", pmax);
  return out;
}

template <int D>
void write_fields_vti(const Fields<D>& f, const std::string& path, VtkEncoding encoding) {
  if (f.spec.layout != FieldLayout::Grid)
    throw InputError(fmt::format("{}: a .vti file holds a grid, not a line of points", path));
  VtiImage im;
  for (int a = 0; a < D; ++a) {
    im.points[static_cast<std::size_t>(a)] = f.counts[static_cast<std::size_t>(a)];
    im.origin[static_cast<std::size_t>(a)] = f.nodes.front()[a];
    im.spacing[static_cast<std::size_t>(a)] = f.cell[a];
  }
  if (D == 2) im.spacing[2] = f.thickness;
  auto scalar = [&](const char* name, const std::vector<double>& v) {
    im.point_data.push_back({name, 1, v});
  };
  auto vector = [&](const char* name, auto get) {
    VtiArray arr{name, 3, {}};
    arr.values.reserve(3 * f.size());
    for (std::size_t k = 0; k < f.size(); ++k) push_vector<D>(arr.values, get(k));
    im.point_data.push_back(std::move(arr));
  };
  auto tensor = [&](const char* name, const std::vector<typename Fields<D>::Mat>& m) {
    VtiArray arr{name, 9, {}};
    arr.values.reserve(9 * f.size());
    for (const auto& x : m) push_tensor<D>(arr.values, x);
    im.point_data.push_back(std::move(arr));
  };
  scalar("density", f.density);
  scalar("volume_fraction", f.volume_fraction);
  vector("velocity", [&](std::size_t k) { return f.velocity[k]; });
  tensor("stress", f.stress);
  tensor("kinetic_stress", f.kinetic_stress);
  tensor("contact_stress", f.contact_stress);
  scalar("pressure", f.pressure);
  scalar("deviator", f.deviator);
  scalar("antisymmetry", f.antisymmetry);
  vector("principal_stress", [&](std::size_t k) { return f.principal[k]; });
  vector("major_direction",
         [&](std::size_t k) { return typename Space<D>::Vec(f.directions[k].col(0)); });
  tensor("ellipsoid", f.ellipsoid);
  im.scalars = "pressure";
  im.vectors = "velocity";
  im.tensors = "ellipsoid";
  write_vti(im, path, encoding);
}

#define SABLE_CG_INSTANTIATE(D)                                           \
  template struct Fields<D>;                                              \
  template void validate(const FieldSpec<D>&);                            \
  template Fields<D> coarse_grain(const Sample<D>&, const FieldSpec<D>&); \
  template void finish(Fields<D>&);                                       \
  template Fields<D>& accumulate(Fields<D>&, const Fields<D>&);           \
  template Fields<D>& scale(Fields<D>&, double);                          \
  template Fields<D>& average(Fields<D>&);                                \
  template Table field_table(const Fields<D>&);                           \
  template Summary field_summary(const Fields<D>&);                       \
  template void write_fields_vti(const Fields<D>&, const std::string&, VtkEncoding);
SABLE_CG_INSTANTIATE(2)
SABLE_CG_INSTANTIATE(3)
#undef SABLE_CG_INSTANTIATE

}  // namespace sable
