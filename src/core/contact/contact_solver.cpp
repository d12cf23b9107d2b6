#include "surgical_sim/core/contact/contact_solver.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "surgical_sim/core/common/validate.h"

namespace surgical_sim::core {
namespace {

/// Relative diagonal regularization of W_AA before its factorization (redundant contacts, e.g.
/// several triangles around one tip, make W_AA singular) [-].
constexpr double kDelassusRegularization = 1e-10;
/// Active-set changes allowed per contact in the LCP refinement [-].
constexpr int kPivotsPerContact = 4;

int checkedMaxContacts(int max_contacts) {
  requireInRange("contact.max_contacts", max_contacts, 1, 4096, "");
  return max_contacts;
}

const std::vector<ToolCoupling>& checkedCouplings(const std::vector<ToolCoupling>& tools) {
  if (tools.empty()) {
    throw std::invalid_argument("contact.tools: the contact solver needs at least one tool");
  }
  for (const ToolCoupling& tool : tools) validateToolCoupling(tool);
  return tools;
}

}  // namespace

void validateContactSolverSettings(const ContactSolverSettings& settings) {
  requireInRange("contact.solver.max_iterations", settings.max_iterations, 1, 100000, "");
  requirePositive("contact.solver.relative_tolerance", settings.relative_tolerance, "");
  requireInHalfOpenRange("contact.solver.relative_tolerance", settings.relative_tolerance, 0.0, 1.0,
                         "");
}

void validateToolCoupling(const ToolCoupling& coupling) {
  requirePositive("tool.coupling_stiffness", coupling.stiffness, "N/m");
  requirePositive("tool.max_force", coupling.max_force, "N");
  requireNonNegative("tool.coupling_damping", coupling.damping, "N s/m");
}

ContactSolver::ContactSolver(const ContactSolverSettings& settings, int max_contacts,
                             const std::vector<ToolCoupling>& tools)
    : settings_(settings),
      max_contacts_(checkedMaxContacts(max_contacts)),
      couplings_(checkedCouplings(tools)),
      force_scale_(tools.size(), 1.0),
      compliance_(tools.size(), 0.0),
      body_offset_(tools.size(), Eigen::Vector3d::Zero()),
      active_set_(max_contacts_) {
  validateContactSolverSettings(settings);
  W_.setZero(max_contacts, max_contacts);
  factor_.setZero(max_contacts, max_contacts);
  normals_.setZero(max_contacts, 3);
  q_.setZero(max_contacts);
  lambda_.setZero(max_contacts);
  active_.reserve(static_cast<size_t>(max_contacts));
  column_slot_.reserve(static_cast<size_t>(max_contacts));
  previous_slot_.reserve(static_cast<size_t>(max_contacts));
  column_keys_.assign(static_cast<size_t>(max_contacts), Eigen::Vector4i::Constant(-1));
  previous_keys_.assign(static_cast<size_t>(max_contacts), Eigen::Vector4i::Constant(-1));
  tools_.assign(static_cast<size_t>(max_contacts), 0);
  contact_normals_.setZero(3, max_contacts);
  dn_du_.assign(static_cast<size_t>(max_contacts), Eigen::Matrix3d::Zero());
  dn_dx_.assign(static_cast<size_t>(max_contacts), Eigen::Matrix<double, 3, 9>::Zero());
  solved_.setZero(max_contacts, 3);
}

void ContactSolver::resize(Eigen::Index size) {
  for (Eigen::VectorXd* v : {&tissue_force_, &column_, &response_, &carried_, &correction_}) {
    v->setZero(size);
  }
}

void ContactSolver::keepColumnsAsStarts() {
  if (columns_used_ == 0) return;
  std::swap(columns_, previous_columns_);
  previous_slot_.assign(column_slot_.begin(), column_slot_.end());
  std::copy(column_keys_.begin(),
            column_keys_.begin() + static_cast<std::ptrdiff_t>(column_slot_.size()),
            previous_keys_.begin());
  columns_used_ = 0;
}

double ContactSolver::rowDot(const SurfaceMapping& mapping, const ContactPoint& contact,
                             const Eigen::VectorXd& v) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    sum += contact.weights[k] * contact.n_S.dot(mapping.vertexValue(contact.nodes[k], v));
  }
  return sum;
}

