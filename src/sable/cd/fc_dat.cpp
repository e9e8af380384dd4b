// Siconos .dat frictional-contact problems (shared/data/fc3d/README.md), 2D and 3D: dense,
// sparse-block and CSparse (cs_print of a compressed-column matrix) storage.
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <utility>

#include "sable/cd/fc_problem.hpp"
#include "sable/core/error.hpp"

namespace sable::cd {

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
  // The next token as it is (the words of CSparse's printout).
  std::string_view word(std::string_view what) {
    if (remaining() == 0) fail(fmt::format("expected {}, found the end of the file", what));
    return take();
  }
  void expect(std::string_view w, std::string_view what) {
    const std::string_view t = word(what);
    if (t != w) fail_here(fmt::format("expected '{}' ({}), found '{}'", w, what, shown(t)));
  }
  // An integer in [0, hi), as integer() reads it.
  std::size_t index(std::string_view what, std::size_t hi) {
    const long long v = integer(what);
    if (v < 0 || static_cast<unsigned long long>(v) >= hi)
      fail_here(fmt::format("{} = {} out of range [0, {})", what, v, hi));
    return static_cast<std::size_t>(v);
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

 public:
  // A token as quoted in messages: at most 40 characters, non-printable bytes as '?'.
  static std::string shown(std::string_view t) {
    std::string s(t.substr(0, 40));
    for (char& c : s)
      if (c < 0x20 || c > 0x7e) c = '?';
    return t.size() <= 40 ? s : s + "...";
  }

 private:
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

// Dense storage: "size0 size1" again, then size0*size1 values in column-major order. Keeps
// the non-zero d x d blocks and every diagonal block.
template <int d>
BlockCsr<d> read_dense(Tokens& t, std::size_t nc) {
  const std::size_t n = d * nc;
  const long long s0 = t.integer("the number of rows of the dense matrix");
  const long long s1 = t.integer("the number of columns of the dense matrix");
  if (s0 != static_cast<long long>(n) || s1 != static_cast<long long>(n))
    t.fail_here(fmt::format("dense matrix declared {} x {}, expected {} x {}", s0, s1, n, n));
  const std::vector<double> v = t.numbers(n * n, "the dense matrix W");
  BlockCsr<d> m;
  for (std::size_t I = 0; I < nc; ++I) {
    for (std::size_t J = 0; J < nc; ++J) {
      LMat<d> B;
      for (int c = 0; c < d; ++c)
        for (int r = 0; r < d; ++r) B(r, c) = v[(d * J + c) * n + d * I + r];
      if (I != J && B.isZero(0.0)) continue;
      m.cols.push_back(J);
      m.blocks.push_back(B);
    }
    m.row_ptr.push_back(m.cols.size());
  }
  return m;
}

// Sparse-block storage, part 1: block counts, block sizes, row pointers, column indices.
template <int d>
BlockCsr<d> read_sparse_structure(Tokens& t, std::size_t nc) {
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
      if (end != d * static_cast<long long>(i + 1))
        t.fail_here(fmt::format("block {} {} ends at {}, expected {} ({}x{} blocks)", what, i, end,
                                d * (i + 1), d, d));
    }
  }
  const long long filled1 = t.integer("the number of row pointers (filled1)");
  const long long filled2 = t.integer("the number of column indices (filled2)");
  if (filled1 != nbr + 1 || filled2 != nb)
    t.fail_here(fmt::format("filled1 = {}, filled2 = {}; expected {} and {}", filled1, filled2,
                            nbr + 1, nb));
  BlockCsr<d> m;
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

// Sparse-block storage, part 2: each block as its index then d*d values (column-major).
template <int d>
void read_sparse_blocks(Tokens& t, BlockCsr<d>& m) {
  const std::size_t nb = m.cols.size();
  m.blocks.assign(nb, LMat<d>::Zero());
  std::vector<bool> seen(nb, false);
  for (std::size_t k = 0; k < nb; ++k) {
    const long long idx = t.integer(fmt::format("the index of block {} of {}", k + 1, nb));
    if (idx < 0 || idx >= static_cast<long long>(nb))
      t.fail_here(fmt::format("block index {} out of range [0, {})", idx, nb));
    const auto i = static_cast<std::size_t>(idx);
    if (seen[i]) t.fail_here(fmt::format("block index {} appears twice", idx));
    seen[i] = true;
    t.numbers(d * d, fmt::format("block {}", idx), m.blocks[i].data());
  }
}

// "M-by-N," as CSparse prints a matrix's size: M and N.
std::pair<long long, long long> read_size(Tokens& t, std::string_view token) {
  const std::size_t at = token.find("-by-");
  std::string_view rows = token.substr(0, at), cols = token.substr(at + 4);
  if (!cols.empty() && cols.back() == ',') cols.remove_suffix(1);
  long long m = -1, n = -1;
  const auto [pr, er] = std::from_chars(rows.data(), rows.data() + rows.size(), m);
  const auto [pc, ec] = std::from_chars(cols.data(), cols.data() + cols.size(), n);
  if (er != std::errc() || ec != std::errc() || pr != rows.data() + rows.size() ||
      pc != cols.data() + cols.size())
    t.fail_here(
        fmt::format("expected the matrix size 'M-by-N,', found '{}'", Tokens::shown(token)));
  return {m, n};
}

// CSparse storage (storage 2): Siconos writes its sparse matrix's own storage (2, compressed
// columns, the only one read), then CSparse's cs_print: a banner, "M-by-N, nzmax: Z nnz: Z,
// 1-norm: X", and for each column j "col j : locations a to b" followed by its b - a + 1
// entries "row : value". cs_print writes "%g": values to 6 digits (the problem is the file's),
// indices exactly below 10^6 (larger ones would not read as integers: refused).
template <int d>
BlockCsr<d> read_csparse(Tokens& t, std::size_t nc) {
  const std::size_t n = d * nc;
  const long long kind = t.integer("the sparse storage (2: compressed columns)");
  if (kind != 2)
    t.fail_here(fmt::format("sparse storage {} not supported (2: compressed columns)", kind));
  std::string_view size_token;
  for (int k = 0; k < 64 && size_token.empty(); ++k) {
    const std::string_view w = t.word("CSparse's banner and the matrix size 'M-by-N,'");
    if (w.find("-by-") != std::string_view::npos) size_token = w;
  }
  if (size_token.empty()) t.fail_here("expected the matrix size 'M-by-N,' after CSparse's banner");
  const auto [m_rows, m_cols] = read_size(t, size_token);
  if (m_rows != static_cast<long long>(n) || m_cols != static_cast<long long>(n))
    t.fail_here(fmt::format("matrix {} x {}, expected {} x {}", m_rows, m_cols, n, n));
  t.expect("nzmax:", "CSparse's 'nzmax: Z'");
  t.integer("nzmax");
  t.expect("nnz:", "CSparse's 'nnz: Z,'");
  const std::string_view nnz_token = t.word("the number of entries");
  t.expect("1-norm:", "CSparse's '1-norm: X'");
  t.word("the 1-norm");
  std::vector<MatrixEntry> entries;
  for (std::size_t j = 0; j < n; ++j) {
    t.expect("col", fmt::format("column {}", j));
    if (t.index(fmt::format("the number of column {}", j), n + 1) != j)
      t.fail_here(fmt::format("expected column {} here (columns in order)", j));
    t.expect(":", "':' after the column number");
    t.expect("locations", "'locations a to b'");
    const long long a = t.integer("the column's first location");
    t.expect("to", "'locations a to b'");
    const long long b = t.integer("the column's last location");
    if (a != static_cast<long long>(entries.size()) || b < a - 1 ||
        static_cast<unsigned long long>(b - a + 1) > t.remaining() / 3)
      t.fail_here(
          fmt::format("column {}: locations {} to {} (expected to start at {}, and no more "
                      "entries than the file holds)",
                      j, a, b, entries.size()));
    for (long long k = a; k <= b; ++k) {
      const std::size_t row = t.index(fmt::format("the row of entry {}", k), n);
      t.expect(":", "':' between an entry's row and value");
      double v = 0.0;
      t.numbers(1, fmt::format("entry {}", k), &v);
      entries.push_back({row, j, v});
    }
  }
  std::string_view nnz = nnz_token;
  if (!nnz.empty() && nnz.back() == ',') nnz.remove_suffix(1);
  if (nnz != std::to_string(entries.size()))
    t.fail(fmt::format("CSparse's header says nnz {}, the columns hold {} entries",
                       Tokens::shown(nnz), entries.size()));
  return blocks_from_entries<d>(std::move(entries), nc);
}

template <int d>
MatrixProblem<d> parse_dimension(Tokens& t) {
  const long long nc_in = t.integer("the number of contacts");
  if (nc_in < 0 || nc_in > 100'000'000)
    t.fail_here(fmt::format("number of contacts {} out of range", nc_in));
  const auto nc = static_cast<std::size_t>(nc_in);
  const long long storage = t.integer("the storage type");
  if (storage < 0 || storage > 2)
    t.fail_here(
        fmt::format("storage type {} not supported (0 dense, 1 sparse-block, 2 sparse)", storage));
  const long long s0 = t.integer("the number of rows (size0)");
  const long long s1 = t.integer("the number of columns (size1)");
  if (s0 != s1) t.fail_here(fmt::format("non-square matrix {} x {}", s0, s1));
  if (s0 != d * nc_in)
    t.fail_here(
        fmt::format("matrix size {} does not match d * nc = {} * {} = {}", s0, d, nc, d * nc));
  BlockCsr<d> m;
  if (storage == 0) {
    m = read_dense<d>(t, nc);
  } else if (storage == 1) {
    m = read_sparse_structure<d>(t, nc);
    read_sparse_blocks<d>(t, m);
  } else {
    m = read_csparse<d>(t, nc);
  }
  const auto fail = [&t](const std::string& msg) { t.fail(msg); };
  check_blocks<d>(m, nc, fail);
  const std::vector<double> q = t.numbers(d * nc, "q");
  std::vector<double> mu = t.numbers(nc, "the friction coefficients mu");
  for (std::size_t a = 0; a < nc; ++a)
    if (mu[a] < 0.0)
      t.fail(fmt::format("negative friction coefficient mu = {} at contact {}", mu[a], a));
  t.expect_end();
  return make_problem<d>(std::move(m), q, std::move(mu), fail);
}

}  // namespace

FcProblem parse_fc_dat(std::string_view text, const std::string& name) {
  Tokens t(text, name);
  const long long d = t.integer("the dimension d");
  if (d == 2) return parse_dimension<2>(t);
  if (d != 3) t.fail_here(fmt::format("dimension d = {}: expected 2 or 3", d));
  return parse_dimension<3>(t);
}

}  // namespace sable::cd
