// Stability over stiff and extreme cases (BENCHMARKS.md "Stability"): every model x implicit
// integrator returns finite results, bounded energy and (Newton, quasi-static) Ok steps in
// equilibrium, or a clear failure status, never a crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "surgical_sim/bench/tissue_case.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/mesh_check.h"
#include "surgical_sim/core/scene/scene_build.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/solve/absolute_product_norm.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::bench {
namespace {

constexpr double kSide = 0.1;  // cube edge [m]
const std::vector<std::string> kModels = {"mass_spring", "corotational", "svk",
                                          "ems",         "neo_hookean",  "efg"};
const std::vector<std::string> kImplicit = {"implicit_euler_linearized", "implicit_euler_newton",
                                            "quasi_static"};

/// A 0.1 m cube (2x2x2 cells, 48 tets) resting on its fixed bottom face under gravity.
struct Rig {
  TetMesh mesh;
  std::unique_ptr<TissueModel> model;
  DynamicsProblem problem;
  SimulationState state;
  std::unique_ptr<Integrator> integrator;

  Rig(const std::string& model_name, const std::string& integrator_name, double E, double nu) {
    mesh = makeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(kSide),
                   Eigen::Vector3i::Constant(2), ElementType::Tet4);
    EfgOptions efg;
    efg.spacing = kSide / 4.0;  // particles on the mesh's 3 x 3 x 3 node lattice
    model = makeTissueModel(*enumFromName(kModelNames, model_name), mesh,
                            Material::create(E, nu, 1000.0), efg);
    problem.model = model.get();
    problem.external_force = model->bodyForce(Eigen::Vector3d(0, 0, -9.81));
    problem.dirichlet.dofs = regionDofs(model->restPositions(), bottom(), Eigen::Vector3i::Ones());
    problem.dirichlet.positions.resize(static_cast<Eigen::Index>(problem.dirichlet.dofs.size()));
    for (std::size_t i = 0; i < problem.dirichlet.dofs.size(); ++i)
      problem.dirichlet.positions[static_cast<Eigen::Index>(i)] =
          model->restPositions()[problem.dirichlet.dofs[i]];
    state.x = model->restPositions();
    state.v = Eigen::VectorXd::Zero(state.x.size());
    IntegratorSettings settings;
    settings.max_iterations = 20;
    settings.relative_tolerance = 1e-8;
    integrator = makeIntegrator(*enumFromName(kIntegratorNames, integrator_name), settings,
                                makeLinearSolver(SolverKind::Cholmod, {}));
  }

  static Region bottom() {
    Region r;
    r.max.z() = 1e-9;
    return r;
  }

  /// Kinetic + elastic energy minus the work potential of gravity, relative to rest [J].
  double totalEnergy() const {
    const Eigen::VectorXd& m = model->lumpedMass();
    return 0.5 * state.v.dot(m.cwiseProduct(state.v)) + model->energy(state.x) -
           problem.external_force.dot(state.x - model->restPositions());
  }

  /// Scale of the energy the load can release: weight times the cube edge [J].
  double energyScale() const { return model->lumpedMass().sum() / 3.0 * 9.81 * kSide; }

  int invertedElements() const {
    TetMesh deformed = mesh;
    for (int n = 0; n < mesh.numNodes(); ++n) deformed.nodes.col(n) = state.x.segment<3>(3 * n);
    int count = 0;
    for (int e = 0; e < mesh.numElements(); ++e) count += signedVolume(deformed, e) <= 0.0;
    return count;
  }
};

/// Equilibrium of a step from (x0, v0) to rig.state over dt, recomputed from the model (no
/// damping in the rig): the residual |M (x - x0 - dt v0) / dt^2 - f_int(x) - f_ext| on the free
/// DOFs (no inertia term for quasi-static steps), the largest of its terms' norms, and the
/// round-off scale of f_int(x), || |K| |x| ||.
struct Equilibrium {
  double residual = 0.0;   ///< [N]
  double scale = 0.0;      ///< [N]
  double round_off = 0.0;  ///< [N]
};

