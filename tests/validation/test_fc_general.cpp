// General frictional-contact problems (cd/fc_problem.hpp): 2D problems (Siconos' fc2d set,
// with its CSparse storage), FCLIB HDF5 files in local and global form, and diagonal blocks
// that are not symmetric. Each reader is checked against what the file itself says (values
// printed in it; the matrices rebuilt densely from the HDF5 datasets), and each problem
// against the solver's answer, with the residual recomputed by fc_residual (a full block
// product, not the NLGS's incremental velocities).
#include <gtest/gtest.h>

#include <unistd.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "../unit/test_data.hpp"
#include "sable/cd/fc_enumerate.hpp"
#include "sable/cd/fc_newton.hpp"
#include "sable/cd/fc_problem.hpp"
#include "sable/core/error.hpp"
#include "sable/io/hdf5_file.hpp"

namespace {

namespace fs = std::filesystem;
using namespace sable::cd;

const fs::path kShared = fs::path(SABLE_SOURCE_DIR) / ".." / "shared" / "data";

// The 2D set: each problem reads as 2D with the contact count of shared/data/fc2d/README.md,
// and the default NLGS (bi-potential, forward, 1,000 sweeps) brings it to Siconos' error
// 1e-4, the error recomputed from scratch agreeing with the solver's to 1e-12.
TEST(Fc2d, EveryProblemReadsAndIsSolved) {
  SABLE_NEEDS(fs::is_directory(kShared / "fc2d"), kShared / "fc2d"
                                                      << " does not exist");
  const std::vector<std::pair<std::string, std::size_t>> files = {
      {"FC2D_SliderCrankLagrangian00000.dat", 2},
      {"FrictionContactProblem00031.dat", 11},
      {"FrictionContactProblem00071.dat", 89},
      {"FrictionContactProblem00237.dat", 376},
      {"FrictionContactProblem00374.dat", 28},
      {"FrictionContactProblem00394.dat", 6},
      {"FrictionContactProblem00727.dat", 367},
      {"fc2d_granularflowonwall_00667_00000.dat", 667},
      {"fc2d_granularflowonwall_02020_00213.dat", 2020}};
  for (const auto& [name, contacts] : files) {
    SCOPED_TRACE(name);
    FcProblem problem = read_fc((kShared / "fc2d" / name).string());
    ASSERT_TRUE(std::holds_alternative<MatrixProblem<2>>(problem));
    auto& p = std::get<MatrixProblem<2>>(problem);
    EXPECT_EQ(p.size(), contacts);
    sable::Rng rng(1);
    const NlgsResult res = solve_nlgs<2>(p, NlgsSettings{}, rng);
    EXPECT_TRUE(res.converged) << res.residual;
    EXPECT_LE(fc_residual<2>(p), 1e-4);
    EXPECT_NEAR(fc_residual<2>(p), res.residual, 1e-12);
  }
}

// The CSparse storage read entry for entry: values as the file prints them (its first and
// last columns: W(0,0) = 856.713, W(649,0) = -454.43, W(648,1) = 454.43, W(1333,1333) =
// 2521.06), the blocks they fall in, and nothing where the file has no entry (W(1,0)).
TEST(Fc2d, CSparseStorageReadEntryForEntry) {
  const fs::path f = kShared / "fc2d" / "fc2d_granularflowonwall_00667_00000.dat";
  SABLE_NEEDS(fs::exists(f), f << " does not exist");
  const auto p = std::get<MatrixProblem<2>>(read_fc(f.string()));
  const auto entry = [&](std::size_t row, std::size_t col) {
    for (std::size_t k = p.row_ptr()[row / 2]; k < p.row_ptr()[row / 2 + 1]; ++k)
      if (p.cols()[k] == col / 2)
        return p.blocks()[k](static_cast<int>(row % 2), static_cast<int>(col % 2));
    return 0.0;
  };
  EXPECT_EQ(entry(0, 0), 856.713);
  EXPECT_EQ(entry(649, 0), -454.43);
  EXPECT_EQ(entry(648, 1), 454.43);
  EXPECT_EQ(entry(1333, 1333), 2521.06);
  EXPECT_EQ(entry(1, 0), 0.0);
  EXPECT_EQ(p.mus()[0], 0.5);
}

// An FCLIB sparse matrix group as a dense matrix, read here with no code shared with the
// reader: triplet (nz >= 0: i rows, p columns), compressed columns (nz = -1) or rows (-2).
Eigen::MatrixXd dense_matrix(const sable::h5::File& h, const std::string& g) {
  const auto scalar = [&](const char* name) { return h.read<std::int32_t>(g + "/" + name, 0)[0]; };
  const int m = scalar("m"), n = scalar("n"), nz = scalar("nz");
  const auto pp = h.read<std::int32_t>(g + "/p", 0), ii = h.read<std::int32_t>(g + "/i", 0);
  const auto x = h.read<double>(g + "/x", 0);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, n);
  if (nz >= 0) {
    for (int k = 0; k < nz; ++k) A(ii[k], pp[k]) += x[k];
  } else {
    const int outer = nz == -1 ? n : m;
    for (int o = 0; o < outer; ++o)
      for (int k = pp[o]; k < pp[o + 1]; ++k) (nz == -1 ? A(ii[k], o) : A(o, ii[k])) += x[k];
  }
  return A;
}

