// Siconos .dat frictional-contact problems: reader, block-sparse problem, solve driver.
#include "sable/cd/fc3d.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "sable/core/error.hpp"

namespace sable::cd {

MatrixProblem::MatrixProblem(std::vector<std::size_t> row_ptr, std::vector<std::size_t> cols,
                             std::vector<Mat> blocks, std::vector<Vec> q, std::vector<double> mu)
    : row_ptr_(std::move(row_ptr)),
      cols_(std::move(cols)),
      blocks_(std::move(blocks)),
      q_(std::move(q)),
      mu_(std::move(mu)) {
  const std::size_t n = q_.size();
  if (mu_.size() != n || row_ptr_.size() != n + 1 || row_ptr_.front() != 0 ||
      row_ptr_.back() != cols_.size() || blocks_.size() != cols_.size())
    throw std::invalid_argument("MatrixProblem: inconsistent sizes");
  diag_.assign(n, cols_.size());
  for (std::size_t a = 0; a < n; ++a) {
    if (row_ptr_[a] > row_ptr_[a + 1]) throw std::invalid_argument("MatrixProblem: row_ptr");
    for (std::size_t k = row_ptr_[a]; k < row_ptr_[a + 1]; ++k) {
      if (cols_[k] >= n) throw std::invalid_argument("MatrixProblem: column out of range");
      if (cols_[k] == a) diag_[a] = k;
    }
    if (diag_[a] == cols_.size()) throw std::invalid_argument("MatrixProblem: no diagonal block");
  }
  double q2 = 0.0;
  for (const Vec& v : q_) q2 += v.squaredNorm();
  q_norm_ = std::sqrt(q2);
  r_.assign(n, Vec::Zero());
}

namespace {

// The whitespace-separated tokens of a file, with their line numbers, read in order. They are
// found as they are read, not listed first (24 bytes a token: a dozen times the file); their
// count is taken once at the start. Every size the file claims is bounded by that count
// before anything that size is allocated: numbers() allocates at most what remains, and the
// other arrays grow a token at a time.
class Tokens {
 public:
  Tokens(std::string_view text, std::string name) : text_(text), name_(std::move(name)) {
    for (std::size_t at = 0; next_token(at).size() > 0;) ++total_;
  }
  const std::string& name() const { return name_; }
  std::size_t remaining() const { return total_ - read_; }

  [[noreturn]] void fail(const std::string& msg) const { throw InputError(name_ + ": " + msg); }
  [[noreturn]] void fail_here(const std::string& msg) const {
    throw InputError(fmt::format("{}, line {}: {}", name_, line_, msg));
  }

  long long integer(std::string_view what) {
    if (remaining() == 0) fail(fmt::format("expected {}, found the end of the file", what));
    const std::string_view t = take();
    long long v = 0;
    const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || p != t.data() + t.size())
      fail_here(fmt::format("expected {} (an integer), found '{}'", what, shown(t)));
    return v;
  }
  // `count` finite numbers of `what` into out[0..count).
  void numbers(std::size_t count, std::string_view what, double* out) {
    const std::size_t avail = std::min(count, remaining());
    for (std::size_t k = 0; k < avail; ++k) out[k] = number(k, what);
    if (avail < count)
      fail(fmt::format("expected {} values of {}, found {} (file ends)", count, what, avail));
  }
  std::vector<double> numbers(std::size_t count, std::string_view what) {
    if (count > remaining()) {  // report a malformed token before the truncation
      std::vector<double> tmp(remaining());
      numbers(count, what, tmp.data());
    }
    std::vector<double> v(count);
    numbers(count, what, v.data());
    return v;
  }
  // The tokens left once the problem is read: one integer (the 'isComplete' flag that old
  // Siconos versions append) is tolerated, anything else is an error.
  void expect_end() {
    if (remaining() == 0) return;
    const std::size_t left = remaining();
    const std::string_view t = take();
    if (left == 1) {
      long long v = 0;
      const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
      if (ec == std::errc() && p == t.data() + t.size()) return;
    }
    fail_here(fmt::format("unexpected data after the friction coefficients ('{}', {} token(s))",
                          shown(t), left));
  }