void ContactSolver::addColumn(const SurfaceMapping& mapping, const ContactPoint& contact,
                              double scale, Eigen::VectorXd& v) {
  for (int k = 0; k < 3; ++k) {
    mapping.addVertexForce(contact.nodes[k], (scale * contact.weights[k]) * contact.n_S, v);
  }
}

StepStatus ContactSolver::solve(Integrator& integrator, const SurfaceMapping& mapping,
                                const std::vector<ContactPoint>& contacts,
                                const Eigen::VectorXd& applied_force, double dt,
                                bool update_velocity, SimulationState& state) {
  updateCompliances(dt);
  const StepStatus status =
      solveContacts(integrator, mapping, contacts, applied_force, dt, update_velocity, state);
  updateBodyOffsets(dt);
  return status;
}

void ContactSolver::updateCompliances(double dt) {
  for (size_t t = 0; t < couplings_.size(); ++t)
    compliance_[t] = 1.0 / (couplings_[t].stiffness + couplings_[t].damping / dt);
}

void ContactSolver::updateBodyOffsets(double dt) {
  for (size_t t = 0; t < couplings_.size(); ++t) {
    Eigen::Vector3d push = (couplings_[t].damping / dt) * body_offset_[t];
    for (Eigen::Index i = 0; i < count_; ++i)
      if (tools_[static_cast<size_t>(i)] == static_cast<int>(t))
        push -= lambda_[i] * contact_normals_.col(i);
    body_offset_[t] = compliance_[t] * push;
  }
}

const Eigen::Vector3d& ContactSolver::bodyOffset(int tool) const {
  return body_offset_[static_cast<size_t>(
      std::clamp(tool, 0, static_cast<int>(couplings_.size()) - 1))];
}

