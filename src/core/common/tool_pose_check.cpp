#include "surgical_sim/core/common/tool_pose_check.h"

namespace surgical_sim::core {

bool isUsableToolPose(const Eigen::Vector3d& p, const Eigen::Vector4d& q_wxyz,
                      double max_distance) {
  if (!p.allFinite() || !q_wxyz.allFinite()) return false;
  const double qn = q_wxyz.norm();
  return qn >= 0.5 && qn <= 2.0 && p.norm() <= max_distance;
}

}  // namespace surgical_sim::core
