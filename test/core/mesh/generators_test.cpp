#include "surgical_sim/core/mesh/generators.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <Eigen/SparseCholesky>

#include "surgical_sim/core/mesh/mesh_check.h"
#include "surgical_sim/core/mesh/tet_faces.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::core {
namespace {

double minElementVolume(const TetMesh& mesh) {
  double smallest = INFINITY;
  for (int e = 0; e < mesh.numElements(); ++e) smallest = std::min(smallest, signedVolume(mesh, e));
  return smallest;
}

void expectInvalidArgument(const std::function<void()>& make, const std::string& message) {
  try {
    make();
    FAIL() << "expected std::invalid_argument: " << message;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

constexpr CellSplit kSplits[] = {CellSplit::Symmetric, CellSplit::Diagonal};

/// Grid index (i, j, k) of every corner node of a makeBox() mesh, from its documented numbering.
std::array<int, 3> gridPoint(int node, const Eigen::Vector3i& cells) {
  const int nx = cells.x() + 1;
  const int ny = cells.y() + 1;
  return {node % nx, (node / nx) % ny, node / (nx * ny)};
}

/// The elements of a Tet4 mesh as sorted corner sets.
std::set<std::array<int, 4>> cornerSets(const TetMesh& mesh) {
  std::set<std::array<int, 4>> sets;
  for (int e = 0; e < mesh.numElements(); ++e) {
    std::array<int, 4> tet{};
    for (int k = 0; k < 4; ++k) tet[k] = mesh.elements(k, e);
    std::sort(tet.begin(), tet.end());
    sets.insert(tet);
  }
  return sets;
}

/// True if the box mesh maps onto itself (nodes and elements) under the mirror of grid axis
/// `axis` about the box's mid-plane.
bool mirrorInvariant(const TetMesh& mesh, const Eigen::Vector3i& cells, int axis) {
  const int nx = cells.x() + 1;
  const int ny = cells.y() + 1;
  const Eigen::Vector3d lo = mesh.nodes.rowwise().minCoeff();
  const Eigen::Vector3d hi = mesh.nodes.rowwise().maxCoeff();
  std::vector<int> image(static_cast<std::size_t>(mesh.numNodes()));
  for (int n = 0; n < mesh.numNodes(); ++n) {
    std::array<int, 3> g = gridPoint(n, cells);
    g[axis] = cells[axis] - g[axis];
    image[n] = g[0] + nx * (g[1] + ny * g[2]);
    Eigen::Vector3d mirrored = mesh.nodes.col(n);
    mirrored[axis] = lo[axis] + hi[axis] - mirrored[axis];
    EXPECT_LT((mesh.nodes.col(image[n]) - mirrored).norm(), 1e-12 * (hi - lo).norm());
  }
  TetMesh mirrored = mesh;
  for (int e = 0; e < mesh.numElements(); ++e) {
    for (int k = 0; k < 4; ++k) mirrored.elements(k, e) = image[mesh.elements(k, e)];
  }
  return cornerSets(mirrored) == cornerSets(mesh);
}

TEST(MakeBox, VolumeCountsAndOrientation) {
  const Eigen::Vector3d min_corner(-1.0, 2.0, 0.5);
  const Eigen::Vector3d size(0.3, 0.2, 0.1);
  const double cell_volume = 0.006 / 60.0;
  for (const CellSplit split : kSplits) {
    const TetMesh mesh =
        makeBox(min_corner, size, Eigen::Vector3i(3, 4, 5), ElementType::Tet4, split);
    const int per_cell = split == CellSplit::Symmetric ? 5 : 6;
    EXPECT_EQ(mesh.numNodes(), 4 * 5 * 6);
    EXPECT_EQ(mesh.numElements(), per_cell * 3 * 4 * 5);
    EXPECT_NEAR(meshVolume(mesh), 0.3 * 0.2 * 0.1, 1e-12 * 0.006);
    // Both splits: the smallest tets (every Kuhn tet, the symmetric corner tets) have 1/6 of the
    // cell volume.
    EXPECT_NEAR(minElementVolume(mesh), cell_volume / 6.0, 1e-15);
    EXPECT_TRUE(mesh.nodes.rowwise().minCoeff().isApprox(min_corner));
    EXPECT_TRUE(mesh.nodes.rowwise().maxCoeff().isApprox(min_corner + size));
    EXPECT_NO_THROW(requireValidMesh(mesh));
  }
}

TEST(MakeBox, ConformingWithEveryUnsharedFaceOnTheBoundary) {
  // Odd and even counts: the split of a cell face must agree between its two cells.
  const Eigen::Vector3d min_corner(0.1, -0.2, 0.3);
  const Eigen::Vector3d size(0.4, 0.3, 0.2);
  for (const CellSplit split : kSplits) {
    for (const Eigen::Vector3i& cells :
         {Eigen::Vector3i(1, 1, 1), Eigen::Vector3i(2, 3, 1), Eigen::Vector3i(3, 4, 5)}) {
      const TetMesh mesh = makeBox(min_corner, size, cells, ElementType::Tet4, split);
      const TetFaceGroups groups = groupTetFaces(mesh);
      int boundary_faces = 0;
      for (int g = 0; g < groups.numGroups(); ++g) {
        const int shared_by = groups.group_offsets[g + 1] - groups.group_offsets[g];
        ASSERT_LE(shared_by, 2) << "face shared by " << shared_by << " elements";
        if (shared_by == 2) continue;
        ++boundary_faces;
        // A face seen by one element only must lie in one of the box's six side planes.
        const std::array<int, 3> face = groups.faces[groups.group_offsets[g]].nodes;
        bool on_side = false;
        for (int a = 0; a < 3; ++a) {
          for (const int side : {0, cells[a]}) {
            bool all = true;
            for (const int n : face) all = all && gridPoint(n, cells)[a] == side;
            on_side = on_side || all;
          }
        }
        EXPECT_TRUE(on_side) << "hanging face " << face[0] << " " << face[1] << " " << face[2];
      }
      // Two triangles per boundary cell face: no face is missing or hanging.
      EXPECT_EQ(boundary_faces,
                4 * (cells.x() * cells.y() + cells.y() * cells.z() + cells.z() * cells.x()));
      EXPECT_GT(minElementVolume(mesh), 0.0);
      EXPECT_NEAR(meshVolume(mesh), size.prod(), 1e-12 * size.prod());
      EXPECT_TRUE(checkMesh(mesh).empty());
      // Tet10 is built on the same tets.
      const TetMesh tet10 = makeBox(min_corner, size, cells, ElementType::Tet10, split);
      EXPECT_EQ(tet10.elements.topRows(4), mesh.elements);
      EXPECT_TRUE(checkMesh(tet10).empty());
    }
  }
}

TEST(MakeBox, SymmetricSplitIsMirrorInvariantAlongEvenCellCounts) {
  const Eigen::Vector3i cells(4, 2, 6);
  const TetMesh symmetric = makeBox(Eigen::Vector3d(-0.1, 0.2, 0.05),
                                    Eigen::Vector3d(0.2, 0.1, 0.3), cells, ElementType::Tet4);
  const TetMesh diagonal = makeBox(Eigen::Vector3d(-0.1, 0.2, 0.05), Eigen::Vector3d(0.2, 0.1, 0.3),
                                   cells, ElementType::Tet4, CellSplit::Diagonal);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_TRUE(mirrorInvariant(symmetric, cells, axis)) << "axis " << axis;
    EXPECT_FALSE(mirrorInvariant(diagonal, cells, axis)) << "axis " << axis;
  }
  // A beam with even counts across (y, z) is symmetric about y = 0 and z = 0.
  const TetMesh beam = makeBeam(0.5, 0.04, 0.02, Eigen::Vector3i(7, 4, 2), ElementType::Tet4);
  EXPECT_TRUE(mirrorInvariant(beam, Eigen::Vector3i(7, 4, 2), 1));
  EXPECT_TRUE(mirrorInvariant(beam, Eigen::Vector3i(7, 4, 2), 2));
  EXPECT_NEAR(beam.nodes.row(1).minCoeff(), -beam.nodes.row(1).maxCoeff(), 1e-17);
  EXPECT_NEAR(beam.nodes.row(2).minCoeff(), -beam.nodes.row(2).maxCoeff(), 1e-17);
}

/// Mean displacement [m] of the tip face (x = length) of a cantilever beam clamped at x = 0
/// under its own weight with gravity `g` [m/s^2], linear elasticity (the corotational model's
/// stiffness at rest).
Eigen::Vector3d cantileverTipDisplacement(const TetMesh& mesh, const Material& material,
                                          double length, const Eigen::Vector3d& g) {
  const auto model = makeTissueModel(ModelKind::Corotational, mesh, material);
  const Eigen::VectorXd& rest = model->restPositions();
  Eigen::SparseMatrix<double> k = model->stiffnessPattern();
  model->assembleStiffness(rest, TangentMode::Exact, k);
  Eigen::VectorXd f = model->bodyForce(g);
  const auto clamped = [&](Eigen::Index dof) { return rest[3 * (dof / 3)] < 1e-9 * length; };
  // Clamped DOFs: identity rows and columns, zero load.
  for (Eigen::Index col = 0; col < k.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, col); it; ++it) {
      if (clamped(it.row()) || clamped(it.col())) it.valueRef() = it.row() == it.col() ? 1.0 : 0.0;
    }
    if (clamped(col)) f[col] = 0.0;
  }
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(k);
  EXPECT_EQ(solver.info(), Eigen::Success);
  const Eigen::VectorXd u = solver.solve(f);
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  int tip_nodes = 0;
  for (int n = 0; n < mesh.numNodes(); ++n) {
    if (rest[3 * n] > length * (1.0 - 1e-9)) {
      tip += u.segment<3>(3 * n);
      ++tip_nodes;
    }
  }
  return tip / tip_nodes;
}

