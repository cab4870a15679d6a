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
