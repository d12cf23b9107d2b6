#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <climits>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include "surgical_sim/core/cutting/cut_mesh_check.h"
#include "surgical_sim/core/cutting/cut_tissue_model.h"
#include "surgical_sim/core/cutting/tet_cutter.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/mesh_check.h"
#include "surgical_sim/core/mesh/surface_closure.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::core {
namespace {

/// A blade segment along y (from y = -w to w) at x = x_cut, moving down from z = z0 to z1.
BladeSweep verticalCut(double x_cut, double w, double z0, double z1) {
  BladeSweep s;
  s.start.resize(3, 2);
  s.end.resize(3, 2);
  s.start << x_cut, x_cut, -w, w, z0, z0;
  s.end << x_cut, x_cut, -w, w, z1, z1;
  return s;
}

/// Problems of a cut mesh (cutMeshProblem), reported as a test failure; 0 or 1.
int topologyErrors(const TetMesh& mesh) {
  const std::string problem = cutMeshProblem(mesh);
  if (!problem.empty()) ADD_FAILURE() << problem;
  return problem.empty() ? 0 : 1;
}

/// Edges where more than two surface triangles meet.
int pinchedEdges(const TetMesh& mesh) {
  return checkSurfaceClosure(extractSurface(mesh).triangles).pinched_edges;
}

TEST(TetCutter, RejectsBadInputNamingTheProblem) {
  const TetMesh tet10 = makeBeam(1, 1, 1, Eigen::Vector3i(1, 1, 1), ElementType::Tet10);
  EXPECT_THROW(TetCutter(tet10, 1000.0), std::invalid_argument);
  const TetMesh tet4 = makeBeam(1, 1, 1, Eigen::Vector3i(1, 1, 1), ElementType::Tet4);
  EXPECT_THROW(TetCutter(tet4, 0.0), std::invalid_argument);
  TetCutter cutter(tet4, 1000.0);
  BladeSweep one_point;
  one_point.start = Eigen::Matrix3Xd::Zero(3, 1);
  one_point.end = Eigen::Matrix3Xd::Zero(3, 1);
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(3 * tet4.numNodes());
  EXPECT_THROW(cutter.cut(one_point, x, x), std::invalid_argument);
  EXPECT_THROW(cutter.cut(verticalCut(0.5, 1, 1, -1), x.head(3), x), std::invalid_argument);
}

TEST(TetCutter, BladePassingThroughAnElementWithinOneStepSplitsIt) {
  // One tet, the blade jumps from far above to far below it in a single step.
  TetMesh tet;
  tet.nodes.resize(3, 4);
  tet.nodes << 0, 1, 0, 0,  //
      0, 0, 1, 0,           //
      0, 0, 0, 1;
  tet.elements.resize(4, 1);
  tet.elements << 0, 1, 2, 3;
  TetCutter cutter(tet, 1000.0);
  Eigen::Map<const Eigen::VectorXd> x(tet.nodes.data(), 12);
  const CutUpdate u = cutter.cut(verticalCut(0.3, 5, 100, -100), x, x);
  EXPECT_TRUE(u.topology_changed);
  EXPECT_EQ(u.edges_cut, 3);  // plane x = 0.3 crosses the edges of corner 1
  EXPECT_EQ(cutter.mesh().numElements(), 2);
  EXPECT_EQ(cutter.numComponents(), 2);
  EXPECT_EQ(cutter.mesh().numNodes(), 8);
  // Corner (1,0,0) is cut off at x = 0.3: fraction 0.7^3.
  const auto& f = cutter.elementFraction();
  EXPECT_NEAR(std::min(f[0], f[1]), 0.343, 1e-9);
  EXPECT_NEAR(cutter.lumpedMass().sum() / 3.0, 1000.0 / 6.0, 1e-9);
  // Embedded cut triangle of each copy lies on the plane x = 0.3.
  ASSERT_EQ(cutter.cutTriangles().size(), 2u);
  for (const auto& tri : cutter.cutTriangles())
    for (const EmbeddedCutPoint& p : tri) {
      const Eigen::Vector3d q =
          (1 - p.w) * cutter.mesh().nodes.col(p.node_a) + p.w * cutter.mesh().nodes.col(p.node_b);
      EXPECT_NEAR(q.x(), 0.3, 1e-9);
    }
  // Cut triangles face away from their copy's real corner(s).
  for (const auto& tri : cutter.cutTriangles()) {
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k)
      p[k] = (1 - tri[k].w) * cutter.mesh().nodes.col(tri[k].node_a) +
             tri[k].w * cutter.mesh().nodes.col(tri[k].node_b);
    const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    const Eigen::Vector3d real = cutter.mesh().nodes.col(tri[0].node_a);
    EXPECT_GT(n.dot(p[0] - real), 0.0);
  }
  // The state transfer gives every node its parent's value: rest positions map onto themselves.
  const Eigen::VectorXd moved = cutter.transfer(x);
  EXPECT_TRUE(moved.isApprox(Eigen::Map<const Eigen::VectorXd>(cutter.mesh().nodes.data(), 24)));
  EXPECT_THROW(cutter.transfer(moved), std::invalid_argument);
  EXPECT_EQ(topologyErrors(cutter.mesh()), 0);
}

