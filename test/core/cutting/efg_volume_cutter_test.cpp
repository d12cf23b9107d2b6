// Meshless EFG volume cutting (Magnoux's scenes): link severing by continuous CCD, neighbour
// re-selection by graph distance, per-IP recompute, mass conservation, pieces.
#include "surgical_sim/core/cutting/efg_volume_cutter.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/cutting/edge_sweep_ccd.h"
#include "surgical_sim/core/mesh/surface_generators.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"
#include "surgical_sim/core/solve/pcg_solver.h"
#include "surgical_sim/core/tissue/material.h"

namespace surgical_sim::core {
namespace {

constexpr double kRho = 1000.0;  // [kg/m^3]

EfgModel efgModel(const TriMesh& surface, double spacing, double young = 3e4) {
  EfgOptions o;
  o.spacing = spacing;
  return EfgModel(surface, Material::create(young, 0.3, kRho), o);
}

// Cylinder of radius 1 cm and length 4 cm along z, d = 2.5 mm.
EfgModel cylinder() { return efgModel(makeCylinder(0.01, 0.04, 32, 4), 0.0025); }

// A straight blade along x at (y, z), 6 cm long.
Eigen::Matrix3Xd straightBlade(double y, double z) {
  Eigen::Matrix3Xd b(3, 2);
  b << -0.03, 0.03, y, y, z, z;
  return b;
}

double totalMass(const EfgModel& m) { return m.lumpedMass().sum() / 3.0; }

Eigen::VectorXd translated(const EfgModel& m, const Eigen::Vector3d& t) {
  Eigen::VectorXd x = m.restPositions();
  for (int i = 0; i < m.numNodes(); ++i) x.segment<3>(3 * i) += t;
  return x;
}

// Partition of unity, linear completeness (values and gradients) at the given IPs.
void expectLinearCompleteness(const EfgModel& m, const std::vector<int>& ips) {
  for (const int e : ips) {
    const std::vector<int>& p = m.ipParticles(e);
    const Eigen::VectorXd phi = m.shapeValues(e);
    const Eigen::MatrixXd G = m.shapeGradients(e);
    ASSERT_TRUE(phi.allFinite() && G.allFinite()) << "IP " << e;
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    Eigen::Matrix3d grad = Eigen::Matrix3d::Zero();
    for (size_t a = 0; a < p.size(); ++a) {
      x += phi(static_cast<Eigen::Index>(a)) * m.grid().particles.col(p[a]);
      grad += m.grid().particles.col(p[a]) * G.row(static_cast<Eigen::Index>(a));
    }
    EXPECT_NEAR(phi.sum(), 1.0, 1e-12) << "IP " << e;
    EXPECT_NEAR(G.colwise().sum().norm(), 0.0, 1e-9 / m.grid().spacing) << "IP " << e;
    EXPECT_LT((x - m.grid().integration_points.col(e)).norm(), 1e-12 * m.grid().spacing)
        << "IP " << e;
    EXPECT_LT((grad - Eigen::Matrix3d::Identity()).norm(), 1e-10) << "IP " << e;
  }
}

// Rigid motion: zero force; force = -dE/dx and K = -df/dx by central differences at a deformed
// state, on the DOFs of the given IPs' particles.
void expectConsistentMechanics(const EfgModel& m, const std::vector<int>& ips) {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  Eigen::VectorXd x = m.restPositions();
  for (int i = 0; i < m.numNodes(); ++i)
    x.segment<3>(3 * i) = R * x.segment<3>(3 * i) + Eigen::Vector3d(0.1, -0.2, 0.3);
  Eigen::VectorXd f_rigid = Eigen::VectorXd::Zero(x.size());
  m.addInternalForce(x, f_rigid);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.05 * m.grid().spacing);
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = m.restPositions()(i) + noise(rng);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  m.addInternalForce(x, f);
  ASSERT_TRUE(f.allFinite());
  const double scale = f.cwiseAbs().maxCoeff();  // [N]
  EXPECT_LT(f_rigid.cwiseAbs().maxCoeff(), 1e-9 * scale);
  Eigen::SparseMatrix<double> K = m.stiffnessPattern();
  m.assembleStiffness(x, TangentMode::Exact, K);
  ASSERT_TRUE(
      Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(K.valuePtr(), K.nonZeros())).allFinite());
  const double h = 1e-7 * m.grid().spacing;
  int checked = 0;
  for (const int e : ips) {
    for (const int p : m.ipParticles(e)) {
      if (checked >= 24) return;
      const int dof = 3 * p + checked % 3;
      ++checked;
      Eigen::VectorXd xp = x, xm = x;
      xp(dof) += h;
      xm(dof) -= h;
      const double dE = (m.energy(xp) - m.energy(xm)) / (2.0 * h);
      EXPECT_NEAR(f(dof), -dE, 1e-5 * scale) << "dof " << dof;
      Eigen::VectorXd fp = Eigen::VectorXd::Zero(x.size()), fm = fp;
      m.addInternalForce(xp, fp);
      m.addInternalForce(xm, fm);
      const Eigen::VectorXd column = -(fp - fm) / (2.0 * h);
      const Eigen::VectorXd k_col = K.col(dof);
      EXPECT_LT((column - k_col).norm(), 1e-5 * (k_col.norm() + 1.0)) << "dof " << dof;
    }
  }
}

// Common invariants after cuts of `original` (same grid) into `cut`.
void expectInvariants(const EfgModel& before, const EfgModel& cut, const std::vector<int>& ips) {
  EXPECT_EQ(cut.numNodes(), before.numNodes());
  EXPECT_NEAR(totalMass(cut), totalMass(before), 1e-12 * totalMass(before));
  EXPECT_GT(cut.lumpedMass().minCoeff(), -1e-15 * totalMass(before));
  EXPECT_TRUE(cut.lumpedMass().allFinite());
  EXPECT_NEAR(cut.grid().volumes.sum(), before.grid().volumes.sum(),
              1e-12 * before.grid().volumes.sum());
  expectLinearCompleteness(cut, ips);
  expectConsistentMechanics(cut, ips);
}

// Severs by a blade along x at z = z_cut moving in y from below the cylinder to above it.
BladeSweep upwardSweep(double z_cut) {
  return {straightBlade(-0.015, z_cut), straightBlade(0.015, z_cut)};
}

