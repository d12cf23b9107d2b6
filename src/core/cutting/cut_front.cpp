#include "surgical_sim/core/cutting/cut_front.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstddef>

namespace surgical_sim::core {

namespace {

/// A candidate triangle worse than this fraction of the other's quality is a sliver: the other
/// is taken instead.
constexpr double kSliver = 0.2;
/// Largest lead of one chain's share of segments done over the other's in a strip [-].
constexpr double kShareLead = 0.25;

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
  // Share of a chain's segments done after k advances.
  const auto share = [](std::size_t k, std::size_t n) {
    return n > 1 ? static_cast<double>(k) / static_cast<double>(n - 1) : 1.0;
  };
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
      // Neither chain's share done runs more than kShareLead ahead of the other's, so unevenly
      // spaced chains (crossings bunched up in a short stretch) make no fan.
      if (advance_behind && share(i + 1, nb) > share(j, na) + kShareLead)
        advance_behind = false;
      else if (!advance_behind && share(j + 1, na) > share(i, nb) + kShareLead)
        advance_behind = true;
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

int gradingLevels(std::size_t dense, std::size_t sparse) {
  int levels = 0;
  for (std::size_t n = dense; n > 2 * sparse + 2 && n > 3; n = n / 2 + 1) ++levels;
  return levels;
}

std::vector<Eigen::Vector3d> halvingRow(const std::vector<int>& behind,
                                        const std::vector<int>& ahead,
                                        const std::function<Eigen::Vector3d(int)>& rest, double f) {
  const std::vector<double> tb = arcParameters(behind, rest), ta = arcParameters(ahead, rest);
  std::vector<Eigen::Vector3d> out;
  std::size_t j = 0;  // ahead's segment [j, j + 1] holding the arc parameter
  for (std::size_t i = 2; i + 1 < behind.size(); i += 2) {
    Eigen::Vector3d on_ahead = rest(ahead[0]);
    if (ahead.size() > 1) {
      while (j + 2 < ahead.size() && ta[j + 1] < tb[i]) ++j;
      const double span = ta[j + 1] - ta[j];
      const double s = span > 0.0 ? std::clamp((tb[i] - ta[j]) / span, 0.0, 1.0) : 0.0;
      on_ahead = (1.0 - s) * rest(ahead[j]) + s * rest(ahead[j + 1]);
    }
    out.push_back((1.0 - f) * rest(behind[i]) + f * on_ahead);
  }
  return out;
}

int frontSegmentCount(double length, int previous, double width) {
  int k = std::max(previous, 2);
  while (length / k > width) ++k;
  while (k > 2 && length / k < 0.5 * width) --k;
  return k;
}

}  // namespace surgical_sim::core
