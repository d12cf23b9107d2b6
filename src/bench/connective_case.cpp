#include "surgical_sim/bench/connective_case.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <sstream>
#include <stdexcept>
#include <string>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/connective/rigid_node_implicit_euler.h"
#include "surgical_sim/core/connective/rigid_node_quasi_static.h"
#include "surgical_sim/core/connective/rigid_node_sampling.h"
#include "surgical_sim/core/mesh/generators.h"

namespace surgical_sim::bench {

namespace {

void checkSpec(const RigidNodeBeamSpec& spec) {
  auto fail = [](const std::string& field, double value, const char* range) {
    std::ostringstream message;
    message << "runRigidNodeBeam: " << field << " = " << value << " must be " << range;
    throw std::invalid_argument(message.str());
  };
  for (int a = 0; a < 3; ++a) {
    if (!(std::isfinite(spec.size[a]) && spec.size[a] > 0.0))
      fail("size[" + std::to_string(a) + "]", spec.size[a], "finite and > 0");
    if (spec.cells[a] < 1) fail("cells[" + std::to_string(a) + "]", spec.cells[a], ">= 1");
  }
  if (!spec.gravity.allFinite()) fail("gravity", spec.gravity.norm(), "finite");
  if (spec.component < 0 || spec.component > 2) fail("component", spec.component, "in [0, 2]");
  if (spec.load_steps < 0) fail("load_steps", spec.load_steps, ">= 0");
  if (!(spec.relative_tolerance > 0.0 && spec.relative_tolerance < 1.0))
    fail("relative_tolerance", spec.relative_tolerance, "in (0, 1)");
  if (spec.max_iterations < 1) fail("max_iterations", spec.max_iterations, ">= 1");
  if (spec.timed_steps < 0) fail("timed_steps", spec.timed_steps, ">= 0");
  if (!(std::isfinite(spec.time_step) && spec.time_step > 0.0))
    fail("time_step", spec.time_step, "finite and > 0");
  if (!(std::isfinite(spec.mass_damping) && spec.mass_damping >= 0.0))
    fail("mass_damping", spec.mass_damping, "finite and >= 0");
  core::validateRigidNodeImplicitEulerSettings(spec.integrator);
}

RigidNodeLayout beamLayout(const RigidNodeBeamSpec& spec) {
  if (spec.weights == RigidNodeWeights::Tet) {
    return tetMeshLayout(
        makeBeam(spec.size.x(), spec.size.y(), spec.size.z(), spec.cells, ElementType::Tet4),
        spec.material);
  }
  const Eigen::Vector3d min_corner(0.0, -0.5 * spec.size.y(), -0.5 * spec.size.z());
  return trilinearGridLayout(min_corner, spec.size, spec.cells + Eigen::Vector3i::Ones(),
                             spec.material);
}

}  // namespace

const char* rigidNodeWeightsName(RigidNodeWeights weights) {
  return weights == RigidNodeWeights::Tet ? "tet" : "trilinear";
}

RigidNodeBeamSpec t1CantileverSpec(const Eigen::Vector3i& nodes) {
  RigidNodeBeamSpec spec;
  spec.size = Eigen::Vector3d(16.0, 0.5, 0.5);
  spec.material = Material::create(200e9, 0.3, 7800.0);
  spec.gravity = Eigen::Vector3d(0, -9.81, 0);
  spec.component = 1;
  spec.cells = nodes - Eigen::Vector3i::Ones();
  spec.relative_tolerance = 1e-8;
  return spec;
}

double threadCpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

RigidNodeBeamResult runRigidNodeBeam(const RigidNodeBeamSpec& spec) {
  checkSpec(spec);
  const RigidNodeLayout layout = beamLayout(spec);
  const RigidNodeModel model(layout.rest, layout.samples);
  RigidNodeBeamResult result;
  result.nodes = model.numNodes();
  result.samples = model.numSamples();
  result.dofs = model.numDofs();
  const double tolerance = 1e-9 * spec.size.x();
  RigidNodeProblem problem;
  problem.model = &model;
  for (int i = 0; i < model.numNodes(); ++i)
    if (std::abs(layout.rest.p_TN[i].x()) <= tolerance)
      for (int c = 0; c < kRigidNodeDofs; ++c) problem.fixed_dofs.push_back(kRigidNodeDofs * i + c);
  auto keep = [&](StepStatus status) {
    if (result.status == StepStatus::Ok) result.status = status;
  };
  auto failed = [](StepStatus status) {
    return status != StepStatus::Ok && status != StepStatus::NotConverged;
  };

  if (spec.load_steps > 0) {
    RigidNodeNewtonSettings settings;
    settings.relative_tolerance = spec.relative_tolerance;
    settings.max_iterations = spec.max_iterations;
    RigidNodeQuasiStatic solver(settings);
    RigidNodeConfiguration q = layout.rest;
    const Stopwatch watch;
    for (int k = 1; k <= spec.load_steps && !failed(result.status); ++k) {
      problem.body_acceleration = spec.gravity * (static_cast<double>(k) / spec.load_steps);
      const StepReport report = solver.solve(problem, q);
      result.newton_iterations += report.newton_iterations;
      result.residual = std::max(result.residual, report.residual);
      keep(report.status);
    }
    result.solve_ms = watch.milliseconds();
    if (!failed(result.status)) {
      double sum = 0.0;
      int count = 0;
      for (int i = 0; i < model.numNodes(); ++i) {
        if (std::abs(layout.rest.p_TN[i].x() - spec.size.x()) > tolerance) continue;
        sum += q.p_TN[i][spec.component] - layout.rest.p_TN[i][spec.component];
        ++count;
      }
      result.tip = sum / count;
    }
  }

  if (spec.timed_steps > 0) {
    problem.body_acceleration = spec.gravity;
    problem.mass_damping = spec.mass_damping;
    RigidNodeState state;
    state.configuration = layout.rest;
    state.velocity.setZero(model.numDofs());
    RigidNodeImplicitEuler integrator(spec.integrator);
    StepStatus status = integrator.step(problem, spec.time_step, state).status;
    StepPhaseTimes sum;
    const Stopwatch watch;
    const double cpu = threadCpuSeconds();
    const int untimed_factorizations = integrator.factorizations();
    int steps = 0, linear_iterations = 0;
    for (; steps < spec.timed_steps && status == StepStatus::Ok; ++steps) {
      const StepReport report = integrator.step(problem, spec.time_step, state);
      status = report.status;
      sum.forces += report.phases.forces;
      sum.factorization += report.phases.factorization;
      sum.linear_solve += report.phases.linear_solve;
      linear_iterations += report.linear_iterations;
    }
    result.factorizations = integrator.factorizations() - untimed_factorizations;
    keep(status);
    if (steps > 0) {
      result.ms_per_step = watch.milliseconds() / steps;
      result.cpu_ms_per_step = 1e3 * (threadCpuSeconds() - cpu) / steps;
      result.forces_ms = 1e3 * sum.forces / steps;
      result.factor_ms = 1e3 * sum.factorization / steps;
      result.linear_solve_ms = 1e3 * sum.linear_solve / steps;
      result.linear_iterations = static_cast<double>(linear_iterations) / steps;
    }
  }
  return result;
}

}  // namespace surgical_sim::bench