// Particle pieces match the side of the plane z = z_cut.
void expectSplitAt(const EfgVolumeCutter& cutter, double z_cut) {
  EXPECT_EQ(cutter.pieces(), 2);
  const std::vector<int> label = cutter.particlePieces();
  const Eigen::Matrix3Xd& X = cutter.model().grid().particles;
  int below = -1, above = -1;
  for (int p = 0; p < X.cols(); ++p)
    (X(2, p) < z_cut ? below : above) = label[static_cast<size_t>(p)];
  ASSERT_NE(below, above);
  for (int p = 0; p < X.cols(); ++p)
    EXPECT_EQ(label[static_cast<size_t>(p)], X(2, p) < z_cut ? below : above) << "particle " << p;
}

// Position of graph node v of `cutter` at particle positions x: a particle's, or an IP's
// sum_a phi_a x_a over its current particles [m].
Eigen::Vector3d nodePosition(const EfgVolumeCutter& cutter, const Eigen::VectorXd& x, int v) {
  const int n = cutter.graph().numParticles();
  if (v < n) return x.segment<3>(3 * v);
  const std::vector<int>& particles = cutter.model().ipParticles(v - n);
  const Eigen::Map<const Eigen::VectorXd> phi = cutter.model().shapeValues(v - n);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (size_t a = 0; a < particles.size(); ++a)
    sum += phi(static_cast<Eigen::Index>(a)) * x.segment<3>(3 * particles[a]);
  return sum;
}

// Brute force: the alive links of `cutter` that a sweep test against every blade segment finds
// crossed, ends moving from x0 to x1, in link order.
std::vector<int> crossedLinks(const EfgVolumeCutter& cutter, const BladeSweep& s,
                              const Eigen::VectorXd& x0, const Eigen::VectorXd& x1) {
  const EfgTopologyGraph& g = cutter.graph();
  std::vector<int> crossed;
  for (int l = 0; l < static_cast<int>(g.links().size()); ++l) {
    if (!g.alive(l)) continue;
    const EfgTopologyGraph::Link& link = g.links()[static_cast<size_t>(l)];
    for (Eigen::Index i = 0; i + 1 < s.start.cols(); ++i)
      if (edgeSweepCrossing(s.start.col(i), s.start.col(i + 1), s.end.col(i), s.end.col(i + 1),
                            nodePosition(cutter, x0, link.a), nodePosition(cutter, x0, link.b),
                            nodePosition(cutter, x1, link.a), nodePosition(cutter, x1, link.b),
                            1e-9 * cutter.model().grid().spacing)) {
        crossed.push_back(l);
        break;
      }
  }
  return crossed;
}

// Particle positions at the step start and end: rest particle X at R0 X + T0 (R1 X + T1), each
// displaced by u(rng) along each axis.
std::array<Eigen::VectorXd, 2> carriedParticles(const EfgModel& model, const Eigen::Matrix3d& R0,
                                                const Eigen::Vector3d& T0,
                                                const Eigen::Matrix3d& R1,
                                                const Eigen::Vector3d& T1, std::mt19937& rng,
                                                std::uniform_real_distribution<double>& u) {
  std::array<Eigen::VectorXd, 2> x = {model.restPositions(), model.restPositions()};
  for (int p = 0; p < model.numNodes(); ++p) {
    const Eigen::Vector3d X = model.grid().particles.col(p);
    x[0].segment<3>(3 * p) = R0 * X + T0 + Eigen::Vector3d(u(rng), u(rng), u(rng));
    x[1].segment<3>(3 * p) = R1 * X + T1 + Eigen::Vector3d(u(rng), u(rng), u(rng));
  }
  return x;
}

// A blade polyline at `points` (3 x k, body frame) sweeping to y = y_end, carried by the body:
// (R0, T0) at the step start, (R1, T1) at its end.
BladeSweep carriedSweep(const Eigen::Matrix3Xd& points, double y_end, const Eigen::Matrix3d& R0,
                        const Eigen::Vector3d& T0, const Eigen::Matrix3d& R1,
                        const Eigen::Vector3d& T1) {
  BladeSweep s;
  s.end = points;
  s.end.row(1).setConstant(y_end);
  s.start = (R0 * points).colwise() + T0;
  s.end = (R1 * s.end).colwise() + T1;
  return s;
}

TEST(EfgTopologyGraph, GridNeighbourLinksAndInitialNeighbourhoods) {
  const EfgModel m = cylinder();
  EfgTopologyGraph g(m);
  const int n = m.numNodes();
  const Eigen::Matrix3Xd& X = m.grid().particles;
  const double side = 2.0 * m.grid().spacing;
  int particle_links = 0, ip_links = 0;
  for (const EfgTopologyGraph::Link& l : g.links()) {
    if (l.b < n) {
      ++particle_links;
      EXPECT_NEAR(l.rest_length, side, 1e-12 * side);
      EXPECT_NEAR((X.col(l.a) - X.col(l.b)).cwiseAbs().maxCoeff(), side, 1e-12 * side);
    } else {
      ++ip_links;
    }
  }
  // Every pair of particles one DOF cell apart along an axis is linked.
  int pairs = 0;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      const Eigen::Vector3d d = (X.col(a) - X.col(b)).cwiseAbs();
      pairs += std::abs(d.maxCoeff() - side) < 1e-9 * side && d.sum() < 1.5 * side;
    }
  EXPECT_EQ(particle_links, pairs);
  EXPECT_EQ(ip_links, 8 * m.numIntegrationPoints());
  // From an IP, the search reaches its 8 cell corners before any other particle.
  const int e = m.numIntegrationPoints() / 2;
  std::vector<int> first;
  g.searchFrom(g.ipNode(e), [&](int v, double, int) {
    if (v < n) first.push_back(v);
    return first.size() < 8;
  });
  std::sort(first.begin(), first.end());
  EXPECT_EQ(first, m.ipParticles(e));
  std::vector<int> labels;
  EXPECT_EQ(g.components(labels), 1);
  for (const int l : g.linksOf(g.ipNode(e))) g.sever(l);
  EXPECT_EQ(g.components(labels), 2);  // the IP alone
  EXPECT_EQ(g.numSevered(), 8);
}

