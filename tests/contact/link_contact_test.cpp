// Colliders on articulated links (docs/contact.md, "Links"): the contact
// term's gradient and Hessian over the joint DoFs against central
// differences, the link's speed bound and safe step against forward
// kinematics sampled along the step, the validation of `link`, and scene 8 —
// a 5-link arm driven by targets pushes a box across the ground. Also the
// nodal pairs' exact Hessian (every pair kind) against central differences.
#include "contact/contact_scenes.h"
#include "scenes/interpenetration.h"
#include "test_scenes.h"
#include "white_box.h"

#include <cmath>
#include <random>

#include <superdex/contact/contact_system.h>
#include <superdex/stage/integrator.h>

using namespace superdex;
using namespace superdex::test;
using internal::ActorTestAccess;

namespace {

constexpr int kLink = 7;  // BranchedTree: its path 0, 1, 3, 4, 7 (free, spherical, fixed, revolute, spherical)

/// A capsule on link `link` of `tree`, off its frame origin and turned.
ColliderParams LinkCapsule(ArticulatedActor const& tree, int link, real friction) {
  ColliderParams capsule;
  capsule.actor = tree.GetHandle();
  capsule.link = link;
  capsule.shape = ShapeType::Capsule;
  capsule.position = Real3(0.05, -0.02, 0.03);
  capsule.rotation = Quat(Eigen::AngleAxis<real>(0.7, Real3(1, 0.3, -0.2).normalized()));
  capsule.radius = 0.01;
  capsule.halfLength = 0.04;
  capsule.friction = friction;
  return capsule;
}

/// The contact term's energy at the actors' current iterate.
real ContactEnergy(internal::ContactSystem const& contact, internal::HessianAssembler const& assembler) {
  internal::EnergySum sum;
  contact.AddEnergy(assembler, 0, sum);
  return sum.energy;
}

/// The contact term's gradient and Hessian over n DoFs: exact, or with
/// `project` the PSD one.
ActorDerivatives ContactDerivatives(internal::ContactSystem const& contact, internal::HessianAssembler& assembler,
                                    int n, bool project) {
  DynamicArray<real> gradient(n, 0);
  assembler.BeginAssembly(gradient);
  internal::AssemblyOptions options;
  options.projectHessian = project;
  contact.AddGradientAndHessian(assembler, 0, options);
  assembler.FinishAssembly();
  return {Eigen::Map<VectorX const>(gradient.data(), n), DenseNaturalHessian(assembler)};
}

/// A tree (every joint type, floating), a capsule on link 7 and a static
/// plane that both of the capsule's ends are within d̂ of, driven through
/// the stage contract by hand as the Newton solver drives it.
struct LinkContact {
  std::unique_ptr<Scene> scene;
  ArticulatedActor* tree = nullptr;
  std::unique_ptr<internal::ContactSystem> contact;
  Collider* capsule = nullptr;
  Real3 normal;
  real offset = 0;  ///< the plane n·x = offset
  internal::HessianAssembler assembler;
  int n = 0;