Equilibrium equilibrium(const Rig& rig, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                        double dt, bool quasi_static) {
  const Eigen::VectorXd& x = rig.state.x;
  Eigen::VectorXd internal = Eigen::VectorXd::Zero(x.size());
  rig.model->addInternalForce(x, internal);
  Eigen::VectorXd inertia = Eigen::VectorXd::Zero(x.size());
  if (!quasi_static) inertia = rig.model->lumpedMass().cwiseProduct(x - x0 - dt * v0) / (dt * dt);
  Eigen::VectorXd r = inertia - internal - rig.problem.external_force;
  for (const int d : rig.problem.dirichlet.dofs) r[d] = internal[d] = inertia[d] = 0.0;
  Eigen::SparseMatrix<double> K = rig.model->stiffnessPattern();
  rig.model->assembleStiffness(x, TangentMode::ProjectedSpd, K);
  Eigen::VectorXd work(x.size());
  return {r.norm(), std::max({inertia.norm(), internal.norm(), rig.problem.external_force.norm()}),
          absoluteProductNorm(K, x, work)};
}

bool isFailureStatus(StepStatus s) {
  return s == StepStatus::SolverFailed || s == StepStatus::NonFinite || s == StepStatus::BlowUp;
}

TEST(Stability, EveryModelAndImplicitIntegratorOverStiffnessPoissonAndTimeStep) {
  int ok_runs = 0;
  for (const auto& model : kModels)
    for (const auto& integrator : kImplicit)
      for (double E : {1e3, 1e6, 1e9})
        for (double nu : {0.3, 0.45, 0.499})
          for (double dt : {1e-4, 1e-2, 1e-1}) {
            if (integrator == "quasi_static" && dt != 1e-2) continue;  // dt plays no role
            SCOPED_TRACE(model + " / " + integrator + " E=" + std::to_string(E) +
                         " nu=" + std::to_string(nu) + " dt=" + std::to_string(dt));
            Rig rig(model, integrator, E, nu);
            const double e0 = rig.totalEnergy();
            bool failed = false;
            for (int k = 0; k < 5 && !failed; ++k) {
              const Eigen::VectorXd x0 = rig.state.x;
              const Eigen::VectorXd v0 = rig.state.v;
              const StepReport r = rig.integrator->step(rig.problem, dt, rig.state);
              ASSERT_TRUE(rig.state.x.allFinite());
              ASSERT_TRUE(rig.state.v.allFinite());
              failed = isFailureStatus(r.status);
              // An Ok Newton / quasi-static step is in equilibrium (its tolerance is 1e-8 of the
              // step's first residual, or the round-off floor 1e-13 || |K| |x| ||).
              if (r.status == StepStatus::Ok && integrator != "implicit_euler_linearized") {
                const Equilibrium eq = equilibrium(rig, x0, v0, dt, integrator == "quasi_static");
                EXPECT_LT(eq.residual, 1e-6 * eq.scale + 1e-12 * eq.round_off) << "step " << k;
              }
            }
            if (failed) continue;  // a clear status, state restored and finite
            // No energy is created: implicit Euler dissipates, quasi-static minimises.
            EXPECT_LE(rig.totalEnergy(), e0 + 1e-3 * rig.energyScale());
            ++ok_runs;
          }
  // The grid is not allowed to "pass" by failing everywhere.
  EXPECT_GT(ok_runs, 150);
}

