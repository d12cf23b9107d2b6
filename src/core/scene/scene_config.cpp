#include "surgical_sim/core/scene/scene_config.h"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>
#include <algorithm>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "surgical_sim/core/common/thread_pool.h"
#include "surgical_sim/core/connective/rigid_node_model.h"
#include "surgical_sim/core/cutting/blade_sweep.h"
#include "surgical_sim/core/mesh/length_unit.h"
#include "surgical_sim/core/mesh/surface_generators.h"

namespace surgical_sim::core {
namespace {

constexpr std::size_t kMaxSceneBytes = 4 << 20;  ///< largest scene file [bytes]
constexpr std::size_t kMaxListLength = 10000;    ///< longest list of any key
constexpr long long kMaxYamlNodes = 1000000;     ///< YAML nodes visited (aliases count again)
constexpr double kMaxTissueOffset = 100.0;       ///< |tissue_pose.position| limit [m]
constexpr double kMaxDisplacement = 10.0;        ///< |prescribed displacement|, |reference| [m]
constexpr double kMaxLoadFactor = 1e3;           ///< |load_factors entry| [-]
constexpr double kMaxLayerRigidNodes = 2e4;      ///< poisson_disk layer: rigid-node estimate
constexpr double kMaxLayerSamples = 2e5;         ///< poisson_disk layer: sample estimate
/// Working memory per node and per element of a case (mesh, model, stiffness and system
/// matrices, sparse factorisation), by element type [bytes]; see estimateMeshSize().
constexpr double kBytesPerNode[2] = {40e3, 50e3};
constexpr double kBytesPerElement[2] = {0.5e3, 3e3};

/// Reads typed values from a YAML map and reports errors with the scene path and dotted key.
class KeyReader {
 public:
  KeyReader(const YAML::Node& node, std::string prefix, std::string path)
      : node_(node), prefix_(std::move(prefix)), path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw std::invalid_argument("scene " + path_ + ": key '" + dotted(key) + "': " + what);
  }

  std::string dotted(const std::string& key) const {
    return prefix_.empty() ? key : prefix_ + "." + key;
  }

  bool has(const std::string& key) const { return node_[key].IsDefined() && !node_[key].IsNull(); }

  YAML::Node required(const std::string& key) const {
    if (!has(key)) fail(key, "missing required key");
    return node_[key];
  }

  /// The sequence under `key` (non-empty unless allow_empty), at most kMaxListLength long.
  YAML::Node list(const std::string& key, const std::string& expected,
                  bool allow_empty = false) const {
    YAML::Node n = required(key);
    if (!n.IsSequence() || (n.size() == 0 && !allow_empty)) fail(key, "expected " + expected);
    if (n.size() > kMaxListLength)
      fail(key, "list has " + std::to_string(n.size()) + " entries, more than the limit of " +
                    std::to_string(kMaxListLength));
    return n;
  }

  KeyReader child(const std::string& key) const {
    YAML::Node c = required(key);
    if (!c.IsMap()) fail(key, "expected a map");
    return KeyReader(c, dotted(key), path_);
  }

  double number(const std::string& key) const { return toNumber(required(key), key); }
  double number(const std::string& key, double fallback) const {
    return has(key) ? number(key) : fallback;
  }

  int integer(const std::string& key, int lo, int hi) const {
    return toInteger(required(key), key, lo, hi);
  }
  int integer(const std::string& key, int lo, int hi, int fallback) const {
    return has(key) ? integer(key, lo, hi) : fallback;
  }

  /// A non-empty string.
  std::string text(const std::string& key) const {
    YAML::Node n = required(key);
    if (!n.IsScalar()) fail(key, "expected a string");
    const std::string v = n.as<std::string>();
    if (v.empty()) fail(key, "must not be empty");
    return v;
  }

  /// A ROS graph resource name: non-empty, starting with a letter, '/' or '~', then letters,
  /// digits, '_' and '/'.
  std::string topic(const std::string& key) const {
    const std::string v = text(key);
    bool valid = std::isalpha(static_cast<unsigned char>(v[0])) || v[0] == '/' || v[0] == '~';
    for (std::size_t i = 1; i < v.size(); ++i)
      valid =
          valid && (std::isalnum(static_cast<unsigned char>(v[i])) || v[i] == '_' || v[i] == '/');
    if (!valid) fail(key, "'" + v + "' is not a valid ROS topic name");
    return v;
  }

  std::string choice(const std::string& key, const std::set<std::string>& allowed) const {
    const std::string v = text(key);
    if (!allowed.count(v)) fail(key, "'" + v + "' is not one of " + join(allowed));
    return v;
  }

  /// A string or a list of strings, each from `allowed`.
  std::vector<std::string> choices(const std::string& key,
                                   const std::set<std::string>& allowed) const {
    YAML::Node n = required(key);
    std::vector<std::string> out;
    if (n.IsScalar()) {
      out.push_back(n.as<std::string>());
    } else if (n.IsSequence() && n.size() > 0) {
      for (const auto& item : list(key, "a non-empty list of strings")) {
        if (!item.IsScalar()) fail(key, "expected a list of strings");
        out.push_back(item.as<std::string>());
      }
    } else {
      fail(key, "expected a string or a non-empty list of strings");
    }
    for (const auto& v : out)
      if (!allowed.count(v)) fail(key, "'" + v + "' is not one of " + join(allowed));
    return out;
  }

  /// [a, b, c]; with allow_infinite, .inf / -.inf are accepted (open region bounds).
  Eigen::Vector3d vector3(const std::string& key, bool allow_infinite = false) const {
    YAML::Node n = required(key);
    if (!n.IsSequence() || n.size() != 3) fail(key, "expected a list of 3 numbers");
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v[i] = toNumber(n[i], key, allow_infinite);
    return v;
  }

  std::vector<double> numbers(const std::string& key) const {
    std::vector<double> out;
    for (const auto& item : list(key, "a non-empty list of numbers"))
      out.push_back(toNumber(item, key));
    return out;
  }

  /// A scalar `n` (found under `key`) as an integer in [lo, hi].
  int toInteger(const YAML::Node& n, const std::string& key, int lo, int hi) const {
    const double v = toNumber(n, key);
    if (v != std::floor(v) || v < lo || v > hi)
      fail(key, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                    "], got " + n.as<std::string>());
    return static_cast<int>(v);
  }

  /// Checks that the map holds no key outside `known` (catches typos such as "young_modulos").
  void onlyKeys(const std::set<std::string>& known) const {
    for (const auto& kv : node_) {
      const std::string k = kv.first.as<std::string>();
      if (!known.count(k)) fail(k, "unknown key (expected one of " + join(known) + ")");
    }
  }

  const YAML::Node& node() const { return node_; }
  const std::string& path() const { return path_; }

  /// A scalar `n` (found under `key`) as a finite number; with allow_infinite, .inf / -.inf too.
  double toNumber(const YAML::Node& n, const std::string& key, bool allow_infinite = false) const {
    if (!n.IsScalar()) fail(key, "expected a number");
    const std::string s = n.as<std::string>();
    if (allow_infinite && (s == ".inf" || s == "+.inf"))
      return std::numeric_limits<double>::infinity();
    if (allow_infinite && s == "-.inf") return -std::numeric_limits<double>::infinity();
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);  // an underflow to 0 / subnormal is accepted
    if (s.empty() || std::isspace(static_cast<unsigned char>(s[0])) || *end != '\0')
      fail(key, "expected a number, got '" + s + "'");
    if (!std::isfinite(v) || (errno == ERANGE && std::abs(v) > 1.0))
      fail(key, "must be finite, got '" + s + "'");
    return v;
  }

