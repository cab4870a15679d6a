// Colliders and contact scenes driven by arbitrary bytes: up to 24 calls on
// one scene — rigid bodies with every shape, small tet solids and rods with
// their Surface, static obstacles (planes, spheres, boxes, capsules, triangle
// meshes) with hostile sizes, poses, thicknesses, frictions and filters;
// obstacles teleported (SetTransform) and moved kinematically
// (SetTargetTransform); bodies given hostile velocities; Step with hostile
// dt; ContactParams hostile at creation. Checked after every call: nothing
// crashes or throws; a call that fails sets an Error and leaves the scene
// bit-identical (bodies, obstacle poses, time, counts); and after every
// successful step no two colliders interpenetrate (the exact test of
// tests/contact/intersection.h).
#include <cmath>
#include <vector>

#include "contact/intersection.h"
#include "fuzz_support.h"

using namespace superdex;
using namespace superdex::fuzz;

namespace {

/// The scene's observable state, bit for bit.
std::vector<std::uint8_t> Digest(Scene const& scene) {
  std::vector<std::uint8_t> out;
  auto put = [&](auto const& value) {
    auto const* bytes = reinterpret_cast<std::uint8_t const*>(&value);
    out.insert(out.end(), bytes, bytes + sizeof value);
  };
  put(scene.GetTime());
  put(scene.GetNumColliders());
  scene.ForEachActor([&](Actor const& actor) {
    if (auto const* rigid = dynamic_cast<RigidActor const*>(&actor)) {
      put(rigid->GetPosition());
      put(rigid->GetRotation().coeffs().eval());
      put(rigid->GetLinearVelocity());
    } else if (auto const* nodal = dynamic_cast<NodalActor const*>(&actor)) {
      for (int i = 0; i < nodal->GetNumNodes(); ++i) put(nodal->GetNodePosition(i));
    }
  });
  for (int id = 0, seen = 0; seen < scene.GetNumColliders() && id < 4096; ++id)
    if (Collider const* c = scene.GetCollider(id)) {
      ++seen;
      put(c->GetPosition());
      put(c->GetRotation().coeffs().eval());
    }
  return out;
}

class Driver {
 public:
  explicit Driver(Input& in) : in_(in) {}

  void Run() {
    SceneParams params;
    if (in_.Int(4) == 0) {
      params.contact.activationDistance = in_.Int(2) ? in_.Real() : 1e-3;
      params.contact.stiffness = in_.Int(2) ? in_.Real() : 1e6;
      params.contact.frictionRampWidth = in_.Int(2) ? in_.Real() : 1e-4;
    }
    params.newton.maxIterations = 20;  // a hostile scene fails fast
    Error error;
    scene_ = Scene::Create(params, error);
    if (!scene_) {
      Expect(static_cast<bool>(error), "Scene::Create failed without an Error");
      return;
    }
    for (int call = 0; call < 24 && !in_.Done(); ++call) {
      before_ = Digest(*scene_);
      Error callError;
      bool const ok = Call(callError);
      if (!ok) {
        Expect(static_cast<bool>(callError), "a call failed without an Error");
        Expect(Digest(*scene_) == before_, "a failed call changed the scene", callError.ToString());
      }
    }
  }

 private:
  bool Call(Error& error) {
    switch (in_.Int(8)) {
      case 0: return CreateRigid(error);
      case 1:
      case 2: return CreateObstacle(error);
      case 3: return CreateNodal(error);
      case 4:
      case 5: return MoveObstacle(error);
      case 6: return Kick(error);
      default: return Step(error);
    }
  }

  real Size() { return in_.Int(4) ? 0.02 * (1 + in_.Int(10)) : in_.Real(); }
  Real3 Place() { return in_.Int(4) ? Real3(0.1 * (in_.Int(11) - 5), 0.1 * in_.Int(10), 0.1 * (in_.Int(11) - 5)) : in_.Vector(); }

  ColliderParams Shape(bool obstacle) {
    ColliderParams p;
    p.shape = static_cast<ShapeType>(in_.Int(obstacle ? 5 : 4) + (obstacle ? 0 : 1));  // a body has no Plane
    p.radius = Size();
    p.halfLength = Size();
    p.halfExtents = Real3(Size(), Size(), Size());
    p.rotation = in_.Rotation();
    if (in_.Int(4) == 0) p.thickness = in_.Real();
    if (in_.Int(4) == 0) p.friction = in_.Real();
    if (in_.Int(4) == 0) p.group = in_.Byte();
    if (in_.Int(4) == 0) p.mask = in_.Byte();
    if (in_.Int(4) == 0) p.normal = in_.Vector();
    if (p.shape == ShapeType::TriangleMesh) {
      int const n = 3 + in_.Int(4);
      for (int i = 0; i < n; ++i) p.vertices.push_back(in_.Int(3) ? Real3(Size(), Size(), Size()) : in_.Vector());
      int const m = 1 + in_.Int(3);
      for (int t = 0; t < m; ++t) p.triangles.push_back({in_.Int(n + 1), in_.Int(n + 1), in_.Int(n + 1)});
    }
    return p;
  }

