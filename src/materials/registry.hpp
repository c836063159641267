// The material laws, by name: the one list of them (registry.cpp) and their construction from
// a material's YAML map. Adding a law: its own .hpp/.cpp (a MaterialLaw with a static kName,
// its Parameters, their key table keys(), make() and parameters()) and one line in
// registry.cpp's list.
#pragma once

#include <yaml-cpp/yaml.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/deck_reader.hpp"
#include "materials/law_keys.hpp"
#include "materials/material.hpp"

namespace hs {

// A key of a law as the docs show it.
struct MaterialLawKey {
  std::string name, type, default_value, meaning;
  bool operator==(const MaterialLawKey& o) const {
    return name == o.name && type == o.type && default_value == o.default_value &&
           meaning == o.meaning;
  }
};

// What the registry knows of a law, all of it from the law's class: its name, its key table
// (Law::keys(), over Law::Parameters), the law made from the keys read (Law::make, which
// checks what involves several keys) and the keys of a law made (Law::parameters()).
struct MaterialLawEntry {
  std::string name;                  // the deck's model name
  std::vector<MaterialLawKey> keys;  // the keys of its map (beside those the caller reads)
  // The law from its map at `key` (keys already checked); throws through r.fail.
  std::shared_ptr<const MaterialLaw> (*parse)(const DeckReader& r, const YAML::Node& node,
                                              const std::string& key);
  // Writes the keys of `law` (a law of this entry) as `key: value` pairs.
  void (*print)(YAML::Emitter& out, const MaterialLaw& law);
};

template <class Law>
MaterialLawEntry registry_entry() {
  std::vector<MaterialLawKey> keys;
  for (const auto& k : Law::keys()) keys.push_back({k.name, k.type, k.default_value, k.meaning});
  return {Law::kName, keys,
          [](const DeckReader& r, const YAML::Node& node, const std::string& key) {
            typename Law::Parameters read{};
            read_law_keys(r, node, key, Law::keys(), read);
            return Law::make(r, node, key, read);
          },
          [](YAML::Emitter& out, const MaterialLaw& law) {
            write_law_keys(out, Law::keys(), dynamic_cast<const Law&>(law).parameters());
          }};
}

// The registered laws' names, in the registry's order.
std::vector<std::string> material_law_names();
// Every key some law reads, each once, in the registry's order.
std::vector<std::string> material_law_keys();
// The laws that read the key `name`, in the registry's order.
std::vector<std::string> material_laws_reading(const std::string& name);

// The law `model` from the material's map `node` at `key`, whose keys `caller_keys` (e.g.
// group, model, density) the caller reads. Fails through r.fail, as "FILE: KEY: reason", on
// an unknown model (listing the registered names), on a key of another law ("only used by
// model ..."), on an unknown key, and on the law's own checks.
std::shared_ptr<const MaterialLaw> parse_material_law(const DeckReader& r, const YAML::Node& node,
                                                      const std::string& key,
                                                      const std::string& model,
                                                      const std::vector<std::string>& caller_keys);

// The keys of `law` as `key: value` pairs, into a map the caller has begun: what its model's
// key table prints (they read back as the same law).
void print_material_law(YAML::Emitter& out, const MaterialLaw& law);

// The docs' table of every law's keys: | key | models | type | default | meaning |, one row
// per declaration (a key declared alike by several laws is one row naming them).
std::string material_laws_markdown();

// The same from numbers (tests, benchmarks), e.g. make_material_law("gent", {{"E", 1e6},
// {"nu", 0.45}, {"Jm", 20}}); throws InputError.
std::shared_ptr<const MaterialLaw> make_material_law(
    const std::string& model, const std::map<std::string, double>& parameters);

}  // namespace hs