 private:
  static std::string join(const std::set<std::string>& items) {
    std::string out;
    for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
    return out;
  }

  YAML::Node node_;
  std::string prefix_;
  std::string path_;
};

/// Rejects, anywhere in the document, a map key that is not a plain scalar and a key written
/// twice in one map (yaml-cpp keeps both and lookups see only one). `dotted` names `node`.
void rejectDuplicateKeys(const YAML::Node& node, const std::string& dotted, const std::string& path,
                         long long& visited) {
  const auto fail = [&](const std::string& key, const std::string& what) {
    throw std::invalid_argument("scene " + path + ": key '" + key + "': " + what);
  };
  if (++visited > kMaxYamlNodes)
    fail(dotted.empty() ? "(top level)" : dotted,
         "the document has more than " + std::to_string(kMaxYamlNodes) + " values");
  if (node.IsSequence()) {
    if (node.size() > kMaxListLength)
      fail(dotted, "list has " + std::to_string(node.size()) + " entries, more than the limit of " +
                       std::to_string(kMaxListLength));
    for (std::size_t i = 0; i < node.size(); ++i)
      rejectDuplicateKeys(node[i], dotted + "[" + std::to_string(i) + "]", path, visited);
  } else if (node.IsMap()) {
    std::set<std::string> seen;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar())
        fail(dotted.empty() ? "(top level)" : dotted, "a map key at line " +
                                                          std::to_string(kv.first.Mark().line + 1) +
                                                          " is not a plain string");
      const std::string key = kv.first.as<std::string>();
      const std::string child = dotted.empty() ? key : dotted + "." + key;
      if (!seen.insert(key).second)
        fail(child, "duplicate key (line " + std::to_string(kv.first.Mark().line + 1) + ")");
      rejectDuplicateKeys(kv.second, child, path, visited);
    }
  }
}

void checkRange(const KeyReader& r, const std::string& key, double v, double lo, double hi,
                const std::string& unit) {
  if (!(v >= lo && v <= hi)) {
    const std::string u = unit.empty() ? "" : " " + unit;
    std::ostringstream s;
    s << v << u << " is out of range [" << lo << ", " << hi << "]" << u;
    r.fail(key, s.str());
  }
}

Region readRegion(const KeyReader& parent, const std::string& key) {
  const KeyReader r = parent.child(key);
  r.onlyKeys({"min", "max"});
  Region region;
  if (r.has("min")) region.min = r.vector3("min", true);
  if (r.has("max")) region.max = r.vector3("max", true);
  if ((region.min.array() > region.max.array()).any()) r.fail("min", "min exceeds max");
  return region;
}

Eigen::Vector3i readComponents(const KeyReader& r) {
  if (!r.has("components")) return Eigen::Vector3i::Ones();
  Eigen::Vector3i c = Eigen::Vector3i::Zero();
  for (const auto& axis : r.choices("components", {"x", "y", "z"})) c[axis[0] - 'x'] = 1;
  return c;
}

/// The names of an enum's table, as a set for KeyReader::choice().
template <class Enum, std::size_t N>
std::set<std::string> nameSet(const std::array<EnumName<Enum>, N>& table) {
  std::set<std::string> names;
  for (const auto& e : table) names.insert(e.name);
  return names;
}

/// One choice from an enum's name table.
template <class Enum, std::size_t N>
Enum readEnum(const KeyReader& r, const std::string& key,
              const std::array<EnumName<Enum>, N>& table) {
  return *enumFromName(table, r.choice(key, nameSet(table)));
}

/// The mesh geometry (no resolution); `extra` are the resolution keys of the scene kind.
MeshSpec readMesh(const KeyReader& scene, const std::set<std::string>& extra) {
  const KeyReader r = scene.child("mesh");
  std::set<std::string> known = {"generator", "size",  "origin", "side",
                                 "length",    "split", "file",   "unit"};
  known.insert(extra.begin(), extra.end());
  r.onlyKeys(known);
  MeshSpec m;
  m.generator = r.choice("generator", {"box", "beam", "hex_beam", "organ_blob", "liver", "file"});
  if (r.has("split")) {
    if (m.generator != "box" && m.generator != "beam")
      r.fail("split", "the cell split applies to the box and beam generators only");
    m.split = readEnum(r, "split", kCellSplitNames);
  }
  if (m.generator == "file" || r.has("unit")) {
    try {
      m.metres_per_unit = lengthUnitToMetres(r.text("unit"));
    } catch (const std::invalid_argument& e) {
      r.fail("unit", e.what());
    }
  }
  if (m.generator == "file") {
    std::filesystem::path file = r.text("file");
    if (file.is_relative()) file = std::filesystem::path(r.path()).parent_path() / file;
    m.file = file.lexically_normal().string();
    return m;
  }
  if (m.metres_per_unit != 1.0)
    r.fail("unit", "generated meshes are sized in metres; 'unit' applies to mesh files only");
  if (m.generator == "hex_beam") {
    m.hex_side = r.number("side");
    m.hex_length = r.number("length");
    checkRange(r, "side", m.hex_side, 1e-6, 1e3, "m");
    checkRange(r, "length", m.hex_length, 1e-6, 1e3, "m");
  } else {
    m.size = r.vector3("size");
    for (int i = 0; i < 3; ++i) checkRange(r, "size", m.size[i], 1e-6, 1e3, "m");
    if (r.has("origin")) m.origin = r.vector3("origin");
  }
  return m;
}

/// One resolution [nx, ny, nz] of a generated mesh, read from `item` (found under mesh.`key`).
Eigen::Vector3i readResolution(const KeyReader& mesh, const std::string& key,
                               const YAML::Node& item, const std::string& generator) {
  if (!item.IsSequence() || item.size() != 3)
    mesh.fail(key, "each resolution is a list of 3 integers");
  // box/beam use all three counts; hex_beam [along, rings, -]; organ_blob [per_axis, -, -];
  // liver [subdivisions, -, -].
  const int used = generator == "hex_beam"                             ? 2
                   : generator == "organ_blob" || generator == "liver" ? 1
                                                                       : 3;
  Eigen::Vector3i cells;
  for (int i = 0; i < 3; ++i) cells[i] = mesh.toInteger(item[i], key, i < used, 4096);
  if (generator == "liver" && cells[0] > kMaxSurfaceSubdivisions) {
    mesh.fail(key, "liver subdivisions = " + std::to_string(cells[0]) + " is out of range: [0, " +
                       std::to_string(kMaxSurfaceSubdivisions) + "] (20 4^s triangles)");
  }
  return cells;
}

ElementType elementType(const std::string& name) {
  return name == "tet4" ? ElementType::Tet4 : ElementType::Tet10;
}

/// Rejects a mesh that exceeds the memory budget, naming mesh.`key`.
void checkBudget(const KeyReader& mesh, const std::string& key, const MeshSpec& m,
                 const Eigen::Vector3i& resolution, ElementType type) {
  const std::string problem = meshBudgetProblem(m, resolution, type);
  if (!problem.empty()) mesh.fail(key, problem);
}

