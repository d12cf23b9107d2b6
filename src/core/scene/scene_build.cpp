#include "surgical_sim/core/scene/scene_build.h"

#include <stdexcept>

#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/gmsh_reader.h"
#include "surgical_sim/core/mesh/mesh_check.h"
#include "surgical_sim/core/mesh/surface_generators.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"

namespace surgical_sim::core {

TetMesh buildSceneMesh(const MeshSpec& spec, const Eigen::Vector3i& res, ElementType type) {
  const std::string problem = meshBudgetProblem(spec, res, type);
  if (!problem.empty())
    throw std::invalid_argument("buildSceneMesh: key 'mesh.resolution': " + problem);
  if (isSurfaceGenerator(spec.generator)) {
    throw std::invalid_argument("buildSceneMesh: key 'mesh.generator': " + spec.generator +
                                " makes a closed surface, not a tet mesh (buildSceneSurface)");
  }
  if (spec.generator == "file") {
    const std::string key = "buildSceneMesh: key 'mesh.file': ";
    TetMesh mesh;
    try {
      mesh = readGmsh(spec.file, spec.metres_per_unit);  // messages start with the path
    } catch (const std::runtime_error& e) {
      throw std::invalid_argument(key + e.what());
    }
    try {
      requireValidMesh(mesh);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(key + spec.file + ": " + e.what());
    }
    if (type == ElementType::Tet10 && mesh.type == ElementType::Tet4) return promoteToTet10(mesh);
    return mesh;
  }
  if (spec.generator == "box") return makeBox(spec.origin, spec.size, res, type, spec.split);
  if (spec.generator == "beam")
    return makeBeam(spec.size[0], spec.size[1], spec.size[2], res, type, spec.split);
  if (spec.generator == "hex_beam")
    return makeHexagonalBeam(spec.hex_side, spec.hex_length, res[0], res[1], type);
  return makeOrganBlob(spec.size, res[0], type);
}

TriMesh buildSceneSurface(const MeshSpec& spec, const Eigen::Vector3i& resolution) {
  if (!isSurfaceGenerator(spec.generator)) {
    throw std::invalid_argument("buildSceneSurface: key 'mesh.generator': " + spec.generator +
                                " makes a tet mesh, not a closed surface (buildSceneMesh)");
  }
  return makeLiverSurface(spec.size, resolution[0]);
}

std::vector<int> regionDofs(const Eigen::VectorXd& rest, const Region& region,
                            const Eigen::Vector3i& components) {
  std::vector<int> dofs;
  for (int n = 0; n < static_cast<int>(rest.size() / 3); ++n)
    if (region.contains(rest.segment<3>(3 * n)))
      for (int c = 0; c < 3; ++c)
        if (components[c]) dofs.push_back(3 * n + c);
  return dofs;
}

void appendRegionDofs(const Eigen::VectorXd& rest, const Region& region,
                      const Eigen::Vector3i& components, const std::string& key,
                      const std::string& scene_path, std::vector<bool>& taken,
                      std::vector<int>& dofs) {
  const std::vector<int> region_dofs = regionDofs(rest, region, components);
  if (region_dofs.empty())
    throw std::invalid_argument("scene " + scene_path + ": key '" + key +
                                ".region' contains no model node");
  for (const int d : region_dofs) {
    if (taken[static_cast<std::size_t>(d)]) continue;
    taken[static_cast<std::size_t>(d)] = true;
    dofs.push_back(d);
  }
}

DirichletBc fixedDirichlet(const SceneBase& scene, const Eigen::VectorXd& rest) {
  DirichletBc bc;
  std::vector<bool> taken(static_cast<std::size_t>(rest.size()), false);
  for (std::size_t i = 0; i < scene.fixed.size(); ++i)
    appendRegionDofs(rest, scene.fixed[i].region, scene.fixed[i].components,
                     "fixed[" + std::to_string(i) + "]", scene.path, taken, bc.dofs);
  bc.positions.resize(static_cast<Eigen::Index>(bc.dofs.size()));
  for (std::size_t i = 0; i < bc.dofs.size(); ++i)
    bc.positions[static_cast<Eigen::Index>(i)] = rest[bc.dofs[i]];
  return bc;
}

std::unique_ptr<Integrator> makeSceneIntegrator(const SceneBase& scene, IntegratorKind integrator,
                                                SolverKind solver, double tolerance) {
  PcgSettings pcg;
  pcg.max_iterations = scene.pcg_max_iterations;
  pcg.relative_tolerance = scene.pcg_tolerance;
  pcg.refresh_interval = scene.pcg_refresh_interval;
  IntegratorSettings settings;
  settings.max_iterations = scene.newton_max_iterations;
  settings.relative_tolerance = tolerance;
  return makeIntegrator(integrator, settings, makeLinearSolver(solver, pcg));
}

}  // namespace surgical_sim::core
