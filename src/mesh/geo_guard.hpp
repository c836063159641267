// The check of an untrusted .geo source before gmsh runs it. A .geo is a program: gmsh runs
// shell commands (SystemCall), reads and writes any file (Include, Merge, Save, Printf > f)
// and ends the process (Exit) on its say. A mesh file handed over by someone else must only
// build geometry and mesh it, so anything that reaches outside is refused before meshing
// (docs/reliability.md, "Untrusted meshes and surfaces"). No gmsh needed.
#pragma once

#include <string>
#include <vector>

namespace hs {

// Throws InputError "FILE: COMMAND: reason (line N)" when the .geo `file`, or a .geo it
// includes, runs a command (SystemCall, System, NonBlockingSystemCall, OnelabRun,
// OnelabAction, Exit, Abort), asks on standard input (GetValue, GetStringValue), writes or
// removes files (Save, Print, Printf > file, CreateDir,
// DeleteFile, RenameFile), sets an option that names a file or a program (an option name
// containing FileName or Executable, General.SaveOptions or SaveSession, any Solver.
// option), reads a file whose name is computed rather than written out, or names a file
// outside `allowed_dirs` and the .geo's own folder (any quoted text that reads as such a
// path: absolute, starting with '~', or climbing out with ".."). Files read by Include,
// Merge, ShapeFromFile and ListFromFile must lie in those folders; included .geo files are
// checked the same way.
void check_untrusted_geo(const std::string& file, const std::vector<std::string>& allowed_dirs);

}  // namespace hs