  bool CreateRigid(Error& error) {
    RigidActorParams body;
    body.position = Place();
    if (in_.Int(4) == 0) body.linearVelocity = in_.Vector();
    RigidActor* rigid = scene_->CreateRigidActor(body, error);
    if (!rigid) return false;
    before_ = Digest(*scene_);  // the collider is the next call
    ColliderParams shape = Shape(false);
    shape.actor = rigid->GetHandle();
    shape.position = in_.Int(4) ? Real3::Zero() : in_.Vector();
    return scene_->CreateCollider(shape, error) != nullptr;
  }

  bool CreateObstacle(Error& error) {
    ColliderParams shape = Shape(true);
    shape.position = Place() - Real3(0, 0.5, 0);
    return scene_->CreateCollider(shape, error) != nullptr;
  }

  bool CreateNodal(Error& error) {
    Real3 const at = Place();
    real const size = Size();
    Actor* actor = nullptr;
    if (in_.Int(2)) {
      DeformableActorParams cube;
      TetMesh mesh;
      if (!MakeTetBox(at, Real3::Constant(size), {1, 1, 1}, mesh, error)) return false;
      cube.nodes = mesh.nodes;
      cube.tetrahedra = mesh.tetrahedra;
      if (in_.Int(4) == 0) cube.youngModulus = in_.Real();
      actor = scene_->CreateDeformableActor(cube, error);
    } else {
      RodActorParams rod;
      int const n = 2 + in_.Int(6);
      for (int i = 0; i < n; ++i) rod.nodes.push_back(at + Real3(size * i, 0.01 * in_.Int(3), 0));
      rod.radius = in_.Int(4) ? 0.005 : in_.Real();
      actor = scene_->CreateRodActor(rod, error);
    }
    if (!actor) return false;
    before_ = Digest(*scene_);
    ColliderParams surface;
    surface.actor = actor->GetHandle();
    if (in_.Int(4) == 0) surface.thickness = in_.Real();
    if (in_.Int(2)) {
      surface.group = 2;
      surface.mask = ~2u;
    }
    return scene_->CreateCollider(surface, error) != nullptr;
  }

  Collider* PickCollider() {
    int const count = scene_->GetNumColliders();
    if (count == 0) return nullptr;
    int pick = in_.Int(count);
    for (int id = 0; id < 4096; ++id)
      if (Collider* c = scene_->GetCollider(id); c && pick-- == 0) return c;
    return nullptr;
  }

  bool MoveObstacle(Error& error) {
    Collider* c = PickCollider();
    if (!c) return true;
    Real3 const position = in_.Int(3) ? Real3(c->GetPosition() + 0.05 * Real3(in_.Int(5) - 2, in_.Int(5) - 2, 0))
                                      : in_.Vector();
    Quat const rotation = in_.Int(3) ? c->GetRotation() : in_.Rotation();
    return in_.Int(2) ? c->SetTargetTransform(position, rotation, error) : c->SetTransform(position, rotation, error);
  }

  bool Kick(Error& error) {
    RigidActor* target = nullptr;
    int pick = in_.Int(8);
    scene_->ForEachActor([&](Actor& actor) {
      if (auto* rigid = dynamic_cast<RigidActor*>(&actor); rigid && pick-- >= 0) target = rigid;
    });
    if (!target) return true;
    return target->SetVelocity(in_.Int(3) ? Real3(0, -5.0 * in_.Int(5), 0) : in_.Vector(), in_.Vector(), error);
  }

  bool Step(Error& error) {
    static constexpr real kRates[] = {30, 60, 120, 240};
    real const dt = in_.Int(8) ? 1 / kRates[in_.Int(4)] : in_.Real();
    if (!scene_->Step(dt, error)) return false;
    // never through each other
    test::InterpenetrationCheck check(scene_->GetParams().contact.activationDistance);
    std::string const found = check.Find(*scene_);
    Expect(found.empty(), "a step left colliders interpenetrating:", found);
    return true;
  }

  Input& in_;
  std::unique_ptr<Scene> scene_;
  std::vector<std::uint8_t> before_;  ///< the state a failing call must leave
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  Driver driver(in);
  driver.Run();
  return 0;
}
