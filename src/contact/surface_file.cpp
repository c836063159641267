#include "contact/surface_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <tuple>

#include "common/error.hpp"
#include "fluidweight/mesh_io.hpp"

namespace hs {
namespace {

namespace fs = std::filesystem;
using Point = Eigen::Vector3d;

std::string corner_text(const Point& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.9g, %.9g, %.9g)", p(0), p(1), p(2));
  return text;
}

// The file itself: there, a regular file, of a size worth reading, an extension we read.
void check_file(const std::string& path) {
  std::error_code error;
  if (!fs::is_regular_file(path, error)) {
    std::error_code ignored;
    const bool exists = fs::exists(path, ignored);
    const std::string why = !exists ? "no such file (a relative path starts at the deck's folder)"
                            : error ? error.message()
                                    : "not a regular file";
    throw InputError(path + ": cannot read the surface: " + why);
  }
  const uintmax_t bytes = fs::file_size(path, error);
  if (error) throw InputError(path + ": cannot read the surface: " + error.message());
  if (bytes > kMaxSurfaceBytes)
    throw InputError(path + ": " + std::to_string(bytes) + " bytes, beyond the " +
                     std::to_string(kMaxSurfaceBytes >> 20) + " MiB read for an obstacle");
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext != ".stl" && ext != ".obj")
    throw InputError(path + ": an obstacle's surface is a .stl or .obj file, not '" + ext + "'");
}

// Every edge used by exactly two triangles, once in each direction: closed and consistently
// oriented. The first bad edge in triangle order is named by its ends.
void check_closed(const std::string& path, const std::vector<Point>& X,
                  const std::vector<std::array<int, 3>>& T) {
  std::vector<std::tuple<int, int, int>> uses;  // (smaller end, larger end, 3 t + k)
  uses.reserve(3 * T.size());
  for (size_t t = 0; t < T.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = T[t][k], b = T[t][(k + 1) % 3];
      uses.emplace_back(std::min(a, b), std::max(a, b), static_cast<int>(3 * t + k));
    }
  std::sort(uses.begin(), uses.end());
  int worst = -1;
  std::string reason;
  for (size_t i = 0; i < uses.size();) {
    size_t j = i;
    while (j < uses.size() && std::get<0>(uses[j]) == std::get<0>(uses[i]) &&
           std::get<1>(uses[j]) == std::get<1>(uses[i]))
      ++j;
    const int first = std::get<2>(uses[i]);
    auto forward = [&](size_t u) {
      const int t = std::get<2>(uses[u]) / 3, k = std::get<2>(uses[u]) % 3;
      return T[t][k] == std::get<0>(uses[u]);
    };
    const bool bad = j - i != 2 || forward(i) == forward(i + 1);
    if (bad && (worst < 0 || first < worst)) {
      worst = first;
      const std::string t1 = std::to_string(first / 3 + 1);
      if (j - i == 1)
        reason = "is used by triangle " + t1 + " alone: the surface is open there";
      else if (j - i > 2)
        reason = "is shared by " + std::to_string(j - i) + " triangles: not a manifold there";
      else
        reason = "runs the same way in triangles " + t1 + " and " +
                 std::to_string(std::get<2>(uses[i + 1]) / 3 + 1) + ": their orientations disagree";
    }
    i = j;
  }
  if (worst < 0) return;
  const int t = worst / 3, k = worst % 3;
  throw InputError(path + ": not a closed, consistently oriented surface: the edge from " +
                   corner_text(X[T[t][k]]) + " to " + corner_text(X[T[t][(k + 1) % 3]]) + " " +
                   reason);
}

}  // namespace

std::shared_ptr<const TriangleSurface> read_obstacle_surface(const std::string& path, double scale,
                                                             size_t max_triangles) {
  check_file(path);
  fluidweight::SurfaceMesh mesh;
  try {
    mesh = fluidweight::read_surface(path);
  } catch (const fluidweight::InputError& e) {
    throw InputError(e.what());
  }
  const size_t nt = mesh.triangles.size() / 3;
  if (nt == 0) throw InputError(path + ": the surface has no triangles");
  if (nt > max_triangles)
    throw InputError(path + ": " + std::to_string(nt) + " triangles, beyond the " +
                     std::to_string(max_triangles) + " an obstacle may have");
  std::vector<Point> X(mesh.vertices.size() / 3);
  for (size_t v = 0; v < X.size(); ++v) {
    X[v] = scale * Point(mesh.vertices[3 * v], mesh.vertices[3 * v + 1], mesh.vertices[3 * v + 2]);
    if (!(X[v].cwiseAbs().maxCoeff() <= kMaxSurfaceCoordinate))
      throw InputError(path + ": vertex " + std::to_string(v + 1) + " at " + corner_text(X[v]) +
                       " m (after scale) is beyond 1e6 m from the origin: a unit or scale error");
  }
  std::vector<std::array<int, 3>> T(nt);
  double volume = 0;
  for (size_t t = 0; t < nt; ++t) {
    T[t] = {mesh.triangles[3 * t], mesh.triangles[3 * t + 1], mesh.triangles[3 * t + 2]};
    const Point &a = X[T[t][0]], &b = X[T[t][1]], &c = X[T[t][2]];
    const double longest =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    // Zero area to round-off: no normal, so no sign near it.
    if (!((b - a).cross(c - a).norm() > 1e-12 * longest))
      throw InputError(path + ": triangle " + std::to_string(t + 1) + " with corners " +
                       corner_text(a) + ", " + corner_text(b) + ", " + corner_text(c) +
                       " has no area (its corners are on one line)");
    volume += a.dot(b.cross(c)) / 6;
  }
  check_closed(path, X, T);
  if (!(volume > 0)) {
    char text[64];
    std::snprintf(text, sizeof text, "%.6g", volume);
    throw InputError(path + ": the surface encloses a volume of " + text +
                     " m^3: its triangles face inward; an obstacle's must face out (counter-"
                     "clockwise seen from outside, where the body is): reverse their corners");
  }
  return std::make_shared<const TriangleSurface>(std::move(X), std::move(T));
}

}  // namespace hs
