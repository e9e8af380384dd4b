// Whether a snapshot's whole state is intact: `sable info`'s integrity line.
//
// read_snapshot_info() reads the header only; a flipped bit in a data array goes unseen there
// and is refused only when a run resumes. verify_snapshot() loads the state as a resume does:
// the model is built from the scenario text stored in the snapshot (materials, walls, contact
// law: the state is checked against them), then load_snapshot() reads and checks every
// dataset and compares the state's hash with the recorded one.
#pragma once

#include <string>

namespace sable {

struct SnapshotIntegrity {
  bool verified = false;
  std::string problem;  // why not, when not verified (the message of the refusal)
};

// Throws InputError only when the header cannot be read (read_snapshot_info()); every later
// refusal is returned as the problem.
SnapshotIntegrity verify_snapshot(const std::string& path);

}  // namespace sable
