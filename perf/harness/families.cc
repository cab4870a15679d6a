// Scene families of the perf harness (families.h).
#include "families.h"

#include <array>
#include <charconv>
#include <cmath>
#include <numbers>

#include "run.h"
#include "scenes/contact_scenes.h"

namespace superdex::perf {
namespace {

using Cells = std::array<int, 3>;

// ---- cantilever: examples/cantilever and perf/deformable_step's beam ----
// 1 × 0.2 × 0.2 m, x along the length, MakeTetBox (6 Kuhn tets per cell),
// stable Neo-Hookean, E = 1e5 Pa × ratio, ν = 0.3, ρ = 1000 kg/m³, clamped
// at x = 0 by one DeformableNodePosition pin per node of that face.
constexpr real kBeamYoung = 1e5;  // [Pa] at stiffness ratio 1
// Clamp pins: k = 1e3 · E [N/m] (1e8 N/m at E = 1e5). An element of edge h
// has a stiffness ~ E·h ≤ 0.1·E here (h ≤ 0.1 m for every size from 10x2x2
// on), so each pin stays ≥ 1e4 times stiffer than the beam next to it at every
// size and stiffness ratio (the brief asks for ≥ 1000×), and scaling it with E
// keeps that ratio, and the conditioning it brings, the same across ratios.
constexpr real kClampPerYoung = 1e3;

// ---- cloth: examples/cloth's sheet ----
// 1 × 1 m in the x–z plane at y = 0 (MakeTriangleGrid), StVK membrane +
// hinge bending, E = 1e6 Pa × ratio, ν = 0.3, h = 1 mm, ρ = 300 kg/m³,
// pinned at its two corners on the edge z = 1 by DeformableNodePosition pins
// of k = 1e5 N/m (they carry the weight, ~3 N, which does not depend on E,
// so they are not scaled).
constexpr real kClothYoung = 1e6;
constexpr real kClothThickness = 1e-3;
constexpr real kClothDensity = 300;
constexpr real kClothPinStiffness = 1e5;
// examples/cloth: where the sheet is compressed the StVK membrane is
// non-convex and Newton converges only linearly; it needs far more than 50.
constexpr int kClothNewtonMaxIterations = 300;

// ---- chain: tests/test_scenes.h MakeChain with boxes ----
// N boxes 0.1 × 0.02 × 0.02 m, 1 kg, along +x at y = 0, joined end to end by
// RigidSphericalJoint constraints, the first pinned to the world at its left
// end (the origin) by a RigidPivotPosition; released horizontally at rest.
// Joint and pivot stiffness 1e6 N/m × ratio (MakeChain's value: the root
// joint of N = 200 carries ~2 kN and stretches ~2 mm).
constexpr real kLinkLength = 0.1, kLinkSide = 0.02, kLinkMass = 1;
constexpr real kJointStiffness = 1e6;

// ---- rods: a bundle of discrete elastic rods clamped to a rigid plate ----
// R straight rods of N nodes (size "RxN"), length 1 m, along +x from the
// plate face x = 0, released horizontally at rest: each droops and swings
// under gravity like a cantilever, a large deflection at stiffness ratio 1.
// Circular section r = 5 mm; E = 1e8 Pa × ratio (a soft polymer, e.g.
// low-density polyethylene ~2e8 Pa), ν = 0.3, ρ = 1000 kg/m³. The load
// parameter γ = ρgAL³/(EI) = 4ρgL³/(E r²) is ~16 at ratio 1 (large
// deflection: linear theory's tip drop γL/8 would be 2 L, so the rod is far
// into the nonlinear range and Newton has work at every step; first bending
// period ~2.3 s), 0.16 at ratio 100 (2 % of L) and 1.6e-3 at ratio 1e4.
constexpr real kRodLength = 1;      // [m]
constexpr real kRodRadius = 5e-3;   // [m]
constexpr real kRodYoung = 1e8;     // [Pa] at stiffness ratio 1
constexpr real kRodDensity = 1000;  // [kg/m³]
// Attachment points: a cols × rows grid (cols = ceil(√R), rows = ceil(R/cols))
// in the plate face (y–z plane), centred on the x axis, pitch 4 radii (a
// 10 × 10 bundle spans 0.18 m). Rods do not interact (no contact); rods of one
// column droop in one plane.
constexpr real kRodSpacing = 4 * kRodRadius;
// The clamp of each rod (ClampRodEnd in tests/test_scenes.h): a
// DeformableNodeToRigid on node 0 and a RodElementRotationToRigid on element
// 0, at kRodClampFactor = 1e3 times the stiffest the rod is next to them, for
// this size's element length l = L/(N − 1):
//   linear  k = 1e3 · max(EA/l, 12 EI/l³)   [N/m]    (stretching; a beam
//           element's transverse stiffness, which wins for l < √3 r: N > 116)
//   angular k = 1e3 · max(4 EI/l, GJ/l)     [N·m/rad] (a beam element's end
//           rotation stiffness; GJ = EI/(1 + ν) < 4EI, so 4EI/l)
// Both are proportional to E, so the clamp is 1e3 times stiffer than the rod
// next to it at every size and stiffness ratio, with the same conditioning
// penalty everywhere (at 100x250, ratio 1: 9.1e9 N/m and 4.9e4 N·m/rad; the
// root carries the rod's weight 0.77 N and a moment ≤ 0.39 N·m, so the clamp
// gives way by < 1e-9 m and < 1e-5 rad).
constexpr real kRodClampFactor = 1e3;
// The plate: 1 kg, 1 cm thick, square with side cols · pitch, behind the face
// x = 0, held by a RigidPivotToRigidTarget and a RigidPivotRotation (tests'
// Anchor) of 1e9 N/m and 1e9 N·m/rad. They carry the bundle's weight and
// inertia, which do not depend on E (not scaled): at 100x250 the rods weigh
// 77 N with a moment ≤ 39 N·m, so the plate moves < 1e-7 m and turns
// < 1e-7 rad; the rods' inertia against a plate motion, R·m/dt² ~ 3e4 N/m at
// dt = 1/60, is ~3e4 times softer than the anchor.
constexpr real kPlateMass = 1, kPlateThickness = 0.01;
constexpr real kPlateAnchorStiffness = 1e9;

constexpr real kPoisson = 0.3;
// The contact families' barrier stiffness at ratio 1: ContactParams' default.
constexpr real kBarrierStiffness = ContactParams{}.stiffness;
constexpr int kDefaultNewtonMaxIterations = 50;

/// `count` positive integers separated by `separator` ("40x8x8"), after
/// `prefix` ("N="). Unused entries of `cells` are set to 1.
bool ParseCounts(std::string_view text, std::string_view prefix, char separator, int count,
                 Cells& cells) {
  if (!text.starts_with(prefix)) return false;
  text.remove_prefix(prefix.size());
  cells = {1, 1, 1};
  for (int k = 0; k < count; ++k) {
    std::size_t const end = k + 1 < count ? text.find(separator) : text.size();
    if (end == std::string_view::npos) return false;
    std::string_view const part = text.substr(0, end);
    auto const [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), cells[k]);
    if (ec != std::errc() || ptr != part.data() + part.size() || cells[k] < 1) return false;
    text.remove_prefix(std::min(text.size(), end + 1));
  }
  return true;
}

/// Pins node `node` of `actor` where it is now.
bool PinNode(Scene& scene, DeformableActor& actor, int node, real stiffness, Error& error) {
  DeformableNodePositionConstraintParams pin;
  pin.actor = actor.GetHandle();
  pin.nodeIndex = node;
  pin.position = actor.GetNodePosition(node);
  pin.stiffness = stiffness;
  return scene.CreateDeformableNodePositionConstraint(pin, error) != nullptr;
}

/// Creates the deformable actor and makes its nodes the tracked points.
DeformableActor* AddDeformable(DeformableActorParams const& params, FamilyScene& out,
                               Error& error) {
  DeformableActor* actor = out.scene->CreateDeformableActor(params, error);
  if (actor) out.trackedPositions = [actor] { return actor->GetNodePositions(); };
  return actor;
}

bool BuildCantilever(Cells const& cells, double ratio, FamilyScene& out, Error& error) {
  TetMesh mesh;
  if (!MakeTetBox(Real3(0, -0.1, -0.1), Real3(1, 0.2, 0.2), cells, mesh, error)) return false;
  DeformableActorParams params;
  params.nodes = std::move(mesh.nodes);
  params.tetrahedra = std::move(mesh.tetrahedra);
  params.material = TetMaterialModel::StableNeoHookean;
  params.youngModulus = kBeamYoung * ratio;
  params.poissonRatio = kPoisson;
  params.density = 1000;
  DeformableActor* beam = AddDeformable(params, out, error);
  if (!beam) return false;
  for (int i = 0; i < beam->GetNumNodes(); ++i)
    if (beam->GetNodeReferencePosition(i).x() <= 1e-9 &&
        !PinNode(*out.scene, *beam, i, kClampPerYoung * params.youngModulus, error))
      return false;
  out.length = 1;
  return true;
}

bool BuildCloth(Cells const& cells, double ratio, FamilyScene& out, Error& error) {
  int const nx = cells[0], nz = cells[1];
  TriangleMesh mesh;
  if (!MakeTriangleGrid(Real3::Zero(), 1, 1, nx, nz, mesh, error)) return false;
  DeformableActorParams params;
  params.nodes = std::move(mesh.nodes);
  params.triangles = std::move(mesh.triangles);
  params.youngModulus = kClothYoung * ratio;
  params.poissonRatio = kPoisson;
  params.thickness = kClothThickness;
  params.density = kClothDensity;
  DeformableActor* cloth = AddDeformable(params, out, error);
  if (!cloth) return false;
  // the corners (0, 0, 1) and (1, 0, 1): grid points (0, nz) and (nx, nz)
  for (int node : {(nx + 1) * nz, (nx + 1) * nz + nx})
    if (!PinNode(*out.scene, *cloth, node, kClothPinStiffness, error)) return false;
  out.length = 1;
  return true;
}

/// A chain link's pose: centre of mass and rotation (body axes: x along the
/// link).
struct LinkPose {
  Real3 center;
  Quat rotation;
};

/// The mechanism probes of both chain families, from the same link poses:
/// link i is held at its left end to link i − 1's right end (link 0 to the
/// origin), each end kLinkLength / 2 from the centre along the link's x axis.
void SetChainProbes(int n, std::function<LinkPose(int)> pose, std::function<real()> kinetic,
                    FamilyScene& out) {
  Real3 const gravity = out.scene->GetParams().gravity;
  out.jointDrift = [n, pose] {
    Real3 const half(kLinkLength / 2, 0, 0);
    real drift = 0;
    Real3 parentEnd = Real3::Zero();
    for (int i = 0; i < n; ++i) {
      LinkPose const p = pose(i);
      drift = std::max(drift, (p.center - p.rotation * half - parentEnd).norm());
      parentEnd = p.center + p.rotation * half;
    }
    return drift;
  };
  out.mechanicalEnergy = [n, pose, kinetic, gravity] {
    real energy = kinetic();
    for (int i = 0; i < n; ++i) energy -= kLinkMass * gravity.dot(pose(i).center);
    return energy;
  };
  out.energyScale = n * kLinkMass * gravity.norm() * n * kLinkLength;
}

bool BuildChain(Cells const& cells, double ratio, FamilyScene& out, Error& error) {
  int const n = cells[0];
  real const stiffness = kJointStiffness * ratio;
  auto const bodies = std::make_shared<DynamicArray<RigidActor*>>();
  for (int i = 0; i < n; ++i) {
    RigidActorParams body;
    body.mass = kLinkMass;
    real const side2 = kLinkSide * kLinkSide, length2 = kLinkLength * kLinkLength;
    body.inertia = kLinkMass / 12 * Real3(2 * side2, length2 + side2, length2 + side2);
    body.position = Real3((i + 0.5) * kLinkLength, 0, 0);
    RigidActor* actor = out.scene->CreateRigidActor(body, error);
    if (!actor) return false;
    bodies->push_back(actor);
  }
  RigidPivotPositionConstraintParams pin;
  pin.actor = (*bodies)[0]->GetHandle();
  pin.localPos = Real3(-kLinkLength / 2, 0, 0);
  pin.position = Real3::Zero();
  pin.stiffness = stiffness;
  if (!out.scene->CreateRigidPivotPositionConstraint(pin, error)) return false;
  for (int i = 0; i + 1 < n; ++i) {
    RigidSphericalJointConstraintParams joint;
    joint.actorA = (*bodies)[i]->GetHandle();
    joint.actorB = (*bodies)[i + 1]->GetHandle();
    joint.localPosA = Real3(kLinkLength / 2, 0, 0);
    joint.localPosB = Real3(-kLinkLength / 2, 0, 0);
    joint.stiffness = stiffness;
    if (!out.scene->CreateRigidSphericalJointConstraint(joint, error)) return false;
  }
  out.length = n * kLinkLength;
  out.trackedPositions = [bodies] {
    DynamicArray<Real3> positions;
    for (RigidActor const* body : *bodies) positions.push_back(body->GetPosition());
    return positions;
  };
  SetChainProbes(
      n, [bodies](int i) { return LinkPose{(*bodies)[i]->GetPosition(), (*bodies)[i]->GetRotation()}; },
      [bodies] {
        real kinetic = 0;
        for (RigidActor const* body : *bodies) kinetic += body->GetKineticEnergy();
        return kinetic;
      },
      out);
  return true;
}

/// R = cells[0] rods of N = cells[1] nodes (see the constants above).
bool BuildRods(Cells const& cells, double ratio, FamilyScene& out, Error& error) {
  int const numRods = cells[0], numNodes = cells[1];
  if (numNodes < 2) {
    error.Set(ErrorCode::InvalidArgument, "rods need at least 2 nodes each (RxN, N >= 2)");
    return false;
  }
  int const cols = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(numRods))));
  int const rows = (numRods + cols - 1) / cols;
  Scene& scene = *out.scene;

  // the plate and its anchor
  real const side = cols * kRodSpacing, thickness2 = kPlateThickness * kPlateThickness;
  RigidActorParams plateParams;
  plateParams.mass = kPlateMass;
  plateParams.inertia =
      kPlateMass / 12 * Real3(2 * side * side, side * side + thickness2, side * side + thickness2);
  plateParams.position = Real3(-kPlateThickness / 2, 0, 0);
  RigidActor* plate = scene.CreateRigidActor(plateParams, error);
  if (!plate) return false;
  RigidPivotToRigidTargetConstraintParams hold;
  hold.actor = plate->GetHandle();
  hold.position = plate->GetPosition();
  hold.rotation = plate->GetRotation();
  hold.stiffness = kPlateAnchorStiffness;
  if (!scene.CreateRigidPivotToRigidTargetConstraint(hold, error)) return false;
  RigidPivotRotationConstraintParams turn;
  turn.actor = plate->GetHandle();
  turn.rotation = plate->GetRotation();
  turn.stiffness = kPlateAnchorStiffness;
  if (!scene.CreateRigidPivotRotationConstraint(turn, error)) return false;

  // the rods and their clamps
  RodActorParams rod;
  rod.radius = kRodRadius;
  rod.youngModulus = kRodYoung * ratio;
  rod.poissonRatio = kPoisson;
  rod.density = kRodDensity;
  real const pi = std::numbers::pi_v<real>;
  real const area = pi * kRodRadius * kRodRadius, inertia = area * kRodRadius * kRodRadius / 4;
  real const element = kRodLength / (numNodes - 1);
  real const ea = rod.youngModulus * area, ei = rod.youngModulus * inertia;
  real const gj = rod.youngModulus / (2 * (1 + kPoisson)) * 2 * inertia;
  real const linear =
      kRodClampFactor * std::max(ea / element, 12 * ei / (element * element * element));
  real const angular = kRodClampFactor * std::max(4 * ei / element, gj / element);
  auto const rods = std::make_shared<DynamicArray<RodActor*>>();
  for (int k = 0; k < numRods; ++k) {
    real const y = (k / cols - (rows - 1) / 2.0) * kRodSpacing;
    real const z = (k % cols - (cols - 1) / 2.0) * kRodSpacing;
    rod.nodes.clear();
    for (int i = 0; i < numNodes; ++i) rod.nodes.push_back(Real3(i * element, y, z));
    RodActor* actor = scene.CreateRodActor(rod, error);
    if (!actor) return false;
    rods->push_back(actor);
    DeformableNodeToRigidConstraintParams node;
    node.deformableActor = actor->GetHandle();
    node.rigidActor = plate->GetHandle();
    node.deformableNodeIndex = 0;
    node.stiffness = linear;
    if (!scene.CreateDeformableNodeToRigidConstraint(node, error)) return false;
    RodElementRotationToRigidConstraintParams frame;
    frame.rigidActor = plate->GetHandle();
    frame.rodActor = actor->GetHandle();
    frame.elementIndex = 0;
    frame.stiffness = angular;
    if (!scene.CreateRodElementRotationToRigidConstraint(frame, error)) return false;
  }
  out.length = kRodLength;
  out.trackedPositions = [rods] {
    DynamicArray<Real3> positions;
    for (RodActor const* actor : *rods)
      for (int i = 0; i < actor->GetNumNodes(); ++i) positions.push_back(actor->GetNodePosition(i));
    return positions;
  };
  return true;
}

