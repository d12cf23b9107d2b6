// FE organs coupled by rigid-node connective layers (ConnectiveCoupling, CoupledSolver).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "rigid_node_test_util.h"
#include "surgical_sim/core/connective/connective_coupling.h"
#include "surgical_sim/core/connective/coupled_solver.h"
#include "surgical_sim/core/connective/rigid_node_sampling.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::core {
namespace {

using test::expectInvalidArgument;

/// CPU time of the calling thread [s].
double threadSeconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Bodies of a coupled scene (owned) and their coupling.
struct Scene {
  std::vector<TetMesh> meshes;
  std::vector<std::unique_ptr<TissueModel>> organs;
  std::vector<std::unique_ptr<RigidNodeModel>> layers;
  std::unique_ptr<ConnectiveCoupling> coupling;
};

/// Nodes of mesh with predicate(position) true.
template <typename Predicate>
std::vector<int> nodesWhere(const TetMesh& mesh, Predicate predicate) {
  std::vector<int> nodes;
  for (int i = 0; i < mesh.numNodes(); ++i)
    if (predicate(Eigen::Vector3d(mesh.nodes.col(i)))) nodes.push_back(i);
  return nodes;
}

/// Two SVK boxes (L x L x L/2) joined by a tet-sampled layer L/8 thick whose rigid nodes sit on
/// a finer grid (so most attached nodes get Shepard weights on 4 rigid nodes), at length scale
/// L [m]; the lower box's nodes where held(rest position) are fixed.
using NodePredicate = std::function<bool(const Eigen::Vector3d&)>;
Scene twoBoxScene(double L, const NodePredicate& held, ModelKind kind = ModelKind::Svk) {
  Scene scene;
  const Material organ_material = Material::create(10e3, 0.3, 1000.0);
  scene.meshes.push_back(makeBox(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(L, L, L / 2),
                                 Eigen::Vector3i(2, 2, 1), ElementType::Tet4));
  scene.meshes.push_back(makeBox(Eigen::Vector3d(0, 0, 5 * L / 8), Eigen::Vector3d(L, L, L / 2),
                                 Eigen::Vector3i(2, 2, 1), ElementType::Tet4));
  for (const TetMesh& mesh : scene.meshes)
    scene.organs.push_back(makeTissueModel(kind, mesh, organ_material));
  const RigidNodeLayout layout =
      tetMeshLayout(makeBox(Eigen::Vector3d(0, 0, L / 2), Eigen::Vector3d(L, L, L / 8),
                            Eigen::Vector3i(3, 3, 1), ElementType::Tet4),
                    Material::create(5e3, 0.3, 1000.0));
  scene.layers.push_back(std::make_unique<RigidNodeModel>(layout.rest, layout.samples));
  std::vector<CoupledOrgan> organs(2);
  organs[0].model = scene.organs[0].get();
  organs[1].model = scene.organs[1].get();
  organs[0].fixed_nodes = nodesWhere(scene.meshes[0], held);
  std::vector<CoupledLayer> layers(1);
  layers[0].model = scene.layers[0].get();
  std::vector<OrganLayerAttachment> attachments(2);
  attachments[0].organ = 0;
  attachments[0].nodes =
      nodesWhere(scene.meshes[0], [&](const Eigen::Vector3d& p) { return p.z() > 0.49 * L; });
  attachments[1].organ = 1;
  attachments[1].nodes =
      nodesWhere(scene.meshes[1], [&](const Eigen::Vector3d& p) { return p.z() < 0.63 * L; });
  scene.coupling = std::make_unique<ConnectiveCoupling>(organs, layers, attachments);
  return scene;
}

/// No node held / the node at the origin held.
bool none(const Eigen::Vector3d&) { return false; }
bool origin(const Eigen::Vector3d& p) { return p.norm() == 0.0; }

/// Every organ node and rigid node of state moved by x -> R x + t.
void moveRigidly(const Eigen::Quaterniond& R, const Eigen::Vector3d& t, CoupledState& state) {
  for (Eigen::VectorXd& x : state.organ_positions)
    for (Eigen::Index a = 0; a < x.size() / 3; ++a)
      x.segment<3>(3 * a) = R * x.segment<3>(3 * a) + t;
  for (RigidNodeConfiguration& q : state.layer_configurations) q = test::rigidlyMoved(q, R, t);
}

/// Largest |a - b| over all organ nodes of two states [m].
double largestOrganDifference(const CoupledState& a, const CoupledState& b) {
  double largest = 0.0;
  for (std::size_t o = 0; o < a.organ_positions.size(); ++o)
    largest =
        std::max(largest, (a.organ_positions[o] - b.organ_positions[o]).cwiseAbs().maxCoeff());
  return largest;
}

TEST(ConnectiveCoupling, RigidMotionOfEverythingIsTransmittedExactlyWithZeroForce) {
  for (const double L : {1e-3, 1.0}) {
    Scene scene = twoBoxScene(L, none);
    ConnectiveCoupling& coupling = *scene.coupling;
    const CoupledState rest = coupling.restState();
    CoupledState moved = rest;
    const Eigen::Quaterniond R = expRotation(Eigen::Vector3d(0.4, -0.7, 1.1));
    const Eigen::Vector3d t = L * Eigen::Vector3d(0.3, -2.0, 0.5);
    moveRigidly(R, t, moved);
    CoupledState mapped = moved;
    coupling.applyMapping(mapped);
    EXPECT_LT(largestOrganDifference(mapped, moved), 1e-13 * L) << "L " << L;
    coupling.assemble(mapped, CoupledLoads{}, CouplingTangentOptions{}, true);
    // Forces of a 1 % strain are ~ E L^2 / 100 = 100 L^2 N.
    EXPECT_LT(coupling.force().norm(), 1e-9 * 100 * L * L) << "L " << L;

    // A uniform velocity: every body translates rigidly under implicit Euler.
    CoupledState state = rest;
    const Eigen::Vector3d v(0.2 * L, -0.1 * L, 0.3 * L);
    for (Eigen::VectorXd& x : state.organ_velocities) x = v.replicate(x.size() / 3, 1);
    for (Eigen::VectorXd& u : state.layer_velocities)
      for (Eigen::Index j = 0; j < u.size() / 6; ++j) u.segment<3>(6 * j) = v;
    CoupledSolverSettings settings;
    settings.mass_damping = 0.0;
    CoupledSolver solver(coupling, settings);
    for (int i = 0; i < 10; ++i)
      ASSERT_EQ(solver.step(CoupledLoads{}, 0.01, state).status, StepStatus::Ok);
    CoupledState expected = rest;
    moveRigidly(Eigen::Quaterniond::Identity(), 0.1 * v, expected);
    EXPECT_LT(largestOrganDifference(state, expected), 1e-10 * L) << "L " << L;
  }
}

/// Coupled force against the potential's gradient and the exact tangent against differences of
/// the force, in every unknown, at a deformed state with gravity, a point force and a spring.
TEST(ConnectiveCoupling, ForceAndTangentMatchFiniteDifferencesAtMmAndMScale) {
  for (const double L : {1e-3, 1.0}) {
    Scene scene = twoBoxScene(L, origin);
    ConnectiveCoupling& coupling = *scene.coupling;
    CoupledState state = coupling.restState();
    std::mt19937 rng(7);
    Eigen::VectorXd du(coupling.numUnknowns());
    for (Eigen::Index k = 0; k < du.size(); ++k) {
      std::uniform_real_distribution<double> u(-1.0, 1.0);
      // Translations within 5 % of L, rotations within 0.1 rad.
      du[k] = u(rng) * 0.05 * L;
    }
    for (Eigen::Index k = du.size() - 6 * scene.layers[0]->numNodes(); k < du.size(); ++k)
      if ((k - (du.size() - 6 * scene.layers[0]->numNodes())) % 6 >= 3) du[k] *= 2.0 / L;
    coupling.applyIncrement(du, 1.0, state);
    CoupledLoads loads;
    loads.gravity = Eigen::Vector3d(0, 1.0, -9.81);
    loads.forces.push_back(CoupledPointForce{1, 3, L * L * Eigen::Vector3d(1.0, -2.0, 0.5)});
    loads.springs.push_back(CoupledSpring{
        1, 5, scene.meshes[1].nodes.col(5) + L * Eigen::Vector3d(0.1, 0, 0.2), 50 * L});
    CouplingTangentOptions exact;
    exact.organ_mode = TangentMode::Exact;
    exact.symmetrize = false;
    coupling.assemble(state, loads, exact, false);
    const Eigen::VectorXd f = coupling.force();
    const Eigen::MatrixXd K = Eigen::MatrixXd(coupling.stiffness());
    double force_error = 0.0, tangent_error = 0.0;
    const double h = 1e-6;
    for (int k = 0; k < coupling.numUnknowns(); ++k) {
      const Eigen::VectorXd e = Eigen::VectorXd::Unit(coupling.numUnknowns(), k);
      const double step =
          (k >= coupling.numUnknowns() - 6 * scene.layers[0]->numNodes() &&
           (k - (coupling.numUnknowns() - 6 * scene.layers[0]->numNodes())) % 6 >= 3)
              ? h
              : h * L;
      CoupledState plus = state, minus = state;
      coupling.applyIncrement(e, step, plus);
      coupling.applyIncrement(e, -step, minus);
      const double dPi =
          (coupling.potentialEnergy(plus, loads) - coupling.potentialEnergy(minus, loads)) /
          (2 * step);
      force_error = std::max(force_error, std::abs(f[k] + dPi));
      coupling.assemble(plus, loads, exact, false);
      const Eigen::VectorXd f_plus = coupling.force();
      coupling.assemble(minus, loads, exact, false);
      const Eigen::VectorXd column = -(f_plus - coupling.force()) / (2 * step);
      tangent_error = std::max(tangent_error, (column - K.col(k)).cwiseAbs().maxCoeff());
    }
    std::printf("L %g m: |f| max %.3e, force error %.3e; |K| max %.3e, tangent error %.3e\n", L,
                f.cwiseAbs().maxCoeff(), force_error, K.cwiseAbs().maxCoeff(), tangent_error);
    EXPECT_LT(force_error, 1e-6 * f.cwiseAbs().maxCoeff()) << "L " << L;
    EXPECT_LT(tangent_error, 1e-6 * K.cwiseAbs().maxCoeff()) << "L " << L;
    // The solver's tangent is symmetric.
    coupling.assemble(state, loads, CouplingTangentOptions{}, true);
    const Eigen::SparseMatrix<double> asym =
        coupling.stiffness() - Eigen::SparseMatrix<double>(coupling.stiffness().transpose());
    EXPECT_LT(asym.coeffs().cwiseAbs().maxCoeff(), 1e-12 * K.cwiseAbs().maxCoeff());
    const Eigen::SparseMatrix<double> masym =
        coupling.mass() - Eigen::SparseMatrix<double>(coupling.mass().transpose());
    EXPECT_LT(masym.coeffs().cwiseAbs().maxCoeff(),
              1e-14 * coupling.mass().coeffs().cwiseAbs().maxCoeff());
  }
}

/// The same scene at mm and m scale with loads scaled by L^2 (same stresses): the quasi-static
/// displacements scale with L.
TEST(ConnectiveCoupling, QuasiStaticAnswerScalesWithLengthFromMmToM) {
  std::vector<double> displacement;
  for (const double L : {1e-3, 1.0}) {
    // The lower box's bottom face held.
    Scene scene = twoBoxScene(
        L, [&](const Eigen::Vector3d& p) { return p.z() < 1e-3 * L; }, ModelKind::Svk);
    ConnectiveCoupling& coupling = *scene.coupling;
    CoupledLoads loads;
    const std::vector<int> top =
        nodesWhere(scene.meshes[1], [&](const Eigen::Vector3d& p) { return p.z() > 1.12 * L; });
    for (const int a : top)
      loads.forces.push_back(CoupledPointForce{1, a, 2.0 * L * L * Eigen::Vector3d(1.0, 0.0, 0.5)});
    CoupledState state = coupling.restState();
    CoupledSolver solver(coupling);
    const StepReport report = solver.solveStatic(loads, state);
    ASSERT_EQ(report.status, StepStatus::Ok) << "L " << L;
    const int a = top.front();
    displacement.push_back(
        (state.organ_positions[1].segment<3>(3 * a) - scene.meshes[1].nodes.col(a)).norm() / L);
    std::printf("L %g m: %d Newton iterations, top node displacement / L %.6e\n", L,
                report.newton_iterations, displacement.back());
  }
  EXPECT_GT(displacement[0], 1e-3);
  EXPECT_NEAR(displacement[0], displacement[1], 1e-6 * displacement[1]);
}

/// Scene (a): three stacked plates 10 x 10 x 1 cm (E 1 MPa) joined by two layers 5 mm thick
/// (E 50 kPa, tet-sampled, rigid nodes on the plates' faces), the top plate held at its front
/// and rear edges (y = 0 and y = 10 cm), under gravity.
TEST(ConnectiveCouplingScenes, ThreeStackedPlatesHangFromTheTopPlateUnderGravity) {
  const double side = 0.1, plate = 0.01, layer = 0.005;
  const Eigen::Vector3i cells(6, 6, 1);
  Scene scene;
  const Material plate_material = Material::create(1e6, 0.3, 1000.0);
  const Material layer_material = Material::create(50e3, 0.3, 1000.0);
  std::vector<CoupledOrgan> organs(3);
  std::vector<CoupledLayer> layers(2);
  std::vector<OrganLayerAttachment> attachments;
  for (int p = 0; p < 3; ++p) {
    const double z0 = -p * (plate + layer);  // plate 0 on top
    scene.meshes.push_back(makeBox(Eigen::Vector3d(0, 0, z0), Eigen::Vector3d(side, side, plate),
                                   cells, ElementType::Tet4));
    scene.organs.push_back(
        makeTissueModel(ModelKind::Corotational, scene.meshes[p], plate_material));
    organs[p].model = scene.organs[p].get();
  }
  organs[0].fixed_nodes = nodesWhere(scene.meshes[0], [&](const Eigen::Vector3d& x) {
    return x.y() < 1e-9 || x.y() > side - 1e-9;
  });
  for (int l = 0; l < 2; ++l) {
    const double z0 = -(l + 1) * (plate + layer) + plate;  // below plate l
    const RigidNodeLayout layout =
        tetMeshLayout(makeBox(Eigen::Vector3d(0, 0, z0), Eigen::Vector3d(side, side, layer), cells,
                              ElementType::Tet4),
                      layer_material);
    scene.layers.push_back(std::make_unique<RigidNodeModel>(layout.rest, layout.samples));
    layers[l].model = scene.layers[l].get();
    // The plate above touches the layer's top face, the plate below its bottom face.
    const double top = z0 + layer, bottom = z0;
    OrganLayerAttachment above, below;
    above.organ = l;
    above.layer = l;
    // The top plate's held edges stay held.
    above.nodes = nodesWhere(scene.meshes[l], [&](const Eigen::Vector3d& x) {
      return std::abs(x.z() - top) < 1e-9 && (l > 0 || (x.y() > 1e-9 && x.y() < side - 1e-9));
    });
    below.organ = l + 1;
    below.layer = l;
    below.nodes = nodesWhere(scene.meshes[l + 1], [&](const Eigen::Vector3d& x) {
      return std::abs(x.z() - bottom) < 1e-9;
    });
    attachments.push_back(above);
    attachments.push_back(below);
  }
  ConnectiveCoupling coupling(organs, layers, attachments);
  CoupledLoads loads;
  loads.gravity = Eigen::Vector3d(0, 0, -9.81);
  CoupledState state = coupling.restState();
  const double rest_energy = coupling.potentialEnergy(state, loads);

  // Damped dynamics from rest: the total energy never grows.
  CoupledSolverSettings settings;
  settings.mass_damping = 20.0;
  settings.stiffness_damping = 1e-3;
  CoupledSolver solver(coupling, settings);
  double energy = rest_energy;
  for (int i = 0; i < 40; ++i) {
    const StepReport report = solver.step(loads, 5e-3, state);
    ASSERT_EQ(report.status, StepStatus::Ok) << "step " << i;
    EXPECT_LE(report.energy, energy + 1e-9 * std::abs(rest_energy)) << "step " << i;
    energy = report.energy;
  }
  EXPECT_LT(energy, rest_energy);

  // Equilibrium.
  const StepReport report = solver.solveStatic(loads, state);
  ASSERT_EQ(report.status, StepStatus::Ok);
  EXPECT_LE(coupling.potentialEnergy(state, loads), energy);
  std::printf("three plates: %d unknowns, static %d Newton iterations, residual %.2e\n",
              coupling.numUnknowns(), report.newton_iterations, report.residual);

  // The reaction at the held edges carries the weight of all five bodies.
  double weight = 0.0;
  for (const auto& organ : scene.organs) weight += organ->lumpedMass().sum() / 3.0 * 9.81;
  for (const auto& layer_model : scene.layers) weight += layer_model->totalMass() * 9.81;
  Eigen::VectorXd f = scene.organs[0]->bodyForce(loads.gravity);
  scene.organs[0]->addInternalForce(state.organ_positions[0], f);
  double reaction = 0.0;
  for (const int a : organs[0].fixed_nodes) reaction -= f[3 * a + 2];
  EXPECT_NEAR(reaction, weight, 1e-6 * weight);

  // Mean sag of each plate: they hang one below the other, held by the layers.
  std::vector<double> sag;
  for (int p = 0; p < 3; ++p) {
    const Eigen::VectorXd u = state.organ_positions[p] - scene.organs[p]->restPositions();
    double sum = 0.0;
    for (Eigen::Index a = 0; a < u.size() / 3; ++a) sum += u[3 * a + 2];
    sag.push_back(-sum / static_cast<double>(u.size() / 3));
  }
  std::printf("three plates: mean sag %.4e / %.4e / %.4e m\n", sag[0], sag[1], sag[2]);
  EXPECT_GT(sag[0], 0.0);
  EXPECT_GT(sag[1], sag[0]);
  EXPECT_GT(sag[2], sag[1]);
  EXPECT_LT(sag[2] - sag[0], 0.2 * layer);  // the layers stretch by a fraction of their thickness
}

/// Scene (b): two box organs (3,240 tets together, E 30 kPa) side by side along x, the second
/// sheared so that the gap between them is a wedge, 3 mm thick at the top and 15 mm at the
/// bottom, filled by a Poisson-disk connective layer (E 10 kPa, Shepard weights). The second
/// organ's far face is held; a tool grasps the first organ's far face with springs.
struct TwoOrganScene {
  Scene scene;
  std::vector<int> grasped;  ///< nodes of organ 0 held by the tool
  std::vector<int> facing;   ///< nodes of organ 1 attached to the layer
};

TwoOrganScene twoOrganScene() {
  const double length = 0.06, width = 0.04, thin = 0.003, thick = 0.015;
  TwoOrganScene out;
  Scene& scene = out.scene;
  const Material organ_material = Material::create(30e3, 0.45, 1000.0);
  const Eigen::Vector3i cells(9, 6, 6);
  scene.meshes.push_back(makeBox(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(length, width, width),
                                 cells, ElementType::Tet4));
  TetMesh second = makeBox(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(length, width, width), cells,
                           ElementType::Tet4);
  auto gap = [&](double z) { return thick + (thin - thick) * z / width; };
  for (int i = 0; i < second.numNodes(); ++i) {
    const double x = second.nodes(0, i), z = second.nodes(2, i);
    second.nodes(0, i) = length + x + gap(z) * (1.0 - x / length);
  }
  scene.meshes.push_back(second);
  for (const TetMesh& mesh : scene.meshes)
    scene.organs.push_back(makeTissueModel(ModelKind::Corotational, mesh, organ_material));

  // The wedge between x = length and x = length + gap(z).
  TriMesh wedge;
  wedge.vertices.resize(3, 8);
  for (int c = 0; c < 8; ++c) {
    const double y = (c & 2) ? width : 0.0, z = (c & 4) ? width : 0.0;
    wedge.vertices.col(c) = Eigen::Vector3d((c & 1) ? length + gap(z) : length, y, z);
  }
  // Outward triangles of the hexahedron with corner c = x + 2 y + 4 z.
  wedge.triangles.resize(3, 12);
  wedge.triangles << 0, 0, 1, 1, 0, 0, 2, 2, 0, 0, 4, 4,  //
      4, 6, 3, 7, 1, 5, 6, 7, 2, 3, 5, 7,                 //
      6, 2, 7, 5, 5, 4, 7, 3, 3, 1, 7, 6;
  std::mt19937 rng(3);
  const RigidNodeLayout layout =
      poissonDiskLayout(wedge, 0.0057, 0.0034, 6, Material::create(10e3, 0.45, 1000.0), rng);
  scene.layers.push_back(std::make_unique<RigidNodeModel>(layout.rest, layout.samples));

  std::vector<CoupledOrgan> organs(2);
  organs[0].model = scene.organs[0].get();
  organs[1].model = scene.organs[1].get();
  organs[1].fixed_nodes = nodesWhere(
      scene.meshes[1], [&](const Eigen::Vector3d& p) { return p.x() > 2 * length - 1e-9; });
  std::vector<CoupledLayer> layers(1);
  layers[0].model = scene.layers[0].get();
  std::vector<OrganLayerAttachment> attachments(2);
  attachments[0].organ = 0;
  attachments[0].nodes =
      nodesWhere(scene.meshes[0], [&](const Eigen::Vector3d& p) { return p.x() > length - 1e-9; });
  attachments[1].organ = 1;
  attachments[1].nodes = nodesWhere(scene.meshes[1], [&](const Eigen::Vector3d& p) {
    return std::abs(p.x() - length - gap(p.z())) < 1e-9;
  });
  out.facing = attachments[1].nodes;
  out.grasped = nodesWhere(scene.meshes[0], [&](const Eigen::Vector3d& p) {
    return p.x() < 1e-9 && (p - Eigen::Vector3d(0, width / 2, width / 2)).norm() < 0.008;
  });
  scene.coupling = std::make_unique<ConnectiveCoupling>(organs, layers, attachments);
  return out;
}

/// Mean displacement [m] of nodes of organ o.
Eigen::Vector3d meanDisplacement(const Scene& scene, const CoupledState& state, int o,
                                 const std::vector<int>& nodes) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const int a : nodes)
    sum += state.organ_positions[o].segment<3>(3 * a) - scene.meshes[o].nodes.col(a);
  return sum / static_cast<double>(nodes.size());
}