TEST(TetCutter, PartialCutDoesNotSeparateUntilTheBladeGoesThrough) {
  // Diagonal split: its crack front (blade stopped 2.5 mm above the beam's mid-plane) crosses
  // elements that keep a pinched edge; on the symmetric split it leaves none.
  const TetMesh beam =
      makeBeam(0.1, 0.02, 0.02, Eigen::Vector3i(10, 2, 2), ElementType::Tet4, CellSplit::Diagonal);
  TetCutter cutter(beam, 1000.0);
  const double x_cut = 0.0525;  // inside the 6th layer of cells
  Eigen::Map<const Eigen::VectorXd> x(beam.nodes.data(), 3 * beam.numNodes());
  const CutUpdate first = cutter.cut(verticalCut(x_cut, 0.05, 0.05, 0.0025), x, x);
  EXPECT_GT(first.edges_cut, 0);
  EXPECT_EQ(cutter.numComponents(), 1);
  EXPECT_EQ(topologyErrors(cutter.mesh()), 0);
  const TetMesh& cut = cutter.mesh();
  Eigen::Map<const Eigen::VectorXd> y(cut.nodes.data(), 3 * cut.numNodes());
  EXPECT_GT(pinchedEdges(cutter.mesh()), 0);  // the crack front, where the two lips meet
  cutter.cut(verticalCut(x_cut, 0.05, 0.0025, -0.05), y, y);
  EXPECT_EQ(cutter.numComponents(), 2);
  EXPECT_EQ(topologyErrors(cutter.mesh()), 0);
  EXPECT_EQ(pinchedEdges(cutter.mesh()), 0);  // cut through: both pieces are manifold
}

