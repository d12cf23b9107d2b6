#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "surgical_sim/core/common/status.h"
#include "surgical_sim/core/contact/contact_point.h"
#include "surgical_sim/core/contact/lcp_active_set.h"
#include "surgical_sim/core/contact/projected_gauss_seidel.h"
#include "surgical_sim/core/solve/dynamics_problem.h"
#include "surgical_sim/core/solve/integrator.h"
#include "surgical_sim/core/tissue/surface_mapping.h"

namespace surgical_sim::core {

/// Settings of ContactSolver. Numerical choices with documented defaults.
struct ContactSolverSettings {
  int max_iterations = 200;  ///< projected Gauss-Seidel sweeps per step [-], in [1, 100000]
  /// Converged when the LCP min-map residual is below relative_tolerance x max_i |q_i|
  /// (q: free gaps) [-], in (0, 1).
  double relative_tolerance = 1e-8;
  /// Compute the compliance column S h_j of every contact (the whole Delassus operator) and start
  /// the LCP with projected Gauss-Seidel. false (default): compute only the columns of the
  /// contacts the active-set LCP makes active, starting from the penetrating ones, and the
  /// correction from those columns; the whole operator only if that LCP does not converge. Both
  /// give the same answer to the linear solver's and the LCP's tolerance.
  bool full_delassus = false;
};

/// @throws std::invalid_argument naming "contact.solver.max_iterations" or
///         "contact.solver.relative_tolerance"
void validateContactSolverSettings(const ContactSolverSettings& settings);

/// How one tool's body follows its commanded pose (DESIGN.md "The tool is coupled, not
/// imposed"): the simulated tool is a massless body tied to the commanded pose by a spring, and
/// its total contact force is capped. Physical parameters have no defaults (NaN fails validation).
struct ToolCoupling {
  /// k_c [N/m], finite and > 0: the tool body sits at the commanded pose displaced by
  /// f_tool / k_c (f_tool: force of the tissue on the tool).
  double stiffness = std::numeric_limits<double>::quiet_NaN();
  /// F_max [N], finite and > 0: cap on the sum of the tool's contact multipliers, which bounds
  /// |f_tool|.
  double max_force = std::numeric_limits<double>::quiet_NaN();
  /// b_c [N s/m], finite and >= 0: damper in parallel with the spring, acting on the rate of the
  /// body's offset from the commanded pose (0: a pure spring).
  double damping = 0.0;
};

/// @throws std::invalid_argument naming "tool.coupling_stiffness", "tool.max_force" or
///         "tool.coupling_damping"
void validateToolCoupling(const ToolCoupling& coupling);

/// Unilateral contact constraints solved through the compliance of the implicit step, in the
/// spirit of SOFA's free-motion / correction loop:
///  1. the integrator takes the free step x_free, with the contact force of the previous step F_a
///     (applied_force, may be zero) already in its external force;
///  2. H has one row per contact, n^T times the barycentric weights on the triangle's 3 surface
///     vertices mapped to the model's DOFs: h = sum_k w_k (A_k^T n) with A_k the vertex's row of
///     the SurfaceMapping (for a tet model the identity on the surface nodes);
///     S = Integrator::applyStepCompliance (one call per contact column that step 3 needs: the
///     columns of the contacts it makes active, or all with full_delassus; an iterative solver
///     starts each column from the last solve's column of the same contact, same tool and
///     triangle vertices, if it computed one, and S F_a from the last S F_a); the gaps are measured
///     with the tool at its commanded pose, and the massless tool body of tool t (ToolCoupling)
///     sits at the offset d_t from it where the spring-damper balances the contact force
///     (backward Euler): (k_t + b_t/dt) d_t = (b_t/dt) d_t,prev - sum_{j of t} lambda_j n_j.
///     With c_t = 1 / (k_t + b_t/dt) the Delassus operator is
///     W = H S H^T + C [m/N], C_ij = c_t n_i . n_j for contacts i, j of the same tool t
///     (W_ii >= c_t: a contact on fixed nodes is well-posed), and the damper's memory shifts
///     the gaps by -c_t (b_t/dt) n_i . d_t,prev;
///  3. the LCP 0 <= lambda _|_ q + W lambda >= 0 with q = g_free - H S F_a (+ the shift) is solved
///  by
///     projected Gauss-Seidel, whose active set is then refined to the exact solution by
///     principal pivoting (refineLcpActiveSet; lambda [N]: the new contact force replaces F_a);
///     a tool whose multipliers sum above its max_force gets them scaled to sum to max_force
///     (contradictory normals on fixed nodes make the LCP infeasible; the cap bounds the answer);
///     (without full_delassus, the active-set pivoting runs first, from the penetrating contacts,
///     computing the columns of the contacts it activates; Gauss-Seidel only if it fails);
///  4. correction dx = S (H^T lambda - F_a): x += dx, v += dx / dt (without full_delassus, as
///     sum lambda_j S h_j - S F_a from the computed columns, no further solve).
/// tissueForce() = H^T lambda is the force on the tissue to carry into the next free step; the
/// force of the tissue on tool t is -sum_{i of t} lambda_i n_i, of magnitude <= max_force.
///
/// Friction (not implemented): two tangent rows per contact with the same node weights and
/// Coulomb cone projection in the Gauss-Seidel sweep fit this row structure unchanged.
class ContactSolver {
 public:
  /// @param max_contacts largest number of contacts solve() will see (all tools), >= 1
  /// @param tools coupling of each tool (index = ContactPoint::tool), at least one
  /// @throws std::invalid_argument (validateContactSolverSettings, validateToolCoupling) or
  ///         naming "contact.max_contacts" or "contact.tools" (empty)
  ContactSolver(const ContactSolverSettings& settings, int max_contacts,
                const std::vector<ToolCoupling>& tools);

