// Command-line overrides of deck keys: "dotted.key=value", e.g. "mesh.order=2",
// "mesh.parameters.h=0.05", "materials[0].E=2e6", "loads.gravity=[0, 0, -9.81]".
#pragma once

#include <yaml-cpp/yaml.h>

#include <map>
#include <string>
#include <vector>

namespace hs {

// Sets each key of the deck's tree (before validation) to its value, read as YAML. Maps
// on the way are created when missing; list entries must exist. Returns, per key set, the
// override text, so that validation errors on those keys can name it. Throws InputError
// "FILE: override 'TEXT': reason" for a malformed override or one that does not fit the
// tree (an index past the end, a key below a number).
std::map<std::string, std::string> apply_overrides(YAML::Node& root,
                                                   const std::vector<std::string>& overrides,
                                                   const std::string& file);

}  // namespace hs
