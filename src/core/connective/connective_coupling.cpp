#include "surgical_sim/core/connective/connective_coupling.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "surgical_sim/core/robot/so3.h"

namespace surgical_sim::core {
namespace {

[[noreturn]] void fail(const std::string& message) {
  throw std::invalid_argument("ConnectiveCoupling: " + message);
}

void checkIndex(const std::string& what, int index, int size) {
  if (index < 0 || index >= size) {
    std::ostringstream msg;
    msg << what << " = " << index << " out of range [0, " << size << ")";
    fail(msg.str());
  }
}

/// Value index of entry (row, col) of a compressed column-major matrix that has it.
int valueIndex(const Eigen::SparseMatrix<double>& A, int row, int col) {
  const int* inner = A.innerIndexPtr();
  const int* begin = inner + A.outerIndexPtr()[col];
  const int* end = inner + A.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, row);
  if (it == end || *it != row) fail("internal: missing pattern entry");
  return static_cast<int>(it - inner);
}

}  // namespace

ConnectiveCoupling::ConnectiveCoupling(std::vector<CoupledOrgan> organs,
                                       std::vector<CoupledLayer> layers,
                                       const std::vector<OrganLayerAttachment>& attachments)
    : organs_(std::move(organs)), layers_(std::move(layers)) {
  if (organs_.empty() && layers_.empty()) fail("no organ and no layer");
  // Per body: 1 for a fixed node, after checking the body's model and fixed nodes.
  auto fixedMask = [](const std::string& body, const void* model, int n,
                      const std::vector<int>& fixed, const std::string& node) {
    if (model == nullptr) fail(body + " has no model");
    std::vector<char> mask(n, 0);
    for (const int a : fixed) {
      checkIndex(body + " fixed " + node, a, n);
      mask[a] = 1;
    }
    return mask;
  };
  std::vector<std::vector<char>> organ_fixed, layer_fixed;
  for (int o = 0; o < numOrgans(); ++o) {
    const TissueModel* model = organs_[o].model;
    organ_fixed.push_back(fixedMask("organ " + std::to_string(o), model,
                                    model ? model->numNodes() : 0, organs_[o].fixed_nodes, "node"));
  }
  for (int l = 0; l < numLayers(); ++l) {
    const RigidNodeModel* model = layers_[l].model;
    layer_fixed.push_back(fixedMask("layer " + std::to_string(l), model,
                                    model ? model->numNodes() : 0, layers_[l].fixed_nodes,
                                    "rigid node"));
  }

  // Skinning weights and offsets of the attached nodes.
  links_.resize(organs_.size());
  for (int o = 0; o < numOrgans(); ++o) links_[o].assign(organs_[o].model->numNodes(), Link{});
  for (std::size_t t = 0; t < attachments.size(); ++t) {
    const OrganLayerAttachment& at = attachments[t];
    const std::string name = "attachment " + std::to_string(t);
    checkIndex(name + " organ", at.organ, numOrgans());
    checkIndex(name + " layer", at.layer, numLayers());
    const RigidNodeConfiguration& rest = layers_[at.layer].model->restConfiguration();
    if (at.neighbours < 1 || at.neighbours > rest.numNodes()) {
      std::ostringstream msg;
      msg << name << " neighbours = " << at.neighbours << " out of range [1, " << rest.numNodes()
          << "]";
      fail(msg.str());
    }
    const Eigen::VectorXd& X = organs_[at.organ].model->restPositions();
    std::vector<int> order(rest.numNodes());
    std::vector<double> distance(rest.numNodes());
    for (const int b : at.nodes) {
      checkIndex(name + " node", b, static_cast<int>(links_[at.organ].size()));
      if (organ_fixed[at.organ][b] != 0) fail(name + " node " + std::to_string(b) + " is fixed");
      if (links_[at.organ][b].count > 0)
        fail(name + " node " + std::to_string(b) + " is attached twice");
      const Eigen::Vector3d p = X.segment<3>(3 * b);
      for (int j = 0; j < rest.numNodes(); ++j) distance[j] = (rest.p_TN[j] - p).norm();
      std::iota(order.begin(), order.end(), 0);
      std::partial_sort(order.begin(), order.begin() + at.neighbours, order.end(),
                        [&](int i, int j) { return distance[i] < distance[j]; });
      const double largest = distance[order[at.neighbours - 1]];
      const bool on_node = distance[order[0]] <= 1e-9 * largest || largest == 0.0;
      const int count = on_node ? 1 : at.neighbours;
      double sum = 0.0;
      for (int k = 0; k < count; ++k) sum += on_node ? 1.0 : 1.0 / std::pow(distance[order[k]], 2);
      links_[at.organ][b] = Link{at.layer, static_cast<int>(skins_.size()), count};
      for (int k = 0; k < count; ++k) {
        const int j = order[k];
        Skin skin;
        skin.layer_node = j;
        skin.weight = (on_node ? 1.0 : 1.0 / std::pow(distance[j], 2)) / sum;
        skin.offset = rest.q_TN[j].conjugate() * (p - rest.p_TN[j]);
        skins_.push_back(skin);
      }
    }
  }
  rotated_.resize(skins_.size());
  jacobian_.resize(skins_.size());

  // Unknowns: free organ nodes, then free rigid nodes.
  organ_column_.resize(organs_.size());
  for (int o = 0; o < numOrgans(); ++o) {
    organ_column_[o].assign(links_[o].size(), -1);
    for (std::size_t a = 0; a < links_[o].size(); ++a) {
      if (organ_fixed[o][a] != 0 || links_[o][a].count > 0) continue;
      organ_column_[o][a] = num_unknowns_;
      num_unknowns_ += 3;
    }
  }
  const int organ_unknowns = num_unknowns_;
  layer_column_.resize(layers_.size());
  for (int l = 0; l < numLayers(); ++l) {
    layer_column_[l].assign(layers_[l].model->numNodes(), -1);
    for (int j = 0; j < layers_[l].model->numNodes(); ++j) {
      if (layer_fixed[l][j] != 0) continue;
      layer_column_[l][j] = num_unknowns_;
      num_unknowns_ += kRigidNodeDofs;
    }
  }
  for (int o = 0; o < numOrgans(); ++o)
    for (const Link& link : links_[o])
      for (int k = link.begin; k < link.begin + link.count; ++k)
        skins_[k].column = layer_column_[link.layer][skins_[k].layer_node];

  // Targets of every organ node: the unknowns its increment depends on.
  targets_.resize(organs_.size());
  target_begin_.resize(organs_.size());
  for (int o = 0; o < numOrgans(); ++o) {
    const int n = static_cast<int>(links_[o].size());
    target_begin_[o].assign(n + 1, 0);
    for (int a = 0; a < n; ++a) {
      target_begin_[o][a] = static_cast<int>(targets_[o].size());
      if (organ_column_[o][a] >= 0) targets_[o].push_back(Target{organ_column_[o][a], -1});
      const Link& link = links_[o][a];
      for (int k = link.begin; k < link.begin + link.count; ++k)
        if (skins_[k].column >= 0) targets_[o].push_back(Target{skins_[k].column, k});
    }
    target_begin_[o][n] = static_cast<int>(targets_[o].size());
  }
  auto width = [](const Target& t) { return t.skin < 0 ? 3 : kRigidNodeDofs; };

  // Organ 3 x 3 node blocks.
  blocks_.resize(organs_.size());
  diagonal_block_.resize(organs_.size());
  for (int o = 0; o < numOrgans(); ++o) {
    const Eigen::SparseMatrix<double>& K = organs_[o].model->stiffnessPattern();
    const int n = organs_[o].model->numNodes();
    if (K.rows() != 3 * n || K.cols() != 3 * n || !K.isCompressed())
      fail("organ " + std::to_string(o) + " stiffness pattern is not compressed 3n x 3n");
    diagonal_block_[o].assign(n, -1);
    for (int b = 0; b < n; ++b) {
      for (int e = K.outerIndexPtr()[3 * b]; e < K.outerIndexPtr()[3 * b + 1]; e += 3) {
        const int row = K.innerIndexPtr()[e];
        OrganBlock block;
        block.a = row / 3;
        block.b = b;
        bool full = row % 3 == 0 && e + 2 < K.outerIndexPtr()[3 * b + 1] &&
                    K.innerIndexPtr()[e + 2] == row + 2;
        for (int c = 0; c < 3 && full; ++c) {
          const int* inner = K.innerIndexPtr();
          const int* begin = inner + K.outerIndexPtr()[3 * b + c];
          const int* end = inner + K.outerIndexPtr()[3 * b + c + 1];
          const int* it = std::lower_bound(begin, end, row);
          full = end - it >= 3 && it[0] == row && it[2] == row + 2;
          block.value[c] = static_cast<int>(it - inner);
        }
        if (!full)
          fail("organ " + std::to_string(o) + " stiffness pattern lacks full 3 x 3 node blocks");
        if (block.a == b) diagonal_block_[o][b] = static_cast<int>(blocks_[o].size());
        blocks_[o].push_back(block);
      }
      if (diagonal_block_[o][b] < 0)
        fail("organ " + std::to_string(o) + " stiffness pattern lacks node " + std::to_string(b) +
             "'s diagonal block");
    }
  }

  // Global pattern: every target pair of every organ block, and every free layer block.
  std::vector<Eigen::Triplet<double>> entries;
  for (int o = 0; o < numOrgans(); ++o) {
    for (const OrganBlock& block : blocks_[o]) {
      for (int ta = target_begin_[o][block.a]; ta < target_begin_[o][block.a + 1]; ++ta) {
        for (int tb = target_begin_[o][block.b]; tb < target_begin_[o][block.b + 1]; ++tb) {
          const Target& A = targets_[o][ta];
          const Target& B = targets_[o][tb];
          for (int c = 0; c < width(B); ++c)
            for (int r = 0; r < width(A); ++r)
              entries.emplace_back(A.column + r, B.column + c, 0.0);
        }
      }
    }
  }
  // Calls visit(value index, global row, global column) for every layer entry between free
  // rigid nodes.
  auto forEachLayerEntry = [&](int l, const auto& visit) {
    const Eigen::SparseMatrix<double>& K = layers_[l].model->stiffnessPattern();
    for (int c = 0; c < K.cols(); ++c) {
      for (int e = K.outerIndexPtr()[c]; e < K.outerIndexPtr()[c + 1]; ++e) {
        const int r = K.innerIndexPtr()[e];
        const int rc = layer_column_[l][r / kRigidNodeDofs];
        const int cc = layer_column_[l][c / kRigidNodeDofs];
        if (rc >= 0 && cc >= 0) visit(e, rc + r % kRigidNodeDofs, cc + c % kRigidNodeDofs);
      }
    }
  };
  for (int l = 0; l < numLayers(); ++l)
    forEachLayerEntry(l, [&](int, int r, int c) { entries.emplace_back(r, c, 0.0); });
  stiffness_.resize(num_unknowns_, num_unknowns_);
  stiffness_.setFromTriplets(entries.begin(), entries.end());
  stiffness_.makeCompressed();
  mass_ = stiffness_;
  force_.setZero(num_unknowns_);

  for (int o = 0; o < numOrgans(); ++o) {
    for (OrganBlock& block : blocks_[o]) {
      block.dst = static_cast<int>(dst_.size());
      for (int ta = target_begin_[o][block.a]; ta < target_begin_[o][block.a + 1]; ++ta) {
        for (int tb = target_begin_[o][block.b]; tb < target_begin_[o][block.b + 1]; ++tb) {
          const Target& B = targets_[o][tb];
          for (int c = 0; c < width(B); ++c)
            dst_.push_back(valueIndex(stiffness_, targets_[o][ta].column, B.column + c));
        }
      }
    }
  }
  layer_value_.resize(layers_.size());
  for (int l = 0; l < numLayers(); ++l) {
    layer_value_[l].assign(layers_[l].model->stiffnessPattern().nonZeros(), -1);
    forEachLayerEntry(
        l, [&](int e, int r, int c) { layer_value_[l][e] = valueIndex(stiffness_, r, c); });
  }
  for (int column = organ_unknowns; column < num_unknowns_; column += kRigidNodeDofs) {
    std::array<int, 3> block{};
    for (int c = 0; c < 3; ++c) {
      block[c] = valueIndex(stiffness_, column + 3, column + 3 + c);
      rotation_diagonal_.push_back(block[c] + c);
    }
    rotation_block_.push_back(block);
  }
  organ_unknowns_ = organ_unknowns;

  organ_force_.resize(organs_.size());
  organ_stiffness_.resize(organs_.size());
  body_gravity_.assign(organs_.size(), Eigen::Vector3d::Constant(std::nan("")));
  body_force_.resize(organs_.size());
  for (int o = 0; o < numOrgans(); ++o) organ_stiffness_[o] = organs_[o].model->stiffnessPattern();
  layer_force_.resize(layers_.size());
  layer_stiffness_.resize(layers_.size());
  layer_mass_.resize(layers_.size());
  increment_.resize(layers_.size());
  work_.resize(organs_.size() + layers_.size());
  for (int l = 0; l < numLayers(); ++l) {
    layer_stiffness_[l] = layers_[l].model->stiffnessPattern();
    layer_mass_[l] = layer_stiffness_[l];
  }
}