TEST(MakeBeam, SymmetricSplitBendsOnlyInTheLoadPlane) {
  // A square cantilever (L/h = 10) under its own weight along -y (-z) is symmetric about z = 0
  // (y = 0): its tip must not move sideways. The diagonal split couples the two bending planes
  // (tet4 by about 16 %, tet10 by about 4e-4) and stiffens tet4 further.
  const double length = 0.2;
  const double side = 0.02;
  const Material material = Material::create(5.0e7, 0.45, 1000.0);
  // Euler-Bernoulli tip deflection q L^4 / (8 E I), q = rho g A, I = side^4 / 12 [m].
  const double beam_theory = material.density * 9.81 * side * side * std::pow(length, 4) /
                             (8.0 * material.young_modulus * std::pow(side, 4) / 12.0);
  const Eigen::Vector3i cells(40, 4, 4);
  for (const ElementType type : {ElementType::Tet4, ElementType::Tet10}) {
    const bool tet4 = type == ElementType::Tet4;
    for (const int load_axis : {1, 2}) {
      SCOPED_TRACE(std::string(toString(type)) + ", load along axis " + std::to_string(load_axis));
      const int side_axis = 3 - load_axis;
      Eigen::Vector3d g = Eigen::Vector3d::Zero();
      g[load_axis] = -9.81;
      const Eigen::Vector3d symmetric =
          cantileverTipDisplacement(makeBeam(length, side, side, cells, type), material, length, g);
      const Eigen::Vector3d diagonal = cantileverTipDisplacement(
          makeBeam(length, side, side, cells, type, CellSplit::Diagonal), material, length, g);
      EXPECT_LE(std::abs(symmetric[side_axis] / symmetric[load_axis]), 1e-6);
      EXPECT_GT(std::abs(diagonal[side_axis] / diagonal[load_axis]), tet4 ? 1e-3 : 1e-4);
      // Tet4 locks in bending (error about 14 % symmetric, 40 % diagonal); tet10 is within the
      // shear correction of beam theory.
      const double symmetric_error = std::abs(-symmetric[load_axis] - beam_theory) / beam_theory;
      const double diagonal_error = std::abs(-diagonal[load_axis] - beam_theory) / beam_theory;
      EXPECT_LT(symmetric_error, tet4 ? 0.2 : 0.03);
      if (tet4) {
        EXPECT_GT(diagonal_error, 0.3);
      }
    }
  }
}