/// One name or a non-empty list of names from an enum's name table (a sweep).
template <class Enum, std::size_t N>
std::vector<Enum> readEnums(const KeyReader& r, const std::string& key,
                            const std::array<EnumName<Enum>, N>& table) {
  std::vector<Enum> out;
  for (const std::string& name : r.choices(key, nameSet(table)))
    out.push_back(*enumFromName(table, name));
  return out;
}

MeasureSpec readMeasure(const KeyReader& scene) {
  const KeyReader r = scene.child("measure");
  r.onlyKeys({"type", "region", "component", "reference", "reference_formula", "face_area",
              "rest_length", "reference_solver"});
  MeasureSpec m;
  m.type = r.choice("type", {"tip_displacement", "uniaxial_svk_force", "self_reference"});
  if (r.has("reference_solver")) {
    if (m.type != "self_reference")
      r.fail("reference_solver", "only a self_reference measure has a reference run");
    m.reference_solver = readEnum(r, "reference_solver", kSolverNames);
  }
  if (m.type == "self_reference") return m;
  m.region = readRegion(r, "region");
  m.component = r.choice("component", {"x", "y", "z"})[0] - 'x';
  if (m.type == "tip_displacement") {
    if (r.has("reference")) {
      m.reference = r.number("reference");
      if (*m.reference == 0.0)
        r.fail("reference", "must be non-zero (error_rel is relative to it)");
      checkRange(r, "reference", std::abs(*m.reference), 1e-12, kMaxDisplacement, "m (magnitude)");
    } else {
      m.reference_formula =
          r.choice("reference_formula", {"euler_bernoulli_timoshenko", "axial_self_weight"});
    }
  } else {
    m.face_area = r.number("face_area");
    m.rest_length = r.number("rest_length");
    checkRange(r, "face_area", m.face_area, 1e-12, 1e6, "m^2");
    checkRange(r, "rest_length", m.rest_length, 1e-6, 1e3, "m");
  }
  return m;
}

/// A name that becomes a ROS namespace, tf frame or joint prefix: [A-Za-z][A-Za-z0-9_]*.
std::string readIdentifier(const KeyReader& r, const std::string& key) {
  const std::string v = r.text(key);
  bool valid = std::isalpha(static_cast<unsigned char>(v[0]));
  for (const char c : v) valid = valid && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
  if (!valid) r.fail(key, "'" + v + "' must start with a letter and hold only letters, digits, _");
  return v;
}

/// The tool's jaws. Topics left empty here are filled by assignToolTopics().
GraspSpec readGrasp(const KeyReader& tool) {
  const KeyReader r = tool.child("grasp");
  r.onlyKeys({"radius", "topic", "joint", "joint_topic", "closed_angle"});
  GraspSpec g;
  g.radius = r.number("radius");
  checkRange(r, "radius", g.radius, 1e-5, 0.05, "m");
  if (r.has("topic")) g.topic = r.topic("topic");
  if (r.has("joint")) g.joint = r.text("joint");
  if (r.has("joint_topic")) g.joint_topic = r.topic("joint_topic");
  if (g.joint.empty() && !g.joint_topic.empty())
    r.fail("joint_topic", "names the topic of a joint: give 'joint' too");
  g.closed_angle = r.number("closed_angle", g.closed_angle);
  checkRange(r, "closed_angle", g.closed_angle, -M_PI, M_PI, "rad");
  return g;
}

ToolSpec readTool(const KeyReader& r) {
  r.onlyKeys({"name", "pose_topic", "wrench_topic", "contact_model_topic", "radius", "shaft_length",
              "contact", "proxy_stiffness", "coupling_stiffness", "coupling_damping", "max_force",
              "grasp"});
  ToolSpec t;
  t.name = readIdentifier(r, "name");
  if (r.has("pose_topic")) t.pose_topic = r.topic("pose_topic");
  if (r.has("wrench_topic")) t.wrench_topic = r.topic("wrench_topic");
  if (r.has("contact_model_topic")) t.contact_model_topic = r.topic("contact_model_topic");
  const std::string contact = r.choice("contact", {"constraint", "proxy", "none"});
  if (contact == "none") {
    for (const char* key :
         {"radius", "shaft_length", "proxy_stiffness", "coupling_stiffness", "coupling_damping",
          "max_force", "grasp", "wrench_topic", "contact_model_topic"})
      if (r.has(key))
        r.fail(key, "a tool with 'contact: none' touches nothing and has no " + std::string(key));
    return t;
  }
  t.contact = contact == "proxy" ? ContactResponse::Proxy : ContactResponse::Constraint;
  t.radius = r.number("radius");
  checkRange(r, "radius", t.radius, 1e-5, 0.05, "m");
  t.shaft_length = r.number("shaft_length");
  checkRange(r, "shaft_length", t.shaft_length, 0.0, 1.0, "m");
  if (t.contact == ContactResponse::Proxy) {
    t.proxy_stiffness = r.number("proxy_stiffness");
    checkRange(r, "proxy_stiffness", *t.proxy_stiffness, 1e-6, 1e6, "N/m");
    for (const char* key : {"coupling_stiffness", "coupling_damping"})
      if (r.has(key)) r.fail(key, "a proxy tool has no coupling (its proxy spring is it)");
  } else {
    if (r.has("proxy_stiffness"))
      r.fail("proxy_stiffness", "only a tool with 'contact: proxy' has a proxy spring");
    t.coupling_stiffness = r.number("coupling_stiffness", t.coupling_stiffness);
    checkRange(r, "coupling_stiffness", t.coupling_stiffness, 1.0, 1e7, "N/m");
    t.coupling_damping = r.number("coupling_damping", t.coupling_damping);
    checkRange(r, "coupling_damping", t.coupling_damping, 0.0, 1e5, "N s/m");
  }
  t.max_force = r.number("max_force", t.max_force);
  checkRange(r, "max_force", t.max_force, 1e-3, 1e4, "N");
  if (r.has("grasp")) t.grasp = readGrasp(r);
  return t;
}

/// Index of the tool named by `key`, or a failure naming the tools there are.
int readToolReference(const KeyReader& r, const std::string& key,
                      const std::vector<ToolSpec>& tools) {
  const std::string name = r.text(key);
  for (std::size_t i = 0; i < tools.size(); ++i)
    if (tools[i].name == name) return static_cast<int>(i);
  std::string names;
  for (const ToolSpec& t : tools) names += (names.empty() ? "" : ", ") + t.name;
  r.fail(key, "no tool is named '" + name + "' (tools: " + (names.empty() ? "none" : names) + ")");
}

Eigen::Isometry3d readPose(const KeyReader& parent, const std::string& key) {
  const KeyReader r = parent.child(key);
  r.onlyKeys({"position", "rpy"});
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  if (r.has("position")) X.translation() = r.vector3("position");
  checkRange(r, "position", X.translation().norm(), 0.0, kMaxTissueOffset, "m (magnitude)");
  if (r.has("rpy")) {
    const Eigen::Vector3d rpy = r.vector3("rpy");
    for (int i = 0; i < 3; ++i) checkRange(r, "rpy", rpy[i], -2.0 * M_PI, 2.0 * M_PI, "rad");
    X.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
  }
  return X;
}

