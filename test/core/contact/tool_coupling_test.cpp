// ContactSolver with the tool coupled to its commanded pose (ToolCoupling): pen-and-paper answers
// for contacts on fixed and on compliant nodes, the force cap and the linearization; computing
// only the compliance columns the LCP needs equals computing the whole Delassus operator.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "surgical_sim/core/contact/contact_solver.h"

namespace surgical_sim::core {
namespace {

constexpr double kCoupling = 1e4;   // k_c [N/m]
constexpr double kMaxForce = 20.0;  // F_max [N]

/// Integrator whose step compliance is a given matrix S [m/N] (S = 0: every node fixed).
class FixedCompliance : public Integrator {
 public:
  explicit FixedCompliance(Eigen::MatrixXd S) : S_(std::move(S)) {}
  std::string name() const override { return "fixed_compliance"; }
  StepReport step(const DynamicsProblem&, double, SimulationState&) override { return {}; }
  void reset() override {}
  bool applyStepCompliance(const Eigen::VectorXd& f, Eigen::VectorXd& dx) override {
    ++calls;
    dx = S_ * f;
    return true;
  }

  int calls = 0;  ///< applyStepCompliance calls

 private:
  Eigen::MatrixXd S_;
};

/// The identity mapping of the 8 nodes (every node a surface vertex).
const SurfaceMapping& eightNodes() {
  static const SurfaceMapping mapping = SurfaceMapping::selection(8, {0, 1, 2, 3, 4, 5, 6, 7});
  return mapping;
}

/// Contact of tool `tool` on node `node` alone (weight 1), normal n (normalized), gap [m].
ContactPoint contactOnNode(int node, const Eigen::Vector3d& n, double gap, int tool = 0) {
  ContactPoint c;
  c.tool = tool;
  c.nodes = Eigen::Vector3i(node, (node + 1) % 8, (node + 2) % 8);
  c.weights = Eigen::Vector3d(1.0, 0.0, 0.0);
  c.n_S = n.normalized();
  c.gap = gap;
  return c;
}

/// Solves `contacts` on 8 nodes of step compliance S; returns the status.
struct Solve {
  Solve(Eigen::MatrixXd S, double max_force = kMaxForce, int tools = 1)
      : integrator(std::move(S)),
        solver(settings(), 16, std::vector<ToolCoupling>(tools, {kCoupling, max_force})) {}

  static ContactSolverSettings settings(bool full_delassus = false) {
    ContactSolverSettings s;
    s.max_iterations = 500;
    s.relative_tolerance = 1e-10;
    s.full_delassus = full_delassus;
    return s;
  }

  StepStatus run(const std::vector<ContactPoint>& contacts) {
    state.x = Eigen::VectorXd::Zero(24);
    state.v = Eigen::VectorXd::Zero(24);
    return solver.solve(integrator, eightNodes(), contacts, Eigen::VectorXd::Zero(24), 0.01, true,
                        state);
  }

