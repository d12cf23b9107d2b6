#include "surgical_sim/core/cutting/blade_sweep.h"

#include <sstream>
#include <stdexcept>

namespace surgical_sim::core {

Eigen::AlignedBox3d sweepBox(const BladeSweep& sweep, double margin) {
  const Eigen::Vector3d lo =
      sweep.start.rowwise().minCoeff().cwiseMin(sweep.end.rowwise().minCoeff()).array() - margin;
  const Eigen::Vector3d hi =
      sweep.start.rowwise().maxCoeff().cwiseMax(sweep.end.rowwise().maxCoeff()).array() + margin;
  return {lo, hi};
}

void validateBladePolyline(const std::string& name, const Eigen::Matrix3Xd& blade) {
  const Eigen::Index k = blade.cols();
  if (k < 2 || k > kMaxBladePoints)
    throw std::invalid_argument(name + " has " + std::to_string(k) +
                                " points; a blade polyline needs at least 2 and at most " +
                                std::to_string(kMaxBladePoints));
  if (!blade.allFinite()) throw std::invalid_argument(name + " is not finite");
  const double length = (blade.rightCols(k - 1) - blade.leftCols(k - 1)).colwise().norm().sum();
  if (!(length >= kMinBladeLength)) {
    std::ostringstream msg;
    msg << name << " has a total length of " << length << " m; a blade needs at least "
        << kMinBladeLength << " m (its points must not all coincide)";
    throw std::invalid_argument(msg.str());
  }
}

void validateBladeSweep(const BladeSweep& sweep) {
  validateBladePolyline("blade_sweep.start", sweep.start);
  if (sweep.end.cols() != sweep.start.cols())
    throw std::invalid_argument("blade_sweep.end has " + std::to_string(sweep.end.cols()) +
                                " points but blade_sweep.start has " +
                                std::to_string(sweep.start.cols()));
  validateBladePolyline("blade_sweep.end", sweep.end);
}

}  // namespace surgical_sim::core