/// The chain's N boxes as one articulated actor: spherical joints at the
/// same points (the root one at the origin, on the world), exact instead of
/// compliant — the same mechanism and the same link inertia terms, so the
/// two families differ only in how the joints are modelled. The stiffness
/// ratio has no joint stiffness to act on and is ignored.
bool BuildArticulatedChainSolvedBy(ArticulatedBlockSolve solve, Cells const& cells, FamilyScene& out,
                                   Error& error) {
  int const n = cells[0];
  ArticulatedActorParams params;
  params.blockSolve = solve;
  real const side2 = kLinkSide * kLinkSide, length2 = kLinkLength * kLinkLength;
  for (int i = 0; i < n; ++i) {
    ArticulatedLinkParams link;
    link.parent = i - 1;
    link.joint = JointType::Spherical;
    link.parentToJointPosition = i == 0 ? Real3::Zero() : Real3(kLinkLength, 0, 0);
    link.mass = kLinkMass;
    link.inertia = kLinkMass / 12 * Real3(2 * side2, length2 + side2, length2 + side2);
    link.centerOfMass = Real3(kLinkLength / 2, 0, 0);
    params.links.push_back(link);
  }
  ArticulatedActor* chain = out.scene->CreateArticulatedActor(params, error);
  if (!chain) return false;
  out.length = n * kLinkLength;
  out.trackedPositions = [chain, n] {
    DynamicArray<Real3> positions;
    for (int i = 0; i < n; ++i) positions.push_back(chain->GetLinkCenterOfMass(i));
    return positions;
  };
  SetChainProbes(
      n, [chain](int i) { return LinkPose{chain->GetLinkCenterOfMass(i), chain->GetLinkRotation(i)}; },
      [chain] { return chain->GetKineticEnergy(); }, out);
  return true;
}

