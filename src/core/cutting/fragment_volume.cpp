#include "surgical_sim/core/cutting/fragment_volume.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace surgical_sim::core {

namespace {

/// Fraction of the way from corner a to corner b where their edge is cut [-].
double sigma(const std::array<double, 6>& edge_s, int a, int b) {
  const double s = edge_s[static_cast<std::size_t>(tetLocalEdge(a, b))];
  return a < b ? s : 1.0 - s;
}

Eigen::Vector3d cutPoint(const Eigen::Matrix<double, 3, 4>& X, const std::array<double, 6>& s,
                         int a, int b) {
  return X.col(a) + sigma(s, a, b) * (X.col(b) - X.col(a));
}

double tetVolume(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                 const Eigen::Vector3d& p3) {
  return std::abs((p1 - p0).cross(p2 - p0).dot(p3 - p0)) / 6.0;
}

int popcount4(int mask) { return (mask & 1) + ((mask >> 1) & 1) + ((mask >> 2) & 1) + (mask >> 3); }

int lowestCorner(int mask) {
  for (int i = 0; i < 4; ++i)
    if (mask & (1 << i)) return i;
  return -1;
}

/// Raw (unclamped) fraction of a singleton {a} or a pair {a, b}.
double rawFraction(const Eigen::Matrix<double, 3, 4>& X, const std::array<double, 6>& s, int mask) {
  const int a = lowestCorner(mask);
  if (popcount4(mask) == 1) {
    double f = 1.0;
    for (int b = 0; b < 4; ++b)
      if (b != a) f *= sigma(s, a, b);
    return f;
  }
  const int b = lowestCorner(mask & ~(1 << a));
  const int rest = 0xF & ~mask;
  const int c = lowestCorner(rest);
  const int d = lowestCorner(rest & ~(1 << c));
  const Eigen::Vector3d v[6] = {X.col(a), cutPoint(X, s, a, c), cutPoint(X, s, a, d),
                                X.col(b), cutPoint(X, s, b, c), cutPoint(X, s, b, d)};
  const double prism = tetVolume(v[0], v[1], v[2], v[3]) + tetVolume(v[1], v[2], v[3], v[4]) +
                       tetVolume(v[2], v[3], v[4], v[5]);
  return prism / tetVolume(X.col(0), X.col(1), X.col(2), X.col(3));
}

}  // namespace

int tetLocalEdge(int i, int j) {
  const int lo = std::min(i, j), hi = std::max(i, j);
  return lo == 0 ? hi - 1 : lo + hi;  // (0,1)0 (0,2)1 (0,3)2 (1,2)3 (1,3)4 (2,3)5
}

std::array<double, 4> fragmentVolumeFractions(const Eigen::Matrix<double, 3, 4>& X,
                                              const std::array<double, 6>& edge_s,
                                              const std::array<int, 4>& masks, int count) {
  std::array<double, 4> f{1.0, 0.0, 0.0, 0.0};
  if (count <= 1) return f;
  if (count == 2) {
    const int small = popcount4(masks[0]) <= popcount4(masks[1]) ? 0 : 1;
    f[small] = rawFraction(X, edge_s, masks[small]);
    f[1 - small] = 1.0 - f[small];
  } else {
    double singles = 0.0;
    int pair = -1;
    for (int k = 0; k < count; ++k) {
      if (popcount4(masks[k]) == 1) {
        f[k] = rawFraction(X, edge_s, masks[k]);
        singles += f[k];
      } else {
        pair = k;
      }
    }
    if (pair >= 0) f[pair] = 1.0 - singles;
  }
  double sum = 0.0;
  for (int k = 0; k < count; ++k) {
    f[k] = std::max(f[k], kMinFragmentFraction);
    sum += f[k];
  }
  for (int k = 0; k < count; ++k) f[k] /= sum;
  return f;
}

}  // namespace surgical_sim::core
