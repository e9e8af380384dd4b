// Coarse-grained continuum fields of a granular sample: density, volume fraction, velocity,
// kinetic and contact stress, and what derives from them (pressure, deviator, principal
// stresses and directions, stress ellipsoids), on a regular grid or along a line.
//
// The method is Glasser & Goldhirsch's (Phys. Fluids 13, 2001; Goldhirsch, Granular Matter 12,
// 2010): every grain quantity is smeared with a kernel w(x) of unit integral, so that
//   rho(x)        = sum_i m_i w(x - x_i)
//   rho v(x)      = sum_i m_i v_i w(x - x_i)
//   sigma_k(x)    = sum_i m_i v'_i (x) v'_i w(x - x_i),       v'_i = v_i - v(x)
//   sigma_c(x)    = -sum_c f_c (x) l_c int_0^1 w(x - x_i - s l_c) ds
// with f_c the force on grain i, l_c = x_j - x_i the branch vector, and the stress POSITIVE IN
// COMPRESSION like everything in the analysis module (a pair pressed together has f_c . l_c < 0,
// so sigma_c . l_c . l_c > 0). These fields satisfy the continuum momentum balance exactly:
// div sigma_c = -sum_i F_i w(x - x_i) (+ the wall forces, see below), whatever the kernel.
// Integrated over all space: int rho = total mass, int sigma_c = the virial -sum_c f_c (x) l_c.
//
// Wall contacts are boundary forces: their branch runs from x_i to the contact point
// (ContactSet::branch = arm_i) and the force is the force on the grain. The wall's reaction is
// then a force density applied at the contact point, outside the grains, so inside the packing
// div sigma = rho g - rho a holds with walls as with grains, and the integral of sigma_c is the
// virial of all contacts, walls included.
//
// Kernels (CgKernel; `width` is w):
//  - "sphere": Guillard, Forterre & Pouliquen (2015) eq. (3)-(4): the average over a ball of
//    radius R = w (V_R = 4/3 pi R^3; pi R^2 * thickness in 2D). A contact counts with the
//    fraction of its branch segment inside the ball (eq. 3, exact segment-ball intersection),
//    a grain with the fraction of its own volume inside the ball (eq. 4: the exact lens volume
//    of two spheres, or the lens area of two disks). Density, momentum and the kinetic moment
//    use that same volume fraction, so that sigma_k is a true fluctuation (see finish()).
//  - "gaussian": w(r) = exp(-r^2 / (2 w^2)) / N for r < 3 w, 0 beyond; N makes the integral
//    over the truncated ball exactly 1, computed analytically (cg_gaussian_norm).
//  - "lucy": w(r) = 105 / (16 pi c^3) (1 + 3 r/c)(1 - r/c)^3 for r < c = w (3D);
//    5 / (pi c^2) (...) in 2D. Smooth (C2) at its edge: the best for fine grids.
//  Gaussian and Lucy weigh grains as point masses at their centres (Goldhirsch's choice);
//  the contact line integral uses Gauss-Legendre quadrature (8 points per panel, one panel per
//  kernel width of branch), so each quadrature point still carries a weight of unit integral.
//
// In 2D grains are disks of Sample::thickness: kernels are normalised over the plane and
// divided by the thickness, so that densities are kg/m^3 and stresses Pa as in 3D.
//
// Layouts (FieldLayout):
//  - Grid: `cells` cells per axis (or cells of size `spacing`) over `box`; one node at the
//    CENTRE of each cell, lo + (k + 1/2) h. The sum over nodes of a field times the cell volume
//    approximates its integral (midpoint rule).
//  - Line: `points` nodes from `from` to `to`, both ends included (one point: at `from`).
//
// Averaging over snapshots: coarse_grain() fills the linear sums (density, volume fraction,
// momentum density, kinetic second moment, contact stress, exact mass and virial) and calls
// finish(). To time-average, accumulate() the Fields of each snapshot, then average() (scale by
// 1 / snapshots and finish()): velocity, kinetic stress, pressure and principal values are
// derived from the averaged sums, never averaged themselves. The kinetic stress of an average
// is then <sum m v v w> - <rho v><rho v>/<rho>: fluctuations about the time-averaged mean
// velocity, which is the Reynolds stress a time-averaged momentum balance needs.
//
// Work: each grain and each contact visits only the nodes whose index range its kernel support
// can reach (the nodes lie on a regular lattice, so the range per axis is computed from the
// support's bounding box), serially in slot order: bit-identical results on any machine load.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "sable/analysis/report.hpp"
#include "sable/analysis/sample.hpp"
#include "sable/core/space.hpp"
#include "sable/io/vtk_xml.hpp"