TEST(MakeBox, ValidAtMillimetreAndKilometreScales) {
  for (const double scale : {1e-3, 1e3}) {
    const TetMesh mesh = makeBox(Eigen::Vector3d::Constant(scale), Eigen::Vector3d::Constant(scale),
                                 Eigen::Vector3i(2, 3, 2), ElementType::Tet10);
    EXPECT_NO_THROW(requireValidMesh(mesh)) << "scale " << scale;
    EXPECT_NEAR(meshVolume(mesh), scale * scale * scale, 1e-12 * scale * scale * scale);
  }
}

TEST(MakeBeam, SpansDocumentedBoundsWithAnalyticVolume) {
  for (const ElementType type : {ElementType::Tet4, ElementType::Tet10}) {
    const TetMesh mesh = makeBeam(0.1, 0.02, 0.01, Eigen::Vector3i(10, 2, 1), type);
    EXPECT_EQ(mesh.type, type);
    EXPECT_TRUE(mesh.nodes.rowwise().minCoeff().isApprox(Eigen::Vector3d(0.0, -0.01, -0.005)));
    EXPECT_TRUE(mesh.nodes.rowwise().maxCoeff().isApprox(Eigen::Vector3d(0.1, 0.01, 0.005)));
    EXPECT_NEAR(meshVolume(mesh), 0.1 * 0.02 * 0.01, 1e-12 * 2e-5);
    EXPECT_GT(minElementVolume(mesh), 0.0);
    EXPECT_NO_THROW(requireValidMesh(mesh));
  }
}