/// Dotted path of the block-style key that encloses line `line` (0-based) of a YAML text, from
/// the indentation of the "key:" lines up to it (list items add "[]"); "" above the first key.
/// Used to name the key of a syntax error, where no parsed node exists.
std::string keyPathAtLine(const std::string& text, int line) {
  struct Level {
    std::size_t indent;
    std::string key;
  };
  std::vector<Level> stack;
  std::istringstream lines(text);
  std::string l;
  for (int i = 0; i <= line && std::getline(lines, l); ++i) {
    std::size_t at = l.find_first_not_of(' ');
    if (at == std::string::npos || l[at] == '#') continue;
    const std::size_t indent = at;
    std::string prefix;
    if (l.compare(at, 2, "- ") == 0) {
      at = l.find_first_not_of(' ', at + 2);
      if (at == std::string::npos) continue;
      prefix = "[].";
    }
    std::size_t end = at;
    while (end < l.size() && (std::isalnum(static_cast<unsigned char>(l[end])) || l[end] == '_'))
      ++end;
    if (end == at || end >= l.size() || l[end] != ':') continue;
    while (!stack.empty() && stack.back().indent >= indent) stack.pop_back();
    if (!prefix.empty() && !stack.empty()) stack.back().key += "[]";
    stack.push_back({at, l.substr(at, end - at)});
  }
  std::string path;
  for (const Level& level : stack) path += (path.empty() ? "" : ".") + level.key;
  return path;
}

/// "malformed YAML at line N (in key 'a.b')" for a syntax error at 0-based line `line`.
std::string syntaxErrorPlace(const std::string& text, int line) {
  const std::string key = keyPathAtLine(text, line);
  return "malformed YAML at line " + std::to_string(line + 1) +
         (key.empty() ? std::string() : " (in key '" + key + "')");
}

/// A key of the other scene kind and what to use instead.
struct ForeignKey {
  const char* key;
  const char* hint;
};

constexpr ForeignKey kBenchmarkKeys[] = {
    {"models",
     "use 'model: <name>': a runtime scene is one simulation; sweeps belong in "
     "benchmark files, which tissue_bench runs"},
    {"integrators",
     "use 'integrator: <name>': a runtime scene is one simulation; sweeps belong "
     "in benchmark files, which tissue_bench runs"},
    {"solvers",
     "use 'solver: <name>': a runtime scene is one simulation; sweeps belong in "
     "benchmark files, which tissue_bench runs"},
    {"steps", "a runtime scene runs until it is stopped; 'steps' belongs in benchmark files"},
    {"load_factors", "a runtime scene has no load path; 'load_factors' belongs in benchmark files"},
    {"prescribed",
     "a runtime scene has no prescribed displacements; they belong in benchmark "
     "files"},
    {"measure",
     "a runtime scene measures nothing; 'measure' belongs in benchmark files, which "
     "tissue_bench runs"},
};
constexpr ForeignKey kRuntimeKeys[] = {
    {"model", "a benchmark file sweeps: use 'models: [<name>, ...]'"},
    {"integrator", "a benchmark file sweeps: use 'integrators: [<name>, ...]'"},
    {"solver", "a benchmark file sweeps: use 'solvers: [<name>, ...]'"},
    {"trocars", "instruments belong in runtime scenes (scene.launch), not in benchmark files"},
    {"blades", "instruments belong in runtime scenes (scene.launch), not in benchmark files"},
    {"robot", "instruments belong in runtime scenes (scene.launch), not in benchmark files"},
};
constexpr ForeignKey kBenchmarkMeshKeys[] = {
    {"resolutions", "use 'resolution: [nx, ny, nz]'; resolution sweeps belong in benchmark files"},
    {"element_types",
     "use 'element_type: tet4|tet10'; element-type sweeps belong in benchmark "
     "files"},
};
constexpr ForeignKey kRuntimeMeshKeys[] = {
    {"resolution", "a benchmark file sweeps: use 'resolutions: [[nx, ny, nz], ...]'"},
    {"element_type", "a benchmark file sweeps: use 'element_types: [tet4, ...]'"},
};

/// Rejects the keys of the other scene kind, at the top level (`top`) and under mesh (`mesh`),
/// naming what to write instead.
template <std::size_t N, std::size_t M>
void rejectForeignKeys(const KeyReader& r, const ForeignKey (&top)[N],
                       const ForeignKey (&mesh)[M]) {
  for (const ForeignKey& k : top)
    if (r.node()[k.key].IsDefined()) r.fail(k.key, k.hint);
  if (!r.has("mesh") || !r.node()["mesh"].IsMap()) return;
  const KeyReader m = r.child("mesh");
  for (const ForeignKey& k : mesh)
    if (m.node()[k.key].IsDefined()) m.fail(k.key, k.hint);
}

/// Calls read(item) for each map in the optional list `key`.
template <class Read>
void forEachItem(const KeyReader& r, const std::string& key, Read read) {
  if (!r.has(key)) return;
  const YAML::Node list = r.list(key, "a list", true);
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (!list[i].IsMap()) r.fail(key, "item " + std::to_string(i) + " is not a map");
    read(KeyReader(list[i], r.dotted(key) + "[" + std::to_string(i) + "]", r.path()));
  }
}

/// The optional 'efg' map: EfgModel settings; efg.spacing [m] is one number, or (benchmark
/// files) a list with one entry per mesh resolution.
void readEfg(const KeyReader& scene, SceneBase& s) {
  if (!scene.has("efg")) return;
  const KeyReader r = scene.child("efg");
  r.onlyKeys({"spacing", "neighbours", "kernel_support", "volume_samples", "rotation",
              "integration_point", "stabilization", "max_cut_triangles"});
  if (r.required("spacing").IsSequence()) {
    s.efg_spacings = r.numbers("spacing");
  } else {
    s.efg_spacings = {r.number("spacing")};
  }
  for (double d : s.efg_spacings) checkRange(r, "spacing", d, 1e-6, 10.0, "m");
  s.efg.spacing = s.efg_spacings.front();
  s.efg.neighbours = r.integer("neighbours", EfgOptions::kMinNeighbours, EfgOptions::kMaxNeighbours,
                               s.efg.neighbours);
  s.efg.kernel_support = r.number("kernel_support", s.efg.kernel_support);
  checkRange(r, "kernel_support", s.efg.kernel_support, 1.1, 10.0, "");
  s.efg.volume_samples =
      r.integer("volume_samples", 1, EfgOptions::kMaxVolumeSamples, s.efg.volume_samples);
  if (r.has("rotation")) s.efg.rotation = readEnum(r, "rotation", kEfgRotationNames);
  s.efg.stabilization = r.number("stabilization", s.efg.stabilization);
  checkRange(r, "stabilization", s.efg.stabilization, 0.0, 1.0, "");
  if (r.has("integration_point"))
    s.efg.ip_at_centroid = r.choice("integration_point", {"centroid", "centre"}) == "centroid";
  s.efg_max_cut_triangles = r.integer("max_cut_triangles", 100, 100000000, s.efg_max_cut_triangles);
}

