// Layout: "hsmesh1", order, then each array as a count followed by its items (native byte
// order: both ends are the same program on the same machine), names as counted bytes, maps as
// a count of (name, array) pairs.
#include "mesh/mesh_wire.hpp"

#include <cstdint>
#include <cstring>
#include <type_traits>

#include "common/error.hpp"

namespace hs {
namespace {

const char kMagic[] = "hsmesh1";

class Writer {
 public:
  template <class T>
  void value(T v) {
    static_assert(std::is_trivially_copyable<T>::value, "plain values only");
    out_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <class T>
  void array(const std::vector<T>& v) {
    value<uint64_t>(v.size());
    out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void text(const std::string& s) {
    value<uint64_t>(s.size());
    out_ += s;
  }
  template <class T>
  void map(const std::map<std::string, std::vector<T>>& m) {
    value<uint64_t>(m.size());
    for (const auto& [name, items] : m) {
      text(name);
      array(items);
    }
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

class WireReader {
 public:
  WireReader(std::string_view bytes, const std::string& file) : in_(bytes), file_(file) {}

  template <class T>
  T value() {
    T v;
    need(sizeof v, "a number");
    std::memcpy(&v, in_.data() + at_, sizeof v);
    at_ += sizeof v;
    return v;
  }
  template <class T>
  std::vector<T> array(const char* what) {
    const uint64_t n = count(sizeof(T), what);
    std::vector<T> v(n);
    std::memcpy(v.data(), in_.data() + at_, n * sizeof(T));
    at_ += n * sizeof(T);
    return v;
  }
  std::string text(const char* what) {
    const uint64_t n = count(1, what);
    std::string s(in_.substr(at_, n));
    at_ += n;
    return s;
  }
  template <class T>
  std::map<std::string, std::vector<T>> map(const char* what) {
    std::map<std::string, std::vector<T>> m;
    // Each entry takes at least its two counts.
    const uint64_t n = count(2 * sizeof(uint64_t), what);
    for (uint64_t i = 0; i < n; ++i) {
      std::string name = text(what);
      m[std::move(name)] = array<T>(what);
    }
    return m;
  }
  bool done() const { return at_ == in_.size(); }
  [[noreturn]] void fail(const std::string& reason) const {
    throw InputError(file_ + ": the mesh gmsh read could not be handed over (" + reason + ")");
  }

 private:
  // A count of items of `bytes` bytes each, checked against the bytes left.
  uint64_t count(size_t bytes, const char* what) {
    const uint64_t n = value<uint64_t>();
    if (n > (in_.size() - at_) / bytes) fail(std::string(what) + ": count beyond the data");
    return n;
  }
  void need(size_t bytes, const char* what) const {
    if (in_.size() - at_ < bytes) fail(std::string("truncated at ") + what);
  }

  std::string_view in_;
  size_t at_ = 0;
  const std::string& file_;
};

bool all_below(const std::vector<int64_t>& v, int64_t bound) {
  for (int64_t i : v)
    if (i < 0 || i >= bound) return false;
  return true;
}

}  // namespace

std::string encode_mesh(const Mesh& mesh) {
  Writer w;
  for (char c : kMagic) w.value(c);
  w.value<int32_t>(mesh.order);
  w.array(mesh.x);
  w.array(mesh.tets);
  w.array(mesh.tet_volume);
  w.value<uint64_t>(mesh.volume_names.size());
  for (const auto& name : mesh.volume_names) w.text(name);
  w.map(mesh.surfaces);
  w.map(mesh.surface_tets);
  w.map(mesh.node_groups);
  return w.take();
}

Mesh decode_mesh(std::string_view bytes, const std::string& file) {
  WireReader r(bytes, file);
  for (char c : kMagic)
    if (r.value<char>() != c) r.fail("not an encoded mesh");
  Mesh m;
  m.order = r.value<int32_t>();
  if (m.order != 1 && m.order != 2) r.fail("order " + std::to_string(m.order));
  m.x = r.array<double>("nodes");
  m.tets = r.array<int64_t>("tetrahedra");
  m.tet_volume = r.array<int>("volume of each tetrahedron");
  const uint64_t volumes = r.value<uint64_t>();
  if (volumes > bytes.size()) r.fail("volume names: count beyond the data");
  for (uint64_t v = 0; v < volumes; ++v) m.volume_names.push_back(r.text("volume names"));
  m.surfaces = r.map<int64_t>("surfaces");
  m.surface_tets = r.map<int64_t>("surface tetrahedra");
  m.node_groups = r.map<int64_t>("node groups");
  if (!r.done()) r.fail("bytes after the end");

  if (m.x.size() % 3 != 0 || m.tets.size() % m.nodes_per_tet() != 0)
    r.fail("partial node or tetrahedron");
  if (!all_below(m.tets, m.num_nodes())) r.fail("a tetrahedron names a node that does not exist");
  if (m.tet_volume.size() != static_cast<size_t>(m.num_tets()))
    r.fail("volume of each tetrahedron");
  for (int v : m.tet_volume)
    if (v < 0 || v >= static_cast<int>(m.volume_names.size())) r.fail("a volume out of range");
  for (const auto& [name, faces] : m.surfaces) {
    const auto bounds = m.surface_tets.find(name);
    if (faces.size() % m.nodes_per_face() != 0 || bounds == m.surface_tets.end() ||
        bounds->second.size() != faces.size() / m.nodes_per_face() ||
        !all_below(faces, m.num_nodes()) || !all_below(bounds->second, m.num_tets()))
      r.fail("surface '" + name + "'");
  }
  if (m.surface_tets.size() != m.surfaces.size()) r.fail("surface tetrahedra");
  for (const auto& [name, nodes] : m.node_groups)
    if (!all_below(nodes, m.num_nodes())) r.fail("group '" + name + "'");
  return m;
}

}  // namespace hs