  FixedCompliance integrator;
  ContactSolver solver;
  SimulationState state;
};

TEST(ToolCoupling, ContactOnAFixedNodePushesTheToolBackThroughTheCoupling) {
  // S = 0: the tissue cannot move; the tool body retracts by d, force k_c d.
  Solve s(Eigen::MatrixXd::Zero(24, 24));
  const Eigen::Vector3d n(0.0, 0.0, -1.0);  // tool above, surface below: normal points down
  const double d = 1e-3;
  ASSERT_EQ(s.run({contactOnNode(0, n, -d)}), StepStatus::Ok);
  EXPECT_NEAR(s.solver.multipliers()[0], kCoupling * d, 1e-9);
  EXPECT_LT((s.solver.toolForce(0) - kCoupling * d * Eigen::Vector3d::UnitZ()).norm(), 1e-9);
  EXPECT_FALSE(s.solver.limited(0));
  ContactLinearization lin;
  s.solver.linearize(0, Eigen::Vector3d::Zero(), lin);
  ASSERT_TRUE(lin.in_contact);
  EXPECT_LT((lin.K_S + kCoupling * n * n.transpose()).norm(), 1e-6 * kCoupling);
  EXPECT_EQ(s.state.x, Eigen::VectorXd::Zero(24));  // fixed: nothing moves

  // 5 mm deep: k_c d = 50 N is capped at F_max, the status says so, the stiffness along the cap
  // is zero (the applied force no longer changes).
  ASSERT_EQ(s.run({contactOnNode(0, n, -5e-3)}), StepStatus::ContactLimited);
  EXPECT_NEAR(s.solver.multipliers()[0], kMaxForce, 1e-9);
  EXPECT_NEAR(s.solver.toolForce(0).norm(), kMaxForce, 1e-9);
  EXPECT_TRUE(s.solver.limited(0));
  s.solver.linearize(0, Eigen::Vector3d::Zero(), lin);
  EXPECT_LT(lin.K_S.norm(), 1e-9 * kCoupling);
}

TEST(ToolCoupling, DamperResistsTheFirstStepThenTheSpringAloneHolds) {
  // Fixed node, gap -d, spring k and damper b (b/dt = k): the body is massless, so
  // (k + b/dt) d_t = (b/dt) d_t,prev - lambda n.
  const double b = 100.0, dt = 0.01, d = 1e-3, rate = b / dt;  // rate = k_c = 1e4 N/m
  FixedCompliance integrator(Eigen::MatrixXd::Zero(24, 24));
  ContactSolver solver(Solve::settings(), 16, {{kCoupling, 1e3, b}});
  SimulationState state;
  state.x = state.v = Eigen::VectorXd::Zero(24);
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(24);
  const Eigen::Vector3d n(0.0, 0.0, -1.0);
  const auto step = [&](const std::vector<ContactPoint>& contacts) {
    EXPECT_EQ(solver.solve(integrator, eightNodes(), contacts, none, dt, true, state),
              StepStatus::Ok);
    return contacts.empty() ? 0.0 : solver.multipliers()[0];
  };
  // First touch: spring and damper both resist, lambda = (k + b/dt) d; the body retracts by d.
  EXPECT_NEAR(step({contactOnNode(0, n, -d)}), (kCoupling + rate) * d, 1e-8);
  EXPECT_LT((solver.bodyOffset(0) + d * n).norm(), 1e-12 + 1e-9 * d);
  // Held at the same depth: the body no longer moves, the damper carries nothing: lambda = k d.
  EXPECT_NEAR(step({contactOnNode(0, n, -d)}), kCoupling * d, 1e-8);
  EXPECT_LT((solver.bodyOffset(0) + d * n).norm(), 1e-12 + 1e-9 * d);
  // Released for one step: the body relaxes halfway back, d_t = (b/dt) / (k + b/dt) d_t,prev.
  step({});
  EXPECT_LT((solver.bodyOffset(0) + 0.5 * d * n).norm(), 1e-9 * d);
  // Touching again, the body still lags by d/2: the effective gap is -d + c (b/dt) d/2 = -3d/4.
  EXPECT_NEAR(step({contactOnNode(0, n, -d)}), 0.75 * (kCoupling + rate) * d, 1e-8);
}

TEST(ToolCoupling, NegativeOrNonFiniteDampingIsRejectedNamingIt) {
  for (const double b : {-1.0, std::nan("")}) {
    try {
      ContactSolver solver(Solve::settings(), 4, {{kCoupling, kMaxForce, b}});
      FAIL() << "accepted damping " << b;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("tool.coupling_damping"), std::string::npos);
    }
  }
}

TEST(ToolCoupling, OppositeNormalsOnCompliantNodesMatchTheCoupledPair) {
  // Tool wedged between two surfaces (normals +z and -z) on nodes of compliance s each: with
  // the shared tool displacement the Delassus matrix is [[s + 1/k, -1/k], [-1/k, s + 1/k]].
  const double s_node = 1e-4;  // [m/N]
  Solve s(s_node * Eigen::MatrixXd::Identity(24, 24));
  const double d1 = 1e-4, d2 = 2e-4, c = 1.0 / kCoupling;
  ASSERT_EQ(s.run({contactOnNode(0, Eigen::Vector3d::UnitZ(), -d1),
                   contactOnNode(4, -Eigen::Vector3d::UnitZ(), -d2)}),
            StepStatus::Ok);
  const double det = (s_node + c) * (s_node + c) - c * c;
  const double lambda1 = ((s_node + c) * d1 + c * d2) / det;
  const double lambda2 = (c * d1 + (s_node + c) * d2) / det;
  EXPECT_NEAR(s.solver.multipliers()[0], lambda1, 1e-9 * lambda1);
  EXPECT_NEAR(s.solver.multipliers()[1], lambda2, 1e-9 * lambda2);
  EXPECT_NEAR(s.solver.toolForce(0).z(), lambda2 - lambda1, 1e-9);
  // The nodes were pushed out of the tool by s lambda along their normals.
  EXPECT_NEAR(s.state.x[2], s_node * lambda1, 1e-12);
  EXPECT_NEAR(s.state.x[14], -s_node * lambda2, 1e-12);
}

TEST(ToolCoupling, OppositeNormalsOnFixedNodesEndBoundedAndLabelled) {
  // Tip inside a fixed slab: no tool displacement clears both contacts, the LCP is infeasible.
  // Without the cap the multipliers grow without bound; with it they sum to F_max.
  Solve s(Eigen::MatrixXd::Zero(24, 24));
  for (const double d2 : {1e-3, 3e-2}) {
    const StepStatus status = s.run({contactOnNode(0, Eigen::Vector3d::UnitZ(), -1e-3),
                                     contactOnNode(4, -Eigen::Vector3d::UnitZ(), -d2)});
    EXPECT_NE(status, StepStatus::Ok) << d2;
    EXPECT_TRUE(status == StepStatus::ContactLimited || status == StepStatus::NotConverged)
        << toString(status);
    const auto lambda = s.solver.multipliers();
    ASSERT_TRUE(lambda.allFinite());
    EXPECT_LE(lambda.sum(), kMaxForce * (1.0 + 1e-12));
    EXPECT_LE(s.solver.toolForce(0).norm(), kMaxForce * (1.0 + 1e-12));
    EXPECT_TRUE(s.solver.tissueForce().allFinite());
  }
}

TEST(ToolCoupling, ForceCapActsPerTool) {
  // Tool 0 deep on a fixed node (capped), tool 1 shallow (k_c d = 5 N, untouched).
  Solve s(Eigen::MatrixXd::Zero(24, 24), kMaxForce, 2);
  ASSERT_EQ(s.run({contactOnNode(0, Eigen::Vector3d::UnitZ(), -1e-2, 0),
                   contactOnNode(4, Eigen::Vector3d::UnitZ(), -5e-4, 1)}),
            StepStatus::ContactLimited);
  EXPECT_TRUE(s.solver.limited(0));
  EXPECT_FALSE(s.solver.limited(1));
  EXPECT_NEAR(s.solver.toolForce(0).norm(), kMaxForce, 1e-9);
  EXPECT_NEAR(s.solver.toolForce(1).norm(), 5.0, 1e-9);
}

/// SPD step compliance on 8 nodes, of order `scale` [m/N], coupling all of them.
Eigen::MatrixXd coupledCompliance(double scale) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd A(24, 24);
  for (Eigen::Index i = 0; i < A.size(); ++i) A.data()[i] = u(rng);
  return scale * (Eigen::MatrixXd::Identity(24, 24) + 0.2 / 24.0 * A * A.transpose());
}