/// chain-articulated: the actor's block solved by the O(N) tree recursion
/// (the default); chain-articulated-dense: by the scene's solver as one
/// dense block (docs/articulated.md, "Solving on the tree")
bool BuildArticulatedChain(Cells const& cells, double /*ratio*/, FamilyScene& out, Error& error) {
  return BuildArticulatedChainSolvedBy(ArticulatedBlockSolve::Tree, cells, out, error);
}
bool BuildArticulatedChainDense(Cells const& cells, double /*ratio*/, FamilyScene& out, Error& error) {
  return BuildArticulatedChainSolvedBy(ArticulatedBlockSolve::Dense, cells, out, error);
}

// ---- the contact families: scenes/contact_scenes.h ----
// Each is built into the harness's scene (its solver, integrator and Newton
// settings) with the default ContactParams, κ times the stiffness ratio.

/// The tracked points: every node of the actors, in order.
template <class Actors>
std::function<DynamicArray<Real3>()> NodesOf(Actors const& actors) {
  return [actors] {
    DynamicArray<Real3> points;
    for (auto const* actor : actors)
      for (Real3 const& p : actor->GetNodePositions()) points.push_back(p);
    return points;
  };
}

/// The scene's bodies added by `add`, or false and the builder's error.
bool Added(scenes::Builder const& builder, Error& error) {
  if (!builder.Ok()) error = builder.GetError();
  return builder.Ok();
}

