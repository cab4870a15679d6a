// Hot paths allocate nothing: once the pattern is built and the solver has
// analyzed it, a whole step (snapshot, Newton iterations, assembly fill,
// factorization, solve, line search, commit) performs no heap allocation
// through operator new. (CHOLMOD's own workspace uses malloc and is reused
// across factorizations by CHOLMOD itself.)
#include "test_scenes.h"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<long> allocations{0};
}

void* operator new(std::size_t size) {
  ++allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

using namespace superdex;
using namespace superdex::test;

TEST_CASE("steps after the first allocate nothing", "[scene][allocation]") {
  LinearSolverType const solver = GENERATE(LinearSolverType::Cholmod, LinearSolverType::Dense);
  CAPTURE(ToString(solver));
  SceneParams params;
  params.linearSolver = solver;
  params.integrator = IntegratorType::Bdf2;
  Chain chain = MakeChain(12, params);
  Error error;
  Constraint* first = nullptr;
  chain.scene->ForEachConstraint([&](Constraint& c) {
    if (!first) first = &c;
  });
  REQUIRE(first->RegisterQuery(QueryType::ConstraintForce, error));
  StepOk(*chain.scene, 1e-3, 2);  // builds pattern, analysis, snapshots

  long const before = allocations.load();
  int newtonIterations = 0;
  for (int i = 0; i < 20; ++i) {
    bool const ok = chain.scene->Step(1e-3, error);
    newtonIterations += chain.scene->GetStats().newtonIterations;
    if (!ok) break;
  }
  long const during = allocations.load() - before;
  INFO(error.ToString());
  REQUIRE_FALSE(error);
  REQUIRE(newtonIterations >= 20);
  REQUIRE(during == 0);
}

TEST_CASE("deformable steps after the first allocate nothing", "[scene][allocation]") {
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  auto scene = MakeScene(params);
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(Real3::Zero(), Real3(0.3, 0.1, 0.1), {6, 2, 2}, mesh, error));
  DeformableActorParams p;
  p.nodes = mesh.nodes;
  p.tetrahedra = mesh.tetrahedra;
  p.triangles = {{0, 1, 7}, {1, 8, 7}, {1, 2, 8}};  // a shell patch on the bottom face, with hinges
  DeformableActor* block = scene->CreateDeformableActor(p, error);
  REQUIRE(block);
  REQUIRE(block->GetNumHinges() > 0);
  for (int i = 0; i < block->GetNumNodes(); ++i) {
    if (block->GetNodeReferencePosition(i).x() > 1e-9) continue;
    DeformableNodePositionConstraintParams pin;
    pin.actor = block->GetHandle();
    pin.nodeIndex = i;
    pin.position = block->GetNodePosition(i);
    pin.stiffness = 1e7;
    Constraint* c = scene->CreateDeformableNodePositionConstraint(pin, error);
    REQUIRE(c);
    REQUIRE(c->RegisterQuery(QueryType::ConstraintForce, error));
  }
  StepOk(*scene, 1e-2, 2);
  REQUIRE(scene->GetStats().linearSolver.find("CHOLMOD") != std::string::npos);
  long const before = allocations.load();
  int newtonIterations = 0;
  for (int i = 0; i < 10; ++i) {
    if (!scene->Step(1e-2, error)) break;
    newtonIterations += scene->GetStats().newtonIterations;
  }
  long const during = allocations.load() - before;
  INFO(error.ToString());
  REQUIRE_FALSE(error);
  REQUIRE(newtonIterations >= 10);
  REQUIRE(during == 0);
}