  /// With `againstLink`, the obstacle is a second capsule on link 6 of the
  /// same tree (path 0, 1, 2, 5, 6: joints 0 and 1 shared with link 7's),
  /// crossing the first 0.4 d̂ from it: a mechanism's self contact.
  explicit LinkContact(real friction, bool againstLink = false) {
    SceneParams params;
    scene = MakeScene(params);
    tree = MakeArticulated(*scene, BranchedTree(true, ArticulatedBlockSolve::Dense));
    n = tree->GetNumDofs();
    contact = std::make_unique<internal::ContactSystem>(params.contact);
    Error error;
    capsule = contact->Add(LinkCapsule(*tree, kLink, friction), nullptr, nullptr, tree, error);
    INFO(error.ToString());
    REQUIRE(capsule);
    if (againstLink) {
      AddCrossingCapsule(friction, params.contact.activationDistance);
      return;
    }
    // the plane under both ends: normal across the capsule's axis, the
    // lower end 0.4 d̂ above it, the other within d̂
    DynamicArray<Real3> ends;
    capsule->GetWorldVertices(ends);
    REQUIRE(ends.size() == 2);
    Real3 const axis = (ends[1] - ends[0]).normalized();
    normal = (Real3(0.1, 1, 0.2) - axis.dot(Real3(0.1, 1, 0.2)) * axis).normalized();
    real const dhat = params.contact.activationDistance;
    Real3 const tilt = (ends[1] - ends[0]).dot(normal) >= 0 ? ends[0] : ends[1];
    offset = normal.dot(tilt) - capsule->GetThickness() - 0.4 * dhat;
    ColliderParams plane;
    plane.shape = ShapeType::Plane;
    plane.normal = normal;
    plane.position = offset * normal;
    plane.friction = friction;
    REQUIRE(contact->Add(plane, nullptr, nullptr, nullptr, error));
    INFO(error.ToString());
    for (Real3 const& end : ends) REQUIRE(normal.dot(end) - offset - capsule->GetThickness() < dhat);
    ActorTestAccess::BeginStage(*tree, internal::MakeStage(IntegratorType::BackwardEuler, 0.01, false),
                                Real3::Zero());
    internal::StageContext stage;
    stage.coefficients.duration = 0.01;
    contact->BeginStage(stage);
    REQUIRE(contact->GetNumCandidates() == 2);  // the capsule's two ends against the plane
    DynamicArray<DynamicArray<int>> reserved;
    internal::StageDofLists pairs;
    contact->AppendContributorDofs(reserved);
    REQUIRE(reserved.size() == 1);
    REQUIRE(static_cast<int>(reserved[0].size()) == 13);  // 6 + 3 + 0 + 1 + 3
    DynamicArray<int> blocks;
    ActorTestAccess::AppendDofBlockSizes(*tree, blocks);
    REQUIRE(assembler.Analyze(n, blocks, reserved, OrderingMethod::Natural, error));
    contact->AppendStageContributorDofs(pairs);
    internal::HessianAssembler::DynamicUpdate update;
    REQUIRE(assembler.SetDynamicContributors(pairs.Lists(), update, error));
  }

  void AddCrossingCapsule(real friction, real dhat) {
    DynamicArray<Real3> ends;
    capsule->GetWorldVertices(ends);
    Real3 const axis = (ends[1] - ends[0]).normalized();
    Real3 const across = axis.cross(Real3(0.2, 0.1, 1)).normalized();
    Real3 const normal = axis.cross(across);
    // the second capsule's axis along `across`, its centre `normal` off the
    // first's middle by both radii and 0.4 d̂; placed in link 6's frame
    ColliderParams other = LinkCapsule(*tree, 6, friction);
    Real3 const centre = 0.5 * (ends[0] + ends[1]) + (2 * other.radius + 0.4 * dhat) * normal;
    Quat const world = Quat::FromTwoVectors(Real3::UnitZ(), across);
    Quat const frame = tree->GetLinkRotation(6);
    other.position = frame.conjugate() * (centre - tree->GetLinkPosition(6));
    other.rotation = frame.conjugate() * world;
    Error error;
    Collider const* second = contact->Add(other, nullptr, nullptr, tree, error);
    INFO(error.ToString());
    REQUIRE(second);
    ActorTestAccess::BeginStage(*tree, internal::MakeStage(IntegratorType::BackwardEuler, 0.01, false),
                                Real3::Zero());
    internal::StageContext stage;
    stage.coefficients.duration = 0.01;
    contact->BeginStage(stage);
    REQUIRE(contact->GetNumCandidates() >= 1);
    // each capsule's path, and their union for the pair's block: joints 0
    // (free, 6), 1 (spherical, 3), 2, 5 (revolute), 6 (spherical), 4
    // (revolute), 7 (spherical); link 3's joint is fixed
    DynamicArray<DynamicArray<int>> reserved;
    contact->AppendContributorDofs(reserved);
    REQUIRE(reserved.size() == 3);
    REQUIRE(reserved[2].size() == 18);
    DynamicArray<int> blocks;
    ActorTestAccess::AppendDofBlockSizes(*tree, blocks);
    REQUIRE(assembler.Analyze(n, blocks, reserved, OrderingMethod::Natural, error));
    internal::StageDofLists pairs;
    contact->AppendStageContributorDofs(pairs);
    for (std::size_t k = 0; k < pairs.size(); ++k) REQUIRE(pairs[k] == reserved[2]);
    internal::HessianAssembler::DynamicUpdate update;
    REQUIRE(assembler.SetDynamicContributors(pairs.Lists(), update, error));
    REQUIRE(!update.grew);  // the union reserved at the pattern build
  }

