// What `hydrosoft --version` prints: the version and git commit of this build and the
// versions of the libraries it runs with.
#pragma once

#include <string>

namespace hs {

std::string version_text();

}  // namespace hs
