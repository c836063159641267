#include "materials/law_keys.hpp"

namespace hs {

const Config& no_sections() {
  static const Config none{};
  return none;
}

}  // namespace hs
