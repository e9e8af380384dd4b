// Frictional-contact problems with an explicit Delassus matrix, 2D and 3D: U = W r + q, find
// r in the Coulomb cones with De Saxce's complementarity (nlgs.hpp). Read from Siconos' .dat
// files (dense, sparse-block and CSparse storage: fc_dat.cpp) and FCLIB HDF5 files (local W,
// q, mu, or the global M, H, f, w reduced to W = H^T M^-1 H: fc_fclib.cpp; formats in
// shared/data/fc3d/README.md), solved by the NLGS of nlgs.hpp. Used by `sable fc3d` and by
// the validation tests, which check the NLGS against Siconos' and FCLIB's problems.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "sable/cd/nlgs.hpp"

namespace sable::cd {

// A problem U = W r + q, W stored as a CSR matrix of d x d blocks (one block row and one
// block column per contact). Satisfies the NlgsProblem concept of nlgs.hpp: velocity(a) sums
// the blocks of row a on the fly; apply() only updates r_a. W need not be symmetric.
template <int d>
class MatrixProblem {
 public:
  using Vec = LVec<d>;
  using Mat = LMat<d>;
  static constexpr int kDim = d;

  MatrixProblem() = default;
  // row_ptr has size() + 1 entries; block k (row_ptr[a] <= k < row_ptr[a+1]) is W_{a, cols[k]}.
  // Every row must hold its diagonal block; throws std::invalid_argument on inconsistent
  // sizes. The reactions start at zero.
  MatrixProblem(std::vector<std::size_t> row_ptr, std::vector<std::size_t> cols,
                std::vector<Mat> blocks, std::vector<Vec> q, std::vector<double> mu);

  // --- NlgsProblem ---
  std::size_t size() const { return q_.size(); }
  const Mat& W(std::size_t a) const { return blocks_[diag_[a]]; }
  double mu(std::size_t a) const { return mu_[a]; }
  Vec& r(std::size_t a) { return r_[a]; }
  const Vec& r(std::size_t a) const { return r_[a]; }
  Vec velocity(std::size_t a) const {
    Vec U = q_[a];
    for (std::size_t k = row_ptr_[a]; k < row_ptr_[a + 1]; ++k)
      U.noalias() += blocks_[k] * r_[cols_[k]];
    return U;
  }
  void apply(std::size_t a, const Vec& dr) { r_[a] += dr; }
  double q_norm() const { return q_norm_; }

  // --- data ---
  std::span<const std::size_t> row_ptr() const { return row_ptr_; }
  std::span<const std::size_t> cols() const { return cols_; }
  std::span<const Mat> blocks() const { return blocks_; }
  std::span<const Vec> q() const { return q_; }
  std::span<const double> mus() const { return mu_; }
  std::span<const Vec> reactions() const { return r_; }
  std::size_t diagonal_block(std::size_t a) const { return diag_[a]; }
  void reset_reactions() { r_.assign(q_.size(), Vec::Zero()); }
  // The reactions set to `r` (one per contact): a kept iterate restored.
  void set_reactions(std::span<const Vec> r) { r_.assign(r.begin(), r.end()); }

