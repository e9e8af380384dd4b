// The [contact] and [cd] tables of a scenario (parse.cpp reads the rest). The contact law's
// names are the registry's (contact/registry.hpp).
#pragma once

#include <string>

#include "sable/scenario/config.hpp"
#include "sable/scenario/toml_reader.hpp"

namespace sable::detail {

ContactConfig parse_contact(const Table& root);
CdConfig parse_cd(const Table& root, const std::string& solver);

}  // namespace sable::detail
