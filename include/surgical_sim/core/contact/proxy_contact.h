#pragma once

#include <Eigen/Core>
#include <vector>

#include "surgical_sim/core/contact/contact_point.h"
#include "surgical_sim/core/contact/surface_bvh.h"
#include "surgical_sim/core/tissue/surface_mapping.h"

namespace surgical_sim::core {

/// God-object proxy contact (Zilles & Salisbury; Chendeb 2007), the simple contact response.
/// A proxy point stays on the deformed surface where the tool tip entered it (a triangle and
/// barycentric weights, so it follows the deformation); while the tip is inside, the proxy slides
/// to the surface point locally closest to the tip. A spring k_proxy between the tip and the
/// proxy gives the force on the tool f = k_proxy (p_proxy - p_tip), saturated at |f| = F_max;
/// its opposite is applied to the proxy triangle's vertices (barycentric weights) as external force
/// in the next step. The stiffness for the haptic loop is K = df/dp = -k_proxy n n^T (n: the
/// proxy triangle's outward normal; the proxy slides tangentially), 0 while saturated. All
/// quantities in the tissue frame S.
class ProxyContact {
 public:
  /// @param stiffness k_proxy [N/m], finite and > 0
  /// @param max_force F_max [N], finite and > 0
  /// @throws std::invalid_argument naming "tool.proxy_stiffness" or "tool.max_force"
  ProxyContact(double stiffness, double max_force);

  /// Updates the proxy for the tip position p_tip_S [m] and the deformed surface (bvh refit to
  /// x). Entry: the tip moved since the last update across a triangle from its outer side, or
  /// (the surface moved over the tip) the surface point closest to the tip within search_radius
  /// has the tip behind its triangle. Release: the tip is on the outer side of the proxy
  /// triangle. Never throws; allocation-free once the candidate buffer has grown.
  /// @param search_radius entry search radius around the tip [m], e.g. the tool radius
  /// @param triangles surface triangles (vertex slots), 3 x t
  /// @param x vertex positions [m] (SurfaceMapping::apply), in S
  void update(const Eigen::Vector3d& p_tip_S, double search_radius,
              const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& x, SurfaceBvh& bvh);
  /// f_ext += force of the tool on the tissue [N]: -toolForce() on the proxy triangle's
  /// vertices, mapped to the model's DOFs by `mapping` (f_ext size 3 mapping.numNodes()).
  void addTissueForce(const SurfaceMapping& mapping, Eigen::VectorXd& f_ext) const;

  bool inContact() const { return in_contact_; }
  /// Proxy point [m], S (meaningful while in contact).
  const Eigen::Vector3d& proxy() const { return p_proxy_; }
  /// Force of the tissue on the tool k_proxy (p_proxy - p_tip) saturated at F_max [N], S; 0
  /// without contact.
  Eigen::Vector3d toolForce() const;
  /// Whether the spring force is saturated at F_max (in contact only).
  bool limited() const;
  /// Local model at the tip: f0 = toolForce(), K = -k_proxy n n^T (0 while limited()).
  ContactLinearization linearization() const;
  double stiffness() const { return stiffness_; }  ///< k_proxy [N/m]

 private:
  /// Enters contact at the closest surface point within search_radius if the tip is behind it.
  void enterIfInside(double search_radius, const Eigen::Matrix3Xi& triangles,
                     const Eigen::VectorXd& x, SurfaceBvh& bvh);
  /// Moves the proxy to the surface point closest to the tip within |tip - proxy|.
  void slide(const Eigen::Matrix3Xi& triangles, const Eigen::VectorXd& x, SurfaceBvh& bvh);
  /// Puts the proxy (nodes_, weights_, p_proxy_) at the surface point closest to the tip if one
  /// lies within `radius` [m]; returns whether one did (otherwise nothing changes).
  bool moveToClosestSurfacePoint(double radius, const Eigen::Matrix3Xi& triangles,
                                 const Eigen::VectorXd& x, SurfaceBvh& bvh);

  double stiffness_;
  double max_force_;  ///< [N]
  bool in_contact_ = false;
  bool has_previous_tip_ = false;
  Eigen::Vector3d p_tip_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d p_proxy_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_ = Eigen::Vector3d::UnitZ();  ///< outward normal of the proxy triangle
  Eigen::Vector3i nodes_ = Eigen::Vector3i::Zero();
  Eigen::Vector3d weights_ = Eigen::Vector3d::Zero();
  std::vector<int> candidates_;
};

}  // namespace surgical_sim::core