 private:
  std::vector<std::size_t> row_ptr_{0};
  std::vector<std::size_t> cols_;
  std::vector<Mat> blocks_;
  std::vector<std::size_t> diag_;
  std::vector<Vec> q_;
  std::vector<double> mu_;
  std::vector<Vec> r_;
  double q_norm_ = 0.0;
};

// A problem read from a file, 2D or 3D as the file says.
using FcProblem = std::variant<MatrixProblem<2>, MatrixProblem<3>>;

// The symmetric part S = (B + B^T) / 2 of a diagonal block must be positive semi-definite: its
// smallest eigenvalue at least -kFcSemiDefiniteTolerance max|S|. The tolerance is round-off's,
// scaled: the shared problems' blocks are Gram-like products of a few terms, exact to about
// 1e-15 relative, and a block with a genuinely negative direction (data garbled, a sign lost)
// is off by O(1). Asymmetric blocks (gyroscopic terms: FCLIB's families have mean asymmetries
// of 3-7 %) are accepted.
inline constexpr double kFcSemiDefiniteTolerance = 1e-9;

// Reads a problem: an FCLIB HDF5 file (recognised by its signature, not its name) or a
// Siconos .dat file (d = 2 or 3). Throws sable::InputError naming the file and the place
// (item being read and line; dataset) on: missing file, truncated file, non-numeric or
// non-finite value, d other than 2 or 3, unknown storage, non-square or wrongly sized
// matrix, block structure errors (row pointers, block index or column out of range, a block
// twice), entries out of range, a contact whose diagonal block has W_NN <= 0 or a symmetric
// part that is not positive semi-definite, a negative friction coefficient, unexpected
// trailing data. Keeps only the non-zero d x d blocks (and every diagonal block).
FcProblem read_fc(const std::string& path);
// A .dat problem from text; `name` stands for the file in messages.
FcProblem parse_fc_dat(std::string_view text, const std::string& name);
// An FCLIB HDF5 file (fclib_local or fclib_global).
FcProblem read_fclib(const std::string& path);
// read_fc, for callers that need a 3D problem: a 2D file is refused (InputError).
MatrixProblem<3> read_fc3d(const std::string& path);

// Siconos' error of the current reactions, recomputed from scratch (a full block product
// U = W r + q over all blocks, not velocity()): ||r - P_K(r - (U + mu|U_T| e_N))|| /
// max(||q||, ||r||, ||U||).
template <int d>
double fc_residual(const MatrixProblem<d>& p);

struct FcReport {
  int dimension = 3;
  std::size_t contacts = 0;
  int iterations = 0;
  double error = 0.0;     // the NLGS criterion at the end
  double residual = 0.0;  // fc_residual() after the solve
  bool converged = false;
  int reordered_at = -1;          // NlgsResult::reordered_at
  bool stagnated = false;         // the NLGS stagnated (after its shuffle) and handed over
  int newton_iterations = 0;      // the semismooth Newton's (fc_newton.hpp), after the NLGS
  bool newton_restarted = false;  // Newton from r = 0 failed and ran from the NLGS's iterate
  bool enumerated = false;        // solved by fc_enumerate.hpp (tiny 2D problems), no sweep
  double seconds = 0.0;           // the first solve's wall time (reading the file excluded)
  int repeats = 1;                // solves run (FcRepeats)
  double warm_seconds = 0.0;      // median wall time of the solves after the first (0: none)
  std::vector<double> reactions;  // the solution, d values per contact ([N, T] or [N, T1, T2])
};

// How often solve_fc solves the problem: `count` solves at most, further ones only while the
// solves so far took less than `time_budget` seconds in all (so a benchmark repeats the small
// problems, where a first solve's start-up costs show, and not the long ones).
struct FcRepeats {
  int count = 1;
  double time_budget = 0.1;
};

// Reads `path`, solves it from r = 0 (a 2D problem of at most kEnumerateMaxContacts contacts
// first by enumeration, fc_enumerate.hpp) with the NLGS (`seed` for the shuffled order) and, if
// that stops short of the tolerance, with at most `newton_iterations` steps of the
// semismooth Newton of fc_newton.hpp (from r = 0, then, if that fails, from the NLGS's
// iterate); reports. With repeats, solves it again from r = 0 (the same bits, checked) and
// reports the first solve's time and the median of the others.
FcReport solve_fc(const std::string& path, const NlgsSettings& s, std::uint64_t seed = 1,
                  int newton_iterations = 100, const FcRepeats& repeats = {});

// --- for the readers: a matrix from its scalar entries, and the checks every problem passes

// A d x d block CSR matrix, one block row and column per contact.
template <int d>
struct BlockCsr {
  std::vector<std::size_t> row_ptr{0};
  std::vector<std::size_t> cols;
  std::vector<LMat<d>> blocks;
};

// One scalar entry W(row, col) = value.
struct MatrixEntry {
  std::size_t row, col;
  double value;
};

// The block matrix holding `entries` (rows and columns < d * nc; duplicates summed, as a
// triplet matrix's are), with only the blocks some entry falls in, and every diagonal block.
template <int d>
BlockCsr<d> blocks_from_entries(std::vector<MatrixEntry> entries, std::size_t nc);

// Every contact has a diagonal block with W_NN > 0 and a positive semi-definite symmetric part;
// no block column twice in a row; no non-finite value. `fail` throws with the message.
template <int d>
void check_blocks(const BlockCsr<d>& m, std::size_t nc,
                  const std::function<void(const std::string&)>& fail);

// The problem from checked blocks, q (d * nc values) and mu (nc, each >= 0, else `fail`).
template <int d>
MatrixProblem<d> make_problem(BlockCsr<d>&& m, const std::vector<double>& q, std::vector<double> mu,
                              const std::function<void(const std::string&)>& fail);

}  // namespace sable::cd
