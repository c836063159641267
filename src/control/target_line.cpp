#include "control/target_line.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "common/deck_reader.hpp"
#include "common/error.hpp"

namespace hs {
namespace {

// A line quoted whole up to this length; longer ones by their first kQuotedStart characters.
constexpr std::size_t kQuotedWhole = 80, kQuotedStart = 40;

std::string g(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

// Whether a word is a finite number (then in x), the whole word read. strtod, not std::stod:
// stod throws on any ERANGE, which strtod also sets for an underflow (1e-320, a subnormal,
// or 1e-400, which rounds to 0), a finite number; an overflow gives +-HUGE_VAL, not finite.
bool finite_number(const std::string& word, double& x) {
  if (word.empty()) return false;
  char* end = nullptr;
  x = std::strtod(word.c_str(), &end);
  // A NUL ends strtod's reading: the word read whole is all of its bytes, NUL included.
  return end == word.c_str() + word.size() && std::isfinite(x);
}

}  // namespace

bool read_target_line(std::istream& in, std::size_t keep, std::string& kept, std::size_t& length) {
  using traits = std::char_traits<char>;
  kept.clear();
  length = 0;
  std::streambuf* buffer = in.rdbuf();
  bool read_any = false;
  char last = 0;
  for (traits::int_type c; buffer;) {
    c = buffer->sbumpc();
    if (traits::eq_int_type(c, traits::eof())) {
      in.setstate(std::ios::eofbit);
      break;
    }
    read_any = true;
    if (traits::to_char_type(c) == '\n') break;
    last = traits::to_char_type(c);
    if (kept.size() < keep) kept.push_back(last);
    ++length;
  }
  if (last == '\r') {  // a line ended by "\r\n"
    if (kept.size() == length) kept.pop_back();
    --length;
  }
  return read_any;
}

std::string quote_target_line(const std::string& kept, std::size_t length) {
  // Control bytes written out (a NUL as \x00): a message is a C string on its way to the
  // user (an exception's what()), which a NUL would cut, and one line on a terminal.
  if (length <= kQuotedWhole && kept.size() == length) return "'" + printable(kept) + "'";
  return "'" + printable(kept.substr(0, kQuotedStart)) + "...' (" + std::to_string(length) +
         " characters)";
}

TargetWords parse_target_words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  if (words.empty()) throw InputError("empty line (expected 'x y z' or 'effector x y z')");
  if (words.size() != 3 && words.size() != 4)
    throw InputError("expected 'x y z' or 'effector x y z', got " + std::to_string(words.size()) +
                     " words");
  TargetWords t;
  if (words.size() == 4) t.effector = words[0];
  for (int d = 0; d < 3; ++d) {
    const std::string& w = words[words.size() - 3 + d];
    if (!finite_number(w, t.position[d]))
      throw InputError("coordinate " + std::string(1, "xyz"[d]) + " " +
                       quote_target_line(w, w.size()) + " is not a finite number");
  }
  return t;
}

std::string target_reach_problem(const std::array<double, 3>& target,
                                 const std::array<double, 3>& low,
                                 const std::array<double, 3>& high) {
  std::array<double, 3> outside{};
  for (int d = 0; d < 3; ++d) outside[d] = std::max({low[d] - target[d], target[d] - high[d], 0.0});
  // hypot: no overflow, a target at 1e300 m is 1e300 m away, not infinitely far.
  const double distance = std::hypot(std::hypot(outside[0], outside[1]), outside[2]);
  const double size = std::hypot(std::hypot(high[0] - low[0], high[1] - low[1]), high[2] - low[2]);
  const double reach = kTargetReachInBodySizes * size;
  if (distance <= reach) return {};
  return "target (" + g(target[0]) + ", " + g(target[1]) + ", " + g(target[2]) + ") is " +
         g(distance) + " m from the body, farther than " + g(kTargetReachInBodySizes) +
         " times its size (" + g(size) + " m, the diagonal of its bounding box): no actuation " +
         "takes it there, and the controller's arithmetic does not hold that far";
}

}  // namespace hs
