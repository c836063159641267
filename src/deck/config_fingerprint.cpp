#include "deck/config_fingerprint.hpp"

#include <cstdint>
#include <cstdio>

#include "deck/deck.hpp"

namespace hs {

std::string config_fingerprint(const Config& config) {
  Config solved = config;
  solved.output = OutputConfig{};
  solved.deck_path.clear();
  solved.deck_name.clear();
  solved.mesh.file.clear();
  solved.mesh.deck_dir.clear();
  const std::string text = format_config(solved);
  uint64_t hash = 14695981039346656037ull;  // FNV-1a: stable across builds and machines
  for (unsigned char byte : text) {
    hash ^= byte;
    hash *= 1099511628211ull;
  }
  char digits[17];
  std::snprintf(digits, sizeof digits, "%016llx", static_cast<unsigned long long>(hash));
  return digits;
}

}  // namespace hs
