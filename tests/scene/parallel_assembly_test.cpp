// Parallel assembly (SceneParams::numThreads): elements, stencils and
// constraints evaluated on several threads write only their own staging
// slots, summed per entry in contributor order, so the assembled Hessian and
// gradient, and every step after them, are bit-identical for any thread
// count.
#include "test_scenes.h"
#include "white_box.h"

#include <cstring>
#include <limits>

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/core/parallel.h>

using namespace superdex;
using namespace superdex::test;
using internal::ActorTestAccess;

namespace {

/// A square cloth of n × n cells in the xz-plane (triangles and hinges).
DeformableActor* MakeCloth(Scene& scene, int n, Real3 const& origin) {
  DeformableActorParams p;
  real const size = 0.3;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) p.nodes.push_back(origin + Real3(size * i / n, 0, size * j / n));
  auto id = [n](int i, int j) { return i + (n + 1) * j; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      p.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      p.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  p.youngModulus = 1e5;
  p.density = 200;
  Error error;
  DeformableActor* cloth = scene.CreateDeformableActor(p, error);
  INFO(error.ToString());
  REQUIRE(cloth);
  return cloth;
}

/// A chain of 80 bodies, a 8×4×4-cell tet beam pinned at one end, a
/// 200-element rod clamped to the chain and a 16×16 cloth pinned at a corner:
/// every loop longer than its parallel grain.
std::unique_ptr<Scene> MakeMixedScene(int numThreads) {
  SceneParams params;
  params.numThreads = numThreads;
  Chain chain = MakeChain(80, params);
  Scene& scene = *chain.scene;
  DeformableActorParams soft;
  soft.youngModulus = 1e5;
  soft.density = 500;
  DeformableActor* beam = MakeBox(scene, Real3(0, -0.5, 0), Real3(0.4, 0.1, 0.1), {8, 4, 4}, soft);
  PinNodes(scene, *beam, 1e6, [](Real3 const& x) { return x.x() < 1e-9; });
  RodActorParams rod;
  rod.radius = 0.003;
  RodActor* r = MakeStraightRod(scene, Real3(0.05, 0, 0), Real3(0, -1, 0.2), 0.4, 200, rod);
  ClampRodEnd(scene, *r, *chain.bodies[0], false, 1e5, 1e2);
  DeformableActor* cloth = MakeCloth(scene, 16, Real3(1, -1, 0));
  PinNodes(scene, *cloth, 1e5, [](Real3 const& x) { return x.x() < 1 + 1e-9 && x.z() < 1e-9; });
  return std::move(chain.scene);
}

/// Every actor's state, concatenated.
DynamicArray<real> State(Scene& scene) {
  DynamicArray<real> state;
  scene.ForEachActor([&](Actor& actor) {
    if (auto* rigid = dynamic_cast<RigidActor*>(&actor)) {
      for (int k = 0; k < 3; ++k) state.push_back(rigid->GetPosition()[k]);
      for (int k = 0; k < 4; ++k) state.push_back(rigid->GetRotation().coeffs()[k]);
    } else if (auto* deformable = dynamic_cast<DeformableActor*>(&actor)) {
      for (int i = 0; i < deformable->GetNumNodes(); ++i)
        for (int k = 0; k < 3; ++k) state.push_back(deformable->GetNodePosition(i)[k]);
    } else if (auto* rod = dynamic_cast<RodActor*>(&actor)) {
      for (int i = 0; i < rod->GetNumNodes(); ++i)
        for (int k = 0; k < 3; ++k) state.push_back(rod->GetNodePosition(i)[k]);
    }
  });
  return state;
}

bool BitIdentical(DynamicArray<real> const& a, DynamicArray<real> const& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(real)) == 0;
}

}  // namespace

TEST_CASE("a mixed scene steps bit-identically on 1, 2, 3 and 4 threads", "[long][scene][assembly][parallel]") {
  std::unique_ptr<Scene> serial = MakeMixedScene(1);
  REQUIRE(serial->GetNumThreads() == 1);
  StepOk(*serial, 1.0 / 60, 4);
  DynamicArray<real> const expected = State(*serial);
  SceneStats const serialStats = serial->GetStats();
  REQUIRE(serialStats.newtonIterations > 0);

  int const threads = GENERATE(2, 3, 4);
  CAPTURE(threads);
  std::unique_ptr<Scene> parallel = MakeMixedScene(threads);
  REQUIRE(parallel->GetNumThreads() == threads);
  StepOk(*parallel, 1.0 / 60, 4);
  CHECK(parallel->GetStats().newtonIterations == serialStats.newtonIterations);
  CHECK(BitIdentical(State(*parallel), expected));

  // switching the thread count between steps keeps it so
  Error error;
  REQUIRE(serial->SetNumThreads(threads, error));
  REQUIRE(parallel->SetNumThreads(1, error));
  StepOk(*serial, 1.0 / 60, 2);
  StepOk(*parallel, 1.0 / 60, 2);
  CHECK(BitIdentical(State(*parallel), State(*serial)));
}

