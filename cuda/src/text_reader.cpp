#include "text_reader.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
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

std::string quoted(const std::string& token) {
  constexpr size_t kShown = 40;
  std::string out = "'";
  for (size_t k = 0; k < token.size() && k < kShown; ++k) {
    unsigned char c = static_cast<unsigned char>(token[k]);
    if (c < 0x20 || c >= 0x7f || c == '\\') {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  out += "'";
  if (token.size() > kShown) out += " (" + std::to_string(token.size()) + " characters)";
  return out;
}

std::string coordinate_problem(const std::string& token, double& value) {
  char* end = nullptr;
  errno = 0;
  value = std::strtod(token.c_str(), &end);
  // strtod stops at a NUL: "0.3\0" "9" would read as 0.3 without this comparison.
  if (end == token.c_str() || end != token.c_str() + token.size()) return "is not a number";
  // NaN and inf parse, and so does a number beyond a double's range (as inf, with ERANGE).
  if (errno == ERANGE && std::fabs(value) > 1.0) return "is not a finite number";
  if (!std::isfinite(value)) return "is not a finite number";
  if (std::fabs(value) > kMaxCoordinate) {
    return "is beyond 1e30 in magnitude (the volume and the weight would overflow)";
  }
  return "";
}

double TextReader::coordinate(const char* what) {
  std::string t = token();
  double v = 0;
  std::string problem = coordinate_problem(t, v);
  if (!problem.empty()) fail(std::string(what) + " " + quoted(t) + " " + problem);
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
  if (end == t.c_str() || end != t.c_str() + t.size() || errno == ERANGE) {
    fail(std::string("expected an integer (") + what + "), got " + quoted(t));
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
