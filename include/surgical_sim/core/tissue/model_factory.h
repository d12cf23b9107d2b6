#pragma once

#include <array>

#include "surgical_sim/core/common/named_enum.h"

#include <memory>
#include <string>

#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/tissue/efg_options.h"
#include "surgical_sim/core/tissue/material.h"
#include "surgical_sim/core/tissue/tissue_model.h"

namespace surgical_sim::core {

/// The tissue models a scene can choose.
enum class ModelKind { MassSpring, Corotational, Svk, Ems, NeoHookean, Efg };

/// Scene / CSV names: mass_spring, corotational, svk, ems, neo_hookean, efg.
inline constexpr std::array<EnumName<ModelKind>, 6> kModelNames{{
    {ModelKind::MassSpring, "mass_spring"},
    {ModelKind::Corotational, "corotational"},
    {ModelKind::Svk, "svk"},
    {ModelKind::Ems, "ems"},
    {ModelKind::NeoHookean, "neo_hookean"},
    {ModelKind::Efg, "efg"},
}};
inline const char* modelName(ModelKind kind) { return enumName(kModelNames, kind); }
/// True for the models defined on linear tets only (mass_spring, ems).
inline bool linearTetOnly(ModelKind kind) {
  return kind == ModelKind::MassSpring || kind == ModelKind::Ems;
}

/// Builds a tissue model: MassSpring (MassSpringModel, Tet4), Corotational, Svk, NeoHookean
/// (FeModel with the corresponding law, Tet4 or Tet10), Ems (EmsModel, Tet4), Efg (EfgModel on
/// the grids of `efg` over the mesh's volume; `efg` is ignored by the other kinds).
/// @throws the model constructor's exceptions for invalid meshes / materials / efg options.
std::unique_ptr<TissueModel> makeTissueModel(ModelKind kind, const TetMesh& mesh,
                                             const Material& material, const EfgOptions& efg = {});

}  // namespace surgical_sim::core
