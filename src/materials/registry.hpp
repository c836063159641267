// The material laws, by name: the one list of them (registry.cpp) and their construction from
// a material's YAML map. Adding a law: its own .hpp/.cpp (a MaterialLaw with a static kName,
// keys() and parse) and one line in registry.cpp's list.
#pragma once

#include <yaml-cpp/yaml.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/deck_reader.hpp"
#include "materials/material.hpp"

namespace hs {

// What the registry knows of a law.
struct MaterialLawEntry {
  std::string name;               // the deck's model name
  std::vector<std::string> keys;  // the keys of its map (beside those the caller reads)
  // The law from its map at `key` (keys already checked); throws through r.fail.
  std::shared_ptr<const MaterialLaw> (*parse)(const DeckReader& r, const YAML::Node& node,
                                              const std::string& key);
};

template <class Law>
MaterialLawEntry registry_entry() {
  return {Law::kName, Law::keys(), &Law::parse};
}

// The registered laws' names, in the registry's order.
std::vector<std::string> material_law_names();
// Every key some law reads, each once, in the registry's order.
std::vector<std::string> material_law_keys();

// The law `model` from the material's map `node` at `key`, whose keys `caller_keys` (e.g.
// group, model, density) the caller reads. Fails through r.fail, as "FILE: KEY: reason", on
// an unknown model (listing the registered names), on a key of another law ("only used by
// model ..."), on an unknown key, and on the law's own checks.
std::shared_ptr<const MaterialLaw> parse_material_law(const DeckReader& r, const YAML::Node& node,
                                                      const std::string& key,
                                                      const std::string& model,
                                                      const std::vector<std::string>& caller_keys);

// The same from numbers (tests, benchmarks), e.g. make_material_law("gent", {{"E", 1e6},
// {"nu", 0.45}, {"Jm", 20}}); throws InputError.
std::shared_ptr<const MaterialLaw> make_material_law(
    const std::string& model, const std::map<std::string, double>& parameters);

}  // namespace hs