// Each settled node's link is alive, joins it to a node settled before it, and makes up its
// distance: its shortest path ends with that link, also after severing links on the way.
TEST(EfgTopologyGraph, SearchReportsTheLastLinkOfEachShortestPath) {
  const EfgModel m = cylinder();
  EfgTopologyGraph g(m);
  const int source = g.ipNode(m.numIntegrationPoints() / 2);
  for (int round = 0; round < 2; ++round) {
    std::vector<double> settled(static_cast<size_t>(g.numNodes()), -1.0);
    int count = 0;
    g.searchFrom(source, [&](int v, double r, int link) {
      if (v == source) {
        EXPECT_EQ(link, -1);
      } else {
        EXPECT_TRUE(g.alive(link));
        const int from = g.otherEnd(link, v);
        EXPECT_GE(settled[static_cast<size_t>(from)], 0.0) << "node " << v;
        EXPECT_DOUBLE_EQ(r, settled[static_cast<size_t>(from)] +
                                g.links()[static_cast<size_t>(link)].rest_length);
      }
      settled[static_cast<size_t>(v)] = r;
      return ++count < 300;
    });
    EXPECT_EQ(count, 300);
    // Sever the source's own links to half its particles: paths now detour through the rest.
    for (size_t i = 0; i < g.linksOf(source).size(); i += 2) g.sever(g.linksOf(source)[i]);
  }
}

// What lets a cut skip the searches it does not touch: severing links off a search's paths (the
// links it reports) leaves the search the same, node for node; severing one of its links does not.
TEST(EfgTopologyGraph, SeveringLinksOffTheSearchPathsLeavesTheSearchUnchanged) {
  const EfgModel m = cylinder();
  EfgTopologyGraph g(m);
  const int source = g.ipNode(m.numIntegrationPoints() / 3);
  using Settled = std::vector<std::pair<int, double>>;
  const auto search = [&](std::vector<int>* links) {
    Settled settled;
    g.searchFrom(source, [&](int v, double r, int link) {
      settled.emplace_back(v, r);
      if (links && link >= 0) links->push_back(link);
      return settled.size() < 120;
    });
    return settled;
  };
  std::vector<int> paths;
  const Settled before = search(&paths);
  std::sort(paths.begin(), paths.end());
  int severed = 0;
  for (int l = 0; l < static_cast<int>(g.links().size()); l += 3) {
    if (std::binary_search(paths.begin(), paths.end(), l)) continue;
    g.sever(l);
    ++severed;
  }
  ASSERT_GT(severed, 1000);
  EXPECT_EQ(search(nullptr), before);
  g.sever(paths[paths.size() / 2]);
  EXPECT_NE(search(nullptr), before);
}

TEST(EfgVolumeCutter, StaticCylinderAndMovingBladeSeverTheSameLinksAsTheMirroredMotion) {
  const double z_cut = 0.0006;  // between particle and IP planes [m]
  EfgModel a = cylinder();
  const EfgModel before = a;
  EfgVolumeCutter blade_moves(a);
  const EfgCutResult ra = blade_moves.cut(upwardSweep(z_cut), a.restPositions(), a.restPositions());
  EfgModel b = cylinder();
  EfgVolumeCutter body_moves(b);
  const BladeSweep fixed{straightBlade(-0.015, z_cut), straightBlade(-0.015, z_cut)};
  const EfgCutResult rb =
      body_moves.cut(fixed, b.restPositions(), translated(b, Eigen::Vector3d(0.0, -0.03, 0.0)));
  ASSERT_FALSE(ra.severed_links.empty());
  EXPECT_EQ(ra.severed_links, rb.severed_links);
  EXPECT_EQ(ra.changed_ips, rb.changed_ips);
  EXPECT_TRUE(ra.pieces_changed);
  EXPECT_EQ(ra.pieces, 2);
  // Exactly the links crossing the plane are severed.
  const EfgTopologyGraph& g = blade_moves.graph();
  const auto rest = [&](int v) -> Eigen::Vector3d {
    return v < g.numParticles()
               ? Eigen::Vector3d(a.grid().particles.col(v))
               : Eigen::Vector3d(a.grid().integration_points.col(v - g.numParticles()));
  };
  for (size_t l = 0; l < g.links().size(); ++l) {
    const bool crosses =
        (rest(g.links()[l].a).z() - z_cut) * (rest(g.links()[l].b).z() - z_cut) < 0.0;
    EXPECT_EQ(g.alive(static_cast<int>(l)), !crosses) << "link " << l;
  }
  expectSplitAt(blade_moves, z_cut);
  expectInvariants(before, a, ra.changed_ips);
}

TEST(EfgVolumeCutter, SeversEveryLinkASweepTestOfEveryLinkFindsUnderLargeMotion) {
  // The cylinder turned by 1 rad and moved 20 m at the step start, by 1.3 rad and 6 cm more at
  // its end, every particle displaced at random by up to 0.1 IP spacing along each axis (links
  // stretch far less than 3 times); a kinked two-segment blade, fixed in the body's frame at
  // each end of the step, sweeps 3 cm across it there. The severed links are exactly those a
  // sweep test of every link finds crossed, in link order.
  EfgModel model = cylinder();
  EfgVolumeCutter cutter(model);
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 2.0, -0.5).normalized();
  const Eigen::Matrix3d R0 = Eigen::AngleAxisd(1.0, axis).toRotationMatrix();
  const Eigen::Matrix3d R1 = Eigen::AngleAxisd(1.3, axis).toRotationMatrix();
  const Eigen::Vector3d T0(20.0, -5.0, 3.0), T1 = T0 + Eigen::Vector3d(0.05, 0.02, -0.03);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.1 * model.grid().spacing, 0.1 * model.grid().spacing);
  const auto [x0, x1] = carriedParticles(model, R0, T0, R1, T1, rng, u);
  Eigen::Matrix3Xd blade(3, 3);
  blade << -0.03, 0.0, 0.03, -0.015, -0.015, -0.015, 0.0006, 0.004, 0.0006;
  const BladeSweep s = carriedSweep(blade, 0.015, R0, T0, R1, T1);
  const std::vector<int> expected = crossedLinks(cutter, s, x0, x1);
  const EfgCutResult r = cutter.cut(s, x0, x1);
  EXPECT_GT(expected.size(), 100u);
  EXPECT_EQ(r.severed_links, expected);
}

