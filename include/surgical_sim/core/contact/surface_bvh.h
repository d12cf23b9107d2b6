#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <vector>

class btDbvt;
struct btDbvtNode;

namespace surgical_sim::core {

/// Dynamic bounding-volume hierarchy over the triangles of a deforming surface, built on Bullet's
/// btDbvt (dynamic AABB tree). Build once per topology; refit() each step from the deformed
/// positions; query() returns the triangles whose exact axis-aligned box overlaps a query box.
///
/// The tree stores "fat" leaf boxes (tight box + fat_margin, rounded outward to Bullet's float
/// precision), so a leaf is re-inserted only when its triangle leaves its fat box; query()
/// filters the tree's candidates with the exact (double) tight boxes, so the result equals a
/// brute-force scan. All boxes are in the tissue frame S.
class SurfaceBvh {
 public:
  /// @param triangles volume node indices, shape 3 x t, each in [0, x.size() / 3)
  /// @param x node positions [m], size 3n, in S
  /// @param fat_margin leaf box inflation [m], finite and >= 0 (e.g. a tenth of an edge length)
  /// @throws std::invalid_argument naming "bvh.fat_margin", or "bvh.triangles" for an index out
  ///         of range
  SurfaceBvh(const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& x, double fat_margin);
  ~SurfaceBvh();
  SurfaceBvh(const SurfaceBvh&) = delete;
  SurfaceBvh& operator=(const SurfaceBvh&) = delete;
  SurfaceBvh(SurfaceBvh&&) noexcept;
  SurfaceBvh& operator=(SurfaceBvh&&) noexcept;

  /// Updates every leaf from the positions x [m] (size 3n, same n as at construction, in S).
  /// Allocation-free (btDbvt reuses its freed node). Never throws.
  void refit(const Eigen::VectorXd& x);

  /// Replaces the triangles (a surface changed by a cut) with positions x [m] (size 3n, in S):
  /// a triangle whose vertices (in order) were a triangle before keeps its leaf, refitted to x;
  /// the others' leaves are removed and the new ones inserted, so the tree is not rebuilt. The
  /// fat margin stays. O(t) hashing plus O(log t) per changed triangle.
  /// @throws std::invalid_argument naming "bvh.triangles" for an index out of range (nothing
  ///         changes then)
  void setTriangles(const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& x);

  /// Writes into out (cleared first; keeps its capacity) the indices of the triangles whose tight
  /// box overlaps box [m] (in S), in no particular order. Allocation-free once out and the
  /// traversal stack have grown to their working sizes. Never throws.
  void query(const Eigen::AlignedBox3d& box, std::vector<int>& out);

  int numTriangles() const { return static_cast<int>(boxes_.size()); }
  /// Tight box of triangle i [m], in S, as of the last refit.
  const Eigen::AlignedBox3d& triangleBox(int i) const { return boxes_[static_cast<size_t>(i)]; }

 private:
  struct Traversal;
  void computeTightBox(int i, const Eigen::VectorXd& x);
  /// Inserts the leaf of triangle i from its tight box (computeTightBox first).
  void insertLeaf(int i);
  /// Re-inserts the leaf of triangle i if its tight box (computeTightBox first) left the leaf's
  /// fat box.
  void refitLeaf(int i);

  Eigen::Matrix3Xi triangles_;
  double fat_margin_;
  std::unique_ptr<btDbvt> tree_;
  std::vector<btDbvtNode*> leaves_;
  std::vector<Eigen::AlignedBox3d> boxes_;
  std::unique_ptr<Traversal> traversal_;  ///< preallocated traversal stack and output pointer
};

}  // namespace surgical_sim::core
