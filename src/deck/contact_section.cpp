#include "deck/contact_section.hpp"

#include <cmath>
#include <filesystem>

#include "common/error.hpp"
#include "contact/surface_file.hpp"
#include "deck/section_keys.hpp"

namespace hs {
namespace {

KeyUse<ObstacleShape> types_only(std::vector<ObstacleType> types, const std::string& doc) {
  return {[types](const ObstacleShape& o, const Config&) {
            return std::find(types.begin(), types.end(), o.type) != types.end();
          },
          [doc](const ObstacleShape& o) {
            return "only used by type " + doc + " (this obstacle is " +
                   name_of(kObstacleTypeNames, o.type) + ")";
          },
          doc};
}

DeckKey<ObstacleShape> vector_key(std::string name, std::array<double, 3> ObstacleShape::*member,
                                  std::string default_value, std::string meaning) {
  return custom_key<ObstacleShape>(
      std::move(name), "3 numbers", std::move(default_value), std::move(meaning),
      [member](const DeckReader& r, const YAML::Node& n, const std::string& key, ObstacleShape& o,
               const Config&) { o.*member = r.vector3(n, key); },
      [member](YAML::Emitter& out, const ObstacleShape& o, const Config&) {
        write_numbers(out, (o.*member).data(), 3);
      });
}

// A direction given by the deck becomes a unit vector; zero length is refused.
void normalise(const DeckReader& r, const YAML::Node& node, const std::string& key,
               std::array<double, 3>& v) {
  const double length = std::hypot(v[0], v[1], v[2]);
  require(length > 0 && std::isfinite(length), r, node, key, "a direction needs a non-zero length");
  for (double& x : v) x /= length;
}

ObstacleShape parse_obstacle(const DeckReader& r, const YAML::Node& node, const std::string& key,
                             const Config& c) {
  ObstacleShape o;
  read_keys(r, node, key, obstacle_keys(), o, c);
  auto needs = [&](const char* name) {
    require(node[name].IsDefined(), r, node, child_key(key, name),
            "type " + name_of(kObstacleTypeNames, o.type) + " needs `" + name + "`");
  };
  require(o.friction == 0 || (o.turn[0] == 0 && o.turn[1] == 0 && o.turn[2] == 0), r, node["turn"],
          child_key(key, "turn"),
          "friction on a turning obstacle is not modelled (its contacts' anchors follow "
          "`move` only): give `friction: 0` or no `turn`");
  switch (o.type) {
    case ObstacleType::plane:
      normalise(r, node["normal"], child_key(key, "normal"), o.normal);
      break;
    case ObstacleType::sphere:
      needs("radius");
      break;
    case ObstacleType::cylinder:
      needs("radius");
      normalise(r, node["axis"], child_key(key, "axis"), o.axis);
      break;
    case ObstacleType::box:
      needs("size");
      for (int i = 0; i < 3; ++i)
        require(o.size[i] > 0, r, node["size"], child_key(key, "size"),
                "every edge length must be > 0, got " + format_number(o.size[i]));
      break;
    case ObstacleType::surface:
      needs("file");
      try {  // read now, so that a bad file stops the run before any work
        o.surface = read_obstacle_surface(o.file, o.scale);
      } catch (const InputError& e) {
        r.fail(child_key(key, "file"), node["file"], e.what());
      }
      break;
  }
  return o;
}

// A number > 0 the map may leave out (then the run works it out: `default_value` says how).
DeckKey<ContactConfig> positive_key(std::string name, std::optional<double> ContactConfig::*member,
                                    std::string default_value, std::string meaning) {
  DeckKey<ContactConfig> k = optional_number_key(std::move(name), member, std::move(meaning));
  k.type = "number > 0";
  k.default_value = std::move(default_value);
  k.read = [member](const DeckReader& r, const YAML::Node& n, const std::string& key,
                    ContactConfig& s, const Config&) {
    s.*member = r.number(n, key);
    require(*(s.*member) > 0, r, n, key, "must be > 0, got " + format_number(*(s.*member)));
  };
  return k;
}

}  // namespace

const KeyTable<ObstacleShape>& obstacle_keys() {
  using T = ObstacleType;
  static const KeyTable<ObstacleShape> keys = {
      text_key("name", &ObstacleShape::name, "name",
               "unique among the obstacles; names its force in summary.json and history.csv")
          .needed(),
      enum_key("type", &ObstacleShape::type, kObstacleTypeNames,
               "`plane` (a half-space), `sphere`, `box` (axis-aligned), `cylinder` (of "
               "infinite length) or `surface` (a closed triangle mesh from a file); the body "
               "stays outside it"),
      vector_key("point", &ObstacleShape::point, "`[0, 0, 0]`", "a point of the plane (m)")
          .only(types_only({T::plane}, "plane")),
      vector_key("normal", &ObstacleShape::normal, "`[0, 0, 1]`",
                 "the plane's normal, pointing to the side where the body is")
          .only(types_only({T::plane}, "plane")),
      vector_key("center", &ObstacleShape::center, "`[0, 0, 0]`",
                 "the centre (m); of a cylinder, a point of its axis")
          .only(types_only({T::sphere, T::box, T::cylinder}, "sphere, box, cylinder")),
      number_key("radius", &ObstacleShape::radius, above(0), "m")
          .only(types_only({T::sphere, T::cylinder}, "sphere, cylinder")),
      vector_key("size", &ObstacleShape::size, "required",
                 "edge lengths along x, y and z (m), each > 0")
          .only(types_only({T::box}, "box")),
      vector_key("axis", &ObstacleShape::axis, "`[0, 0, 1]`", "the cylinder's axis")
          .only(types_only({T::cylinder}, "cylinder")),
      custom_key<ObstacleShape>(
          "file", "path", "required",
          "a closed, outward-oriented triangle surface: STL (ASCII or binary) or Wavefront OBJ "
          "(`v` and `f` lines), at most 2,000,000 triangles and 512 MiB; a relative path starts "
          "at the deck's folder; checked when the deck is read (docs/contact.md, \"Surface "
          "obstacles\")",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, ObstacleShape& o,
             const Config& c) {
            namespace fs = std::filesystem;
            const fs::path given = r.text(n, key);
            const fs::path deck_dir = fs::path(c.deck_path).parent_path();
            o.file = fs::absolute(given.is_absolute() ? given : deck_dir / given)
                         .lexically_normal()
                         .string();
          },
          [](YAML::Emitter& out, const ObstacleShape& o, const Config&) { out << o.file; })
          .only(types_only({T::surface}, "surface")),
      number_key("scale", &ObstacleShape::scale, above(0),
                 "the file's coordinates times this are metres (0.001 for a file in mm)")
          .only(types_only({T::surface}, "surface")),
      number_key("friction", &ObstacleShape::friction, at_least(0, "a Coulomb coefficient"),
                 "Coulomb friction coefficient between the body and the obstacle (0: "
                 "frictionless); the friction force is at most this times the normal force, "
                 "lagged over each step (docs/contact.md)"),
      vector_key("move", &ObstacleShape::move, "`[0, 0, 0]`",
                 "a rigid translation (m) at full load, applied with the load factor as a "
                 "Dirichlet value is (a press, a plate brought down)"),
      vector_key("rotation", &ObstacleShape::rotation, "`[0, 0, 0]`",
                 "a fixed rotation of the shape as given, a rotation vector in degrees (the "
                 "axis times the angle: `[0, 0, 30]` turns it 30 degrees about z), about its "
                 "pivot: a plane's `point`, the `center` of a sphere, box or cylinder, a "
                 "surface's `pivot` (a box need not be axis-aligned)"),
      vector_key("turn", &ObstacleShape::turn, "`[0, 0, 0]`",
                 "a rotation vector (degrees) at full load, applied with the load factor after "
                 "`rotation`, about the pivot carried by `move` (a lever, a turning cam); not "
                 "with `friction`"),
      vector_key("pivot", &ObstacleShape::pivot, "`[0, 0, 0]`",
                 "the point (m, after `scale`) a surface turns about")
          .only(types_only({T::surface}, "surface")),
  };
  return keys;
}

