// The contact law of contact_model.hpp for a batch of 3D grain-pair contacts at once, laid out
// as lanes (one array per quantity), so that the compiler runs it in SIMD registers: 2, 4 or 8
// contacts per instruction (SSE2, AVX2 or AVX-512, chosen at run time).
//
// Why a second copy of the law: contact_force() branches on the contact's state (sliding or
// not, a spring to turn or not), which stops the vectorizer, and it is the kernel every other
// caller (walls, the wet and rolling passes, 2D) keeps. This one takes every branch as a
// select, operation for operation as contact_force() does it, so its results are the same
// bits: tests/unit/test_contact_lanes.cpp checks that over every option of the law, and the
// DEM state hashes are unchanged by it. Change the two together.
//
// The DEM's dry pass fills the lanes from the grains it finds touching, runs the batch, and
// then adds each force to its grains in list order (dem/dem_solver_impl.hpp, PairPass::entries).
#pragma once

#include <cstdint>
#include <string_view>

#include "sable/contact/registry.hpp"

namespace sable {

struct alignas(64) ContactLanes {
  // 64 contacts: about 20 KiB of lanes, within the L1 data cache next to what the pass reads.
  static constexpr int kWidth = 64;
  // Inputs. d = x_i - x_j with |d|^2 = dist2 < rsum^2; dv = v_i - v_j; w: angular velocities;
  // inv_mass: 1/m (0 for a fixed grain); the pair's material parameters (PairParams).
  double dx[kWidth], dy[kWidth], dz[kWidth], dist2[kWidth], rsum[kWidth];
  double ra[kWidth], rb[kWidth], inv_mass_a[kWidth], inv_mass_b[kWidth];
  double dvx[kWidth], dvy[kWidth], dvz[kWidth];
  double wax[kWidth], way[kWidth], waz[kWidth], wbx[kWidth], wby[kWidth], wbz[kWidth];
  double y_star[kWidth], g_star[kWidth], beta[kWidth], st_over_sn_sqrt[kWidth], friction[kWidth];
  // The tangential spring: read, then written back turned, advanced and capped.
  double sx[kWidth], sy[kWidth], sz[kWidth];
  // Outputs: the force on grain i, n x F, the overlap, and the lever arms R - delta/2.
  double fx[kWidth], fy[kWidth], fz[kWidth], mx[kWidth], my[kWidth], mz[kWidth];
  double delta[kWidth], lever_a[kWidth], lever_b[kWidth];
  // Bookkeeping for the caller: the list entry and the two grains of each lane.
  std::uint32_t entry[kWidth], a[kWidth], b[kWidth];

  // Lane l from pair params p (the other inputs are written by the caller).
  void set_params(int l, const PairParams& p) {
    y_star[l] = p.y_star;
    g_star[l] = p.g_star;
    beta[l] = p.beta;
    st_over_sn_sqrt[l] = p.st_over_sn_sqrt;
    friction[l] = p.friction;
  }
};

// Lanes [0, n) (n <= kWidth): what contact_force<3, HertzNormal>() gives for each, without
// cohesion. (The linear law's lanes did not vectorize: GCC 12 kept its PairParams in memory.
// It runs contact_force() one contact at a time.)
// It runs the widest instruction set this machine has (an AVX-512, an AVX2 and a baseline
// SSE2 copy are compiled in, all giving the same bits).
void contact_lanes_hertz(ContactLanes& lanes, int n, const ContactModel& model, double dt);

// The instruction sets of the batched law, narrowest first.
enum class SimdLevel : std::uint8_t { kBaseline, kAvx2, kAvx512 };
SimdLevel best_simd_level();
std::string_view simd_level_name(SimdLevel level);
// The copy for `level` (tests compare them); std::invalid_argument if this machine lacks it.
void contact_lanes_hertz(SimdLevel level, ContactLanes& lanes, int n, const ContactModel& model,
                         double dt);

}  // namespace sable
