// A table of contact laws chosen by name, and the one visitor that dispatches on it.
//
// A law is a struct of static members (contact/hertz_law.hpp is the model): its registry
// name and summary, its force coefficients at an overlap, its stiffness for the servo and the
// rolling sub-model, and its critical time step. A table is the list of those structs; a World
// stores which row its contacts use (NormalModel), and every place that needs the law's code
// (the DEM pair pass, the servo's stiffness, the time-step check) reaches it through visit(),
// so the law's kernels are compiled into each loop with no call through a pointer.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>

namespace sable {

// Which row of a law table a World's contacts use (the default table: contact/registry.hpp).
struct NormalModel {
  std::uint8_t row = 0;
  friend bool operator==(NormalModel, NormalModel) = default;
};

template <class... Laws>
struct LawTable {
  static constexpr std::size_t kSize = sizeof...(Laws);
  static_assert(kSize > 0 && kSize <= 255, "a law table has 1 to 255 rows");
  static constexpr std::array<std::string_view, kSize> kNames{Laws::kName...};
  static constexpr std::array<std::string_view, kSize> kSummaries{Laws::kSummary...};

  // The row of Law; a law absent from the table does not compile.
  template <class Law>
  static constexpr NormalModel id() {
    constexpr std::array<bool, kSize> same{std::is_same_v<Law, Laws>...};
    for (std::size_t k = 0; k < kSize; ++k)
      if (same[k]) return NormalModel{static_cast<std::uint8_t>(k)};
    throw std::logic_error("law not in the table");  // reached only at compile time
  }

  // The row whose name is `name`, if any.
  static constexpr std::optional<NormalModel> find(std::string_view name) {
    for (std::size_t k = 0; k < kSize; ++k)
      if (kNames[k] == name) return NormalModel{static_cast<std::uint8_t>(k)};
    return std::nullopt;
  }

  // f.template operator()<Law>() for the law in row `id` (a lambda `[&]<class Law>() {...}`),
  // returning what it returns. A row outside the table is a programming error: it throws.
  template <class F>
  static decltype(auto) visit(NormalModel id, F&& f) {
    if (id.row >= kSize)
      throw std::out_of_range("contact law row " + std::to_string(id.row) + " of a table of " +
                              std::to_string(kSize));
    return visit_row<0>(id.row, f);
  }

 private:
  template <std::size_t I, class F>
  static decltype(auto) visit_row(std::size_t row, F& f) {
    using Law = std::tuple_element_t<I, std::tuple<Laws...>>;
    if constexpr (I + 1 == kSize) {
      return f.template operator()<Law>();
    } else {
      if (row == I) return f.template operator()<Law>();
      return visit_row<I + 1>(row, f);
    }
  }
};

}  // namespace sable
