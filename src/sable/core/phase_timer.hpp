// Named, timed phases of a step (as Box2D's b2World_Step profile): cheap enough to stay on.
#pragma once

#include <array>
#include <chrono>
#include <string_view>

namespace sable {

// Each enumerator is the name a summary prints (kPhaseNames), so that a timing points at its
// code. DEM uses the first four, one per stage of DemSolver::step() (integrate: the first
// half kick and the drift; neighbors: the neighbour and near lists; pair pass: the contact
// forces and each grain's closing, its wall contacts, sum and second half kick; closing: the
// walls' total forces), contact dynamics integrate, neighbors, contact build and NLGS solve;
// a summary lists the phases that took time. Under MPI the DEM step has a fifth, exchange. Used by
// every solver: it sits in core, below them.
enum class Phase : int {
  kIntegrate,
  kNeighbors,
  kPairPass,
  kClosing,
  kContactBuild,
  kNlgsSolve,
  kExchange,  // MPI: the ghosts' motion from their owners, the lists' global tests
  kCount
};
inline constexpr std::array<std::string_view, static_cast<int>(Phase::kCount)> kPhaseNames = {
    "integrate", "neighbors", "pair pass", "closing", "contact build", "NLGS solve", "exchange"};

class PhaseTimers {
 public:
  using Clock = std::chrono::steady_clock;
  class Scope {
   public:
    Scope(PhaseTimers& t, Phase p) : t_(t), p_(p), start_(Clock::now()) {}
    ~Scope() {
      t_.seconds_[static_cast<int>(p_)] +=
          std::chrono::duration<double>(Clock::now() - start_).count();
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    PhaseTimers& t_;
    Phase p_;
    Clock::time_point start_;
  };
  Scope time(Phase p) { return Scope(*this, p); }
  double seconds(Phase p) const { return seconds_[static_cast<int>(p)]; }
  void reset() { seconds_.fill(0.0); }

 private:
  std::array<double, static_cast<int>(Phase::kCount)> seconds_{};
};

}  // namespace sable
