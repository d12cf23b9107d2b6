#include "surgical_sim/core/tissue/efg_grid.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/mesh/generators.h"

namespace surgical_sim::core {
namespace {

// Tet mesh of the ball of radius r [m]: makeOrganBlob with its lobe shaping undone, so the
// boundary nodes lie on the sphere.
TetMesh ballMesh(double r, int cells) {
  TetMesh mesh = makeOrganBlob(Eigen::Vector3d::Ones(), cells, ElementType::Tet4);
  for (int i = 0; i < mesh.numNodes(); ++i) {
    const Eigen::Vector3d v = mesh.nodes.col(i);
    mesh.nodes.col(i) = r * Eigen::Vector3d(v.x(), v.y(), v.z() / (1.0 - 0.25 * v.x() * v.x()));
  }
  return mesh;
}

double tetMeshVolume(const TetMesh& mesh) {
  double volume = 0.0;
  for (int e = 0; e < mesh.numElements(); ++e) {
    Eigen::Matrix3d T;
    for (int a = 0; a < 3; ++a)
      T.col(a) = mesh.nodes.col(mesh.elements(a + 1, e)) - mesh.nodes.col(mesh.elements(0, e));
    volume += T.determinant() / 6.0;
  }
  return volume;
}

EfgOptions options(double spacing, int neighbours = 8, int samples = 4) {
  EfgOptions o;
  o.spacing = spacing;
  o.neighbours = neighbours;
  o.volume_samples = samples;
  return o;
}

TEST(EfgGrid, AlignedBoxHasFullCellsOnCornerParticles) {
  const TetMesh box = makeBox(Eigen::Vector3d(-0.5, 0.0, 1.0), Eigen::Vector3d::Ones(),
                              Eigen::Vector3i(3, 3, 3), ElementType::Tet4);
  const EfgGrid grid = buildEfgGrid(box, options(0.25));
  ASSERT_EQ(grid.integration_points.cols(), 64);
  EXPECT_EQ(grid.particles.cols(), 27);
  EXPECT_LT((grid.volumes.array() - std::pow(0.25, 3)).abs().maxCoeff(), 1e-15);
  for (int e = 0; e < 64; ++e) {
    const Eigen::Vector3d x = grid.integration_points.col(e);
    for (int a = 0; a < 8; ++a) {
      // The 8 neighbours are the corners of the enclosing DOF cell of side 0.5: each coordinate
      // 0.125 (near side) or 0.375 (far side) from the IP.
      const Eigen::Vector3d offset = grid.particles.col(grid.neighbours(a, e)) - x;
      EXPECT_LT(((offset.cwiseAbs().array() - 0.25).abs() - 0.125).abs().maxCoeff(), 1e-12);
    }
    EXPECT_EQ(
        std::set<int>(grid.neighbours.col(e).data(), grid.neighbours.col(e).data() + 8).size(), 8u);
  }
}

TEST(EfgGrid, IntegrationPointIsTheCentroidOfTheInsidePart) {
  // Cells of d = 1/3.5 m over the unit cube: the last layer per axis, [3d, 4d], is cut at 1 m
  // through its middle, between volume samples (4 per axis), so volumes are exact.
  const TetMesh box = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(),
                              Eigen::Vector3i(2, 2, 2), ElementType::Tet4);
  const double d = 1.0 / 3.5;
  EfgOptions o = options(d);
  const EfgGrid centroid = buildEfgGrid(box, o);
  o.ip_at_centroid = false;
  const EfgGrid centre = buildEfgGrid(box, o);
  ASSERT_EQ(centroid.integration_points.cols(), 64);
  EXPECT_NEAR(centroid.volumes.sum(), 1.0, 1e-12);
  for (int e = 0; e < 64; ++e) {
    const Eigen::Vector3d c = centre.integration_points.col(e);
    const Eigen::Vector3d p = centroid.integration_points.col(e);
    // A cut cell's inside half [3d, 1] has its centroid d/4 below the cell centre 1.
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(p(a), c(a) > 0.99 ? c(a) - d / 4 : c(a), 1e-12);
  }
  // First moment exact: sum V_e x_e = V x_centroid of the body.
  EXPECT_LT(
      (centroid.integration_points * centroid.volumes - Eigen::Vector3d::Constant(0.5)).norm(),
      1e-12);
  EXPECT_GT((centre.integration_points * centre.volumes - Eigen::Vector3d::Constant(0.5)).norm(),
            1e-2);
}

TEST(EfgGrid, ExtraNeighboursAreTheNearestOtherParticles) {
  const TetMesh box = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(),
                              Eigen::Vector3i(2, 2, 2), ElementType::Tet4);
  for (int k : {9, 12, 16}) {
    const EfgGrid grid = buildEfgGrid(box, options(0.125, k));
    ASSERT_EQ(grid.neighbours.rows(), k);
    for (int e = 0; e < grid.neighbours.cols(); ++e) {
      const Eigen::Vector3d x = grid.integration_points.col(e);
      std::set<int> distinct;
      double previous = 0.0;
      for (int a = 0; a < k; ++a) {
        distinct.insert(grid.neighbours(a, e));
        const double r = (grid.particles.col(grid.neighbours(a, e)) - x).norm() / 0.125;
        if (a >= 8) {
          // Beyond the corners (farthest at sqrt(6.75) d): non-decreasing distances.
          EXPECT_GE(r, std::max(previous, std::sqrt(6.75)) - 1e-12);
          previous = r;
        }
      }
      EXPECT_EQ(distinct.size(), static_cast<size_t>(k));
    }
  }
}

