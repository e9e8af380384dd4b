// Stresses from grains and contacts: per particle, over a region, and with body forces.
//
// Sign and order conventions (docs/analysis.md): stresses are positive in compression, and a
// tensor built from a force f and a lever x is f (x) x, i.e. sigma_ab = sum f_a x_b, as in
// Richefeu et al. (2009) eq. 11. Dumont-Fortin-Ouafik (2010) write x (x) f positive in
// tension: their Sigma is minus the transpose of ours.
//
//  - particle stress (Richefeu eq. 11-13): sigma_i = -(1/V_i) sum_c f_c (x) arm_c, the sum over
//    grain i's contacts (grains and walls), f_c the force on i, arm_c = contact point - x_i,
//    V_i = V_grain / nu the grain's free volume (eq. 12: pi d^3 / (6 nu) for a sphere), and
//    p_i = tr(sigma_i) / D;
//  - Love-Weber over a region of volume V: sigma = -(1/V) sum over contacts of the grains whose
//    centre lies in the region, f (x) (arm_i - arm_j) when both grains are inside, f (x) arm_i
//    (or -f (x) arm_j) when only one is, so sum_i V_i sigma_i / V equals it exactly;
//  - mean stress with body forces (Dumont-Fortin-Ouafik eq. 16; de Saxce et al. 2004), summed
//    over the free (not fixed) grains of the region about a reference point x0:
//      contact  part  C = -(1/V) sum_i sum_c f_c (x) (x_c - x0)
//      gravity  part  G = -(1/V) sum_i m_i g (x) (x_i - x0)
//      inertia  part  A = +(1/V) sum_i [ m_i a_i (x) (x_i - x0) + J_i ([alpha_i]x + w w^T - |w|^2
//      I) ]
//    with J_i = I_i / 2 the grain's second moment of mass (int rho r r^T = J_i Id for a disk or
//    sphere; a polyhedron's J_i is its tensor, Sample::second_moment, multiplying on the right).
//    Each part alone need not be symmetric; their sum is, when every grain obeys m a = sum f + m g
//    and I alpha = sum arm x f (any instant of a DEM run; a CD step up to the solver's tolerance),
//    and it does not depend on x0.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "sable/analysis/report.hpp"
#include "sable/analysis/sample.hpp"

namespace sable {

template <int D>
using Tensor = Eigen::Matrix<double, D, D>;

template <int D>
struct ParticleStresses {
  std::vector<Tensor<D>> sigma;  // per grain (Pa), positive in compression
  std::vector<double> pressure;  // tr(sigma) / D (Pa)
  std::vector<double> free_volume;
  double solid_fraction = 0.0;  // the nu used for the free volumes
};

// nu <= 0: use the solid fraction of the grains' bounding box (sum of grain volumes / box).
template <int D>
ParticleStresses<D> particle_stresses(const Sample<D>& s, double solid_fraction = 0.0);

// Solid fraction of a region: grain volumes whose centre lies inside, over the region volume.
template <int D>
double solid_fraction(const Sample<D>& s, const Region<D>& region);

template <int D>
Tensor<D> love_weber(const Sample<D>& s, const Region<D>& region);

template <int D>
struct MeanStress {
  Tensor<D> contact = Tensor<D>::Zero(), gravity = Tensor<D>::Zero(), inertia = Tensor<D>::Zero();
  Tensor<D> total() const { return contact + gravity + inertia; }
  typename Space<D>::Vec origin = Space<D>::Vec::Zero();
  double volume = 0.0;
  std::size_t grains = 0;
};

// The reference point x0 defaults to the coordinates' origin, as the paper writes x; the total
// does not depend on it, the parts do.
template <int D>
MeanStress<D> mean_stress(const Sample<D>& s, const Region<D>& region,
                          const typename Space<D>::Vec& origin = Space<D>::Vec::Zero());

// |A - A^T| / 2 over |A| (Frobenius), 0 for a zero tensor: how far from symmetric.
template <int D>
double asymmetry(const Tensor<D>& t);

// Outputs: per-grain table (id, position, pressure, sigma components) and the pressure PDF.
template <int D>
Table particle_stress_table(const Sample<D>& s, const ParticleStresses<D>& ps);
template <int D>
Summary tensor_summary(const Tensor<D>& t);
template <int D>
Summary mean_stress_summary(const MeanStress<D>& m, const Tensor<D>& love_weber);

}  // namespace sable