  real Energy() const { return ContactEnergy(*contact, assembler); }
  /// With `project`, the curvature of the rotated arms and of the link
  /// frame is left out (the PSD Hessian); without, the exact one.
  ActorDerivatives Derivatives(bool project = false) { return ContactDerivatives(*contact, assembler, n, project); }
  /// The iterate moved by α d from the saved one.
  void Move(VectorX const& d, real alpha) {
    ActorTestAccess::ApplyIncrementFromSaved(*tree, Span<real const>(d.data(), n), alpha);
  }
};

}  // namespace

TEST_CASE("a link collider's contact: gradient and Hessian over the joint DoFs match central differences",
          "[contact][articulated][derivatives]") {
  // against a plane, and against a capsule on another branch of the same
  // tree (the two links' paths share two joints: their columns summed)
  for (auto [friction, againstLink] : {std::pair{0.0, false}, {0.5, false}, {0.0, true}, {0.5, true}}) {
    CAPTURE(friction, againstLink);
    LinkContact c(friction, againstLink);
    REQUIRE(c.tree->GetDofOffset() == 0);
    // away from the stage start (a slip for friction to resist), still in
    // contact: a small joint move
    std::mt19937 rng(7);
    std::uniform_real_distribution<real> uniform(-1, 1);
    VectorX away(c.n);
    for (int i = 0; i < c.n; ++i) away[i] = 2e-5 * uniform(rng);
    ActorTestAccess::SaveIterate(*c.tree);
    c.Move(away, 1);
    ActorTestAccess::SaveIterate(*c.tree);
    ActorDerivatives const exact = c.Derivatives();
    REQUIRE(exact.gradient.norm() > 0);
    real const step = 1e-7;
    VectorX gradient(c.n);
    MatrixX hessian(c.n, c.n);
    for (int j = 0; j < c.n; ++j) {
      VectorX e = VectorX::Zero(c.n);
      e[j] = 1;
      c.Move(e, step);
      real const ep = c.Energy();
      VectorX const gp = c.Derivatives().gradient;
      c.Move(e, -step);
      real const em = c.Energy();
      VectorX const gm = c.Derivatives().gradient;
      gradient[j] = (ep - em) / (2 * step);
      hessian.col(j) = (gp - gm) / (2 * step);
    }
    ActorTestAccess::RestoreIterate(*c.tree);
    // central differences of the barrier (−(d−d̂)² log(d/d̂) at d ≈ 0.4 d̂) at
    // a step of 1e-7 in the joints (≤ 1e-7 m at the capsule): truncation
    // ~ step² |E'''| / 6, about 1e-7 of the gradient's scale here
    real const gradientError = (gradient - exact.gradient).cwiseAbs().maxCoeff() / exact.gradient.cwiseAbs().maxCoeff();
    CAPTURE(exact.gradient.transpose(), gradient.transpose());
    CHECK(gradientError <= 1e-6);
    if (friction == 0) {
      // the exact Hessian (barrier, the rotated arms' and the link frame's
      // curvature; with friction its chart's curvature is left out by
      // design) against the differences' symmetric part: the gradient of a
      // spherical or free joint's rotation is in its local increments
      // R Exp(δ), whose second differences differ by the antisymmetric
      // ½ ∇E·[eᵢ, eⱼ] (7.8e-5 of the largest entry here), which the
      // symmetric Hessian leaves out (stage/link_path.h)
      hessian = 0.5 * (hessian + hessian.transpose()).eval();
      real const hessianError = (hessian - exact.hessian).cwiseAbs().maxCoeff() / exact.hessian.cwiseAbs().maxCoeff();
      CHECK(hessianError <= 1e-6);
      // the curvature matters here: without it the Hessian misses by far
      // more than the tolerance (so the check above can fail)
      MatrixX const psd = c.Derivatives(true).hessian;
      CHECK((hessian - psd).cwiseAbs().maxCoeff() / exact.hessian.cwiseAbs().maxCoeff() >= 1e-4);
    }
  }
}