TEST(Stability, ElementInvertedAtStartRecoversForInversionRobustModels) {
  for (const auto& model : kModels)
    for (const auto& integrator : {"implicit_euler_linearized", "implicit_euler_newton"}) {
      if (model == "efg") continue;  // no tets: the mesh's elements do not follow its particles
      SCOPED_TRACE(model + std::string(" / ") + integrator);
      Rig rig(model, integrator, 1e4, 0.3);
      rig.problem.external_force.setZero();
      rig.problem.damping.mass_coefficient = 5.0;
      // Push the top corner node (0.1, 0.1, 0.1) down through its cell.
      const auto corner = regionDofs(
          rig.model->restPositions(),
          Region{Eigen::Vector3d::Constant(kSide - 1e-9), Eigen::Vector3d::Constant(kSide + 1e-9)},
          Eigen::Vector3i(0, 0, 1));
      ASSERT_EQ(corner.size(), 1u);
      rig.state.x[corner[0]] = 0.3 * kSide;
      ASSERT_GT(rig.invertedElements(), 0);
      StepStatus last = StepStatus::Ok;
      for (int k = 0; k < 100; ++k) {
        last = rig.integrator->step(rig.problem, 0.01, rig.state).status;
        ASSERT_TRUE(rig.state.x.allFinite());
        if (isFailureStatus(last)) break;
      }
      if (model == "corotational" || model == "neo_hookean") {
        EXPECT_FALSE(isFailureStatus(last)) << toString(last);
        EXPECT_EQ(rig.invertedElements(), 0);
        EXPECT_NEAR(rig.state.x[corner[0]], kSide, 0.05 * kSide);
      }
    }
}

TEST(Stability, CrushToTenPercentOfHeight) {
  for (const auto& model : kModels)
    for (const auto& integrator : kImplicit) {
      SCOPED_TRACE(model + " / " + integrator);
      Rig rig(model, integrator, 1e4, 0.45);
      rig.problem.external_force.setZero();
      Region top;
      top.min.z() = kSide - 1e-9;
      const auto top_dofs = regionDofs(rig.model->restPositions(), top, Eigen::Vector3i(0, 0, 1));
      const auto n_fixed = rig.problem.dirichlet.dofs.size();
      rig.problem.dirichlet.dofs.insert(rig.problem.dirichlet.dofs.end(), top_dofs.begin(),
                                        top_dofs.end());
      rig.problem.dirichlet.positions.conservativeResize(
          static_cast<Eigen::Index>(rig.problem.dirichlet.dofs.size()));
      const int steps = 30;
      StepStatus last = StepStatus::Ok;
      for (int k = 1; k <= steps && !isFailureStatus(last); ++k) {
        const double height = kSide * (1.0 - 0.9 * k / steps);
        for (std::size_t i = 0; i < top_dofs.size(); ++i)
          rig.problem.dirichlet.positions[static_cast<Eigen::Index>(n_fixed + i)] = height;
        last = rig.integrator->step(rig.problem, 0.01, rig.state).status;
        ASSERT_TRUE(rig.state.x.allFinite());
        ASSERT_TRUE(rig.state.v.allFinite());
      }
      if (!isFailureStatus(last)) {
        for (int d : top_dofs) EXPECT_NEAR(rig.state.x[d], 0.1 * kSide, 1e-12);
      }
      if (model == "neo_hookean" && integrator != std::string("implicit_euler_linearized")) {
        EXPECT_FALSE(isFailureStatus(last)) << toString(last);
      }
    }
}

