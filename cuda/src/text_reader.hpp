// Whitespace-separated tokens of a text file, with the line number for error messages.
#pragma once

#include <string>

#include "fluidweight/fluidweight.hpp"

namespace fluidweight::detail {

// Whole file as bytes (throws InputError when it cannot be read).
std::string read_file(const std::string& path);

class TextReader {
 public:
  TextReader(const std::string& path, std::string text) : path_(path), text_(std::move(text)) {}

  bool at_end();                    // only whitespace (and '#' comments if enabled) remains
  std::string token();              // next token; error at the end of the file
  double number(const char* what);  // finite: NaN, inf and overflowing values are refused
  long long integer(const char* what);
  // A count just read, of items that take at least `min_bytes` each in the file: refused
  // when negative or when the rest of the file cannot hold that many, so that nothing is
  // allocated for a count the file does not back (a 330-byte file claimed 2^31 nodes).
  void check_count(long long count, long long min_bytes, const std::string& what) const;
  // Rest of the current line (without the newline); moves to the next line.
  std::string line();
  int line_number() const { return line_; }
  [[noreturn]] void fail(const std::string& reason) const;
  void set_comments(bool hash_comments) { hash_comments_ = hash_comments; }

 private:
  void skip_space();
  std::string path_;
  std::string text_;
  size_t pos_ = 0;
  int line_ = 1;
  bool hash_comments_ = false;
};

}  // namespace fluidweight::detail