bool BuildContactCloth(Cells const& cells, double, FamilyScene& out, Error& error) {
  if (cells[0] != cells[1]) {
    error.Set(ErrorCode::InvalidArgument, "contact-cloth: the cloth is square (size NxN)");
    return false;
  }
  scenes::Builder b(*out.scene);
  DeformableActor* cloth = scenes::AddClothOnSphere(b, cells[0]);
  out.length = 0.6;
  out.trackedPositions = NodesOf(std::array{cloth});
  return Added(b, error);
}

bool BuildContactSolids(Cells const& cells, double, FamilyScene& out, Error& error) {
  scenes::Builder b(*out.scene);
  auto const cubes = scenes::AddCubeStack(b, cells[0], cells[1]);
  out.length = 0.1 * cells[0];
  out.trackedPositions = NodesOf(cubes);
  out.restingPoints = out.trackedPositions;
  return Added(b, error);
}

bool BuildContactRigid(Cells const& cells, double, FamilyScene& out, Error& error) {
  scenes::Builder b(*out.scene);
  auto const boxes = scenes::AddBoxStack(b, cells[0]);
  out.length = 0.2 * cells[0];
  out.trackedPositions = [boxes] {
    DynamicArray<Real3> centres;
    for (RigidActor const* box : boxes) centres.push_back(box->GetPosition());
    return centres;
  };
  out.restingPoints = out.trackedPositions;
  return Added(b, error);
}

