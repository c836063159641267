// OutputFolder: results are written to "<folder>.partial" and replace <folder> only when
// the run succeeds; a run that fails after some steps keeps them in "<folder>.failed". Replacing
// means deleting, so a folder is only ever deleted when it carries the marker file that hydrosoft
// writes into every output folder (or is empty): a mistyped output.folder cannot wipe out a user's
// own files. The folder is locked for the object's life (FolderLock), so that a second run on the
// same folder stops at once instead of deleting this run's staging folder.
#include <fcntl.h>  // AT_FDCWD
#include <stdio.h>  // renameat2, RENAME_EXCHANGE

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "common/error.hpp"
#include "io/output.hpp"

namespace hs {
namespace {

namespace fs = std::filesystem;

const char* kMarker = ".hydrosoft_output";

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
  for (const fs::path& p :
       {path, fs::path(path.string() + ".partial"), fs::path(path.string() + ".old"),
        fs::path(path.string() + ".failed")}) {
    if (!fs::exists(p)) continue;
    if (!fs::is_directory(p)) return "'" + p.string() + "' exists and is not a folder";
    if (!fs::is_empty(p) && !fs::exists(p / kMarker))
      return "'" + p.string() + "' exists and was not written by hydrosoft (which replaces its " +
             "output folders): move it away or choose another folder";
  }
  return {};
}

OutputFolder::OutputFolder(std::string folder) {
  require_usable(folder);
  fs::path path = fs::path(folder).lexically_normal();
  if (!path.has_filename()) path = path.parent_path();
  final_ = path.string();
  staging_ = final_ + ".partial";
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  lock_ = std::make_unique<FolderLock>(final_);  // before anything is deleted
  fs::remove_all(staging_);  // a crashed run's leftovers (no other run holds the lock)
  fs::create_directories(staging_);
  std::ofstream(fs::path(staging_) / kMarker)
      << "Written by hydrosoft. The next run with this output folder replaces the folder.\n";
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
    fs::remove_all(staging_);
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
  if (had_old) fs::remove_all(old);
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
