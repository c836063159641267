// OutputFolder: results are written to "<folder>.partial" and replace <folder> only when
// the run succeeds; a run that fails after some steps keeps them in "<folder>.failed". Replacing
// means deleting, so a folder is only ever deleted when it carries the marker file that hydrosoft
// writes into every output folder (or is empty): a mistyped output.folder cannot wipe out a user's
// own files. The folder is locked for the object's life (FolderLock), so that a second run on the
// same folder stops at once instead of deleting this run's staging folder.
#include <fcntl.h>   // AT_FDCWD
#include <limits.h>  // NAME_MAX, PATH_MAX
#include <stdio.h>   // renameat2, RENAME_EXCHANGE

#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "common/error.hpp"
#include "io/atomic_file.hpp"
#include "io/output.hpp"

namespace hs {
namespace {

namespace fs = std::filesystem;

const char* kMarker = ".hydrosoft_output";

// The names beside <folder> that a run on it uses.
const char* const kFamily[] = {".partial", ".failed", ".old", ".lock"};

std::string what_suffix(const std::string& suffix) {
  if (suffix == ".partial") return "staging folder";
  if (suffix == ".failed") return "kept failed run";
  if (suffix == ".old") return "earlier results, while they are replaced,";
  return "lock file";
}

void require_usable(const std::string& folder) {
  const std::string problem = output_folder_problem(folder);
  if (!problem.empty()) throw InputError("output folder '" + folder + "': " + problem);
}

}  // namespace

std::string output_folder_problem(const std::string& folder) {
  fs::path path = fs::path(folder).lexically_normal();
  if (!path.has_filename()) path = path.parent_path();  // "out/run/" -> "out/run"
  const std::string name = path.filename().string();
  if (name.empty() || name == "." || name == "..") return "must name a folder (not . or ..)";
  // The names of a run's other folders and its lock: a run on one of them would delete or
  // replace the files of a run on the folder they belong to (its staging folder, at once;
  // its kept failure or its results, later), and the reverse.
  for (const std::string suffix : kFamily) {
    if (name.size() <= suffix.size() ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string head =
        (path.parent_path() / name.substr(0, name.size() - suffix.size())).string();
    return "a name ending in '" + suffix + "' is that of the " + what_suffix(suffix) + " of '" +
           head + "' (a run on '" + head + "' would delete or replace it): choose a name " +
           "without .partial, .failed, .old or .lock at its end";
  }
  // The longest names a run makes: "<folder>.partial" in the parent folder, and within it
  // "<deck>.xmf.tmp" (a deck's name is at most NAME_MAX characters long).
  if (name.size() + std::strlen(".partial") > NAME_MAX)
    return "the folder's name is " + std::to_string(name.size()) + " characters long: with " +
           "'.partial' added it would exceed the " + std::to_string(NAME_MAX) +
           " characters a name may have (File name too long)";
  if (path.string().size() + std::strlen(".partial/") + NAME_MAX + std::strlen(".xmf.tmp") >=
      PATH_MAX)
    return "the path is " + std::to_string(path.string().size()) + " characters long: with " +
           "the files a run writes in it, it could exceed the " + std::to_string(PATH_MAX) +
           " characters a path may have (File name too long)";
  for (const std::string suffix : {"", ".partial", ".old", ".failed", ".lock"}) {
    const fs::path p = path.string() + suffix;
    std::error_code error;
    const fs::file_status status = fs::symlink_status(p, error);
    if (error && error != std::errc::no_such_file_or_directory)
      return "'" + p.string() + "' cannot be examined: " + error.message();
    if (!fs::exists(status)) continue;
    if (fs::is_symlink(status)) {
      if (suffix.empty())
        return "'" + p.string() + "' is a symbolic link (to '" +
               fs::read_symlink(p, error).string() +
               "'): a run replaces its output folder by renaming another over it, which would " +
               "replace the link and leave the folder it names as it was; give that folder " +
               "as output.folder (or link the folder above it)";
      return "'" + p.string() + "' is a symbolic link: a run " +
             (suffix == ".lock"
                  ? std::string("writes into its lock file")
                  : "deletes, renames and writes its folder " + p.filename().string()) +
             " without following links: remove the link";
    }
    if (suffix == ".lock") {
      if (!fs::is_regular_file(status)) return "'" + p.string() + "' exists and is not a file";
      continue;
    }
    if (!fs::is_directory(status)) return "'" + p.string() + "' exists and is not a folder";
    const bool empty = fs::is_empty(p, error);
    if (!error && !empty && !fs::exists(p / kMarker, error))
      return "'" + p.string() + "' exists and was not written by hydrosoft (which replaces its " +
             "output folders): move it away or choose another folder";
    if (error) return "'" + p.string() + "' cannot be examined: " + error.message();
  }
  return {};
}

OutputFolder::OutputFolder(std::string folder) {
  require_usable(folder);
  fs::path path = fs::path(folder).lexically_normal();
  if (!path.has_filename()) path = path.parent_path();
  final_ = path.string();
  staging_ = final_ + ".partial";
  std::error_code error;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), error);
  if (error)
    throw InputError("output folder '" + final_ + "': cannot create the folder '" +
                     path.parent_path().string() + "': " + error.message());
  lock_ = std::make_unique<FolderLock>(final_);  // before anything is deleted
  require_usable(final_);           // again under the lock: another run may have changed it
  fs::remove_all(staging_, error);  // a crashed run's leftovers (no other run holds the lock)
  if (!error) fs::create_directories(staging_, error);
  if (error)
    throw InputError("output folder '" + final_ + "': cannot make its staging folder '" + staging_ +
                     "': " + error.message());
  try {
    write_file_atomically(staging_ + "/" + kMarker,
                          "Written by hydrosoft. The next run with this output folder replaces "
                          "the folder.\n");
  } catch (const std::exception& e) {
    fs::remove_all(staging_, error);
    throw InputError("output folder '" + final_ + "': " + e.what());
  }
}