TEST(ConnectiveCouplingScenes, PullingOneOrganDragsTheOtherAndReleasingReturnsBothToRest) {
  TwoOrganScene two = twoOrganScene();
  Scene& scene = two.scene;
  ConnectiveCoupling& coupling = *scene.coupling;
  const RigidNodeModel& layer = *scene.layers[0];
  const int tets = scene.meshes[0].numElements() + scene.meshes[1].numElements();
  std::printf("two organs: %d tets, layer %d rigid nodes, %d samples, %.3e m^3; %d unknowns\n",
              tets, layer.numNodes(), layer.numSamples(), layer.totalVolume(),
              coupling.numUnknowns());
  EXPECT_NEAR(tets, 3000, 300);
  EXPECT_NEAR(layer.numNodes(), 80, 20);
  EXPECT_NEAR(layer.numSamples(), 300, 60);
  ASSERT_GE(two.grasped.size(), 4u);

  CoupledSolverSettings settings;
  settings.mass_damping = 5.0;
  settings.stiffness_damping = 0.01;
  CoupledSolver solver(coupling, settings);
  CoupledState state = coupling.restState();
  const Eigen::Vector3d pull(-0.01, 0.0, 0.004);  // away from the second organ [m]
  const double dt = 0.01;
  const int pull_steps = 40, release_steps = 400;
  CoupledLoads loads;
  double seconds = 0.0;
  StepPhaseTimes phases;
  for (int i = 0; i < pull_steps; ++i) {
    const double ramp = std::min(1.0, (i + 1) / 20.0);
    loads.springs.clear();
    for (const int a : two.grasped)
      loads.springs.push_back(
          CoupledSpring{0, a, Eigen::Vector3d(scene.meshes[0].nodes.col(a)) + ramp * pull, 200.0});
    const double t0 = threadSeconds();
    const StepReport report = solver.step(loads, dt, state);
    seconds += threadSeconds() - t0;
    phases.forces += report.phases.forces;
    phases.factorization += report.phases.factorization;
    phases.linear_solve += report.phases.linear_solve;
    ASSERT_EQ(report.status, StepStatus::Ok) << "pull step " << i;
  }
  std::printf(
      "two organs: %.2f ms/step CPU (wall: assembly %.2f, factorization %.2f, solve %.2f ms; one "
      "core, shared machine)\n",
      1e3 * seconds / pull_steps, 1e3 * phases.forces / pull_steps,
      1e3 * phases.factorization / pull_steps, 1e3 * phases.linear_solve / pull_steps);
  const Eigen::Vector3d grasped = meanDisplacement(scene, state, 0, two.grasped);
  const Eigen::Vector3d dragged = meanDisplacement(scene, state, 1, two.facing);
  const Eigen::Vector3d direction = pull.normalized();
  std::printf(
      "two organs pulled: grasped %.3e m, second organ's facing nodes %.3e m along the "
      "pull (%.3e m across)\n",
      grasped.dot(direction), dragged.dot(direction),
      (dragged - dragged.dot(direction) * direction).norm());
  EXPECT_GT(grasped.dot(direction), 0.5 * pull.norm());
  EXPECT_GT(dragged.dot(direction), 0.01 * pull.norm());
  EXPECT_GT(dragged.dot(direction), (dragged - dragged.dot(direction) * direction).norm());

  // Release: both organs return to rest.
  loads.springs.clear();
  double largest = 0.0;
  int step = 0;
  for (; step < release_steps; ++step) {
    ASSERT_EQ(solver.step(loads, dt, state).status, StepStatus::Ok) << "release step " << step;
    largest = largestOrganDifference(state, coupling.restState());
    if (largest < 1e-6 * pull.norm()) break;
  }
  std::printf("two organs released: largest displacement %.3e m after %d steps\n", largest,
              step + 1);
  EXPECT_LT(largest, 1e-6 * pull.norm());
}

