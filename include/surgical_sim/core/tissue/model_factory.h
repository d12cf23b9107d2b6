#pragma once

#include <memory>
#include <string>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/material.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// Builds a tissue model by name: "mass_spring" (MassSpringModel, Tet4), "corotational",
/// "svk", "neo_hookean" (FeModel with the corresponding law, Tet4 or Tet10), "ems" (EmsModel,
/// Tet4).
/// @throws std::invalid_argument "tissue.model = 'foo' is unknown (expected mass_spring,
///         corotational, svk, ems, neo_hookean)" for unknown names, and the model constructor's
///         exceptions for invalid meshes / materials.
std::unique_ptr<TissueModel> makeTissueModel(const std::string& name, const TetMesh& mesh,
                                             const Material& material);

}  // namespace surgical_sim::core