CoupledState ConnectiveCoupling::restState() const {
  CoupledState state;
  for (const CoupledOrgan& organ : organs_) {
    state.organ_positions.push_back(organ.model->restPositions());
    state.organ_velocities.push_back(Eigen::VectorXd::Zero(organ.model->restPositions().size()));
  }
  for (const CoupledLayer& layer : layers_) {
    state.layer_configurations.push_back(layer.model->restConfiguration());
    state.layer_velocities.push_back(Eigen::VectorXd::Zero(layer.model->numDofs()));
  }
  applyMapping(state);
  return state;
}

void ConnectiveCoupling::checkState(const CoupledState& state) const {
  bool ok = static_cast<int>(state.organ_positions.size()) == numOrgans() &&
            static_cast<int>(state.organ_velocities.size()) == numOrgans() &&
            static_cast<int>(state.layer_configurations.size()) == numLayers() &&
            static_cast<int>(state.layer_velocities.size()) == numLayers();
  for (int o = 0; ok && o < numOrgans(); ++o) {
    const Eigen::Index n = organs_[o].model->restPositions().size();
    ok = state.organ_positions[o].size() == n && state.organ_velocities[o].size() == n;
  }
  for (int l = 0; ok && l < numLayers(); ++l)
    ok = state.layer_configurations[l].numNodes() == layers_[l].model->numNodes() &&
         static_cast<int>(state.layer_configurations[l].q_TN.size()) ==
             layers_[l].model->numNodes() &&
         state.layer_velocities[l].size() == layers_[l].model->numDofs();
  if (!ok) fail("state does not match the bodies (use restState())");
}