TEST(MakeHexagonalBeam, CrossSectionAreaIsExactlyTheHexagon) {
  const double side = 0.013;
  const double length = 0.2;
  for (int rings = 1; rings <= 4; ++rings) {
    const TetMesh mesh = makeHexagonalBeam(side, length, 7, rings, ElementType::Tet4);
    EXPECT_EQ(mesh.numNodes(), (1 + 3 * rings * (rings + 1)) * 8);
    EXPECT_EQ(mesh.numElements(), 18 * rings * rings * 7);
    const double exact = 3.0 * std::sqrt(3.0) / 2.0 * side * side * length;
    EXPECT_NEAR(meshVolume(mesh), exact, 1e-12 * exact) << "rings " << rings;
    EXPECT_GT(minElementVolume(mesh), 0.0);
    EXPECT_NO_THROW(requireValidMesh(mesh));
    // Corners at (y, z) = side (cos 60 s, sin 60 s): flat sides at z = +-side sqrt(3)/2.
    EXPECT_NEAR(mesh.nodes.row(1).maxCoeff(), side, 1e-15);
    EXPECT_NEAR(mesh.nodes.row(2).maxCoeff(), side * std::sqrt(3.0) / 2.0, 1e-15);
    EXPECT_NEAR(mesh.nodes.row(0).maxCoeff(), length, 1e-15);
    EXPECT_NEAR(mesh.nodes.row(0).minCoeff(), 0.0, 1e-15);
  }
}

TEST(MakeHexagonalBeam, Tet10IsValid) {
  const TetMesh mesh = makeHexagonalBeam(0.01, 0.05, 3, 2, ElementType::Tet10);
  EXPECT_EQ(mesh.type, ElementType::Tet10);
  EXPECT_NO_THROW(requireValidMesh(mesh));
}

TEST(MakeOrganBlob, ElementQualityDoesNotDegradeWithRefinement) {
  // The plain cube-to-sphere map is singular at the cube corners and inverts elements there
  // from about 24 cells per axis; the generator's map keeps the smallest element volume a fixed
  // fraction of the mean at every resolution, odd or even.
  const Eigen::Vector3d semi_axes(0.075, 0.05, 0.03);
  for (const int cells : {1, 2, 3, 4, 5, 8, 13, 24, 31, 40}) {
    const TetMesh mesh = makeOrganBlob(semi_axes, cells, ElementType::Tet4);
    EXPECT_EQ(mesh.numNodes(), (cells + 1) * (cells + 1) * (cells + 1));
    EXPECT_EQ(mesh.numElements(), 6 * cells * cells * cells);
    const double mean_volume = meshVolume(mesh) / mesh.numElements();
    EXPECT_GT(minElementVolume(mesh), 0.25 * mean_volume) << "cells " << cells;
    if (cells <= 13) {
      EXPECT_NO_THROW(requireValidMesh(mesh)) << "cells " << cells;
    }
  }
}