  /// Solves the contacts (gaps measured at the free positions state.x) and corrects state.
  /// @param integrator integrator that just took the free step (its step compliance is used)
  /// @param mapping the model's surface mapping (ContactPoint::nodes are its slots)
  /// @param contacts at most max_contacts contacts, in S
  /// @param applied_force contact force already applied during the free step [N], size 3n
  /// @param dt step [s] (> 0) for the velocity correction
  /// @param update_velocity false for quasi-static integrators (v stays 0)
  /// @return Ok; ContactLimited if a tool's multipliers were scaled down to its max_force;
  ///         otherwise NotConverged (state corrected with the last Gauss-Seidel iterate) if
  ///         neither Gauss-Seidel nor the active-set refinement converged; SolverFailed (state
  ///         untouched, zero force) if the step compliance is unavailable, contacts exceed
  ///         max_contacts, a contact names an unknown tool or a slot outside the mapping, the
  ///         mapping's node count does not match state.x or the multipliers are not finite.
  ///         Never throws; allocation-free once it has seen the size 3n and its largest contact
  ///         count.
  StepStatus solve(Integrator& integrator, const SurfaceMapping& mapping,
                   const std::vector<ContactPoint>& contacts, const Eigen::VectorXd& applied_force,
                   double dt, bool update_velocity, SimulationState& state);

  /// H^T lambda of the last solve [N], size 3n, in S (zero before the first solve).
  const Eigen::VectorXd& tissueForce() const { return tissue_force_; }
  /// Force of the tissue on tool `tool` [N], in S: -sum lambda_i n_i over its contacts.
  Eigen::Vector3d toolForce(int tool) const;
  /// Local linearization of tool `tool` at tip p0_S [m]: f0 = toolForce(tool) and
  /// K = -E^T Y - sum_i lambda_i (dn_i/du + dn_i/dx_i S H^T Y), Y = W_AA^-1 E, on the active set
  /// A = {lambda_i > 0} (E: rows n_i^T of this tool's contacts, other tools held fixed; W includes
  /// the coupling, so |K| is bounded by the coupling stiffness). The first term is the constraint
  /// stiffness (pushing along a normal n changes the force by -n/W per metre); the second turns
  /// the normals at fixed multipliers, with the tool (vertex and edge contacts,
  /// ContactPoint::dn_du) and with the tissue under the tool, which the multiplier change moves
  /// by S H^T Y (ContactPoint::dn_dx). For a tool capped at max_force F the applied multipliers
  /// are lambda = F lambda* / sum(lambda*), so its rows of Y become
  /// (F / sum(lambda*)) (Y_i - (lambda_i / F) sum_{j of the tool} Y_j): the stiffness of the
  /// force actually applied (no change of magnitude along the cap). K is not symmetric in
  /// general. Allocation-free after the solve.
  /// Allocation-free. out.in_contact is false (f0 = 0, K = 0) without an active contact.
  void linearize(int tool, const Eigen::Vector3d& p0_S, ContactLinearization& out);
  /// Multipliers lambda [N] of the last solve, one per contact.
  Eigen::Ref<const Eigen::VectorXd> multipliers() const { return lambda_.head(count_); }
  /// Delassus operator W = H S H^T + C [m/N] of the last solve, count x count; without
  /// full_delassus, columns of contacts whose compliance column was not needed hold C alone
  /// (rows and columns of the active contacts are complete).
  Eigen::Ref<const Eigen::MatrixXd> delassus() const { return W_.topLeftCorner(count_, count_); }
  /// Free gaps with the carried force removed, q [m], of the last solve.
  Eigen::Ref<const Eigen::VectorXd> freeGaps() const { return q_.head(count_); }
  /// Report of the last LCP solve (the active-set refinement's when it converged).
  const PgsReport& report() const { return report_; }
  /// Whether tool `tool`'s multipliers were capped at its max_force in the last solve.
  bool limited(int tool) const;
  /// Offset d_t of tool `tool`'s body from its commanded pose after the last solve [m], in S.
  const Eigen::Vector3d& bodyOffset(int tool) const;