void ConnectiveCoupling::checkLoads(const CoupledLoads& loads) const {
  if (!loads.gravity.allFinite()) fail("loads.gravity is not finite");
  for (const CoupledPointForce& f : loads.forces) {
    checkIndex("loads.forces organ", f.organ, numOrgans());
    checkIndex("loads.forces node", f.node, organs_[f.organ].model->numNodes());
    if (!f.force.allFinite()) fail("loads.forces force is not finite");
  }
  for (const CoupledSpring& s : loads.springs) {
    checkIndex("loads.springs organ", s.organ, numOrgans());
    checkIndex("loads.springs node", s.node, organs_[s.organ].model->numNodes());
    if (!s.target.allFinite()) fail("loads.springs target is not finite");
    if (!std::isfinite(s.stiffness) || s.stiffness < 0.0) {
      std::ostringstream msg;
      msg << "loads.springs stiffness = " << s.stiffness << " N/m must be finite and >= 0";
      fail(msg.str());
    }
  }
}

void ConnectiveCoupling::applyMapping(CoupledState& state) const {
  checkState(state);
  for (int l = 0; l < numLayers(); ++l)
    for (int j = 0; j < layers_[l].model->numNodes(); ++j)
      if (layer_column_[l][j] < 0)
        state.layer_velocities[l].segment<6>(kRigidNodeDofs * j).setZero();
  for (int o = 0; o < numOrgans(); ++o) {
    for (std::size_t a = 0; a < links_[o].size(); ++a) {
      const Link& link = links_[o][a];
      if (link.count == 0) {
        if (organ_column_[o][a] < 0) state.organ_velocities[o].segment<3>(3 * a).setZero();
        continue;
      }
      const RigidNodeConfiguration& q = state.layer_configurations[link.layer];
      const Eigen::VectorXd& v = state.layer_velocities[link.layer];
      Eigen::Vector3d x = Eigen::Vector3d::Zero(), xdot = Eigen::Vector3d::Zero();
      for (int k = link.begin; k < link.begin + link.count; ++k) {
        const Skin& skin = skins_[k];
        const Eigen::Vector3d r = q.q_TN[skin.layer_node] * skin.offset;
        const Eigen::Matrix<double, 6, 1> vj = v.segment<6>(kRigidNodeDofs * skin.layer_node);
        x += skin.weight * (q.p_TN[skin.layer_node] + r);
        xdot += skin.weight * (vj.head<3>() + vj.tail<3>().cross(r));
      }
      state.organ_positions[o].segment<3>(3 * a) = x;
      state.organ_velocities[o].segment<3>(3 * a) = xdot;
    }
  }
}