namespace sable {

enum class CgKernel { Sphere, Gaussian, Lucy };
enum class FieldLayout { Grid, Line };

// "sphere", "gaussian", "lucy".
const char* cg_kernel_name(CgKernel k);
// Throws InputError naming `key` and listing the valid names.
CgKernel parse_cg_kernel(const std::string& name, const std::string& key = "kernel");

template <int D>
struct FieldSpec {
  using Vec = typename Space<D>::Vec;
  FieldLayout layout = FieldLayout::Grid;
  // Grid. The box: its unbounded sides (the default Region) are taken from grain_bounds().
  Region<D> box;
  std::array<int, D> cells{};  // cells per axis (each >= 1); all 0: use `spacing`
  // Cell size (m) when cells are all 0: ceil(L / spacing) cells per axis, the box grown about
  // its centre to a whole number of cells of exactly `spacing`.
  double spacing = 0.0;
  // Line.
  Vec from = Vec::Zero(), to = Vec::Zero();
  int points = 0;  // >= 1
  // Kernel.
  CgKernel kernel = CgKernel::Sphere;
  double width = 0.0;  // sphere radius R, Gaussian standard deviation, Lucy support c (m), > 0
};

// Throws InputError naming the key ("cells", "spacing", "width", "points", "from/to", "box") if
// the spec cannot describe a set of nodes and a kernel.
template <int D>
void validate(const FieldSpec<D>& spec);

template <int D>
struct Fields {
  using Vec = typename Space<D>::Vec;
  using Mat = Eigen::Matrix<double, D, D>;

  FieldSpec<D> spec;  // resolved: grid box and cells filled in, spacing = 0
  double thickness = 1.0;
  // Geometry. Grid: nodes x fastest, then y, then z; `cell` the cell size per axis.
  std::vector<Vec> nodes;
  Vec cell = Vec::Zero();
  std::array<int, D> counts{};  // grid: nodes per axis; line: {points, 1, ...}

  // Linear sums: what accumulate() adds and scale() multiplies.
  int snapshots = 0;            // how many samples were summed
  std::vector<double> density;  // rho (kg/m^3)
  std::vector<double> volume_fraction;
  std::vector<Vec> momentum;        // rho v (kg/(m^2 s))
  std::vector<Mat> second_moment;   // sum m_i v_i v_i w (Pa)
  std::vector<Mat> contact_stress;  // sigma_c (Pa), compression positive, not symmetrised
  double mass = 0.0;                // exact sum of the grain masses (kg)
  Mat virial = Mat::Zero();         // exact -sum_c f_c (x) l_c (J = Pa m^3)

  // Derived by finish().
  std::vector<Vec> velocity;        // momentum / rho; 0 where rho = 0
  std::vector<Mat> kinetic_stress;  // second_moment - rho v v (Pa)
  std::vector<Mat> stress;          // contact + kinetic (Pa)
  std::vector<double> pressure;     // tr(stress) / D (Pa)
  // Maximum shear stress (sigma_1 - sigma_D) / 2 (Pa), the radius of the largest Mohr circle,
  // the same quantity in 2D and 3D (in 2D it equals sqrt(s:s / 2), s the deviator).
  std::vector<double> deviator;
  std::vector<double> antisymmetry;  // Frobenius norm of (stress - stress^T) / 2 (Pa)
  std::vector<Vec> principal;        // eigenvalues of the symmetric part, descending (Pa)
  // Columns: unit principal directions in the order of `principal`, each with its largest
  // component positive (a deterministic sign); column 0 is the major direction.
  std::vector<Mat> directions;
  // Guillard et al. (2015) eq. (5): OM = sigma . n / P, the ellipsoid of the symmetric part
  // scaled by the pressure (semi-axes sigma_k / P along the principal directions); 0 where
  // P = 0.
  std::vector<Mat> ellipsoid;

