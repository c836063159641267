// One line of the interactive mode (`hydrosoft DECK --targets -`, docs/control.md): reading
// it with a bound on what is kept, its words as a target, and whether a target is one the
// controller can answer. Text and arithmetic only, no PETSc: solvers/control_run.cpp checks
// the effector's name and answers the line.
#pragma once

#include <array>
#include <cstddef>
#include <istream>
#include <string>

namespace hs {

// A line keeps at most this many characters: a target line is far shorter, and a client's
// runaway line must not make the controller's memory grow without bound.
inline constexpr std::size_t kTargetLineKept = 4096;

// Reads the next line of `in` up to '\n' (dropped, with a '\r' before it), keeping its first
// `keep` characters in `kept` and counting all of them in `length`. False at the end of the
// input with nothing read; a last line without '\n' is still a line.
bool read_target_line(std::istream& in, std::size_t keep, std::string& kept, std::size_t& length);

// The line as a message quotes it: whole when short, else its start, "...", and its length,
// so that a 1 MB line gives a message of one short line; control bytes written out (\x00).
std::string quote_target_line(const std::string& kept, std::size_t length);

struct TargetWords {
  std::string effector;  // empty: the first effector ("x y z")
  std::array<double, 3> position{};
};

// "x y z" or "effector x y z", each coordinate a finite number (m; a subnormal such as 1e-320
// is one). Throws InputError with the reason alone (the caller names the line): an empty line,
// a wrong count of words, a word that is not a finite number.
TargetWords parse_target_words(const std::string& line);

// How far the controller answers: a target farther from the body than this many body sizes
// (the diagonal of its bounding box) is refused. No actuation takes a soft robot there, and
// the QP's bounds hold only to about 1e-16 of the distance to the target divided by the
// motion of one step: at 1000 sizes, to 1e-7 of a step even when a step moves the effector by
// a millionth of the body (a target 1e12 m from the 9 cm finger broke its 0..30 kPa bounds by
// 240 Pa; 1e300 m gave an error that is not a number).
inline constexpr double kTargetReachInBodySizes = 1000;

// Why `target` is too far from the body with bounding box [low, high] (docs above), or "".
std::string target_reach_problem(const std::array<double, 3>& target,
                                 const std::array<double, 3>& low,
                                 const std::array<double, 3>& high);

}  // namespace hs
