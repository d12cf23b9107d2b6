// Each phase of a TetCutter cut seen through the cutter: element splitting conserves volume and
// mass, node classification puts every node on its side of the blade, and the incremental
// refresh of the derived data equals a full rebuild.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "surgical_sim/core/cutting/tet_cutter.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/mesh_check.h"

namespace surgical_sim::core {
namespace {

constexpr double kDensity = 1000.0;  // [kg/m^3]
constexpr double kCutX = 0.0525;     // [m], inside the 6th cell layer of the beam

/// Beam 0.1 x 0.02 x 0.02 m, 10 x 2 x 2 cells: nodes at z = -0.01, 0, 0.01 m. Diagonal cell
/// split: the partial-cut expectations below hold on it (on the symmetric split a partial cut
/// leaves nodes with 3 or 4 copies and no pinched edge at the crack front).
TetMesh beam() {
  return makeBeam(0.1, 0.02, 0.02, Eigen::Vector3i(10, 2, 2), ElementType::Tet4,
                  CellSplit::Diagonal);
}

/// Blade across the beam (y in [-0.05, 0.05] m) at x = kCutX, moving down from z_from to z_to.
BladeSweep downwardBlade(double z_from, double z_to) {
  BladeSweep sweep{Eigen::Matrix3Xd(3, 2), Eigen::Matrix3Xd(3, 2)};
  sweep.start.row(0).setConstant(kCutX);
  sweep.start.row(1) << -0.05, 0.05;
  sweep.start.row(2).setConstant(z_from);
  sweep.end = sweep.start;
  sweep.end.row(2).setConstant(z_to);
  return sweep;
}

/// Cuts at the current rest positions (a blade through tissue at rest).
CutUpdate cutAtRest(TetCutter& cutter, const BladeSweep& sweep) {
  const TetMesh& mesh = cutter.mesh();
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(mesh.nodes.data(), mesh.nodes.size());
  return cutter.cut(sweep, x, x);
}

/// Current nodes per original node.
std::vector<int> nodesPerOrigin(const TetCutter& cutter, int original_nodes) {
  std::vector<int> count(static_cast<std::size_t>(original_nodes), 0);
  for (int origin : cutter.nodeOrigin()) ++count[static_cast<std::size_t>(origin)];
  return count;
}

/// Real corners of split copies on the wrong side: a copy's real corners must all lie on one side
/// of the blade plane and its virtual corners on the other.
int cornersOnTheWrongSide(const TetCutter& cutter) {
  int wrong = 0;
  const TetMesh& mesh = cutter.mesh();
  for (int c = 0; c < mesh.numElements(); ++c) {
    const int real = cutter.realCorners(c);
    if (real == 0xF) continue;
    int real_side = -1;
    for (int i = 0; i < 4; ++i)
      if (real & (1 << i)) real_side = mesh.nodes(0, mesh.elements(i, c)) > kCutX ? 1 : 0;
    for (int i = 0; i < 4; ++i) {
      const int side = mesh.nodes(0, mesh.elements(i, c)) > kCutX ? 1 : 0;
      wrong += (side == real_side) == static_cast<bool>(real & (1 << i)) ? 0 : 1;
    }
  }
  return wrong;
}

TEST(TetCutterPhases, SplittingConservesEveryElementsVolumeAndTheTotalMass) {
  const TetMesh mesh = beam();
  TetCutter cutter(mesh, kDensity);
  cutAtRest(cutter, downwardBlade(0.05, -0.05));
  std::vector<double> fraction(static_cast<std::size_t>(mesh.numElements()), 0.0);
  int split_copies = 0;
  for (int c = 0; c < cutter.mesh().numElements(); ++c) {
    fraction[static_cast<std::size_t>(cutter.elementOrigin()[c])] += cutter.elementFraction()[c];
    split_copies += cutter.realCorners(c) == 0xF ? 0 : 1;
    EXPECT_GT(signedVolume(cutter.mesh(), c), 0.0) << "copy " << c;
  }
  EXPECT_GT(split_copies, 0);
  for (double f : fraction) EXPECT_NEAR(f, 1.0, 1e-14);
  const double mass = kDensity * 0.1 * 0.02 * 0.02;
  EXPECT_NEAR(cutter.lumpedMass().sum() / 3.0, mass, 1e-12 * mass);
}

TEST(TetCutterPhases, ThroughCutClassifiesEveryNodeOnItsSide) {
  const TetMesh mesh = beam();
  TetCutter cutter(mesh, kDensity);
  cutAtRest(cutter, downwardBlade(0.05, -0.05));
  ASSERT_EQ(cutter.numComponents(), 2);
  EXPECT_EQ(cornersOnTheWrongSide(cutter), 0);
  // The real corners of each piece lie on one side of the plane, the pieces on opposite sides.
  std::map<int, std::set<int>> sides_of_component;
  std::vector<char> on_split(static_cast<std::size_t>(mesh.numNodes()), 0);
  for (int c = 0; c < cutter.mesh().numElements(); ++c)
    for (int i = 0; i < 4; ++i) {
      const int node = cutter.mesh().elements(i, c);
      if (cutter.realCorners(c) != 0xF)
        on_split[static_cast<std::size_t>(cutter.nodeOrigin()[node])] = 1;
      if (cutter.realCorners(c) & (1 << i))
        sides_of_component[cutter.nodeComponent()[node]].insert(
            cutter.mesh().nodes(0, node) > kCutX ? 1 : 0);
    }
  ASSERT_EQ(sides_of_component.size(), 2u);
  EXPECT_EQ(sides_of_component[0].size(), 1u);
  EXPECT_EQ(sides_of_component[1].size(), 1u);
  EXPECT_NE(*sides_of_component[0].begin(), *sides_of_component[1].begin());
  // A node is duplicated (one copy per piece) iff it is a corner of a split element.
  const std::vector<int> count = nodesPerOrigin(cutter, mesh.numNodes());
  for (int v = 0; v < mesh.numNodes(); ++v)
    EXPECT_EQ(count[static_cast<std::size_t>(v)], on_split[static_cast<std::size_t>(v)] ? 2 : 1)
        << "original node " << v;
}

TEST(TetCutterPhases, PartialCutDuplicatesOnlyTheNodesWhereTheMaterialOpened) {
  const TetMesh mesh = beam();
  TetCutter cutter(mesh, kDensity);
  cutAtRest(cutter, downwardBlade(0.05, 0.0025));  // stops in the upper cell layer
  EXPECT_EQ(cutter.numComponents(), 1);
  EXPECT_EQ(cornersOnTheWrongSide(cutter), 0);
  const std::vector<int> count = nodesPerOrigin(cutter, mesh.numNodes());
  int duplicated_top = 0;
  for (int v = 0; v < mesh.numNodes(); ++v) {
    const double z = mesh.nodes(2, v);
    if (z < -0.005) {
      EXPECT_EQ(count[static_cast<std::size_t>(v)], 1) << "bottom node " << v;
    }
    if (z > 0.005 && count[static_cast<std::size_t>(v)] == 2) ++duplicated_top;
    EXPECT_LE(count[static_cast<std::size_t>(v)], 2) << "node " << v;
  }
  EXPECT_GT(duplicated_top, 0);  // the top face opened along the blade
}

/// Numbering-independent description of the derived data: per original node the node count
/// and total lumped mass, and the surface triangles as sorted origin triples with their cut flag.
struct DerivedData {
  std::vector<int> nodes_per_origin;
  std::vector<double> mass_per_origin;
  std::multiset<std::pair<std::array<int, 3>, bool>> triangles;
  int components = 0;
  std::size_t surface_nodes = 0;
};

DerivedData derivedData(const TetCutter& cutter, int original_nodes) {
  DerivedData d;
  d.nodes_per_origin = nodesPerOrigin(cutter, original_nodes);
  d.mass_per_origin.assign(static_cast<std::size_t>(original_nodes), 0.0);
  for (int v = 0; v < cutter.mesh().numNodes(); ++v)
    d.mass_per_origin[static_cast<std::size_t>(cutter.nodeOrigin()[v])] +=
        cutter.lumpedMass()[3 * v];
  const Eigen::Matrix3Xi& tris = cutter.surface().triangles;
  for (Eigen::Index t = 0; t < tris.cols(); ++t) {
    std::array<int, 3> origins{};
    for (int k = 0; k < 3; ++k) origins[k] = cutter.nodeOrigin()[tris(k, t)];
    std::sort(origins.begin(), origins.end());
    d.triangles.insert({origins, cutter.cutFaces()[static_cast<std::size_t>(t)]});
  }
  d.components = cutter.numComponents();
  d.surface_nodes = cutter.surface().nodes.size();
  return d;
}

TEST(TetCutterPhases, IncrementalRefreshEqualsTheFullRebuildAfterAPartialAndAThroughCut) {
  const TetMesh mesh = beam();
  TetCutter incremental(mesh, kDensity), rebuilt(mesh, kDensity, CutUpdateMode::Rebuild);
  for (const BladeSweep& sweep : {downwardBlade(0.05, 0.0025), downwardBlade(0.0025, -0.05)}) {
    EXPECT_TRUE(cutAtRest(incremental, sweep).topology_changed);
    EXPECT_TRUE(cutAtRest(rebuilt, sweep).topology_changed);
    const DerivedData a = derivedData(incremental, mesh.numNodes());
    const DerivedData b = derivedData(rebuilt, mesh.numNodes());
    EXPECT_EQ(a.nodes_per_origin, b.nodes_per_origin);
    for (std::size_t v = 0; v < a.mass_per_origin.size(); ++v)
      EXPECT_NEAR(a.mass_per_origin[v], b.mass_per_origin[v], 1e-12 * b.mass_per_origin[v]);
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.components, b.components);
    EXPECT_EQ(a.surface_nodes, b.surface_nodes);
  }
  EXPECT_EQ(incremental.fullRebuilds(), 1);  // construction only
  EXPECT_EQ(rebuilt.fullRebuilds(), 3);
}

}  // namespace
}  // namespace surgical_sim::core
