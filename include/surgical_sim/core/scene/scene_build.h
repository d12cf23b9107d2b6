#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/scene/scene_config.h"
#include "surgical_sim/core/solve/dynamics_problem.h"
#include "surgical_sim/core/solve/integrator.h"

namespace surgical_sim::core {

/// Builds the scene's mesh at one resolution and element type (metres).
/// @throws std::invalid_argument on bad generator arguments, naming 'mesh.generator' for a surface
///         generator (buildSceneSurface()); naming 'mesh.file' and the file
///         for a mesh file that cannot be read or fails requireValidMesh(); naming
///         'mesh.resolution' before allocating anything when the mesh exceeds the memory budget
///         (meshBudgetProblem()).
TetMesh buildSceneMesh(const MeshSpec& spec, const Eigen::Vector3i& resolution, ElementType type);

/// Builds the closed surface of a surface generator (isSurfaceGenerator(): `liver`, at
/// resolution {subdivisions, -, -}) in metres; buildSceneMesh() rejects these generators.
/// @throws std::invalid_argument naming 'mesh.generator' for a tet-mesh generator, or the bad
///         generator argument.
TriMesh buildSceneSurface(const MeshSpec& spec, const Eigen::Vector3i& resolution);

/// Node-major DOF indices of every model node whose rest position (`rest`, size 3n [m]: a tissue
/// model's restPositions(), the mesh nodes for tet models, the particles for efg) lies in
/// `region`, for the set components.
std::vector<int> regionDofs(const Eigen::VectorXd& rest, const Region& region,
                            const Eigen::Vector3i& components);

/// Appends to `dofs` the DOFs of `region` (set components) not yet marked in `taken` (size 3n),
/// and marks them: the first boundary condition that names a DOF keeps it.
/// @throws std::invalid_argument "scene <scene_path>: key '<key>.region' contains no model node".
void appendRegionDofs(const Eigen::VectorXd& rest, const Region& region,
                      const Eigen::Vector3i& components, const std::string& key,
                      const std::string& scene_path, std::vector<bool>& taken,
                      std::vector<int>& dofs);

/// The scene's fixed DOFs (every `fixed` entry, in order), held at the rest positions `rest`.
/// @throws std::invalid_argument as appendRegionDofs().
DirichletBc fixedDirichlet(const SceneBase& scene, const Eigen::VectorXd& rest);

/// The integrator `integrator` with linear solver `solver` and the scene's Newton / PCG settings,
/// Newton converging at `tolerance` (relative residual).
std::unique_ptr<Integrator> makeSceneIntegrator(const SceneBase& scene, IntegratorKind integrator,
                                                SolverKind solver, double tolerance);

}  // namespace surgical_sim::core