bool BuildContactRods(Cells const& cells, double, FamilyScene& out, Error& error) {
  if (cells[1] < 2) {
    error.Set(ErrorCode::InvalidArgument, "contact-rods: a rod needs at least 2 nodes (size RxN)");
    return false;
  }
  scenes::Builder b(*out.scene);
  auto const rods = scenes::AddRodPile(b, cells[0], cells[1]);
  out.length = 0.5;
  out.trackedPositions = NodesOf(rods);
  return Added(b, error);
}

bool BuildContactGrasp(Cells const& cells, double, FamilyScene& out, Error& error) {
  scenes::Builder b(*out.scene);
  scenes::Grasp const grasp = scenes::AddGrasp(b, cells[0]);
  real const dhat = b.ActivationDistance();
  out.length = 0.1;
  out.trackedPositions = NodesOf(std::array{grasp.cube});
  out.restingPoints = out.trackedPositions;  // held still from 0.5 s on
  out.drive = [grasp, dhat](real, real to, Error& driveError) {
    return scenes::DriveGrasp(grasp, dhat, to, driveError);
  };
  return Added(b, error);
}

struct Family {
  std::string_view name;
  std::string_view sizePrefix;  ///< before the counts: "N=" for the chain
  int numCounts;                ///< counts in the size label
  std::string_view sizeExample;
  std::string_view stiffnessSymbol;  ///< "E" or "k" in the material label
  real baseStiffness;
  int newtonMaxIterations;
  int (*dofs)(Cells const&);
  bool (*build)(Cells const&, double, FamilyScene&, Error&);
  bool contact = false;  ///< the stiffness ratio scales the barrier's κ
};

