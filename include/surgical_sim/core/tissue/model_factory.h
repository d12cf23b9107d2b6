#pragma once

#include <array>

#include "surgical_sim/core/common/named_enum.h"

#include <memory>
#include <string>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/material.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// The tissue models a scene can choose.
enum class ModelKind { MassSpring, Corotational, Svk, Ems, NeoHookean };

/// Scene / CSV names: mass_spring, corotational, svk, ems, neo_hookean.
inline constexpr std::array<EnumName<ModelKind>, 5> kModelNames{{
    {ModelKind::MassSpring, "mass_spring"},
    {ModelKind::Corotational, "corotational"},
    {ModelKind::Svk, "svk"},
    {ModelKind::Ems, "ems"},
    {ModelKind::NeoHookean, "neo_hookean"},
}};
inline const char* modelName(ModelKind kind) { return enumName(kModelNames, kind); }
/// True for the models defined on linear tets only (mass_spring, ems).
inline bool linearTetOnly(ModelKind kind) {
  return kind == ModelKind::MassSpring || kind == ModelKind::Ems;
}

/// Builds a tissue model: MassSpring (MassSpringModel, Tet4), Corotational, Svk, NeoHookean
/// (FeModel with the corresponding law, Tet4 or Tet10), Ems (EmsModel, Tet4).
/// @throws the model constructor's exceptions for invalid meshes / materials.
std::unique_ptr<TissueModel> makeTissueModel(ModelKind kind, const TetMesh& mesh,
                                             const Material& material);

}  // namespace surgical_sim::core
