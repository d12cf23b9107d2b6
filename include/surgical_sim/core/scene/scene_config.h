#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "surgical_sim/core/contact/contact_phase.h"
#include "surgical_sim/core/mesh/generators.h"
#include "surgical_sim/core/mesh/tet_mesh.h"
#include "surgical_sim/core/solve/make_integrator.h"
#include "surgical_sim/core/solve/make_linear_solver.h"
#include "surgical_sim/core/tissue/efg_options.h"
#include "surgical_sim/core/tissue/material.h"
#include "surgical_sim/core/tissue/model_factory.h"

namespace surgical_sim::core {

/// Axis-aligned region in the tissue rest frame [m]; a node belongs to it when
/// min <= p <= max component-wise (missing bounds are +-infinity in the YAML).
struct Region {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  Eigen::Vector3d max = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  bool contains(const Eigen::Vector3d& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
};

/// Where the mesh comes from: exactly one generator and its geometry (the resolution and element
/// type are chosen by the runtime scene, or swept by a benchmark scene).
struct MeshSpec {
  std::string generator;  ///< "box", "beam", "hex_beam", "organ_blob", "liver" or "file"
  // box / beam / organ_blob / liver
  Eigen::Vector3d size =
      Eigen::Vector3d::Zero();  ///< box/beam edge lengths, blob/liver semi-axes [m]
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< box min corner [m]
  CellSplit split = CellSplit::Symmetric;            ///< box / beam cell split (mesh.split)
  // hex_beam
  double hex_side = 0.0;    ///< side of the regular hexagon [m]
  double hex_length = 0.0;  ///< beam length along x [m]
  // file
  std::string file;            ///< Gmsh .msh path (relative paths: to the scene file)
  double metres_per_unit = 1;  ///< from mesh.unit ("m", "cm", "mm", "um")
};

/// True for a generator that makes a closed triangle surface instead of a tet mesh ("liver":
/// makeLiverSurface()); only the efg model fills such a body.
inline bool isSurfaceGenerator(const std::string& generator) { return generator == "liver"; }

/// A group of constrained DOFs: the listed components of every node in region.
struct FixedBc {
  Region region;
  Eigen::Vector3i components = Eigen::Vector3i::Ones();  ///< 1 = constrained (x, y, z)
};

/// Nodes in region are displaced by `displacement` times the current load factor.
struct PrescribedBc {
  Region region;
  Eigen::Vector3i components = Eigen::Vector3i::Ones();
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  ///< [m] at load factor 1
};

/// What error_rel is measured against.
struct MeasureSpec {
  /// "tip_displacement": mean displacement component of the nodes in region vs reference [m];
  /// "uniaxial_svk_force": reaction force on the prescribed region along `component` at each
  ///   stretch in load_factors vs (E S0/2) l (l^2 - 1); error = max relative over the path;
  /// "self_reference": final positions vs a tight Newton run of the same mesh (relative
  ///   residual 1e-10) with reference_solver.
  std::string type;
  /// self_reference only: the reference run's linear solver (key 'reference_solver', default
  /// cholmod; an iterative one solves each Newton system to a relative residual of 1e-10).
  SolverKind reference_solver = SolverKind::Cholmod;
  Region region;
  int component = 0;                ///< 0 = x, 1 = y, 2 = z
  std::optional<double> reference;  ///< tip_displacement reference [m] (sign included)
  std::string reference_formula;    ///< or: "euler_bernoulli_timoshenko", "axial_self_weight"
  double face_area = 0.0;           ///< uniaxial_svk_force: S0 [m^2]
  double rest_length = 0.0;         ///< uniaxial_svk_force: L0 [m]
};

/// The jaws of a tool: nodes within `radius` of the tip are held while the jaws are closed. The
/// jaws follow a std_msgs/Bool topic, a device joint, or both (the last message wins).
struct GraspSpec {
  double radius = 0.0;  ///< [m], (0, 0.05]
  std::string topic;    ///< std_msgs/Bool jaws (true = closed); empty: none
  /// The joint `joint` of the sensor_msgs/JointState messages on joint_topic closes the jaws at
  /// or below closed_angle [rad] (trocar grip: 0 = closed); empty: none.
  std::string joint;
  std::string joint_topic;
  double closed_angle = 0.05;  ///< [rad], [-pi, pi]
};

/// A surgical instrument touching the tissue (tissue_simulator). The tool is a capsule: the tip
/// pose comes from pose_topic; the shaft runs back from the tip along the tool's -z axis. What
/// the tool does not use is absent: a proxy tool has a proxy stiffness and no coupling, a
/// constraint tool the reverse; a tool without jaws has no grasp; a tool without contact has
/// none of these.
struct ToolSpec {
  std::string name;                 ///< unique, [A-Za-z][A-Za-z0-9_]*
  std::string pose_topic;           ///< geometry_msgs/PoseStamped (tip)
  std::string wrench_topic;         ///< WrenchStamped output
  std::string contact_model_topic;  ///< ContactModel output
  /// How the tool touches the tissue; none: it touches nothing (e.g. it only carries a blade)
  /// and has no capsule, coupling, proxy or jaws.
  std::optional<ContactResponse> contact;
  double radius = 0.0;                    ///< capsule radius [m], (0, 0.05]
  double shaft_length = 0.0;              ///< capsule length behind the tip [m], [0, 1]
  std::optional<double> proxy_stiffness;  ///< proxy spring [N/m], (0, 1e6]; proxy tools only
  /// Constraint tools: the simulated tool body follows the commanded pose through this spring
  /// [N/m], [1, 1e7]. Default 1e4: about 30x the tissue under a 5 mm tool (50-300 N/m), so a
  /// palpation force changes by a few percent while a push against fixed tissue stays bounded.
  double coupling_stiffness = 1e4;
  /// Constraint tools: damper in parallel with the coupling spring [N s/m], [0, 1e5]. Default 0
  /// (a pure spring); b > 0 makes the tool body lag its commanded pose like a spring-damper.
  double coupling_damping = 0.0;
  /// Cap on the tool's contact force and grasp force (the jaws slip above it) [N], [1e-3, 1e4].
  /// Default 20 N: above what a laparoscopic instrument applies to soft tissue in palpation.
  double max_force = 20.0;
  std::optional<GraspSpec> grasp;  ///< none: the tool has no jaws
};

/// An active trocar (trocar_device node) holding one of the scene's tools.
struct TrocarSpec {
  std::string name;  ///< unique; namespace, tf frame and joint prefix "<name>_" of the device
  int tool = 0;      ///< index into the scene's tools
  Eigen::Isometry3d X_WF = Eigen::Isometry3d::Identity();  ///< fulcrum frame F in world
};

/// A cutting blade (cutting_tool node) carried by one of the scene's tools.
struct BladeSpec {
  int tool = 0;           ///< index into the scene's tools
  Eigen::Matrix3Xd edge;  ///< polyline in the tool frame [m], 2..1000 points
};

/// The continuum robot (continuum_robot_controller node).
struct RobotSpec {
  std::string description;  ///< a key of config/continuum_robot.yaml (trunk, cable)
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();  ///< robot_base in world
};

/// An FE organ of a multi-body scene (key bodies[i]).
struct BodySpec {
  std::string name;  ///< unique among bodies and connective layers, [A-Za-z][A-Za-z0-9_]*
  MeshSpec mesh;     ///< a tet-mesh generator or file (tet4)
  Eigen::Vector3i resolution = Eigen::Vector3i::Zero();  ///< generated meshes only
  ModelKind model = ModelKind::Corotational;             ///< any tet model but efg
  Material material;
  /// Rest pose of the mesh in the scene (tissue) frame: the generated or read mesh is moved by it.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  /// Nodes held at rest: those whose position in the mesh frame (before `pose`) lies in a region.
  std::vector<Region> fixed;
  Eigen::Vector3f colour = Eigen::Vector3f(0.95f, 0.65f, 0.65f);  ///< rgb, each in [0, 1]
};

/// Organ nodes skinned to a connective layer (key connective[i].attachments[j]).
struct AttachmentSpec {
  int body = 0;            ///< index into RuntimeScene::bodies (key: the body's name)
  double distance = 1e-4;  ///< surface nodes within this of the layer's boundary [m], (0, 0.01]
  int neighbours = 4;      ///< rigid nodes per attached node (Shepard weights), [1, 16]
};

/// A rigid-node connective layer of a multi-body scene (key connective[i]).
struct ConnectiveSpec {
  std::string name;  ///< unique among bodies and connective layers
  /// "tet_mesh": a rigid node per node of `mesh`, 4 samples per tet, barycentric weights;
  /// "poisson_disk": rigid nodes and samples by Poisson-disk sampling inside `hexahedron`,
  /// Shepard weights on `neighbours` rigid nodes.
  std::string sampling;
  MeshSpec mesh;                                         ///< tet_mesh: the layer's tet4 mesh
  Eigen::Vector3i resolution = Eigen::Vector3i::Zero();  ///< tet_mesh: generated meshes only
  /// poisson_disk: the 8 corners of the layer's hexahedron [m], corner c at bits (x, y, z) of c.
  std::vector<Eigen::Vector3d> hexahedron;
  double node_spacing = 0.0;    ///< poisson_disk: rigid-node spacing [m], [1e-4, 1]
  double sample_spacing = 0.0;  ///< poisson_disk: sample spacing [m], [5e-5, node_spacing)
  int neighbours = 6;           ///< poisson_disk: rigid nodes per sample, [1, 16]
  int seed = 0;                 ///< poisson_disk: random seed, [0, 2^31 - 1]
  Material material;
  std::vector<Region> fixed;  ///< rigid nodes held (all 6 DOFs): rest positions in a region
  std::vector<AttachmentSpec> attachments;
  Eigen::Vector3f colour = Eigen::Vector3f(0.95f, 0.85f, 0.45f);  ///< rgb, each in [0, 1]
};

/// What runtime and benchmark scenes share: the tissue, its material, loads and boundary
/// conditions, the time step and solver settings, the tools. Every physical key has a unit and
/// no silent default.
struct SceneBase {
  std::string name;
  std::string path;  ///< file it was read from
  MeshSpec mesh;
  Material material;
  double time_step = 0.0;                             ///< dt [s], (0, 1]
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< body acceleration [m/s^2]
  double damping_mass = 0.0;                          ///< Rayleigh alpha [1/s]
  double damping_stiffness = 0.0;                     ///< Rayleigh beta [s]
  int newton_max_iterations = 20;
  double newton_tolerance = 1e-8;  ///< relative residual [-]
  /// CG iteration limit [-]; unset: sized from the problem (pcgIterationCap).
  std::optional<int> pcg_max_iterations;
  double pcg_tolerance = 1e-6;    ///< relative residual [-]
  int pcg_refresh_interval = 10;  ///< steps between preconditioner refreshes
  /// Key contact.full_delassus: ContactSolverSettings::full_delassus of the constraint tools.
  bool contact_full_delassus = false;
  std::vector<FixedBc> fixed;
  std::vector<ToolSpec> tools;  ///< empty: no contact structures are built
  /// Pose of the tissue rest frame in the world frame (tf world -> tissue).
  Eigen::Isometry3d tissue_pose = Eigen::Isometry3d::Identity();
  /// Settings of the efg model (key 'efg'); efg.spacing = efg_spacings.front().
  EfgOptions efg;
  /// efg.spacing [m]: empty without an 'efg' key; a benchmark file may give one per resolution.
  std::vector<double> efg_spacings;
  /// efg.max_cut_triangles [-]: no new cut starts on a meshless body whose cut surface has
  /// this many triangles (the step reports CutRefused); range [100, 1e8].
  int efg_max_cut_triangles = 1000000;
};

/// The simulation a node runs: one mesh resolution, element type, model, integrator and solver,
/// and the instruments (trocars, blades, robot) that decide which nodes a launch starts.
struct RuntimeScene : SceneBase {
  Eigen::Vector3i resolution = Eigen::Vector3i::Zero();  ///< see BenchmarkScene::resolutions
  ElementType element_type = ElementType::Tet4;
  ModelKind model = ModelKind::Corotational;
  IntegratorKind integrator = IntegratorKind::ImplicitEulerLinearized;
  SolverKind solver = SolverKind::Cholmod;
  std::vector<TrocarSpec> trocars;  ///< at most 4, each holding a different tool
  std::vector<BladeSpec> blades;    ///< at most 4
  std::optional<RobotSpec> robot;
  /// Multi-body scene (key 'bodies'): FE organs coupled by connective layers; empty for a
  /// single-body scene. A multi-body scene has none of mesh, material, model, integrator, solver,
  /// fixed, newton, pcg, efg, contact, trocars, blades and robot (SceneBase::mesh stays empty).
  std::vector<BodySpec> bodies;
  std::vector<ConnectiveSpec> connective;  ///< the layers of a multi-body scene
};

struct BenchmarkVariant;

/// A benchmark file: the shared scene, sweeps over resolution, element type, model, integrator
/// and solver, a number of steps or a load path, prescribed displacements, and what error_rel
/// is measured against.
struct BenchmarkScene : SceneBase {
  /// Sweep of resolutions: cells along x,y,z (box/beam), {cells_along, rings, -} (hex_beam),
  /// {cells_per_axis, -, -} (organ_blob); a file mesh has one implicit resolution. (Runtime
  /// scenes also take {subdivisions, -, -} for the liver surface.)
  std::vector<Eigen::Vector3i> resolutions;
  std::vector<ElementType> element_types;  ///< sweep of element types (tet4, tet10)
  std::vector<ModelKind> models;
  std::vector<IntegratorKind> integrators;
  std::vector<SolverKind> solvers;
  int steps = 1;  ///< steps per case (quasi_static: load increments)
  /// Key 'threads': SURGICAL_SIM_THREADS for the benches' case processes, [1, kMaxThreads];
  /// unset: the environment's (docs/models.md).
  std::optional<int> threads;
  std::vector<double> load_factors;  ///< load path (quasi-static stretch values etc.)
  std::vector<PrescribedBc> prescribed;
  MeasureSpec measure;
  /// Key 'variants': configurations run side by side by the benches (e.g. a solver set-up
  /// before and after a change). Each item has a `name` and any other keys of the file, laid
  /// over it (maps merge key by key, other values replace); empty: the file is one configuration.
  std::vector<BenchmarkVariant> variants;
};

/// One item of BenchmarkScene::variants: the whole file with the item's keys laid over it.
struct BenchmarkVariant {
  std::string name;  ///< [A-Za-z][A-Za-z0-9_]*, unique in the file
  BenchmarkScene scene;
  std::vector<std::string> keys;  ///< the dotted keys the item sets, e.g. "pcg.tolerance"
};

/// Working-memory budget of one case of a scene [bytes]: a generated mesh whose estimate
/// (estimateMeshSize()) exceeds it is rejected before it is built.
constexpr double kSceneMemoryBudgetBytes = 8e9;

/// Rough upper estimate of the size of a generated scene mesh and of the working memory of a
/// case on it.
struct MeshSizeEstimate {
  double nodes = 0.0;     ///< mesh nodes (tet10: corners plus edge nodes)
  double elements = 0.0;  ///< tetrahedra
  double bytes = 0.0;     ///< mesh, model, stiffness and system matrices and sparse
                          ///< factorisation: 40 kB (tet4) or 50 kB (tet10) per node plus 0.5 kB
                          ///< (tet4) or 3 kB (tet10) per element [bytes]
};

/// Estimate for the generator of `spec` at `resolution` (see BenchmarkScene::resolutions) and
/// element type, computed without building anything (doubles: no overflow). A "file" mesh has no
/// estimate (all zero): its size is bounded by the file's.
MeshSizeEstimate estimateMeshSize(const MeshSpec& spec, const Eigen::Vector3i& resolution,
                                  ElementType type);

/// "" if the estimate is within kSceneMemoryBudgetBytes, else a message naming the resolution,
/// the element type, the estimate [GB] and the budget.
std::string meshBudgetProblem(const MeshSpec& spec, const Eigen::Vector3i& resolution,
                              ElementType type);

/// Reads and validates a runtime scene file (docs/scenes.md). @throws std::invalid_argument whose
/// message starts with "scene <path>: key '<dotted.key>': " and says what is wrong (missing,
/// duplicate, wrong type, malformed or out-of-range value, empty string or topic name, list
/// longer than 10,000 entries, mesh resolution above the memory budget, a benchmark key such as
/// a sweep list or `measure`, which a runtime scene does not have); without a key for a file that
/// cannot be opened, is larger than 4 MiB, is not YAML (names the line) or is not a map.
RuntimeScene loadRuntimeScene(const std::string& path);

/// Same from YAML text (path used in messages and to resolve relative mesh files).
RuntimeScene parseRuntimeScene(const std::string& yaml_text, const std::string& path);

/// Reads and validates a benchmark file: the shared keys, the sweep lists, steps, load_factors,
/// prescribed and measure (docs/benchmarks.md); errors as loadRuntimeScene().
BenchmarkScene loadBenchmarkScene(const std::string& path);

/// Same from YAML text.
BenchmarkScene parseBenchmarkScene(const std::string& yaml_text, const std::string& path);

}  // namespace surgical_sim::core