StepStatus ContactSolver::solveContacts(Integrator& integrator, const SurfaceMapping& mapping,
                                        const std::vector<ContactPoint>& contacts,
                                        const Eigen::VectorXd& applied_force, double dt,
                                        bool update_velocity, SimulationState& state) {
  const Eigen::Index size = state.x.size();
  if (tissue_force_.size() != size) resize(size);
  count_ = 0;
  tissue_force_.setZero();
  std::fill(force_scale_.begin(), force_scale_.end(), 1.0);
  if (contacts.size() > static_cast<size_t>(max_contacts_) || applied_force.size() != size ||
      3 * mapping.numNodes() != size) {
    return StepStatus::SolverFailed;
  }
  for (const ContactPoint& contact : contacts) {
    if (contact.tool < 0 || static_cast<size_t>(contact.tool) >= couplings_.size() ||
        contact.nodes.minCoeff() < 0 || contact.nodes.maxCoeff() >= mapping.numSlots()) {
      return StepStatus::SolverFailed;
    }
  }
  const bool carried = applied_force.squaredNorm() > 0.0;
  if (contacts.empty() && !carried) return StepStatus::Ok;
  // carried_ holds the last S F_a: the start of this one (the same force on a steady press).
  if (carried) {
    if (!integrator.applyStepCompliance(applied_force, carried_)) return StepStatus::SolverFailed;
  } else {
    carried_.setZero();
  }
  keepColumnsAsStarts();

  const auto m = static_cast<Eigen::Index>(contacts.size());
  double q_scale = 0.0;
  for (Eigen::Index i = 0; i < m; ++i) {
    const ContactPoint& contact = contacts[static_cast<size_t>(i)];
    const auto tool = static_cast<size_t>(contact.tool);
    // The damper's memory: the body lags at its previous offset d_t,prev (step 2 above).
    q_[i] =
        contact.gap - rowDot(mapping, contact, carried_) -
        compliance_[tool] * (couplings_[tool].damping / dt) * contact.n_S.dot(body_offset_[tool]);
    q_scale = std::max(q_scale, std::abs(q_[i]));
    tools_[static_cast<size_t>(i)] = contact.tool;
    column_keys_[static_cast<size_t>(i)] << contact.tool, contact.nodes;
    contact_normals_.col(i) = contact.n_S;
    dn_du_[static_cast<size_t>(i)] = contact.dn_du;
    dn_dx_[static_cast<size_t>(i)] = contact.dn_dx;
  }
  if (coupling_.size() < static_cast<size_t>(m * m)) coupling_.resize(static_cast<size_t>(m * m));
  column_slot_.assign(static_cast<size_t>(m), -1);
  column_failed_ = false;
  // W starts as the tool-body coupling C: contacts of one tool share its displacement
  // -c_t sum lambda_j n_j. computeColumn adds the columns of H S H^T.
  auto W = W_.topLeftCorner(m, m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const int tool = tools_[static_cast<size_t>(j)];
    const double compliance = compliance_[static_cast<size_t>(tool)];
    for (Eigen::Index i = 0; i < m; ++i) {
      W(i, j) = tools_[static_cast<size_t>(i)] == tool
                    ? compliance * contact_normals_.col(i).dot(contact_normals_.col(j))
                    : 0.0;
    }
  }
  count_ = m;

  auto lambda = lambda_.head(m);
  lambda.setZero();
  const double tolerance = settings_.relative_tolerance * q_scale;
  const int max_pivots = kPivotsPerContact * static_cast<int>(m);
  // Two captured pointers: std::function keeps them without allocating.
  const ColumnInputs inputs{&integrator, &mapping, &contacts};
  const LcpColumnSource source = [this, &inputs](Eigen::Index j) {
    return computeColumn(inputs, j);
  };
  report_ = PgsReport();
  if (!settings_.full_delassus) {
    // Only the columns the active set needs, from the penetrating contacts on.
    for (Eigen::Index i = 0; i < m; ++i) lambda[i] = q_[i] < 0.0 ? 1.0 : 0.0;
    report_ = refineLcpActiveSet(W, q_.head(m), tolerance, max_pivots, lambda, active_set_, source);
    if (!report_.converged) lambda.setZero();
  }
  if (!report_.converged) {
    for (Eigen::Index j = 0; j < m && !column_failed_; ++j) source(j);
    if (!column_failed_) {
      report_ =
          solveLcpProjectedGaussSeidel(W, q_.head(m), settings_.max_iterations, tolerance, lambda);
      const PgsReport refined =
          refineLcpActiveSet(W, q_.head(m), tolerance, max_pivots, lambda, active_set_);
      if (refined.converged) report_ = refined;
    }
  }
  if (column_failed_ || !lambda.allFinite()) {
    count_ = 0;
    return StepStatus::SolverFailed;
  }
  const bool capped = capToolForces();
  for (Eigen::Index i = 0; i < m; ++i) {
    addColumn(mapping, contacts[static_cast<size_t>(i)], lambda[i], tissue_force_);
  }
  if (!correct(integrator, applied_force, dt, update_velocity, state)) {
    tissue_force_.setZero();
    count_ = 0;
    return StepStatus::SolverFailed;
  }
  if (capped) return StepStatus::ContactLimited;
  return report_.converged || m == 0 ? StepStatus::Ok : StepStatus::NotConverged;
}

