#include "surgical_sim/core/contact/contact_detector.h"

#include <algorithm>
#include <cmath>

#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/contact/closest_points_segment_triangle.h"
#include "surgical_sim/core/contact/normal_derivative.h"

namespace surgical_sim::core {

void validateContactDetectorSettings(const ContactDetectorSettings& settings) {
  requireNonNegative("contact.margin", settings.margin, "m");
  requireInRange("contact.max_contacts", settings.max_contacts, 1, 1024, "");
  requireInHalfOpenRange("contact.merge_tolerance", settings.merge_tolerance, 0.0, 1.0, "");
}

ContactDetector::ContactDetector(const ContactDetectorSettings& settings) : settings_(settings) {
  validateContactDetectorSettings(settings);
  found_.reserve(static_cast<size_t>(4 * settings.max_contacts));
}

void ContactDetector::detect(int tool, const ToolCapsule& capsule,
                             const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& x,
                             SurfaceBvh& bvh, std::vector<ContactPoint>& contacts) {
  const double radius = capsule.radius();
  const Eigen::Vector3d a = capsule.tip();
  const Eigen::Vector3d b = capsule.shaftEnd();
  const double merge_squared = std::pow(settings_.merge_tolerance * radius, 2);
  bvh.query(capsule.bounds(settings_.margin), candidates_);
  found_.clear();
  for (const int t : candidates_) {
    const Eigen::Vector3i nodes = triangles.col(t);
    const Eigen::Vector3d v0 = x.segment<3>(3 * nodes[0]);
    const Eigen::Vector3d v1 = x.segment<3>(3 * nodes[1]);
    const Eigen::Vector3d v2 = x.segment<3>(3 * nodes[2]);
    const Eigen::Vector3d outward = (v1 - v0).cross(v2 - v0);
    if (!(outward.squaredNorm() > 0.0)) continue;  // degenerate triangle: no normal
    const Eigen::Vector3d n_t = outward.normalized();
    const SegmentTriangleClosest closest = closestPointsSegmentTriangle(a, b, v0, v1, v2);
    ContactPoint contact;
    contact.tool = tool;
    contact.triangle = t;
    contact.nodes = nodes;
    contact.weights = closest.barycentric;
    contact.p_S = closest.point_triangle;
    const Eigen::Vector3d axis_to_surface = closest.point_triangle - closest.point_segment;
    const double distance = std::sqrt(closest.distance_squared);
    if (closest.intersects || !(distance > 0.0)) {
      contact.n_S = -n_t;
      const double depth = std::min(n_t.dot(a - contact.p_S), n_t.dot(b - contact.p_S));
      contact.gap = std::min(depth, 0.0) - radius;
    } else {
      // In front of the triangle n points from the axis to the surface; with the axis behind it
      // (less than a radius deep; deeper it was pushed through) n is reversed.
      const bool in_front = n_t.dot(axis_to_surface) <= 0.0;
      if (!in_front && distance >= radius) continue;
      const double side = in_front ? 1.0 : -1.0;
      contact.n_S = side * axis_to_surface / distance;
      contact.gap = side * distance - radius;
      contact.dn_du = side * normalTranslationDerivative(closest, a, b, v0, v1, v2);
    }
    contact.dn_dx = contactNormalNodeDerivative(closest, contact.n_S, contact.dn_du, v0, v1, v2);
    if (!(contact.gap < settings_.margin)) continue;
    bool merged = false;
    for (ContactPoint& other : found_) {
      if ((other.p_S - contact.p_S).squaredNorm() <= merge_squared) {
        if (contact.gap < other.gap) other = contact;
        merged = true;
        break;
      }
    }
    if (!merged) found_.push_back(contact);
  }
  const auto cap = static_cast<size_t>(settings_.max_contacts);
  const auto deeper = [](const ContactPoint& l, const ContactPoint& r) { return l.gap < r.gap; };
  if (found_.size() > cap) {
    std::nth_element(found_.begin(), found_.begin() + static_cast<std::ptrdiff_t>(cap - 1),
                     found_.end(), deeper);
    found_.resize(cap);
  }
  contacts.insert(contacts.end(), found_.begin(), found_.end());
}

}  // namespace surgical_sim::core
