#pragma once

#include <Eigen/Core>
#include <vector>

#include "surgical_sim/core/contact/contact_point.h"
#include "surgical_sim/core/contact/surface_bvh.h"
#include "surgical_sim/core/contact/tool_capsule.h"

namespace surgical_sim::core {

/// Settings of ContactDetector. Numerical choices with documented defaults.
struct ContactDetectorSettings {
  double margin = 1e-3;   ///< contacts are kept while gap < margin [m], finite and >= 0
  int max_contacts = 64;  ///< per tool; the deepest are kept [-], in [1, 1024]
  /// Contacts whose surface points are closer than merge_tolerance x radius are one contact (the
  /// deepest is kept): shared vertices and edges of neighbouring triangles [-], in [0, 1).
  double merge_tolerance = 1e-6;
};

/// @throws std::invalid_argument naming "contact.margin", "contact.max_contacts" or
///         "contact.merge_tolerance"
void validateContactDetectorSettings(const ContactDetectorSettings& settings);

/// Narrow phase of a tool capsule against the deforming surface (broad phase: SurfaceBvh).
///
/// For each candidate triangle the exact closest points between the capsule axis and the
/// triangle give the contact point p and, with c the axis point and n_t the triangle's outward
/// normal:
/// - axis in front of the triangle (n_t . (c - p) >= 0): n = (p - c) / |p - c|,
///   gap = |p - c| - radius;
/// - axis behind it by less than radius (crossed the surface): n = (c - p) / |p - c|,
///   gap = -|p - c| - radius; deeper crossings are dropped (tool pushed through);
/// - axis piercing the triangle: n = -n_t, gap = (depth of the inner axis end, <= 0) - radius.
/// Contacts with gap >= margin are dropped, duplicates merged, and at most max_contacts (the
/// deepest) kept per tool.
class ContactDetector {
 public:
  /// @throws std::invalid_argument (validateContactDetectorSettings)
  explicit ContactDetector(const ContactDetectorSettings& settings);

  /// Appends the contacts of tool `tool` to contacts (capacity kept; allocation-free once the
  /// buffers reached their working sizes). Calls bvh.query(); bvh must be refit to x.
  /// @param triangles surface triangles (volume node indices), 3 x t, as given to the bvh
  /// @param x node positions [m], size 3n, in S
  void detect(int tool, const ToolCapsule& capsule, const Eigen::Matrix3Xi& triangles,
              const Eigen::VectorXd& x, SurfaceBvh& bvh, std::vector<ContactPoint>& contacts);

  const ContactDetectorSettings& settings() const { return settings_; }

 private:
  ContactDetectorSettings settings_;
  std::vector<int> candidates_;
  std::vector<ContactPoint> found_;
};

}  // namespace surgical_sim::core
