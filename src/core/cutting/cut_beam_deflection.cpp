#include "surgical_sim/core/cutting/cut_beam_deflection.h"

#include <limits>

#include "surgical_sim/core/cutting/cut_tissue_model.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"

namespace surgical_sim::core {

double cutBeamTipDeflection(const TetCutter& cutter, const std::string& model_name,
                            const Material& material, const Eigen::Vector3d& load) {
  const std::unique_ptr<TissueModel> model = makeCutTissueModel(model_name, cutter, material);
  const TetMesh& mesh = cutter.mesh();
  const double length = mesh.nodes.row(0).maxCoeff();
  DynamicsProblem problem;
  problem.model = model.get();
  problem.external_force = model->bodyForce(load);
  std::vector<int> tip;
  for (int v = 0; v < mesh.numNodes(); ++v) {
    const double x = mesh.nodes(0, v);
    if (x <= 1e-9 * length)
      for (int k = 0; k < 3; ++k) problem.dirichlet.dofs.push_back(3 * v + k);
    if (x >= length * (1.0 - 1e-9)) tip.push_back(v);
  }
  problem.dirichlet.positions.resize(static_cast<Eigen::Index>(problem.dirichlet.dofs.size()));
  for (std::size_t i = 0; i < problem.dirichlet.dofs.size(); ++i)
    problem.dirichlet.positions[static_cast<Eigen::Index>(i)] =
        model->restPositions()[problem.dirichlet.dofs[i]];
  SimulationState state{model->restPositions(),
                        Eigen::VectorXd::Zero(model->restPositions().size()), 0.0};
  IntegratorSettings settings;
  settings.relative_tolerance = 1e-10;
  const auto integrator = makeIntegrator("quasi_static", settings, makeLinearSolver("cholmod", {}));
  if (integrator->step(problem, 1.0, state).status != StepStatus::Ok)
    return std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d direction = load.normalized();
  double sum = 0.0;
  for (int v : tip) sum += (state.x - model->restPositions()).segment<3>(3 * v).dot(direction);
  return sum / static_cast<double>(tip.size());
}

}  // namespace surgical_sim::core
