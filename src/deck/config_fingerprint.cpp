#include "deck/config_fingerprint.hpp"

#include <cstdint>
#include <cstdio>
#include <filesystem>

#include "deck/deck.hpp"

namespace hs {

std::string config_fingerprint(const Config& config) {
  Config solved = config;
  solved.output = OutputConfig{};
  solved.deck_path.clear();
  solved.deck_name.clear();
  // The file by its name alone: the same mesh reached by another path is the same problem.
  solved.mesh.file = std::filesystem::path(solved.mesh.file).filename().string();
  solved.mesh.deck_dir.clear();
  for (auto& o : solved.obstacles)  // a surface obstacle's file likewise
    if (!o.file.empty()) o.file = std::filesystem::path(o.file).filename().string();
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
