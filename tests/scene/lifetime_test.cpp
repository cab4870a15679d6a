// Lifetime rules (docs/lifetime.md): a handle names its scene, so another
// scene refuses it; ForEachActor / ForEachConstraint iterate over a snapshot,
// so a callback may destroy, create or step; a pointer to a recently
// destroyed constraint is recognised, never dereferenced.
#include "test_scenes.h"

#include <set>

using namespace superdex;
using namespace superdex::test;

namespace {

/// Positions of every rigid actor, in creation order.
DynamicArray<Real3> Positions(Scene const& scene) {
  DynamicArray<Real3> out;
  scene.ForEachActor([&](Actor& a) {
    if (a.GetType() == ActorType::Rigid) out.push_back(static_cast<RigidActor&>(a).GetPosition());
  });
  return out;
}

}  // namespace

TEST_CASE("a handle of one scene is refused by another, naming the scene", "[scene][lifetime]") {
  Chain one = MakeChain(3), two = MakeChain(3);
  Scene &s1 = *one.scene, &s2 = *two.scene;
  REQUIRE(s1.GetId() != s2.GetId());
  ActorHandle const foreignActor = two.bodies[0]->GetHandle();
  ConstraintHandle const foreignConstraint = two.constraints[1]->GetHandle();
  // same slots in both scenes: before, s1 resolved these to its own objects
  REQUIRE(foreignActor.index == one.bodies[0]->GetHandle().index);
  REQUIRE(foreignActor.generation == one.bodies[0]->GetHandle().generation);
  REQUIRE(foreignActor.scene == s2.GetId());

  REQUIRE(s1.GetActor(foreignActor) == nullptr);
  REQUIRE(s1.GetConstraint(foreignConstraint) == nullptr);
  Error error;
  REQUIRE_FALSE(s1.DestroyActor(foreignActor, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidHandle);
  REQUIRE(Mentions(error, "belongs to another scene"));
  REQUIRE(Mentions(error, "scene " + std::to_string(s2.GetId())));
  error.Clear();
  REQUIRE_FALSE(s1.DestroyConstraint(foreignConstraint, error));
  REQUIRE(Mentions(error, "belongs to another scene"));
  error.Clear();
  REQUIRE_FALSE(s1.DestroyConstraint(two.constraints[1], error));  // pointer of the other scene
  REQUIRE(error.GetCode() == ErrorCode::InvalidHandle);
  error.Clear();
  // every factory looks its actors up the same way
  RigidSphericalJointConstraintParams joint;
  joint.actorA = one.bodies[2]->GetHandle();
  joint.actorB = foreignActor;
  REQUIRE_FALSE(s1.CreateRigidSphericalJointConstraint(joint, error));
  REQUIRE(Mentions(error, "RigidSphericalJointConstraintParams.actorB"));
  REQUIRE(Mentions(error, "belongs to another scene"));

  // nothing changed in either scene, and both still step
  REQUIRE(s1.GetNumActors() == 3);
  REQUIRE(s1.GetNumConstraints() == 3);
  REQUIRE(s2.GetNumActors() == 3);
  REQUIRE(s2.GetNumConstraints() == 3);
  StepOk(s1, 1e-3);
  StepOk(s2, 1e-3);
  // a handle built from numbers (scene 0) names nothing
  REQUIRE(s1.GetActor(ActorHandle{foreignActor.index, foreignActor.generation}) == nullptr);
  REQUIRE(s1.GetActor(one.bodies[0]->GetHandle()) == one.bodies[0]);
}

TEST_CASE("ForEachConstraint: a callback that destroys the visited constraint visits every other",
          "[scene][lifetime]") {
  Chain chain = MakeChain(5);  // pin + 4 joints
  Scene& scene = *chain.scene;
  std::set<std::uint32_t> visited;
  Error error;
  // destroy every visited constraint: each of the 5 must still be visited once
  scene.ForEachConstraint([&](Constraint& c) {
    REQUIRE(visited.insert(c.GetHandle().index).second);
    REQUIRE(scene.DestroyConstraint(c.GetHandle(), error));
  });
  REQUIRE(visited.size() == 5);
  REQUIRE(scene.GetNumConstraints() == 0);
  StepOk(scene, 1e-3);
}

TEST_CASE("ForEachActor / ForEachConstraint: destroyed objects are skipped, created ones not visited",
          "[scene][lifetime]") {
  Chain chain = MakeChain(4);
  Scene& scene = *chain.scene;
  Error error;
  int actorVisits = 0;
  scene.ForEachActor([&](Actor& actor) {
    ++actorVisits;
    if (&actor == chain.bodies[0]) {
      // destroys a later actor (and its joints) and creates one
      REQUIRE(scene.DestroyActor(chain.bodies[2]->GetHandle(), error));
      REQUIRE(MakeRigid(scene, {}));
    }
    REQUIRE(&actor != chain.bodies[2]);
  });
  REQUIRE(actorVisits == 3);  // 0, 1, 3: not the destroyed 2, not the new one
  REQUIRE(scene.GetNumActors() == 4);

  // destroying an actor from inside ForEachConstraint takes its constraints
  // out of the rest of the iteration
  int constraintVisits = 0;
  scene.ForEachConstraint([&](Constraint* c) {  // the reference page's form
    ++constraintVisits;
    if (c == chain.constraints[0]) REQUIRE(scene.DestroyActor(chain.bodies[1]->GetHandle(), error));
  });
  // left before: the pin and joint 0-1 (joints 1-2 and 2-3 went with body 2);
  // the pin's visit destroyed body 1 and with it joint 0-1
  REQUIRE(constraintVisits == 1);
  REQUIRE(scene.GetNumConstraints() == 1);
  StepOk(scene, 1e-3);
}

TEST_CASE("Step inside a ForEach callback steps the scene as outside one", "[scene][lifetime]") {
  Chain inside = MakeChain(3), outside = MakeChain(3);
  int visits = 0;
  Error error;
  inside.scene->ForEachConstraint([&](Constraint&) {
    ++visits;
    REQUIRE(inside.scene->Step(1e-3, error));
  });
  REQUIRE(visits == 3);
  StepOk(*outside.scene, 1e-3, 3);
  REQUIRE(Positions(*inside.scene) == Positions(*outside.scene));
  REQUIRE(inside.scene->GetTime() == outside.scene->GetTime());
}

TEST_CASE("DestroyConstraint(pointer) refuses a pointer to a destroyed constraint", "[scene][lifetime]") {
  Chain chain = MakeChain(3);
  Scene& scene = *chain.scene;
  Error error;
  Constraint* stale = chain.constraints[1];
  REQUIRE(scene.DestroyConstraint(stale, error));
  // new constraints of the same type and size: before, one could take the
  // freed address, and the stale pointer then destroyed it
  DynamicArray<ConstraintHandle> fresh;
  for (int i = 0; i < Scene::kPointerQuarantine - 1; ++i) {
    RigidSphericalJointConstraintParams joint;
    joint.actorA = chain.bodies[0]->GetHandle();
    joint.actorB = chain.bodies[1]->GetHandle();
    joint.stiffness = 1e6;
    Constraint* c = scene.CreateRigidSphericalJointConstraint(joint, error);
    REQUIRE(c);
    REQUIRE(c != stale);
    fresh.push_back(c->GetHandle());
  }
  int const before = scene.GetNumConstraints();
  REQUIRE_FALSE(scene.DestroyConstraint(stale, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidHandle);
  REQUIRE(Mentions(error, "was destroyed"));
  REQUIRE(scene.GetNumConstraints() == before);
  for (ConstraintHandle h : fresh) REQUIRE(scene.GetConstraint(h) != nullptr);
  // constraints destroyed with their actor are recognised too
  Constraint* withActor = chain.constraints[2];  // joint 1-2
  REQUIRE(scene.DestroyActor(chain.bodies[2]->GetHandle(), error));
  error.Clear();
  REQUIRE_FALSE(scene.DestroyConstraint(withActor, error));
  REQUIRE(Mentions(error, "was destroyed"));
  error.Clear();
  REQUIRE_FALSE(scene.DestroyConstraint(static_cast<Constraint*>(nullptr), error));
  REQUIRE(Mentions(error, "null"));
}

TEST_CASE("the reference page's DestroyConstraint forms without an Error", "[scene][lifetime]") {
  Chain chain = MakeChain(3);
  Scene& scene = *chain.scene;
  ConstraintHandle handle = chain.constraints[1]->GetHandle();
  REQUIRE(scene.DestroyConstraint(handle));
  REQUIRE_FALSE(scene.DestroyConstraint(handle));  // stale: false, nothing changes
  REQUIRE(scene.DestroyConstraint(chain.constraints[2]));
  REQUIRE(scene.GetNumConstraints() == 1);
}

TEST_CASE("a scene without actors steps: time advances (found by fuzz_scene_api)", "[scene][lifetime]") {
  // before: Newton's step norm took the largest entry of an empty vector
  // (a segmentation fault in a Release build)
  std::unique_ptr<Scene> scene = MakeScene();
  StepOk(*scene, 0.25);
  REQUIRE(scene->GetTime() == 0.25);
  Chain chain = MakeChain(2);
  Error error;
  for (RigidActor* body : chain.bodies) REQUIRE(chain.scene->DestroyActor(body->GetHandle(), error));
  StepOk(*chain.scene, 1e-3, 2);
  REQUIRE(chain.scene->GetNumConstraints() == 0);
  // and actors added afterwards step as in a new scene
  RigidActorParams body;
  body.linearVelocity = Real3(1, 0, 0);
  RigidActor* moving = MakeRigid(*chain.scene, body);
  StepOk(*chain.scene, 1e-3);
  std::unique_ptr<Scene> fresh = MakeScene();
  RigidActor* reference = MakeRigid(*fresh, body);
  StepOk(*fresh, 1e-3);
  REQUIRE(moving->GetPosition().x() > 0);
  REQUIRE(moving->GetPosition() == reference->GetPosition());
  REQUIRE(moving->GetLinearVelocity() == reference->GetLinearVelocity());
}
