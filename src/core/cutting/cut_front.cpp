#include "surgical_sim/core/cutting/cut_front.h"

#include <algorithm>
#include <cstddef>

namespace surgical_sim::core {

void appendStrip(const std::vector<int>& behind, const std::vector<int>& ahead,
                 const std::function<Eigen::Vector3d(int)>& rest,
                 std::vector<std::array<int, 3>>& out) {
  const std::size_t nb = behind.size(), na = ahead.size();
  const auto& X = rest;
  auto emit = [&out](int a, int b, int c) {
    if (a != b && b != c && c != a) out.push_back({a, b, c});
  };
  std::size_t i = 0, j = 0;
  while (i + 1 < nb || j + 1 < na) {
    bool advance_behind;
    if (i + 1 >= nb)
      advance_behind = false;
    else if (j + 1 >= na)
      advance_behind = true;
    else  // diagonal (behind_i+1, ahead_j) vs (behind_i, ahead_j+1)
      advance_behind = (X(behind[i + 1]) - X(ahead[j])).squaredNorm() <=
                       (X(behind[i]) - X(ahead[j + 1])).squaredNorm();
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
