// Lines and fields of a text file held in memory, for the .msh checks (msh_ascii_check.cpp):
// nothing is copied; a field is a view into the file.
#pragma once

#include <charconv>
#include <cstdint>
#include <string>
#include <string_view>

namespace hs::msh_text {

inline bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

inline std::string_view trim_end(std::string_view s) {
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

// A line as a message shows it: at most 60 characters, control and non-ASCII bytes as '?'
// (a message is one line of plain text).
inline std::string shown(std::string_view line) {
  std::string s(line.substr(0, 60));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  return "'" + s + (line.size() > 60 ? "...'" : "'");
}

// The whitespace-separated fields of one line.
class Fields {
 public:
  explicit Fields(std::string_view line) : s_(line) {}
  std::string_view next() {
    while (at_ < s_.size() && is_blank(s_[at_])) ++at_;
    const size_t start = at_;
    while (at_ < s_.size() && !is_blank(s_[at_])) ++at_;
    return s_.substr(start, at_ - start);
  }
  // What follows the fields taken so far, without the blanks around it.
  std::string_view rest() const {
    std::string_view r = trim_end(s_.substr(at_));
    while (!r.empty() && is_blank(r.front())) r.remove_prefix(1);
    return r;
  }
  size_t count() const {
    Fields all(s_);
    size_t n = 0;
    while (!all.next().empty()) ++n;
    return n;
  }

 private:
  std::string_view s_;
  size_t at_ = 0;
};

inline bool parse_integer(std::string_view t, int64_t& value) {
  const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), value);
  return !t.empty() && error == std::errc() && end == t.data() + t.size();
}

// What fscanf's %lf reads as a whole field: a sign, then a decimal or hexadecimal number,
// inf or nan; out of range (1e999) too, which the mesh checks refuse later naming the node.
inline bool is_real(std::string_view t) {
  if (!t.empty() && (t[0] == '+' || t[0] == '-')) t.remove_prefix(1);
  auto format = std::chars_format::general;
  if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
    t.remove_prefix(2);
    format = std::chars_format::hex;
  }
  if (t.empty() || t[0] == '+' || t[0] == '-') return false;
  double value = 0;
  const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), value, format);
  return end == t.data() + t.size() &&
         (error == std::errc() || error == std::errc::result_out_of_range);
}

// The lines of the file, one at a time, with their number.
class Lines {
 public:
  explicit Lines(std::string_view text) : d_(text) {}
  bool next() {
    if (next_ >= d_.size()) return false;
    const size_t nl = d_.find('\n', next_);
    const size_t end = nl == std::string_view::npos ? d_.size() : nl;
    line_ = d_.substr(next_, end - next_);
    if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
    next_ = end == d_.size() ? end : end + 1;
    ++number_;
    return true;
  }
  std::string_view line() const { return line_; }
  int64_t number() const { return number_; }
  int64_t left() const { return static_cast<int64_t>(d_.size() - next_); }
  int64_t size() const { return static_cast<int64_t>(d_.size()); }

 private:
  std::string_view d_, line_;
  size_t next_ = 0;
  int64_t number_ = 0;
};

}  // namespace hs::msh_text
