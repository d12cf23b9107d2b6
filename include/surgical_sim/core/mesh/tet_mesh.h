#pragma once

#include <Eigen/Core>

namespace surgical_sim::core {

/// Volume element types. Linear tets first; quadratic tets avoid the volumetric / shear locking of
/// linear tets near incompressibility and in bending.
enum class ElementType {
  Tet4,   ///< 4-node linear tetrahedron
  Tet10,  ///< 10-node quadratic tetrahedron, Gmsh node order (element type 11):
          ///< corners 0..3, then mid-edge nodes 4:(0,1) 5:(1,2) 6:(0,2) 7:(0,3) 8:(2,3) 9:(1,3)
};

/// Number of nodes of one element of the given type (4 or 10).
int nodesPerElement(ElementType type);
/// "tet4" / "tet10".
const char* toString(ElementType type);

/// A volume mesh in metres. Corner nodes of every element are positively oriented
/// (det[x1-x0, x2-x0, x3-x0] > 0) after meshCheck passes.
struct TetMesh {
  ElementType type = ElementType::Tet4;
  Eigen::Matrix3Xd nodes;    ///< node positions [m], shape 3 x n
  Eigen::MatrixXi elements;  ///< node indices, shape nodesPerElement(type) x m

  int numNodes() const { return static_cast<int>(nodes.cols()); }
  int numElements() const { return static_cast<int>(elements.cols()); }
};

/// A triangle surface in metres, outward-oriented (counter-clockwise seen from outside).
struct TriMesh {
  Eigen::Matrix3Xd vertices;   ///< [m], shape 3 x n
  Eigen::Matrix3Xi triangles;  ///< vertex indices, shape 3 x m
};

}  // namespace surgical_sim::core