// FCLIB files: the W and q Sable reads equal those computed here densely from the file's own
// datasets, to 1e-10 of max|W| and max|q| (round-off of two different solves): for the local
// file W and q themselves, for the global ones W = H^T M^-1 H and q = H^T M^-1 f + w (Siconos'
// global problem M v = f + H r, u = H^T v + w; the files store no solution to compare with:
// their /solution datasets are empty). Then Sable's default NLGS solves each to 1e-4.
TEST(Fclib, LocalAndGlobalFilesReadAsTheirDenseForm) {
  for (const char* name : {"Capsules-i125-1213.hdf5", "Box_Stacks-i0122-82-5.hdf5",
                           "spheres-in-a-box-98-i10000-256-10.hdf5"}) {
    SCOPED_TRACE(name);
    const fs::path f = kShared / "fc3d" / name;
    SABLE_NEEDS(fs::exists(f), f << " does not exist");
    MatrixProblem<3> p = read_fc3d(f.string());
    const sable::h5::File h = sable::h5::File::open(f.string(), name);
    Eigen::MatrixXd W;
    Eigen::VectorXd q;
    if (h.exists("/fclib_local")) {
      W = dense_matrix(h, "/fclib_local/W");
      const auto qv = h.read<double>("/fclib_local/vectors/q", 0);
      q = Eigen::Map<const Eigen::VectorXd>(qv.data(), static_cast<Eigen::Index>(qv.size()));
    } else {
      const Eigen::MatrixXd M = dense_matrix(h, "/fclib_global/M");
      const Eigen::MatrixXd H = dense_matrix(h, "/fclib_global/H");
      const auto fv = h.read<double>("/fclib_global/vectors/f", 0);
      const auto wv = h.read<double>("/fclib_global/vectors/w", 0);
      const auto lu = M.partialPivLu();
      W = H.transpose() * lu.solve(H);
      q = H.transpose() * lu.solve(Eigen::Map<const Eigen::VectorXd>(fv.data(), M.rows())) +
          Eigen::Map<const Eigen::VectorXd>(wv.data(), H.cols());
    }
    ASSERT_EQ(W.rows(), static_cast<Eigen::Index>(3 * p.size()));
    Eigen::MatrixXd Ws = Eigen::MatrixXd::Zero(W.rows(), W.cols());
    for (std::size_t a = 0; a < p.size(); ++a)
      for (std::size_t k = p.row_ptr()[a]; k < p.row_ptr()[a + 1]; ++k)
        Ws.block<3, 3>(3 * static_cast<Eigen::Index>(a),
                       3 * static_cast<Eigen::Index>(p.cols()[k])) = p.blocks()[k];
    EXPECT_LE((Ws - W).cwiseAbs().maxCoeff(), 1e-10 * W.cwiseAbs().maxCoeff());
    double dq = 0.0;
    for (std::size_t a = 0; a < p.size(); ++a)
      dq = std::max(
          dq, (p.q()[a] - q.segment<3>(3 * static_cast<Eigen::Index>(a))).cwiseAbs().maxCoeff());
    EXPECT_LE(dq, 1e-10 * q.cwiseAbs().maxCoeff());
    sable::Rng rng(1);
    EXPECT_TRUE(solve_nlgs<3>(p, NlgsSettings{}, rng).converged);
    EXPECT_LE(fc_residual<3>(p), 1e-4);
  }
}