TEST(EfgVolumeCutter, SeversEveryCrossedLinkHoweverFarTheParticlesMove) {
  // The cylinder moved 0.3 m (60 particle spacings) and turned, every particle displaced at random
  // by up to 4 particle spacings along each axis at each end of the step (links stretch to many
  // times their rest length); two kinked blades sweep across the displaced body in turn, the
  // second after the first cut re-selected IPs. The severed links are exactly those a sweep test
  // of every alive link finds crossed, in link order.
  EfgModel model = cylinder();
  EfgVolumeCutter cutter(model);
  const EfgTopologyGraph& g = cutter.graph();
  const double step = 2.0 * model.grid().spacing;  // particle spacing [m]
  const Eigen::Vector3d axis = Eigen::Vector3d(-0.3, 1.0, 0.7).normalized();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-4.0 * step, 4.0 * step);
  for (int sweep = 0; sweep < 2; ++sweep) {
    const Eigen::Matrix3d R0 = Eigen::AngleAxisd(0.4 + sweep, axis).toRotationMatrix();
    const Eigen::Matrix3d R1 = Eigen::AngleAxisd(0.6 + sweep, axis).toRotationMatrix();
    const Eigen::Vector3d T0(0.3, -0.2, 0.1), T1 = T0 + Eigen::Vector3d(0.01, -0.02, 0.005);
    const auto [x0, x1] = carriedParticles(model, R0, T0, R1, T1, rng, u);
    Eigen::Matrix3Xd blade(3, 3);
    blade << -0.03, 0.0, 0.03, -0.02, -0.02, -0.02, 0.002 - 0.01 * sweep, 0.006, 0.002;
    const BladeSweep s = carriedSweep(blade, 0.02, R0, T0, R1, T1);
    const std::vector<int> expected = crossedLinks(cutter, s, x0, x1);
    // Some crossed link is stretched beyond 3 times its rest length.
    double stretch = 0.0;  // [-]
    for (const int l : expected) {
      const EfgTopologyGraph::Link& link = g.links()[static_cast<size_t>(l)];
      for (const Eigen::VectorXd* x : {&x0, &x1})
        stretch = std::max(
            stretch, (nodePosition(cutter, *x, link.a) - nodePosition(cutter, *x, link.b)).norm() /
                         link.rest_length);
    }
    EXPECT_GT(stretch, 3.0) << "sweep " << sweep;
    const EfgCutResult r = cutter.cut(s, x0, x1);
    EXPECT_GT(expected.size(), 100u) << "sweep " << sweep;
    EXPECT_EQ(r.severed_links, expected) << "sweep " << sweep;
    EXPECT_FALSE(r.changed_ips.empty()) << "sweep " << sweep;
  }
}

TEST(EfgVolumeCutter, SeversTheLinksOfAnIpCarriedBeyondItsParticles) {
  // After a cut at rest, the re-selected IP e with the largest sum_a |phi_a| (L > 1: some
  // phi_a < 0) has its particles moved 10 m along +z (phi_a > 0) or -z (phi_a < 0): e moves L x
  // 10 m, every particle at most 10 m. A blade sweeping across the body halfway between the
  // highest particle's reach and e's height severs e's links (and any other link reaching that
  // high): exactly those a sweep test of every alive link finds crossed.
  EfgModel model = cylinder();
  EfgVolumeCutter cutter(model);
  const EfgCutResult first =
      cutter.cut(upwardSweep(0.0006), model.restPositions(), model.restPositions());
  int e = -1;
  double gain = 0.0;  // L [-]
  for (const int c : first.changed_ips) {
    const double l1 = model.shapeValues(c).lpNorm<1>();
    if (model.grid().volumes(c) > 0.0 && l1 > gain) {
      gain = l1;
      e = c;
    }
  }
  ASSERT_GE(e, 0);
  ASSERT_GT(gain, 1.02);
  const double lift = 10.0;  // [m]
  Eigen::VectorXd x = model.restPositions();
  const std::vector<int>& particles = model.ipParticles(e);
  for (size_t a = 0; a < particles.size(); ++a)
    x(3 * particles[a] + 2) +=
        model.shapeValues(e)(static_cast<Eigen::Index>(a)) > 0.0 ? lift : -lift;
  const double top = model.grid().particles.row(2).maxCoeff() + lift;                  // [m]
  const double z = 0.5 * (top + model.grid().integration_points(2, e) + gain * lift);  // [m]
  ASSERT_GT(z, top + 0.05);
  const BladeSweep s{straightBlade(-0.03, z), straightBlade(0.03, z)};
  const std::vector<int> expected = crossedLinks(cutter, s, x, x);
  const EfgCutResult r = cutter.cut(s, x, x);
  ASSERT_FALSE(expected.empty());
  EXPECT_EQ(r.severed_links, expected);
}

TEST(EfgVolumeCutter, CylinderFallingOntoAStaticBladeIsCutInTwo) {
  const double z_cut = 0.0006;
  EfgModel model = cylinder();
  const EfgModel before = model;
  EfgVolumeCutter cutter(model);
  const BladeSweep blade{straightBlade(-0.0125, z_cut), straightBlade(-0.0125, z_cut)};
  DynamicsProblem problem;
  problem.model = &model;
  const Eigen::Vector3d g(0.0, -9.81, 0.0);
  SimulationState state{model.restPositions(), Eigen::VectorXd::Zero(model.restPositions().size()),
                        0.0};
  const auto integrator = makeIntegrator(IntegratorKind::ImplicitEulerLinearized, {},
                                         makeLinearSolver(SolverKind::Cholmod, {}));
  const double dt = 0.005;
  std::vector<int> changed;
  int cutting_steps = 0;
  for (int i = 0; i < 30; ++i) {
    problem.external_force = model.bodyForce(g);
    const Eigen::VectorXd x_start = state.x;
    ASSERT_EQ(integrator->step(problem, dt, state).status, StepStatus::Ok) << "step " << i;
    const EfgCutResult r = cutter.cut(blade, x_start, state.x);
    if (!r.changed_ips.empty()) {
      ++cutting_steps;
      integrator->reset();  // new stiffness pattern
      changed.insert(changed.end(), r.changed_ips.begin(), r.changed_ips.end());
    }
    ASSERT_TRUE(state.x.allFinite());
  }
  EXPECT_GT(cutting_steps, 2);  // progressive: over several steps
  // The whole body passed the blade.
  double top = -INFINITY;
  for (int i = 0; i < model.numNodes(); ++i) top = std::max(top, state.x(3 * i + 1));
  ASSERT_LT(top, -0.0125);
  expectSplitAt(cutter, z_cut);
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  expectInvariants(before, model, changed);
}

