// Writing a whole file so that a reader sees either the old or the new content, never a
// half-written one: the text goes to "<path>.tmp", which is then renamed over <path>
// (rename is atomic within one file system).
#pragma once

#include <string>

namespace hs {

// A file's new content written beside it ("<path>.tmp") and put in its place by commit(): a
// caller that writes other files too stages this one first, so that a full disk stops it
// before anything is written, and commits it last. The .tmp is removed unless committed.
class StagedFile {
 public:
  // Throws std::runtime_error naming the file and the system's reason ("No space left on
  // device") if it cannot be written; the .tmp is then removed and <path> left as it was.
  StagedFile(std::string path, const std::string& text);
  ~StagedFile();
  StagedFile(const StagedFile&) = delete;
  StagedFile& operator=(const StagedFile&) = delete;
  // Throws std::runtime_error naming the file if the rename fails (<path> is then unchanged).
  void commit();

 private:
  std::string path_, tmp_;
  bool committed_ = false;
};

// A StagedFile committed at once.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace hs
