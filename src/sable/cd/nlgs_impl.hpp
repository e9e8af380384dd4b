// Implementation of nlgs.hpp. The local solvers (solve_local) depend on d only: they are
// defined in local_solvers.cpp and explicitly instantiated there for d = 2, 3. The projection,
// the natural map and the loops over a Problem (solve_nlgs, natural_map_error) are templates
// defined here.
#pragma once

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include "sable/core/parallel.hpp"

namespace sable::cd {

// The projection and the natural map are here, not in local_solvers.cpp, so that the residual
// pass after every sweep (natural_map_error) inlines them: out of line, that pass runs 14 %
// more instructions (callgrind on bench/pour_cd.sh).
// |x_T|, the norm of the tangential part.
template <int d>
double tangent_norm(const LVec<d>& x) {
  return x.template tail<d - 1>().norm();
}

template <int d>
LVec<d> project_cone(const LVec<d>& x, double mu) {
  LVec<d> p = LVec<d>::Zero();
  const double xn = x[0];
  if (mu <= 0.0) {  // frictionless: the cone is the half-line of normal impulses
    p[0] = std::max(xn, 0.0);
    return p;
  }
  const double t = tangent_norm<d>(x);
  if (t <= mu * xn) return x;   // inside K_mu
  if (mu * t <= -xn) return p;  // in the polar cone: projects onto the apex
  // Onto the boundary generator through x_T: (s, mu s x_T / |x_T|), s = (x_N + mu t)/(1 + mu^2).
  const double sn = (xn + mu * t) / (1.0 + mu * mu);
  p[0] = sn;
  p.template tail<d - 1>() = (mu * sn / t) * x.template tail<d - 1>();
  return p;
}

template <int d>
LVec<d> natural_map(const LVec<d>& r, const LVec<d>& U, double mu) {
  LVec<d> u_ds = U;  // De Saxce's modified velocity U + mu |U_T| e_N
  u_ds[0] += mu * tangent_norm<d>(U);
  return r - project_cone<d>(r - u_ds, mu);
}

extern template LVec<2> solve_local<2>(const LMat<2>&, const LVec<2>&, double, const LVec<2>&,
                                       LocalSolver);
extern template LVec<3> solve_local<3>(const LMat<3>&, const LVec<3>&, double, const LVec<3>&,
                                       LocalSolver);

// The contact order of sweep number `sweep` (0-based) into `order` (whose size is the number of
// contacts): forward 0..n-1; alternating: forward on even sweeps, backward on odd ones; shuffled:
// a fresh Fisher-Yates permutation of 0..n-1 drawn with rng.below().
void fill_sweep_order(std::vector<std::size_t>& order, SweepOrder o, int sweep, Rng& rng);

// What one sweep measured, for the Quad and Maxm criteria (see nlgs_sweep).
struct SweepStats {
  double du2 = 0.0;     // sum_a |U_a^k - U_a^{k-1}|^2
  double u2 = 0.0;      // sum_a |U_a^k|^2
  double du_max = 0.0;  // max_a |U_a^k - U_a^{k-1}|
  double u_sum = 0.0;   // sum_a |U_a^k|
};

// One Gauss-Seidel sweep over the contacts in `order`. For each contact a:
//   U = U_a (current), q = U - W_aa r_a, r_loc = solve_local(W_aa, q, mu_a, r_a),
//   r_a <- r_a + s.relaxation (r_loc - r_a), through problem.apply().
// If `last_u` is not empty (size n), U_a^k = U + W_aa dr_a, the velocity of a just after its
// update in sweep k, is compared with last_u[a] (the same in sweep k-1; the initial velocity
// before the first sweep), last_u[a] is replaced by U_a^k, and the sums of SweepStats are
// accumulated. Allocates nothing.
template <int d, class Problem>
SweepStats nlgs_sweep(Problem& problem, std::span<const std::size_t> order, const NlgsSettings& s,
                      std::span<LVec<d>> last_u) {
  SweepStats st;
  const bool track = !last_u.empty();
  for (const std::size_t a : order) {
    const LVec<d> U = problem.velocity(a);
    const LMat<d>& W = problem.W(a);
    const LVec<d> r_old = problem.r(a);
    const LVec<d> q = U - W * r_old;
    const LVec<d> r_loc = solve_local<d>(W, q, problem.mu(a), r_old, s.local);
    const LVec<d> dr = s.relaxation * (r_loc - r_old);
    problem.apply(a, dr);
    // A problem with more unknowns per contact than the impulse (rolling couples) solves them
    // right after, from the contact's new normal impulse.
    if constexpr (requires { problem.solve_extra(a); }) problem.solve_extra(a);
    if (track) {
      const LVec<d> u_new = U + W * dr;
      const double du = (u_new - last_u[a]).norm();
      const double u = u_new.norm();
      st.du2 += du * du;
      st.u2 += u * u;
      st.du_max = std::max(st.du_max, du);
      st.u_sum += u;
      last_u[a] = u_new;
    }
  }
  return st;
}

namespace detail {

// Below this many contacts a coloured sweep and its residual stay on one thread (the same
// bits: only the team changes); above, the team's start-up is small beside the work.
inline constexpr auto kMinParallelContacts = static_cast<std::size_t>(kMinParallelItems);

inline void add_stats(SweepStats& to, const SweepStats& from) {
  to.du2 += from.du2;
  to.u2 += from.u2;
  to.du_max = std::max(to.du_max, from.du_max);
  to.u_sum += from.u_sum;
}

}  // namespace detail

// One sweep in the coloured order (colouring.hpp): colour after colour, the blocks of a
// colour shared among the threads (any schedule: they touch disjoint bodies), each block
// swept by nlgs_sweep in index order; then the serial tail. The blocks' stats go to
// block_stats (size: the blocks) and are added in block order, so the result's bits do not
// depend on the threads either.
template <int d, class Problem>
SweepStats nlgs_sweep_coloured(Problem& problem, const SweepColouring& col, const NlgsSettings& s,
                               std::span<LVec<d>> last_u, std::span<SweepStats> block_stats) {
  const bool parallel = problem.size() >= detail::kMinParallelContacts;
#pragma omp parallel if (parallel)
  for (std::size_t c = 0; c < col.colours(); ++c) {
#pragma omp for schedule(dynamic, 4)
    for (std::size_t b = col.colour_begin(c); b < col.colour_begin(c + 1); ++b)
      block_stats[b] = nlgs_sweep<d>(problem, col.block(b), s, last_u);
  }
  SweepStats st;
  for (std::size_t b = 0; b < col.blocks(); ++b) detail::add_stats(st, block_stats[b]);
  detail::add_stats(st, nlgs_sweep<d>(problem, col.serial(), s, last_u));
  return st;
}

namespace detail {

// num / den with the conventions 0 / 0 = 0 and x / 0 = +inf (x > 0).
inline double safe_ratio(double num, double den) {
  if (num == 0.0) return 0.0;
  return den > 0.0 ? num / den : std::numeric_limits<double>::infinity();
}

// The criterion of nlgs.hpp, from the stats of sweep k (n contacts, n > 0):
//   Quad = sqrt( sum_a |U_a^k - U_a^{k-1}|^2 / sum_a |U_a^k|^2 )
//   Maxm = max_a |U_a^k - U_a^{k-1}| / ( (1/n) sum_a |U_a^k| )
// with U_a^k the local velocity of contact a right after its update in sweep k (U_a^0: before
// the first sweep). A fully sticking solution has U = 0: there 0/0 counts as 0 (converged).
inline double sweep_criterion(Criterion c, const SweepStats& st, std::size_t n) {
  if (c == Criterion::kQuad) return std::sqrt(safe_ratio(st.du2, st.u2));
  return safe_ratio(st.du_max, st.u_sum / static_cast<double>(n));
}

// The natural map's sums over contacts [a0, a1), added to s = {f2, r2, u2} in index order.
template <int d, class Problem>
void natural_map_sums(Problem& problem, std::size_t a0, std::size_t a1, std::array<double, 3>& s) {
  double f2 = s[0], r2 = s[1], u2 = s[2];
  for (std::size_t a = a0; a < a1; ++a) {
    const LVec<d> U = problem.velocity(a);
    const LVec<d> r = problem.r(a);
    f2 += natural_map<d>(r, U, problem.mu(a)).squaredNorm();
    r2 += r.squaredNorm();
    u2 += U.squaredNorm();
    if constexpr (requires { problem.extra_residual(a, f2, r2, u2); })
      problem.extra_residual(a, f2, r2, u2);
  }
  s = {f2, r2, u2};
}

template <class Problem>
double natural_map_ratio(const Problem& problem, const std::array<double, 3>& s) {
  const double den = std::max({problem.q_norm(), std::sqrt(s[1]), std::sqrt(s[2])});
  return safe_ratio(std::sqrt(s[0]), den);
}

inline constexpr std::size_t kErrorChunk = 1024;  // contacts per partial sum

// natural_map_error's sum in fixed chunks of contacts, the chunks' partial sums (in
// `partial`, reused by the caller from sweep to sweep) added in chunk order: what the coloured
// sweep uses, spread over the threads with the same bits for any count.
template <int d, class Problem>
double natural_map_error_chunked(Problem& problem, std::vector<std::array<double, 3>>& partial) {
  const std::size_t n = problem.size();
  const std::size_t chunks = (n + kErrorChunk - 1) / kErrorChunk;
  partial.assign(chunks, {0.0, 0.0, 0.0});
#pragma omp parallel for schedule(static) if (n >= kMinParallelContacts)
  for (std::size_t k = 0; k < chunks; ++k)
    natural_map_sums<d>(problem, k * kErrorChunk, std::min(n, (k + 1) * kErrorChunk), partial[k]);
  std::array<double, 3> s = {0.0, 0.0, 0.0};
  for (const auto& p : partial)
    for (int m = 0; m < 3; ++m) s[m] += p[m];
  return natural_map_ratio(problem, s);
}

}  // namespace detail

template <int d, class Problem>
double natural_map_error(Problem& problem) {
  std::array<double, 3> s = {0.0, 0.0, 0.0};
  detail::natural_map_sums<d>(problem, 0, problem.size(), s);
  return detail::natural_map_ratio(problem, s);
}

template <int d, class Problem>
NlgsResult solve_nlgs(Problem& problem, const NlgsSettings& s, Rng& rng) {
  NlgsResult res;
  const std::size_t n = problem.size();
  if (n == 0) {
    res.converged = true;
    return res;
  }
  const bool coloured = s.order == SweepOrder::kColoured;
  std::vector<std::size_t> order(coloured ? 0 : n);
  std::vector<SweepStats> block_stats;
  std::vector<std::array<double, 3>> partial;  // the chunked residual's sums
  if constexpr (requires { problem.colouring(); }) {
    if (coloured) block_stats.resize(problem.colouring().blocks());
  } else if (coloured) {
    throw std::invalid_argument("NLGS: the coloured order needs a problem with a colouring");
  }
  std::vector<LVec<d>> last_u;
  if (s.criterion != Criterion::kNatural) {
    last_u.resize(n);
    for (std::size_t a = 0; a < n; ++a) last_u[a] = problem.velocity(a);
  }
  auto sweep = [&](SweepOrder o, int k) {
    if constexpr (requires { problem.colouring(); }) {
      if (o == SweepOrder::kColoured)
        return nlgs_sweep_coloured<d>(problem, problem.colouring(), s, std::span<LVec<d>>(last_u),
                                      std::span<SweepStats>(block_stats));
    }
    fill_sweep_order(order, o, k, rng);
    return nlgs_sweep<d>(problem, order, s, std::span<LVec<d>>(last_u));
  };
  auto residual = [&] {
    return coloured ? detail::natural_map_error_chunked<d>(problem, partial)
                    : natural_map_error<d>(problem);
  };
  bool error_is_residual = false;
  SweepOrder sweep_order = s.order;
  double checkpoint = 0.0;  // the error after sweep checkpoint_at (the first, then each window's)
  int checkpoint_at = 1;
  bool checked = true;  // res.error is the state's after the last sweep
  for (int k = 0; k < s.max_iterations; ++k) {
    const SweepStats st = sweep(sweep_order, k);
    res.iterations = k + 1;
    error_is_residual = s.criterion == Criterion::kNatural;
    checked = !error_is_residual || !s.spaced_checks || residual_due(k + 1);
    if (!checked) continue;
    res.error = error_is_residual ? residual() : detail::sweep_criterion(s.criterion, st, n);
    if (res.error <= s.tolerance) {
      res.converged = true;
      break;
    }
    // A NaN never falls below the tolerance, and sweeps over non-finite data cost hundreds of
    // times a normal one: stop, and let the caller report the state (the residual says why).
    // An infinite sweep criterion (Quad, Maxm) can be a normal event (every U reaching 0 at
    // once); an infinite natural-map residual cannot.
    if (std::isnan(res.error) || (error_is_residual && std::isinf(res.error))) break;
    if (k == 0) checkpoint = res.error;
    if (s.stagnation_window > 0 && k + 1 - checkpoint_at >= s.stagnation_window) {
      if (res.error > 0.9 * checkpoint) {
        // The coloured order stays (a shuffle would give up the threads).
        const bool shuffle = s.shuffle_on_stagnation && sweep_order != SweepOrder::kShuffled &&
                             sweep_order != SweepOrder::kColoured;
        if (!shuffle && s.stop_on_stagnation) {
          res.stagnated = true;
          break;
        }
        if (shuffle) {
          res.reordered_at = k + 1;
          sweep_order = SweepOrder::kShuffled;
        }
      }
      checkpoint = res.error;
      checkpoint_at = k + 1;
    }
  }
  if (!checked) {  // the last sweep (the cap) was between two checks
    res.error = residual();
    res.converged = res.error <= s.tolerance;
  }
  res.residual = error_is_residual ? res.error : residual();
  if (res.iterations == 0) {  // max_iterations <= 0: report the state as it is
    res.error = res.residual;
    res.converged = res.residual <= s.tolerance;
  }
  return res;
}

}  // namespace sable::cd