/// A tool yanking the grasped organ far in one step (a hostile motion): the spring forces make
/// the mapping term so indefinite that no rotation shift factorizes the full tangent. The step
/// falls back to the material tangent, moves the grasped nodes toward the tool, and once
/// released both organs return to rest on the full tangent.
TEST(ConnectiveCouplingScenes, AYankThatMakesTheFullTangentIndefiniteStillSteps) {
  TwoOrganScene two = twoOrganScene();
  Scene& scene = two.scene;
  ConnectiveCoupling& coupling = *scene.coupling;
  CoupledSolverSettings settings;
  settings.mass_damping = 5.0;
  settings.stiffness_damping = 0.01;
  CoupledSolver solver(coupling, settings);
  CoupledState state = coupling.restState();
  const Eigen::Vector3d yank(-0.05, 0.0, 0.0);  // 5 cm in one step [m]
  CoupledLoads loads;
  for (const int a : two.grasped)
    loads.springs.push_back(
        CoupledSpring{0, a, Eigen::Vector3d(scene.meshes[0].nodes.col(a)) + yank, 2000.0});
  const double dt = 0.01;
  int fallbacks = 0;
  for (int i = 0; i < 10; ++i) {
    const StepReport report = solver.step(loads, dt, state);
    ASSERT_EQ(report.status, StepStatus::Ok) << "yank step " << i;
    ASSERT_TRUE(std::isfinite(report.energy)) << "yank step " << i;
    fallbacks += solver.usedMaterialTangentOnly() ? 1 : 0;
  }
  const Eigen::Vector3d grasped = meanDisplacement(scene, state, 0, two.grasped);
  std::printf("yank: %d of 10 steps on the material tangent; grasped nodes moved %.3e m along it\n",
              fallbacks, grasped.dot(yank.normalized()));
  EXPECT_GT(fallbacks, 0);
  EXPECT_GT(grasped.dot(yank.normalized()), 0.3 * yank.norm());
  EXPECT_LT(grasped.norm(), 1.5 * yank.norm());

  loads.springs.clear();
  double largest = 0.0;
  int step = 0;
  for (; step < 1000; ++step) {
    ASSERT_EQ(solver.step(loads, dt, state).status, StepStatus::Ok) << "release step " << step;
    largest = largestOrganDifference(state, coupling.restState());
    if (largest < 1e-6 * yank.norm()) break;
  }
  std::printf("yank released: largest displacement %.3e m after %d steps\n", largest, step + 1);
  EXPECT_LT(largest, 1e-6 * yank.norm());
  EXPECT_FALSE(solver.usedMaterialTangentOnly());
}