 private:
  static bool blank(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
  }
  // The token at or after `at` (empty at the end), `at` moved past it; counts the newlines
  // passed into `lines` when given.
  std::string_view next_token(std::size_t& at, std::size_t* lines = nullptr) const {
    while (at < text_.size() && blank(text_[at])) {
      if (lines != nullptr && text_[at] == '\n') ++*lines;
      ++at;
    }
    const std::size_t start = at;
    while (at < text_.size() && !blank(text_[at])) ++at;
    return text_.substr(start, at - start);
  }
  std::string_view take() {
    ++read_;
    return next_token(pos_, &line_);
  }
  // A token as quoted in messages: at most 40 characters, non-printable bytes as '?'.
  static std::string shown(std::string_view t) {
    std::string s(t.substr(0, 40));
    for (char& c : s)
      if (c < 0x20 || c > 0x7e) c = '?';
    return t.size() <= 40 ? s : s + "...";
  }
  double number(std::size_t k, std::string_view what) {
    const std::string_view token = take();
    std::string_view t = token;
    if (t.size() > 1 && t[0] == '+') t.remove_prefix(1);
    double v = 0.0;
    const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || p != t.data() + t.size() || !std::isfinite(v))
      fail_here(
          fmt::format("value {} of {} is not a finite number: '{}'", k + 1, what, shown(token)));
    return v;
  }

  std::string_view text_;
  std::string name_;
  std::size_t total_ = 0, read_ = 0, pos_ = 0;
  std::size_t line_ = 1;  // the line of the last token read
};

using Mat3 = MatrixProblem::Mat;
using Vec3 = MatrixProblem::Vec;

struct BlockCsr {
  std::vector<std::size_t> row_ptr{0};
  std::vector<std::size_t> cols;
  std::vector<Mat3> blocks;
};

// Dense storage: "size0 size1" again, then size0*size1 values in column-major order. Keeps the
// non-zero 3x3 blocks and every diagonal block.
BlockCsr read_dense(Tokens& t, std::size_t nc) {
  const std::size_t n = 3 * nc;
  const long long s0 = t.integer("the number of rows of the dense matrix");
  const long long s1 = t.integer("the number of columns of the dense matrix");
  if (s0 != static_cast<long long>(n) || s1 != static_cast<long long>(n))
    t.fail_here(fmt::format("dense matrix declared {} x {}, expected {} x {}", s0, s1, n, n));
  const std::vector<double> v = t.numbers(n * n, "the dense matrix W");
  BlockCsr m;
  for (std::size_t I = 0; I < nc; ++I) {
    for (std::size_t J = 0; J < nc; ++J) {
      Mat3 B;
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) B(r, c) = v[(3 * J + c) * n + 3 * I + r];
      if (I != J && B.isZero(0.0)) continue;
      m.cols.push_back(J);
      m.blocks.push_back(B);
    }
    m.row_ptr.push_back(m.cols.size());
  }
  return m;
}