  std::size_t size() const { return nodes.size(); }
  // Grid: the cell volume (area times thickness in 2D); line: 0.
  double cell_volume() const;
  // Grid: the sum over nodes of rho times the cell volume (kg); line: 0.
  double mass_on_grid() const;
  // Grid: the sum over nodes of sigma_c times the cell volume (J); line: 0.
  Mat virial_on_grid() const;
};

// Coarse-grain one sample: the linear sums, then finish(). Throws InputError (validate()).
// Why the sphere kernel refuses polyhedral grains: it spreads each grain's volume as a ball's
// (the fraction of the ball inside the kernel's), which a polyhedron is not.
inline constexpr const char* kSphereKernelPolyhedra =
    "the sphere kernel spreads each grain as a ball; use --kernel gaussian or lucy";

// Throws InputError for the sphere kernel on polyhedral grains (kSphereKernelPolyhedra).
template <int D>
Fields<D> coarse_grain(const Sample<D>& sample, const FieldSpec<D>& spec);

// Derive velocity, kinetic and total stress, pressure, deviator, principal values and
// directions, and ellipsoids from the linear sums.
template <int D>
void finish(Fields<D>& f);

// sum += add, on the linear sums (snapshots and exact totals included); an empty `sum`
// (no nodes, 0 snapshots) becomes a copy of `add`. Throws InputError unless both were made
// with the same nodes and kernel. Derived fields of `sum` are stale until finish().
template <int D>
Fields<D>& accumulate(Fields<D>& sum, const Fields<D>& add);

// Multiply the linear sums (and `snapshots`' weight: the exact totals) by `factor`.
template <int D>
Fields<D>& scale(Fields<D>& f, double factor);

// The time average of accumulated Fields: scale by 1 / snapshots, then finish().
template <int D>
Fields<D>& average(Fields<D>& f);

// One row per node: "s_m" (line: distance from `from`), "x_m", "y_m" ["z_m"],
// "density_kg_m3", "volume_fraction", "vx_m_s", ... , "sigma_xx_Pa", "sigma_xy_Pa", ...
// (all D x D components, row = first index), "contact_pressure_Pa", "kinetic_pressure_Pa",
// "pressure_Pa", "deviator_Pa", "antisymmetry_Pa", "sigma_1_Pa", ... (descending),
// "major_x", ... (the major direction).
template <int D>
Table field_table(const Fields<D>& f);

// Spec (layout, counts, box, cell size or line ends, kernel, width, reach), snapshots, and
// the totals: mass and virial (exact), and for a grid their integrals on the grid.
template <int D>
Summary field_summary(const Fields<D>& f);

// Grid layout only (InputError otherwise). PointData: density, volume_fraction, velocity (3),
// stress, kinetic_stress, contact_stress (9, row-major, 2D padded with zeros), pressure,
// deviator, antisymmetry, principal_stress (3, descending; 2D: sigma_3 = 0), major_direction
// (3), ellipsoid (9, sigma / P, the symmetric part; 2D: zz = 0). 2D: one layer of points at
// z = 0, z spacing = thickness.
template <int D>
void write_fields_vti(const Fields<D>& f, const std::string& path,
                      VtkEncoding encoding = VtkEncoding::kBinary);

// The weights, exposed for tests and for anyone building other averages on them.
namespace cg {

// Fraction of the segment [p, p + l] lying inside the ball |y - c| < R: the exact
// intersection length over |l| (0 for a tangent or missing segment; for l = 0, 1 if p is
// strictly inside).
template <int D>
double segment_fraction_in_ball(const typename Space<D>::Vec& p, const typename Space<D>::Vec& l,
                                const typename Space<D>::Vec& c, double radius);

// Volume of the intersection of two balls of radii r1, r2 with centres d apart (3D: the lens;
// 2D: the lens area of two disks).
template <int D>
double ball_intersection(double r1, double r2, double d);

// The volume (3D) or area (2D) of a ball of radius r.
template <int D>
double ball_measure(double r);

// The integral over the D-ball of radius 3 w of exp(-r^2 / (2 w^2)), in closed form:
// 2 pi w^2 (1 - e^{-9/2}) in 2D, 4 pi w^3 (sqrt(pi/2) erf(3/sqrt 2) - 3 e^{-9/2}) in 3D.
template <int D>
double gaussian_norm(double w);

// A kernel ready to weigh: normalisation, reach and the D-dim thickness factor precomputed.
template <int D>
struct Kernel {
  using Vec = typename Space<D>::Vec;
  CgKernel kind = CgKernel::Sphere;
  double width = 0.0;
  double thickness = 1.0;

  Kernel(CgKernel k, double w, double thick);
  // The support radius of a point weight (sphere R, Gaussian 3 w, Lucy c).
  double reach() const { return reach_; }
  // Weight per unit volume (1/m^3) of a point at distance sqrt(r2): the sphere's 1 / V_R
  // inside, the normalised Gaussian or Lucy; divided by the thickness in 2D.
  double point(double r2) const;
  // Weight of a grain of radius `radius` centred at d from the node: the sphere's volume
  // fraction inside the ball over V_R; the point weight otherwise. Reach: reach() + radius
  // for the sphere kernel, reach() otherwise.
  double grain(const Vec& d, double radius) const;
  double grain_reach(double radius) const;
  // int_0^1 weight(node - p - s l) ds (1/m^3): the contact's share of the node.
  double segment(const Vec& node, const Vec& p, const Vec& l) const;

 private:
  double reach_ = 0.0;
  double norm_ = 0.0;  // multiplies the unnormalised profile; includes 1 / thickness in 2D
};

}  // namespace cg

}  // namespace sable
