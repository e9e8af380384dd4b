#include "sable/cd/fc_enumerate.hpp"

#include <Eigen/LU>
#include <cmath>

namespace sable::cd {
namespace {

// At most 2 kEnumerateMaxContacts unknowns: fixed-capacity storage, no heap allocation.
constexpr int kMaxUnknowns = 2 * static_cast<int>(kEnumerateMaxContacts);
using Mat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxUnknowns, kMaxUnknowns>;
using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxUnknowns, 1>;

// A contact's state, one base-4 digit of a combination's code.
enum State : std::size_t { kTakeOff = 0, kStick = 1, kSlidePlus = 2, kSlideMinus = 3 };

struct Dense {
  Mat W;
  Vec q;
  Vec mu;  // one per contact
  double slack = 0.0;
};

State digit(std::size_t code, std::size_t a) {
  for (std::size_t k = 0; k < a; ++k) code /= 4;
  return static_cast<State>(code % 4);
}

// The combination's equations: take-off r = 0; stick U = 0; slide U_N = 0 and
// r_T = -sigma mu r_N (sigma = +1: U_T >= 0).
void assemble(const Dense& p, std::size_t code, Mat& A, Vec& b) {
  A.setZero();
  b.setZero();
  for (Eigen::Index a = 0; a < p.mu.size(); ++a) {
    const Eigen::Index N = 2 * a, T = N + 1;
    const State s = digit(code, static_cast<std::size_t>(a));
    if (s == kTakeOff) {
      A(N, N) = A(T, T) = 1.0;
      continue;
    }
    A.row(N) = p.W.row(N), b[N] = -p.q[N];
    if (s == kStick) {
      A.row(T) = p.W.row(T), b[T] = -p.q[T];
    } else {
      A(T, T) = 1.0, A(T, N) = (s == kSlidePlus ? 1.0 : -1.0) * p.mu[a];
    }
  }
}

// The inequalities of each contact's state, to the round-off slack.
bool admissible(const Dense& p, std::size_t code, const Vec& r, const Vec& U) {
  if (!r.allFinite()) return false;
  for (Eigen::Index a = 0; a < p.mu.size(); ++a) {
    const Eigen::Index N = 2 * a, T = N + 1;
    bool ok = true;
    switch (digit(code, static_cast<std::size_t>(a))) {
      case kTakeOff:
        ok = U[N] >= -p.slack;
        break;
      case kStick:
        ok = r[N] >= -p.slack && std::abs(r[T]) <= p.mu[a] * r[N] + p.slack;
        break;
      case kSlidePlus:
        ok = r[N] >= -p.slack && U[T] >= -p.slack;
        break;
      case kSlideMinus:
        ok = r[N] >= -p.slack && U[T] <= p.slack;
        break;
    }
    if (!ok) return false;
  }
  return true;
}

// The combination each contact alone points to (its diagonal block, the others' reactions
// zero): take-off where q_N >= 0, stick where the stick solution lies in the cone, slide
// against r_T elsewhere. Tried first; it is the answer when the coupling does not change any
// contact's state.
std::size_t guess(const Dense& p) {
  std::size_t code = 0, place = 1;
  for (Eigen::Index a = 0; a < p.mu.size(); ++a, place *= 4) {
    const Eigen::Matrix2d W = p.W.block<2, 2>(2 * a, 2 * a);
    const Eigen::Vector2d r = -W.partialPivLu().solve(p.q.segment<2>(2 * a));
    const State s = !(p.q[2 * a] < 0.0)                ? kTakeOff
                    : std::abs(r[1]) <= p.mu[a] * r[0] ? kStick
                    : r[1] < 0.0                       ? kSlidePlus
                                                       : kSlideMinus;
    code += place * s;
  }
  return code;
}

}  // namespace

bool solve_enumeration_2d(MatrixProblem<2>& p, double tolerance) {
  const std::size_t n = p.size();
  if (n == 0 || n > kEnumerateMaxContacts) return false;
  const auto m = static_cast<Eigen::Index>(2 * n);
  Dense dense{Mat::Zero(m, m), Vec(m), Vec(static_cast<Eigen::Index>(n))};
  for (std::size_t a = 0; a < n; ++a) {
    const auto N = 2 * static_cast<Eigen::Index>(a);
    for (std::size_t k = p.row_ptr()[a]; k < p.row_ptr()[a + 1]; ++k)
      dense.W.block<2, 2>(N, 2 * static_cast<Eigen::Index>(p.cols()[k])) = p.blocks()[k];
    dense.q.segment<2>(N) = p.q()[a];
    dense.mu[static_cast<Eigen::Index>(a)] = p.mu(a);
  }
  // Inequalities hold to a round-off margin of the data's size; the law is then checked on
  // the whole problem by fc_residual.
  dense.slack = 1e-12 * (dense.W.cwiseAbs().maxCoeff() + dense.q.cwiseAbs().maxCoeff());
  std::size_t combinations = 1;
  for (std::size_t a = 0; a < n; ++a) combinations *= 4;
  Mat A(m, m);
  Vec b(m);
  const std::size_t first = guess(dense);
  for (std::size_t k = 0; k < combinations; ++k) {
    // The guess first, then every other combination in code order.
    const std::size_t code = k == 0 ? first : (k - 1 < first ? k - 1 : k);
    assemble(dense, code, A, b);
    // Partial pivoting (a third of full pivoting's cost): a singular combination gives a
    // non-finite or inadmissible r, and whatever passes is checked on the law below.
    const Vec r = Eigen::PartialPivLU<Mat>(A).solve(b);
    if (!admissible(dense, code, r, dense.W * r + dense.q)) continue;
    for (std::size_t a = 0; a < n; ++a) p.r(a) = r.segment<2>(2 * static_cast<Eigen::Index>(a));
    if (fc_residual<2>(p) <= tolerance) return true;
  }
  p.reset_reactions();
  return false;
}

}  // namespace sable::cd
