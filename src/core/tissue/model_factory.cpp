#include "surgical_sim/core/tissue/model_factory.h"

#include <stdexcept>

#include "surgical_sim/core/tissue/corotational_law.h"
#include "surgical_sim/core/tissue/ems_model.h"
#include "surgical_sim/core/tissue/fe_model.h"
#include "surgical_sim/core/tissue/mass_spring_model.h"
#include "surgical_sim/core/tissue/st_venant_kirchhoff_law.h"
#include "surgical_sim/core/tissue/stable_neo_hookean_law.h"

namespace surgical_sim::core {

std::unique_ptr<TissueModel> makeTissueModel(const std::string& name, const TetMesh& mesh,
                                             const Material& material) {
  if (name == "mass_spring") return std::make_unique<MassSpringModel>(mesh, material);
  if (name == "ems") return std::make_unique<EmsModel>(mesh, material);
  if (name == "corotational") {
    return std::make_unique<FeModel>(mesh, material, std::make_unique<CorotationalLaw>(material));
  }
  if (name == "svk") {
    return std::make_unique<FeModel>(mesh, material,
                                     std::make_unique<StVenantKirchhoffLaw>(material));
  }
  if (name == "neo_hookean") {
    return std::make_unique<FeModel>(mesh, material,
                                     std::make_unique<StableNeoHookeanLaw>(material));
  }
  throw std::invalid_argument("tissue.model = '" + name +
                              "' is unknown (expected mass_spring, corotational, svk, ems, "
                              "neo_hookean)");
}

}  // namespace surgical_sim::core
