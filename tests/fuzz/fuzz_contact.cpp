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
// scenes/interpenetration.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "scenes/interpenetration.h"
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
    } else if (auto const* arm = dynamic_cast<ArticulatedActor const*>(&actor)) {
      for (real q : arm->GetJointPositions()) put(q);
      for (real v : arm->GetJointVelocities()) put(v);
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
    // a hostile velocity (a box spun hard: a Newton step of norm 1.2e9)
    // spends few CCD evaluations per pair: the safe step is safe at any
    // cap, and the sanitizers' instrumentation makes each one ~50 times
    // slower
    params.contact.ccdMaxIterations = 64;
    if (in_.Int(4) == 0) {
      // (at most 5 cm: a d̂ of 2 m made every pair of primitives of the
      // scene a candidate, 3,271 for three small cubes, 70 s for one step
      // under the sanitizers; NaN and negative values still reach Create)
      params.contact.activationDistance = in_.Int(2) ? std::min(in_.Real(), 0.05) : 1e-3;
      params.contact.stiffness = in_.Int(2) ? in_.Real() : 1e6;
      params.contact.frictionRampWidth = in_.Int(2) ? in_.Real() : 1e-4;
      if (in_.Int(2)) params.contact.ccdMaxIterations = in_.Int(300) - 10;
    }
    // a hostile scene fails fast: one step of two nodal actors with 1,032
    // active pairs failing Newton at 12 iterations took 22 s under the
    // sanitizers
    params.newton.maxIterations = 8;
    Error error;
    scene_ = Scene::Create(params, error);
    if (!scene_) {
      Expect(static_cast<bool>(error), "Scene::Create failed without an Error");
      return;
    }
    for (int call = 0; call < 24 && !in_.Done(); ++call) {
      before_ = Digest(*scene_);
      Error callError;
      auto const start = std::chrono::steady_clock::now();
      bool const ok = Call(callError);
      if (trace_)
        std::fprintf(stderr, "call %d %s (%.3f s): %s\n", call, kind_,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), ok ? "ok" : callError.ToString().c_str());
      if (!ok) {
        Expect(static_cast<bool>(callError), "a call failed without an Error");
        Expect(Digest(*scene_) == before_, "a failed call changed the scene", callError.ToString());
      }
    }
  }

 private:
  bool Call(Error& error) {
    // (Int(9): the named seeds' calls, bytes 0..7, kept their meaning when
    // CreateArm came)
    switch (in_.Int(9)) {
      case 0: return kind_ = "CreateRigid", CreateRigid(error);
      case 1:
      case 2: return kind_ = "CreateObstacle", CreateObstacle(error);
      case 3: return kind_ = "CreateNodal", CreateNodal(error);
      case 4:
      case 5: return kind_ = "MoveObstacle", MoveObstacle(error);
      case 6: return kind_ = "Kick", Kick(error);
      case 8: return kind_ = "CreateArm", CreateArm(error);
      default: return kind_ = "Step", Step(error);
    }
  }

  real Size() { return in_.Int(4) ? 0.02 * (1 + in_.Int(10)) : in_.Real(); }
  Real3 Place() {
    if (!in_.Int(4)) return in_.Vector();
    real const x = 0.1 * (in_.Int(11) - 5);
    real const y = 0.1 * in_.Int(10);
    return Real3(x, y, 0.1 * (in_.Int(11) - 5));
  }
  Real3 Sizes() { return Input::Triple([&] { return Size(); }); }

  ColliderParams Shape(bool obstacle) {
    ColliderParams p;
    p.shape = static_cast<ShapeType>(in_.Int(obstacle ? 5 : 4) + (obstacle ? 0 : 1));  // a body has no Plane
    p.radius = Size();
    p.halfLength = Size();
    p.halfExtents = Sizes();
    p.rotation = in_.Rotation();
    if (in_.Int(4) == 0) p.thickness = in_.Real();
    if (in_.Int(4) == 0) p.friction = in_.Real();
    if (in_.Int(4) == 0) p.group = in_.Byte();
    if (in_.Int(4) == 0) p.mask = in_.Byte();
    if (in_.Int(4) == 0) p.normal = in_.Vector();
    if (p.shape == ShapeType::TriangleMesh) {
      int const n = 3 + in_.Int(4);
      for (int i = 0; i < n; ++i) p.vertices.push_back(in_.Int(3) ? Sizes() : in_.Vector());
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
    if (trace_)
      std::fprintf(stderr, "  body %d at (%g, %g, %g) + (%g, %g, %g), radius %g, half length %g, thickness %g\n",
                   static_cast<int>(shape.shape), body.position.x(), body.position.y(), body.position.z(),
                   shape.position.x(), shape.position.y(), shape.position.z(), shape.radius, shape.halfLength,
                   shape.thickness);
    return scene_->CreateCollider(shape, error) != nullptr;
  }

  bool CreateObstacle(Error& error) {
    ColliderParams shape = Shape(true);
    shape.position = Place() - Real3(0, 0.5, 0);
    if (trace_)
      std::fprintf(stderr, "  obstacle %d at (%g, %g, %g), radius %g, half length %g, thickness %g\n",
                   static_cast<int>(shape.shape), shape.position.x(), shape.position.y(), shape.position.z(),
                   shape.radius, shape.halfLength, shape.thickness);
    return scene_->CreateCollider(shape, error) != nullptr;
  }

  bool CreateNodal(Error& error) {
    if (nodalActors_ == kMaxNodalActors) return true;
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
    ++nodalActors_;
    if (trace_)
      std::fprintf(stderr, "  %s at (%g, %g, %g), size %g, %d nodes\n", ToString(actor->GetType()).data(), at.x(), at.y(),
                   at.z(), size, static_cast<NodalActor*>(actor)->GetNumNodes());
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

  /// An articulated actor of 1–3 links (any joint types, hostile axes and
  /// masses now and then) and a body shape on one of its links (the link
  /// index out of range now and then).
  bool CreateArm(Error& error) {
    if (arms_ == kMaxArms) return true;
    static constexpr JointType kJoints[] = {JointType::Revolute, JointType::Prismatic, JointType::Spherical,
                                            JointType::Free, JointType::Fixed};
    ArticulatedActorParams arm;
    int const links = 1 + in_.Int(3);
    for (int i = 0; i < links; ++i) {
      ArticulatedLinkParams link;
      link.parent = i - 1;
      link.joint = kJoints[in_.Int(5)];
      link.axis = in_.Int(4) ? Real3::UnitZ() : in_.Vector();
      link.parentToJointPosition = i == 0 ? Place() : Real3(0, -Size(), 0);
      link.centerOfMass = Real3(0, -0.05, 0);
      link.inertia = Real3::Constant(1e-3);
      if (in_.Int(4) == 0) link.mass = in_.Real();
      arm.links.push_back(link);
    }
    ArticulatedActor* actor = scene_->CreateArticulatedActor(arm, error);
    if (!actor) return false;
    ++arms_;
    before_ = Digest(*scene_);  // the collider is the next call
    ColliderParams shape = Shape(false);
    shape.actor = actor->GetHandle();
    shape.link = in_.Int(4) ? in_.Int(links) : in_.Int(256) - 128;
    shape.position = Real3(0, -0.05, 0);
    if (trace_)
      std::fprintf(stderr, "  arm of %d links, shape %d on link %d\n", links, static_cast<int>(shape.shape), shape.link);
    if (!scene_->CreateCollider(shape, error)) return false;
    // now and then a second shape two links away: the mechanism's links
    // touch each other (not a parent and its child)
    if (links < 3 || in_.Int(2)) return true;
    before_ = Digest(*scene_);  // the second collider is the next call
    ColliderParams other = Shape(false);
    other.actor = actor->GetHandle();
    other.link = (shape.link + 2) % links;
    other.position = Real3(0, -0.05, 0);
    if (trace_) std::fprintf(stderr, "  and shape %d on link %d\n", static_cast<int>(other.shape), other.link);
    return scene_->CreateCollider(other, error) != nullptr;
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
    Real3 position = c->GetPosition();
    if (in_.Int(3)) {
      real const dx = 0.05 * (in_.Int(5) - 2);
      position += Real3(dx, 0.05 * (in_.Int(5) - 2), 0);
    } else {
      position = in_.Vector();
    }
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
    Real3 const linear = in_.Int(3) ? Real3(0, -5.0 * in_.Int(5), 0) : in_.Vector();
    return target->SetVelocity(linear, in_.Vector(), error);
  }

  bool Step(Error& error) {
    static constexpr real kRates[] = {30, 60, 120, 240};
    real const dt = in_.Int(8) ? 1 / kRates[in_.Int(4)] : in_.Real();
    // an input's work is bounded, so that no input outlasts libFuzzer's
    // timeout under the sanitizers (~1 ms per contact pair and Newton
    // iteration there): Newton iterations weighted by the last stage's
    // pairs, over all steps (tiny cubes failing Newton at every step took
    // 20 s for 24 calls)
    if (work_ >= kWorkBudget) return true;
    bool const stepped = scene_->Step(dt, error);
    work_ += scene_->GetStats().newtonIterations * (1 + scene_->GetStats().stageContributors / 100.0);
    if (trace_)
      std::fprintf(stderr, "  %d Newton iterations, %d contact pairs in the last stage\n",
                   scene_->GetStats().newtonIterations, scene_->GetStats().stageContributors);
    if (!stepped) return false;
    if (trace_)
      scene_->ForEachActor([&](Actor const& actor) {
        if (auto const* rigid = dynamic_cast<RigidActor const*>(&actor))
          std::fprintf(stderr, "  rigid at (%g, %g, %g)\n", rigid->GetPosition().x(), rigid->GetPosition().y(),
                       rigid->GetPosition().z());
      });
    // never through each other
    scenes::InterpenetrationCheck check(scene_->GetParams().contact.activationDistance);
    std::string const found = check.Find(*scene_);
    Expect(found.empty(), "a step left colliders interpenetrating:", found);
    return true;
  }

  static constexpr double kWorkBudget = 120;  ///< weighted Newton iterations per input
  static constexpr int kMaxNodalActors = 2;   ///< at most ~800 contact pairs
  static constexpr int kMaxArms = 1;
  double work_ = 0;
  int nodalActors_ = 0;
  int arms_ = 0;
  Input& in_;
  bool const trace_ = std::getenv("SUPERDEX_FUZZ_TRACE") != nullptr;  ///< each call's outcome on stderr
  char const* kind_ = "";  ///< the current call's name, for the trace
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
