#include "surgical_sim/core/cutting/cut_front.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstddef>

namespace surgical_sim::core {

namespace {

/// A candidate triangle worse than this fraction of the other's quality is a sliver: the other
/// is taken instead.
constexpr double kSliver = 0.2;

/// Shape quality of a triangle: twice its area over the sum of its squared edge lengths
/// (0 for a degenerate triangle, largest for an equilateral one).
double quality(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double edges = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return edges > 0.0 ? (b - a).cross(c - a).norm() / edges : 0.0;
}

/// Cumulative rest length along a chain, normalised to end at 1 (all 0 for a point chain).
std::vector<double> arcParameters(const std::vector<int>& chain,
                                  const std::function<Eigen::Vector3d(int)>& rest) {
  std::vector<double> t(chain.size(), 0.0);
  for (std::size_t i = 1; i < chain.size(); ++i)
    t[i] = t[i - 1] + (rest(chain[i]) - rest(chain[i - 1])).norm();
  if (t.back() > 0.0)
    for (double& x : t) x /= t.back();
  return t;
}

}  // namespace

void appendStrip(const std::vector<int>& behind, const std::vector<int>& ahead,
                 const std::function<Eigen::Vector3d(int)>& rest,
                 std::vector<std::array<int, 3>>& out) {
  const std::size_t nb = behind.size(), na = ahead.size();
  const std::vector<double> tb = arcParameters(behind, rest), ta = arcParameters(ahead, rest);
  auto emit = [&out](int a, int b, int c) {
    if (a != b && b != c && c != a) out.push_back({a, b, c});
  };
  const bool shared_start = behind.front() == ahead.front();
  const bool shared_end = behind.back() == ahead.back();
  std::size_t i = 0, j = 0;
  while (i + 1 < nb || j + 1 < na) {
    bool advance_behind;
    if (i + 1 >= nb) {
      advance_behind = false;
    } else if (j + 1 >= na) {
      advance_behind = true;
    } else {
      advance_behind = tb[i + 1] <= ta[j + 1];
      const double q_behind = quality(rest(behind[i]), rest(behind[i + 1]), rest(ahead[j]));
      const double q_ahead = quality(rest(behind[i]), rest(ahead[j + 1]), rest(ahead[j]));
      if (advance_behind ? q_behind < kSliver * q_ahead : q_ahead < kSliver * q_behind)
        advance_behind = !advance_behind;
      // At a shared end vertex no triangle may take all three corners from one chain (it would
      // overlap the neighbouring strip): leave the shared start at once, reach the shared end
      // last.
      if (shared_start && j == 0 && i > 0) advance_behind = false;
      if (shared_start && i == 0 && j > 0) advance_behind = true;
      if (shared_end && j + 2 == na && i + 2 < nb) advance_behind = true;
      if (shared_end && i + 2 == nb && j + 2 < na) advance_behind = false;
    }
    if (advance_behind) {
      emit(behind[i], behind[i + 1], ahead[j]);
      ++i;
    } else {
      emit(behind[i], ahead[j + 1], ahead[j]);
      ++j;
    }
  }
}

int frontSegmentCount(double length, int previous, double width) {
  int k = std::max(previous, 2);
  while (length / k > width) ++k;
  while (k > 2 && length / k < 0.5 * width) --k;
  return k;
}

}  // namespace surgical_sim::core