// A contact whose block is not symmetric (a gyroscopic-like skew part: W = S + K, S = diag(2,
// 3, 3) positive definite, K skew): read, and solved exactly. Sticking (q = (-1, 0.1, 0.05),
// mu = 0.8): the only solution is r = -W^-1 q (U = 0), inside the cone, reached to 1e-12.
// Sliding (q = (-1, 3, 0), mu = 0.3): the solution's natural map vanishes to 1e-10.
TEST(FcAsymmetric, OneContactStickingAndSliding) {
  Eigen::Matrix3d W;
  W << 2.0, 0.3, 0.0, -0.3, 3.0, 0.2, 0.0, -0.2, 3.0;
  for (const auto kind : {LocalSolver::kExact, LocalSolver::kBipotential}) {
    SCOPED_TRACE(std::string(to_string(kind)));
    const Eigen::Vector3d q_stick(-1.0, 0.1, 0.05);
    const Eigen::Vector3d r_stick = -W.partialPivLu().solve(q_stick);
    ASSERT_LT(std::hypot(r_stick[1], r_stick[2]), 0.8 * r_stick[0]);  // inside: a sticking answer
    MatrixProblem<3> stick({0, 1}, {0}, {W}, {q_stick}, {0.8});
    NlgsSettings s;
    s.local = kind;
    s.tolerance = 1e-14;
    s.max_iterations = 200;
    sable::Rng rng(1);
    solve_nlgs<3>(stick, s, rng);
    EXPECT_LE((stick.r(0) - r_stick).norm(), 1e-12 * r_stick.norm());

    MatrixProblem<3> slide({0, 1}, {0}, {W}, {Eigen::Vector3d(-1.0, 3.0, 0.0)}, {0.3});
    solve_nlgs<3>(slide, s, rng);
    const Eigen::Vector3d U = slide.velocity(0);
    EXPECT_GT(std::hypot(U[1], U[2]), 0.1);  // it slides
    EXPECT_LE(natural_map<3>(slide.r(0), U, 0.3).norm(), 1e-10 * slide.r(0).norm());
    EXPECT_LE(fc_residual<3>(slide), 1e-10);
  }
}

// An asymmetric block is read from a file; one whose symmetric part has a negative direction
// is refused, naming the contact.
TEST(FcAsymmetric, FileBlocksCheckedOnTheirSymmetricPart) {
  const auto text = [](const std::string& w01, const std::string& w10) {
    return "3\n1\n0\n3\n3\n3 3\n2 " + w10 + " 0\n" + w01 + " 2 0\n0 0 2\n-1 0.1 0.2\n0.5\n";
  };
  const auto p = std::get<MatrixProblem<3>>(parse_fc_dat(text("0.5", "-0.5"), "skew.dat"));
  EXPECT_EQ(p.W(0)(0, 1), 0.5);  // column-major: the second value of column 1 is W(0, 1)
  EXPECT_EQ(p.W(0)(1, 0), -0.5);
  try {
    parse_fc_dat(text("5", "0"), "bad.dat");  // S(0, 1) = 2.5: eigenvalues 2 -+ 2.5
    ADD_FAILURE() << "no error";
  } catch (const sable::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.dat: contact 0: the symmetric part of its diagonal "
                                         "block is not positive semi-definite (eigenvalue -0.5"),
              std::string::npos)
        << e.what();
  }
}