double ConnectiveCoupling::potentialEnergy(const CoupledState& state,
                                           const CoupledLoads& loads) const {
  checkState(state);
  checkLoads(loads);
  double energy = 0.0;
  for (int o = 0; o < numOrgans(); ++o) {
    const Eigen::VectorXd& x = state.organ_positions[o];
    energy += organs_[o].model->energy(x) - organs_[o].model->bodyForce(loads.gravity).dot(x);
  }
  for (const CoupledPointForce& f : loads.forces)
    energy -= f.force.dot(state.organ_positions[f.organ].segment<3>(3 * f.node));
  for (const CoupledSpring& s : loads.springs)
    energy += 0.5 * s.stiffness *
              (state.organ_positions[s.organ].segment<3>(3 * s.node) - s.target).squaredNorm();
  for (int l = 0; l < numLayers(); ++l) {
    const RigidNodeConfiguration& q = state.layer_configurations[l];
    energy += layers_[l].model->energy(q) + layers_[l].model->bodyForcePotential(q, loads.gravity);
  }
  return energy;
}

void ConnectiveCoupling::rotateOffsets(const CoupledState& state) {
  for (int o = 0; o < numOrgans(); ++o)
    for (const Link& link : links_[o])
      for (int k = link.begin; k < link.begin + link.count; ++k) {
        const Skin& skin = skins_[k];
        rotated_[k] = state.layer_configurations[link.layer].q_TN[skin.layer_node] * skin.offset;
        jacobian_[k].leftCols<3>() = skin.weight * Eigen::Matrix3d::Identity();
        jacobian_[k].rightCols<3>() = -skin.weight * skew(rotated_[k]);
      }
}

