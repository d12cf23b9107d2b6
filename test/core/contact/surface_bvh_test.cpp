#include "surgical_sim/core/contact/surface_bvh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>

#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/surface.h"

namespace surgical_sim::core {
namespace {

Eigen::VectorXd flatten(const Eigen::Matrix3Xd& nodes) {
  return Eigen::Map<const Eigen::VectorXd>(nodes.data(), nodes.size());
}

std::vector<int> bruteForce(const SurfaceMesh& surface, const Eigen::VectorXd& x,
                            const Eigen::AlignedBox3d& box) {
  std::vector<int> out;
  for (int t = 0; t < surface.triangles.cols(); ++t) {
    Eigen::AlignedBox3d tri;
    for (int k = 0; k < 3; ++k) tri.extend(x.segment<3>(3 * surface.triangles(k, t)));
    if (tri.intersects(box)) out.push_back(t);
  }
  return out;
}

TEST(SurfaceBvh, SameCandidatesAsBruteForceAfterLargeDeformation) {
  const TetMesh mesh = makeBox({0, 0, 0}, {0.1, 0.08, 0.05}, {6, 5, 3}, ElementType::Tet4);
  const SurfaceMesh surface = extractSurface(mesh);
  Eigen::VectorXd x = flatten(mesh.nodes);
  SurfaceBvh bvh(surface.triangles, x, 0.002);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<int> candidates;
  for (int round = 0; round < 5; ++round) {
    // Large deformation: bend + twist + random noise of the order of the element size.
    for (int a = 0; a < mesh.numNodes(); ++a) {
      const Eigen::Vector3d p = mesh.nodes.col(a);
      const double angle = 3.0 * round * p.x();
      x.segment<3>(3 * a) =
          Eigen::Vector3d(
              p.x(), std::cos(angle) * p.y() - std::sin(angle) * p.z(),
              std::sin(angle) * p.y() + std::cos(angle) * p.z() + 0.5 * round * p.x() * p.x()) +
          0.01 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    }
    bvh.refit(x);
    for (int q = 0; q < 20; ++q) {
      const Eigen::Vector3d centre =
          0.06 * Eigen::Vector3d(u(rng), u(rng), u(rng)) + Eigen::Vector3d(0.05, 0.0, 0.0);
      const Eigen::AlignedBox3d box(centre - Eigen::Vector3d::Constant(0.01),
                                    centre + Eigen::Vector3d::Constant(0.02));
      bvh.query(box, candidates);
      std::sort(candidates.begin(), candidates.end());
      EXPECT_EQ(candidates, bruteForce(surface, x, box));
    }
  }
}

TEST(SurfaceBvh, NewTrianglesKeepTheUnchangedLeavesAndQueryAsABruteForceScan) {
  // Rounds of "cuts": a random third of the triangles replaced by triangles on other vertices
  // (some repeated, some reversed), the rest shuffled, the positions deformed. After each
  // setTriangles the queries equal a brute-force scan, and a bad index changes nothing.
  const TetMesh mesh = makeBox({0, 0, 0}, {0.1, 0.08, 0.05}, {6, 5, 3}, ElementType::Tet4);
  SurfaceMesh surface = extractSurface(mesh);
  Eigen::VectorXd x = flatten(mesh.nodes);
  SurfaceBvh bvh(surface.triangles, x, 0.002);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int nodes = mesh.numNodes();
  std::vector<int> candidates;
  for (int round = 0; round < 6; ++round) {
    Eigen::Matrix3Xi next = surface.triangles;
    for (Eigen::Index t = 0; t < next.cols(); ++t) {
      if (rng() % 3 == 0) next.col(t) = next.col(t).reverse().eval();
      if (rng() % 3 == 0) next(0, t) = static_cast<int>(rng() % nodes);
    }
    std::vector<Eigen::Index> order(static_cast<size_t>(next.cols()));
    for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<Eigen::Index>(k);
    std::shuffle(order.begin(), order.end(), rng);
    const Eigen::Index kept = next.cols() - static_cast<Eigen::Index>(rng() % 40);
    surface.triangles.resize(3, kept + 1);
    for (Eigen::Index k = 0; k < kept; ++k) surface.triangles.col(k) = next.col(order[k]);
    surface.triangles.col(kept) = surface.triangles.col(0);  // a repeated triangle
    for (int a = 0; a < nodes; ++a)
      x.segment<3>(3 * a) += 0.004 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    bvh.setTriangles(surface.triangles, x);
    ASSERT_EQ(bvh.numTriangles(), surface.triangles.cols());
    Eigen::Matrix3Xi bad = surface.triangles;
    bad(1, 2) = nodes;
    EXPECT_THROW(bvh.setTriangles(bad, x), std::invalid_argument);
    for (int q = 0; q < 30; ++q) {
      const Eigen::Vector3d centre =
          0.06 * Eigen::Vector3d(u(rng), u(rng), u(rng)) + Eigen::Vector3d(0.05, 0.04, 0.02);
      const Eigen::AlignedBox3d box(centre - Eigen::Vector3d::Constant(0.01),
                                    centre + Eigen::Vector3d::Constant(0.015));
      bvh.query(box, candidates);
      std::sort(candidates.begin(), candidates.end());
      EXPECT_EQ(candidates, bruteForce(surface, x, box)) << "round " << round;
    }
  }
}

TEST(SurfaceBvh, RejectsBadMarginAndIndices) {
  const TetMesh mesh = makeBox({0, 0, 0}, {1, 1, 1}, {1, 1, 1}, ElementType::Tet4);
  const SurfaceMesh surface = extractSurface(mesh);
  const Eigen::VectorXd x = flatten(mesh.nodes);
  EXPECT_THROW(SurfaceBvh(surface.triangles, x, -1.0), std::invalid_argument);
  Eigen::Matrix3Xi bad = surface.triangles;
  bad(0, 0) = 99;
  EXPECT_THROW(SurfaceBvh(bad, x, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