TEST(EfgGrid, SphereVolumeConvergesToAnalytic) {
  const double r = 0.05;
  const TetMesh ball = ballMesh(r, 24);
  const double exact = 4.0 / 3.0 * M_PI * r * r * r;
  const double tet_volume = tetMeshVolume(ball);
  ASSERT_NEAR(tet_volume, exact, 0.01 * exact);
  double previous = INFINITY;
  for (int cells : {4, 8, 16}) {
    const EfgGrid grid = buildEfgGrid(ball, options(r / cells));
    const double error = std::abs(grid.volumes.sum() - tet_volume) / tet_volume;
    EXPECT_LT(error, previous) << cells;
    previous = error;
    EXPECT_GT(grid.volumes.minCoeff(), 0.0);
    EXPECT_LE(grid.volumes.maxCoeff(), std::pow(r / cells, 3) * (1.0 + 1e-12));
  }
  EXPECT_LT(previous, 2e-3);
  // Denser sampling on the finest grid: converges to the analytic sphere up to the tet mesh's
  // own polyhedral error.
  const EfgGrid fine = buildEfgGrid(ball, options(r / 16, 8, 8));
  EXPECT_LT(std::abs(fine.volumes.sum() - exact) / exact, 0.01);
  EXPECT_LT(std::abs(fine.volumes.sum() - tet_volume) / tet_volume, 1e-3);
}

TEST(EfgGrid, VolumeScalesWithLengthUnit) {
  const TetMesh ball_m = ballMesh(0.05, 8);
  TetMesh ball_mm = ball_m;
  ball_mm.nodes *= 1e-3;
  const EfgGrid m = buildEfgGrid(ball_m, options(0.01));
  const EfgGrid mm = buildEfgGrid(ball_mm, options(1e-5));
  ASSERT_EQ(m.integration_points.cols(), mm.integration_points.cols());
  EXPECT_NEAR(mm.volumes.sum(), 1e-9 * m.volumes.sum(), 1e-12 * 1e-9 * m.volumes.sum());
  EXPECT_LT((1e-3 * m.particles - mm.particles).norm(), 1e-12 * mm.particles.norm());
}

TEST(EfgGrid, RejectsBadOptionsAndMeshesNamingTheKey) {
  const TetMesh box = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(),
                              Eigen::Vector3i(1, 1, 1), ElementType::Tet4);
  const auto message = [&](const EfgOptions& o, const TetMesh& mesh) -> std::string {
    try {
      buildEfgGrid(mesh, o);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no exception";
  };
  EXPECT_NE(message(options(-0.1), box).find("efg.spacing"), std::string::npos);
  EXPECT_NE(message(options(NAN), box).find("efg.spacing"), std::string::npos);
  EXPECT_NE(message(options(1e-4), box).find("efg.spacing"), std::string::npos);  // too many cells
  EXPECT_NE(message(options(0.1, 7), box).find("efg.neighbours"), std::string::npos);
  EXPECT_NE(message(options(0.1, 17), box).find("efg.neighbours"), std::string::npos);
  EXPECT_NE(message(options(0.1, 8, 0), box).find("efg.volume_samples"), std::string::npos);
  EXPECT_NE(message(options(0.1, 8, 9), box).find("efg.volume_samples"), std::string::npos);
  EfgOptions support = options(0.1);
  support.kernel_support = 1.0;
  EXPECT_NE(message(support, box).find("efg.kernel_support"), std::string::npos);
  // One DOF cell has only its 8 corner particles.
  EXPECT_NE(message(options(0.5, 9), box).find("efg.neighbours"), std::string::npos);
  TetMesh broken = box;
  broken.elements(2, 0) = 99;
  EXPECT_NE(message(options(0.1), broken).find("mesh.elements"), std::string::npos);
  EXPECT_NE(message(options(0.1), TetMesh{}).find("no nodes"), std::string::npos);
}

}  // namespace
}  // namespace surgical_sim::core
