#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core::test {

/// Test double of TissueModel: nodes joined by springs, with exact energy, force and stiffness.
///   Linear:    E = k/2 |u_i - u_j|^2, u = x - X (linear, translation invariant, K constant)
///   Nonlinear: E = k/2 (|x_i - x_j| - L)^2 (geometrically exact spring)
/// Counts calls so tests can check which evaluations an integrator performs.
class SpringLatticeModel final : public TissueModel {
 public:
  enum class Law { Linear, Nonlinear };
  struct Spring {
    int i, j;
    double stiffness;  ///< [N/m]
  };

  SpringLatticeModel(Eigen::VectorXd rest, std::vector<Spring> springs, double node_mass, Law law)
      : rest_(std::move(rest)), springs_(std::move(springs)), law_(law) {
    mass_ = Eigen::VectorXd::Constant(rest_.size(), node_mass);
    std::vector<Eigen::Triplet<double>> entries;
    const int n = static_cast<int>(rest_.size() / 3);
    auto block = [&](int a, int b) {
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) entries.emplace_back(3 * a + r, 3 * b + c, 0.0);
    };
    for (int a = 0; a < n; ++a) block(a, a);
    for (const Spring& s : springs_) {
      block(s.i, s.j);
      block(s.j, s.i);
    }
    pattern_.resize(rest_.size(), rest_.size());
    pattern_.setFromTriplets(entries.begin(), entries.end());
    pattern_.makeCompressed();
  }

  /// Straight chain of n nodes along x with the given spacing [m].
  static SpringLatticeModel chain(int n, double spacing, double stiffness, double node_mass,
                                  Law law) {
    Eigen::VectorXd rest = Eigen::VectorXd::Zero(3 * n);
    std::vector<Spring> springs;
    for (int a = 0; a < n; ++a) rest[3 * a] = a * spacing;
    for (int a = 0; a + 1 < n; ++a) springs.push_back({a, a + 1, stiffness});
    return SpringLatticeModel(rest, springs, node_mass, law);
  }

  /// nx x ny x nz grid of nodes; springs on cell edges, face diagonals and body diagonals.
  static SpringLatticeModel lattice(int nx, int ny, int nz, double spacing, double stiffness,
                                    double node_mass, Law law) {
    auto id = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
    Eigen::VectorXd rest(3 * nx * ny * nz);
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          rest.segment<3>(3 * id(i, j, k)) = spacing * Eigen::Vector3d(i, j, k);
    std::vector<Spring> springs;
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          for (int dk = 0; dk <= 1; ++dk)
            for (int dj = -1; dj <= 1; ++dj)
              for (int di = -1; di <= 1; ++di) {
                // each unordered neighbour pair once: lexicographically positive offsets
                const bool positive = dk > 0 || (dk == 0 && (dj > 0 || (dj == 0 && di > 0)));
                const int i2 = i + di, j2 = j + dj, k2 = k + dk;
                if (!positive || i2 < 0 || j2 < 0 || i2 >= nx || j2 >= ny || k2 >= nz) continue;
                springs.push_back({id(i, j, k), id(i2, j2, k2), stiffness});
              }
    return SpringLatticeModel(rest, springs, node_mass, law);
  }

  /// The lattice cut like a virtual-node cut: every node in `split` (sorted) gets a copy appended
  /// after the existing nodes (same rest position and mass), and the springs from a split node to
  /// a node on the `far` side (far(rest position of the other node) true) move to the copy.
  template <class Side>
  SpringLatticeModel split(const std::vector<int>& nodes, Side&& far) const {
    Eigen::VectorXd rest(rest_.size() + 3 * static_cast<Eigen::Index>(nodes.size()));
    rest << rest_, Eigen::VectorXd::Zero(3 * static_cast<Eigen::Index>(nodes.size()));
    std::vector<int> copy(rest_.size() / 3, -1);
    for (size_t k = 0; k < nodes.size(); ++k) {
      copy[static_cast<size_t>(nodes[k])] = static_cast<int>(rest_.size() / 3 + k);
      rest.segment<3>(rest_.size() + 3 * static_cast<Eigen::Index>(k)) =
          rest_.segment<3>(3 * nodes[k]);
    }
    std::vector<Spring> springs = springs_;
    for (Spring& s : springs) {
      const int ci = copy[static_cast<size_t>(s.i)], cj = copy[static_cast<size_t>(s.j)];
      if (ci >= 0 && cj < 0 && far(Eigen::Vector3d(rest_.segment<3>(3 * s.j)))) s.i = ci;
      if (cj >= 0 && ci < 0 && far(Eigen::Vector3d(rest_.segment<3>(3 * s.i)))) s.j = cj;
    }
    return SpringLatticeModel(rest, springs, mass_[0], law_);
  }

  std::string name() const override { return "spring_lattice_test_double"; }
  const Eigen::VectorXd& restPositions() const override { return rest_; }
  const Eigen::VectorXd& lumpedMass() const override { return mass_; }
  Eigen::VectorXd bodyForce(const Eigen::Vector3d& a) const override {
    Eigen::VectorXd f(rest_.size());
    for (Eigen::Index i = 0; i < f.size(); i += 3) f.segment<3>(i) = mass_[i] * a;
    return f;
  }

  double energy(const Eigen::VectorXd& x) const override {
    ++energy_calls;
    double e = 0.0;
    for (const Spring& s : springs_) {
      if (law_ == Law::Linear) {
        e += 0.5 * s.stiffness * relativeDisplacement(x, s).squaredNorm();
      } else {
        const double stretch = edge(x, s).norm() - restEdge(s).norm();
        e += 0.5 * s.stiffness * stretch * stretch;
      }
    }
    return e;
  }

  void addInternalForce(const Eigen::VectorXd& x, Eigen::VectorXd& f) const override {
    ++force_calls;
    for (const Spring& s : springs_) {
      Eigen::Vector3d fi;
      if (law_ == Law::Linear) {
        fi = -s.stiffness * relativeDisplacement(x, s);
      } else {
        const Eigen::Vector3d e = edge(x, s);
        const double l = e.norm();
        fi = -s.stiffness * (l - restEdge(s).norm()) * e / l;
      }
      f.segment<3>(3 * s.i) += fi;
      f.segment<3>(3 * s.j) -= fi;
      if (poison_forces) f[3 * s.i] = std::numeric_limits<double>::quiet_NaN();
    }
  }

  const Eigen::SparseMatrix<double>& stiffnessPattern() const override { return pattern_; }

  void assembleStiffness(const Eigen::VectorXd& x, TangentMode mode,
                         Eigen::SparseMatrix<double>& K) const override {
    ++stiffness_calls;
    std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
    for (const Spring& s : springs_) {
      const Eigen::Matrix3d h = springHessian(x, s, mode);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          K.coeffRef(3 * s.i + r, 3 * s.i + c) += h(r, c);
          K.coeffRef(3 * s.j + r, 3 * s.j + c) += h(r, c);
          K.coeffRef(3 * s.i + r, 3 * s.j + c) -= h(r, c);
          K.coeffRef(3 * s.j + r, 3 * s.i + c) -= h(r, c);
        }
    }
  }

  void applyStiffness(const Eigen::VectorXd& x, TangentMode mode, const Eigen::VectorXd& v,
                      Eigen::VectorXd& y) const override {
    ++apply_calls;
    y.setZero(v.size());
    for (const Spring& s : springs_) {
      const Eigen::Vector3d hv =
          springHessian(x, s, mode) * (v.segment<3>(3 * s.i) - v.segment<3>(3 * s.j));
      y.segment<3>(3 * s.i) += hv;
      y.segment<3>(3 * s.j) -= hv;
    }
  }

  /// Spring force on node i, f_i = -dE/dx_i; Hessian block of one spring [N/m].
  Eigen::Matrix3d springHessian(const Eigen::VectorXd& x, const Spring& s, TangentMode mode) const {
    if (law_ == Law::Linear) return s.stiffness * Eigen::Matrix3d::Identity();
    const Eigen::Vector3d e = edge(x, s);
    const double l = e.norm();
    const Eigen::Vector3d d = e / l;
    double transverse = 1.0 - restEdge(s).norm() / l;
    if (mode == TangentMode::ProjectedSpd) transverse = std::max(0.0, transverse);
    const Eigen::Matrix3d ddt = d * d.transpose();
    return s.stiffness * (ddt + transverse * (Eigen::Matrix3d::Identity() - ddt));
  }

  mutable int energy_calls = 0;
  mutable int force_calls = 0;
  mutable int stiffness_calls = 0;
  mutable int apply_calls = 0;
  bool poison_forces = false;  ///< when set, forces contain NaN (non-finite path tests)

 private:
  Eigen::Vector3d edge(const Eigen::VectorXd& x, const Spring& s) const {
    return x.segment<3>(3 * s.i) - x.segment<3>(3 * s.j);
  }
  Eigen::Vector3d restEdge(const Spring& s) const { return edge(rest_, s); }
  Eigen::Vector3d relativeDisplacement(const Eigen::VectorXd& x, const Spring& s) const {
    return edge(x, s) - restEdge(s);
  }

  Eigen::VectorXd rest_;
  Eigen::VectorXd mass_;
  std::vector<Spring> springs_;
  Law law_;
  Eigen::SparseMatrix<double> pattern_;
};

}  // namespace surgical_sim::core::test
