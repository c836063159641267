#include "common/key_table.hpp"

#include <cmath>

namespace hs {
namespace {

std::string with_note(const std::string& note) { return note.empty() ? "" : " (" + note + ")"; }

}  // namespace

std::string doc_number(double value) {
  if (value == std::floor(value) && std::abs(value) < 1e15)
    return std::to_string(static_cast<long long>(value));
  std::string text = format_number(value);
  if (const size_t plus = text.find("e+"); plus != std::string::npos) text.erase(plus + 1, 1);
  return text;
}

Limit at_least(double low, const std::string& note) {
  return {"≥ " + doc_number(low), [low, note](double x) {
            return x >= low ? std::string()
                            : "must be >= " + format_number(low) + with_note(note) + ", got " +
                                  format_number(x);
          }};
}

Limit above(double low, const std::string& note) {
  return {"> " + doc_number(low), [low, note](double x) {
            return x > low ? std::string()
                           : "must be > " + format_number(low) + with_note(note) + ", got " +
                                 format_number(x);
          }};
}

Limit within(double low, double high) {
  return {"in [" + doc_number(low) + ", " + doc_number(high) + "]", [low, high](double x) {
            if (x < low) return "must be >= " + format_number(low) + ", got " + format_number(x);
            if (x > high) return "must be <= " + format_number(high) + ", got " + format_number(x);
            return std::string();
          }};
}

Limit any_number() {
  return {"", [](double) { return std::string(); }};
}

}  // namespace hs