bool ContactSolver::computeColumn(const ColumnInputs& inputs, Eigen::Index j) {
  const SurfaceMapping& mapping = *inputs.mapping;
  const std::vector<ContactPoint>& contacts = *inputs.contacts;
  if (column_failed_) return false;
  if (column_slot_[static_cast<size_t>(j)] >= 0) return true;
  const auto slot = static_cast<size_t>(columns_used_);
  if (columns_.size() <= slot) columns_.emplace_back();
  Eigen::VectorXd& response = columns_[slot];
  const ContactPoint& contact = contacts[static_cast<size_t>(j)];
  response.setZero(column_.size());
  for (size_t i = 0; i < previous_slot_.size(); ++i) {
    if (previous_slot_[i] >= 0 && previous_keys_[i] == column_keys_[static_cast<size_t>(j)]) {
      response = previous_columns_[static_cast<size_t>(previous_slot_[i])];
      break;
    }
  }
  addColumn(mapping, contact, 1.0, column_);
  const bool ok = inputs.integrator->applyStepCompliance(column_, response);
  for (int k = 0; k < 3; ++k) {
    const SurfaceMapping::Row support = mapping.row(contact.nodes[k]);
    for (int a = 0; a < support.size; ++a) column_.segment<3>(3 * support.nodes[a]).setZero();
  }
  if (!ok) {
    column_failed_ = true;
    return false;
  }
  column_slot_[static_cast<size_t>(j)] = columns_used_++;
  const Eigen::Index m = count_;
  for (Eigen::Index i = 0; i < m; ++i) {
    const ContactPoint& row = contacts[static_cast<size_t>(i)];
    W_(i, j) += rowDot(mapping, row, response);
    Eigen::Matrix<double, 9, 1>& coupling = coupling_[static_cast<size_t>(i * m + j)];
    for (int k = 0; k < 3; ++k)
      coupling.segment<3>(3 * k) = mapping.vertexValue(row.nodes[k], response);
  }
  // H S H^T is symmetric: the two computed entries of a pair become their mean.
  for (Eigen::Index i = 0; i < m; ++i) {
    if (i == j || column_slot_[static_cast<size_t>(i)] < 0) continue;
    const double mean = 0.5 * (W_(i, j) + W_(j, i));
    W_(i, j) = mean;
    W_(j, i) = mean;
  }
  return true;
}

bool ContactSolver::correct(Integrator& integrator, const Eigen::VectorXd& applied_force, double dt,
                            bool update_velocity, SimulationState& state) {
  correction_ = tissue_force_ - applied_force;
  if (!(correction_.squaredNorm() > 0.0)) return true;
  if (settings_.full_delassus) {
    response_.setZero();
    if (!integrator.applyStepCompliance(correction_, response_)) return false;
  } else {
    // S (H^T lambda - F_a) from the computed columns (lambda_j > 0 only for those) and S F_a.
    response_ = -carried_;
    for (Eigen::Index j = 0; j < count_; ++j) {
      if (lambda_[j] != 0.0)
        response_ += lambda_[j] * columns_[static_cast<size_t>(column_slot_[j])];
    }
  }
  state.x += response_;
  if (update_velocity) state.v += response_ / dt;
  return true;
}

bool ContactSolver::capToolForces() {
  bool capped = false;
  for (size_t t = 0; t < couplings_.size(); ++t) {
    double sum = 0.0;
    for (Eigen::Index i = 0; i < count_; ++i) {
      if (tools_[static_cast<size_t>(i)] == static_cast<int>(t)) sum += lambda_[i];
    }
    if (sum <= couplings_[t].max_force) continue;
    capped = true;
    force_scale_[t] = couplings_[t].max_force / sum;
    for (Eigen::Index i = 0; i < count_; ++i) {
      if (tools_[static_cast<size_t>(i)] == static_cast<int>(t)) lambda_[i] *= force_scale_[t];
    }
  }
  return capped;
}

bool ContactSolver::limited(int tool) const {
  return tool >= 0 && static_cast<size_t>(tool) < force_scale_.size() &&
         force_scale_[static_cast<size_t>(tool)] < 1.0;
}

Eigen::Vector3d ContactSolver::toolForce(int tool) const {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < count_; ++i) {
    if (tools_[static_cast<size_t>(i)] == tool) force -= lambda_[i] * contact_normals_.col(i);
  }
  return force;
}

