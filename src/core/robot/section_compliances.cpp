#include "surgical_sim/core/robot/section_compliances.h"

#include <cstdio>
#include <map>

#include "surgical_sim/core/common/stopwatch.h"
#include "surgical_sim/core/robot/compliance_cache.h"
#include "surgical_sim/core/robot/section_condensation.h"
#include "surgical_sim/core/robot/tube_mesh.h"

namespace surgical_sim::core {

std::vector<double> sectionStations(const ContinuumRobotDescription& d, int gap) {
  const double start = gap * d.vertebra_spacing + 0.5 * d.vertebra_thickness;
  const double end = (gap + 1) * d.vertebra_spacing - 0.5 * d.vertebra_thickness;
  std::vector<double> stations(d.mesh.axial_layers + 1);
  for (int i = 0; i <= d.mesh.axial_layers; ++i)
    stations[i] = start + (end - start) * i / d.mesh.axial_layers;
  return stations;
}

std::string sectionCacheKey(const ContinuumRobotDescription& d, int gap) {
  const std::vector<double> st = sectionStations(d, gap);
  char buf[512];
  std::snprintf(buf, sizeof(buf),
                "tube_section v1 length=%.17g spacing=%.17g inner=%.17g outer0=%.17g "
                "outer1=%.17g E=%.17g nu=%.17g res=%d,%d,%d",
                st.back() - st.front(), d.vertebra_spacing, d.inner_radius,
                d.outerRadiusAt(st.front()), d.outerRadiusAt(st.back()), d.material.young_modulus,
                d.material.poisson_ratio, d.mesh.radial_layers, d.mesh.circumferential_segments,
                d.mesh.axial_layers);
  return buf;
}

SectionCompliances computeSectionCompliances(const ContinuumRobotDescription& d,
                                             const std::string& cache_directory) {
  validateContinuumRobotDescription(d);
  const Stopwatch clock;
  const ComplianceCache cache(cache_directory);
  SectionCompliances out;
  out.compliance.resize(d.num_vertebrae);
  std::map<std::string, Eigen::Matrix<double, 6, 6>> computed;
  bool progress_shown = false;
  for (int gap = 0; gap < d.num_vertebrae; ++gap) {
    const std::string key = sectionCacheKey(d, gap);
    Eigen::Matrix<double, 6, 6> C;
    if (const auto it = computed.find(key); it != computed.end()) {
      C = it->second;
    } else if (cache.load(key, C)) {
      ++out.cache_hits;
    } else {
      // Mesh in the proximal rigid node's frame: shift x by -x_gap.
      std::vector<double> st = sectionStations(d, gap);
      const double x_gap = gap * d.vertebra_spacing;
      const double r0 = d.outerRadiusAt(st.front()), r1 = d.outerRadiusAt(st.back());
      for (double& s : st) s -= x_gap;
      const TetMesh mesh = makeTubeMesh(st, d.inner_radius, r0, r1, d.mesh.radial_layers,
                                        d.mesh.circumferential_segments);
      C = condenseSection(mesh, d.material, st.front(), st.back(),
                          Eigen::Vector3d(d.vertebra_spacing, 0.0, 0.0));
      cache.store(key, C);
    }
    computed[key] = C;
    out.compliance[gap] = C;
    if (clock.seconds() > 1.0 || (progress_shown && gap + 1 == d.num_vertebrae)) {
      const int width = 30, done = width * (gap + 1) / d.num_vertebrae;
      std::fprintf(stderr, "\r[%-*s] condensing %s sections %d/%d (%.1f s)", width,
                   std::string(done, '#').c_str(), d.name.c_str(), gap + 1, d.num_vertebrae,
                   clock.seconds());
      progress_shown = true;
    }
  }
  if (progress_shown) std::fprintf(stderr, "\n");
  out.seconds = clock.seconds();
  return out;
}

}  // namespace surgical_sim::core