TEST(TetCutter, BeamCutThroughGivesTwoBodiesWithTheMassAndTheFreePieceFalls) {
  const double rho = 1000.0;
  const TetMesh beam = makeBeam(0.1, 0.02, 0.02, Eigen::Vector3i(10, 2, 2), ElementType::Tet4);
  TetCutter cutter(beam, rho);
  Eigen::Map<const Eigen::VectorXd> x0(beam.nodes.data(), 3 * beam.numNodes());
  cutter.cut(verticalCut(0.0525, 0.05, 0.05, -0.05), x0, x0);
  ASSERT_EQ(cutter.numComponents(), 2);
  const double total = rho * 0.1 * 0.02 * 0.02;
  const Eigen::VectorXd& m = cutter.lumpedMass();
  std::array<double, 2> piece{0, 0};
  for (int v = 0; v < cutter.mesh().numNodes(); ++v) piece[cutter.nodeComponent()[v]] += m[3 * v];
  EXPECT_NEAR(piece[0] + piece[1], total, 1e-12 * total);
  // The cut at x = 0.0525 leaves 52.5 % of the beam on the clamped side.
  const int clamped = cutter.nodeComponent()[0];  // node 0 is at x = 0
  EXPECT_NEAR(piece[clamped], 0.525 * total, 1e-9 * total);
  // Cut faces lie in the cut cell layer x in [0.05, 0.06]; the others on the original boundary.
  int cut_faces = 0;
  const SurfaceMesh& surface = cutter.surface();
  for (Eigen::Index t = 0; t < surface.triangles.cols(); ++t) {
    if (!cutter.cutFaces()[static_cast<std::size_t>(t)]) continue;
    ++cut_faces;
    for (int k = 0; k < 3; ++k) {
      const double x = cutter.mesh().nodes(0, surface.triangles(k, t));
      EXPECT_TRUE(x > 0.05 - 1e-12 && x < 0.06 + 1e-12) << x;
    }
  }
  EXPECT_GT(cut_faces, 0);

  // Clamp x = 0 and simulate with linearized implicit Euler under gravity.
  const Material material = Material::create(5e4, 0.3, rho);
  const auto model = makeCutTissueModel(ModelKind::Corotational, cutter, material);
  DynamicsProblem problem;
  problem.model = model.get();
  const Eigen::Vector3d g(0, 0, -9.81);
  problem.external_force = model->bodyForce(g);
  for (int v = 0; v < cutter.mesh().numNodes(); ++v)
    if (cutter.mesh().nodes(0, v) < 1e-12)
      for (int k = 0; k < 3; ++k) problem.dirichlet.dofs.push_back(3 * v + k);
  problem.dirichlet.positions =
      Eigen::VectorXd::Zero(static_cast<Eigen::Index>(problem.dirichlet.dofs.size()));
  for (std::size_t i = 0; i < problem.dirichlet.dofs.size(); ++i)
    problem.dirichlet.positions[static_cast<Eigen::Index>(i)] =
        model->restPositions()[problem.dirichlet.dofs[i]];
  SimulationState state{model->restPositions(),
                        Eigen::VectorXd::Zero(model->restPositions().size()), 0.0};
  const auto integrator = makeIntegrator(IntegratorKind::ImplicitEulerLinearized, {},
                                         makeLinearSolver(SolverKind::Cholmod, {}));
  const double dt = 0.01;
  const int steps = 20;
  for (int i = 0; i < steps; ++i)
    ASSERT_EQ(integrator->step(problem, dt, state).status, StepStatus::Ok);
  // Free piece: internal forces cancel, so its mass centre falls exactly as implicit Euler
  // integrates free fall: z_n = -g dt^2 n (n + 1) / 2.
  double free_mass = 0.0, free_dz = 0.0, clamped_dz = 0.0;
  for (int v = 0; v < cutter.mesh().numNodes(); ++v) {
    const double dz = state.x[3 * v + 2] - model->restPositions()[3 * v + 2];
    if (cutter.nodeComponent()[v] == clamped) {
      clamped_dz = std::min(clamped_dz, dz);
    } else {
      free_mass += m[3 * v];
      free_dz += m[3 * v] * dz;
    }
  }
  const double expected = -9.81 * dt * dt * steps * (steps + 1) / 2.0;
  EXPECT_NEAR(free_dz / free_mass, expected, 1e-6 * std::abs(expected));
  EXPECT_GT(clamped_dz, 0.2 * expected);  // the clamped half only sags
}

TEST(TetCutter, ElementRemovalAboveAStrainThresholdKeepsTheMass) {
  const TetMesh beam = makeBeam(0.1, 0.02, 0.02, Eigen::Vector3i(10, 2, 2), ElementType::Tet4);
  TetCutter cutter(beam, 1000.0);
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(beam.nodes.data(), 3 * beam.numNodes());
  const double mass = cutter.lumpedMass().sum();
  x[3 * 0 + 2] -= 0.01;  // pull node 0 down by half a cell: only its elements are strained
  const std::vector<int> strained = cutter.overstrainedElements(x, 0.1);
  ASSERT_FALSE(strained.empty());
  for (int e : strained) {
    bool has_node0 = false;
    for (int i = 0; i < 4; ++i) has_node0 = has_node0 || beam.elements(i, e) == 0;
    EXPECT_TRUE(has_node0);
  }
  const CutUpdate u = cutter.removeElements(strained);
  EXPECT_TRUE(u.topology_changed);
  EXPECT_EQ(cutter.mesh().numElements(), beam.numElements() - static_cast<int>(strained.size()));
  EXPECT_NEAR(cutter.lumpedMass().sum() + 3.0 * cutter.removedMass(), mass, 1e-12 * mass);
  EXPECT_EQ(topologyErrors(cutter.mesh()), 0);
  EXPECT_THROW(cutter.removeElements({-1}), std::invalid_argument);
}

