// SurfaceMapping: the selection of a tet model's surface nodes (bit for bit), the MLS rows of an
// EFG model (partition of unity, linear fields reproduced), virtual work, bad input.
#include "surgical_sim/core/tissue/surface_mapping.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/tissue/efg_model.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::core {
namespace {

const Material kMaterial = Material::create(5e3, 0.45, 1000.0);

Eigen::VectorXd randomVector(Eigen::Index size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd v(size);
  for (Eigen::Index i = 0; i < size; ++i) v[i] = u(rng);
  return v;
}

// The organ blob (a curved surface, tet cells cut by it) and its surface.
struct Body {
  TetMesh mesh = makeOrganBlob(Eigen::Vector3d(0.04, 0.03, 0.02), 6, ElementType::Tet4);
  SurfaceMesh surface = extractSurface(mesh);
};

EfgModel efgModel(const TetMesh& mesh) {
  EfgOptions options;
  options.spacing = 0.006;
  return EfgModel(mesh, kMaterial, options);
}

TEST(SurfaceMapping, OfATetModelIsTheSelectionOfItsSurfaceNodesBitForBit) {
  const Body body;
  const auto model = makeTissueModel(ModelKind::Corotational, body.mesh, kMaterial);
  const SurfaceMapping mapping = makeSurfaceMapping(*model, body.mesh, body.surface);
  ASSERT_EQ(mapping.numSlots(), body.mesh.numNodes());
  ASSERT_EQ(mapping.numNodes(), body.mesh.numNodes());
  EXPECT_EQ(mapping.vertices(), body.surface.nodes);
  std::vector<bool> on_surface(static_cast<size_t>(body.mesh.numNodes()), false);
  for (const int v : body.surface.nodes) on_surface[static_cast<size_t>(v)] = true;

  const Eigen::VectorXd x = randomVector(3 * body.mesh.numNodes(), 1);
  Eigen::VectorXd x_s;
  mapping.apply(x, x_s);
  const Eigen::VectorXd f_s = randomVector(3 * body.mesh.numNodes(), 2);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  mapping.addTransposed(f_s, f);
  for (int n = 0; n < body.mesh.numNodes(); ++n) {
    const SurfaceMapping::Row row = mapping.row(n);
    if (on_surface[static_cast<size_t>(n)]) {
      ASSERT_EQ(row.size, 1);
      EXPECT_EQ(row.nodes[0], n);
      EXPECT_EQ(row.weights[0], 1.0);
      // Exactly equal, not to round-off: tet scenes keep their numbers.
      EXPECT_EQ(Eigen::Vector3d(x_s.segment<3>(3 * n)), Eigen::Vector3d(x.segment<3>(3 * n)));
      EXPECT_EQ(Eigen::Vector3d(f.segment<3>(3 * n)), Eigen::Vector3d(f_s.segment<3>(3 * n)));
    } else {
      EXPECT_EQ(row.size, 0);
      EXPECT_TRUE(x_s.segment<3>(3 * n).isZero(0.0));
      EXPECT_TRUE(f.segment<3>(3 * n).isZero(0.0));
    }
  }
}

TEST(SurfaceMapping, OfAnEfgModelHasRowsSummingToOneAndReproducesLinearFields) {
  const Body body;
  const EfgModel model = efgModel(body.mesh);
  const SurfaceMapping mapping = makeSurfaceMapping(model, body.mesh, body.surface);
  ASSERT_EQ(mapping.numNodes(), model.numNodes());
  ASSERT_EQ(mapping.numSlots(), body.mesh.numNodes());
  // Particles every 12 mm: the surface is finer than the DOF grid.
  EXPECT_GT(static_cast<int>(body.surface.nodes.size()), model.numNodes() / 2);
  const Eigen::SparseMatrix<double> W = mapping.matrix();
  for (const int v : body.surface.nodes) {
    EXPECT_EQ(mapping.row(v).size, model.options().neighbours) << v;
    EXPECT_NEAR(W.row(v).sum(), 1.0, 1e-12) << v;
  }
  // x = A X + b on the particles moves every vertex to A X_v + b.
  Eigen::Matrix3d A;
  A << 1.2, 0.3, -0.1, 0.05, 0.9, 0.2, -0.3, 0.1, 1.1;
  const Eigen::Vector3d b(0.01, -0.02, 0.03);
  Eigen::VectorXd x = model.restPositions();
  for (int a = 0; a < model.numNodes(); ++a) x.segment<3>(3 * a) = A * x.segment<3>(3 * a) + b;
  Eigen::VectorXd x_s;
  mapping.apply(x, x_s);
  for (const int v : body.surface.nodes) {
    const Eigen::Vector3d expected = A * body.mesh.nodes.col(v) + b;
    EXPECT_LT((x_s.segment<3>(3 * v) - expected).norm(), 1e-12) << v;
  }
}

TEST(SurfaceMapping, TransposeKeepsTheVirtualWork) {
  const Body body;
  const EfgModel model = efgModel(body.mesh);
  const SurfaceMapping mapping = makeSurfaceMapping(model, body.mesh, body.surface);
  const Eigen::VectorXd dx = randomVector(3 * model.numNodes(), 3);
  Eigen::VectorXd f_s = randomVector(3 * mapping.numSlots(), 4);
  Eigen::VectorXd dx_s;
  mapping.apply(dx, dx_s);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(dx.size());
  mapping.addTransposed(f_s, f);
  // Only the vertices carry force: f_s on other slots does no work and maps to nothing.
  std::vector<bool> on_surface(static_cast<size_t>(mapping.numSlots()), false);
  for (const int v : mapping.vertices()) on_surface[static_cast<size_t>(v)] = true;
  for (int s = 0; s < mapping.numSlots(); ++s)
    if (!on_surface[static_cast<size_t>(s)]) f_s.segment<3>(3 * s).setZero();
  const double work_s = f_s.dot(dx_s);
  EXPECT_NEAR(work_s, f.dot(dx), 1e-12 * f_s.norm() * dx_s.norm());
  // One vertex force alone: the same as the transposed map of a force on that vertex only.
  const int v = mapping.vertices()[mapping.vertices().size() / 2];
  Eigen::VectorXd f_v = Eigen::VectorXd::Zero(dx.size());
  mapping.addVertexForce(v, Eigen::Vector3d(0.0, 0.0, -2.0), f_v);
  EXPECT_NEAR(f_v.dot(dx), -2.0 * mapping.vertexValue(v, dx).z(), 1e-14);
  // The total force is kept (rows sum to 1).
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int a = 0; a < model.numNodes(); ++a) total += f_v.segment<3>(3 * a);
  EXPECT_LT((total - Eigen::Vector3d(0.0, 0.0, -2.0)).norm(), 1e-12);
}