// Every shared problem (shared/data/fc3d and fc2d: Siconos' .dat files and the FCLIB HDF5
// files) reaches Siconos' error 1e-4 and 1e-6 with `sable fc3d`'s default settings (NLGS with
// the exact local solver, forward order, 1,000 sweeps; a shuffled order at a stagnation, then
// the semismooth Newton of fc_newton.hpp), the error recomputed from scratch by fc_residual.
TEST(FcDefaults, EverySharedProblemReachesBothTolerances) {
  SABLE_NEEDS(fs::is_directory(kShared / "fc3d") && fs::is_directory(kShared / "fc2d"),
              kShared << " does not hold fc3d/ and fc2d/");
  std::vector<fs::path> files;
  for (const char* dir : {"fc3d", "fc2d"})
    for (const auto& e : fs::directory_iterator(kShared / dir))
      if (e.path().extension() == ".dat" || e.path().extension() == ".hdf5")
        files.push_back(e.path());
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files.size(), 41u);  // 29 + 3 in fc3d, 9 in fc2d
  int handed_over = 0, enumerated = 0;
  for (const double tol : {1e-4, 1e-6}) {
    for (const fs::path& f : files) {
      SCOPED_TRACE(f.filename().string() + " at " + std::to_string(tol));
      NlgsSettings s;
      s.local = LocalSolver::kExact;  // as `sable fc3d`
      s.tolerance = tol;
      const FcReport r = solve_fc(f.string(), s);
      EXPECT_TRUE(r.converged);
      EXPECT_LE(r.residual, tol);
      handed_over += r.newton_iterations > 0 ? 1 : 0;
      // Only 2D problems of at most kEnumerateMaxContacts contacts are enumerated (of the set:
      // FC2D_SliderCrankLagrangian00000, 2 contacts, where the NLGS needed 166 sweeps).
      EXPECT_EQ(r.enumerated, r.dimension == 2 && r.contacts <= kEnumerateMaxContacts);
      enumerated += r.enumerated ? 1 : 0;
    }
  }
  EXPECT_GE(handed_over, 3);  // the Newton fallback is needed, not idle
  EXPECT_EQ(enumerated, 2);   // the slider crank, at both tolerances
}

// Siconos' OneObject-i100000-316 is a problem where the forward sweep cycles: 1,000 forward
// sweeps leave it at 1.7e-3 (no stagnation response); with it, the sweep turns shuffled and
// reaches 1e-6 without Newton.
TEST(FcStagnation, ForwardCycleIsShuffledAway) {
  const fs::path f = kShared / "fc3d" / "OneObject-i100000-316.hdf5.dat";
  SABLE_NEEDS(fs::exists(f), f << " does not exist");
  NlgsSettings s;
  s.tolerance = 1e-6;
  s.stagnation_window = 0;
  MatrixProblem<3> p = read_fc3d(f.string());
  sable::Rng rng(1);
  const NlgsResult cycling = solve_nlgs<3>(p, s, rng);
  EXPECT_FALSE(cycling.converged);
  EXPECT_GT(cycling.residual, 1e-3);
  s.stagnation_window = NlgsSettings{}.stagnation_window;
  const FcReport r = solve_fc(f.string(), s);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.reordered_at, 0);
  EXPECT_EQ(r.newton_iterations, 0);
}

// The semismooth Newton alone, from r = 0: on Capsules-i101-404 (225 contacts) it reaches
// 1e-10 in at most 40 steps (23 measured; Newton's local convergence, where the NLGS needs
// 153 sweeps for 1e-6); on the asymmetric one-contact problems above, to 1e-12.
TEST(FcNewton, ConvergesFromZero) {
  const fs::path f = kShared / "fc3d" / "Capsules-i101-404.dat";
  SABLE_NEEDS(fs::exists(f), f << " does not exist");
  MatrixProblem<3> p = read_fc3d(f.string());
  const NewtonResult res = solve_newton_ac<3>(p, {.tolerance = 1e-10, .max_iterations = 40});
  EXPECT_TRUE(res.converged) << res.residual;
  EXPECT_LE(fc_residual<3>(p), 1e-10);
  Eigen::Matrix3d W;
  W << 2.0, 0.3, 0.0, -0.3, 3.0, 0.2, 0.0, -0.2, 3.0;
  for (const Eigen::Vector3d& q :
       {Eigen::Vector3d(-1.0, 0.1, 0.05), Eigen::Vector3d(-1.0, 3.0, 0.0),
        Eigen::Vector3d(1.0, 0.5, 0.0)}) {
    MatrixProblem<3> one({0, 1}, {0}, {W}, {q}, {0.3});
    EXPECT_TRUE(solve_newton_ac<3>(one, {.tolerance = 1e-12, .max_iterations = 40}).converged)
        << q.transpose();
  }
}