 private:
  void resize(Eigen::Index size);
  /// Keeps the computed columns of the last solve as warm starts (previous_*), if it has any.
  void keepColumnsAsStarts();
  /// Scales each tool's multipliers whose sum exceeds its max_force down to it (force_scale_);
  /// returns whether any tool was capped.
  bool capToolForces();
  /// What computeColumn needs of the current solve.
  struct ColumnInputs {
    Integrator* integrator;
    const SurfaceMapping* mapping;
    const std::vector<ContactPoint>* contacts;
  };
  /// If not done yet in this solve: column j of H S H^T into W_ (pairs of computed entries
  /// symmetrized), the response S h_j kept for the correction and coupling_; the solve starts
  /// from the previous column of the same key, else from zero. False if the step compliance
  /// fails (column_failed_ is then set).
  bool computeColumn(const ColumnInputs& inputs, Eigen::Index j);
  /// Correction dx = S (H^T lambda - F_a) (step 4) applied to state; false if S fails.
  bool correct(Integrator& integrator, const Eigen::VectorXd& applied_force, double dt,
               bool update_velocity, SimulationState& state);
  /// solve() between the coupling updates.
  StepStatus solveContacts(Integrator& integrator, const SurfaceMapping& mapping,
                           const std::vector<ContactPoint>& contacts,
                           const Eigen::VectorXd& applied_force, double dt, bool update_velocity,
                           SimulationState& state);
  /// Per tool c_t = 1 / (k_t + b_t/dt) [m/N] for the step dt [s].
  void updateCompliances(double dt);
  /// d_t = c_t ((b_t/dt) d_t,prev - sum_{i of t} lambda_i n_i) from the last solve's multipliers.
  void updateBodyOffsets(double dt);
  /// h_i^T v for contact i.
  static double rowDot(const SurfaceMapping& mapping, const ContactPoint& contact,
                       const Eigen::VectorXd& v);
  /// v += scale h_i.
  static void addColumn(const SurfaceMapping& mapping, const ContactPoint& contact, double scale,
                        Eigen::VectorXd& v);

  ContactSolverSettings settings_;
  int max_contacts_;
  std::vector<ToolCoupling> couplings_;
  /// Per tool: applied / LCP multipliers of the last solve (1 when not capped) [-].
  std::vector<double> force_scale_;
  std::vector<double> compliance_;            ///< per tool c_t of the current step [m/N]
  std::vector<Eigen::Vector3d> body_offset_;  ///< per tool d_t [m], S
  Eigen::Index count_ = 0;
  Eigen::MatrixXd W_;                   ///< max x max, top-left count x count used
  Eigen::MatrixXd factor_;              ///< max x max, W_AA factorization work space
  Eigen::MatrixXd normals_;             ///< max x 3, rows n_i^T of the tool being linearized
  Eigen::VectorXd q_, lambda_;          ///< max
  std::vector<int> active_;             ///< active contact indices (capacity max)
  std::vector<int> tools_;              ///< tool of each contact of the last solve
  Eigen::Matrix3Xd contact_normals_;    ///< 3 x max, n_i of the last solve
  std::vector<Eigen::Matrix3d> dn_du_;  ///< max, dn_i/du of the last solve
  std::vector<Eigen::Matrix<double, 3, 9>> dn_dx_;  ///< max, dn_i/dx_nodes of the last solve
  /// count x count (row-major), W S h_j at contact i's three vertices [m/N]
  std::vector<Eigen::Matrix<double, 9, 1>> coupling_;
  Eigen::MatrixXd solved_;                                                   ///< max x 3, W_AA^-1 E
  Eigen::VectorXd tissue_force_, column_, response_, carried_, correction_;  ///< 3n
  std::vector<Eigen::VectorXd> columns_;  ///< S h_j of the computed columns (3n each), by slot
  std::vector<int> column_slot_;          ///< per contact: its slot in columns_, -1 not computed
  std::vector<Eigen::Vector4i> column_keys_;  ///< max, per contact: tool and triangle vertices
  /// The columns of the last solve that computed any (warm starts): slots, per-contact slots
  /// (-1 none) and keys.
  std::vector<Eigen::VectorXd> previous_columns_;
  std::vector<int> previous_slot_;
  std::vector<Eigen::Vector4i> previous_keys_;
  int columns_used_ = 0;        ///< slots of columns_ filled in this solve
  bool column_failed_ = false;  ///< a compliance column failed in this solve
  PgsReport report_;
  LcpActiveSetWorkspace active_set_;
};

}  // namespace surgical_sim::core
