// Plain values the scenario's data types share with the layers below the scenario: a 3-vector
// whatever the dimension (2D pads z = 0), and where in an input file a value came from.
#pragma once

#include <array>
#include <string>

namespace sable {

using Vec3a = std::array<double, 3>;

// Where a value came from, for messages raised after parsing ("pour.toml:12:3: ...").
struct SourceLoc {
  std::string file;
  int line = 0;
  int column = 0;
  std::string str() const {
    return line > 0 ? file + ":" + std::to_string(line) + ":" + std::to_string(column) : file;
  }
};

}  // namespace sable