TEST_CASE("a link's speed bound holds along forward kinematics, and its safe step keeps the capsule off the plane",
          "[contact][articulated][ccd]") {
  LinkContact c(0.5);
  internal::LinkPath path = c.tree->GetLinkPath(kLink);
  std::mt19937 rng(3);
  std::uniform_real_distribution<real> uniform(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    VectorX d(c.n);
    for (int i = 0; i < c.n; ++i) d[i] = 0.2 * uniform(rng);
    real const arm = 0.1;
    real const bound = c.tree->LinkSpeedBound(path, d.data(), 1, arm);
    // a point `arm` from the link's origin: its speed sampled along α ∈ [0, 1]
    Real3 const local = arm * Real3(uniform(rng), uniform(rng), uniform(rng)).normalized();
    Real3 previous = Real3::Zero();
    int const samples = 400;
    for (int s = 0; s <= samples; ++s) {
      Real3 origin;
      Quat rotation;
      c.tree->ComputeLinkFrameAlong(path, d.data(), static_cast<real>(s) / samples, origin, rotation);
      Real3 const x = origin + rotation * local;
      if (s > 0) REQUIRE((x - previous).norm() * samples <= bound);
      previous = x;
    }
    // the frame at α = 0 is the current one
    Real3 origin;
    Quat rotation;
    c.tree->ComputeLinkFrameAlong(path, d.data(), 0, origin, rotation);
    c.tree->ComputeLinkFrame(path);
    REQUIRE((origin - path.position).norm() <= 1e-15);
  }
  // a step that drives the capsule through the plane: the safe step stops
  // before, and not far before, the first α where an end would touch it
  VectorX d = VectorX::Zero(c.n);
  d.segment<3>(0) = -0.05 * c.normal;  // the free root's translation (joint frame = world)
  d[4] = 0.3;                          // and a turn
  ActorTestAccess::SaveIterate(*c.tree);
  real const safe = c.contact->LargestSafeStep(Span<real const>(d.data(), c.n), 1);
  auto lowestGap = [&](real alpha) {
    c.Move(d, alpha);
    c.tree->ComputeLinkFrame(path);
    ColliderParams const shape = LinkCapsule(*c.tree, kLink, 0.5);
    real lowest = std::numeric_limits<real>::infinity();
    for (real z : {-shape.halfLength, shape.halfLength}) {
      Real3 const x = path.position + path.rotation * (shape.position + shape.rotation * Real3(0, 0, z));
      lowest = std::min(lowest, c.normal.dot(x) - c.offset - shape.radius);
    }
    return lowest;
  };
  REQUIRE(lowestGap(1) < 0);  // the full step passes through
  real touch = 1;             // the first touching α, by bisection on the true motion
  for (real lo = 0, hi = 1; hi - lo > 1e-9;) {
    touch = 0.5 * (lo + hi);
    (lowestGap(touch) > 0 ? lo : hi) = touch;
  }
  CAPTURE(safe, touch);
  CHECK(lowestGap(safe) > 0);
  CHECK(safe < touch);
  CHECK(safe >= 0.2 * touch);
  ActorTestAccess::RestoreIterate(*c.tree);
}