void ConnectiveCoupling::evaluateOrgan(int o, const CoupledState& state, const CoupledLoads& loads,
                                       TangentMode mode) {
  const TissueModel& model = *organs_[o].model;
  if (body_gravity_[o] != loads.gravity) {
    body_force_[o] = model.bodyForce(loads.gravity);
    body_gravity_[o] = loads.gravity;
  }
  const Eigen::VectorXd& x = state.organ_positions[o];
  Eigen::VectorXd& f = organ_force_[o];
  f = body_force_[o];
  for (const CoupledPointForce& p : loads.forces)
    if (p.organ == o) f.segment<3>(3 * p.node) += p.force;
  for (const CoupledSpring& s : loads.springs)
    if (s.organ == o)
      f.segment<3>(3 * s.node) += s.stiffness * (s.target - x.segment<3>(3 * s.node));
  applied_squared_ += f.squaredNorm();
  Eigen::VectorXd& internal = work_[o];
  internal.setZero(x.size());
  Eigen::SparseMatrix<double>& K = organ_stiffness_[o];
  model.addInternalForceAndStiffness(x, mode, internal, K);
  internal_squared_ += internal.squaredNorm();
  f += internal;
  for (const CoupledSpring& s : loads.springs) {
    if (s.organ != o) continue;
    const OrganBlock& block = blocks_[o][diagonal_block_[o][s.node]];
    for (int c = 0; c < 3; ++c) K.valuePtr()[block.value[c] + c] += s.stiffness;
  }
}