/// The map `material` under `parent`.
Material readMaterial(const KeyReader& parent) {
  const KeyReader mat = parent.child("material");
  mat.onlyKeys({"young_modulus", "poisson_ratio", "density"});
  const double young_modulus = mat.number("young_modulus");
  const double poisson_ratio = mat.number("poisson_ratio");
  const double density = mat.number("density");
  try {
    return Material::create(young_modulus, poisson_ratio, density);
  } catch (const std::invalid_argument& e) {
    // Material names the parameter "material.<key> = ...".
    const std::string what = e.what();
    const std::string prefix = "material.";
    const std::size_t end = what.find(' ');
    if (what.rfind(prefix, 0) == 0 && end != std::string::npos)
      mat.fail(what.substr(prefix.size(), end - prefix.size()), what);
    mat.fail("young_modulus", what);
  }
}

/// The keys of every scene kind but the body's (mesh, material): time step, gravity, damping,
/// solver settings, fixed regions, tools, tissue pose, efg settings (each optional but the first).
void readShared(const KeyReader& r, SceneBase& s) {
  s.time_step = r.number("time_step");
  checkRange(r, "time_step", s.time_step, 1e-7, 1.0, "s");
  if (r.has("gravity")) s.gravity = r.vector3("gravity");
  checkRange(r, "gravity", s.gravity.norm(), 0.0, 1e4, "m/s^2");
  if (r.has("damping")) {
    const KeyReader d = r.child("damping");
    d.onlyKeys({"mass", "stiffness"});
    s.damping_mass = d.number("mass", 0.0);
    s.damping_stiffness = d.number("stiffness", 0.0);
    checkRange(d, "mass", s.damping_mass, 0.0, 1e6, "1/s");
    checkRange(d, "stiffness", s.damping_stiffness, 0.0, 1e3, "s");
  }
  if (r.has("newton")) {
    const KeyReader n = r.child("newton");
    n.onlyKeys({"max_iterations", "tolerance"});
    s.newton_max_iterations = n.integer("max_iterations", 1, 10000, s.newton_max_iterations);
    s.newton_tolerance = n.number("tolerance", s.newton_tolerance);
    checkRange(n, "tolerance", s.newton_tolerance, 1e-15, 1.0, "");
  }
  if (r.has("pcg")) {
    const KeyReader p = r.child("pcg");
    p.onlyKeys({"max_iterations", "tolerance", "refresh_interval"});
    if (p.has("max_iterations")) s.pcg_max_iterations = p.integer("max_iterations", 1, 100000);
    s.pcg_tolerance = p.number("tolerance", s.pcg_tolerance);
    checkRange(p, "tolerance", s.pcg_tolerance, 1e-15, 1.0, "");
    s.pcg_refresh_interval = p.integer("refresh_interval", 1, 100000, s.pcg_refresh_interval);
  }
  if (r.has("contact")) {
    const KeyReader c = r.child("contact");
    c.onlyKeys({"full_delassus"});
    s.contact_full_delassus = c.choice("full_delassus", {"true", "false"}) == "true";
  }
  forEachItem(r, "fixed", [&](const KeyReader& item) {
    item.onlyKeys({"region", "components"});
    s.fixed.push_back({readRegion(item, "region"), readComponents(item)});
  });
  forEachItem(r, "tools", [&](const KeyReader& item) {
    s.tools.push_back(readTool(item));
    for (std::size_t i = 0; i + 1 < s.tools.size(); ++i)
      if (s.tools[i].name == s.tools.back().name)
        item.fail("name", "duplicate tool name '" + s.tools.back().name + "'");
  });
  if (s.tools.size() > 4) r.fail("tools", "at most 4 tools are supported");
  if (r.has("tissue_pose")) s.tissue_pose = readPose(r, "tissue_pose");
  readEfg(r, s);
}

/// The keys both scene kinds share (mesh geometry without its resolution keys `mesh_keys`).
void readBase(const KeyReader& r, const std::set<std::string>& mesh_keys, SceneBase& s) {
  s.name = r.text("name");
  s.mesh = readMesh(r, mesh_keys);
  s.material = readMaterial(r);
  readShared(r, s);
}

