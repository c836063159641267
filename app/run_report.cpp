#include "run_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

namespace hs {
namespace {

using Json = nlohmann::json;

// A minus sign before digits that are all zero ("-0.000" for -4.5e-13 Pa in kPa) says nothing.
std::string format(const char* spec, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, spec, v);
  std::string s = buffer;
  const std::string mantissa = s.substr(0, s.find_first_of("eE"));
  if (!s.empty() && s[0] == '-' && mantissa.find_first_of("123456789") == std::string::npos)
    s.erase(0, 1);
  return s;
}

// A value within 1e-10 of its column's largest magnitude is round-off of zero (a cavity let
// down to 0 Pa ends at -4.5e-13 Pa beside 2e4 Pa) and printed as 0 in the column's format.
std::string cell(const char* spec, double v, double column_scale) {
  return std::abs(v) <= 1e-10 * column_scale ? format(spec, 0.0) : format(spec, v);
}

double number(const Json& j, const char* key, double fallback = 0) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : fallback;
}

std::string millimetres(const Json& point) {
  std::string s;
  for (const auto& c : point) s += (s.empty() ? "" : ", ") + format("%.2f", 1e3 * c.get<double>());
  return s;
}

// A contact force (N), marked as such in a column of millimetres.
std::string newtons(const Json& force) {
  std::string s;
  for (const auto& c : force) s += (s.empty() ? "" : ", ") + format("%.4g", c.get<double>());
  return s + " N";
}

// Rows of cells, each column padded to its widest cell, two spaces apart.
std::string table(const std::vector<std::vector<std::string>>& rows) {
  std::vector<size_t> width;
  for (const auto& row : rows)
    for (size_t k = 0; k < row.size(); ++k) {
      if (width.size() <= k) width.push_back(0);
      width[k] = std::max(width[k], row[k].size());
    }
  std::ostringstream out;
  for (const auto& row : rows) {
    std::string line = " ";
    for (size_t k = 0; k < row.size(); ++k)
      line += " " + row[k] + std::string(width[k] - row[k].size() + 1, ' ');
    out << line.substr(0, line.find_last_not_of(' ') + 1) << "\n";
  }
  return out.str();
}

// The tip face's inclination below the plane normal to gravity, its rotation since the
// undeformed mesh and how far its centroid moved (summary.json's per-state `tip`), or "-"
// without a tip.
std::vector<std::string> tip_cells(const Json& state) {
  if (!state.contains("tip") || !state["tip"].is_object()) return {"-", "-", "-"};
  const Json& tip = state["tip"];
  return {format("%.2f", number(tip, "inclination_deg")),
          format("%.2f", number(tip, "rotation_deg")),
          tip.contains("displacement_magnitude_m")
              ? format("%.3f", 1e3 * number(tip, "displacement_magnitude_m"))
              : "-"};
}

std::string states_table(const Json& states) {
  double largest_pressure = 0;
  for (const auto& s : states)
    for (const auto& c : s.value("cavities", Json::array()))
      largest_pressure = std::max(largest_pressure, std::abs(number(c, "pressure")));
  std::vector<std::vector<std::string>> rows = {{"state", "tip inclination (deg)",
                                                 "tip rotation (deg)", "tip displacement (mm)",
                                                 "cavity", "p (kPa)", "V (ml)", "added (ml)"}};
  for (const auto& s : states) {
    const auto tip = tip_cells(s);
    bool first = true;
    for (const auto& c : s.value("cavities", Json::array())) {
      rows.push_back({first ? s.value("name", "") : "", first ? tip[0] : "", first ? tip[1] : "",
                      first ? tip[2] : "", c.value("name", ""),
                      cell("%.3f", 1e-3 * number(c, "pressure"), 1e-3 * largest_pressure),
                      format("%.3f", number(c, "volume_ml")),
                      format("%.3f", number(c, "added_volume_ml"))});
      first = false;
    }
    if (first) rows.push_back({s.value("name", ""), tip[0], tip[1], tip[2], "-", "-", "-", "-"});
  }
  return table(rows);
}

// Per state and cable: its tension and how far it was pulled since the end of the first state.
std::string cables_table(const Json& states) {
  std::vector<std::vector<std::string>> rows = {{"state", "cable", "force (N)", "pull (mm)"}};
  double largest_force = 0;
  for (const auto& s : states)
    for (const auto& c : s.value("cables", Json::array()))
      largest_force = std::max(largest_force, std::abs(number(c, "force")));
  for (const auto& s : states)
    for (const auto& c : s.value("cables", Json::array()))
      rows.push_back({s.value("name", ""), c.value("name", ""),
                      cell("%.4g", number(c, "force"), largest_force),
                      format("%.3f", 1e3 * number(c, "pull"))});
  return rows.size() > 1 ? table(rows) : "";
}

