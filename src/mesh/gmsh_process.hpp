// gmsh runs in a child process of its own, confined (common/confinement.hpp), for every mesh it
// reads or makes. A .geo is a program, and gmsh reads files a .geo only names (Merge, Include,
// <file>.opt beside every file it merges, ...): the checks before gmsh (geo_guard, msh_prescan)
// refuse what they can see, and the confinement holds for what they cannot. The child also
// keeps gmsh's crashes and hangs out of the run: a crash is an input error naming the file, and
// a SIGTERM or SIGINT to the run ends the meshing at once (docs/reliability.md).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace hs {

// Runs `work` (which drives gmsh and returns the mesh) in a child process and returns its mesh;
// the child is confined unless `confined` is false (a .geo the deck trusts: mesh.trust_geo).
// What `work` throws is thrown here: an InputError as InputError, anything else as
// std::runtime_error, with its message; an exception that escapes inside gmsh's parallel
// regions (std::terminate) is an InputError "FILE: gmsh: ...". A child that dies on a signal
// is an InputError naming `file` and the signal. When this process gets SIGTERM or SIGINT
// (common/interrupt.hpp) while the child works, the child is killed and Interrupted is thrown.
// The child reads nothing from standard input, prints nothing (its standard output and error
// go to /dev/null) and holds no descriptor of this process but those in `keep`.
struct GmshProcess {
  bool confined = true;
  std::vector<int> keep;
};
Mesh run_gmsh_process(const std::string& file, const std::function<Mesh()>& work,
                      const GmshProcess& how = {});

// A line for the run's standard error from inside `work` (a .geo's Printf, a warning on the
// mesh): the child sends it with its answer, and the parent writes it (control characters
// written out, at most kMaxRelayedLines lines) before it returns the mesh or throws, so that
// what a failing .geo printed shows too. Outside the child it is written at once.
void tell_user(const std::string& line);
constexpr size_t kMaxRelayedLines = 200;

}  // namespace hs
