// The check of an untrusted .geo source before gmsh runs it. A .geo is a program: gmsh runs
// shell commands (SystemCall), reads and writes any file (Include, Merge, Save, Printf > f)
// and ends the process (Exit) on its say. A mesh file handed over by someone else must only
// build geometry and mesh it, so anything that reaches outside is refused before meshing
// (docs/reliability.md, "Untrusted meshes and surfaces"). No gmsh needed.
#pragma once

#include <string>
#include <vector>

namespace hs {

// Throws InputError "FILE: COMMAND: reason (line N)" when the .geo `file`, or a file it reads,
// runs a command (SystemCall, System, NonBlockingSystemCall, OnelabRun, OnelabAction, Exit,
// Abort), asks on standard input (GetValue, GetStringValue), writes or removes files (Save,
// Print, Printf > file, CreateDir, DeleteFile, RenameFile), sets an option that names a file or
// a program (an option name containing FileName or Executable, General.SaveOptions or
// SaveSession, any Solver. option), reads a file whose name is computed rather than written
// out, or names a file outside `allowed_dirs` and the .geo's own folder (any quoted text that
// reads as such a path: absolute, starting with '~', or climbing out with "..").
// Files read by Include, Merge, Open, MergeWithBoundingBox, ShapeFromFile and ListFromFile must
// lie in those folders, and are checked as gmsh reads them: an Include as a script, whatever its
// name; a merged file by its extension, or by its first line when gmsh does not know the
// extension (a script, checked the same way; a mesh, checked by prescan_msh; a STEP, BREP or
// IGES file; anything else is refused, a .gz among them, which gmsh uncompresses with a shell
// command). The options file "<name>.opt" that gmsh merges unasked beside every file it merges
// (`file` itself included) is checked as a script.
void check_untrusted_geo(const std::string& file, const std::vector<std::string>& allowed_dirs);

// Throws InputError when gmsh would not read the .msh `file` as a mesh (gmsh runs a file whose
// first line does not begin a mesh section as a .geo script, whatever its name), or when the
// options file "<file>.opt" beside it fails the checks of check_untrusted_geo.
void check_untrusted_msh(const std::string& file, const std::vector<std::string>& allowed_dirs);

}  // namespace hs
