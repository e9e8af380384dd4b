// Force-network analyses of one Sample: force distributions, coordination, fabric and
// polarization (mobilisation of friction).
//
// Every function reads the conventions of sample.hpp: fn > 0 is compressive, ft the tangential
// force on grain i, n from i towards its partner; wall contacts have wall[k] = 1. Forces are in
// N (N per metre of thickness in 2D). Each analysis is a result struct, a function computing
// it, and summary()/table() turning it into the files of report.hpp. Bad options or data that
// cannot give the statistic (no contacts) raise InputError naming what is missing.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "sable/analysis/report.hpp"
#include "sable/analysis/sample.hpp"

namespace sable {

// ---------------------------------------------------------------- contact selections

// Masks over a ContactSet (true = selected), for the CLI's "bulk / wall / region" choices.
template <int D>
std::vector<bool> select_bulk(const ContactSet<D>& c);  // grain-grain contacts
template <int D>
std::vector<bool> select_walls(const ContactSet<D>& c);  // every grain-wall contact
template <int D>
std::vector<bool> select_wall(const ContactSet<D>& c, std::uint32_t wall);  // one wall's
// Contacts whose point (x_i + arm_i) lies in `region`; wall contacts only if include_walls.
template <int D>
std::vector<bool> select_region(const ContactSet<D>& c,
                                const std::vector<typename Space<D>::Vec>& x,
                                const Region<D>& region, bool include_walls = false);

// ---------------------------------------------------------------- force distributions

// For each side, x = |f| / f_norm, with f_norm the mean compressive normal force <f> (normal
// component; both sides are normalised by it, as Richefeu et al. 2009 Fig. 3 do), the mean
// |ft| (tangential component), or the given reference force f0 (Richefeu eq. 10, wet samples).
//  - pdf: histogram of x over [0, x_max] (x_max: the side's largest x), density normalised so
//    that it integrates to 1 over the side's own samples; the side's count and fraction of all
//    selected contacts are reported beside it;
//  - tail (eq. 9, P ~ exp(-beta x) for x > 1): maximum likelihood of a truncated exponential,
//    beta = 1 / mean(x - 1), standard error beta / sqrt(n_tail); and for comparison a
//    count-weighted least-squares line through log(pdf) of the bins wholly above x = 1;
//  - alpha (eq. 10, P ~ exp(-alpha x) over the whole side): 1 / mean(x);
//  - p0: the density of x over [0, p0_window), i.e. P(0) read off a fixed window at zero;
//  - fraction_below_mean: share of the side with |f| below the side's mean.
// A side with no sample (the tensile side of a dry sample) has count 0, NaN statistics (null in
// the summary) and an empty histogram.
enum class ForceComponent { normal, tangential };

struct ForceStatsOptions {
  bool include_walls = false;  // default: grain-grain contacts only
  int bins = 50;               // histogram bins of each side's PDF
  ForceComponent component = ForceComponent::normal;
  // Normalising force f0 (> 0), e.g. the capillary force of a wet sample (Richefeu et al. 2009
  // eq. 10). 0: normalise by the mean, <f> of the compressive forces (normal) or <|ft|>.
  double reference_force = 0.0;
  double p0_window = 0.1;  // P(0) = density of x = |f| / f_norm over [0, p0_window)
};

// Fit of an exponential tail P(x) ~ exp(-beta x) over x > 1 (x = |f| / f_norm).
struct TailFit {
  std::size_t n_tail = 0;  // samples with x > 1
  double beta = 0.0;       // maximum likelihood: 1 / mean(x - 1)
  double beta_stderr = 0.0;
  double beta_lsq = 0.0;     // weighted least squares of log(pdf) on the bins above x = 1
  double r2_lsq = 0.0;       // its (weighted) coefficient of determination
  std::size_t lsq_bins = 0;  // bins used by the least-squares fit
};

// The distribution of |f| / f_norm over one side: compressive or tensile normal forces, or
// the tangential force magnitudes.
struct ForceDistribution {
  std::string side;      // "compressive", "tensile" or "tangential"
  std::string variable;  // table column of x: "f_over_mean", "f_over_f0", "ft_over_mean", ...
  std::size_t count = 0;
  double fraction = 0.0;             // count / all selected contacts
  double mean_force = 0.0;           // mean |f| of this side (N, N/m in 2D)
  double fraction_below_mean = 0.0;  // share of this side with |f| < mean_force
  double alpha = 0.0;                // exponential fit over the whole side: 1 / mean(x)
  double p0 = 0.0;                   // density near x = 0 (see p0_window)
  TailFit tail;
  double bin_width = 0.0;           // histogram over [0, bins * bin_width), x units
  std::vector<double> counts, pdf;  // pdf integrates to 1 over this side's samples
};

struct ForceStats {
  ForceComponent component = ForceComponent::normal;
  bool include_walls = false;
  int dim = 3;
  std::size_t contacts = 0;    // selected contacts
  std::size_t zero_count = 0;  // normal: contacts with fn == 0 exactly (on neither side)
  double f_norm = 0.0;         // the normalising force
  bool reference = false;      // f_norm is the given reference_force
  double p0_window = 0.1;
  std::vector<ForceDistribution> sides;  // normal: {compressive, tensile}; else {tangential}
};

template <int D>
ForceStats force_statistics(const ContactSet<D>& c, const ForceStatsOptions& opt = {});
Summary summary(const ForceStats& s);
Table table(const ForceDistribution& d);  // one CSV per side: x_lo, x_hi, x, count, pdf

// ---------------------------------------------------------------- coordination

struct CoordinationOptions {
  // Remove rattlers repeatedly (a grain left with too few contacts once its rattling
  // neighbours are removed becomes one too). Off: one pass, as in the plain definition.
  bool iterate_rattlers = false;
};

// z = 2 N_c / N over grain-grain contacts (wall contacts reported apart); a sample without
// contacts is valid (z = 0, every grain a rattler). Fixed grains count like free ones.
struct Coordination {
  int dim = 3;
  std::size_t grains = 0, fixed_grains = 0;
  std::size_t contacts = 0;  // grain-grain
  std::size_t compressive = 0, tensile = 0, wall_contacts = 0;
  double z = 0.0;                               // 2 contacts / grains
  double z_compressive = 0.0, z_tensile = 0.0;  // 2 compressive (tensile) / grains
  double wall_per_grain = 0.0;                  // wall_contacts / grains
  int rattler_threshold = 3;                    // fewer contacts than this (walls counted): rattler
  std::size_t rattlers = 0;
  double rattler_fraction = 0.0;
  std::size_t non_rattler_contacts = 0;  // grain-grain contacts between non-rattlers
  double z_without_rattlers = 0.0;       // 2 non_rattler_contacts / non-rattler grains
  std::vector<std::uint32_t> per_grain;  // force-carrying contacts of each grain (walls too)
  std::vector<std::uint8_t> rattler;     // 1 for a rattler
};

template <int D>
Coordination coordination(const Sample<D>& s, const CoordinationOptions& opt = {});
Summary summary(const Coordination& c);
Table table(const Coordination& c);  // contacts, grains, fraction: the contact-number histogram

// ---------------------------------------------------------------- fabric

struct FabricOptions {
  bool include_walls = false;
  bool compressive_only = false;  // only contacts with fn > 0
  int bins = 36;                  // 2D angle / 3D polar-angle histogram
  int azimuth_bins = 36;          // 3D only
};

struct Fabric {
  int dim = 3;
  std::size_t contacts = 0;
  Eigen::MatrixXd tensor;        // phi = <n (x) n>, D x D
  Eigen::VectorXd eigenvalues;   // descending
  Eigen::MatrixXd eigenvectors;  // columns, matching; sign: largest component positive
  double anisotropy = 0.0;       // 2D: 2 (phi1 - phi2); 3D: 5/2 (phi1 - phi3)
  double major_angle_deg = 0.0;  // 2D: direction of the major eigenvector in [0, 180)
  // 2D: angle of n in [0, 180) deg. 3D: polar angle of n from z folded to [0, 90] deg.
  std::vector<double> angle_lo_deg, angle_hi_deg, counts, density;
  std::vector<double> over_isotropic;  // density / isotropic density (1 when isotropic)
  // 3D: azimuth of the projection of n on xy, folded to [0, 180) deg (contacts along z skipped).
  std::vector<double> azimuth_counts, azimuth_density;
  std::size_t azimuth_skipped = 0;
};

template <int D>
Fabric fabric(const ContactSet<D>& c, const FabricOptions& opt = {});
Summary summary(const Fabric& f);
Table table(const Fabric& f);          // the 2D angle / 3D polar-angle histogram
Table azimuth_table(const Fabric& f);  // 3D azimuth histogram (empty table in 2D)

// ---------------------------------------------------------------- polarization

struct PolarizationOptions {
  int bins = 50;               // histogram of m over [0, 1]
  double eps = 0.01;           // on the Coulomb cone: m >= 1 - eps; 0 <= eps < 1
  std::string label = "bulk";  // what the selection is, echoed in the summary
};

struct Polarization {
  std::string label;
  double eps = 0.01;
  std::size_t selected = 0;                  // contacts in the mask
  std::size_t excluded_non_compressive = 0;  // fn <= 0
  std::size_t excluded_frictionless = 0;     // fn > 0 but mu <= 0
  std::size_t count = 0;                     // used: fn > 0 and mu > 0
  std::size_t sliding = 0;                   // m >= 1 - eps
  double fraction_sliding = 0.0;
  double mean_m = 0.0, max_m = 0.0;
  std::size_t above_one = 0;        // m > 1 (outside the cone; counted in the last bin)
  std::vector<double> counts, pdf;  // over [0, 1], bins of 1 / bins
};

// m = |ft| / (mu fn) for the masked contacts (Dumont, Fortin & Ouafik 2010: m = 1 on the
// Coulomb cone, |ft| = mu fn, where the contact slides or is about to).
template <int D>
Polarization polarization(const ContactSet<D>& c, const std::vector<bool>& mask,
                          const PolarizationOptions& opt = {});
Summary summary(const Polarization& p);
Table table(const Polarization& p);  // m_lo, m_hi, m, count, pdf

}  // namespace sable