TEST(MakeOrganBlob, VolumeConvergesToMappedBallVolume) {
  // The shape map has Jacobian determinant a b c (1 - u_x^2 / 4) on the unit ball, and
  // the integral of u_x^2 over the ball is 4 pi / 15: V = (19/20) (4/3) pi a b c.
  const Eigen::Vector3d semi_axes(0.075, 0.05, 0.03);
  const double exact = 0.95 * 4.0 / 3.0 * std::acos(-1.0) * semi_axes.prod();
  const double coarse = meshVolume(makeOrganBlob(semi_axes, 8, ElementType::Tet4));
  const double fine = meshVolume(makeOrganBlob(semi_axes, 16, ElementType::Tet4));
  EXPECT_LT(fine, exact);  // inscribed polyhedron of a convex smooth body
  EXPECT_LT(std::abs(fine - exact), std::abs(coarse - exact));
  EXPECT_LT(std::abs(fine - exact) / exact, 0.03);
}

TEST(MakeOrganBlob, MirrorSymmetricWithTheDocumentedSurface) {
  const Eigen::Vector3d semi_axes(0.075, 0.05, 0.03);
  for (const int cells : {7, 10}) {
    const TetMesh mesh = makeOrganBlob(semi_axes, cells, ElementType::Tet4);
    // Every node has a mirror image under x -> -x, y -> -y and z -> -z.
    for (int axis = 0; axis < 3; ++axis) {
      for (int i = 0; i < mesh.numNodes(); ++i) {
        Eigen::Vector3d mirrored = mesh.nodes.col(i);
        mirrored[axis] = -mirrored[axis];
        double nearest = INFINITY;
        for (int j = 0; j < mesh.numNodes(); ++j) {
          nearest = std::min(nearest, (mesh.nodes.col(j) - mirrored).norm());
        }
        ASSERT_LT(nearest, 1e-12) << "node " << i << " mirrored along axis " << axis;
      }
    }
    // Boundary nodes lie on (x/a)^2 + (y/b)^2 + (z / (c (1 - (x/a)^2 / 4)))^2 = 1, interior
    // nodes inside; the extremes are (+-a, 0, 0), (0, +-b, 0) and (0, 0, +-c).
    int on_surface = 0;
    for (int i = 0; i < mesh.numNodes(); ++i) {
      const Eigen::Vector3d p = mesh.nodes.col(i).cwiseQuotient(semi_axes);
      const double taper = 1.0 - p.x() * p.x() / 4.0;
      const double level = p.x() * p.x() + p.y() * p.y() + p.z() * p.z() / (taper * taper);
      EXPECT_LT(level, 1.0 + 1e-12) << "node " << i;
      if (level > 1.0 - 1e-12) ++on_surface;
    }
    EXPECT_EQ(on_surface, 6 * cells * cells + 2);  // the nodes of the cube's surface
    if (cells % 2 == 0) {
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_NEAR(mesh.nodes.row(axis).maxCoeff(), semi_axes[axis], 1e-15);
        EXPECT_NEAR(mesh.nodes.row(axis).minCoeff(), -semi_axes[axis], 1e-15);
      }
    }
  }
}

TEST(MakeOrganBlob, Tet10MidNodesFollowTheCurvedShape) {
  const TetMesh mesh = makeOrganBlob(Eigen::Vector3d(0.075, 0.05, 0.03), 4, ElementType::Tet10);
  EXPECT_EQ(mesh.type, ElementType::Tet10);
  EXPECT_NO_THROW(requireValidMesh(mesh));
  // Mapped mid-edge nodes are not all at straight midpoints.
  double max_offset = 0.0;
  for (int e = 0; e < mesh.numElements(); ++e) {
    const Eigen::Vector3d mid =
        0.5 * (mesh.nodes.col(mesh.elements(0, e)) + mesh.nodes.col(mesh.elements(1, e)));
    max_offset = std::max(max_offset, (mesh.nodes.col(mesh.elements(4, e)) - mid).norm());
  }
  EXPECT_GT(max_offset, 1e-4);
}