/// Contacts of tool 0 at the commanded tool position u [m] (gaps move by -n . u) and one of
/// tool 1 that stays put.
std::vector<ContactPoint> contactsAt(const Eigen::Vector3d& u) {
  std::vector<ContactPoint> contacts = {
      contactOnNode(0, Eigen::Vector3d(0.2, 0.1, -1.0), -1.0e-3),
      contactOnNode(3, Eigen::Vector3d(-0.6, 0.2, -1.0), -0.8e-3),
      contactOnNode(5, Eigen::Vector3d(0.1, -0.7, -1.0), -1.2e-3),
      contactOnNode(6, Eigen::Vector3d(0.0, 0.0, -1.0), -0.2e-3, 1)};
  for (ContactPoint& c : contacts) {
    if (c.tool == 0) c.gap -= c.n_S.dot(u);
  }
  return contacts;
}

TEST(ToolCoupling, LinearizationEqualsFiniteDifferencesOfTheSolvedForce) {
  // Below the cap (F_max large) and at the cap: K must be the derivative of the force the
  // solver actually applies.
  for (const double max_force : {1e3, 2.0}) {
    SCOPED_TRACE(max_force);
    Solve s(coupledCompliance(2e-4), max_force, 2);
    const StepStatus status = s.run(contactsAt(Eigen::Vector3d::Zero()));
    ASSERT_EQ(status, max_force < 100.0 ? StepStatus::ContactLimited : StepStatus::Ok);
    ASSERT_EQ((s.solver.multipliers().array() > 0.0).count(), 4);  // all active
    ContactLinearization lin;
    s.solver.linearize(0, Eigen::Vector3d::Zero(), lin);
    const Eigen::Vector3d f0 = s.solver.toolForce(0);
    EXPECT_EQ(lin.f0_S, f0);
    const double h = 1e-7;  // [m]
    Eigen::Matrix3d K_fd;
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(s.run(contactsAt(h * Eigen::Vector3d::Unit(k))), status);
      const Eigen::Vector3d plus = s.solver.toolForce(0);
      ASSERT_EQ(s.run(contactsAt(-h * Eigen::Vector3d::Unit(k))), status);
      K_fd.col(k) = (plus - s.solver.toolForce(0)) / (2.0 * h);
    }
    EXPECT_LT((lin.K_S - K_fd).norm(), 1e-5 * K_fd.norm()) << "K\n"
                                                           << lin.K_S << "\nfinite differences\n"
                                                           << K_fd;
    // Bounded by the coupling: no direction is stiffer than k_c.
    EXPECT_LE(lin.K_S.norm(), 3.0 * kCoupling);
  }
}