TEST(EfgVolumeCutter, CurvedBladeTwistingWhileAdvancingCutsThrough) {
  EfgModel model = cylinder();
  const EfgModel before = model;
  EfgVolumeCutter cutter(model);
  // Arc blade in the xz-plane, bulging by 4 mm, rotating 0.4 rad about y as it rises.
  const auto blade = [](double s) {
    const int k = 7;
    Eigen::Matrix3Xd b(3, k);
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(0.4 * s, Eigen::Vector3d::UnitY()).toRotationMatrix();
    for (int i = 0; i < k; ++i) {
      const double x = -0.03 + 0.06 * i / (k - 1);
      b.col(i) = R * Eigen::Vector3d(x, 0.0, 0.0011 + 0.004 * (1.0 - x * x / 0.0009)) +
                 Eigen::Vector3d(0.0, -0.015 + 0.03 * s, 0.0);
    }
    return b;
  };
  const int steps = 10;
  std::vector<int> changed;
  int severed = 0;
  for (int i = 0; i < steps; ++i) {
    const EfgCutResult r = cutter.cut({blade(double(i) / steps), blade(double(i + 1) / steps)},
                                      model.restPositions(), model.restPositions());
    severed += static_cast<int>(r.severed_links.size());
    changed.insert(changed.end(), r.changed_ips.begin(), r.changed_ips.end());
  }
  EXPECT_GT(severed, 50);
  EXPECT_EQ(cutter.pieces(), 2);
  EXPECT_EQ(cutter.graph().numSevered(), severed);
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  expectInvariants(before, model, changed);
}

TEST(EfgVolumeCutter, TorusSectionCutFreeFallsAtGWhileTheHeldPartStays) {
  const double R = 0.03, r = 0.01;
  EfgModel model = efgModel(makeTorus(R, r, 48, 16), 0.003, 1e6);
  const EfgModel before = model;
  EfgVolumeCutter cutter(model);
  // Radial blades sweeping down through the tube at angle u; the last one only half-way.
  const auto radial = [&](double u, double z_end) {
    const Eigen::Vector3d d(std::cos(u), std::sin(u), 0.0);
    Eigen::Matrix3Xd start(3, 2), end(3, 2);
    start << (R - 2 * r) * d + Eigen::Vector3d(0, 0, 2 * r),
        (R + 2 * r) * d + Eigen::Vector3d(0, 0, 2 * r);
    end = start;
    end.row(2).setConstant(z_end);
    return BladeSweep{start, end};
  };
  std::vector<int> changed;
  std::vector<int> unused;  // particles left without material: pinned
  for (const auto& [u, z_end] :
       {std::pair{0.45, -2 * r}, std::pair{-0.6, -2 * r}, std::pair{2.5, 0.0}}) {
    const EfgCutResult c =
        cutter.cut(radial(u, z_end), model.restPositions(), model.restPositions());
    ASSERT_FALSE(c.severed_links.empty());
    unused.insert(unused.end(), c.unused_particles.begin(), c.unused_particles.end());
    changed.insert(changed.end(), c.changed_ips.begin(), c.changed_ips.end());
  }
  EXPECT_EQ(cutter.pieces(), 2);
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  expectInvariants(before, model, changed);

  EXPECT_EQ(cutter.unusedParticles(), [&] {
    std::sort(unused.begin(), unused.end());
    return unused;
  }());
  for (const int p : unused) EXPECT_EQ(model.lumpedMass()(3 * p), 0.0);
  // Hold the particles with x < -R / 2 and the unused ones; gravity -z.
  const std::vector<int> label = cutter.particlePieces();
  const Eigen::Matrix3Xd& X = model.grid().particles;
  int free_piece = -1;
  (X.colwise() - Eigen::Vector3d(R, 0.0, 0.0)).colwise().squaredNorm().minCoeff(&free_piece);
  free_piece = label[static_cast<size_t>(free_piece)];
  DynamicsProblem problem;
  problem.model = &model;
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  problem.external_force = model.bodyForce(g);
  for (int p = 0; p < model.numNodes(); ++p) {
    const bool pinned = std::find(unused.begin(), unused.end(), p) != unused.end();
    if (X(0, p) >= -R / 2 && !pinned) continue;
    if (!pinned) {
      ASSERT_NE(label[static_cast<size_t>(p)], free_piece);
    }
    for (int k = 0; k < 3; ++k) problem.dirichlet.dofs.push_back(3 * p + k);
  }
  problem.dirichlet.positions.resize(static_cast<Eigen::Index>(problem.dirichlet.dofs.size()));
  for (size_t i = 0; i < problem.dirichlet.dofs.size(); ++i)
    problem.dirichlet.positions(static_cast<Eigen::Index>(i)) =
        model.restPositions()(problem.dirichlet.dofs[i]);
  SimulationState state{model.restPositions(), Eigen::VectorXd::Zero(model.restPositions().size()),
                        0.0};
  const auto integrator = makeIntegrator(IntegratorKind::ImplicitEulerLinearized, {},
                                         makeLinearSolver(SolverKind::Cholmod, {}));
  const double dt = 0.01;
  const int steps = 10;
  for (int i = 0; i < steps; ++i)
    ASSERT_EQ(integrator->step(problem, dt, state).status, StepStatus::Ok);
  double free_mass = 0.0, free_dz = 0.0, held_dz = 0.0;
  for (int p = 0; p < model.numNodes(); ++p) {
    const double dz = state.x(3 * p + 2) - model.restPositions()(3 * p + 2);
    const double m = model.lumpedMass()(3 * p);
    if (label[static_cast<size_t>(p)] == free_piece) {
      free_mass += m;
      free_dz += m * dz;
    } else {
      held_dz = std::min(held_dz, dz);
    }
  }
  const double expected = -9.81 * dt * dt * steps * (steps + 1) / 2.0;
  EXPECT_GT(free_mass, 0.05 * totalMass(model));
  EXPECT_NEAR(free_dz / free_mass, expected, 1e-6 * std::abs(expected));
  EXPECT_GT(held_dz, 0.2 * expected);  // the held part only sags
}