// contact.friction_between: each entry names two of contact.surfaces (read before it) and a
// coefficient >= 0.
std::vector<ContactConfig::FrictionBetween> parse_friction_between(const DeckReader& r,
                                                                   const YAML::Node& node,
                                                                   const std::string& key,
                                                                   const ContactConfig& contact) {
  r.check_list(node, key);
  std::vector<ContactConfig::FrictionBetween> list;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string ikey = item_key(key, i);
    r.check_map(node[i], ikey, {"surfaces", "friction"});
    const YAML::Node names = required(r, node[i], ikey, "surfaces");
    const std::string skey = child_key(ikey, "surfaces");
    r.check_list(names, skey);
    require(names.size() == 2, r, names, skey,
            "needs two surface names (the same twice: a "
            "surface on itself)");
    ContactConfig::FrictionBetween f;
    for (int k = 0; k < 2; ++k) {
      f.surfaces[k] = r.text(names[k], item_key(skey, k));
      if (!contains(contact.surfaces, f.surfaces[k]))
        r.fail(item_key(skey, k), names[k],
               "'" + f.surfaces[k] + "' is not one of contact.surfaces (did you mean '" +
                   nearest(f.surfaces[k], contact.surfaces) + "'?)");
    }
    const std::string fkey = child_key(ikey, "friction");
    f.friction = r.number(required(r, node[i], ikey, "friction"), fkey);
    require(f.friction >= 0, r, node[i]["friction"], fkey,
            "must be >= 0 (a Coulomb coefficient), got " + format_number(f.friction));
    list.push_back(f);
  }
  return list;
}

