// Scenes on 2 MPI ranks against the same scenes in one process
// (docs/distributed.md), started by ctest through mpiexec
// (tests/mpi/CMakeLists.txt). The scenes are the perf harness's families, as
// `superdex_perf run --family F` builds them. Every rank also steps the
// one-process scene itself (the default communicator), so each rank compares
// its distributed result with its own reference.
#include <catch2/catch.hpp>

#include <functional>
#include <memory>
#include <tuple>
#include <string>

#include <mpi.h>

#include <superdex/core/mpi.h>
#include <superdex/solver/newton_solver.h>

#include "harness/families.h"
#include "scenes/contact_scenes.h"
#include "white_box.h"

using namespace superdex;

namespace {

constexpr real kDt = 1.0 / 60;

int Rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

/// True on every rank when `value` is the same on all of them.
bool SameOnAllRanks(unsigned long long value) {
  unsigned long long low = value, high = value;
  MPI_Allreduce(MPI_IN_PLACE, &low, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &high, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
  return low == high;
}

/// FNV-1a of the positions' bits
unsigned long long Hash(DynamicArray<Real3> const& positions) {
  unsigned long long hash = 1469598103934665603ull;
  for (Real3 const& x : positions)
    for (int c = 0; c < 3; ++c) {
      unsigned long long bits;
      std::memcpy(&bits, &x[c], sizeof bits);
      hash = (hash ^ bits) * 1099511628211ull;
    }
  return hash;
}

struct Solver {
  LinearSolverType type;
  PcgPreconditioner preconditioner = PcgPreconditioner::Gamg;
};

SceneParams Params(Communicator const& communicator, Solver const& solver) {
  SceneParams params;
  params.communicator = communicator;
  params.linearSolver = solver.type;
  params.pcg.preconditioner = solver.preconditioner;
  params.pcg.relativeTolerance = 1e-12;
  // Newton to well below the compared 1e-8: a step as a velocity of 1e-9 m/s
  // moves the nodes by < 2e-11 m
  params.newton.velocityTolerance = 1e-9;
  params.numThreads = 1;
  return params;
}

perf::FamilyScene Build(std::string const& family, std::string const& size, SceneParams const& params) {
  perf::FamilyScene out;
  Error error;
  bool const built = perf::BuildFamilyScene(family, size, 1, params, out, error);
  INFO(error.ToString());
  REQUIRE(built);
  return out;
}

/// Takes the steps; returns the Newton systems solved by CG on a reused
/// factorization, over all of them.
int Steps(Scene& scene, int steps) {
  int reusedFactorSolves = 0;
  for (int s = 0; s < steps; ++s) {
    Error error;
    bool const ok = scene.Step(kDt, error);
    INFO("step " << s << ": " << error.ToString());
    REQUIRE(ok);
    reusedFactorSolves += scene.GetStats().reusedFactorSolves;
  }
  return reusedFactorSolves;
}

/// How far `actual` is from `expected` and how far `expected` moved from
/// `initial`, each the largest over the points [m].
struct Agreement {
  real worst = 0, moved = 0;
};
Agreement Compare(DynamicArray<Real3> const& initial, DynamicArray<Real3> const& expected,
                  DynamicArray<Real3> const& actual) {
  REQUIRE(expected.size() == actual.size());
  REQUIRE(initial.size() == expected.size());
  Agreement a;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    a.worst = std::max(a.worst, (actual[i] - expected[i]).norm());
    a.moved = std::max(a.moved, (expected[i] - initial[i]).norm());
  }
  return a;
}

/// Steps `family` at `size` 20 times in one process and on the 2 ranks of
/// MPI_COMM_WORLD with `solver`, and checks that the positions agree;
/// returns the reused-factor solves {in one process, on 2 ranks}.
std::pair<int, int> CheckAgreement(std::string const& family, std::string const& size, Solver const& solver) {
  Error error;
  Communicator const world = Communicator::World(error);
  REQUIRE(world.GetSize() == 2);
  perf::FamilyScene reference = Build(family, size, Params(Communicator(), solver));
  perf::FamilyScene distributed = Build(family, size, Params(world, solver));
  int const referenceReuse = Steps(*reference.scene, 20);
  int const distributedReuse = Steps(*distributed.scene, 20);

  // the work was divided: each rank owns part of the rows, and the solver
  // ran across both ranks
  SceneStats const& stats = distributed.scene->GetStats();
  CAPTURE(stats.linearSolver, stats.ownedDofs, stats.numDofs);
  REQUIRE(stats.ranks == 2);
  REQUIRE(stats.ownedDofs > 0);
  REQUIRE(stats.ownedDofs < stats.numDofs);
  int owned = stats.ownedDofs;
  MPI_Allreduce(MPI_IN_PLACE, &owned, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  REQUIRE(owned == stats.numDofs);
  REQUIRE(stats.linearSolver.find("2 ranks") != std::string::npos);

  // every position within 1e-8 of the scene length L (the positions are of
  // order L), after 20 steps in which the scene moved by far more
  DynamicArray<Real3> const expected = reference.trackedPositions();
  DynamicArray<Real3> const actual = distributed.trackedPositions();
  perf::FamilyScene start = Build(family, size, Params(Communicator(), solver));
  auto const [worst, moved] = Compare(start.trackedPositions(), expected, actual);
  CAPTURE(worst, moved, reference.length);
  REQUIRE(moved > 1e-4 * reference.length);
  REQUIRE(worst <= 1e-8 * reference.length);
  // and the ranks hold the same state, bit for bit
  REQUIRE(SameOnAllRanks(Hash(actual)));
  return {referenceReuse, distributedReuse};
}

}  // namespace

TEST_CASE("a scene on 2 ranks agrees with the same scene in one process", "[mpi][agreement]") {
  auto const [family, size] = GENERATE(std::pair<std::string, std::string>{"cantilever", "12x3x3"},
                                       std::pair<std::string, std::string>{"rods", "6x24"});
  auto const solver = GENERATE(Solver{LinearSolverType::PetscMumps},
                               Solver{LinearSolverType::PetscPcg, PcgPreconditioner::Gamg},
                               Solver{LinearSolverType::PetscPcg, PcgPreconditioner::BlockJacobi});
  CAPTURE(family, size, ToString(solver.type), ToString(solver.preconditioner));
  CheckAgreement(family, size, solver);
}

TEST_CASE("MUMPS reuses its factorization across ranks as in one process", "[mpi][agreement]") {
  // (NewtonParams::reuseFactorization, on by default): CG preconditioned by
  // the distributed factor, on products of each rank's own rows, gathered.
  // The beam is large enough for a factorization to be worth CG iterations
  // (12x3x3 is not: it refactorizes every iteration)
  auto const [referenceReuse, distributedReuse] = CheckAgreement("cantilever", "24x6x6", {LinearSolverType::PetscMumps});
  CAPTURE(referenceReuse, distributedReuse);
  REQUIRE(referenceReuse > 0);
  REQUIRE(distributedReuse > 0);
}

TEST_CASE("each contributor's energy is counted on exactly one rank", "[mpi][energy]") {
  // The stage solver's energy across ranks (the line search's): each rank
  // sums the contributors it owns (HessianAssembler::Owns, the owner of
  // their first DoF) through Actor::Energy(owned), and the ranks' sums are
  // added. Checked here on the assembler and the actors directly: the flags
  // split the contributors, and each actor's shares add up to its energy.
  auto const [family, size] = GENERATE(std::pair<std::string, std::string>{"cantilever", "12x3x3"},
                                       std::pair<std::string, std::string>{"cloth", "8x8"},
                                       std::pair<std::string, std::string>{"rods", "6x24"},
                                       std::pair<std::string, std::string>{"chain-articulated", "N=8"},
                                       std::pair<std::string, std::string>{"chain", "N=8"});
  CAPTURE(family, size);
  perf::FamilyScene scene = Build(family, size, Params(Communicator(), {LinearSolverType::PetscMumps}));
  Steps(*scene.scene, 2);  // a deformed state, and a stage's targets to measure against
  using Access = internal::ActorTestAccess;
  DynamicArray<Actor const*> actors;
  DynamicArray<int> blockSizes, firstContributor;
  DynamicArray<DynamicArray<int>> contributorDofs;
  scene.scene->ForEachActor([&](Actor const& actor) {
    actors.push_back(&actor);
    Access::AppendDofBlockSizes(actor, blockSizes);
    firstContributor.push_back(static_cast<int>(contributorDofs.size()));
    Access::AppendContributorDofs(actor, contributorDofs);
  });
  firstContributor.push_back(static_cast<int>(contributorDofs.size()));
  int const numContributors = firstContributor.back();

  internal::HessianAssembler assembler;
  Error error;
  REQUIRE(assembler.Analyze(scene.scene->GetNumDofs(), blockSizes, contributorDofs, OrderingMethod::Metis,
                            error, 2, Rank()));
  // every contributor owned by exactly one rank
  DynamicArray<int> owners(numContributors);
  for (int c = 0; c < numContributors; ++c) owners[c] = assembler.Owns(c) ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, owners.data(), numContributors, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  REQUIRE(std::all_of(owners.begin(), owners.end(), [](int n) { return n == 1; }));

  for (std::size_t a = 0; a < actors.size(); ++a) {
    int const count = firstContributor[a + 1] - firstContributor[a];
    real const whole = Access::Energy(*actors[a]);
    real shares[2] = {Access::Energy(*actors[a], assembler, firstContributor[a]), 0};
    shares[1] = std::abs(shares[0]);
    MPI_Allreduce(MPI_IN_PLACE, shares, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    CAPTURE(a, count, whole, shares[0]);
    // the same terms added in another grouping: round-off of the terms' size
    REQUIRE(std::abs(shares[0] - whole) <= 1e-12 * shares[1]);
  }
}

TEST_CASE("a Newton failure on one rank fails the step on both and changes nothing",
          "[mpi][failure]") {
  Error error;
  Communicator const world = Communicator::World(error);
  REQUIRE(world.GetSize() == 2);
  auto const solver = GENERATE(Solver{LinearSolverType::PetscMumps},
                               Solver{LinearSolverType::PetscPcg, PcgPreconditioner::Gamg});
  CAPTURE(ToString(solver.type));
  perf::FamilyScene scene = Build("cantilever", "12x3x3", Params(world, solver));
  Steps(*scene.scene, 3);
  DynamicArray<Real3> const before = scene.trackedPositions();
  real const time = scene.scene->GetTime();

  // rank 1 alone fails its first linear solve
  if (Rank() == 1) internal::SetFaultInjectionForTesting(*scene.scene, {.failLinearSolveAtIteration = 1});
  Error stepError;
  bool const ok = scene.scene->Step(kDt, stepError);
  CAPTURE(stepError.ToString());
  REQUIRE_FALSE(ok);
  REQUIRE(stepError.GetCode() == ErrorCode::LinearSolverFailed);
  REQUIRE(stepError.GetMessage().find("failure injected by a test") != std::string::npos);
  REQUIRE(SameOnAllRanks(std::hash<std::string>{}(stepError.GetMessage())));
  REQUIRE(Hash(scene.trackedPositions()) == Hash(before));
  REQUIRE(scene.scene->GetTime() == time);

  // without the fault both ranks step on, from the unchanged state
  internal::SetFaultInjectionForTesting(*scene.scene, {});
  Steps(*scene.scene, 1);
  REQUIRE(Hash(scene.trackedPositions()) != Hash(before));
  REQUIRE(SameOnAllRanks(Hash(scene.trackedPositions())));
}

TEST_CASE("solvers of one process are refused across ranks, naming the field", "[mpi][refusal]") {
  Error error;
  Communicator const world = Communicator::World(error);
  REQUIRE(world.GetSize() == 2);
  for (LinearSolverType type : {LinearSolverType::Cholmod, LinearSolverType::Dense}) {
    SceneParams params;
    params.communicator = world;
    params.linearSolver = type;
    Error refused;
    REQUIRE_FALSE(Scene::Create(params, refused));
    CAPTURE(refused.ToString());
    REQUIRE(refused.GetCode() == ErrorCode::InvalidArgument);
    REQUIRE(refused.GetMessage().find(std::string(ToString(type))) != std::string::npos);
    REQUIRE(refused.GetMessage().find("2 ranks") != std::string::npos);
  }
  SceneParams params;
  params.communicator = world;
  params.linearSolver = LinearSolverType::PetscPcg;
  params.pcg.preconditioner = PcgPreconditioner::Icc;
  Error refused;
  REQUIRE_FALSE(Scene::Create(params, refused));
  CAPTURE(refused.ToString());
  REQUIRE(refused.GetMessage().find("preconditioner Icc") != std::string::npos);

  // a scene refuses the change too, and keeps its solver
  params.pcg.preconditioner = PcgPreconditioner::Gamg;
  auto scene = Scene::Create(params, error);
  REQUIRE(scene);
  REQUIRE_FALSE(scene->SetLinearSolver(LinearSolverType::Cholmod, PcgParams{}, refused));
  REQUIRE(scene->GetParams().linearSolver == LinearSolverType::PetscPcg);
}

TEST_CASE("a step whose dt or sub-stepping differs between the ranks fails on both and changes nothing",
          "[mpi][refusal]") {
  // a different dt per rank was accepted (the scene times drifted apart);
  // sub-stepping on one rank only deadlocked. One reduction before the step
  // refuses both on every rank with the same message
  Error error;
  Communicator const world = Communicator::World(error);
  REQUIRE(world.GetSize() == 2);
  perf::FamilyScene scene = Build("cantilever", "12x3x3", Params(world, Solver{LinearSolverType::PetscMumps}));
  Steps(*scene.scene, 1);
  DynamicArray<Real3> const before = scene.trackedPositions();
  real const time = scene.scene->GetTime();
  auto refused = [&](real dt, std::string const& what) {
    Error stepError;
    REQUIRE_FALSE(scene.scene->Step(dt, stepError));
    CAPTURE(stepError.ToString());
    REQUIRE(stepError.GetCode() == ErrorCode::InvalidArgument);
    REQUIRE(stepError.GetMessage() == "Step: the 2 ranks of SceneParams.communicator disagree on " + what +
                                          " (every rank must make the same calls with the same arguments: "
                                          "docs/distributed.md); the scene is unchanged");
    REQUIRE(Hash(scene.trackedPositions()) == Hash(before));
    REQUIRE(scene.scene->GetTime() == time);
  };
  refused(Rank() == 0 ? kDt : 2 * kDt, "dt");
  if (Rank() == 1) REQUIRE(scene.scene->SetSubstepParams({.maxSubsteps = 8}, error));
  refused(kDt, "SceneParams.substeps.maxSubsteps");
  if (Rank() == 0) REQUIRE(scene.scene->SetSubstepParams({.maxSubsteps = 8}, error));
  Steps(*scene.scene, 1);  // agreeing again
  REQUIRE(scene.scene->GetTime() == time + kDt);
  REQUIRE(SameOnAllRanks(Hash(scene.trackedPositions())));
}

TEST_CASE("a Fortran handle that names no communicator is refused", "[mpi][refusal]") {
  // it ran as one rank, silently
  Error error;
  REQUIRE(Communicator::World(error).GetSize() == 2);
  SceneParams params;
  params.communicator = Communicator::FromFortranHandle(12345);
  REQUIRE_FALSE(Scene::Create(params, error));
  CHECK(error.GetCode() == ErrorCode::InvalidArgument);
  CHECK(error.GetMessage() == "SceneParams.communicator has Fortran handle 12345, which is not a communicator of "
                              "this process (MPI_Comm_f2c gives no valid communicator)");
  CHECK(params.communicator.GetSize() == 1);
  params.communicator = ToCommunicator(MPI_COMM_NULL);
  REQUIRE_FALSE(Scene::Create(params, error));
  CHECK(error.GetMessage().find("is not a communicator of this process") != std::string::npos);
}

namespace {

/// Every collider's world vertices, in id order.
DynamicArray<Real3> ColliderVertices(Scene const& scene) {
  DynamicArray<Real3> all, vertices;
  for (int id = 0; id < scene.GetNumColliders(); ++id) {
    Collider const* collider = scene.GetCollider(id);
    REQUIRE(collider);
    collider->GetWorldVertices(vertices);
    all.insert(all.end(), vertices.begin(), vertices.end());
  }
  return all;
}

using ContactBuilder = std::function<scenes::ContactScene(SceneParams, Error&)>;

std::unique_ptr<Scene> BuildContact(ContactBuilder const& build, SceneParams const& params) {
  Error error;
  scenes::ContactScene built = build(params, error);
  INFO(error.ToString());
  REQUIRE(built.scene);
  return std::move(built.scene);
}

/// A straight 30-node rod (0.6 m, r = 5 mm, E = 1e7 Pa) falling 5 cm onto
/// the ground beside a falling 0.2 m, 1 kg rigid box: the two in group 2,
/// which their masks leave out (each touches the ground only)
scenes::ContactScene RodAndBoxOnTheGround(SceneParams params, Error& error) {
  scenes::Builder b(params);
  b.AddGround();
  RodActorParams rod;
  for (int i = 0; i < 30; ++i) rod.nodes.push_back(Real3(-0.3 + 0.6 * i / 29, 0.05, 0.3));
  rod.radius = 5e-3;
  rod.youngModulus = 1e7;
  b.AddSurface(b.AddRod(rod), false);
  RigidActorParams body;
  body.position = Real3(0, 0.15, -0.3);
  body.inertia = Real3::Constant(0.08 / 12);
  ColliderParams box;
  RigidActor* actor = b.AddRigid(body);
  if (actor) box.actor = actor->GetHandle();
  box.shape = ShapeType::Box;
  box.halfExtents = Real3::Constant(0.1);
  box.group = 2;
  box.mask = ~2u;
  b.AddCollider(box);
  return scenes::Finish(b, 0.5, error);
}

}  // namespace

TEST_CASE("contact with obstacles on 2 ranks agrees with the same scene in one process", "[mpi][contact]") {
  // (docs/distributed.md, "Contact across ranks", step 1): every rank holds
  // every pair and takes the same safe step; each part assembles its rows
  auto const [name, build, integrator] = GENERATE(
      std::tuple<std::string, ContactBuilder, IntegratorType>{
          "a soft ball landing on the ground",
          [](SceneParams p, Error& e) { return scenes::BallDropScene(p, 0.05, 4, e); }, IntegratorType::Bdf2},
      std::tuple<std::string, ContactBuilder, IntegratorType>{"a rod and a rigid box landing on the ground",
                                                              RodAndBoxOnTheGround, IntegratorType::BackwardEuler});
  auto const solver = GENERATE(Solver{LinearSolverType::PetscMumps},
                               Solver{LinearSolverType::PetscPcg, PcgPreconditioner::BlockJacobi});
  CAPTURE(name, ToString(solver.type), ToString(solver.preconditioner));
  Error error;
  Communicator const world = Communicator::World(error);
  REQUIRE(world.GetSize() == 2);
  SceneParams one = Params(Communicator(), solver), two = Params(world, solver);
  for (SceneParams* p : {&one, &two}) {
    p->integrator = integrator;
    // 1e-9 m/s is below what the contact scenes' Newton reaches (round-off
    // in the barrier's sums): 1e-8 m/s moves the nodes < 2e-10 m per step
    p->newton.velocityTolerance = 1e-8;
    p->newton.maxIterations = 100;
  }
  auto reference = BuildContact(build, one);
  auto distributed = BuildContact(build, two);
  DynamicArray<Real3> const initial = ColliderVertices(*reference);
  int touching = 0;
  for (int s = 0; s < 30; ++s) {
    bool const a = reference->Step(kDt, error);
    INFO("one process, step " << s << ": " << error.ToString());
    REQUIRE(a);
    bool const b = distributed->Step(kDt, error);
    INFO("2 ranks, step " << s << ": " << error.ToString());
    REQUIRE(b);
    touching += distributed->GetStats().activeContacts > 0;
    REQUIRE(distributed->GetStats().activeContacts == reference->GetStats().activeContacts);
  }
  SceneStats const& stats = distributed->GetStats();
  REQUIRE(stats.ranks == 2);
  REQUIRE(stats.ownedDofs < stats.numDofs);
  CHECK(touching > 0);  // it landed
  // the analysed pattern held every contact: built once, never grown
  CHECK(stats.patternBuilds == 1);
  CHECK(stats.contactPatternBuilds == 0);
  DynamicArray<Real3> const expected = ColliderVertices(*reference), actual = ColliderVertices(*distributed);
  auto const [worst, moved] = Compare(initial, expected, actual);
  CAPTURE(worst, moved);
  REQUIRE(moved > 1e-3);  // it fell (0.05 m or 0.9 d̂ and then some)
  // within round-off of the one-process run (the ranks sum in another order)
  CHECK(worst <= 1e-8);
  REQUIRE(SameOnAllRanks(Hash(actual)));
}

TEST_CASE("contact that may join two bodies is refused across ranks, naming the colliders", "[mpi][refusal]") {
  Error error;
  SceneParams params;
  params.communicator = Communicator::World(error);
  REQUIRE(params.communicator.GetSize() == 2);
  auto scene = Scene::Create(params, error);
  REQUIRE(scene);
  auto make = [&](ColliderParams const& p, Error& e) { return scene->CreateCollider(p, e); };
  auto body = [&](real y) {
    RigidActorParams rigid;
    rigid.position = Real3(0, y, 0);
    RigidActor* actor = scene->CreateRigidActor(rigid, error);
    REQUIRE(actor);
    return actor->GetHandle();
  };
  ColliderParams ground;
  ground.shape = ShapeType::Plane;  // group 1, every group in its mask
  REQUIRE(make(ground, error));     // an obstacle: accepted
  ColliderParams box;
  box.actor = body(0.5);
  box.shape = ShapeType::Box;
  box.halfExtents = Real3::Constant(0.1);
  box.group = 2;
  box.mask = 1;  // the ground's group only
  REQUIRE(make(box, error));
  // a second body whose group the box's mask holds not, but whose mask
  // holds the box's group: it may touch the box
  ColliderParams sphere;
  sphere.actor = body(1);
  sphere.shape = ShapeType::Sphere;
  sphere.radius = 0.1;
  sphere.group = 1;
  Error refused;
  CHECK_FALSE(make(sphere, refused));
  CHECK(refused.GetCode() == ErrorCode::NotSupported);
  CHECK(refused.GetMessage() ==
        "CreateCollider: on a scene across 2 MPI ranks only contact with static and kinematic obstacles is "
        "supported: it may touch collider 1 (Box, on a body): give them groups and masks that exclude each other");
  CHECK(scene->GetNumColliders() == 2);
  // in a group of its own, touching the ground's only: accepted
  sphere.group = 4;
  sphere.mask = 1;
  CHECK(make(sphere, refused));
  // a Surface that touches itself
  DeformableActorParams cloth;
  cloth.nodes = {Real3(0, 2, 0), Real3(1, 2, 0), Real3(0, 2, 1)};
  cloth.triangles = {{0, 2, 1}};
  DeformableActor* sheet = scene->CreateDeformableActor(cloth, error);
  REQUIRE(sheet);
  ColliderParams surface;
  surface.actor = sheet->GetHandle();
  surface.group = 8;
  surface.mask = 8u | 1u;
  CHECK_FALSE(make(surface, refused));
  CHECK(refused.GetCode() == ErrorCode::NotSupported);
  CHECK(refused.GetMessage().find("this Surface would touch itself") != std::string::npos);
  CHECK(scene->GetNumColliders() == 3);
  surface.mask = 1u;  // the ground only
  Collider* accepted = make(surface, refused);
  INFO(refused.ToString());
  CHECK(accepted);
  CHECK(scene->GetNumColliders() == 4);
}

TEST_CASE("the re-analysing pattern policy is refused for contact across ranks", "[mpi][refusal]") {
  Error error;
  SceneParams params;
  params.communicator = Communicator::World(error);
  params.patternPolicy = PatternPolicy::RebuildWhenChanged;
  auto scene = Scene::Create(params, error);
  REQUIRE(scene);
  ColliderParams ground;
  ground.shape = ShapeType::Plane;
  Error refused;
  CHECK_FALSE(scene->CreateCollider(ground, refused));
  CHECK(refused.GetCode() == ErrorCode::NotSupported);
  CHECK(refused.GetMessage().find("SceneParams.patternPolicy RebuildWhenChanged") != std::string::npos);
  CHECK(scene->GetNumColliders() == 0);
}