TEST(ConnectiveCoupling, BadInputIsRejectedWithTheFieldNamed) {
  Scene scene = twoBoxScene(1.0, none);
  std::vector<CoupledOrgan> organs(1);
  organs[0].model = scene.organs[0].get();
  std::vector<CoupledLayer> layers(1);
  layers[0].model = scene.layers[0].get();
  std::vector<OrganLayerAttachment> attachments(1);
  attachments[0].nodes = {0, 1};
  auto make = [&]() { ConnectiveCoupling(organs, layers, attachments); };
  attachments[0].neighbours = 0;
  expectInvalidArgument(make, "attachment 0 neighbours = 0 out of range");
  attachments[0].neighbours = 4;
  attachments[0].layer = 1;
  expectInvalidArgument(make, "attachment 0 layer = 1 out of range [0, 1)");
  attachments[0].layer = 0;
  attachments[0].nodes = {0, 0};
  expectInvalidArgument(make, "attachment 0 node 0 is attached twice");
  attachments[0].nodes = {0, 1000};
  expectInvalidArgument(make, "attachment 0 node = 1000 out of range");
  attachments[0].nodes = {0};
  organs[0].fixed_nodes = {0};
  expectInvalidArgument(make, "attachment 0 node 0 is fixed");
  organs[0].fixed_nodes = {};
  layers[0].fixed_nodes = {-1};
  expectInvalidArgument(make, "layer 0 fixed rigid node = -1 out of range");
  layers[0].fixed_nodes = {};
  organs[0].model = nullptr;
  expectInvalidArgument(make, "organ 0 has no model");
  organs[0].model = scene.organs[0].get();

  ConnectiveCoupling& coupling = *scene.coupling;
  CoupledState state = coupling.restState();
  CoupledLoads loads;
  loads.springs.push_back(CoupledSpring{0, 0, Eigen::Vector3d::Zero(), -1.0});
  expectInvalidArgument([&]() { coupling.assemble(state, loads, {}, true); },
                        "loads.springs stiffness = -1 N/m must be finite and >= 0");
  loads.springs.clear();
  loads.forces.push_back(CoupledPointForce{2, 0, Eigen::Vector3d::Zero()});
  expectInvalidArgument([&]() { coupling.assemble(state, loads, {}, true); },
                        "loads.forces organ = 2 out of range");
  state.organ_positions.pop_back();
  expectInvalidArgument([&]() { coupling.applyMapping(state); }, "state does not match");
  CoupledSolverSettings settings;
  settings.mass_damping = -1.0;
  expectInvalidArgument([&]() { CoupledSolver solver(coupling, settings); },
                        "CoupledSolverSettings.mass_damping");
}

}  // namespace
}  // namespace surgical_sim::core
