#include "surgical_sim/core/robot/full_fe_plant.h"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

#include "surgical_sim/core/common/validate.h"
#include "surgical_sim/core/robot/chamber_pressure_model.h"
#include "surgical_sim/core/robot/pressure_chamber_actuator.h"
#include "surgical_sim/core/robot/summed_tissue_model.h"
#include "surgical_sim/core/robot/tendon_model.h"
#include "surgical_sim/core/robot/tube_mesh.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::core {

void validateFullFePlantSettings(const FullFePlantSettings& s) {
  requireInRange("full_fe_plant.vertebra_stiffness_ratio", s.vertebra_stiffness_ratio, 1.0, 1e9,
                 "");
  requireInRange("full_fe_plant.follower_iterations", s.follower_iterations, 1, 1000, "");
  requirePositive("full_fe_plant.follower_tolerance", s.follower_tolerance, "");
  validateIntegratorSettings(s.newton);
}

FullFePlant::FullFePlant(const ContinuumRobotModel& model, const FullFePlantSettings& settings)
    : model_(model), settings_(settings) {
  validateFullFePlantSettings(settings_);
  const ContinuumRobotDescription& d = model_.description();
  if (!(d.vertebra_thickness > 0.0))
    throw std::invalid_argument("robot." + d.name +
                                ".vertebra_thickness must be > 0 for the FE plant");
  const int n = d.num_vertebrae;
  const double s = d.vertebra_spacing, h = 0.5 * d.vertebra_thickness;
  std::vector<double> stations{h};
  for (int k = 0; k < n; ++k) {
    for (int i = 1; i <= d.mesh.axial_layers; ++i)
      stations.push_back(k * s + h + (s - 2.0 * h) * i / d.mesh.axial_layers);
    stations.push_back((k + 1) * s);
    stations.push_back((k + 1) * s + h);
  }
  const TetMesh mesh = makeTubeMesh(stations, d.inner_radius, d.outerRadiusAt(stations.front()),
                                    d.outerRadiusAt(stations.back()), d.mesh.radial_layers,
                                    d.mesh.circumferential_segments);
  TetMesh soft = mesh, stiff = mesh;
  int n_soft = 0, n_stiff = 0;
  soft.elements.resize(4, mesh.numElements());
  stiff.elements.resize(4, mesh.numElements());
  for (int e = 0; e < mesh.numElements(); ++e) {
    double xc = 0.0;
    for (int a = 0; a < 4; ++a) xc += 0.25 * mesh.nodes(0, mesh.elements(a, e));
    const double u = xc / s;
    const bool in_vertebra = std::abs(u - std::round(u)) * s < h && std::round(u) >= 1;
    if (in_vertebra)
      stiff.elements.col(n_stiff++) = mesh.elements.col(e);
    else
      soft.elements.col(n_soft++) = mesh.elements.col(e);
  }
  soft.elements.conservativeResize(4, n_soft);
  stiff.elements.conservativeResize(4, n_stiff);
  const Material stiff_material =
      Material::create(d.material.young_modulus * settings_.vertebra_stiffness_ratio,
                       d.material.poisson_ratio, d.material.density);
  std::vector<std::unique_ptr<TissueModel>> parts;
  parts.push_back(makeTissueModel(ModelKind::Corotational, soft, d.material));
  parts.push_back(makeTissueModel(ModelKind::Corotational, stiff, stiff_material));
  for (size_t a = 0; a < d.chambers.size(); ++a) {
    const auto& chamber = dynamic_cast<const PressureChamberActuator&>(*model_.actuators()[a]);
    auto pressure = std::make_unique<ChamberPressureModel>(
        mesh, chamber.vertexPositions(model_.restNodes()), chamber.triangles());
    chambers_.push_back(pressure.get());
    parts.push_back(std::move(pressure));
  }
  for (const CableDescription& c : d.cables) {
    std::vector<Eigen::Vector3d> eyelets;
    for (int k = 0; k <= c.last_vertebra; ++k)
      eyelets.emplace_back(k == 0 ? h : k * s, c.radial_offset * std::cos(c.angle),
                           c.radial_offset * std::sin(c.angle));
    auto tendon = std::make_unique<TendonModel>(mesh, eyelets);
    tendons_.push_back(tendon.get());
    parts.push_back(std::move(tendon));
  }
  tissue_ = std::make_unique<SummedTissueModel>(std::move(parts));

  const double tol = 1e-9 * s;
  vertebra_nodes_.assign(n + 1, {});
  for (int i = 0; i < mesh.numNodes(); ++i) {
    const double x = mesh.nodes(0, i);
    if (x <= h + tol)
      for (int c = 0; c < 3; ++c) problem_.dirichlet.dofs.push_back(3 * i + c);
    const int k = static_cast<int>(std::lround(x / s));
    if (k >= 1 && std::abs(x - k * s) <= h + tol) vertebra_nodes_[k].push_back(i);
  }
  problem_.model = tissue_.get();
  problem_.dirichlet.positions.resize(problem_.dirichlet.dofs.size());
  for (size_t j = 0; j < problem_.dirichlet.dofs.size(); ++j)
    problem_.dirichlet.positions[j] = tissue_->restPositions()[problem_.dirichlet.dofs[j]];
  gravity_force_ = d.gravity_enabled ? tissue_->bodyForce(Eigen::Vector3d(0.0, 0.0, -9.81))
                                     : Eigen::VectorXd::Zero(3 * mesh.numNodes());
  problem_.external_force = gravity_force_;
  integrator_ = makeIntegrator(IntegratorKind::QuasiStatic, settings_.newton,
                               makeLinearSolver(SolverKind::Cholmod, PcgSettings{}));
  poses_ = model_.restNodes();
  wrench_.resize(6 * (n + 1));
  reset();
}