std::string targets_table(const Json& targets) {
  std::vector<std::vector<std::string>> rows = {
      {"target (mm)", "reached (mm)", "error (mm)", "actuation (Pa or N)"}};
  // A contact-force effector's rows are forces, marked N.
  for (const auto& t : targets)
    if (t.contains("error_N")) {
      rows[0] = {"target (mm or N)", "reached (mm or N)", "error (mm or N)", "actuation (Pa or N)"};
      break;
    }
  // Each actuator's scale over the targets: pressures (Pa) and forces (N) share the column.
  std::vector<double> largest;
  for (const auto& t : targets) {
    size_t k = 0;
    for (const auto& a : t.value("actuation", Json::array())) {
      if (largest.size() <= k) largest.push_back(0);
      largest[k] = std::max(largest[k], std::abs(a.get<double>()));
      ++k;
    }
  }
  for (const auto& t : targets) {
    std::string actuation;
    size_t k = 0;
    for (const auto& a : t.value("actuation", Json::array()))
      actuation += (actuation.empty() ? "" : ", ") + cell("%.4g", a.get<double>(), largest[k++]);
    if (t.contains("error_N")) {
      rows.push_back({newtons(t.value("target", Json::array())),
                      newtons(t.value("reached", Json::array())),
                      t["error_N"].is_number() ? format("%.3g N", t["error_N"].get<double>()) : "-",
                      actuation});
      continue;
    }
    rows.push_back(
        {millimetres(t.value("target", Json::array())),
         millimetres(t.value("reached", Json::array())),
         t["error_m"].is_number() ? format("%.3f", 1e3 * t["error_m"].get<double>()) : "-",
         actuation});
  }
  return table(rows);
}

// The force each boundary group's constraint exerts on the body at the end of the run, its
// components round-off of zero against the largest of the table printed as 0.
std::string reactions_table(const Json& reactions) {
  std::vector<std::vector<std::string>> rows = {
      {"boundary group", "reaction x (N)", "reaction y (N)", "reaction z (N)"}};
  double largest = 0;
  for (const auto& [group, force] : reactions.items())
    for (const auto& c : force) largest = std::max(largest, std::abs(c.get<double>()));
  for (const auto& [group, force] : reactions.items()) {
    std::vector<std::string> row = {group};
    for (const auto& c : force) {
      const double value = c.get<double>();
      row.push_back(cell("%.6g", value, largest));
    }
    rows.push_back(row);
  }
  return rows.size() > 1 ? table(rows) : "";
}

// The scalars of a map, one "key value" line each.
std::string scalars(const Json& map) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& [key, value] : map.items())
    if (value.is_number()) rows.push_back({key, format("%.6g", value.get<double>())});
  return table(rows);
}

}  // namespace

std::string run_report(const Json& summary) {
  std::ostringstream out;
  const Json time = summary.value("time_s", Json::object());
  const bool control = summary.contains("targets") && !summary["targets"].empty();
  out << "# hydrosoft: done: ";
  if (control)  // its steps and Newton iterations count the loading before the control only
    out << summary["targets"].size() << " targets, ";
  else {
    out << summary.value("steps", 0) << " steps, ";
    // The steps count the sub-steps of cut-back steps: the cutbacks say why they exceed the plan.
    if (summary.value("cutbacks", 0) > 0) out << summary.value("cutbacks", 0) << " cutbacks, ";
    out << summary.value("newton_iterations", 0) << " Newton iterations, ";
  }
  out << format("%.2f", number(time, "total")) << " s on " << summary.value("ranks", 1)
      << (summary.value("ranks", 1) == 1 ? " rank\n" : " ranks\n");
  const Json output = summary.value("output", Json::object());
  if (output.contains("xdmf"))
    out << "# results: " << output["xdmf"].get<std::string>()
        << " (ParaView); summary.json and history.csv beside it\n";
  if (control)
    out << targets_table(summary["targets"]);
  else if (summary.contains("states") && !summary["states"].empty())
    out << states_table(summary["states"]) << cables_table(summary["states"]);
  if (summary.contains("reactions_N") && summary["reactions_N"].is_object())
    out << reactions_table(summary["reactions_N"]);
  for (const char* key : {"verification", "error"})
    if (summary.contains(key) && summary[key].is_object()) out << scalars(summary[key]);
  return out.str();
}

}  // namespace hs
