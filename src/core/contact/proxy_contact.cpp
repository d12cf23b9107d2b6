#include "surgical_sim/core/contact/proxy_contact.h"

#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/contact/closest_point_on_triangle.h"
#include "surgical_sim/core/contact/closest_points_segment_triangle.h"

namespace surgical_sim::core {
namespace {

Eigen::Vector3d outwardNormal(const Eigen::Vector3i& nodes, const Eigen::VectorXd& x) {
  const Eigen::Vector3d v0 = x.segment<3>(3 * nodes[0]);
  const Eigen::Vector3d normal =
      (x.segment<3>(3 * nodes[1]) - v0).cross(x.segment<3>(3 * nodes[2]) - v0);
  const double length = normal.norm();
  return length > 0.0 ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::Zero();
}

}  // namespace

ProxyContact::ProxyContact(double stiffness, double max_force)
    : stiffness_(stiffness), max_force_(max_force) {
  requirePositive("tool.proxy_stiffness", stiffness, "N/m");
  requirePositive("tool.max_force", max_force, "N");
}

void ProxyContact::update(const Eigen::Vector3d& p_tip_S, double search_radius,
                          const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& x,
                          SurfaceBvh& bvh) {
  const Eigen::Vector3d previous = p_tip_;
  const bool had_previous = has_previous_tip_;
  p_tip_ = p_tip_S;
  has_previous_tip_ = true;
  if (!in_contact_) {
    if (!had_previous) return;
    Eigen::AlignedBox3d box(previous.cwiseMin(p_tip_), previous.cwiseMax(p_tip_));
    bvh.query(box, candidates_);
    double first = 2.0;
    for (const int t : candidates_) {
      const Eigen::Vector3i nodes = triangles.col(t);
      const Eigen::Vector3d v0 = x.segment<3>(3 * nodes[0]);
      const SegmentTriangleClosest hit = closestPointsSegmentTriangle(
          previous, p_tip_, v0, x.segment<3>(3 * nodes[1]), x.segment<3>(3 * nodes[2]));
      const Eigen::Vector3d normal = outwardNormal(nodes, x);
      const bool entering = normal.dot(previous - v0) > 0.0 && normal.dot(p_tip_ - v0) < 0.0;
      if (!hit.intersects || !entering || hit.t >= first) continue;
      first = hit.t;
      in_contact_ = true;
      nodes_ = nodes;
      weights_ = hit.barycentric;
      normal_ = normal;
    }
    if (!in_contact_) enterIfInside(search_radius, triangles, x, bvh);
    if (!in_contact_) return;
  }
  p_proxy_ = weights_[0] * x.segment<3>(3 * nodes_[0]) + weights_[1] * x.segment<3>(3 * nodes_[1]) +
             weights_[2] * x.segment<3>(3 * nodes_[2]);
  normal_ = outwardNormal(nodes_, x);
  slide(triangles, x, bvh);
  if (normal_.dot(p_tip_ - p_proxy_) >= 0.0) in_contact_ = false;  // tip back outside
}

void ProxyContact::enterIfInside(double search_radius, const Eigen::Matrix3Xi& triangles,
                                 const Eigen::VectorXd& x, SurfaceBvh& bvh) {
  if (!moveToClosestSurfacePoint(search_radius, triangles, x, bvh)) return;
  normal_ = outwardNormal(nodes_, x);
  in_contact_ = normal_.dot(p_tip_ - p_proxy_) < 0.0;  // tip behind the closest triangle
}

void ProxyContact::slide(const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& x,
                         SurfaceBvh& bvh) {
  moveToClosestSurfacePoint((p_tip_ - p_proxy_).norm(), triangles, x, bvh);
  normal_ = outwardNormal(nodes_, x);
}

bool ProxyContact::moveToClosestSurfacePoint(double radius, const Eigen::Matrix3Xi& triangles,
                                             const Eigen::VectorXd& x, SurfaceBvh& bvh) {
  const Eigen::Vector3d extent = Eigen::Vector3d::Constant(radius);
  bvh.query(Eigen::AlignedBox3d(p_tip_ - extent, p_tip_ + extent), candidates_);
  double best = radius * radius;
  bool found = false;
  for (const int t : candidates_) {
    const Eigen::Vector3i nodes = triangles.col(t);
    const TrianglePointClosest closest = closestPointOnTriangle(
        x.segment<3>(3 * nodes[0]), x.segment<3>(3 * nodes[1]), x.segment<3>(3 * nodes[2]), p_tip_);
    if (closest.distance_squared >= best) continue;
    best = closest.distance_squared;
    found = true;
    nodes_ = nodes;
    weights_ = closest.barycentric;
    p_proxy_ = closest.point;
  }
  return found;
}

void ProxyContact::addTissueForce(const SurfaceMapping& mapping, Eigen::VectorXd& f_ext) const {
  if (!in_contact_) return;
  const Eigen::Vector3d force = -toolForce();
  for (int k = 0; k < 3; ++k) mapping.addVertexForce(nodes_[k], weights_[k] * force, f_ext);
}

Eigen::Vector3d ProxyContact::toolForce() const {
  if (!in_contact_) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d spring = stiffness_ * (p_proxy_ - p_tip_);
  const double magnitude = spring.norm();
  return magnitude > max_force_ ? Eigen::Vector3d((max_force_ / magnitude) * spring) : spring;
}

bool ProxyContact::limited() const {
  return in_contact_ && stiffness_ * (p_proxy_ - p_tip_).norm() > max_force_;
}

ContactLinearization ProxyContact::linearization() const {
  ContactLinearization out;
  out.p0_S = p_tip_;
  if (!in_contact_) return out;
  out.in_contact = true;
  out.contacts = 1;
  out.f0_S = toolForce();
  if (!limited()) out.K_S = -stiffness_ * normal_ * normal_.transpose();
  return out;
}

}  // namespace surgical_sim::core
