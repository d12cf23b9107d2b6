#include "surgical_sim/core/common/tool_pose_check.h"

namespace surgical_sim::core {

ToolPoseProblem toolPoseProblem(const Eigen::Vector3d& p, const Eigen::Vector4d& q_wxyz,
                                double max_distance) {
  if (!p.allFinite()) return ToolPoseProblem::NonFinitePosition;
  const double qn = q_wxyz.norm();  // NaN for a non-finite component: fails the range test
  if (!(qn >= 0.5 && qn <= 2.0)) return ToolPoseProblem::BadQuaternion;
  return p.norm() <= max_distance ? ToolPoseProblem::None : ToolPoseProblem::TooFar;
}

bool isUsableToolPose(const Eigen::Vector3d& p, const Eigen::Vector4d& q_wxyz,
                      double max_distance) {
  return toolPoseProblem(p, q_wxyz, max_distance) == ToolPoseProblem::None;
}

}  // namespace surgical_sim::core