void ContactSolver::linearize(int tool, const Eigen::Vector3d& p0_S, ContactLinearization& out) {
  out = ContactLinearization();
  out.p0_S = p0_S;
  active_.clear();
  for (Eigen::Index i = 0; i < count_; ++i) {
    if (lambda_[i] > 0.0) active_.push_back(static_cast<int>(i));
  }
  const auto a = static_cast<Eigen::Index>(active_.size());
  for (Eigen::Index r = 0; r < a; ++r) {
    const int i = active_[static_cast<size_t>(r)];
    if (tools_[static_cast<size_t>(i)] == tool) ++out.contacts;
  }
  if (out.contacts == 0) return;
  out.in_contact = true;
  out.f0_S = toolForce(tool);

  // W_AA (regularized) and E (rows n_i^T for the tool's active contacts, 0 for other tools).
  Eigen::Ref<Eigen::MatrixXd> Waa = factor_.topLeftCorner(a, a);
  Eigen::Ref<Eigen::MatrixXd> E = normals_.topRows(a);
  double trace = 0.0;
  for (Eigen::Index r = 0; r < a; ++r) {
    const int i = active_[static_cast<size_t>(r)];
    for (Eigen::Index c = 0; c < a; ++c) Waa(r, c) = W_(i, active_[static_cast<size_t>(c)]);
    trace += W_(i, i);
    if (tools_[static_cast<size_t>(i)] == tool) {
      E.row(r) = contact_normals_.col(i).transpose();
    } else {
      E.row(r).setZero();
    }
  }
  Waa.diagonal().array() += kDelassusRegularization * trace / static_cast<double>(a);
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(Waa);
  if (llt.info() != Eigen::Success) return;  // K stays 0: no usable stiffness
  // Y = W_AA^-1 E: multiplier change per metre of tool motion; constraint part -E^T Y.
  Eigen::Ref<Eigen::MatrixXd> Y = solved_.topRows(a);
  Y = E;
  llt.solveInPlace(Y);
  const bool capped = limited(tool);
  if (capped) {
    // Applied multipliers F lambda* / sum(lambda*): their derivative, on this tool's rows.
    const double scale = force_scale_[static_cast<size_t>(tool)];
    const double max_force = couplings_[static_cast<size_t>(tool)].max_force;
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for (Eigen::Index r = 0; r < a; ++r) {
      if (tools_[static_cast<size_t>(active_[static_cast<size_t>(r)])] == tool) sum += Y.row(r);
    }
    for (Eigen::Index r = 0; r < a; ++r) {
      const int i = active_[static_cast<size_t>(r)];
      if (tools_[static_cast<size_t>(i)] != tool) continue;
      Y.row(r) = scale * (Y.row(r) - (lambda_[i] / max_force) * sum);
    }
  }
  out.K_S = -E.transpose() * Y;
  if (!capped) out.K_S = (0.5 * (out.K_S + out.K_S.transpose())).eval();
  // Geometric part: f = -sum lambda_i n_i with n_i turning with the tool (dn_du) and with the
  // tissue nodes under contact i, which move by sum_s S h_s Y_s per metre of tool motion.
  for (Eigen::Index r = 0; r < a; ++r) {
    const auto i = static_cast<size_t>(active_[static_cast<size_t>(r)]);
    if (tools_[i] != tool) continue;
    Eigen::Matrix<double, 9, 3> node_motion = Eigen::Matrix<double, 9, 3>::Zero();
    for (Eigen::Index c = 0; c < a; ++c) {
      const auto j = static_cast<size_t>(active_[static_cast<size_t>(c)]);
      node_motion += coupling_[i * static_cast<size_t>(count_) + j] * Y.row(c);
    }
    out.K_S -= lambda_[static_cast<Eigen::Index>(i)] * (dn_du_[i] + dn_dx_[i] * node_motion);
  }
}

}  // namespace surgical_sim::core
