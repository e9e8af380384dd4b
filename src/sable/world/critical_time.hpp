// The critical time step of a World's grains under its contact law: the smallest over the
// grains of the law's own estimate (HertzNormal: the Rayleigh time; LinearNormal: sqrt(m/2k)).
// The scenario's automatic dt is a fraction of it, and a dt too close to it is refused
// (scenario/build.cpp).
#pragma once

#include <algorithm>
#include <limits>
#include <string_view>

#include "sable/contact/registry.hpp"
#include "sable/geometry/polyhedron_contact.hpp"
#include "sable/world/world.hpp"

namespace sable {

// With polyhedral grains (DEM: linear law) a contact's springs are those of its manifold's
// points in parallel, up to PolyhedronContact::kMaxPoints of them (dem/polyhedral_dem.hpp):
// the estimate takes the stiffest, that many times the law's.
template <class Laws = NormalLaws, int D>
double critical_time(const World<D>& w) {
  ContactModel model = w.model;
  if (!w.shapes.empty()) {
    model.kn *= PolyhedronContact::kMaxPoints;
    model.kt *= PolyhedronContact::kMaxPoints;
  }
  return Laws::visit(w.model.normal, [&]<class Law>() {
    const auto& p = w.particles;
    double t_crit = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < p.size(); ++k)
      t_crit = std::min(
          t_crit, Law::critical_time(w.materials[p.material[k]], p.radius[k], p.mass[k], model));
    return t_crit;
  });
}

// What critical_time() measures, in words, for messages.
template <class Laws = NormalLaws, int D>
std::string_view critical_time_name(const World<D>& w) {
  return Laws::visit(w.model.normal, [&]<class Law>() { return Law::kCriticalTimeName; });
}

}  // namespace sable