TEST(EfgVolumeCutter, ThinSliceStaysFiniteAndIsolatedPointsKeepTheMass) {
  EfgModel model = cylinder();
  const EfgModel before = model;
  EfgVolumeCutter cutter(model);
  std::vector<int> changed, unused;
  int isolated = 0;
  // Two cuts one integration cell apart, then one inside the slice.
  for (const double z : {0.0006, 0.0031, 0.0019}) {
    const EfgCutResult r = cutter.cut(upwardSweep(z), model.restPositions(), model.restPositions());
    changed.insert(changed.end(), r.changed_ips.begin(), r.changed_ips.end());
    for (const int e : r.isolated_ips) EXPECT_EQ(model.grid().volumes(e), 0.0);
    isolated += static_cast<int>(r.isolated_ips.size());
    unused.insert(unused.end(), r.unused_particles.begin(), r.unused_particles.end());
  }
  EXPECT_EQ(cutter.pieces(), 2);  // the slice holds no particle: its IPs are isolated
  EXPECT_GT(isolated, 0);
  // Every particle left without mass (also those only the isolated IPs used) was reported.
  std::sort(unused.begin(), unused.end());
  EXPECT_EQ(cutter.unusedParticles(), unused);
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  std::vector<int> active;
  for (const int e : changed)
    if (model.grid().volumes(e) > 0.0) active.push_back(e);
  expectInvariants(before, model, active);
}

TEST(EfgVolumeCutter, ReusedFactorSolvesLikeTheDirectSolverThroughCutsWithoutReanalysis) {
  // 16 cm long along z: the cuts change the top end's pattern only.
  EfgModel model = efgModel(makeCylinder(0.01, 0.16, 32, 8), 0.0025);
  EfgVolumeCutter cutter(model);
  PcgSettings pcg;
  pcg.refresh_interval = 10;
  auto reuse = std::make_unique<PcgSolver>(PcgPreconditioner::CholeskyReuse, pcg);
  PcgSolver& reused = *reuse;
  const auto direct = makeIntegrator(IntegratorKind::ImplicitEulerLinearized, {},
                                     makeLinearSolver(SolverKind::Cholmod, {}));
  const auto iterative =
      makeIntegrator(IntegratorKind::ImplicitEulerLinearized, {}, std::move(reuse));
  DynamicsProblem problem;
  problem.model = &model;
  std::vector<char> fixed(static_cast<size_t>(model.numNodes()), 0);
  const Eigen::Matrix3Xd& X = model.grid().particles;
  for (int p = 0; p < model.numNodes(); ++p) fixed[static_cast<size_t>(p)] = X(2, p) < -0.075;
  SimulationState a{model.restPositions(), Eigen::VectorXd::Zero(model.restPositions().size()),
                    0.0};
  SimulationState b = a;
  const double dt = 0.01;
  int cuts = 0;
  // A blade descending in steps through the upper part of the cylinder, sideways, while it sags.
  for (int i = 0; i < 9; ++i) {
    problem.external_force = model.bodyForce(Eigen::Vector3d(-9.81, 0.0, 0.0));
    problem.dirichlet = {};
    for (int p = 0; p < model.numNodes(); ++p)
      if (fixed[static_cast<size_t>(p)])
        for (int k = 0; k < 3; ++k) problem.dirichlet.dofs.push_back(3 * p + k);
    problem.dirichlet.positions.resize(static_cast<Eigen::Index>(problem.dirichlet.dofs.size()));
    for (size_t k = 0; k < problem.dirichlet.dofs.size(); ++k)
      problem.dirichlet.positions(static_cast<Eigen::Index>(k)) = a.x(problem.dirichlet.dofs[k]);
    const Eigen::VectorXd x_start = a.x;
    ASSERT_EQ(direct->step(problem, dt, a).status, StepStatus::Ok) << "step " << i;
    ASSERT_EQ(iterative->step(problem, dt, b).status, StepStatus::Ok) << "step " << i;
    const double displacement = (a.x - model.restPositions()).cwiseAbs().maxCoeff();
    EXPECT_LT((a.x - b.x).cwiseAbs().maxCoeff(), 1e-7 * displacement) << "step " << i;
    b = a;  // both continue from the same state
    const double z0 = 0.08 - 0.003 * i, z1 = z0 - 0.003;
    const EfgCutResult r =
        cutter.cut({straightBlade(0.0, z0), straightBlade(0.0, z1)}, x_start, a.x);
    for (const int p : r.unused_particles) fixed[static_cast<size_t>(p)] = 1;
    if (!r.changed_ips.empty()) {
      ++cuts;
      direct->reset();  // new stiffness pattern
      iterative->reset();
    }
  }
  EXPECT_GE(cuts, 6);
  // The factor was kept across the cuts and refreshed on schedule: one analysis, not one a cut.
  EXPECT_EQ(reused.choleskyAnalyses(), 1);
  EXPECT_LE(reused.choleskyFactorizations(), 2);
}

