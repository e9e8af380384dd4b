#include "sable/scenario/parse_contact.hpp"

#include "sable/contact/registry.hpp"
#include "sable/core/error.hpp"

namespace sable::detail {

namespace {

// cohesion = "capillary" with its liquid's properties (contact/capillary.hpp).
void parse_cohesion(const Table& t, ContactConfig& c) {
  c.cohesion = t.choice("cohesion", sub_model_names("cohesion"), c.cohesion);
  const char* keys[] = {"surface_tension", "contact_angle", "capillary_c", "ruptured_liquid"};
  if (c.cohesion != "capillary") {
    for (const char* k : keys) t.reject(k, "unless cohesion = \"capillary\"");
    return;
  }
  c.surface_tension = t.number_or("surface_tension", kPositive, c.surface_tension);
  c.contact_angle_deg =
      t.number_or("contact_angle", Range{0.0, 90.0, false, true}, c.contact_angle_deg);
  c.capillary_c = t.number_or("capillary_c", kPositive, c.capillary_c);
  c.ruptured_liquid = t.choice("ruptured_liquid", {"grains", "lost"}, c.ruptured_liquid);
}

// Whether the normal law `name` (a registered one) reads contact.kn and contact.kt.
bool law_takes_spring_constants(const std::string& name) {
  return NormalLaws::visit(*NormalLaws::find(name),
                           []<class Law>() { return Law::kSpringConstants; });
}

// The laws that read contact.kn and contact.kt, for messages: normal = "linear", ...
std::string spring_laws() {
  std::string out;
  for (std::string_view name : NormalLaws::kNames)
    if (law_takes_spring_constants(std::string(name)))
      out += (out.empty() ? "normal = " : ", ") + in_quotes(std::string(name));
  return out;
}

}  // namespace

ContactConfig parse_contact(const Table& root) {
  ContactConfig c;
  const auto t = root.table("contact");
  if (!t) return c;
  t->check_keys({"normal", "tangential", "attractive_damping", "keep_spring_length", "kn", "kt",
                 "cohesion", "surface_tension", "contact_angle", "capillary_c", "ruptured_liquid",
                 "rolling", "rolling_damping"});
  // The names are the registry's (contact/registry.hpp).
  c.normal = t->choice("normal", sub_model_names("normal"), c.normal);
  c.tangential = t->choice("tangential", sub_model_names("tangential"), c.tangential);
  c.attractive_damping = t->boolean_or("attractive_damping", c.attractive_damping);
  c.keep_spring_length = t->boolean_or("keep_spring_length", c.keep_spring_length);
  c.loc = t->loc();
  parse_cohesion(*t, c);
  c.rolling = t->choice("rolling", sub_model_names("rolling"), c.rolling);
  if (c.rolling == "none")
    t->reject("rolling_damping", "unless rolling = \"epsd\"");
  else
    c.rolling_damping =
        t->number_or("rolling_damping", Range{0.0, 1.0, false, false}, c.rolling_damping);
  if (!law_takes_spring_constants(c.normal)) {
    const std::string why =
        "to normal = " + in_quotes(c.normal) + " (only to " + spring_laws() + ")";
    t->reject("kn", why);
    t->reject("kt", why);
    return c;
  }
  c.kn = t->required_number("kn", kPositive);
  if (c.tangential == "none") {
    c.kt = t->number_or("kt", kPositive, 0.0);
  } else {
    c.kt = t->required_number("kt", kPositive);
  }
  return c;
}

CdConfig parse_cd(const Table& root, const std::string& solver) {
  CdConfig c;
  const auto t = root.table("cd");
  if (!t) return c;
  if (solver != "cd") root.reject("cd", "unless simulation.solver = \"cd\"");
  t->check_keys({"theta", "tolerance", "max_iterations", "criterion", "local_solver", "sweep",
                 "relaxation", "warm_start", "newton_iterations", "colour_block", "residual_checks",
                 "overlap_recovery"});
  c.theta = t->number_or("theta", Range{0.5, 1.0, false, false}, c.theta);
  c.tolerance = t->number_or("tolerance", kPositive, c.tolerance);
  c.max_iterations = t->unsigned_or("max_iterations", c.max_iterations, 1);
  c.criterion = t->choice("criterion", {"natural", "quad", "maxm"}, c.criterion);
  c.local_solver = t->choice("local_solver", {"bipotential", "exact"}, c.local_solver);
  c.sweep = t->choice("sweep", {"forward", "alternating", "shuffled", "coloured"}, c.sweep);
  c.colour_block = t->unsigned_or("colour_block", c.colour_block, 1);
  c.relaxation = t->number_or("relaxation", Range{0.0, 2.0, true, true}, c.relaxation);
  c.warm_start = t->boolean_or("warm_start", c.warm_start);
  c.overlap_recovery =
      t->number_or("overlap_recovery", Range{0.0, 1.0, false, false}, c.overlap_recovery);
  c.newton_iterations = t->unsigned_or("newton_iterations", c.newton_iterations, 0);
  c.residual_checks = t->choice("residual_checks", {"every_sweep", "spaced"}, c.residual_checks);
  c.loc = t->loc();
  return c;
}

}  // namespace sable::detail
