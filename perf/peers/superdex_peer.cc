// SuperDex in perf/peers: the scenes built by the project's own builders
// (scenes/contact_scenes.h: InclineScene, BoxStackScene, FastBoxScene) with
// the default SceneParams (backward Euler, ContactParams' d̂ = 1 mm, κ = 1e4
// Pa, ḡ = 1e-4 m), stepped by Scene::Step and measured by the shared driver
// from RigidActor::GetPosition / GetRotation.
#include <cstdio>

#include "peer_scenes.h"
#include "scenes/contact_scenes.h"

namespace {

using superdex::Error;
using superdex::RigidActor;
using superdex::SceneParams;

class SuperDexWorld final : public peers::World {
 public:
  SuperDexWorld(superdex::scenes::ContactScene scene, double dt)
      : scene_(std::move(scene)), dt_(dt) {
    // creation order: the stack's boxes from the bottom (AddBoxStack)
    scene_.scene->ForEachActor([this](superdex::Actor& actor) {
      if (auto* rigid = dynamic_cast<RigidActor*>(&actor)) boxes_.push_back(rigid);
    });
  }

  bool Step(std::string& why) override {
    Error error;
    if (scene_.scene->Step(dt_, error)) return true;
    why = error.ToString();
    return false;
  }

  double LastIterations() const override { return scene_.scene->GetStats().newtonIterations; }

  peers::Pose BoxPose(int i) const override {
    RigidActor const& box = *boxes_.at(i);
    peers::Pose pose;
    for (int k = 0; k < 3; ++k) pose.position[k] = box.GetPosition()[k];
    auto const r = box.GetRotation().toRotationMatrix();
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) pose.rotation[a][b] = r(a, b);
    return pose;
  }

 private:
  superdex::scenes::ContactScene scene_;
  double dt_;
  std::vector<RigidActor*> boxes_;
};

/// The scene as a World, or null and `why`.
std::unique_ptr<peers::World> Wrap(superdex::scenes::ContactScene scene, Error const& error,
                                   double dt, std::string& why) {
  if (!scene.scene) {
    why = error.ToString();
    return nullptr;
  }
  return std::make_unique<SuperDexWorld>(std::move(scene), dt);
}

}  // namespace

int main(int argc, char** argv) {
  // The driver's starting gaps are fractions of the default d̂; a change of
  // the default would start the peers from other positions than SuperDex.
  if (SceneParams().contact.activationDistance != peers::kActivation) {
    std::fprintf(stderr, "superdex_peer: the default activation distance is no longer %g m\n",
                 peers::kActivation);
    return 1;
  }
  peers::PeerEngine engine;
  engine.name = "superdex";
  engine.note =
      "backward Euler; default SceneParams (d-hat 1 mm; kappa 1e4 Pa; ramp 1e-4 m); all CPUs";
  engine.incline = [](double tanTheta, double dt, std::string& why) {
    Error error;
    return Wrap(superdex::scenes::InclineScene(SceneParams(), tanTheta, error), error, dt, why);
  };
  engine.stack = [](double dt, std::string& why) {
    Error error;
    return Wrap(superdex::scenes::BoxStackScene(SceneParams(), peers::kStackCount, error), error,
                dt, why);
  };
  engine.fastBox = [](double dt, std::string& why) {
    Error error;
    return Wrap(superdex::scenes::FastBoxScene(SceneParams(), error), error, dt, why);
  };
  return peers::RunPeers({engine}, argc, argv);
}
