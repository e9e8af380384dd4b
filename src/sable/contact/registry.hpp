// The registry: every contact law and sub-model Sable knows, by category and name. It is the
// single source for the scenario's names (scenario/parse.cpp), the build's choice
// (scenario/build.cpp), `sable models` and the docs.
//
// Normal laws are types (one file each) listed in NormalLaws; the DEM pair pass, the servo
// and the time-step check dispatch on a World's row through NormalLaws::visit. The other
// sub-models are enumerators switched inside the one kernel (contact/contact_model.hpp), so
// they are rows of kOtherSubModels. Row 0 of NormalLaws is the default law.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sable/contact/contact_model.hpp"
#include "sable/contact/hertz_law.hpp"
#include "sable/contact/law_table.hpp"
#include "sable/contact/linear_law.hpp"

namespace sable {

using NormalLaws = LawTable<HertzNormal, LinearNormal>;

struct SubModelEntry {
  std::string_view category;
  std::string_view name;
  int code;  // the normal law's row, or the sub-model's enumerator
  std::string_view summary;
};

inline constexpr SubModelEntry kOtherSubModels[] = {
    {"tangential", "history", static_cast<int>(TangentialModel::kHistory),
     "Mindlin spring on the accumulated tangential displacement, Coulomb-capped"},
    {"tangential", "none", static_cast<int>(TangentialModel::kNone), "frictionless contact"},
    {"rolling", "none", static_cast<int>(RollingModel::kNone), "grains roll freely"},
    {"rolling", "epsd", static_cast<int>(RollingModel::kEpsd),
     "elastic-plastic spring-dashpot couple, capped at mu_r R* F_n (Iwashita & Oda 1998; Ai et "
     "al. 2011 model C); CD: its rigid limit"},
    {"cohesion", "none", static_cast<int>(CohesionModel::kNone), "dry grains"},
    {"cohesion", "capillary", static_cast<int>(CohesionModel::kCapillary),
     "liquid bridges, Richefeu et al. 2009 eq. 1-8: -kappa R in contact, exponential decay to "
     "the rupture distance; formed at contact (hysteresis); DEM, 3D"},
};

// Every row: the normal laws of a table first, then the other sub-models.
template <class Laws>
constexpr auto sub_model_rows() {
  std::array<SubModelEntry, Laws::kSize + std::size(kOtherSubModels)> rows{};
  std::size_t k = 0;
  for (std::size_t i = 0; i < Laws::kSize; ++i, ++k)
    rows[k] = {"normal", Laws::kNames[i], static_cast<int>(i), Laws::kSummaries[i]};
  for (const SubModelEntry& e : kOtherSubModels) rows[k++] = e;
  return rows;
}
inline constexpr auto kContactSubModels = sub_model_rows<NormalLaws>();

// The names of one category, in table order (the parser's choices).
inline std::vector<std::string_view> sub_model_names(std::string_view category) {
  std::vector<std::string_view> names;
  for (const SubModelEntry& e : kContactSubModels)
    if (e.category == category) names.push_back(e.name);
  return names;
}

// The code of (category, name); nullopt when the registry has no such row.
inline std::optional<int> sub_model_code(std::string_view category, std::string_view name) {
  for (const SubModelEntry& e : kContactSubModels)
    if (e.category == category && e.name == name) return e.code;
  return std::nullopt;
}

}  // namespace sable