/// A cut mesh described independently of its node and element numbering: a slot is (original
/// element, real corners of the copy, local corner); a node is named by its smallest slot.
struct CanonicalCut {
  using Slot = std::array<int, 3>;
  std::map<Slot, Slot> slot_node;
  std::map<Slot, double> node_mass;
  std::multiset<std::pair<std::array<Slot, 3>, bool>> triangles;
  int components = 0;
  double removed_mass = 0.0;
};

std::vector<CanonicalCut::Slot> nodeNames(const TetCutter& cutter) {
  const TetMesh& mesh = cutter.mesh();
  std::vector<CanonicalCut::Slot> name(static_cast<std::size_t>(mesh.numNodes()),
                                       {INT_MAX, INT_MAX, INT_MAX});
  for (int c = 0; c < mesh.numElements(); ++c)
    for (int i = 0; i < 4; ++i) {
      CanonicalCut::Slot& n = name[static_cast<std::size_t>(mesh.elements(i, c))];
      n = std::min(n, CanonicalCut::Slot{cutter.elementOrigin()[c], cutter.realCorners(c), i});
    }
  return name;
}

CanonicalCut canonical(const TetCutter& cutter) {
  const TetMesh& mesh = cutter.mesh();
  const std::vector<CanonicalCut::Slot> name = nodeNames(cutter);
  CanonicalCut out;
  for (int c = 0; c < mesh.numElements(); ++c)
    for (int i = 0; i < 4; ++i)
      out.slot_node[{cutter.elementOrigin()[c], cutter.realCorners(c), i}] =
          name[static_cast<std::size_t>(mesh.elements(i, c))];
  for (int v = 0; v < mesh.numNodes(); ++v)
    out.node_mass[name[static_cast<std::size_t>(v)]] = cutter.lumpedMass()[3 * v];
  const SurfaceMesh& surface = cutter.surface();
  for (Eigen::Index t = 0; t < surface.triangles.cols(); ++t) {
    std::array<CanonicalCut::Slot, 3> tri;
    for (int k = 0; k < 3; ++k) tri[k] = name[static_cast<std::size_t>(surface.triangles(k, t))];
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
    out.triangles.insert({tri, cutter.cutFaces()[static_cast<std::size_t>(t)]});
  }
  out.components = cutter.numComponents();
  out.removed_mass = cutter.removedMass();
  return out;
}

/// Node-major vector (origin, index, 0) of each current node.
Eigen::VectorXd encodeNodes(const TetCutter& cutter) {
  Eigen::VectorXd x(3 * cutter.mesh().numNodes());
  for (int v = 0; v < cutter.mesh().numNodes(); ++v)
    x.segment<3>(3 * v) = Eigen::Vector3d(cutter.nodeOrigin()[v], v, 0);
  return x;
}

/// Transfer problems: a node whose parent has another origin or is not an old node.
int transferErrors(const TetCutter& cutter, const Eigen::VectorXd& transferred, int old_nodes) {
  int errors = 0;
  for (int v = 0; v < cutter.mesh().numNodes(); ++v) {
    const Eigen::Vector3d t = transferred.segment<3>(3 * v);
    errors += t.x() == cutter.nodeOrigin()[v] && t.y() >= 0 && t.y() < old_nodes ? 0 : 1;
  }
  return errors;
}

