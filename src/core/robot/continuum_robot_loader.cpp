#include "surgical_sim/core/robot/continuum_robot_loader.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace surgical_sim::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Typed access to a YAML map; every error names the dotted key.
class Keys {
 public:
  Keys(YAML::Node node, std::string prefix, std::string source)
      : node_(std::move(node)), prefix_(std::move(prefix)), source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw std::invalid_argument(source_ + ": key '" + prefix_ + key + "': " + what);
  }
  YAML::Node required(const std::string& key) const {
    const YAML::Node n = node_[key];
    if (!n.IsDefined() || n.IsNull()) fail(key, "missing required key");
    return n;
  }
  double number(const std::string& key) const {
    const YAML::Node n = required(key);
    double v = 0.0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v)) fail(key, "expected a number");
    return v;
  }
  int integer(const std::string& key) const {
    const double v = number(key);
    if (v != std::floor(v) || std::abs(v) > 1e9) fail(key, "expected an integer");
    return static_cast<int>(v);
  }
  bool boolean(const std::string& key) const {
    const YAML::Node n = required(key);
    bool v = false;
    if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) fail(key, "expected true or false");
    return v;
  }
  Keys child(const std::string& key) const {
    const YAML::Node n = required(key);
    if (!n.IsMap()) fail(key, "expected a map");
    return Keys(n, prefix_ + key + ".", source_);
  }
  /// Items of an optional list; empty if absent.
  std::vector<Keys> items(const std::string& key) const {
    std::vector<Keys> out;
    const YAML::Node n = node_[key];
    if (!n.IsDefined() || n.IsNull()) return out;
    if (!n.IsSequence()) fail(key, "expected a list");
    for (size_t i = 0; i < n.size(); ++i) {
      if (!n[i].IsMap()) fail(key + "[" + std::to_string(i) + "]", "expected a map");
      out.emplace_back(n[i], prefix_ + key + "[" + std::to_string(i) + "].", source_);
    }
    return out;
  }
  std::string text(const std::string& key) const {
    const YAML::Node n = required(key);
    if (!n.IsScalar()) fail(key, "expected a string");
    return n.as<std::string>();
  }

 private:
  YAML::Node node_;
  std::string prefix_;
  std::string source_;
};

}  // namespace

ContinuumRobotDescription parseContinuumRobot(const std::string& yaml_text, const std::string& name,
                                              const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(source + ": YAML syntax error: " + e.what());
  }
  const Keys robots = Keys(root, "", source).child("robots");
  const Keys r = robots.child(name);
  ContinuumRobotDescription d;
  d.name = name;
  d.num_vertebrae = r.integer("num_vertebrae");
  d.vertebra_spacing = r.number("vertebra_spacing_m");
  d.vertebra_thickness = r.number("vertebra_thickness_m");
  d.outer_radius_base = 0.5 * r.number("outer_diameter_base_m");
  d.outer_radius_tip = 0.5 * r.number("outer_diameter_tip_m");
  d.inner_radius = 0.5 * r.number("inner_diameter_m");
  const Keys m = r.child("material");
  d.material.young_modulus = m.number("young_modulus_pa");
  d.material.poisson_ratio = m.number("poisson_ratio");
  d.material.density = m.number("density_kg_m3");
  d.vertebra_mass = r.number("vertebra_mass_kg");
  d.gravity_enabled = r.boolean("gravity_enabled");
  const Keys mesh = r.child("mesh");
  d.mesh.radial_layers = mesh.integer("radial_layers");
  d.mesh.circumferential_segments = mesh.integer("circumferential_segments");
  d.mesh.axial_layers = mesh.integer("axial_layers");
  for (const Keys& c : r.items("chambers")) {
    PressureChamberDescription ch;
    ch.name = c.text("name");
    ch.first_gap = c.integer("first_gap");
    ch.last_gap = c.integer("last_gap");
    ch.angle = c.number("angle_deg") * kPi / 180.0;
    ch.radial_offset = c.number("radial_offset_m");
    ch.radius = c.number("radius_m");
    ch.pressure_min = 1e3 * c.number("pressure_min_kpa");
    ch.pressure_max = 1e3 * c.number("pressure_max_kpa");
    d.chambers.push_back(ch);
  }
  for (const Keys& c : r.items("cables")) {
    CableDescription cb;
    cb.name = c.text("name");
    cb.last_vertebra = c.integer("last_vertebra");
    cb.angle = c.number("angle_deg") * kPi / 180.0;
    cb.radial_offset = c.number("radial_offset_m");
    cb.tension_max = c.number("tension_max_n");
    d.cables.push_back(cb);
  }
  validateContinuumRobotDescription(d);
  return d;
}

ContinuumRobotDescription loadContinuumRobot(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("robot description file '" + path + "' cannot be read");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parseContinuumRobot(buffer.str(), name, path);
}

}  // namespace surgical_sim::core
