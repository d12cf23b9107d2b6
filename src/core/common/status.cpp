#include "surgical_sim/core/common/status.h"

namespace surgical_sim::core {

const char* toString(StepStatus status) {
  switch (status) {
    case StepStatus::Ok:
      return "ok";
    case StepStatus::NotConverged:
      return "not_converged";
    case StepStatus::SolverFailed:
      return "solver_failed";
    case StepStatus::NonFinite:
      return "non_finite";
    case StepStatus::BlowUp:
      return "blow_up";
    case StepStatus::ContactLimited:
      return "contact_limited";
    case StepStatus::CutRefused:
      return "cut_refused";
  }
  return "unknown";
}

}  // namespace surgical_sim::core