void ConnectiveCoupling::scatterOrganBlock(int o, const OrganBlock& block, const Eigen::Matrix3d& X,
                                           double* values) const {
  const int* dst = dst_.data() + block.dst;
  for (int ta = target_begin_[o][block.a]; ta < target_begin_[o][block.a + 1]; ++ta) {
    const Target& A = targets_[o][ta];
    for (int tb = target_begin_[o][block.b]; tb < target_begin_[o][block.b + 1]; ++tb) {
      const Target& B = targets_[o][tb];
      if (A.skin < 0 && B.skin < 0) {
        for (int c = 0; c < 3; ++c) {
          double* column = values + *dst++;
          for (int r = 0; r < 3; ++r) column[r] += X(r, c);
        }
        continue;
      }
      // J^T X J with J = w [I, -[r]x] of a skin (cached per step) or I of a free node.
      Matrix6d G;
      if (A.skin < 0) {
        G.topRows<3>().noalias() = X * jacobian_[B.skin];
      } else if (B.skin < 0) {
        G.leftCols<3>().noalias() = jacobian_[A.skin].transpose() * X;
      } else {
        const Eigen::Matrix<double, 3, 6> XJ = X * jacobian_[B.skin];
        G.noalias() = jacobian_[A.skin].transpose() * XJ;
      }
      const int rows = A.skin < 0 ? 3 : kRigidNodeDofs;
      const int cols = B.skin < 0 ? 3 : kRigidNodeDofs;
      for (int c = 0; c < cols; ++c) {
        double* column = values + *dst++;
        for (int r = 0; r < rows; ++r) column[r] += G(r, c);
      }
    }
  }
}

void ConnectiveCoupling::assemble(const CoupledState& state, const CoupledLoads& loads,
                                  const CouplingTangentOptions& options, bool with_mass) {
  checkState(state);
  checkLoads(loads);
  rotateOffsets(state);
  force_.setZero();
  stiffness_.coeffs().setZero();
  if (with_mass) mass_.coeffs().setZero();
  internal_squared_ = 0.0;
  applied_squared_ = 0.0;
  double* K = stiffness_.valuePtr();
  for (int o = 0; o < numOrgans(); ++o) {
    evaluateOrgan(o, state, loads, options.organ_mode);
    const Eigen::VectorXd& f = organ_force_[o];
    const double* values = organ_stiffness_[o].valuePtr();
    for (const OrganBlock& block : blocks_[o]) {
      Eigen::Matrix3d X;
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) X(r, c) = values[block.value[c] + r];
      scatterOrganBlock(o, block, X, K);
    }
    const Eigen::VectorXd& lumped = organs_[o].model->lumpedMass();
    for (std::size_t a = 0; a < links_[o].size(); ++a) {
      if (with_mass)
        scatterOrganBlock(o, blocks_[o][diagonal_block_[o][a]],
                          lumped[3 * a] * Eigen::Matrix3d::Identity(), mass_.valuePtr());
      const Eigen::Vector3d fa = f.segment<3>(3 * a);
      if (organ_column_[o][a] >= 0) force_.segment<3>(organ_column_[o][a]) += fa;
      const Link& link = links_[o][a];
      for (int k = link.begin; k < link.begin + link.count; ++k) {
        const Skin& skin = skins_[k];
        if (skin.column < 0) continue;
        force_.segment<3>(skin.column) += skin.weight * fa;
        force_.segment<3>(skin.column + 3) += skin.weight * rotated_[k].cross(fa);
        if (!options.geometric) continue;
        // K_map = -w [f]x [r]x on the rotation block (P depends on R_j).
        Eigen::Matrix3d G = -skin.weight * skew(fa) * skew(rotated_[k]);
        if (options.symmetrize) G = 0.5 * (G + G.transpose()).eval();
        const std::array<int, 3>& block = rotation_block_[(skin.column - organ_unknowns_) / 6];
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r) K[block[c] + r] += G(r, c);
      }
    }
  }
  RigidNodeTangentOptions layer_options;
  layer_options.symmetrize = options.symmetrize;
  layer_options.geometric = options.geometric;
  for (int l = 0; l < numLayers(); ++l) {
    const RigidNodeModel& model = *layers_[l].model;
    const RigidNodeConfiguration& q = state.layer_configurations[l];
    Eigen::VectorXd& f = layer_force_[l];
    f.setZero(model.numDofs());
    model.addBodyForce(q, loads.gravity, f);
    applied_squared_ += f.squaredNorm();
    Eigen::VectorXd& internal = work_[numOrgans() + l];
    internal.setZero(model.numDofs());
    model.addInternalForceAndStiffness(q, layer_options, internal, layer_stiffness_[l]);
    internal_squared_ += internal.squaredNorm();
    f += internal;
    if (options.geometric)
      model.addBodyForceStiffness(q, loads.gravity, options.symmetrize, layer_stiffness_[l]);
    if (with_mass) model.assembleNodeMass(q, layer_mass_[l]);
    const std::vector<int>& dst = layer_value_[l];
    const double* Kl = layer_stiffness_[l].valuePtr();
    const double* Ml = layer_mass_[l].valuePtr();
    for (std::size_t e = 0; e < dst.size(); ++e) {
      if (dst[e] < 0) continue;
      K[dst[e]] += Kl[e];
      if (with_mass) mass_.valuePtr()[dst[e]] += Ml[e];
    }
    for (int j = 0; j < model.numNodes(); ++j)
      if (layer_column_[l][j] >= 0)
        force_.segment<6>(layer_column_[l][j]) += f.segment<6>(kRigidNodeDofs * j);
  }
  force_scale_ = std::sqrt(internal_squared_) + std::sqrt(applied_squared_);
}

