// Writing a whole file so that a reader sees either the old or the new content, never a
// half-written one: the text goes to "<path>.tmp", which is then renamed over <path>
// (rename is atomic within one file system).
#pragma once

#include <string>

namespace hs {

// Throws std::runtime_error naming the file and the system's reason ("No space left on
// device") if it cannot be written; the .tmp is then removed and <path> left as it was.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace hs
