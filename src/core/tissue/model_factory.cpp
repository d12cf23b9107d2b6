#include "surgical_sim/core/tissue/model_factory.h"

#include <stdexcept>

#include "surgical_sim/core/tissue/corotational_law.h"
#include "surgical_sim/core/tissue/efg_model.h"
#include "surgical_sim/core/tissue/ems_model.h"
#include "surgical_sim/core/tissue/fe_model.h"
#include "surgical_sim/core/tissue/mass_spring_model.h"
#include "surgical_sim/core/tissue/st_venant_kirchhoff_law.h"
#include "surgical_sim/core/tissue/stable_neo_hookean_law.h"

namespace surgical_sim::core {

std::unique_ptr<TissueModel> makeTissueModel(ModelKind kind, const TetMesh& mesh,
                                             const Material& material, const EfgOptions& efg) {
  switch (kind) {
    case ModelKind::MassSpring:
      return std::make_unique<MassSpringModel>(mesh, material);
    case ModelKind::Ems:
      return std::make_unique<EmsModel>(mesh, material);
    case ModelKind::Corotational:
      return std::make_unique<FeModel>(mesh, material, std::make_unique<CorotationalLaw>(material));
    case ModelKind::Svk:
      return std::make_unique<FeModel>(mesh, material,
                                       std::make_unique<StVenantKirchhoffLaw>(material));
    case ModelKind::NeoHookean:
      return std::make_unique<FeModel>(mesh, material,
                                       std::make_unique<StableNeoHookeanLaw>(material));
    case ModelKind::Efg:
      return std::make_unique<EfgModel>(mesh, material, efg);
  }
  throw std::invalid_argument("makeTissueModel: invalid ModelKind");
}

}  // namespace surgical_sim::core