void ConnectiveCoupling::gatherVelocity(const CoupledState& state, Eigen::VectorXd& u) const {
  checkState(state);
  u.resize(num_unknowns_);
  for (int o = 0; o < numOrgans(); ++o)
    for (std::size_t a = 0; a < organ_column_[o].size(); ++a)
      if (organ_column_[o][a] >= 0)
        u.segment<3>(organ_column_[o][a]) = state.organ_velocities[o].segment<3>(3 * a);
  for (int l = 0; l < numLayers(); ++l)
    for (std::size_t j = 0; j < layer_column_[l].size(); ++j)
      if (layer_column_[l][j] >= 0)
        u.segment<6>(layer_column_[l][j]) =
            state.layer_velocities[l].segment<6>(kRigidNodeDofs * j);
}

void ConnectiveCoupling::scatterVelocity(const Eigen::VectorXd& u, CoupledState& state) const {
  checkState(state);
  if (u.size() != num_unknowns_) fail("velocity of the wrong size");
  for (int o = 0; o < numOrgans(); ++o)
    for (std::size_t a = 0; a < organ_column_[o].size(); ++a)
      if (organ_column_[o][a] >= 0)
        state.organ_velocities[o].segment<3>(3 * a) = u.segment<3>(organ_column_[o][a]);
  for (int l = 0; l < numLayers(); ++l)
    for (std::size_t j = 0; j < layer_column_[l].size(); ++j)
      if (layer_column_[l][j] >= 0)
        state.layer_velocities[l].segment<6>(kRigidNodeDofs * j) =
            u.segment<6>(layer_column_[l][j]);
  applyMapping(state);
}

void ConnectiveCoupling::applyIncrement(const Eigen::VectorXd& du, double scale,
                                        CoupledState& state) const {
  checkState(state);
  if (du.size() != num_unknowns_) fail("increment of the wrong size");
  for (int o = 0; o < numOrgans(); ++o)
    for (std::size_t a = 0; a < organ_column_[o].size(); ++a)
      if (organ_column_[o][a] >= 0)
        state.organ_positions[o].segment<3>(3 * a) += scale * du.segment<3>(organ_column_[o][a]);
  for (int l = 0; l < numLayers(); ++l) {
    Eigen::VectorXd& dq = increment_[l];
    dq.setZero(layers_[l].model->numDofs());
    for (std::size_t j = 0; j < layer_column_[l].size(); ++j)
      if (layer_column_[l][j] >= 0)
        dq.segment<6>(kRigidNodeDofs * j) = du.segment<6>(layer_column_[l][j]);
    applyRigidNodeIncrement(dq, scale, state.layer_configurations[l]);
  }
  applyMapping(state);
}

}  // namespace surgical_sim::core
