// What a resume may change (docs/reliability.md, "Resuming").
//
// A snapshot stores the scenario text it was written by. A resume with another text compares
// the two key by key. [output], [[stage]] and simulation.reorder_every may change freely:
// they are the run's programme and its storage order, not its physics. Any other difference is
// refused unless the user accepts it
// (`--accept-changes`), and then each changed key either applies (the model is rebuilt from
// the new scenario: materials' stiffness and friction, the contact law, the solver, the time
// step, gravity, ...) or cannot apply, because the snapshot carries that part of the state:
// the grains (positions, sizes, velocities, masses: a changed density or thickness), the
// walls' positions, velocities and rotations, the contact-detection grid and the random
// generator.
#pragma once

#include <string>
#include <vector>

namespace sable {

struct ScenarioChange {
  std::string key;     // dotted, with array indices: "material[0].density"
  std::string before;  // the old value, shown short; "(absent)" for an added key
  std::string after;   // the new value; "(absent)" for a removed key
  // Empty when the change applies on resume; else why the snapshot's value is kept.
  std::string kept_because;
};

// The differences between two scenario texts outside [output] and [[stage]], in key order.
// `old_label` and `new_label` name the texts in a syntax error (InputError).
std::vector<ScenarioChange> scenario_changes(const std::string& old_text,
                                             const std::string& old_label,
                                             const std::string& new_text,
                                             const std::string& new_label);

// "key (before -> after)" for the first few changes, and how many more.
std::string describe_changes(const std::vector<ScenarioChange>& changes);

}  // namespace sable