std::array<Family, 11> const kFamilies{{
    {"cantilever", "", 3, "40x8x8", "E", kBeamYoung, kDefaultNewtonMaxIterations,
     [](Cells const& c) { return 3 * (c[0] + 1) * (c[1] + 1) * (c[2] + 1); }, BuildCantilever},
    {"cloth", "", 2, "32x32", "E", kClothYoung, kClothNewtonMaxIterations,
     [](Cells const& c) { return 3 * (c[0] + 1) * (c[1] + 1); }, BuildCloth},
    {"chain", "N=", 1, "N=50", "k", kJointStiffness, kDefaultNewtonMaxIterations,
     [](Cells const& c) { return RigidActor::kNumDofs * c[0]; }, BuildChain},
    {"rods", "", 2, "100x250", "E", kRodYoung, kDefaultNewtonMaxIterations,
     [](Cells const& c) { return 4 * c[0] * c[1] + RigidActor::kNumDofs; }, BuildRods},
    {"chain-articulated", "N=", 1, "N=50", "k", 0, kDefaultNewtonMaxIterations,
     [](Cells const& c) { return 3 * c[0]; }, BuildArticulatedChain},
    {"chain-articulated-dense", "N=", 1, "N=50", "k", 0, kDefaultNewtonMaxIterations,
     [](Cells const& c) { return 3 * c[0]; }, BuildArticulatedChainDense},
    {"contact-cloth", "", 2, "32x32", "kappa", kBarrierStiffness, kDefaultNewtonMaxIterations,
     [](Cells const& c) { return 3 * c[0] * c[1]; }, BuildContactCloth, true},
    {"contact-solids", "", 2, "5x2", "kappa", kBarrierStiffness, kDefaultNewtonMaxIterations,
     [](Cells const& c) { return 3 * c[0] * (c[1] + 1) * (c[1] + 1) * (c[1] + 1); }, BuildContactSolids, true},
    {"contact-rigid", "N=", 1, "N=5", "kappa", kBarrierStiffness, kDefaultNewtonMaxIterations,
     [](Cells const& c) { return RigidActor::kNumDofs * c[0]; }, BuildContactRigid, true},
    {"contact-rods", "", 2, "20x50", "kappa", kBarrierStiffness, kDefaultNewtonMaxIterations,
     [](Cells const& c) { return 4 * c[0] * c[1]; }, BuildContactRods, true},
    // the lift's steps take up to 44 Newton iterations (docs/contact.md)
    {"contact-grasp", "C=", 1, "C=3", "kappa", kBarrierStiffness, 100,
     [](Cells const& c) { return 3 * (c[0] + 1) * (c[0] + 1) * (c[0] + 1); }, BuildContactGrasp, true},
}};

