#include "surgical_sim/core/scene/scene_urdf.h"

#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <cctype>
#include <set>
#include <stdexcept>

#include "surgical_sim/core/common/number_text.h"
#include "surgical_sim/core/robot/continuum_robot_urdf.h"

namespace surgical_sim::core {
namespace {

bool isIdentifier(const std::string& name) {
  if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) return false;
  for (const char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

/// Contract prefixing: trocar -> T, trocar_x -> T_x, other x -> T_x.
std::string prefixed(const std::string& name, const std::string& trocar) {
  if (name == "trocar") return trocar;
  if (name.rfind("trocar_", 0) == 0) return trocar + name.substr(6);
  return trocar + "_" + name;
}

void prefixAttribute(TiXmlElement* element, const char* attribute, const std::string& trocar) {
  if (element && element->Attribute(attribute))
    element->SetAttribute(attribute, prefixed(element->Attribute(attribute), trocar));
}

/// Parses `text` as a <robot> document.
void parseRobot(TiXmlDocument& document, const std::string& text, const std::string& what) {
  document.Parse(text.c_str());
  if (document.Error() || !document.RootElement() || document.RootElement()->ValueStr() != "robot")
    throw std::invalid_argument("scene URDF: " + what + " is not a URDF <robot> document" +
                                (document.Error() ? std::string(": ") + document.ErrorDesc() : ""));
}

/// Appends copies of the <material> elements of `source` whose names `robot` lacks.
void appendMaterials(TiXmlElement& robot, const TiXmlElement& source,
                     std::set<std::string>& materials) {
  for (const TiXmlElement* e = source.FirstChildElement("material"); e;
       e = e->NextSiblingElement("material"))
    if (e->Attribute("name") && materials.insert(e->Attribute("name")).second)
      robot.InsertEndChild(*e);
}

void appendFixedJoint(TiXmlElement& robot, const std::string& name, const std::string& parent,
                      const std::string& child, const Eigen::Isometry3d& X,
                      const std::string& what) {
  const Eigen::Matrix3d R = X.linear();
  if (!X.matrix().allFinite() || !(R.transpose() * R).isApprox(Eigen::Matrix3d::Identity(), 1e-9) ||
      R.determinant() < 0.0)
    throw std::invalid_argument("scene URDF: " + what +
                                " is out of range: must be a finite rigid transform (rotation "
                                "orthonormal, det +1)");
  // URDF rpy: R = Rz(yaw) Ry(pitch) Rx(roll).
  const Eigen::Vector3d ypr = R.eulerAngles(2, 1, 0);
  const Eigen::Vector3d p = X.translation();
  TiXmlElement joint("joint");
  joint.SetAttribute("name", name);
  joint.SetAttribute("type", "fixed");
  TiXmlElement parent_element("parent"), child_element("child"), origin("origin");
  parent_element.SetAttribute("link", parent);
  child_element.SetAttribute("link", child);
  origin.SetAttribute("xyz", numberText(p.x()) + " " + numberText(p.y()) + " " + numberText(p.z()));
  origin.SetAttribute("rpy",
                      numberText(ypr[2]) + " " + numberText(ypr[1]) + " " + numberText(ypr[0]));
  joint.InsertEndChild(parent_element);
  joint.InsertEndChild(child_element);
  joint.InsertEndChild(origin);
  robot.InsertEndChild(joint);
}

}  // namespace

std::string sceneUrdf(const std::vector<TrocarPlacement>& trocars,
                      const std::optional<RobotPlacement>& robot, const std::string& trocar_urdf,
                      const std::vector<ContinuumRobotDescription>& robots) {
  TiXmlElement scene("robot");
  scene.SetAttribute("name", "scene");
  TiXmlElement world("link");
  world.SetAttribute("name", "world");
  scene.InsertEndChild(world);
  std::set<std::string> materials, names;

  if (!trocars.empty()) {
    TiXmlDocument source;
    parseRobot(source, trocar_urdf, "the trocar URDF");
    const TiXmlElement& root = *source.RootElement();
    appendMaterials(scene, root, materials);
    for (const TrocarPlacement& trocar : trocars) {
      const std::string& T = trocar.name;
      if (!isIdentifier(T) || T == "world")
        throw std::invalid_argument("scene URDF: trocar name '" + T +
                                    "' is invalid: must match [A-Za-z][A-Za-z0-9_]* and not be "
                                    "'world'");
      if (!names.insert(T).second)
        throw std::invalid_argument("scene URDF: trocar name '" + T + "' appears twice");
      appendFixedJoint(scene, "world_to_" + T, "world", T, trocar.X_WF,
                       "pose of trocar '" + T + "'");
      for (const TiXmlElement* e = root.FirstChildElement(); e; e = e->NextSiblingElement()) {
        if (e->ValueStr() != "link" && e->ValueStr() != "joint") continue;
        TiXmlElement copy(*e);
        prefixAttribute(&copy, "name", T);
        prefixAttribute(copy.FirstChildElement("parent"), "link", T);
        prefixAttribute(copy.FirstChildElement("child"), "link", T);
        prefixAttribute(copy.FirstChildElement("mimic"), "joint", T);
        scene.InsertEndChild(copy);
      }
    }
  }

  if (robot) {
    const ContinuumRobotDescription* description = nullptr;
    std::string known;
    for (const ContinuumRobotDescription& d : robots) {
      if (d.name == robot->description) description = &d;
      known += (known.empty() ? "" : ", ") + d.name;
    }
    if (!description)
      throw std::invalid_argument("scene URDF: robot description '" + robot->description +
                                  "' is unknown (known: " + known + ")");
    const ContinuumRobotFrames frames;
    appendFixedJoint(scene, "world_to_" + frames.base, "world", frames.base, robot->X_WB,
                     "robot base pose");
    TiXmlDocument source;
    parseRobot(source, continuumRobotUrdf(*description, frames), "the robot URDF");
    const TiXmlElement& root = *source.RootElement();
    appendMaterials(scene, root, materials);
    for (const TiXmlElement* e = root.FirstChildElement(); e; e = e->NextSiblingElement())
      if (e->ValueStr() == "link" || e->ValueStr() == "joint") scene.InsertEndChild(*e);
  }

  TiXmlDocument document;
  document.InsertEndChild(TiXmlDeclaration("1.0", "", ""));
  document.InsertEndChild(TiXmlComment(
      " Scene URDF generated by surgical_sim (core::sceneUrdf): trocars and robot in world. "));
  document.InsertEndChild(scene);
  TiXmlPrinter printer;
  printer.SetIndent("  ");
  document.Accept(&printer);
  const std::string text = printer.Str();
  if (!urdf::parseURDF(text))
    throw std::invalid_argument(
        "scene URDF: urdfdom rejects the assembled URDF (its reason is printed above; e.g. a "
        "trocar name that clashes with a robot link)");
  return text;
}

}  // namespace surgical_sim::core
