#include "text_reader.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace fluidweight::detail {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void TextReader::skip_space() {
  while (pos_ < text_.size()) {
    char c = text_[pos_];
    if (c == '\n') {
      ++line_;
      ++pos_;
    } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      ++pos_;
    } else if (c == '#' && hash_comments_) {
      while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    } else {
      return;
    }
  }
}

bool TextReader::at_end() {
  skip_space();
  return pos_ >= text_.size();
}

std::string TextReader::token() {
  skip_space();
  if (pos_ >= text_.size()) fail("unexpected end of file");
  size_t start = pos_;
  while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  return text_.substr(start, pos_ - start);
}

double TextReader::number(const char* what) {
  std::string t = token();
  char* end = nullptr;
  errno = 0;
  double v = std::strtod(t.c_str(), &end);
  if (end == t.c_str() || *end != '\0') {
    fail(std::string("expected a number (") + what + "), got '" + t + "'");
  }
  // NaN and inf parse, and so does a number beyond a double's range (as inf, with ERANGE).
  if (errno == ERANGE || !std::isfinite(v)) {
    fail(std::string("expected a finite number (") + what + "), got '" + t + "'");
  }
  return v;
}

void TextReader::check_count(long long count, long long min_bytes, const std::string& what) const {
  if (count < 0)
    fail("claims " + std::to_string(count) + " " + what + ": a count cannot be negative");
  const long long left = static_cast<long long>(text_.size() - pos_);
  if (count > left / min_bytes) {
    fail("claims " + std::to_string(count) + " " + what + ", more than the " +
         std::to_string(text_.size()) + "-byte file can hold (at most " +
         std::to_string(left / min_bytes) + " in the " + std::to_string(left) +
         " bytes after this line)");
  }
}

long long TextReader::integer(const char* what) {
  std::string t = token();
  char* end = nullptr;
  errno = 0;
  long long v = std::strtoll(t.c_str(), &end, 10);
  if (end == t.c_str() || *end != '\0' || errno == ERANGE) {
    fail(std::string("expected an integer (") + what + "), got '" + t + "'");
  }
  return v;
}

std::string TextReader::line() {
  size_t start = pos_;
  while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  std::string s = text_.substr(start, pos_ - start);
  if (pos_ < text_.size()) {
    ++pos_;
    ++line_;
  }
  if (!s.empty() && s.back() == '\r') s.pop_back();
  return s;
}

void TextReader::fail(const std::string& reason) const {
  throw InputError(path_ + ":" + std::to_string(line_) + ": " + reason);
}

}  // namespace fluidweight::detail