/// Fills the topics a scene left out (docs/scenes.md): a tool held by trocar T talks on T's
/// namespace and takes its jaws from joint T_grip; a free tool uses tool/pose, tissue/wrench,
/// tissue/contact_model and tool/grasp; a tool without contact publishes nothing. Rejects two
/// tools on one topic.
void assignToolTopics(const KeyReader& r, std::vector<ToolSpec>& tools,
                      const std::vector<TrocarSpec>& trocars) {
  for (std::size_t i = 0; i < tools.size(); ++i) {
    ToolSpec& t = tools[i];
    const TrocarSpec* holder = nullptr;
    for (const TrocarSpec& trocar : trocars)
      if (trocar.tool == static_cast<int>(i)) holder = &trocar;
    const std::string ns = holder ? "/" + holder->name + "/" : "";
    const auto fill = [](std::string& topic, const std::string& fallback) {
      if (topic.empty()) topic = fallback;
    };
    fill(t.pose_topic, ns + "tool/pose");
    if (t.contact) {
      fill(t.wrench_topic, ns + "tissue/wrench");
      fill(t.contact_model_topic, ns + "tissue/contact_model");
    }
    if (t.grasp) {
      if (holder && t.grasp->topic.empty()) fill(t.grasp->joint, holder->name + "_grip");
      if (t.grasp->joint.empty()) fill(t.grasp->topic, "tool/grasp");
      if (!t.grasp->joint.empty()) fill(t.grasp->joint_topic, "joint_states");
    }
  }
  const auto unique = [&](const char* key, auto topic_of) {
    for (std::size_t i = 0; i < tools.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (!topic_of(tools[i]).empty() && topic_of(tools[i]) == topic_of(tools[j]))
          r.fail("tools[" + std::to_string(i) + "]." + key,
                 "'" + topic_of(tools[i]) + "' is also the " + key + " of tool '" + tools[j].name +
                     "': give each tool its own topics");
  };
  unique("pose_topic", [](const ToolSpec& t) { return t.pose_topic; });
  unique("wrench_topic", [](const ToolSpec& t) { return t.wrench_topic; });
  unique("contact_model_topic", [](const ToolSpec& t) { return t.contact_model_topic; });
}

TrocarSpec readTrocar(const KeyReader& r, const std::vector<ToolSpec>& tools) {
  r.onlyKeys({"name", "tool", "fulcrum"});
  TrocarSpec t;
  t.name = readIdentifier(r, "name");
  if (t.name == "world" || t.name == "tissue" || t.name == "robot")
    r.fail("name", "'" + t.name + "' is the name of another frame or namespace");
  t.tool = readToolReference(r, "tool", tools);
  t.X_WF = readPose(r, "fulcrum");
  return t;
}

BladeSpec readBlade(const KeyReader& r, const std::vector<ToolSpec>& tools) {
  r.onlyKeys({"tool", "edge"});
  BladeSpec b;
  b.tool = readToolReference(r, "tool", tools);
  const YAML::Node edge = r.list("edge", "a list of [x, y, z] points");
  b.edge.resize(3, static_cast<Eigen::Index>(edge.size()));
  for (std::size_t i = 0; i < edge.size(); ++i) {
    if (!edge[i].IsSequence() || edge[i].size() != 3) r.fail("edge", "each point is [x, y, z]");
    for (int k = 0; k < 3; ++k)
      b.edge(k, static_cast<Eigen::Index>(i)) = r.toNumber(edge[i][k], "edge");
  }
  try {
    validateBladePolyline("edge", b.edge);
  } catch (const std::invalid_argument& e) {
    r.fail("edge", e.what());
  }
  return b;
}

/// The tet4 mesh under `r`.mesh of a body or tet-sampled layer, with its resolution (generated
/// meshes) into `resolution`.
MeshSpec readTetMesh(const KeyReader& r, Eigen::Vector3i& resolution) {
  MeshSpec m = readMesh(r, {"resolution"});
  const KeyReader mesh = r.child("mesh");
  if (isSurfaceGenerator(m.generator))
    mesh.fail("generator", "'" + m.generator + "' makes a closed surface; a body needs a tet mesh");
  if (m.generator != "file") {
    resolution = readResolution(mesh, "resolution", mesh.required("resolution"), m.generator);
    checkBudget(mesh, "resolution", m, resolution, ElementType::Tet4);
  } else if (mesh.has("resolution")) {
    mesh.fail("resolution", "a mesh file has its own resolution");
  }
  return m;
}

/// The optional list of regions `fixed` (items {region: {min, max}}).
std::vector<Region> readFixedRegions(const KeyReader& r) {
  std::vector<Region> regions;
  forEachItem(r, "fixed", [&](const KeyReader& item) {
    item.onlyKeys({"region"});
    regions.push_back(readRegion(item, "region"));
  });
  return regions;
}

/// The optional rgb `colour` (each in [0, 1]), else `fallback`.
Eigen::Vector3f readColour(const KeyReader& r, const Eigen::Vector3f& fallback) {
  if (!r.has("colour")) return fallback;
  const Eigen::Vector3d c = r.vector3("colour");
  for (int i = 0; i < 3; ++i) checkRange(r, "colour", c[i], 0.0, 1.0, "");
  return c.cast<float>();
}

BodySpec readBody(const KeyReader& r) {
  r.onlyKeys({"name", "mesh", "model", "material", "pose", "fixed", "colour"});
  BodySpec b;
  b.name = readIdentifier(r, "name");
  b.mesh = readTetMesh(r, b.resolution);
  b.model = readEnum(r, "model", kModelNames);
  if (b.model == ModelKind::Efg)
    r.fail("model", "a body of a multi-body scene needs a tet model (not efg)");
  b.material = readMaterial(r);
  if (r.has("pose")) b.pose = readPose(r, "pose");
  b.fixed = readFixedRegions(r);
  b.colour = readColour(r, b.colour);
  return b;
}

ConnectiveSpec readConnective(const KeyReader& r, const std::vector<BodySpec>& bodies) {
  ConnectiveSpec c;
  c.sampling = r.choice("sampling", {"tet_mesh", "poisson_disk"});
  const std::set<std::string> common = {"name",  "sampling",    "material",
                                        "fixed", "attachments", "colour"};
  std::set<std::string> known = common;
  if (c.sampling == "tet_mesh") {
    known.insert("mesh");
  } else {
    known.insert({"hexahedron", "node_spacing", "sample_spacing", "neighbours", "seed"});
  }
  for (const auto& kv : r.node()) {
    const std::string key = kv.first.as<std::string>();
    if (!known.count(key) && (key == "mesh" || key == "hexahedron" || key == "node_spacing" ||
                              key == "sample_spacing" || key == "neighbours" || key == "seed"))
      r.fail(key, "does not apply to sampling " + c.sampling);
  }
  r.onlyKeys(known);
  c.name = readIdentifier(r, "name");
  if (c.sampling == "tet_mesh") {
    c.mesh = readTetMesh(r, c.resolution);
  } else {
    const YAML::Node corners = r.list("hexahedron", "a list of 8 [x, y, z] corners");
    if (corners.size() != 8) r.fail("hexahedron", "expected a list of 8 [x, y, z] corners");
    for (const auto& corner : corners) {
      if (!corner.IsSequence() || corner.size() != 3)
        r.fail("hexahedron", "each corner is [x, y, z]");
      Eigen::Vector3d p;
      for (int k = 0; k < 3; ++k) p[k] = r.toNumber(corner[k], "hexahedron");
      c.hexahedron.push_back(p);
    }
    c.node_spacing = r.number("node_spacing");
    checkRange(r, "node_spacing", c.node_spacing, 1e-4, 1.0, "m");
    c.sample_spacing = r.number("sample_spacing");
    checkRange(r, "sample_spacing", c.sample_spacing, 5e-5, c.node_spacing, "m");
    if (c.sample_spacing == c.node_spacing)
      r.fail("sample_spacing", "must be smaller than node_spacing");
    // Poisson-disk points fill the hexahedron's bounding box at most at one point per spacing^3.
    Eigen::AlignedBox3d box;
    for (const Eigen::Vector3d& p : c.hexahedron) box.extend(p);
    const double volume = box.volume();
    if (!std::isfinite(volume)) r.fail("hexahedron", "corners must be finite");
    const auto checkCount = [&](const char* key, double spacing, double limit) {
      const double count = volume / (spacing * spacing * spacing);
      if (count > limit)
        r.fail(key, "about " + std::to_string(static_cast<long long>(count)) +
                        " points in the hexahedron's bounding box; at most " +
                        std::to_string(static_cast<long long>(limit)) + " are supported");
    };
    checkCount("node_spacing", c.node_spacing, kMaxLayerRigidNodes);
    checkCount("sample_spacing", c.sample_spacing, kMaxLayerSamples);
    c.neighbours = r.integer("neighbours", 1, kMaxSampleNeighbours, c.neighbours);
    c.seed = r.integer("seed", 0, std::numeric_limits<int>::max(), c.seed);
  }
  c.material = readMaterial(r);
  c.fixed = readFixedRegions(r);
  std::vector<bool> used(bodies.size(), false);
  forEachItem(r, "attachments", [&](const KeyReader& item) {
    item.onlyKeys({"body", "distance", "neighbours"});
    AttachmentSpec a;
    const std::string body = item.text("body");
    a.body = -1;
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].name == body) a.body = static_cast<int>(i);
    if (a.body < 0) item.fail("body", "no body is named '" + body + "'");
    if (used[static_cast<std::size_t>(a.body)])
      item.fail("body", "body '" + body + "' is already attached to this layer");
    used[static_cast<std::size_t>(a.body)] = true;
    a.distance = item.number("distance", a.distance);
    checkRange(item, "distance", a.distance, 1e-9, 0.01, "m");
    a.neighbours = item.integer("neighbours", 1, kMaxSampleNeighbours, a.neighbours);
    c.attachments.push_back(a);
  });
  if (c.attachments.empty()) r.fail("attachments", "missing required key: a layer joins bodies");
  c.colour = readColour(r, c.colour);
  return c;
}

