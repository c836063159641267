// An exclusive lock on an output folder for the length of a run, so that two runs never
// stage, replace or delete the same folder at once (each would delete the other's
// "<folder>.partial", and one would report success with files the other half-wrote).
//
// The lock is flock(2) on the file "<folder>.lock" beside the folder. The kernel releases it
// when the process ends, however it ends, so the lock of a killed run never blocks the next
// one. The file is removed on release; a killed run leaves it behind, which is harmless:
// only the flock counts, and the next run takes it over.
#pragma once

#include <string>

namespace hs {

class FolderLock {
 public:
  // Takes the lock of `folder` (a normalised path; its parent folder must exist) at once,
  // without waiting. Throws InputError naming the folder when another process holds it
  // ("another run is writing it", with that process's id and host when it wrote them), or
  // when the lock file cannot be created or locked (with the system's reason).
  explicit FolderLock(const std::string& folder);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

  const std::string& path() const { return path_; }  // the lock file

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace hs
