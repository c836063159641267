// write_json: summary.json and the like. JSON has no NaN or infinity (nlohmann would
// write null), so a non-finite number is refused with the key path that holds it.
#include <cmath>

#include "common/error.hpp"
#include "io/atomic_file.hpp"
#include "io/output.hpp"

namespace hs {
namespace {

// Throws SolveError for the first non-finite number below `j`; `key` is its dotted path.
void require_finite(const nlohmann::json& j, const std::string& key, const std::string& path) {
  if (j.is_number_float() && !std::isfinite(j.get<double>()))
    throw SolveError(path + ": " + (key.empty() ? "the value" : key) + " is not finite (" +
                     std::to_string(j.get<double>()) + "); not written");
  if (j.is_object())
    for (const auto& [name, value] : j.items())
      require_finite(value, key.empty() ? name : key + "." + name, path);
  if (j.is_array())
    for (size_t i = 0; i < j.size(); ++i)
      require_finite(j[i], key + "[" + std::to_string(i) + "]", path);
}

}  // namespace

void write_json(const std::string& path, const nlohmann::json& j) {
  require_finite(j, "", path);
  write_file_atomically(path, j.dump(2) + "\n");
}

}  // namespace hs