// Progressive cuts of the liver-like body at d = 6 mm (the cutting_bench sequence: 2 sweeps per
// cut, 30 % of the height deep, vertical planes at 137.5 deg steps, golden-ratio offsets), tissue
// at rest. Sweep 55 isolates an IP that alone used a particle: that particle loses its mass and
// must be reported, or the pinned system stays singular (the progressive bench's failed step).
TEST(EfgVolumeCutter, ProgressiveLiverCutsReportEveryParticleLeftWithoutMass) {
  const Eigen::Vector3d semi(0.075, 0.05, 0.03);
  const TriMesh liver = makeLiverSurface(semi, 4);
  EfgModel model = efgModel(liver, 0.006, 5e3);
  EfgVolumeCutter cutter(model);
  const Eigen::VectorXd x = model.restPositions();
  const double top = liver.vertices.row(2).maxCoeff(), bottom = liver.vertices.row(2).minCoeff();
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  std::vector<int> reported;
  int isolated = 0;
  for (int c = 0; c < 28; ++c) {
    const double angle = c * 2.0 * M_PI * (1.0 - golden);
    const Eigen::Vector3d along(std::cos(angle), std::sin(angle), 0.0);
    const Eigen::Vector3d centre =
        semi.x() * (std::fmod(c * golden, 1.0) - 0.5) * Eigen::Vector3d(-along.y(), along.x(), 0);
    const double z_from = top + 0.1 * semi.z(), z_to = top - 0.3 * (top - bottom);
    for (int s = 0; s < 2; ++s) {
      BladeSweep sweep{Eigen::Matrix3Xd(3, 2), Eigen::Matrix3Xd(3, 2)};
      for (int k = 0; k < 2; ++k) {
        const Eigen::Vector3d p = centre + (k ? 3.0 : -3.0) * semi.x() * along;
        sweep.start.col(k) = Eigen::Vector3d(p.x(), p.y(), z_from + (z_to - z_from) * s / 2);
        sweep.end.col(k) = Eigen::Vector3d(p.x(), p.y(), z_from + (z_to - z_from) * (s + 1) / 2);
      }
      const EfgCutResult r = cutter.cut(sweep, x, x);
      isolated += static_cast<int>(r.isolated_ips.size());
      reported.insert(reported.end(), r.unused_particles.begin(), r.unused_particles.end());
      std::sort(reported.begin(), reported.end());
      reported.erase(std::unique(reported.begin(), reported.end()), reported.end());
      // A reported particle may be used again by a later re-selection; none goes unreported.
      const std::vector<int> unused = cutter.unusedParticles();
      ASSERT_TRUE(std::includes(reported.begin(), reported.end(), unused.begin(), unused.end()))
          << "cut " << c << " sweep " << s;
    }
  }
  EXPECT_GT(isolated, 0);
  ASSERT_FALSE(reported.empty());
  // Reported particles and the lowest layer pinned: the implicit step's system is definite.
  DynamicsProblem problem;
  problem.model = &model;
  problem.external_force = model.bodyForce(Eigen::Vector3d(0.0, 0.0, -9.81));
  const double clamp_z = model.grid().particles.row(2).minCoeff() + 0.012;
  for (int p = 0; p < model.numNodes(); ++p)
    if (model.grid().particles(2, p) < clamp_z ||
        std::binary_search(reported.begin(), reported.end(), p))
      for (int k = 0; k < 3; ++k) problem.dirichlet.dofs.push_back(3 * p + k);
  problem.dirichlet.positions.resize(static_cast<Eigen::Index>(problem.dirichlet.dofs.size()));
  for (size_t k = 0; k < problem.dirichlet.dofs.size(); ++k)
    problem.dirichlet.positions(static_cast<Eigen::Index>(k)) = x(problem.dirichlet.dofs[k]);
  SimulationState state{x, Eigen::VectorXd::Zero(x.size()), 0.0};
  const auto integrator = makeIntegrator(IntegratorKind::ImplicitEulerLinearized, {},
                                         makeLinearSolver(SolverKind::Cholmod, {}));
  EXPECT_EQ(integrator->step(problem, 0.01, state).status, StepStatus::Ok);
}

TEST(EfgVolumeCutter, MidCellCutMovesTheVolumeBeyondThePlane) {
  const double z_cut = 0.0006;
  EfgModel model = cylinder();
  const Eigen::VectorXd v0 = model.grid().volumes;
  EfgVolumeCutter cutter(model);
  cutter.cut(upwardSweep(z_cut), model.restPositions(), model.restPositions());
  // Cells [0, d] in z are crossed at 0.24 d: their IPs (z > z_cut) lose the part below.
  double moved_out = 0.0, moved_in = 0.0;
  for (int e = 0; e < model.numIntegrationPoints(); ++e) {
    const double dv = model.grid().volumes(e) - v0(e);
    const double z = model.grid().integration_points(2, e);
    if (dv < 0.0) {
      EXPECT_GT(z, z_cut);
      moved_out -= dv;
    } else if (dv > 0.0) {
      EXPECT_LT(z, z_cut);
      moved_in += dv;
    }
  }
  EXPECT_GT(moved_out, 0.0);
  EXPECT_NEAR(moved_in, moved_out, 1e-15);
}

// A blade advancing through the cylinder in steps of about half a particle spacing: an IP behind
// the cut front reaches particles across the cut around the front, and later steps sever those
// paths without crossing a link of the IP's own. After every step each IP's neighbourhood is the
// one a new search selects (this fails when a severed path does not mark its searches for a
// re-search), and the mass is kept.
TEST(EfgVolumeCutter, AdvancingBladeKeepsEveryNeighbourhoodCurrent) {
  EfgModel model = cylinder();
  const double mass = totalMass(model);
  EfgVolumeCutter cutter(model);
  const double z = 0.0006 + model.grid().spacing, step = 0.6 * model.grid().spacing;  // [m]
  for (double y = -0.012; y < 0.012; y += step) {
    cutter.cut({straightBlade(y, z), straightBlade(y + step, z)}, model.restPositions(),
               model.restPositions());
    ASSERT_EQ(cutter.staleNeighbourhoods(), std::vector<int>()) << "blade at y = " << y;
  }
  EXPECT_NEAR(totalMass(model), mass, 1e-12 * mass);
}

TEST(EfgVolumeCutter, RandomSweepsKeepMassCompletenessFinitenessAndCurrentNeighbourhoods) {
  EfgModel model = cylinder();
  const EfgModel before = model;
  EfgVolumeCutter cutter(model);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-0.025, 0.025);
  const auto point = [&] { return Eigen::Vector3d(u(rng), u(rng), u(rng)); };
  std::vector<int> changed;
  for (int i = 0; i < 40; ++i) {
    BladeSweep sweep{Eigen::Matrix3Xd(3, 3), Eigen::Matrix3Xd(3, 3)};
    for (int c = 0; c < 3; ++c) {
      sweep.start.col(c) = point();
      sweep.end.col(c) = sweep.start.col(c) + 0.4 * point();
    }
    const EfgCutResult r = cutter.cut(sweep, model.restPositions(), model.restPositions());
    for (const int e : r.changed_ips)
      if (model.grid().volumes(e) > 0.0) changed.push_back(e);
    // Every IP a cut re-selected (or left, its searches untouched) matches a new search.
    ASSERT_EQ(cutter.staleNeighbourhoods(), std::vector<int>()) << "sweep " << i;
  }
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  EXPECT_GT(changed.size(), 100u);
  EXPECT_NEAR(totalMass(model), totalMass(before), 1e-12 * totalMass(before));
  expectLinearCompleteness(model, changed);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.restPositions().size());
  model.addInternalForce(model.restPositions(), f);
  EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_TRUE(model.bodyForce(Eigen::Vector3d(0, 0, -9.81)).allFinite());
}

