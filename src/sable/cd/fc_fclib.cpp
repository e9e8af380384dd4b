// FCLIB HDF5 frictional-contact problems (fclib.h of the FCLIB project, Acary et al.).
//
// A file holds a local problem, /fclib_local: W (sparse), vectors q and mu, spacedim; or a
// global one, /fclib_global: M (n x n) and H (n x d nc) sparse, vectors f (n), w (d nc), mu
// (nc), spacedim, with M v = H r + f and u = H^T v + w, so that in local form
//   W = H^T M^-1 H,   q = H^T M^-1 f + w.
// (The files' own solutions, /solution/{r,u}, satisfy u = W r + q with this W and q: the
// validation test checks it.) A sparse matrix is a group with m, n, nz, nzmax, p, i, x as in
// CSparse: nz = -1 compressed columns (p: n + 1 column pointers, i: row indices), nz = -2
// compressed rows (p: m + 1 row pointers, i: column indices), nz >= 0 a triplet matrix of nz
// entries (i: rows, p: columns; duplicates summed).
#include <fmt/format.h>

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "sable/cd/fc_problem.hpp"
#include "sable/io/hdf5_file.hpp"

namespace sable::cd {

namespace {

using Index = std::size_t;

// One integer stored as a dataset of one value (FCLIB's m, n, nz, nzmax, spacedim).
long long read_scalar(const h5::File& f, const std::string& dset) {
  const std::vector<std::int32_t> v = f.read<std::int32_t>(dset, 0, 1, "a single value");
  return v[0];
}

// A sparse matrix group, as its m, n and entries; every index checked against m and n.
struct Sparse {
  long long m = 0, n = 0;
  std::vector<MatrixEntry> entries;
};

// The entries of a compressed matrix: `outer` pointers over `count` outer indices into
// `inner` (the other index) and `x`. `outer_is_col` for compressed columns.
void read_compressed(const h5::File& f, const std::string& g, Sparse& s, bool outer_is_col) {
  const long long count = outer_is_col ? s.n : s.m, inner_max = outer_is_col ? s.m : s.n;
  const auto p =
      f.read<std::int32_t>(g + "/p", 0, static_cast<hsize_t>(count + 1),
                           outer_is_col ? "n + 1 column pointers" : "m + 1 row pointers");
  const auto i = f.read<std::int32_t>(g + "/i", 0);
  const auto x = f.read<double>(g + "/x", 0);
  if (p[0] != 0) f.fail(fmt::format("'{}/p' starts at {}, expected 0", g, p[0]));
  for (long long k = 0; k < count; ++k)
    if (p[k + 1] < p[k] || static_cast<std::size_t>(p[k + 1]) > std::min(i.size(), x.size()))
      f.fail(
          fmt::format("'{}/p' value {} = {} is out of order, or beyond the {} entries that "
                      "'{}/i' and '{}/x' hold",
                      g, k + 1, p[k + 1], std::min(i.size(), x.size()), g, g));
  s.entries.reserve(static_cast<std::size_t>(p[count]));
  for (long long k = 0; k < count; ++k)
    for (auto e = static_cast<std::size_t>(p[k]); e < static_cast<std::size_t>(p[k + 1]); ++e) {
      if (i[e] < 0 || i[e] >= inner_max)
        f.fail(fmt::format("'{}/i' value {} = {} is out of range [0, {})", g, e, i[e], inner_max));
      const auto outer = static_cast<Index>(k), inner = static_cast<Index>(i[e]);
      s.entries.push_back({outer_is_col ? inner : outer, outer_is_col ? outer : inner, x[e]});
    }
}

Sparse read_sparse(const h5::File& f, const std::string& g) {
  Sparse s;
  s.m = read_scalar(f, g + "/m");
  s.n = read_scalar(f, g + "/n");
  if (s.m < 0 || s.n < 0) f.fail(fmt::format("'{}' is {} x {}, expected sizes >= 0", g, s.m, s.n));
  const long long nz = read_scalar(f, g + "/nz");
  if (nz == -1 || nz == -2) {
    read_compressed(f, g, s, nz == -1);
  } else if (nz >= 0) {
    const auto n = static_cast<hsize_t>(nz);
    const std::string why = "nz entries, as '" + g + "/nz'";
    const auto rows = f.read<std::int32_t>(g + "/i", 0), cols = f.read<std::int32_t>(g + "/p", 0);
    const auto x = f.read<double>(g + "/x", 0);
    if (rows.size() < n || cols.size() < n || x.size() < n)
      f.fail(fmt::format("'{}' claims {} entries; '{}/i', '/p', '/x' hold {}, {}, {}", g, nz, g,
                         rows.size(), cols.size(), x.size()));
    for (std::size_t e = 0; e < n; ++e) {
      if (rows[e] < 0 || rows[e] >= s.m || cols[e] < 0 || cols[e] >= s.n)
        f.fail(fmt::format("'{}' entry {} at ({}, {}) is outside the {} x {} matrix", g, e, rows[e],
                           cols[e], s.m, s.n));
      s.entries.push_back({static_cast<Index>(rows[e]), static_cast<Index>(cols[e]), x[e]});
    }
  } else {
    f.fail(
        fmt::format("'{}/nz' is {}: expected -1 (compressed columns), -2 (compressed rows) "
                    "or a triplet count >= 0",
                    g, nz));
  }
  for (std::size_t e = 0; e < s.entries.size(); ++e)
    if (!std::isfinite(s.entries[e].value))
      f.fail(fmt::format("'{}/x' value {} is not finite", g, e));
  return s;
}

Eigen::SparseMatrix<double> to_eigen(const Sparse& s) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(s.entries.size());
  for (const MatrixEntry& e : s.entries)
    t.emplace_back(static_cast<int>(e.row), static_cast<int>(e.col), e.value);
  Eigen::SparseMatrix<double> m(static_cast<Eigen::Index>(s.m), static_cast<Eigen::Index>(s.n));
  m.setFromTriplets(t.begin(), t.end());  // duplicates summed
  return m;
}

std::vector<double> read_vector(const h5::File& f, const std::string& dset, std::size_t n,
                                const std::string& why) {
  return f.read<double>(dset, 0, static_cast<hsize_t>(n), why);
}

template <int d>
MatrixProblem<d> read_local(const h5::File& f) {
  const std::string g = "/fclib_local";
  std::vector<double> mu = f.read<double>(g + "/vectors/mu", 0);
  const std::size_t nc = mu.size(), n = d * nc;
  const Sparse W = read_sparse(f, g + "/W");
  if (W.m != static_cast<long long>(n) || W.n != static_cast<long long>(n))
    f.fail(
        fmt::format("'{}/W' is {} x {}, expected d * nc = {} square ({} contacts, as "
                    "'{}/vectors/mu')",
                    g, W.m, W.n, n, nc, g));
  const std::vector<double> q = read_vector(f, g + "/vectors/q", n, "d values per contact");
  const auto fail = [&f](const std::string& msg) { f.fail(msg); };
  BlockCsr<d> m = blocks_from_entries<d>(W.entries, nc);
  check_blocks<d>(m, nc, fail);
  return make_problem<d>(std::move(m), q, std::move(mu), fail);
}

template <int d>
MatrixProblem<d> read_global(const h5::File& f) {
  const std::string g = "/fclib_global";
  std::vector<double> mu = f.read<double>(g + "/vectors/mu", 0);
  const std::size_t nc = mu.size(), mc = d * nc;
  const Sparse M = read_sparse(f, g + "/M"), H = read_sparse(f, g + "/H");
  if (M.m != M.n) f.fail(fmt::format("'{}/M' is {} x {}, expected square", g, M.m, M.n));
  if (H.m != M.m || H.n != static_cast<long long>(mc))
    f.fail(fmt::format("'{}/H' is {} x {}, expected {} x {} (M's size x d * nc)", g, H.m, H.n, M.m,
                       mc));
  const auto n = static_cast<std::size_t>(M.m);
  const std::vector<double> fv = read_vector(f, g + "/vectors/f", n, "one per row of M");
  const std::vector<double> w = read_vector(f, g + "/vectors/w", mc, "d values per contact");
  const Eigen::SparseMatrix<double> Me = to_eigen(M), He = to_eigen(H);
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  lu.compute(Me);
  if (lu.info() != Eigen::Success)
    f.fail(fmt::format("'{}/M' cannot be factorised (singular?): {}", g, lu.lastErrorMessage()));
  const Eigen::SparseMatrix<double> X = lu.solve(He);  // M^-1 H
  const Eigen::SparseMatrix<double> We = He.transpose() * X;
  const Eigen::VectorXd fe = Eigen::Map<const Eigen::VectorXd>(fv.data(), M.m);
  const Eigen::VectorXd qe =
      He.transpose() * lu.solve(fe) + Eigen::Map<const Eigen::VectorXd>(w.data(), H.n);
  std::vector<MatrixEntry> entries;
  for (Eigen::Index k = 0; k < We.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(We, k); it; ++it)
      if (it.value() != 0.0)
        entries.push_back({static_cast<Index>(it.row()), static_cast<Index>(it.col()), it.value()});
  const auto fail = [&f](const std::string& msg) { f.fail(msg); };
  BlockCsr<d> m = blocks_from_entries<d>(std::move(entries), nc);
  check_blocks<d>(m, nc, fail);
  return make_problem<d>(std::move(m), std::vector<double>(qe.begin(), qe.end()), std::move(mu),
                         fail);
}

template <int d>
MatrixProblem<d> read_kind(const h5::File& f) {
  if (f.exists("/fclib_local")) return read_local<d>(f);
  return read_global<d>(f);
}

}  // namespace

FcProblem read_fclib(const std::string& path) {
  h5::File f = h5::File::open(path, fmt::format("FCLIB file '{}'", path));
  const bool local = f.exists("/fclib_local");
  if (!local && !f.exists("/fclib_global"))
    f.fail("holds neither '/fclib_local' nor '/fclib_global': not an FCLIB problem");
  const long long d = read_scalar(f, local ? "/fclib_local/spacedim" : "/fclib_global/spacedim");
  if (d == 2) return read_kind<2>(f);
  if (d != 3) f.fail(fmt::format("spacedim = {}: expected 2 or 3", d));
  return read_kind<3>(f);
}

}  // namespace sable::cd