const KeyTable<ContactConfig>& contact_keys() {
  static const KeyTable<ContactConfig> keys = {
      names_key<ContactConfig>("surfaces", &ContactConfig::surfaces, "required",
                               "surface groups of the body whose nodes may touch the obstacles")
          .needed(),
      positive_key("distance", &ContactConfig::distance, "1e-3 of the mesh's bounding-box diagonal",
                   "dhat (m): the gap below which the barrier pushes; a node never comes closer "
                   "than 0 and rests at a gap below dhat"),
      positive_key("stiffness", &ContactConfig::stiffness,
                   "0.01 E / distance (E the stiffest material's)",
                   "kappa (Pa/m): the barrier's scale; the contact pressure at gap d is about "
                   "kappa dhat^2 / d for d << dhat (docs/contact.md)"),
      positive_key("slip", &ContactConfig::slip, "0.1 distance",
                   "eps_v (m): the slip within a step below which friction sticks (a spring whose "
                   "force reaches the Coulomb limit at this slip) and beyond which the node "
                   "slides"),
      bool_key("self", &ContactConfig::self,
               "the surfaces also touch each other: a node of them is kept off every triangle "
               "of them it is not a corner of (self-contact, and contact between the bodies of "
               "one mesh; a P2 face is its four flat sub-triangles)"),
      bool_key("edges", &ContactConfig::edges,
               "with `self`: an edge of the surfaces is also kept off every edge of them it "
               "shares no node with, so that sharp edges pressed across each other cannot pass "
               "through (docs/contact.md, \"Edge pairs\"); false: nodes against triangles only"),
      number_key("friction", &ContactConfig::friction, at_least(0, "a Coulomb coefficient"),
                 "Coulomb friction coefficient between the surfaces where they touch each other "
                 "(with `self`; 0: frictionless), lagged over each step as an obstacle's "
                 "(docs/contact.md)"),
      custom_key<ContactConfig>(
          "friction_between", "list of {surfaces: [A, B], friction: mu}", "none",
          "with `self`: the Coulomb coefficient between two of `surfaces` (the same name twice: "
          "a surface on itself), in place of `friction` there; a node on two surfaces takes "
          "the larger coefficient",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, ContactConfig& s,
             const Config&) { s.friction_between = parse_friction_between(r, n, key, s); },
          [](YAML::Emitter& out, const ContactConfig& s, const Config&) {
            out << YAML::BeginSeq;
            for (const auto& f : s.friction_between) {
              out << YAML::Flow << YAML::BeginMap << YAML::Key << "surfaces" << YAML::Value
                  << YAML::Flow << YAML::BeginSeq << f.surfaces[0] << f.surfaces[1] << YAML::EndSeq
                  << YAML::Key << "friction" << YAML::Value << format_number(f.friction)
                  << YAML::EndMap;
            }
            out << YAML::EndSeq;
          })
          .printed_when([](const ContactConfig& s) { return !s.friction_between.empty(); }),
  };
  return keys;
}

std::vector<ObstacleShape> parse_obstacles(const DeckReader& r, const YAML::Node& node,
                                           const Config& c) {
  r.check_list(node, "obstacles");
  std::vector<ObstacleShape> obstacles;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string key = item_key("obstacles", i);
    obstacles.push_back(parse_obstacle(r, node[i], key, c));
    for (size_t j = 0; j < i; ++j)
      if (obstacles[j].name == obstacles[i].name)
        r.fail(child_key(key, "name"), node[i]["name"],
               "duplicate obstacle name '" + obstacles[i].name + "' (also " +
                   item_key("obstacles", j) + ")");
  }
  return obstacles;
}

ContactConfig parse_contact(const DeckReader& r, const YAML::Node& node, const Config& c) {
  ContactConfig contact;
  read_keys(r, node, "contact", contact_keys(), contact, c);
  return contact;
}

}  // namespace hs
