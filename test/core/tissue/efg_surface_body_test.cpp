// The efg model of a body given by its closed triangle surface instead of a tet mesh.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/surface.h"
#include "surgical_sim/core/mesh/surface_generators.h"
#include "surgical_sim/core/mesh/surface_inside.h"
#include "surgical_sim/core/tissue/efg_grid.h"
#include "surgical_sim/core/tissue/efg_model.h"

namespace surgical_sim::core {
namespace {

EfgOptions spacing(double d) {
  EfgOptions o;
  o.spacing = d;
  return o;
}

/// The boundary of a tet mesh as a closed triangle surface on the mesh's nodes.
TriMesh boundaryOf(const TetMesh& mesh) { return {mesh.nodes, extractSurface(mesh).triangles}; }

void expectSameGrid(const EfgGrid& a, const EfgGrid& b, double volume_tolerance) {
  ASSERT_EQ(a.integration_points.cols(), b.integration_points.cols());
  ASSERT_EQ(a.particles.cols(), b.particles.cols());
  EXPECT_EQ(a.particles, b.particles);
  EXPECT_EQ(a.neighbours, b.neighbours);
  EXPECT_LE((a.volumes - b.volumes).cwiseAbs().maxCoeff(), volume_tolerance);
  EXPECT_LE((a.integration_points - b.integration_points).cwiseAbs().maxCoeff(),
            volume_tolerance > 0.0 ? a.spacing : 0.0);
}

TEST(EfgSurfaceBody, SurfaceOfATetMeshGivesTheTetMeshGrid) {
  // A box whose faces fall between the volume samples: the same samples are inside, bit for bit.
  const TetMesh box = makeBox(Eigen::Vector3d(-0.5, 0.0, 1.0), Eigen::Vector3d(1.0, 0.75, 0.5),
                              Eigen::Vector3i(4, 3, 2), ElementType::Tet4);
  expectSameGrid(buildEfgGrid(boundaryOf(box), spacing(0.125)), buildEfgGrid(box, spacing(0.125)),
                 0.0);
  // A curved organ: samples exactly on the boundary are decided differently at most.
  const TetMesh blob = makeOrganBlob(Eigen::Vector3d(0.075, 0.05, 0.024), 10, ElementType::Tet4);
  const double d = 0.005;
  const double sample_volume = std::pow(d / 4, 3);
  expectSameGrid(buildEfgGrid(boundaryOf(blob), spacing(d)), buildEfgGrid(blob, spacing(d)),
                 2.0 * sample_volume);
}

TEST(EfgSurfaceBody, InsideVolumeOfASphereSurfaceConverges) {
  TriMesh ball = makeIcosphere(6);
  ball.vertices *= 0.05;  // radius 5 cm
  const double volume = enclosedVolume(ball);
  double previous = INFINITY;
  for (const double d : {0.01, 0.005, 0.0025}) {
    const EfgModel model(ball, Material{5e3, 0.45, 1000.0}, spacing(d));
    const double error = std::abs(model.grid().volumes.sum() - volume) / volume;
    EXPECT_LT(error, previous) << d;
    previous = error;
    // Rows of the mapping of the surface vertices sum to 1 and reproduce them at rest.
    const Eigen::SparseMatrix<double> W = model.interpolation(ball.vertices);
    const Eigen::Map<const Eigen::Matrix3Xd> particles(model.restPositions().data(), 3,
                                                       model.numNodes());
    EXPECT_LT((particles * W.transpose() - ball.vertices).cwiseAbs().maxCoeff(), 1e-12);
  }
  EXPECT_LT(previous, 0.002);
}

TEST(EfgSurfaceBody, OpenOrEmptySurfaceIsRejected) {
  TriMesh open = makeIcosphere(2);
  open.triangles.conservativeResize(3, open.triangles.cols() - 1);
  try {
    buildEfgGrid(open, spacing(0.1));
    FAIL() << "accepted an open surface";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
  }
  EXPECT_THROW(buildEfgGrid(TriMesh{}, spacing(0.1)), std::invalid_argument);
  TriMesh far = makeIcosphere(2);
  far.vertices(0, 5) = NAN;
  EXPECT_THROW(buildEfgGrid(far, spacing(0.1)), std::invalid_argument);
}

}  // namespace
}  // namespace surgical_sim::core