// Sparse-block storage, part 1: block counts, block sizes, row pointers, column indices.
BlockCsr read_sparse_structure(Tokens& t, std::size_t nc) {
  const long long nb = t.integer("the number of blocks");
  const long long nbr = t.integer("the number of block rows");
  const long long nbc = t.integer("the number of block columns");
  if (nb < 0) t.fail_here(fmt::format("negative number of blocks {}", nb));
  if (nbr != static_cast<long long>(nc) || nbc != static_cast<long long>(nc))
    t.fail_here(
        fmt::format("{} x {} blocks, expected {} x {} (one per contact)", nbr, nbc, nc, nc));
  for (const char* what : {"row", "column"}) {
    for (std::size_t i = 0; i < nc; ++i) {
      const long long end = t.integer(fmt::format("the end of block {} {}", what, i));
      if (end != 3 * static_cast<long long>(i + 1))
        t.fail_here(fmt::format("block {} {} ends at {}, expected {} (3x3 blocks)", what, i, end,
                                3 * (i + 1)));
    }
  }
  const long long filled1 = t.integer("the number of row pointers (filled1)");
  const long long filled2 = t.integer("the number of column indices (filled2)");
  if (filled1 != nbr + 1 || filled2 != nb)
    t.fail_here(fmt::format("filled1 = {}, filled2 = {}; expected {} and {}", filled1, filled2,
                            nbr + 1, nb));
  BlockCsr m;
  m.row_ptr.clear();
  for (std::size_t i = 0; i <= nc; ++i) {
    const long long p = t.integer(fmt::format("row pointer {}", i));
    const long long prev = i == 0 ? 0 : static_cast<long long>(m.row_ptr.back());
    if (p < prev || p > nb || (i == 0 && p != 0) || (i == nc && p != nb))
      t.fail_here(fmt::format("row pointer {} = {} is out of order or range (0..{})", i, p, nb));
    m.row_ptr.push_back(static_cast<std::size_t>(p));
  }
  for (long long k = 0; k < nb; ++k) {
    const long long c = t.integer(fmt::format("the column index of block {}", k));
    if (c < 0 || c >= nbc)
      t.fail_here(fmt::format("block {} has column index {}, out of range [0, {})", k, c, nbc));
    m.cols.push_back(static_cast<std::size_t>(c));
  }
  return m;
}

// Sparse-block storage, part 2: each block as its index then 9 values (column-major 3x3).
void read_sparse_blocks(Tokens& t, BlockCsr& m) {
  const std::size_t nb = m.cols.size();
  m.blocks.assign(nb, Mat3::Zero());
  std::vector<bool> seen(nb, false);
  for (std::size_t k = 0; k < nb; ++k) {
    const long long idx = t.integer(fmt::format("the index of block {} of {}", k + 1, nb));
    if (idx < 0 || idx >= static_cast<long long>(nb))
      t.fail_here(fmt::format("block index {} out of range [0, {})", idx, nb));
    const auto i = static_cast<std::size_t>(idx);
    if (seen[i]) t.fail_here(fmt::format("block index {} appears twice", idx));
    seen[i] = true;
    t.numbers(9, fmt::format("block {}", idx), m.blocks[i].data());
  }
}

// Every contact has a symmetric diagonal block with W_NN > 0; no block column twice in a row.
void check_blocks(const Tokens& t, const BlockCsr& m, std::size_t nc) {
  std::vector<std::size_t> last_row(nc, nc);  // the last block row that held each column
  for (std::size_t a = 0; a < nc; ++a) {
    const Mat3* diag = nullptr;
    for (std::size_t k = m.row_ptr[a]; k < m.row_ptr[a + 1]; ++k) {
      if (last_row[m.cols[k]] == a)
        t.fail(fmt::format("block row {} holds block column {} twice", a, m.cols[k]));
      last_row[m.cols[k]] = a;
      if (m.cols[k] == a) diag = &m.blocks[k];
    }
    if (diag == nullptr) t.fail(fmt::format("contact {} has no diagonal block W_{}{}", a, a, a));
    const double scale = diag->cwiseAbs().maxCoeff();
    const double asym = (*diag - diag->transpose()).cwiseAbs().maxCoeff();
    if (asym > kFc3dSymmetryTolerance * scale)
      t.fail(
          fmt::format("the diagonal block of contact {} is not symmetric (relative asymmetry "
                      "{:.3g} > {:g})",
                      a, asym / scale, kFc3dSymmetryTolerance));
    if (!((*diag)(0, 0) > 0.0))
      t.fail(fmt::format("contact {}: W_NN = {} in its diagonal block, expected > 0", a,
                         (*diag)(0, 0)));
  }
}

}  // namespace