/// A multi-body scene (key 'bodies'): the single-body keys are rejected.
RuntimeScene parseMultiBody(const KeyReader& r) {
  for (const char* key : {"mesh", "material", "model", "integrator", "solver", "fixed", "newton",
                          "pcg", "efg", "contact", "trocars", "blades", "robot"})
    if (r.has(key))
      r.fail(key, "a multi-body scene (key 'bodies') has no top-level '" + std::string(key) +
                      "': each body and connective layer has its own mesh, material and fixed "
                      "regions");
  r.onlyKeys({"name", "description", "time_step", "gravity", "damping", "tools", "tissue_pose",
              "bodies", "connective"});
  RuntimeScene s;
  s.path = r.path();
  s.name = r.text("name");
  readShared(r, s);
  std::set<std::string> names;
  const auto unique = [&](const KeyReader& item, const std::string& name) {
    if (!names.insert(name).second)
      item.fail("name", "duplicate name '" + name + "' (bodies and layers share one namespace)");
  };
  r.list("bodies", "a non-empty list of bodies");
  forEachItem(r, "bodies", [&](const KeyReader& item) {
    s.bodies.push_back(readBody(item));
    unique(item, s.bodies.back().name);
  });
  if (s.bodies.size() > 16) r.fail("bodies", "at most 16 bodies are supported");
  forEachItem(r, "connective", [&](const KeyReader& item) {
    s.connective.push_back(readConnective(item, s.bodies));
    unique(item, s.connective.back().name);
  });
  if (s.connective.size() > 16) r.fail("connective", "at most 16 layers are supported");
  assignToolTopics(r, s.tools, s.trocars);
  return s;
}

RuntimeScene parseRuntime(const YAML::Node& root, const std::string& path) {
  const KeyReader r(root, "", path);
  rejectForeignKeys(r, kBenchmarkKeys, kBenchmarkMeshKeys);
  if (r.has("bodies")) return parseMultiBody(r);
  r.onlyKeys({"name",      "description", "mesh",    "material",    "model", "integrator", "solver",
              "time_step", "gravity",     "damping", "newton",      "pcg",   "fixed",      "tools",
              "trocars",   "blades",      "robot",   "tissue_pose", "efg",   "contact"});
  RuntimeScene s;
  s.path = path;
  readBase(r, {"resolution", "element_type"}, s);
  const KeyReader mesh = r.child("mesh");
  if (s.mesh.generator != "file") {
    s.resolution =
        readResolution(mesh, "resolution", mesh.required("resolution"), s.mesh.generator);
  } else if (mesh.has("resolution")) {
    mesh.fail("resolution", "a mesh file has its own resolution");
  }
  if (mesh.has("element_type")) {
    if (isSurfaceGenerator(s.mesh.generator))
      mesh.fail("element_type", "the liver generator makes a closed surface, without elements");
    s.element_type = elementType(mesh.choice("element_type", {"tet4", "tet10"}));
  }
  checkBudget(mesh, "resolution", s.mesh, s.resolution, s.element_type);
  s.model = readEnum(r, "model", kModelNames);
  if (isSurfaceGenerator(s.mesh.generator) && s.model != ModelKind::Efg) {
    r.fail("model", std::string(modelName(s.model)) +
                        " needs a tet mesh; mesh.generator liver is a closed surface, which only "
                        "model efg fills");
  }
  if (linearTetOnly(s.model) && s.element_type == ElementType::Tet10)
    r.fail("model", std::string(modelName(s.model)) + " is defined on tet4 meshes only");
  if (s.model == ModelKind::Efg && s.efg_spacings.empty())
    r.fail("efg", "model efg needs 'efg: {spacing: <m>}'");
  if (s.efg_spacings.size() > 1) r.fail("efg", "a runtime scene takes one efg.spacing, not a list");
  s.integrator = readEnum(r, "integrator", kIntegratorNames);
  s.solver = readEnum(r, "solver", kSolverNames);

  std::vector<bool> held(s.tools.size(), false);
  forEachItem(r, "trocars", [&](const KeyReader& item) {
    s.trocars.push_back(readTrocar(item, s.tools));
    const TrocarSpec& t = s.trocars.back();
    for (std::size_t i = 0; i + 1 < s.trocars.size(); ++i)
      if (s.trocars[i].name == t.name) item.fail("name", "duplicate trocar name '" + t.name + "'");
    if (held[static_cast<std::size_t>(t.tool)])
      item.fail("tool", "tool '" + s.tools[static_cast<std::size_t>(t.tool)].name +
                            "' is already held by another trocar");
    held[static_cast<std::size_t>(t.tool)] = true;
  });
  if (s.trocars.size() > 4) r.fail("trocars", "at most 4 trocars are supported");
  forEachItem(r, "blades", [&](const KeyReader& item) {
    s.blades.push_back(readBlade(item, s.tools));
    for (std::size_t i = 0; i + 1 < s.blades.size(); ++i)
      if (s.blades[i].tool == s.blades.back().tool)
        item.fail("tool", "tool '" + s.tools[static_cast<std::size_t>(s.blades.back().tool)].name +
                              "' already carries a blade");
  });
  if (r.has("robot")) {
    const KeyReader robot = r.child("robot");
    robot.onlyKeys({"description", "base_pose"});
    RobotSpec spec;
    spec.description = readIdentifier(robot, "description");
    if (robot.has("base_pose")) spec.X_WB = readPose(robot, "base_pose");
    s.robot = spec;
  }
  assignToolTopics(r, s.tools, s.trocars);
  return s;
}

/// `base` with `overlay` laid over it: maps merge key by key (recursively), anything else
/// (scalars, lists) replaces. `base` is not changed.
YAML::Node overlaid(const YAML::Node& base, const YAML::Node& overlay) {
  if (!base.IsMap() || !overlay.IsMap()) return YAML::Clone(overlay);
  YAML::Node merged = YAML::Clone(base);
  for (const auto& entry : overlay) {
    const std::string key = entry.first.as<std::string>();
    merged[key] =
        merged[key].IsDefined() ? overlaid(merged[key], entry.second) : YAML::Clone(entry.second);
  }
  return merged;
}

BenchmarkScene parseBenchmark(const YAML::Node& root, const std::string& path);

/// The dotted paths of the leaves (non-map values) of `node` under `prefix`, appended to `out`.
void appendLeafKeys(const YAML::Node& node, const std::string& prefix,
                    std::vector<std::string>& out) {
  if (!node.IsMap()) {
    out.push_back(prefix);
    return;
  }
  for (const auto& entry : node) {
    const std::string key = entry.first.as<std::string>();
    appendLeafKeys(entry.second, prefix.empty() ? key : prefix + "." + key, out);
  }
}

/// The optional 'variants' list: each item a name and keys laid over the rest of the file
/// (overlaid()), parsed as a whole benchmark file of its own.
std::vector<BenchmarkVariant> readVariants(const KeyReader& r, const YAML::Node& root,
                                           const std::string& path) {
  std::vector<BenchmarkVariant> variants;
  YAML::Node base = YAML::Clone(root);
  base.remove("variants");
  forEachItem(r, "variants", [&](const KeyReader& item) {
    const std::string name = readIdentifier(item, "name");
    for (const BenchmarkVariant& v : variants)
      if (v.name == name) item.fail("name", "duplicate variant name '" + name + "'");
    if (item.has("variants")) item.fail("variants", "a variant cannot have variants");
    YAML::Node overlay = YAML::Clone(item.node());
    overlay.remove("name");
    try {
      variants.push_back({name, parseBenchmark(overlaid(base, overlay), path), {}});
      appendLeafKeys(overlay, "", variants.back().keys);
    } catch (const std::invalid_argument& e) {
      item.fail("name", "variant '" + name + "' with its keys laid over the file: " + e.what());
    }
  });
  if (r.has("variants") && variants.empty()) r.fail("variants", "must list at least one variant");
  return variants;
}