TEST_CASE("link colliders are validated", "[contact][articulated][errors]") {
  auto scene = MakeScene();
  ArticulatedActor* tree = MakeArticulated(*scene, BranchedTree(false, ArticulatedBlockSolve::Tree));
  Error error;
  ColliderParams capsule = LinkCapsule(*tree, 8, 0.5);
  REQUIRE(!scene->CreateCollider(capsule, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(error.GetMessage() == "link must name a link of the articulated actor, in [0, 8), got 8");
  capsule.link = -1;
  REQUIRE(!scene->CreateCollider(capsule, error));
  REQUIRE(error.GetMessage().find("link must name a link") != std::string::npos);
  // a link on another kind of actor
  RigidActor* box = MakeRigidBox(*scene, Real3(3, 0, 0), Quat::Identity(), Real3::Constant(0.1), 1);
  ColliderParams sphere;
  sphere.actor = box->GetHandle();
  sphere.link = 0;
  sphere.shape = ShapeType::Sphere;
  sphere.radius = 0.1;
  REQUIRE(!scene->CreateCollider(sphere, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(error.GetMessage().find("link: only a collider of an articulated actor names a link") == 0);
  // shapes a link cannot carry
  ColliderParams plane;
  plane.actor = tree->GetHandle();
  plane.link = 2;
  plane.shape = ShapeType::Plane;
  REQUIRE(!scene->CreateCollider(plane, error));
  REQUIRE(error.GetMessage().find("shape: a Plane is a static obstacle") == 0);
  plane.shape = ShapeType::Surface;
  REQUIRE(!scene->CreateCollider(plane, error));
  REQUIRE(error.GetMessage().find("shape: Surface needs a deformable or rod actor") == 0);
  REQUIRE(scene->GetNumColliders() == 1);  // the box's only
  capsule.link = 3;
  REQUIRE(scene->CreateCollider(capsule, error));
  REQUIRE(scene->GetNumColliders() == 2);
}

TEST_CASE("a mechanism's links touch each other: an arm folding onto itself stops on its own link",
          "[contact][articulated][self]") {
  // scenes::FoldingArmScene: link 2's target turns past where its capsule
  // meets link 0's; the exact check (which tests links 0 and 2 against each
  // other, not 0 and 1 or 1 and 2) at every step end
  SceneParams params;
  params.gravity = Real3::Zero();
  scenes::Builder b(params);
  scenes::FoldingArm const fold = scenes::AddFoldingArm(b);
  std::unique_ptr<Scene> scene = b.TakeScene();
  INFO(b.GetError().ToString());
  REQUIRE(scene);
  InterpenetrationCheck check(params.contact.activationDistance);
  REQUIRE(check.Find(*scene).empty());
  real const dt = 1.0 / 60;
  int const steps = 60;
  long newton = 0;
  DynamicArray<ContactInfo> contacts;
  for (int s = 0; s < steps; ++s) {
    Error error;
    REQUIRE(scenes::DriveFoldingArm(fold, (s + 1) * dt, error));
    StepChecked(*scene, dt, s, check, newton);
  }
  real const angle = fold.arm->GetJointCoordinate(2, 0);
  INFO("joint 2 at " << angle << " rad (first touch " << scenes::kFoldTouch << ", target " << scenes::kFoldTarget
                     << "), " << static_cast<real>(newton) / steps << " Newton/step");
  // it stopped on link 0, far short of its target: near the first touch
  // with the arm straight (the held joints 0 and 1 give a little under the
  // contact's moment, 100 N·m/rad each, so joint 2 turns a little further)
  CHECK(angle > scenes::kFoldTouch - 0.01);
  CHECK(angle < scenes::kFoldTouch + 0.05);
  // at rest, link 2's contacts balance its drive: their moment about joint 2
  // against the target's k (target − angle)
  scene->GetContacts(contacts);
  REQUIRE(!contacts.empty());
  Real3 const joint2 = fold.arm->GetLinkPosition(2);
  real moment = 0;
  for (ContactInfo const& c : contacts) {
    Collider const* a = scene->GetCollider(c.colliderA);
    Collider const* b = scene->GetCollider(c.colliderB);
    REQUIRE((a && b));
    CHECK(a->GetLink() == 0);  // only links 0 and 2 touch
    CHECK(b->GetLink() == 2);
    CHECK(c.normalForce > 0);
    // the force on link 2 (side B): the opposite of A's
    Real3 const onLink2 = -(c.normalForce * c.normal + c.frictionForce);
    moment += (c.point - joint2).cross(onLink2).z();
  }
  real const drive = 2 * (scenes::kFoldTarget - angle);
  INFO("contact moment " << moment << " N·m against the drive's " << drive);
  CHECK(std::abs(moment + drive) <= 0.02 * drive);
  // the pairs' union block was reserved at the pattern build: no growth
  SceneStats const& stats = scene->GetStats();
  CHECK(stats.patternBuilds == 1);
  CHECK(stats.contactPatternBuilds == 0);
  CHECK(static_cast<real>(newton) / steps <= 8);
}

TEST_CASE("a 5-link arm driven by targets pushes a box across the ground", "[contact][articulated]") {
  SceneParams params;
  params.gravity = Real3(0, -kGravity, 0);
  auto scene = MakeScene(params);
  ArmPush const push = MakeArmPush(*scene);
  InterpenetrationCheck check(params.contact.activationDistance);
  real const dt = 1.0 / 60;
  Real3 const box0 = push.box->GetPosition();
  int const steps = 120;
  long newton = 0;
  for (int s = 0; s < steps; ++s) {
    Error error;
    REQUIRE(push.carriage->SetTargetDof(push.start + push.speed * s * dt, error));
    StepChecked(*scene, dt, s, check, newton);
  }
  // the carriage travelled 0.6 m, 0.15 m of it before the capsule met the
  // box: the box follows at the carriage's speed (the hanging links bent by
  // the push within a few mm, the targets' stiffness against μ m g)
  real const moved = push.box->GetPosition().x() - box0.x();
  real const speed = push.box->GetLinearVelocity().x();
  std::printf("arm push: box moved %.4f m, speed %.4f m/s, %.2f Newton/step, %lld pattern builds\n", moved, speed,
              static_cast<real>(newton) / steps, static_cast<long long>(scene->GetStats().patternBuilds));
  CHECK(moved >= 0.4);
  CHECK(moved <= 0.45);
  CHECK(std::abs(speed - push.speed) <= 0.05 * push.speed);
  CHECK(std::abs(push.box->GetPosition().y() - box0.y()) <= 1e-3);  // slid, not lifted
  CHECK(static_cast<real>(newton) / steps <= 8);
  // the arm's joints were solved as one dense block (its colliders' paths span joints)
  CHECK(scene->GetStats().activeContacts > 0);
}

TEST_CASE("nodal contacts of every pair kind: gradient and exact Hessian match central differences",
          "[contact][derivatives]") {
  // a 3 × 3-node sheet (a deformable's Surface, no self contact) 0.2–0.8 d̂
  // above a static triangle-mesh grid turned 45° under it: point–triangle
  // pairs both ways, crossing edges, and points near edges and vertices
  SceneParams params;
  real const dhat = params.contact.activationDistance;
  for (real friction : {0.0, 0.5}) {
    CAPTURE(friction);
    auto scene = MakeScene(params);
    Error error;
    TriangleMesh grid;
    REQUIRE(MakeTriangleGrid(Real3(-0.01, 0, -0.01), 0.02, 0.02, 2, 2, grid, error));
    std::mt19937 rng(11);
    std::uniform_real_distribution<real> uniform(-1, 1);
    DeformableActorParams sheet;
    for (Real3 const& p : grid.nodes)
      sheet.nodes.push_back(p + Real3(1e-3 * uniform(rng), (0.5 + 0.3 * uniform(rng)) * dhat, 1e-3 * uniform(rng)));
    sheet.triangles = grid.triangles;
    sheet.thickness = 1e-3;
    DeformableActor* actor = MakeDeformable(*scene, sheet);
    int const n = actor->GetNumDofs();
    auto contact = std::make_unique<internal::ContactSystem>(params.contact);
    ColliderParams surface;
    surface.actor = actor->GetHandle();
    surface.group = 2;
    surface.mask = ~2u;
    surface.friction = friction;
    REQUIRE(contact->Add(surface, nullptr, actor, nullptr, error));
    ColliderParams below;
    below.shape = ShapeType::TriangleMesh;
    Quat const turn(Eigen::AngleAxis<real>(M_PI / 4, Real3::UnitY()));
    for (Real3 const& p : grid.nodes) below.vertices.push_back(turn * p);
    below.triangles = grid.triangles;
    below.friction = friction;
    INFO(error.ToString());
    REQUIRE(contact->Add(below, nullptr, nullptr, nullptr, error));
    ActorTestAccess::BeginStage(*actor, internal::MakeStage(IntegratorType::BackwardEuler, 0.01, false),
                                Real3::Zero());
    internal::StageContext stage;
    stage.coefficients.duration = 0.01;
    contact->BeginStage(stage);
    REQUIRE(contact->GetNumCandidates() > 20);
    DynamicArray<DynamicArray<int>> reserved;
    contact->AppendContributorDofs(reserved);
    DynamicArray<int> blocks;
    ActorTestAccess::AppendDofBlockSizes(*actor, blocks);
    internal::HessianAssembler assembler;
    REQUIRE(assembler.Analyze(n, blocks, reserved, OrderingMethod::Natural, error));
    internal::StageDofLists pairs;
    contact->AppendStageContributorDofs(pairs);
    internal::HessianAssembler::DynamicUpdate update;
    REQUIRE(assembler.SetDynamicContributors(pairs.Lists(), update, error));
    auto energy = [&] { return ContactEnergy(*contact, assembler); };
    auto derivatives = [&](bool project) { return ContactDerivatives(*contact, assembler, n, project); };
    auto move = [&](VectorX const& d, real alpha) {
      ActorTestAccess::ApplyIncrementFromSaved(*actor, Span<real const>(d.data(), n), alpha);
    };
    // a slip away from the stage start (5e-5 m, within the ramp's 1e-4 m)
    VectorX away(n);
    for (int i = 0; i < n; ++i) away[i] = 2e-5 * uniform(rng);
    ActorTestAccess::SaveIterate(*actor);
    move(away, 1);
    ActorTestAccess::SaveIterate(*actor);
    ActorDerivatives const exact = derivatives(false);
    REQUIRE(exact.gradient.norm() > 0);
    real const step = 1e-8;  // m: 1e-5 of d̂
    VectorX gradient(n);
    MatrixX hessian(n, n);
    for (int j = 0; j < n; ++j) {
      VectorX e = VectorX::Zero(n);
      e[j] = 1;
      move(e, step);
      real const ep = energy();
      VectorX const gp = derivatives(false).gradient;
      move(e, -step);
      real const em = energy();
      VectorX const gm = derivatives(false).gradient;
      gradient[j] = (ep - em) / (2 * step);
      hessian.col(j) = (gp - gm) / (2 * step);
    }
    ActorTestAccess::RestoreIterate(*actor);
    // truncation ~ (step / gap)² ≈ 1e-9 of the scale; the energy's
    // round-off over 2·step ~ 1e-16 |E| / 1e-8 m, ~1e-7 of the gradient
    real const gradientError =
        (gradient - exact.gradient).cwiseAbs().maxCoeff() / exact.gradient.cwiseAbs().maxCoeff();
    CHECK(gradientError <= 1e-6);
    real const scale = exact.hessian.cwiseAbs().maxCoeff();
    real const hessianError = (hessian - exact.hessian).cwiseAbs().maxCoeff() / scale;
    CHECK(hessianError <= 1e-6);
    std::printf("nodal contacts (friction %g): %d candidates, gradient error %.2g, Hessian error %.2g, projected %.2g\n",
                friction, contact->GetNumCandidates(), gradientError, hessianError,
                (hessian - derivatives(true).hessian).cwiseAbs().maxCoeff() / scale);
    // the distances' curvature matters: the projected Hessian misses it by
    // far more than the tolerance (so the check above can fail)
    CHECK((hessian - derivatives(true).hessian).cwiseAbs().maxCoeff() / scale >= 1e-4);
  }
}
