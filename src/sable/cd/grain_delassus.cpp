// The grains' Delassus matrix: see grain_delassus.hpp.
#include "sable/cd/grain_delassus.hpp"

#include <algorithm>
#include <utility>

namespace sable::cd {

template <int D>
MatrixProblem<D> assemble_grain_problem(const typename CdSolver<D>::Contacts& c,
                                        const ParticleStore<D>& p, std::vector<LVec<D>> q) {
  using S = Space<D>;
  using Vec = typename S::Vec;
  using Mat = LMat<D>;
  const std::size_t n = c.size(), grains = p.size();
  // Each grain's contacts: contact a enters grain i's list with +1 and its partner's with -1.
  struct Touch {
    std::uint32_t contact;
    double sign;
    Vec arm;
  };
  std::vector<std::uint32_t> start(grains + 1, 0);
  for (std::size_t a = 0; a < n; ++a) {
    ++start[c.i[a] + 1];
    if (!c.wall[a]) ++start[c.partner[a] + 1];
  }
  for (std::size_t g = 0; g < grains; ++g) start[g + 1] += start[g];
  std::vector<Touch> touches(start[grains]);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t a = 0; a < n; ++a) {
    const auto id = static_cast<std::uint32_t>(a);
    touches[fill[c.i[a]]++] = {id, 1.0, c.arm_i[a]};
    if (!c.wall[a]) touches[fill[c.partner[a]]++] = {id, -1.0, c.arm_j[a]};
  }
  std::vector<std::size_t> row_ptr{0}, cols;
  std::vector<Mat> blocks;
  std::vector<std::pair<std::uint32_t, Mat>> row;
  for (std::size_t a = 0; a < n; ++a) {
    row.clear();
    const std::uint32_t own[2] = {c.i[a], c.partner[a]};
    for (int side = 0; side < (c.wall[a] ? 1 : 2); ++side) {
      const std::uint32_t g = own[side];
      const double sa = side == 0 ? 1.0 : -1.0;
      const Vec& arm_a = side == 0 ? c.arm_i[a] : c.arm_j[a];
      const double im = p.inv_mass[g], ii = p.inv_inertia[g];
      if (im == 0.0 && ii == 0.0) continue;  // a fixed grain moves for nobody
      for (std::uint32_t k = start[g]; k < start[g + 1]; ++k) {
        const Touch& b = touches[k];
        Mat block;
        for (int col = 0; col < D; ++col) {
          const Vec P = b.sign * c.frame[b.contact].col(col);
          const Vec dv = im * P + S::spin_velocity(ii * S::moment(b.arm, P), arm_a);
          block.col(col) = sa * (c.frame[a].transpose() * dv);
        }
        row.emplace_back(b.contact, block);
      }
    }
    // Sorted by column, the two grains' shares of one block summed (the diagonal block, or a
    // contact b that shares both grains with a).
    std::sort(row.begin(), row.end(),
              [](const auto& x, const auto& y) { return x.first < y.first; });
    for (std::size_t k = 0; k < row.size(); ++k) {
      if (k > 0 && row[k].first == row[k - 1].first) {
        blocks.back() += row[k].second;
        continue;
      }
      cols.push_back(row[k].first);
      blocks.push_back(row[k].second);
    }
    // Every row holds its diagonal block, even a contact between two fixed bodies.
    if (std::find(cols.begin() + static_cast<std::ptrdiff_t>(row_ptr.back()), cols.end(), a) ==
        cols.end()) {
      cols.push_back(a);
      blocks.push_back(Mat::Zero());
    }
    row_ptr.push_back(cols.size());
  }
  return MatrixProblem<D>(std::move(row_ptr), std::move(cols), std::move(blocks), std::move(q),
                          std::vector<double>(c.mu.begin(), c.mu.end()));
}

template MatrixProblem<2> assemble_grain_problem<2>(const CdSolver<2>::Contacts&,
                                                    const ParticleStore<2>&, std::vector<LVec<2>>);
template MatrixProblem<3> assemble_grain_problem<3>(const CdSolver<3>::Contacts&,
                                                    const ParticleStore<3>&, std::vector<LVec<3>>);

}  // namespace sable::cd