FullFePlant::~FullFePlant() = default;

int FullFePlant::numNodes() const { return tissue_->numNodes(); }

void FullFePlant::reset() {
  state_.x = tissue_->restPositions();
  state_.v = Eigen::VectorXd::Zero(state_.x.size());
  state_.time = 0.0;
  integrator_->reset();
  fitPoses();
}

void FullFePlant::fitPoses() {
  const auto& rest = tissue_->restPositions();
  for (size_t k = 1; k < vertebra_nodes_.size(); ++k) {
    const auto& ids = vertebra_nodes_[k];
    Eigen::Vector3d c = Eigen::Vector3d::Zero(), c0 = Eigen::Vector3d::Zero();
    for (int i : ids) {
      c += state_.x.segment<3>(3 * i);
      c0 += rest.segment<3>(3 * i);
    }
    c /= ids.size();
    c0 /= ids.size();
    Eigen::Matrix3d Hm = Eigen::Matrix3d::Zero();
    for (int i : ids)
      Hm += (rest.segment<3>(3 * i) - c0) * (state_.x.segment<3>(3 * i) - c).transpose();
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(Hm, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
    const Eigen::Matrix3d R = svd.matrixV() * D * svd.matrixU().transpose();
    poses_[k].q_BN = Eigen::Quaterniond(R).normalized();
    poses_[k].p_BN = c - R * (c0 - model_.restNodes()[k].p_BN);
  }
}

void FullFePlant::buildLoads(const Eigen::VectorXd& actuation) {
  wrench_.setZero();
  const int n_chambers = static_cast<int>(chambers_.size());
  for (int a = 0; a < n_chambers; ++a) chambers_[a]->setPressure(actuation[a]);
  for (size_t c = 0; c < tendons_.size(); ++c) tendons_[c]->setTension(actuation[n_chambers + c]);
  wrench_.segment<3>(wrench_.size() - 6) += tip_force_;
  problem_.external_force = gravity_force_;
  for (size_t k = 1; k < vertebra_nodes_.size(); ++k) {
    const auto& ids = vertebra_nodes_[k];
    const Eigen::Vector3d c = poses_[k].p_BN;
    const Eigen::Vector3d F = wrench_.segment<3>(6 * k);
    // Torque about the node set's centroid.
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int i : ids) centroid += state_.x.segment<3>(3 * i);
    centroid /= ids.size();
    const Eigen::Vector3d M = wrench_.segment<3>(6 * k + 3) + (c - centroid).cross(F);
    Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
    for (int i : ids) {
      const Eigen::Vector3d r = state_.x.segment<3>(3 * i) - centroid;
      J += r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose();
    }
    const Eigen::Vector3d w = J.ldlt().solve(M);
    for (int i : ids) {
      const Eigen::Vector3d r = state_.x.segment<3>(3 * i) - centroid;
      problem_.external_force.segment<3>(3 * i) += F / ids.size() + w.cross(r);
    }
  }
}

StepReport FullFePlant::solve(const Eigen::VectorXd& actuation) {
  StepReport report;
  const double length = model_.description().length();
  for (int pass = 0; pass < settings_.follower_iterations; ++pass) {
    fitPoses();
    buildLoads(actuation);
    const Eigen::Vector3d tip_before = tipPosition();
    const StepReport r = integrator_->step(problem_, 0.0, state_);
    report.newton_iterations += r.newton_iterations;
    report.linear_iterations += r.linear_iterations;
    report.residual = r.residual;
    report.status = r.status;
    if (r.status != StepStatus::Ok && r.status != StepStatus::NotConverged) return report;
    fitPoses();
    if ((tipPosition() - tip_before).norm() <= settings_.follower_tolerance * length && pass > 0)
      return report;
  }
  if (report.status == StepStatus::Ok) report.status = StepStatus::NotConverged;
  return report;
}

Eigen::Vector3d FullFePlant::tipPosition() const { return poses_.back().p_BN; }

}  // namespace surgical_sim::core
