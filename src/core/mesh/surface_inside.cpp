#include "surgical_sim/core/mesh/surface_inside.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {
namespace {

/// Sign (+1 / -1) of the orientation of q relative to the directed edge a -> b in the xy-plane,
/// with q moved by (e, e^2), e -> 0+: exact ties are broken by the edge's direction. The edge is
/// evaluated from its lexicographically smaller endpoint, so both triangles of an edge see the
/// same value (up to the sign of their traversal). 0 only for a vertical edge (a = b in xy).
int perturbedOrientation(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double qx, double qy) {
  const bool forward = a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  const Eigen::Vector3d& p = forward ? a : b;
  const Eigen::Vector3d& r = forward ? b : a;
  const double dx = r.x() - p.x();
  const double dy = r.y() - p.y();
  const double o = dx * (qy - p.y()) - dy * (qx - p.x());
  int sign = o > 0.0 ? 1 : o < 0.0 ? -1 : 0;
  if (sign == 0) sign = dy != 0.0 ? (dy > 0.0 ? -1 : 1) : (dx > 0.0 ? 1 : dx < 0.0 ? -1 : 0);
  return forward ? sign : -sign;
}

}  // namespace

double enclosedVolume(const TriMesh& surface) {
  double volume = 0.0;
  for (Eigen::Index t = 0; t < surface.triangles.cols(); ++t) {
    const Eigen::Vector3d a = surface.vertices.col(surface.triangles(0, t));
    const Eigen::Vector3d b = surface.vertices.col(surface.triangles(1, t));
    const Eigen::Vector3d c = surface.vertices.col(surface.triangles(2, t));
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

std::vector<std::uint8_t> markInsideLattice(const TriMesh& surface, const Eigen::Vector3d& origin,
                                            double pitch, const Eigen::Vector3i& count) {
  requirePositive("markInsideLattice: pitch", pitch, "m");
  for (int c = 0; c < 3; ++c) {
    requireFinite("markInsideLattice: origin", origin[c], "m");
    if (count[c] < 1) {
      throw std::invalid_argument("markInsideLattice: count = " + std::to_string(count[c]) +
                                  " must be >= 1");
    }
  }
  if (!surface.vertices.allFinite())
    throw std::invalid_argument("markInsideLattice: surface vertices not finite");
  const auto n = static_cast<int>(surface.vertices.cols());
  std::vector<std::vector<double>> crossings(static_cast<std::size_t>(count.x()) * count.y());
  for (Eigen::Index t = 0; t < surface.triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int v = surface.triangles(k, t);
      if (v < 0 || v >= n) {
        throw std::invalid_argument("markInsideLattice: triangles(" + std::to_string(k) + ", " +
                                    std::to_string(t) + ") = " + std::to_string(v) +
                                    " is not a vertex index");
      }
    }
    const Eigen::Vector3d& a = surface.vertices.col(surface.triangles(0, t));
    const Eigen::Vector3d& b = surface.vertices.col(surface.triangles(1, t));
    const Eigen::Vector3d& c = surface.vertices.col(surface.triangles(2, t));
    int first[2];
    int last[2];
    for (int d = 0; d < 2; ++d) {
      const double lo = std::min({a[d], b[d], c[d]});
      const double hi = std::max({a[d], b[d], c[d]});
      first[d] = std::max(0, static_cast<int>(std::ceil((lo - origin[d]) / pitch - 0.5)));
      last[d] =
          std::min(count[d] - 1, static_cast<int>(std::floor((hi - origin[d]) / pitch - 0.5)));
    }
    for (int j = first[1]; j <= last[1]; ++j) {
      const double qy = origin.y() + pitch * (j + 0.5);
      for (int i = first[0]; i <= last[0]; ++i) {
        const double qx = origin.x() + pitch * (i + 0.5);
        const int sa = perturbedOrientation(b, c, qx, qy);
        const int sb = perturbedOrientation(c, a, qx, qy);
        const int sc = perturbedOrientation(a, b, qx, qy);
        if (sa == 0 || sa != sb || sa != sc) continue;
        // Barycentric weights of q from the (unperturbed) sub-triangle areas.
        const auto area = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& r) {
          return std::abs((r.x() - p.x()) * (qy - p.y()) - (r.y() - p.y()) * (qx - p.x()));
        };
        const double wa = area(b, c), wb = area(c, a), wc = area(a, b);
        const double sum = wa + wb + wc;
        const double z = sum > 0.0 ? (wa * a.z() + wb * b.z() + wc * c.z()) / sum
                                   : (a.z() + b.z() + c.z()) / 3.0;
        crossings[static_cast<std::size_t>(i + count.x() * j)].push_back(z);
      }
    }
  }
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(count.prod()), 0);
  const auto plane = static_cast<std::size_t>(count.x()) * count.y();
  for (std::size_t column = 0; column < crossings.size(); ++column) {
    std::vector<double>& z = crossings[column];
    std::sort(z.begin(), z.end());
    for (std::size_t p = 0; p + 1 < z.size(); p += 2) {
      const int k0 = std::max(0, static_cast<int>(std::ceil((z[p] - origin.z()) / pitch - 0.5)));
      const int k1 = std::min(count.z() - 1,
                              static_cast<int>(std::floor((z[p + 1] - origin.z()) / pitch - 0.5)));
      for (int k = k0; k <= k1; ++k) inside[column + plane * static_cast<std::size_t>(k)] = 1;
    }
  }
  return inside;
}

}  // namespace surgical_sim::core
