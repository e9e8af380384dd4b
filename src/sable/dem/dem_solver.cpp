// The DEM solver for the shipped law table (contact/registry.hpp: NormalLaws), in 2D and 3D.
// A table of other laws instantiates DemSolver<D, ItsTable> from the same definitions
// (tests/unit/test_law_registry.cpp does).
#include "sable/dem/dem_solver_impl.hpp"

namespace sable {

template class DemSolver<2>;
template class DemSolver<3>;

}  // namespace sable
