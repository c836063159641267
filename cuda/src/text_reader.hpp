// Whitespace-separated tokens of a text file, with the line number for error messages.
#pragma once

#include <string>

#include "fluidweight/fluidweight.hpp"
#include "fluidweight/mesh_io.hpp"

namespace fluidweight::detail {

// Whole file as bytes (throws InputError when it cannot be read).
std::string read_file(const std::string& path);

// A token of the file as an error message quotes it: control and non-ASCII bytes written out
// (\x1c), so that a hostile file cannot split or overwrite the message's line, and at most
// 40 characters of a long token.
std::string quoted(const std::string& token);

// The coordinate `token` spells in `value`; else why it is none ("" when it is one). The whole
// token must be the number (a NUL inside it ends nothing), finite and within kMaxCoordinate.
std::string coordinate_problem(const std::string& token, double& value);

class TextReader {
 public:
  TextReader(const std::string& path, std::string text) : path_(path), text_(std::move(text)) {}

  bool at_end();                        // only whitespace (and '#' comments if enabled) remains
  std::string token();                  // next token; error at the end of the file
  double coordinate(const char* what);  // see coordinate_problem
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