TEST(PromoteToTet10, MidNodesAtEdgeMidpointsAndShared) {
  const TetMesh tet4 = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 2.0, 3.0),
                               Eigen::Vector3i(2, 2, 2), ElementType::Tet4);
  const TetMesh tet10 = promoteToTet10(tet4);
  ASSERT_EQ(tet10.type, ElementType::Tet10);
  ASSERT_EQ(tet10.numElements(), tet4.numElements());
  EXPECT_EQ(tet10.elements.topRows(4), tet4.elements);
  EXPECT_EQ(tet10.nodes.leftCols(tet4.numNodes()), tet4.nodes);
  const int edges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
  std::map<std::pair<int, int>, int> edge_node;
  for (int e = 0; e < tet10.numElements(); ++e) {
    for (int m = 0; m < 6; ++m) {
      const int p = tet10.elements(edges[m][0], e);
      const int q = tet10.elements(edges[m][1], e);
      const int mid = tet10.elements(4 + m, e);
      EXPECT_TRUE(tet10.nodes.col(mid).isApprox(0.5 * (tet10.nodes.col(p) + tet10.nodes.col(q))));
      const auto inserted = edge_node.emplace(std::make_pair(std::min(p, q), std::max(p, q)), mid);
      EXPECT_EQ(inserted.first->second, mid) << "edge (" << p << ", " << q << ") not shared";
    }
  }
  // One node per unique edge, no more.
  EXPECT_EQ(tet10.numNodes(), tet4.numNodes() + static_cast<int>(edge_node.size()));
  EXPECT_NO_THROW(requireValidMesh(tet10));
}

TEST(PromoteToTet10, RejectsTet10AndBadIndices) {
  const TetMesh tet4 = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(),
                               Eigen::Vector3i(1, 1, 1), ElementType::Tet4);
  expectInvalidArgument([&] { promoteToTet10(promoteToTet10(tet4)); },
                        "promoteToTet10: mesh type is tet10, expected tet4");
  TetMesh broken = tet4;
  broken.elements(2, 3) = 8;
  expectInvalidArgument([&] { promoteToTet10(broken); },
                        "promoteToTet10: element 3 references node 8 but the mesh has 8 nodes");
}

TEST(Generators, ValidatorsNameTheParameter) {
  const Eigen::Vector3i cells(2, 2, 2);
  expectInvalidArgument(
      [&] { makeBeam(1.0, 0.1, 0.1, Eigen::Vector3i(0, 1, 1), ElementType::Tet4); },
      "makeBeam: cells.x = 0 must be >= 1");
  expectInvalidArgument([&] { makeBeam(-1.0, 0.1, 0.1, cells, ElementType::Tet4); },
                        "makeBeam: length = -1 m");
  expectInvalidArgument([&] { makeBeam(1.0, 0.1, NAN, cells, ElementType::Tet4); },
                        "makeBeam: height");
  expectInvalidArgument(
      [&] {
        makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.0, 1.0), cells, ElementType::Tet4);
      },
      "makeBox: size.y = 0 m");
  expectInvalidArgument(
      [&] {
        makeBox(Eigen::Vector3d(0.0, 0.0, INFINITY), Eigen::Vector3d::Ones(), cells,
                ElementType::Tet4);
      },
      "makeBox: min_corner.z");
  expectInvalidArgument(
      [&] {
        makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), Eigen::Vector3i(1, 1, -2),
                ElementType::Tet4);
      },
      "makeBox: cells.z = -2 must be >= 1");
  expectInvalidArgument([&] { makeHexagonalBeam(0.0, 1.0, 1, 1, ElementType::Tet4); },
                        "makeHexagonalBeam: side = 0 m");
  expectInvalidArgument([&] { makeHexagonalBeam(1.0, 1.0, 0, 1, ElementType::Tet4); },
                        "makeHexagonalBeam: cells_along = 0 must be >= 1");
  expectInvalidArgument([&] { makeHexagonalBeam(1.0, 1.0, 1, 0, ElementType::Tet4); },
                        "makeHexagonalBeam: rings = 0 must be >= 1");
  expectInvalidArgument(
      [&] { makeOrganBlob(Eigen::Vector3d(1.0, 1.0, -1.0), 4, ElementType::Tet4); },
      "makeOrganBlob: semi_axes.z = -1 m");
  expectInvalidArgument([&] { makeOrganBlob(Eigen::Vector3d::Ones(), 0, ElementType::Tet4); },
                        "makeOrganBlob: cells_per_axis = 0 must be >= 1");
  expectInvalidArgument([&] { makeBeam(1.0, 0.1, 0.1, cells, static_cast<ElementType>(3)); },
                        "makeBeam: type = 3 is not a known ElementType");
  expectInvalidArgument(
      [&] {
        makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), cells, ElementType::Tet4,
                static_cast<CellSplit>(7));
      },
      "makeBox: split = 7 is not a known CellSplit");
}

}  // namespace
}  // namespace surgical_sim::core