BenchmarkScene parseBenchmark(const YAML::Node& root, const std::string& path) {
  const KeyReader r(root, "", path);
  rejectForeignKeys(r, kRuntimeKeys, kRuntimeMeshKeys);
  r.onlyKeys({"name",        "description", "mesh",     "material",     "models",  "integrators",
              "solvers",     "time_step",   "steps",    "load_factors", "gravity", "damping",
              "newton",      "pcg",         "fixed",    "prescribed",   "measure", "tools",
              "tissue_pose", "efg",         "variants", "threads",      "contact"});
  BenchmarkScene s;
  s.path = path;
  readBase(r, {"resolutions", "element_types"}, s);
  const KeyReader mesh = r.child("mesh");
  if (isSurfaceGenerator(s.mesh.generator))
    mesh.fail("generator",
              "liver (a closed surface) is for runtime efg scenes; a benchmark "
              "file needs a tet mesh");
  if (s.mesh.generator == "file") {
    s.resolutions = {Eigen::Vector3i::Zero()};
  } else {
    for (const auto& item :
         mesh.list("resolutions", "a non-empty list of [nx, ny, nz] cell counts"))
      s.resolutions.push_back(readResolution(mesh, "resolutions", item, s.mesh.generator));
  }
  for (const auto& t : mesh.has("element_types") ? mesh.choices("element_types", {"tet4", "tet10"})
                                                 : std::vector<std::string>{"tet4"})
    s.element_types.push_back(elementType(t));
  for (const Eigen::Vector3i& res : s.resolutions)
    for (ElementType type : s.element_types) checkBudget(mesh, "resolutions", s.mesh, res, type);
  s.models = readEnums(r, "models", kModelNames);
  if (std::count(s.models.begin(), s.models.end(), ModelKind::Efg) > 0 && s.efg_spacings.empty())
    r.fail("efg", "model efg needs 'efg: {spacing: <m>}'");
  if (s.efg_spacings.size() > 1 && s.efg_spacings.size() != s.resolutions.size())
    r.fail("efg", "efg.spacing lists " + std::to_string(s.efg_spacings.size()) +
                      " values: give one, or one per mesh.resolutions entry (" +
                      std::to_string(s.resolutions.size()) + ")");
  s.integrators = readEnums(r, "integrators", kIntegratorNames);
  s.solvers = readEnums(r, "solvers", kSolverNames);
  s.steps = r.integer("steps", 1, 1000000);
  if (r.has("threads")) s.threads = r.integer("threads", 1, kMaxThreads);
  if (r.has("load_factors")) s.load_factors = r.numbers("load_factors");
  for (double f : s.load_factors)
    checkRange(r, "load_factors", f, -kMaxLoadFactor, kMaxLoadFactor, "");
  forEachItem(r, "prescribed", [&](const KeyReader& item) {
    item.onlyKeys({"region", "components", "displacement"});
    s.prescribed.push_back(
        {readRegion(item, "region"), readComponents(item), item.vector3("displacement")});
    checkRange(item, "displacement", s.prescribed.back().displacement.norm(), 0.0, kMaxDisplacement,
               "m (magnitude)");
  });
  s.measure = readMeasure(r);
  assignToolTopics(r, s.tools, {});
  if (s.measure.type == "uniaxial_svk_force" && (s.prescribed.empty() || s.load_factors.empty()))
    r.fail("measure", "uniaxial_svk_force needs 'prescribed' and 'load_factors'");
  if (!s.measure.reference_formula.empty() && s.gravity[s.measure.component] == 0.0)
    r.fail("gravity", "measure.reference_formula '" + s.measure.reference_formula +
                          "' needs a non-zero gravity component along measure.component");
  s.variants = readVariants(r, root, path);
  return s;
}

/// Parses YAML text into a scene of the kind `parse` reads (errors named as in loadRuntimeScene).
template <class Parse>
auto parseText(const std::string& yaml_text, const std::string& path, Parse parse) {
  if (yaml_text.size() > kMaxSceneBytes)
    throw std::invalid_argument("scene " + path + ": the file has " +
                                std::to_string(yaml_text.size()) +
                                " bytes, more than the limit of " + std::to_string(kMaxSceneBytes));
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::DeepRecursion& e) {
    throw std::invalid_argument("scene " + path + ": " + syntaxErrorPlace(yaml_text, e.mark.line) +
                                ": nested more than " + std::to_string(e.depth() - 1) +
                                " levels deep");
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument("scene " + path + ": " + syntaxErrorPlace(yaml_text, e.mark.line) +
                                ": " + e.msg);
  }
  if (!root.IsMap())
    throw std::invalid_argument("scene " + path + ": the file is not a YAML map of keys");
  long long visited = 0;
  rejectDuplicateKeys(root, "", path, visited);
  try {
    return parse(root, path);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument("scene " + path + ": malformed value at line " +
                                std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("scene " + path + ": cannot open file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace

MeshSizeEstimate estimateMeshSize(const MeshSpec& spec, const Eigen::Vector3i& resolution,
                                  ElementType type) {
  MeshSizeEstimate e;
  const Eigen::Vector3d cells = resolution.cast<double>();
  if (spec.generator == "box" || spec.generator == "beam") {
    e.nodes = (cells.array() + 1.0).prod();
    e.elements = 6.0 * cells.prod();
  } else if (spec.generator == "organ_blob") {
    e.nodes = std::pow(cells[0] + 1.0, 3);
    e.elements = 6.0 * std::pow(cells[0], 3);
  } else if (spec.generator == "liver") {
    e.nodes = 10.0 * std::pow(4.0, cells[0]) + 2.0;  // surface vertices, no elements
  } else if (spec.generator == "hex_beam") {
    const double rings = cells[1];
    e.nodes = (3.0 * rings * (rings + 1.0) + 1.0) * (cells[0] + 1.0);
    e.elements = 18.0 * rings * rings * cells[0];
  } else {
    return e;  // a mesh file: bounded by the file size
  }
  const int t = type == ElementType::Tet4 ? 0 : 1;
  if (type == ElementType::Tet10) e.nodes *= 8.0;  // corners plus one node per edge
  e.bytes = kBytesPerNode[t] * e.nodes + kBytesPerElement[t] * e.elements;
  return e;
}

std::string meshBudgetProblem(const MeshSpec& spec, const Eigen::Vector3i& resolution,
                              ElementType type) {
  const MeshSizeEstimate e = estimateMeshSize(spec, resolution, type);
  if (e.bytes <= kSceneMemoryBudgetBytes) return "";
  std::ostringstream s;
  s.precision(3);
  s << "resolution [" << resolution[0] << ", " << resolution[1] << ", " << resolution[2]
    << "] with " << toString(type) << " needs about " << e.bytes / 1e9 << " GB (" << e.nodes
    << " nodes, " << e.elements << " elements), above the budget of "
    << kSceneMemoryBudgetBytes / 1e9 << " GB";
  return s.str();
}

RuntimeScene parseRuntimeScene(const std::string& yaml_text, const std::string& path) {
  return parseText(yaml_text, path, parseRuntime);
}

RuntimeScene loadRuntimeScene(const std::string& path) {
  return parseRuntimeScene(readFile(path), path);
}

BenchmarkScene parseBenchmarkScene(const std::string& yaml_text, const std::string& path) {
  return parseText(yaml_text, path, parseBenchmark);
}

BenchmarkScene loadBenchmarkScene(const std::string& path) {
  return parseBenchmarkScene(readFile(path), path);
}

}  // namespace surgical_sim::core