MatrixProblem parse_fc3d(std::string_view text, const std::string& name) {
  Tokens t(text, name);
  const long long d = t.integer("the dimension d");
  if (d != 3) t.fail_here(fmt::format("dimension d = {}: only 3D problems (d = 3) are read", d));
  const long long nc_in = t.integer("the number of contacts");
  if (nc_in < 0 || nc_in > 100'000'000)
    t.fail_here(fmt::format("number of contacts {} out of range", nc_in));
  const auto nc = static_cast<std::size_t>(nc_in);
  const long long storage = t.integer("the storage type");
  if (storage != 0 && storage != 1)
    t.fail_here(fmt::format("storage type {} not supported (0 dense, 1 sparse-block)", storage));
  const long long s0 = t.integer("the number of rows (size0)");
  const long long s1 = t.integer("the number of columns (size1)");
  if (s0 != s1) t.fail_here(fmt::format("non-square matrix {} x {}", s0, s1));
  if (s0 != 3 * nc_in)
    t.fail_here(fmt::format("matrix size {} does not match d * nc = 3 * {} = {}", s0, nc, 3 * nc));
  BlockCsr m;
  if (storage == 0) {
    m = read_dense(t, nc);
  } else {
    m = read_sparse_structure(t, nc);
    read_sparse_blocks(t, m);
  }
  check_blocks(t, m, nc);
  const std::vector<double> qv = t.numbers(3 * nc, "q");
  std::vector<double> mu = t.numbers(nc, "the friction coefficients mu");
  std::vector<Vec3> q(nc);
  for (std::size_t a = 0; a < nc; ++a) q[a] = Vec3(qv[3 * a], qv[3 * a + 1], qv[3 * a + 2]);
  for (std::size_t a = 0; a < nc; ++a)
    if (mu[a] < 0.0)
      t.fail(fmt::format("negative friction coefficient mu = {} at contact {}", mu[a], a));
  t.expect_end();
  return MatrixProblem(std::move(m.row_ptr), std::move(m.cols), std::move(m.blocks), std::move(q),
                       std::move(mu));
}

MatrixProblem read_fc3d(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(clip(path) + ": cannot open the file");  // any command-line text
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path + ": read error");
  return parse_fc3d(ss.str(), path);
}

double fc3d_residual(const MatrixProblem& p) {
  const std::size_t n = p.size();
  std::vector<Vec3> U(p.q().begin(), p.q().end());
  const auto rp = p.row_ptr();
  const auto cols = p.cols();
  const auto blocks = p.blocks();
  const auto r = p.reactions();
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t k = rp[a]; k < rp[a + 1]; ++k) U[a] += blocks[k] * r[cols[k]];
  double f2 = 0.0, r2 = 0.0, u2 = 0.0, q2 = 0.0;
  for (std::size_t a = 0; a < n; ++a) {
    f2 += natural_map<3>(r[a], U[a], p.mu(a)).squaredNorm();
    r2 += r[a].squaredNorm();
    u2 += U[a].squaredNorm();
    q2 += p.q()[a].squaredNorm();
  }
  const double den = std::sqrt(std::max({q2, r2, u2}));
  if (f2 == 0.0) return 0.0;
  return den > 0.0 ? std::sqrt(f2) / den : std::numeric_limits<double>::infinity();
}

Fc3dReport solve_fc3d(const std::string& path, const NlgsSettings& s, std::uint64_t seed) {
  MatrixProblem p = read_fc3d(path);
  Rng rng(seed);
  const auto t0 = std::chrono::steady_clock::now();
  const NlgsResult res = solve_nlgs<3>(p, s, rng);
  const auto t1 = std::chrono::steady_clock::now();
  Fc3dReport rep;
  rep.contacts = p.size();
  rep.iterations = res.iterations;
  rep.error = res.error;
  rep.converged = res.converged;
  rep.seconds = std::chrono::duration<double>(t1 - t0).count();
  rep.residual = fc3d_residual(p);
  return rep;
}

}  // namespace sable::cd
