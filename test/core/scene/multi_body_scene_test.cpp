// Scene keys of multi-body scenes (bodies, connective): parsing, defaults and validation.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "surgical_sim/core/scene/multi_body_simulation.h"
#include "surgical_sim/core/scene/scene_config.h"

namespace surgical_sim::core {
namespace {

/// Two 2 x 2 x 1 cm boxes joined by a 5 mm tet-sampled layer, and a Poisson-disk layer filling
/// a 4 mm gap on their other side.
const std::string kScene =
    "name: keys\n"
    "time_step: 0.01\n"
    "bodies:\n"
    "  - name: lower\n"
    "    mesh: {generator: box, size: [0.02, 0.02, 0.01], resolution: [2, 2, 1]}\n"
    "    model: corotational\n"
    "    material: {young_modulus: 1.0e4, poisson_ratio: 0.3, density: 1000.0}\n"
    "    fixed:\n"
    "      - region: {max: [.inf, .inf, 1.0e-9]}\n"
    "  - name: upper\n"
    "    mesh: {generator: box, size: [0.02, 0.02, 0.01], resolution: [2, 2, 1]}\n"
    "    model: svk\n"
    "    material: {young_modulus: 1.0e4, poisson_ratio: 0.3, density: 1000.0}\n"
    "    pose: {position: [0.0, 0.0, 0.015], rpy: [0.0, 0.0, 0.0]}\n"
    "    colour: [0.2, 0.4, 0.6]\n"
    "  - name: side\n"
    "    mesh: {generator: box, size: [0.02, 0.02, 0.01], resolution: [2, 2, 1]}\n"
    "    model: corotational\n"
    "    material: {young_modulus: 1.0e4, poisson_ratio: 0.3, density: 1000.0}\n"
    "    pose: {position: [0.024, 0.0, 0.0], rpy: [0.0, 0.0, 0.0]}\n"
    "connective:\n"
    "  - name: sheet\n"
    "    sampling: tet_mesh\n"
    "    mesh: {generator: box, origin: [0.0, 0.0, 0.01], size: [0.02, 0.02, 0.005], "
    "resolution: [2, 2, 1]}\n"
    "    material: {young_modulus: 5.0e3, poisson_ratio: 0.3, density: 1000.0}\n"
    "    attachments:\n"
    "      - {body: lower}\n"
    "      - {body: upper, distance: 1.0e-5, neighbours: 3}\n"
    "  - name: gap\n"
    "    sampling: poisson_disk\n"
    "    hexahedron: [[0.02, 0, 0], [0.024, 0, 0], [0.02, 0.02, 0], [0.024, 0.02, 0],\n"
    "                 [0.02, 0, 0.01], [0.024, 0, 0.01], [0.02, 0.02, 0.01], [0.024, 0.02, 0.01]]\n"
    "    node_spacing: 0.004\n"
    "    sample_spacing: 0.002\n"
    "    neighbours: 4\n"
    "    seed: 7\n"
    "    material: {young_modulus: 5.0e3, poisson_ratio: 0.3, density: 1000.0}\n"
    "    fixed:\n"
    "      - region: {max: [.inf, .inf, 0.001]}\n"
    "    attachments:\n"
    "      - {body: side}\n"
    "    colour: [1.0, 1.0, 0.0]\n";

std::string replaced(const std::string& from, const std::string& to) {
  const std::size_t at = kScene.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  std::string out = kScene;
  if (at != std::string::npos) out.replace(at, from.size(), to);
  return out;
}

/// The message of the rejection of `text` (parsed, then built), or "accepted".
std::string rejection(const std::string& text) {
  try {
    MultiBodySimulation simulation(parseRuntimeScene(text, "keys.yaml"));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

/// `text` is rejected with a message containing every part of `parts`.
void expectRejected(const std::string& text, std::initializer_list<const char*> parts) {
  const std::string message = rejection(text);
  for (const char* part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
}

TEST(MultiBodySceneKeys, ParsedWithDefaults) {
  const RuntimeScene s = parseRuntimeScene(kScene, "keys.yaml");
  ASSERT_EQ(s.bodies.size(), 3u);
  ASSERT_EQ(s.connective.size(), 2u);
  EXPECT_EQ(s.bodies[0].model, ModelKind::Corotational);
  EXPECT_EQ(s.bodies[1].model, ModelKind::Svk);
  EXPECT_EQ(s.bodies[1].pose.translation(), Eigen::Vector3d(0, 0, 0.015));
  EXPECT_EQ(s.bodies[0].colour, Eigen::Vector3f(0.95f, 0.65f, 0.65f));  // default
  EXPECT_EQ(s.bodies[1].colour, Eigen::Vector3f(0.2f, 0.4f, 0.6f));
  ASSERT_EQ(s.bodies[0].fixed.size(), 1u);
  EXPECT_EQ(s.connective[0].sampling, "tet_mesh");
  ASSERT_EQ(s.connective[0].attachments.size(), 2u);
  EXPECT_EQ(s.connective[0].attachments[0].distance, 1e-4);  // default
  EXPECT_EQ(s.connective[0].attachments[0].neighbours, 4);   // default
  EXPECT_EQ(s.connective[0].attachments[1].body, 1);
  EXPECT_EQ(s.connective[0].attachments[1].distance, 1e-5);
  EXPECT_EQ(s.connective[0].attachments[1].neighbours, 3);
  EXPECT_EQ(s.connective[1].hexahedron.size(), 8u);
  EXPECT_EQ(s.connective[1].node_spacing, 0.004);
  EXPECT_EQ(s.connective[1].seed, 7);
  EXPECT_TRUE(s.mesh.generator.empty());

  const MultiBodySimulation simulation(s);
  EXPECT_EQ(simulation.numBodies(), 3);
  EXPECT_EQ(simulation.numLayers(), 2);
  // The gap layer's rigid nodes at z <= 1 mm are held, and some are free.
  EXPECT_GT(simulation.coupling().layer(1).fixed_nodes.size(), 0u);
  EXPECT_LT(static_cast<int>(simulation.coupling().layer(1).fixed_nodes.size()),
            simulation.layer(1).numNodes());
  // The lower box's top face and the upper box's bottom face are attached to the sheet.
  int attached_lower = 0, attached_upper = 0;
  for (int a = 0; a < simulation.bodyMesh(0).numNodes(); ++a)
    attached_lower += simulation.coupling().attached(0, a);
  for (int a = 0; a < simulation.bodyMesh(1).numNodes(); ++a)
    attached_upper += simulation.coupling().attached(1, a);
  EXPECT_EQ(attached_lower, 9);
  EXPECT_EQ(attached_upper, 9);
}

TEST(MultiBodySceneKeys, SingleBodyKeysAreRejectedBesideBodies) {
  for (const char* key : {"mesh", "material", "model", "integrator", "solver", "fixed", "efg"})
    expectRejected(replaced("time_step: 0.01\n", std::string("time_step: 0.01\n") + key + ": x\n"),
                   {(std::string("key '") + key + "'").c_str(), "multi-body scene"});
  expectRejected(replaced("time_step: 0.01\n", "time_step: 0.01\nbogus: 1\n"),
                 {"key 'bogus'", "unknown key"});
  expectRejected("name: empty\ntime_step: 0.01\nbodies: []\n",
                 {"key 'bodies'", "expected a non-empty list of bodies"});
}

TEST(MultiBodySceneKeys, BadBodyKeysAreRejectedNamingTheKey) {
  expectRejected(replaced("name: lower", "name: 1lower"), {"key 'bodies[0].name'"});
  expectRejected(replaced("name: upper", "name: lower"),
                 {"key 'bodies[1].name'", "duplicate name 'lower'"});
  expectRejected(replaced("generator: box, size: [0.02, 0.02, 0.01], resolution: [2, 2, 1]}\n"
                          "    model: svk",
                          "generator: liver, size: [0.02, 0.02, 0.01], resolution: [2, 0, 0]}\n"
                          "    model: svk"),
                 {"key 'bodies[1].mesh.generator'", "closed surface"});
  expectRejected(
      replaced("0.01], resolution: [2, 2, 1]}\n    model: svk", "0.01]}\n    model: svk"),
      {"key 'bodies[1].mesh.resolution'", "missing"});
  expectRejected(replaced("model: svk", "model: efg"), {"key 'bodies[1].model'", "not efg"});
  expectRejected(replaced("model: svk", "model: rubber"), {"key 'bodies[1].model'"});
  expectRejected(replaced("model: svk\n    material: {young_modulus: 1.0e4",
                          "model: svk\n    material: {young_modulus: -1.0"),
                 {"key 'bodies[1].material.young_modulus'"});
  expectRejected(
      replaced("rpy: [0.0, 0.0, 0.0]}\n    colour", "rpy: [0.0, .nan, 0.0]}\n    colour"),
      {"key 'bodies[1].pose.rpy'"});
  expectRejected(replaced("{max: [.inf, .inf, 1.0e-9]}", "{min: [0, 0, 1], max: [1, 1, 0]}"),
                 {"key 'bodies[0].fixed[0].region.min'", "min exceeds max"});
  expectRejected(replaced("region: {max: [.inf, .inf, 1.0e-9]}",
                          "region: {max: [.inf, .inf, 1.0e-9]}\n        components: [x]"),
                 {"key 'bodies[0].fixed[0].components'", "unknown key"});
  expectRejected(replaced("{max: [.inf, .inf, 1.0e-9]}", "{max: [.inf, .inf, -1.0]}"),
                 {"key 'bodies[0].fixed[0].region'", "contains no node"});
  expectRejected(replaced("colour: [0.2, 0.4, 0.6]", "colour: [1.5, 0.4, 0.6]"),
                 {"key 'bodies[1].colour'", "1.5 is out of range [0, 1]"});
}

TEST(MultiBodySceneKeys, BadLayerKeysAreRejectedNamingTheKey) {
  expectRejected(replaced("sampling: tet_mesh", "sampling: voxels"),
                 {"key 'connective[0].sampling'", "'voxels' is not one of"});
  expectRejected(replaced("    mesh: {generator: box, origin: [0.0, 0.0, 0.01], size: [0.02, 0.02, "
                          "0.005], resolution: [2, 2, 1]}\n",
                          ""),
                 {"key 'connective[0].mesh'"});
  expectRejected(replaced("material: {young_modulus: 5.0e3, poisson_ratio: 0.3",
                          "material: {young_modulus: 5.0e3, poisson_ratio: 0.5"),
                 {"key 'connective[0].material.poisson_ratio'"});
  expectRejected(replaced("{max: [.inf, .inf, 0.001]}", "{min: [0, 0, 1], max: [1, 1, 0]}"),
                 {"key 'connective[1].fixed[0].region.min'", "min exceeds max"});
  expectRejected(replaced("sampling: tet_mesh", "sampling: tet_mesh\n    seed: 3"),
                 {"key 'connective[0].seed'", "does not apply to sampling tet_mesh"});
  expectRejected(replaced("    mesh: {generator: box, origin: [0.0, 0.0, 0.01]",
                          "    bogus: {generator: box, origin: [0.0, 0.0, 0.01]"),
                 {"key 'connective[0].bogus'", "unknown key"});
  expectRejected(
      replaced("sampling: poisson_disk", "sampling: poisson_disk\n    mesh: {generator: box}"),
      {"key 'connective[1].mesh'", "does not apply to sampling poisson_disk"});
  expectRejected(replaced("resolution: [2, 2, 1]}\n    material: {young_modulus: 5.0e3",
                          "resolution: [2, 2, 1]}\n    material: {young_modulus: 5.0e3, shear: 1"),
                 {"key 'connective[0].material.shear'", "unknown key"});
  expectRejected(replaced(", [0.024, 0.02, 0.01]]", "]"),
                 {"key 'connective[1].hexahedron'", "8 [x, y, z] corners"});
  expectRejected(replaced("node_spacing: 0.004", "node_spacing: 0.0"),
                 {"key 'connective[1].node_spacing'", "out of range [0.0001, 1] m"});
  expectRejected(replaced("sample_spacing: 0.002", "sample_spacing: 0.00005"),
                 {"key 'connective[1].sample_spacing'", "at most 200000 are supported"});
  expectRejected(replaced("[0.024, 0.02, 0.01]]", "[1.0, 1.0, 1.0]]"),
                 {"key 'connective[1].node_spacing'", "at most 20000 are supported"});
  expectRejected(replaced("sample_spacing: 0.002", "sample_spacing: 0.004"),
                 {"key 'connective[1].sample_spacing'", "smaller than node_spacing"});
  expectRejected(replaced("sample_spacing: 0.002", "sample_spacing: 0.005"),
                 {"key 'connective[1].sample_spacing'", "out of range"});
  expectRejected(replaced("neighbours: 4\n", "neighbours: 17\n"),
                 {"key 'connective[1].neighbours'", "[1, 16]"});
  expectRejected(replaced("seed: 7", "seed: -1"), {"key 'connective[1].seed'"});
  expectRejected(replaced("{max: [.inf, .inf, 0.001]}", "{max: [.inf, .inf, -0.001]}"),
                 {"key 'connective[1].fixed[0].region'", "contains no node"});
  expectRejected(replaced("colour: [1.0, 1.0, 0.0]", "colour: [1.0, -1.0, 0.0]"),
                 {"key 'connective[1].colour'"});
  expectRejected(replaced("name: sheet", "name: upper"),
                 {"key 'connective[0].name'", "duplicate name 'upper'"});
  expectRejected(replaced("- {body: lower}", "- {body: liver}"),
                 {"key 'connective[0].attachments[0].body'", "no body is named 'liver'"});
  expectRejected(replaced("- {body: upper, distance", "- {body: lower, distance"),
                 {"key 'connective[0].attachments[1].body'", "already attached"});
  expectRejected(replaced("distance: 1.0e-5", "distance: 0.02"),
                 {"key 'connective[0].attachments[1].distance'", "out of range"});
  expectRejected(replaced("neighbours: 3}", "neighbours: 0}"),
                 {"key 'connective[0].attachments[1].neighbours'"});
  expectRejected(replaced("    attachments:\n      - {body: side}\n", ""),
                 {"key 'connective[1].attachments'", "missing"});
  // The side box does not touch the sheet.
  expectRejected(replaced("- {body: upper, distance: 1.0e-5, neighbours: 3}", "- {body: side}"),
                 {"key 'connective[0].attachments[1]'", "no free surface node of body 'side'"});
}

}  // namespace
}  // namespace surgical_sim::core