/// T2 (BENCHMARKS.md) through the whole pipeline: quasi-static Newton + CHOLMOD on the shipped
/// scene reproduces f(l) = (E S0/2) l (l^2 - 1) to solver tolerance: on one element for every
/// l in [0.5, 1.5] (through the compressive peak 9.62 N at l = 1/sqrt3); on a 2x2x2 mesh the
/// homogeneous path holds up to the limit point and then bifurcates (the SVK compressive
/// instability: internal nodes find a lower-energy, non-homogeneous state), so l >= 0.7 there.
TEST(Benchmarks, SvkAndEmsUniaxialCubeMatchClosedForm) {
  BenchmarkScene scene =
      loadBenchmarkScene(std::string(SURGICAL_SIM_SOURCE_DIR) + "/config/bench/t2_svk_cube.yaml");
  const double peak = 20e3 * 0.0025 / (3.0 * std::sqrt(3.0));
  EXPECT_NEAR(peak, 9.62, 0.005);
  for (const ModelKind model : {ModelKind::Svk, ModelKind::Ems})
    for (int cells : {1, 2}) {
      SCOPED_TRACE(std::string(modelName(model)) + " cells=" + std::to_string(cells));
      CaseSpec spec{Eigen::Vector3i::Constant(cells), ElementType::Tet4, model,
                    IntegratorKind::QuasiStatic, SolverKind::Cholmod};
      const CaseResult r = runTissueCase(scene, spec);
      EXPECT_EQ(r.status, StepStatus::Ok);
      ASSERT_EQ(r.path_stretch.size(), 10u);
      for (std::size_t i = 0; i < r.path_stretch.size(); ++i) {
        const double l = r.path_stretch[i];
        const double exact = 0.5 * 20e3 * 0.0025 * l * (l * l - 1.0);
        EXPECT_NEAR(r.path_exact[i], exact, 1e-12);
        if (cells == 1 || l >= 0.7) {
          EXPECT_NEAR(r.path_force[i], exact, 1e-6 * std::abs(exact)) << l;
        }
        EXPECT_LE(-r.path_force[i], peak * (1 + 1e-9)) << "no compressive force beyond the peak";
      }
      if (cells == 1) {
        EXPECT_LT(r.error_rel, 1e-6);
      }
    }
}

/// The same cantilever under self-weight at 1e-3 m, 1 m and 1e3 m scale s, with E = 1e9 s Pa so
/// that the deformed shape is geometrically similar (u scales like rho g L^2 / E ~ s): u / s is
/// scale-invariant even with geometric nonlinearity. Solver tolerances are relative, so all
/// three agree.
TEST(Benchmarks, ScaleRobustCantilever) {
  std::vector<double> normalised;
  for (double s : {1e-3, 1.0, 1e3}) {
    TetMesh mesh = makeBeam(10.0 * s, s, s, Eigen::Vector3i(10, 1, 1), ElementType::Tet10);
    auto model =
        makeTissueModel(ModelKind::Corotational, mesh, Material::create(1e9 * s, 0.3, 1000.0));
    DynamicsProblem problem;
    problem.model = model.get();
    problem.external_force = model->bodyForce(Eigen::Vector3d(0, -9.81, 0));
    Region clamp;
    clamp.max.x() = 1e-9 * s;
    problem.dirichlet.dofs = regionDofs(model->restPositions(), clamp, Eigen::Vector3i::Ones());
    problem.dirichlet.positions =
        Eigen::VectorXd::Zero(static_cast<Eigen::Index>(problem.dirichlet.dofs.size()));
    for (std::size_t i = 0; i < problem.dirichlet.dofs.size(); ++i)
      problem.dirichlet.positions[static_cast<Eigen::Index>(i)] =
          model->restPositions()[problem.dirichlet.dofs[i]];
    SimulationState state{model->restPositions(), Eigen::VectorXd::Zero(3 * mesh.numNodes()), 0};
    IntegratorSettings settings;
    settings.max_iterations = 30;
    settings.relative_tolerance = 1e-10;
    auto integrator = makeIntegrator(IntegratorKind::QuasiStatic, settings,
                                     makeLinearSolver(SolverKind::Cholmod, {}));
    ASSERT_EQ(integrator->step(problem, 1.0, state).status, StepStatus::Ok);
    Region tip;
    tip.min.x() = 10.0 * s * (1 - 1e-9);
    const auto dofs = regionDofs(model->restPositions(), tip, Eigen::Vector3i(0, 1, 0));
    double u = 0.0;
    for (int d : dofs) u += (state.x[d] - model->restPositions()[d]) / dofs.size();
    normalised.push_back(u / s);
  }
  EXPECT_LT(normalised[0], 0.0);
  EXPECT_NEAR(normalised[0] / normalised[1], 1.0, 1e-6);
  EXPECT_NEAR(normalised[2] / normalised[1], 1.0, 1e-6);
}

}  // namespace
}  // namespace surgical_sim::bench
