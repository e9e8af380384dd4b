// Stresses on walls as a function of height: what a silo designer compares with Janssen.
//
// The contacts of one wall are binned by the height of their contact point along an axis
// (default: against gravity). In each bin of height h the wall area is h times the wall's
// width: the out-of-plane thickness in 2D; in 3D the sample's extent along the plane wall's
// horizontal direction (or a width given by the user), or 2 pi R for a cylinder. Per bin:
//   normal stress  sigma_n = sum fn / area       (compression positive)
//   shear stress   tau     = sum ft . e_up / area (the friction the wall exerts on the grains
//                            along the axis: positive when the wall holds the grains up)
//   mobilisation   sum |ft| / sum mu fn          (1 when every contact slides)
// Depth is measured from the top of the packing (the highest grain top along the axis).
#pragma once

#include <string>
#include <vector>

#include "sable/analysis/report.hpp"
#include "sable/analysis/sample.hpp"

namespace sable {

struct WallProfileOptions {
  int axis = -1;       // 0, 1, 2; -1: the axis most opposed to gravity (z in 3D, y in 2D)
  double bin = 0.0;    // bin height (m); <= 0: twice the mean grain diameter
  double width = 0.0;  // wall width (m, 3D planes); <= 0: from the grains' extent
  // Fixed bins (to average profiles over snapshots): lowest bin edge, number of bins, and the
  // top depth is measured from. count = 0: from this sample's grains.
  double bottom = 0.0, top = 0.0;
  std::size_t count = 0;
};

struct WallProfile {
  std::string wall;
  int axis = 0;
  double bin = 0.0, width = 0.0, top = 0.0;
  std::vector<double> height, depth, sigma_n, tau, abs_tau, mobilisation;
  std::vector<std::size_t> contacts;
  double total_normal = 0.0, total_shear = 0.0;  // sums of fn and ft . e_up (N)
};

// Throws InputError naming the wall if no wall has that name (listing those that exist).
template <int D>
WallProfile wall_profile(const Sample<D>& s, const std::string& wall,
                         const WallProfileOptions& opt);

// True for a wall a height profile makes sense for: a cylinder, or a plane not perpendicular
// to the profile axis (a side wall, not a floor or a lid). Never a mesh.
template <int D>
bool is_side_wall(const Sample<D>& s, std::size_t wall, int axis = -1);

// Sum of profiles with the same bins (b's values added to a's), and division by n.
void accumulate(WallProfile& sum, const WallProfile& add);
void scale(WallProfile& p, double factor);

Table wall_profile_table(const WallProfile& p);
Summary wall_profile_summary(const WallProfile& p);

}  // namespace sable
