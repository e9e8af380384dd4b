#include "sable/scenario/resume_changes.hpp"

#include <fmt/format.h>

#include <map>
#include <optional>
#include <sstream>
#include <string_view>

#include "sable/core/error.hpp"
#include "sable/scenario/toml_reader.hpp"

namespace sable {
namespace {

constexpr std::size_t kListed = 8;  // changes quoted in a message; the rest are counted

using Leaves = std::map<std::string, const toml::node*>;

bool is_table_array(const toml::array& a) {
  if (a.empty()) return false;
  for (const auto& e : a)
    if (!e.is_table()) return false;
  return true;
}

// Every value of `t` under its dotted key; arrays of tables are entered ("wall[1].point"),
// any other array is one value.
void flatten(const toml::table& t, const std::string& prefix, Leaves& out) {
  for (auto&& [k, v] : t) {
    const std::string key =
        prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const auto* sub = v.as_table()) {
      flatten(*sub, key, out);
    } else if (const auto* arr = v.as_array(); arr && is_table_array(*arr)) {
      for (std::size_t i = 0; i < arr->size(); ++i)
        flatten(*arr->get(i)->as_table(), fmt::format("{}[{}]", key, i), out);
    } else {
      out.emplace(key, &v);
    }
  }
}

// The top-level table a key belongs to: "material" for "material[0].density".
std::string_view section(std::string_view key) {
  return key.substr(0, key.find_first_of(".["));
}

std::string_view leaf(std::string_view key) {
  const auto dot = key.rfind('.');
  return dot == std::string_view::npos ? key : key.substr(dot + 1);
}

// Why a changed key cannot act on a resumed state, or "" when it applies.
std::string kept_because(const std::string& key) {
  const std::string_view s = section(key), l = leaf(key);
  if (s == "grains") return "the grains come from the snapshot";
  if ((s == "material" && l == "density") || key == "simulation.thickness")
    return "the grains' masses come from the snapshot (an automatic time step follows the new "
           "value)";
  if (key == "simulation.seed") return "the random generator's state comes from the snapshot";
  if (s == "domain") return "the contact-detection grid comes from the snapshot";
  // A turning wall's spin, pivot and orientation are state too (a mesh's surface, rebuilt from
  // the new scenario, is placed at the snapshot's pose: its offset is a position).
  if (s == "wall" && (l == "point" || l == "lo" || l == "hi" || l == "center" || l == "velocity" ||
                      l == "offset" || key.find(".rotation.") != std::string::npos))
    return "the walls' positions, velocities and rotations come from the snapshot";
  return {};
}

// The run's programme and its storage order: a resumed run may take new ones.
bool free_to_change(const std::string& key) {
  const std::string_view s = section(key);
  return s == "output" || s == "stage" || key == "simulation.reorder_every";
}

std::string shown(const toml::node* n) {
  return n ? detail::show(*n) : "(absent)";
}

std::optional<double> number(const toml::node& n) {
  if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = n.as_floating_point()) return f->get();
  return std::nullopt;
}

// Equal values: numbers by value (2500 and 2500.0 are the same density), arrays element by
// element, anything else by its TOML text.
bool same_value(const toml::node& a, const toml::node& b) {
  const auto x = number(a), y = number(b);
  if (x || y) return x && y && *x == *y;
  const auto* aa = a.as_array();
  const auto* ba = b.as_array();
  if (aa || ba) {
    if (!aa || !ba || aa->size() != ba->size()) return false;
    for (std::size_t k = 0; k < aa->size(); ++k)
      if (!same_value(*aa->get(k), *ba->get(k))) return false;
    return true;
  }
  std::ostringstream sa, sb;
  a.visit([&sa](auto&& v) { sa << v; });
  b.visit([&sb](auto&& v) { sb << v; });
  return a.type() == b.type() && sa.str() == sb.str();
}

}  // namespace

std::vector<ScenarioChange> scenario_changes(const std::string& old_text,
                                             const std::string& old_label,
                                             const std::string& new_text,
                                             const std::string& new_label) {
  const toml::table a = detail::parse_document(old_text, old_label);
  const toml::table b = detail::parse_document(new_text, new_label);
  Leaves la, lb;
  flatten(a, "", la);
  flatten(b, "", lb);
  std::map<std::string, ScenarioChange> out;  // sorted by key
  auto note = [&](const std::string& key, const toml::node* before, const toml::node* after) {
    if (free_to_change(key)) return;
    out.emplace(key, ScenarioChange{key, shown(before), shown(after), kept_because(key)});
  };
  for (const auto& [key, node] : la) {
    const auto it = lb.find(key);
    if (it == lb.end())
      note(key, node, nullptr);
    else if (!same_value(*node, *it->second))
      note(key, node, it->second);
  }
  for (const auto& [key, node] : lb)
    if (!la.count(key)) note(key, nullptr, node);
  std::vector<ScenarioChange> v;
  for (auto& [key, c] : out) v.push_back(std::move(c));
  return v;
}

std::string describe_changes(const std::vector<ScenarioChange>& changes) {
  std::string s;
  for (std::size_t k = 0; k < changes.size() && k < kListed; ++k)
    s += fmt::format("{}{} ({} -> {})", k ? ", " : "", clip(changes[k].key),
                     clip(changes[k].before), clip(changes[k].after));
  if (changes.size() > kListed) s += fmt::format(" and {} more", changes.size() - kListed);
  return s;
}

}  // namespace sable