TEST(TetCutter, IncrementalUpdateMatchesTheFullRebuildAfterEverySweep) {
  const Eigen::Vector3d semi(0.075, 0.05, 0.03);
  const TetMesh organ = makeOrganBlob(semi, 5, ElementType::Tet4);
  TetCutter incremental(organ, 1000.0), rebuilt(organ, 1000.0, CutUpdateMode::Rebuild);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int changes = 0;
  for (int i = 0; i < 80; ++i) {
    BladeSweep sweep;
    sweep.start.resize(3, 2);
    sweep.end.resize(3, 2);
    const Eigen::Vector3d motion(0.3 * semi.x() * u(rng), 0.3 * semi.y() * u(rng),
                                 -semi.z() * (0.5 + 0.5 * std::abs(u(rng))));
    for (int k = 0; k < 2; ++k) {
      sweep.start.col(k) = Eigen::Vector3d(semi.x() * u(rng), semi.y() * u(rng), semi.z());
      sweep.end.col(k) = sweep.start.col(k) + motion;
    }
    TetCutter* cutters[2] = {&incremental, &rebuilt};
    bool changed[2];
    for (int k = 0; k < 2; ++k) {
      const TetMesh& mesh = cutters[k]->mesh();
      const int old_nodes = mesh.numNodes();
      const Eigen::VectorXd x =
          Eigen::Map<const Eigen::VectorXd>(mesh.nodes.data(), 3 * mesh.numNodes());
      const Eigen::VectorXd nodes = encodeNodes(*cutters[k]);
      changed[k] = cutters[k]->cut(sweep, x, x).topology_changed;
      if (changed[k]) {
        ASSERT_EQ(transferErrors(*cutters[k], cutters[k]->transfer(nodes), old_nodes), 0)
            << "sweep " << i << (k == 0 ? " incremental" : " rebuilt");
      }
    }
    ASSERT_EQ(changed[0], changed[1]) << "sweep " << i;
    changes += changed[0] ? 1 : 0;
    const CanonicalCut a = canonical(incremental);
    const CanonicalCut b = canonical(rebuilt);
    ASSERT_EQ(incremental.mesh().numNodes(), rebuilt.mesh().numNodes()) << "sweep " << i;
    ASSERT_EQ(a.slot_node, b.slot_node) << "sweep " << i;
    ASSERT_EQ(a.triangles, b.triangles) << "sweep " << i;
    ASSERT_EQ(a.components, b.components) << "sweep " << i;
    for (const auto& [node, mass] : a.node_mass)
      ASSERT_NEAR(mass, b.node_mass.at(node), 1e-12 * mass) << "sweep " << i;
    EXPECT_EQ(incremental.cutTriangles().size(), rebuilt.cutTriangles().size());
    // The incrementally kept surface node list is the sorted node set of its triangles.
    const Eigen::Matrix3Xi& tris = incremental.surface().triangles;
    std::vector<int> nodes(tris.data(), tris.data() + tris.size());
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    ASSERT_EQ(incremental.surface().nodes, nodes) << "sweep " << i;
  }
  EXPECT_GT(changes, 20);
  EXPECT_GT(incremental.numComponents(), 1);
  EXPECT_EQ(incremental.fullRebuilds(), 1);  // construction only
  // Element removal after the cuts: both rebuild, and still agree.
  const std::vector<int> some = {0, incremental.mesh().numElements() / 2};
  std::vector<int> same;
  for (int c : some)
    for (int d = 0; d < rebuilt.mesh().numElements(); ++d)
      if (rebuilt.elementOrigin()[d] == incremental.elementOrigin()[c] &&
          rebuilt.realCorners(d) == incremental.realCorners(c))
        same.push_back(d);
  ASSERT_EQ(same.size(), some.size());
  const int old_nodes = incremental.mesh().numNodes();
  const Eigen::VectorXd nodes = encodeNodes(incremental);
  incremental.removeElements(some);
  rebuilt.removeElements(same);
  EXPECT_EQ(transferErrors(incremental, incremental.transfer(nodes), old_nodes), 0);
  const CanonicalCut a = canonical(incremental), b = canonical(rebuilt);
  EXPECT_EQ(a.slot_node, b.slot_node);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.removed_mass, b.removed_mass);
}

}  // namespace
}  // namespace surgical_sim::core