Family const* FindFamily(std::string_view name) {
  for (Family const& f : kFamilies)
    if (f.name == name) return &f;
  return nullptr;
}

/// The family and parsed size, or nullptr and `message`.
Family const* Resolve(std::string const& family, std::string const& size, Cells& cells,
                      std::string& message) {
  Family const* f = FindFamily(family);
  if (!f) {
    std::string names;
    for (Family const& known : kFamilies) names += (names.empty() ? "" : ", ") + std::string(known.name);
    message = "unknown family '" + family + "' (" + names + ")";
    return nullptr;
  }
  if (!ParseCounts(size, f->sizePrefix, 'x', f->numCounts, cells)) {
    message =
        "bad size '" + size + "' for " + family + " (e.g. " + std::string(f->sizeExample) + ")";
    return nullptr;
  }
  return f;
}

}  // namespace

std::vector<std::string_view> const& FamilyNames() {
  static std::vector<std::string_view> const names = FieldOf(kFamilies, &Family::name);
  return names;
}

bool IsContactFamily(std::string_view family) {
  Family const* f = FindFamily(family);
  return f && f->contact;
}

int CountDofs(std::string const& family, std::string const& size, std::string& message) {
  Cells cells;
  Family const* f = Resolve(family, size, cells, message);
  return f ? f->dofs(cells) : -1;
}

std::string MaterialLabel(std::string const& family, double stiffnessRatio) {
  Family const* f = FindFamily(family);
  if (!f) return "";
  if (f->baseStiffness == 0) return "exact joints";  // nothing for the ratio to scale
  return std::string(f->stiffnessSymbol) + "=" + ShortNumber(f->baseStiffness * stiffnessRatio);
}

int DefaultNewtonMaxIterations(std::string const& family) {
  Family const* f = FindFamily(family);
  return f ? f->newtonMaxIterations : kDefaultNewtonMaxIterations;
}

bool BuildFamilyScene(std::string const& family, std::string const& size, double stiffnessRatio,
                      SceneParams const& params, FamilyScene& out, Error& error) {
  Cells cells;
  std::string message;
  Family const* f = Resolve(family, size, cells, message);
  if (!f) {
    error.Set(ErrorCode::InvalidArgument, message);
    return false;
  }
  if (!(stiffnessRatio > 0) || !std::isfinite(stiffnessRatio)) {
    error.Set(ErrorCode::InvalidArgument, "stiffness ratio must be finite and > 0");
    return false;
  }
  SceneParams scaled = params;
  if (f->contact) scaled.contact.stiffness *= stiffnessRatio;
  out.scene = Scene::Create(scaled, error);
  return out.scene && f->build(cells, stiffnessRatio, out, error);
}

}  // namespace superdex::perf
