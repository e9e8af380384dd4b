// Janssen's silo model fitted to measured wall stresses (Dumont-Fortin-Ouafik 2010, eq. 4).
//
// In a silo of cross-section A and wall perimeter P, with wall friction mu_w and a constant
// ratio K = sigma_xx / sigma_zz, the vertical stress at depth z below the free surface is
//   sigma_zz(z) = rho_b g lambda (1 - exp(-z / lambda)),   lambda = A / (P K mu_w),
// and the wall normal stress sigma_xx = K sigma_zz. A 2D silo of width W has A / P = W / 2
// (lambda = W / (2 K mu_w)); a cylinder of diameter D and a square box of side W have A / P =
// D / 4 and W / 4. Note sigma_xx(z) = rho_b g (A / P) / mu_w (1 - exp(-z / lambda)): its
// saturation does not depend on K, only the depth over which it is reached does.
//
// The fit: K minimising the squared residuals of the measured wall normal stress (least squares
// over log K, golden section), its standard error from the curvature of the residual sum, and
// R^2 = 1 - SS_res / SS_tot. Measured bins with no contact are left out.
#pragma once

#include <vector>

#include "sable/analysis/report.hpp"

namespace sable {

struct JanssenInput {
  std::vector<double> depth, sigma_xx;  // measured profile (m, Pa)
  double rho_b = 0.0;                   // bulk density (kg/m^3)
  double g = 9.81;                      // |gravity| (m/s^2)
  double area_over_perimeter = 0.0;     // A / P (m)
  double mu_w = 0.0;                    // wall friction
  double height = 0.0;                  // packing height H (m)
};

struct JanssenFit {
  double k = 0.0, k_stderr = 0.0, lambda = 0.0, r2 = 0.0;
  std::size_t points = 0;
  double saturation = 0.0;          // rho_b g (A / P) / mu_w, the deep wall normal stress (Pa)
  double sigma_zz_bottom = 0.0;     // Janssen's vertical stress at depth H (Pa)
  double hydrostatic_bottom = 0.0;  // rho_b g H (Pa)
  std::vector<double> depth, measured, fitted;  // the fitted points
};

// Throws InputError if fewer than 3 bins carry contacts or an input is not positive.
JanssenFit janssen_fit(const JanssenInput& in);

// sigma_xx(z) of the model for a given K.
double janssen_wall_stress(const JanssenInput& in, double k, double depth);

Summary janssen_summary(const JanssenFit& f);
Table janssen_table(const JanssenFit& f);

}  // namespace sable