TEST(ToolCoupling, NeededColumnsOnlyEqualTheWholeDelassusOperator) {
  // Ten contacts of two tools, some separated (positive gaps), over steps that carry the last
  // force into the next: the multipliers, the corrected state, the tissue force and the
  // linearization agree, with fewer compliance solves.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<ContactPoint> contacts;
  for (int i = 0; i < 10; ++i) {
    const Eigen::Vector3d n(0.3 * u(rng), 0.3 * u(rng), -1.0);
    contacts.push_back(contactOnNode(i % 8, n, 1e-3 * (u(rng) - 0.3), i % 3 == 2 ? 1 : 0));
    contacts.back().weights = Eigen::Vector3d(0.6, 0.3, 0.1);
  }
  FixedCompliance full_integrator(coupledCompliance(2e-4));
  FixedCompliance needed_integrator(coupledCompliance(2e-4));
  const std::vector<ToolCoupling> tools(2, {kCoupling, 1e3, 50.0});
  ContactSolver full(Solve::settings(true), 16, tools);
  ContactSolver needed(Solve::settings(false), 16, tools);
  SimulationState full_state, needed_state;
  full_state.x = full_state.v = needed_state.x = needed_state.v = Eigen::VectorXd::Zero(24);
  for (int step = 0; step < 3; ++step) {
    SCOPED_TRACE(step);
    const Eigen::VectorXd full_applied =
        full.tissueForce().size() == 24 ? full.tissueForce() : Eigen::VectorXd::Zero(24).eval();
    const Eigen::VectorXd needed_applied =
        needed.tissueForce().size() == 24 ? needed.tissueForce() : Eigen::VectorXd::Zero(24).eval();
    full_integrator.calls = needed_integrator.calls = 0;
    ASSERT_EQ(
        full.solve(full_integrator, eightNodes(), contacts, full_applied, 0.01, true, full_state),
        StepStatus::Ok);
    ASSERT_EQ(needed.solve(needed_integrator, eightNodes(), contacts, needed_applied, 0.01, true,
                           needed_state),
              StepStatus::Ok);
    const auto lambda = full.multipliers();
    const Eigen::Index active = (lambda.array() > 0.0).count();
    ASSERT_GT(active, 0);
    ASSERT_LT(active, 10);
    EXPECT_LT((needed.multipliers() - lambda).norm(), 1e-8 * lambda.norm());
    EXPECT_LT((needed_state.x - full_state.x).norm(), 1e-8 * full_state.x.norm());
    EXPECT_LT((needed_state.v - full_state.v).norm(), 1e-8 * full_state.v.norm());
    EXPECT_LT((needed.tissueForce() - full.tissueForce()).norm(), 1e-8 * full.tissueForce().norm());
    for (int tool = 0; tool < 2; ++tool) {
      ContactLinearization a, b;
      full.linearize(tool, Eigen::Vector3d::Zero(), a);
      needed.linearize(tool, Eigen::Vector3d::Zero(), b);
      EXPECT_EQ(a.contacts, b.contacts);
      EXPECT_LT((a.K_S - b.K_S).norm(), 1e-8 * a.K_S.norm()) << tool;
    }
    // Whole operator: carried force, every column, correction. Needed: the active columns (and
    // any the pivoting tried) and the carried force.
    EXPECT_EQ(full_integrator.calls, 10 + 1 + (step > 0 ? 1 : 0));
    EXPECT_LE(needed_integrator.calls, full_integrator.calls - 2);
    EXPECT_GE(needed_integrator.calls, active + (step > 0 ? 1 : 0));
  }
}

}  // namespace
}  // namespace surgical_sim::core