// Pieces from scratch: the graph's components holding an IP with volume, and a particle label
// per component.
int piecesFromScratch(const EfgVolumeCutter& cutter, std::vector<int>& labels) {
  const int count = cutter.graph().components(labels);
  std::vector<char> holds(static_cast<size_t>(count), 0);
  for (int e = 0; e < cutter.model().numIntegrationPoints(); ++e)
    if (cutter.model().grid().volumes(e) > 0.0)
      holds[static_cast<size_t>(labels[static_cast<size_t>(cutter.graph().ipNode(e))])] = 1;
  labels.resize(static_cast<size_t>(cutter.graph().numParticles()));
  return static_cast<int>(std::count(holds.begin(), holds.end(), 1));
}

// Through-cuts carve the cylinder into many pieces (and isolate IPs): after every sweep the
// pieces found by searching from the severed links are the graph's components, with the same
// particle partition.
TEST(EfgVolumeCutter, PiecesFromTheSeveredLinksAreTheGraphComponents) {
  EfgModel model = cylinder();
  EfgVolumeCutter cutter(model);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int splits = 0;
  for (int i = 0; i < 30; ++i) {
    // A blade longer than the body, through a random point, swept across it.
    const Eigen::Vector3d centre = 0.015 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    const Eigen::Vector3d along = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    Eigen::Vector3d across = along.cross(Eigen::Vector3d(u(rng), u(rng), u(rng))).normalized();
    BladeSweep sweep{Eigen::Matrix3Xd(3, 2), Eigen::Matrix3Xd(3, 2)};
    sweep.start << centre - 0.1 * along - 0.1 * across, centre + 0.1 * along - 0.1 * across;
    sweep.end << centre - 0.1 * along + 0.1 * across, centre + 0.1 * along + 0.1 * across;
    const EfgCutResult r = cutter.cut(sweep, model.restPositions(), model.restPositions());
    splits += r.pieces_changed ? 1 : 0;
    std::vector<int> labels;
    ASSERT_EQ(cutter.pieces(), piecesFromScratch(cutter, labels)) << "sweep " << i;
    EXPECT_EQ(r.pieces, cutter.pieces());
    // Same partition: label pairs map one to one.
    const std::vector<int> mine = cutter.particlePieces();
    std::map<int, int> forward, backward;
    for (size_t p = 0; p < labels.size(); ++p) {
      ASSERT_EQ(forward.emplace(mine[p], labels[p]).first->second, labels[p]) << "sweep " << i;
      ASSERT_EQ(backward.emplace(labels[p], mine[p]).first->second, mine[p]) << "sweep " << i;
    }
  }
  EXPECT_GE(splits, 5);
  EXPECT_GE(cutter.pieces(), 6);
}

TEST(EfgVolumeCutter, BladeThatMissesChangesNoBit) {
  EfgModel model = cylinder();
  const EfgModel before = model;
  EfgVolumeCutter cutter(model);
  // Beside the outermost particles, inside the broad phase's margin.
  const double x_side = model.grid().particles.row(0).maxCoeff() + 0.001;
  Eigen::Matrix3Xd b(3, 2);
  b << x_side, x_side, -0.02, -0.02, -0.03, 0.03;
  Eigen::Matrix3Xd e = b;
  e.row(1).setConstant(0.02);
  const EfgCutResult r = cutter.cut({b, e}, model.restPositions(), model.restPositions());
  EXPECT_TRUE(r.severed_links.empty());
  EXPECT_TRUE(r.changed_ips.empty());
  EXPECT_FALSE(r.pieces_changed);
  EXPECT_EQ(r.pieces, 1);
  EXPECT_EQ(cutter.graph().numSevered(), 0);
  const auto bits = [](const Eigen::VectorXd& v) {
    return std::vector<double>(v.data(), v.data() + v.size());
  };
  EXPECT_EQ(bits(model.lumpedMass()), bits(before.lumpedMass()));
  EXPECT_EQ(bits(model.bodyForce(Eigen::Vector3d(0, 0, -9.81))),
            bits(before.bodyForce(Eigen::Vector3d(0, 0, -9.81))));
  EXPECT_EQ(bits(model.grid().volumes), bits(before.grid().volumes));
  Eigen::VectorXd x = model.restPositions();
  x(7) += 1e-4;
  Eigen::VectorXd fa = Eigen::VectorXd::Zero(x.size()), fb = fa;
  model.addInternalForce(x, fa);
  before.addInternalForce(x, fb);
  EXPECT_EQ(bits(fa), bits(fb));
  EXPECT_EQ(model.stiffnessPattern().nonZeros(), before.stiffnessPattern().nonZeros());
  for (int ip = 0; ip < model.numIntegrationPoints(); ++ip) {
    EXPECT_EQ(model.ipParticles(ip), before.ipParticles(ip));
    EXPECT_EQ(bits(model.shapeValues(ip)), bits(before.shapeValues(ip)));
  }
}

TEST(EfgVolumeCutter, BadInputIsNamed) {
  EfgModel model = cylinder();
  EfgVolumeCutter cutter(model);
  const Eigen::VectorXd x = model.restPositions();
  const auto message = [&](const BladeSweep& s, const Eigen::VectorXd& a,
                           const Eigen::VectorXd& b) {
    try {
      cutter.cut(s, a, b);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  BladeSweep nan_blade = upwardSweep(0.0);
  nan_blade.end(1, 0) = NAN;
  EXPECT_NE(message(nan_blade, x, x).find("blade_sweep.end"), std::string::npos);
  EXPECT_NE(message(upwardSweep(0.0), x.head(6), x).find("x_start has size 6"), std::string::npos);
  Eigen::VectorXd bad = x;
  bad(3) = INFINITY;
  EXPECT_NE(message(upwardSweep(0.0), x, bad).find("x_end is not finite"), std::string::npos);
  EXPECT_EQ(cutter.graph().numSevered(), 0);
}

}  // namespace
}  // namespace surgical_sim::core
