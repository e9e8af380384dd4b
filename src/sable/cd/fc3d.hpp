// Frictional-contact problems with an explicit Delassus matrix, read from Siconos' .dat format
// (FrictionContactProblem files: dense column-major or sparse-block storage; see
// shared/data/fc3d/README.md), and solved by the NLGS of nlgs.hpp. Used by `sable fc3d` and by
// the validation tests, which check the NLGS against Siconos' reference problems.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sable/cd/nlgs.hpp"

namespace sable::cd {

// A 3D problem U = W r + q, W stored as a CSR matrix of 3x3 blocks (one block row and one block
// column per contact). Satisfies the NlgsProblem concept of nlgs.hpp: velocity(a) sums the
// blocks of row a on the fly; apply() only updates r_a.
class MatrixProblem {
 public:
  using Vec = LVec<3>;
  using Mat = LMat<3>;

  MatrixProblem() = default;
  // row_ptr has size() + 1 entries; block k (row_ptr[a] <= k < row_ptr[a+1]) is W_{a, cols[k]}.
  // Every row must hold its diagonal block; throws std::invalid_argument on inconsistent sizes.
  // The reactions start at zero.
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

// Largest relative asymmetry max|B - B^T| / max|B| accepted in a diagonal block B. Meant to
// catch garbled data (shifted or transposed values give O(1)), not round-off: the Siconos
// reference problems are not exactly symmetric (Rover4609: 1.2e-5, Capsules-i122-1617: 3.6e-3
// at contact 277), so the tolerance cannot be near machine precision.
inline constexpr double kFc3dSymmetryTolerance = 1e-2;

// Reads a Siconos .dat file (d must be 3). Throws sable::InputError naming the file and the
// place (item being read, line) on: missing file, truncated file, non-numeric or non-finite
// value, d != 3, unknown storage, non-square or wrongly sized matrix, block structure errors
// (block sizes other than 3, row pointers, block index or column out of range, a contact
// without diagonal block), a diagonal block that is not symmetric (kFc3dSymmetryTolerance)
// or has W_NN <= 0, a negative friction coefficient, unexpected trailing data. Dense matrices
// keep only their non-zero 3x3 blocks (and every diagonal block).
MatrixProblem read_fc3d(const std::string& path);
// The same from text; `name` stands for the file in messages.
MatrixProblem parse_fc3d(std::string_view text, const std::string& name);

// Siconos' error of the current reactions, recomputed from scratch (a full block product
// U = W r + q over all blocks, not velocity()): ||r - P_K(r - (U + mu|U_T| e_N))|| /
// max(||q||, ||r||, ||U||).
double fc3d_residual(const MatrixProblem& p);

struct Fc3dReport {
  std::size_t contacts = 0;
  int iterations = 0;
  double error = 0.0;     // the NLGS criterion at the end
  double residual = 0.0;  // fc3d_residual() after the solve
  bool converged = false;
  double seconds = 0.0;  // NLGS wall time (reading the file excluded)
};

// Reads `path`, solves it from r = 0 with the NLGS (`seed` for the shuffled order), reports.
Fc3dReport solve_fc3d(const std::string& path, const NlgsSettings& s, std::uint64_t seed = 1);

}  // namespace sable::cd
