// Every contact scene of docs/contact.md at dt = 1/30, 1/60 and 1/120 with
// the default ContactParams: each step succeeds, Newton takes at most 8
// iterations per step on average, and no two colliders interpenetrate at any
// step end — checked by scenes/interpenetration.h's exact test on the
// colliders' geometry, not by the barrier's distance. Prints a row per scene
// and dt (steps, Newton iterations per step, smallest gap, seconds) for the
// table of docs/contact.md.
#include "contact/contact_scenes.h"
#include "scenes/interpenetration.h"

#include <chrono>
#include <cstdio>

using namespace superdex;
using namespace superdex::test;

namespace {

void Sweep(std::string const& name, std::function<ContactScene(SceneParams)> const& build,
           IntegratorType integrator = IntegratorType::BackwardEuler) {
  for (int rate : {30, 60, 120}) {
    SceneParams params;
    params.integrator = integrator;
    ContactScene scene = build(params);
    InterpenetrationCheck check(params.contact.activationDistance);
    REQUIRE(check.Find(*scene.scene).empty());
    int const steps = static_cast<int>(std::lround(scene.seconds * rate));
    long newton = 0;
    int touching = 0;
    real minGap = std::numeric_limits<real>::infinity();
    auto const start = std::chrono::steady_clock::now();
    for (int s = 0; s < steps; ++s) {
      Drive(scene, static_cast<real>(s) / rate, static_cast<real>(s + 1) / rate);
      Error error;
      bool const stepped = scene.scene->Step(1.0 / rate, error);
      INFO(name << " at dt = 1/" << rate << ", step " << s << ": " << error.ToString());
      REQUIRE(stepped);
      newton += scene.scene->GetStats().newtonIterations;
      std::string const found = check.Find(*scene.scene);
      INFO(found);
      REQUIRE(found.empty());
      minGap = std::min(minGap, check.GetMinGap());
      touching += scene.scene->GetStats().activeContacts > 0;
    }
    real const seconds = std::chrono::duration<real>(std::chrono::steady_clock::now() - start).count();
    real const perStep = static_cast<real>(newton) / steps;
    std::printf("sweep %-16s dt 1/%-3d %4d steps  %5.2f Newton/step  min gap %9.3g m  %7.2f s\n", name.c_str(), rate,
                steps, perStep, minGap, seconds);
    INFO(name << " at dt = 1/" << rate << ": " << perStep << " Newton iterations per step");
    CHECK(perStep <= 8);
    CHECK(touching > 0);  // the bodies did touch
  }
}

}  // namespace

TEST_CASE("contact sweep: a box resting on an incline", "[contact][sweep]") {
  Sweep("incline", [](SceneParams p) { return InclineScene(p); });
}

TEST_CASE("contact sweep: a sphere rolling down an incline", "[contact][sweep]") {
  Sweep("rolling", RollingScene, IntegratorType::Bdf2);
}

TEST_CASE("contact sweep: a soft ball dropped from 1 m", "[contact][sweep][long]") {
  Sweep("ball drop", [](SceneParams p) { return BallDropScene(p); }, IntegratorType::Bdf2);
}

TEST_CASE("contact sweep: a stack of 5 rigid boxes", "[contact][sweep][long]") {
  Sweep("box stack", [](SceneParams p) { return BoxStackScene(p); });
}

TEST_CASE("contact sweep: a 5-link arm pushes a box across the ground", "[contact][sweep][articulated]") {
  Sweep("arm push", ArmPushScene);
}

TEST_CASE("contact sweep: a 3-link arm folding onto itself", "[contact][sweep][articulated]") {
  Sweep("arm fold", FoldingArmScene);
}

TEST_CASE("contact sweep: a stack of 5 tet cubes", "[contact][sweep][long]") {
  Sweep("cube stack", [](SceneParams p) { return CubeStackScene(p); });
}

TEST_CASE("contact sweep: a 100-node rod coiling onto the ground", "[contact][sweep][long]") {
  Sweep("rod coil", [](SceneParams p) { return RodCoilScene(p); }, IntegratorType::Bdf2);
}

// Open (hidden, [.open]; run with `contact_sweep_test "[open]"`): the 32 × 32
// cloth on a sphere needs more than Newton's 50 iterations in some steps at
// dt = 1/30, and more than 8 per step on average at 1/30 and 1/60
// (docs/contact.md, "Not met yet": contacts forming against a barrier far
// stiffer than a light body's inertia). Full size (hidden, [.full]; run
// with `contact_sweep_test "[full]"`): the 24 × 24 fold passes (6.69, 4.96,
// 3.62 Newton iterations per step at 1/30, 1/60, 1/120 with each vertex's
// own self bound, 2026-12-04; 6.78, 5.16, 3.65 before) but takes 260 s; the
// 12 × 12 one below is its case in the suite.
// Also
// [long]: the sanitizer build's test spec ~[long] would otherwise match
// these hidden cases.
TEST_CASE("contact sweep: a 32 x 32 cloth dropped on a sphere", "[contact][sweep][long][.open]") {
  Sweep("cloth on sphere", [](SceneParams p) { return ClothOnSphereScene(p); });
}

TEST_CASE("contact sweep: a cloth folding onto itself", "[contact][sweep][long][.full]") {
  Sweep("cloth fold", [](SceneParams p) { return ClothFoldScene(p); });
}

// Measured: 5.69, 3.76, 2.69 Newton iterations per step at dt = 1/30, 1/60,
// 1/120 (6.09, 3.82, 2.80 with one self bound per body; before the line
// search's per-DoF limited step 8.87 at 1/30: this fails).
TEST_CASE("contact sweep: a 12 x 12 cloth folding onto itself", "[contact][sweep][long]") {
  Sweep("cloth fold 12", [](SceneParams p) { return ClothFoldScene(p, 12); });
}

TEST_CASE("contact sweep: a fast box onto a thin plate", "[contact][sweep]") {
  Sweep("fast box", FastBoxScene);
}