TEST_CASE("assembled Hessian and gradient of an actor are bit-identical for any thread count",
          "[assembly][parallel]") {
  std::unique_ptr<Scene> scene = MakeMixedScene(1);
  StepOk(*scene, 1.0 / 60, 1);  // a deformed state
  int checkedActors = 0;
  scene->ForEachActor([&](Actor& actor) {
    if (!dynamic_cast<DeformableActor*>(&actor) && !dynamic_cast<RodActor*>(&actor)) return;
    ++checkedActors;
    int const n = actor.GetNumDofs();
    DynamicArray<DynamicArray<int>> contributors;
    DynamicArray<int> blocks;
    ActorTestAccess::AppendContributorDofs(actor, contributors);
    ActorTestAccess::AppendDofBlockSizes(actor, blocks);
    // the actor's DoFs as if it were alone: from 0
    for (auto& dofs : contributors)
      for (int& d : dofs) d -= actor.GetDofOffset();
    auto assemble = [&](int threads, DynamicArray<real>& gradient) {
      internal::ParallelExecutor executor;
      executor.SetNumThreads(threads);
      internal::HessianAssembler assembler;
      Error error;
      REQUIRE(assembler.Analyze(n, blocks, contributors, OrderingMethod::Metis, error));
      assembler.SetExecutor(&executor);
      REQUIRE(assembler.IsStaged() == (threads > 1));
      gradient.assign(n, 0);
      ActorTestAccess::AddGradientAndHessian(actor, Span<real>(gradient.data(), n), assembler, 0, false);
      return assembler.GetMatrix().values;
    };
    DynamicArray<real> serialGradient, gradient;
    DynamicArray<real> const serialValues = assemble(1, serialGradient);
    REQUIRE(std::any_of(serialGradient.begin(), serialGradient.end(), [](real g) { return g != 0; }));
    for (int threads : {2, 3, 8}) {
      CAPTURE(actor.GetNumDofs(), threads);
      DynamicArray<real> const values = assemble(threads, gradient);
      CHECK(BitIdentical(values, serialValues));
      CHECK(BitIdentical(gradient, serialGradient));
    }
  });
  REQUIRE(checkedActors == 3);
}

TEST_CASE("a thread count outside [0, kMaxThreads] is refused, naming the field, and changes nothing",
          "[scene][parallel][input]") {
  // 1000 workers exhausted a 4 GB address space and aborted the process;
  // 2^31 - 1 raised bad_alloc from the per-thread scratch and left the scene
  // set to it (every later step failing)
  for (int bad : {kMaxThreads + 1, 1000, std::numeric_limits<int>::max()}) {
    CAPTURE(bad);
    SceneParams params;
    params.numThreads = bad;
    Error error;
    REQUIRE_FALSE(Scene::Create(params, error));
    CHECK(error.GetCode() == ErrorCode::InvalidArgument);
    CHECK(error.GetMessage() == "SceneParams.numThreads must be in [0, kMaxThreads = 256] (0: every CPU), got " +
                                    std::to_string(bad));
    std::unique_ptr<Scene> scene = MakeMixedScene(2);
    REQUIRE_FALSE(scene->SetNumThreads(bad, error));
    CHECK(Contains(error.GetMessage(), "numThreads must be in [0, kMaxThreads = 256]"));
    CHECK(scene->GetNumThreads() == 2);
    CHECK(scene->GetParams().numThreads == 2);
    INFO(error.ToString());
    REQUIRE(scene->Step(0.01, error));
  }
}

TEST_CASE("the thread count set between a destruction and the next step touches no destroyed actor",
          "[scene][parallel][lifetime]") {
  // SetNumThreads reserved per-thread scratch on every term of the last
  // analysis, a destroyed actor's included (a use after free found by
  // fuzz_scene_api: corpus/scene_api/found_stale_term_set_threads.bin;
  // ASan and UBSan see it, a Release build may not)
  std::unique_ptr<Scene> scene = MakeMixedScene(2);
  Error error;
  REQUIRE(scene->Step(0.01, error));
  DynamicArray<ActorHandle> handles;
  scene->ForEachActor([&](Actor& actor) { handles.push_back(actor.GetHandle()); });
  REQUIRE(handles.size() >= 2);
  REQUIRE(scene->DestroyActor(handles.front(), error));
  REQUIRE(scene->SetNumThreads(1, error));
  REQUIRE(scene->SetNumThreads(2, error));
  INFO(error.ToString());
  REQUIRE(scene->Step(0.01, error));
  REQUIRE(scene->GetNumActors() == static_cast<int>(handles.size()) - 1);
}

TEST_CASE("a negative thread count is refused, naming the field", "[scene][parallel][input]") {
  SceneParams params;
  params.numThreads = -1;
  Error error;
  REQUIRE_FALSE(Scene::Create(params, error));
  CHECK(error.GetCode() == ErrorCode::InvalidArgument);
  CHECK(Contains(error.GetMessage(), "SceneParams.numThreads"));
  CHECK(Contains(error.GetMessage(), "-1"));
  std::unique_ptr<Scene> scene = MakeMixedScene(2);
  REQUIRE_FALSE(scene->SetNumThreads(-3, error));
  CHECK(Contains(error.GetMessage(), "-3"));
  CHECK(scene->GetNumThreads() == 2);
  REQUIRE(scene->SetNumThreads(0, error));
  CHECK(scene->GetNumThreads() == internal::AvailableCpus());
}
