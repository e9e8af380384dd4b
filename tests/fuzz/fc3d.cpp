// Fuzz target: a Siconos .dat frictional-contact problem's bytes (2D or 3D) through Sable's
// reader, and a problem that reads through a few NLGS sweeps of each local solver and the
// residual, as `sable fc3d` does.
//
// Bad input must end in sable::InputError; any other exception, a crash or a sanitizer report
// is a finding. Large problems are only read: a sweep over them takes longer than an input
// may.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <type_traits>
#include <variant>

#include "sable/cd/fc_problem.hpp"
#include "sable/core/error.hpp"
#include "sable/core/rng.hpp"

namespace {

constexpr std::size_t kSweptBlocks = 10'000;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    sable::cd::FcProblem problem = sable::cd::parse_fc_dat(text, "fuzz.dat");
    std::visit(
        [](auto& p) {
          constexpr int d = std::remove_reference_t<decltype(p)>::kDim;
          if (p.blocks().size() > kSweptBlocks) return;
          for (auto local :
               {sable::cd::LocalSolver::kBipotential, sable::cd::LocalSolver::kExact}) {
            sable::cd::NlgsSettings s;
            s.local = local;
            s.order = sable::cd::SweepOrder::kShuffled;
            s.max_iterations = 5;
            sable::Rng rng(1);
            p.reset_reactions();
            sable::cd::solve_nlgs<d>(p, s, rng);
            sable::cd::fc_residual<d>(p);
          }
        },
        problem);
  } catch (const sable::InputError& e) {
    // SABLE_FUZZ_VERBOSE=1: say why each input was refused (to check a corpus reaches deep).
    if (std::getenv("SABLE_FUZZ_VERBOSE") != nullptr)
      std::fprintf(stderr, "refused: %s\n", e.what());
  }
  return 0;
}