// Bad CSparse storage and bad FCLIB files: an InputError naming the file and the place.
std::string error_of(const std::function<void()>& read) {
  try {
    read();
  } catch (const sable::InputError& e) {
    return e.what();
  }
  return "no error";
}

::testing::AssertionResult has(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" lacks \"" << part << "\"";
}

TEST(FcBadInput, CSparseStorage) {
  const auto text = [](const std::string& col1, const std::string& row1, const std::string& nnz) {
    return "2\n1\n2\n2\n2\n2\nCSparse Version 3.1.9, May 4, 2016.  Copyright (c) T. A. D.\n"
           "2-by-2, nzmax: 2 nnz: " +
           nnz + ", 1-norm: 3\n    col 0 : locations 0 to 0\n      0 : 2\n    col " + col1 +
           " : locations 1 to 1\n      " + row1 + " : 3\n-1 0\n0.5\n";
  };
  const auto p = std::get<MatrixProblem<2>>(parse_fc_dat(text("1", "1", "2"), "ok.dat"));
  EXPECT_EQ(p.W(0)(0, 0), 2.0);
  EXPECT_EQ(p.W(0)(1, 1), 3.0);
  const auto err = [&](const std::string& t) {
    return error_of([&] { parse_fc_dat(t, "cs.dat"); });
  };
  EXPECT_TRUE(has(err(text("2", "1", "2")), "cs.dat, line 11: expected column 1 here"));
  EXPECT_TRUE(
      has(err(text("1", "5", "2")), "cs.dat, line 12: the row of entry 1 = 5 out of range"));
  EXPECT_TRUE(has(err(text("1", "1", "3")),
                  "cs.dat: CSparse's header says nnz 3, the columns hold 2 entries"));
}

TEST(FcBadInput, FclibFiles) {
  const fs::path dir = fs::temp_directory_path() / ("sable_fclib_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto write = [&](const std::string& name, std::vector<std::int32_t> p_values) {
    const fs::path f = dir / name;
    sable::h5::File h = sable::h5::File::create(f.string(), name);
    h.write("/fclib_local/spacedim", std::vector<std::int32_t>{2});
    h.write("/fclib_local/W/m", std::vector<std::int32_t>{2});
    h.write("/fclib_local/W/n", std::vector<std::int32_t>{2});
    h.write("/fclib_local/W/nz", std::vector<std::int32_t>{-1});
    h.write("/fclib_local/W/p", p_values);
    h.write("/fclib_local/W/i", std::vector<std::int32_t>{0, 1});
    h.write("/fclib_local/W/x", std::vector<double>{2.0, 3.0});
    h.write("/fclib_local/vectors/q", std::vector<double>{-1.0, 0.0});
    h.write("/fclib_local/vectors/mu", std::vector<double>{0.5});
    h.close();
    return f.string();
  };
  const std::string ok = write("ok.hdf5", {0, 1, 2});
  const auto p = std::get<MatrixProblem<2>>(read_fc(ok));
  EXPECT_EQ(p.W(0)(1, 1), 3.0);
  const std::string bad = write("bad.hdf5", {0, 2, 1});
  EXPECT_TRUE(has(error_of([&] { read_fc(bad); }),
                  "bad.hdf5': '/fclib_local/W/p' value 2 = 1 is out of order"));
  const fs::path other = dir / "other.h5";
  {
    sable::h5::File h = sable::h5::File::create(other.string(), "other.h5");
    h.write("/particles/radius", std::vector<double>{1.0});
    h.close();
  }
  EXPECT_TRUE(has(error_of([&] { read_fc(other.string()); }),
                  "holds neither '/fclib_local' nor '/fclib_global': not an FCLIB problem"));
  fs::remove_all(dir);
}

}  // namespace