TEST(SurfaceMapping, RowTablesGiveTheSameMappingAsTheMatrix) {
  // Slots 0 and 3 have rows, 1 and 2 none; a 4 x 3 matrix's rows, in its order 3, 0.
  Eigen::SparseMatrix<double, Eigen::RowMajor> W(2, 3);
  W.insert(0, 1) = 0.25;
  W.insert(0, 2) = 0.75;
  W.insert(1, 0) = 1.0;
  const SurfaceMapping from_matrix(4, {3, 0}, W);
  const SurfaceMapping from_rows =
      SurfaceMapping::fromRows(3, {0, 3}, {0, 1, 1, 1, 3}, {0, 1, 2}, {1.0, 0.25, 0.75});
  EXPECT_EQ(from_rows.numSlots(), 4);
  EXPECT_EQ(from_rows.numNodes(), 3);
  EXPECT_EQ(from_rows.vertices(), (std::vector<int>{0, 3}));
  EXPECT_EQ(Eigen::MatrixXd(from_rows.matrix()), Eigen::MatrixXd(from_matrix.matrix()));
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(9, 1.0, 9.0);
  EXPECT_EQ(from_rows.vertexValue(3, x),
            Eigen::Vector3d(0.25 * 4 + 0.75 * 7, 0.25 * 5 + 0.75 * 8, 0.25 * 6 + 0.75 * 9));
  EXPECT_EQ(from_rows.row(1).size, 0);
}

TEST(SurfaceMapping, RejectsBadInputNamingIt) {
  Eigen::SparseMatrix<double, Eigen::RowMajor> one(1, 2);
  one.insert(0, 1) = 1.0;
  const auto rejects = [](const auto& make, const std::string& part) {
    try {
      make();
      ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  rejects([&] { SurfaceMapping(3, {3}, one); }, "vertex 3");
  rejects([&] { SurfaceMapping(3, {0, 1}, one); }, "1 weight rows for 2 vertices");
  rejects([&] { SurfaceMapping::selection(4, {0, 0}); }, "repeated");
  rejects([&] { SurfaceMapping::selection(4, {5}); }, "vertex 5");
  Eigen::SparseMatrix<double, Eigen::RowMajor> nan(1, 2);
  nan.insert(0, 0) = std::nan("");
  rejects([&] { SurfaceMapping(3, {0}, nan); }, "not finite");
  // Row tables: ranges that skip, overlap or overrun the entries, an unlisted slot with a row,
  // a node outside the model.
  rejects([&] { SurfaceMapping::fromRows(2, {0}, {0, 1, 2}, {1}, {1.0}); }, "row ranges");
  rejects([&] { SurfaceMapping::fromRows(2, {0}, {0, 2, 1}, {1, 0}, {1.0, 0.0}); }, "row ranges");
  rejects([&] { SurfaceMapping::fromRows(2, {0}, {0, 1}, {1}, {}); }, "row ranges");
  rejects(
      [&] {
        SurfaceMapping::fromRows(2, {0}, {0, 1, 2}, {1, 0}, {1.0, 1.0});
      },
      "slot 1 has a row");
  rejects([&] { SurfaceMapping::fromRows(2, {0, 0}, {0, 1}, {1}, {1.0}); }, "repeated");
  rejects([&] { SurfaceMapping::fromRows(2, {0}, {0, 1}, {2}, {1.0}); }, "maps to node 2");
  rejects([&] { SurfaceMapping::fromRows(2, {0}, {0, 1}, {1}, {std::nan("")}); }, "not finite");
  const Body body;
  const TetMesh other = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(),
                                Eigen::Vector3i::Ones(), ElementType::Tet4);
  const auto model = makeTissueModel(ModelKind::Corotational, other, kMaterial);
  rejects([&] { makeSurfaceMapping(*model, body.mesh, body.surface); }, "nodes");
}

}  // namespace
}  // namespace surgical_sim::core