OutputFolder::~OutputFolder() {
  // The lock (member lock_) is released after this body, once nothing is left to delete.
  if (committed_ || kept_) return;
  std::error_code ignored;
  fs::remove_all(staging_, ignored);
}

void OutputFolder::commit() {
  if (committed_ || kept_) throw std::logic_error("OutputFolder::commit after commit or keep");
  require_usable(final_);  // checked at construction; the folder may have changed since
  const bool had_old = fs::exists(final_);
  // One atomic exchange of the two folders: a kill at any moment leaves either the old
  // results or the new ones at <folder>, never neither. The staging name then holds the old
  // results, deleted here or, after a kill, by the next run on the folder.
  if (had_old &&
      renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, final_.c_str(), RENAME_EXCHANGE) == 0) {
    committed_ = true;
    std::error_code ignored;  // committed: what is left is deleted by the next run
    fs::remove_all(staging_, ignored);
    return;
  }
  // No exchange (none to make, or a file system without it): move the old results aside
  // first, so that they come back if the rename fails.
  const fs::path old = final_ + ".old";
  if (had_old) {
    fs::remove_all(old);
    fs::rename(final_, old);
  }
  try {
    fs::rename(staging_, final_);
  } catch (const fs::filesystem_error&) {
    if (had_old) fs::rename(old, final_);
    throw;
  }
  committed_ = true;
  std::error_code ignored;
  if (had_old) fs::remove_all(old, ignored);
}

std::string OutputFolder::keep_failed() {
  if (committed_ || kept_) throw std::logic_error("OutputFolder::keep_failed after commit or keep");
  // Only "<folder>.failed" is replaced: the results of an earlier good run stay in <folder>.
  const std::string failed = final_ + ".failed";
  require_usable(final_);  // .failed, if it exists, is an earlier run's (marked) folder
  fs::remove_all(failed);
  fs::rename(staging_, failed);
  kept_ = true;
  return failed;
}

}  // namespace hs
