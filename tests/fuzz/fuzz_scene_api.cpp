// The Scene API driven by arbitrary bytes: a sequence of create / set / step
// / destroy calls on two scenes, with handles and pointers drawn from every
// object either scene ever issued (live, destroyed, or of the other scene),
// values drawn from a table of hostile numbers (NaN, ±inf, 5e-324, 1e300, …),
// destruction and stepping inside ForEach callbacks. Checked after every
// call: nothing crashes or throws, and a call that fails leaves both scenes
// bit-identical (docs/lifetime.md).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string_view>
#include <variant>
#include <vector>

#include "fuzz_support.h"

using namespace superdex;
using namespace superdex::fuzz;

namespace {

#define SUPERDEX_FUZZ_COUNT(Name, Class, file) +1
constexpr int kNumConstraintTypes = 0 SUPERDEX_CONSTRAINT_TYPES(SUPERDEX_FUZZ_COUNT);
#undef SUPERDEX_FUZZ_COUNT

bool Trace() {
  static bool const trace = std::getenv("FUZZ_TRACE") != nullptr;
  return trace;
}

/// Everything a scene issued, live or not.
struct Issued {
  std::vector<ActorHandle> actors;
  std::vector<ConstraintHandle> constraints;
  std::vector<Constraint*> pointers;  ///< passed only to DestroyConstraint(Constraint*)
};

/// The scenes' observable state, bit for bit.
std::vector<std::uint8_t> Digest(Scene const& scene) {
  std::vector<std::uint8_t> out;
  auto put = [&](auto const& value) {
    std::size_t const at = out.size();
    out.resize(at + sizeof value);
    std::memcpy(out.data() + at, &value, sizeof value);
  };
  auto putVector = [&](Real3 const& v) {
    for (int k = 0; k < 3; ++k) put(v[k]);
  };
  put(scene.GetNumActors());
  put(scene.GetNumConstraints());
  put(scene.GetNumDofs());
  put(scene.GetTime());
  put(static_cast<int>(scene.GetParams().linearSolver));
  scene.ForEachActor([&](Actor& actor) {
    put(actor.GetHandle());
    put(static_cast<int>(actor.GetType()));
    switch (actor.GetType()) {
      case ActorType::Rigid: {
        auto const& r = static_cast<RigidActor&>(actor);
        putVector(r.GetPosition());
        put(r.GetRotation().coeffs()[0]);
        put(r.GetRotation().coeffs()[1]);
        put(r.GetRotation().coeffs()[2]);
        put(r.GetRotation().coeffs()[3]);
        putVector(r.GetLinearVelocity());
        putVector(r.GetAngularVelocity());
        break;
      }
      case ActorType::Deformable:
      case ActorType::Rod: {
        auto const& n = static_cast<NodalActor&>(actor);
        for (int i = 0; i < n.GetNumNodes(); ++i) {
          putVector(n.GetNodePosition(i));
          putVector(n.GetNodeVelocity(i));
        }
        break;
      }
      case ActorType::Articulated: {
        auto const& a = static_cast<ArticulatedActor&>(actor);
        for (real q : a.GetJointPositions()) put(q);
        for (real v : a.GetJointVelocities()) put(v);
        break;
      }
    }
  });
  scene.ForEachConstraint([&](Constraint& c) {
    put(c.GetHandle());
    put(c.GetStiffness());
    put(c.GetDamping());
    put(c.GetSaturation());
    for (real g : c.GetDeviation()) put(g);
  });
  return out;
}

class Driver {
 public:
  explicit Driver(Input& in) : in_(in) {
    for (int s = 0; s < 2; ++s) {
      SceneParams params;
      params.newton.maxIterations = 25;  // keeps hostile steps short
      Error error;
      scenes_[s] = Scene::Create(params, error);
      Expect(scenes_[s] != nullptr, "Scene::Create failed", error.ToString());
    }
  }

  void Run() {
    for (int call = 0; call < 48 && !in_.Done(); ++call) {
      int const s = in_.Int(2);
      Scene& scene = *scenes_[s];
      std::vector<std::uint8_t> const before[2] = {Digest(*scenes_[0]), Digest(*scenes_[1])};
      bool const ok = Call(s, scene);
      // FUZZ_TRACE=1 replays an input call by call (to read a finding)
      if (Trace()) std::fprintf(stderr, "scene %d: %s -> %s (%d DoFs)\n", s, lastCall_.c_str(),
                                ok ? "ok" : "failed", scene.GetNumDofs());
      if (!ok) {
        Expect(Digest(*scenes_[0]) == before[0] && Digest(*scenes_[1]) == before[1],
               "a failed call changed a scene", lastCall_);
      }
    }
  }

 private:
  /// One call on scene s; returns false when it failed (an Error).
  bool Call(int s, Scene& scene) {
    Error error;
    bool ok = true;
    // op bytes 240-255 select the calls added later (the options of the
    // second hardening round), so that the corpus's earlier inputs decode
    // as before wherever their op bytes are below 240
    int const op = in_.Byte();
    if (op >= 240) ok = ExtendedCall(s, op - 240, error);
    else switch (op % 16) {
      case 0: {
        lastCall_ = "CreateRigidActor";
        RigidActorParams p;
        p.mass = in_.Int(4) ? 1 : in_.Real();
        if (!in_.Int(4)) p.inertia = in_.Vector();
        p.position = Real3(0.3 * in_.Int(8), 0, 0);
        if (!in_.Int(4)) p.rotation = in_.Rotation();
        if (!in_.Int(4)) p.linearVelocity = in_.Vector();
        ok = Track(s, scene.CreateRigidActor(p, error));
        break;
      }
      case 1: {
        lastCall_ = "CreateDeformableActor";
        DeformableActorParams p;
        TetMesh mesh;
        Expect(MakeTetBox(Real3(0, 1, 0), Real3(0.1, 0.1, 0.1), {1, 1, 1}, mesh, error), "MakeTetBox");
        p.nodes = mesh.nodes;
        p.tetrahedra = mesh.tetrahedra;
        if (!in_.Int(3)) p.density = in_.Real();
        if (!in_.Int(3)) p.youngModulus = in_.Real();
        if (!in_.Int(4)) p.tetrahedra[in_.Int(6)][in_.Int(4)] = in_.Int(12) - 2;
        if (!in_.Int(4)) p.nodes[in_.Int(8)] = in_.Vector();
        ok = Track(s, scene.CreateDeformableActor(p, error));
        break;
      }
      case 2: {
        lastCall_ = "CreateRodActor";
        RodActorParams p;
        p.nodes = {Real3(0, 2, 0), Real3(0.1, 2, 0), Real3(0.2, 2, 0)};
        if (!in_.Int(3)) p.radius = in_.Real();
        if (!in_.Int(3)) p.density = in_.Real();
        if (!in_.Int(4)) p.nodes[in_.Int(3)] = in_.Vector();
        ok = Track(s, scene.CreateRodActor(p, error));
        break;
      }
      case 3: {
        lastCall_ = "CreateArticulatedActor";
        ArticulatedActorParams p;
        p.links.resize(1 + in_.Int(2));
        for (std::size_t i = 0; i < p.links.size(); ++i) {
          ArticulatedLinkParams& l = p.links[i];
          l.parent = static_cast<int>(i) - 1;
          l.joint = static_cast<JointType>(in_.Int(6));  // one past the last: an invalid value
          l.jointToChildPosition = Real3(0.2, 0, 0);
          if (!in_.Int(3)) l.axis = in_.Vector();
          if (!in_.Int(3)) {
            int const count = in_.Int(7);  // read before the value
            l.initialPosition.assign(count, in_.Real());
          }
        }
        ok = Track(s, scene.CreateArticulatedActor(p, error));
        break;
      }
      case 4:
      case 5:
        ok = CreateConstraint(s, scene, error);
        break;
      case 6:
        lastCall_ = "DestroyActor";
        ok = scene.DestroyActor(PickActor(s), error);
        break;
      case 7:
        lastCall_ = "DestroyConstraint(handle)";
        ok = scene.DestroyConstraint(PickConstraint(s), error);
        break;
      case 8: {
        lastCall_ = "DestroyConstraint(pointer)";
        // live, destroyed (never dereferenced by the scene) or the other scene's
        Issued const& from = issued_[in_.Int(2)];
        Constraint* pointer = from.pointers.empty() ? nullptr : from.pointers[in_.Int(256) % from.pointers.size()];
        ok = scene.DestroyConstraint(pointer, error);
        break;
      }
      case 9: {
        lastCall_ = "a runtime setter";
        Constraint* c = scene.GetConstraint(PickConstraint(s));  // only live ones are used
        if (!c) return true;
        switch (in_.Int(9)) {
          case 0: ok = c->SetStiffness(in_.Real(), error); break;
          case 1: ok = c->SetDamping(in_.Real(), error); break;
          case 2: ok = c->SetSaturation(in_.Real(), error); break;
          case 3: ok = c->SetTargetPosition(in_.Vector(), error); break;
          case 4: ok = c->SetTargetRotation(in_.Rotation(), error); break;
          case 5: ok = c->SetTargetDof(in_.Real(), error); break;
          case 6: ok = c->UpdateOldTarget(error); break;
          case 7: ok = c->RegisterQuery(static_cast<QueryType>(in_.Int(3)), error); break;
          case 8: ok = c->SetHessianApproximation(static_cast<ConstraintHessian>(in_.Int(4)), error); break;
        }
        // a query registered or not: reading the force never crashes
        Error ignored;
        (void)c->GetForce(ignored);
        break;
      }
      case 10:
      case 11: {
        lastCall_ = "Step";
        static real const kDt[] = {1e-3, 1.0 / 60, 1.0 / 30, 0, -1e-3, std::nan(""), 1e300};
        real const dt = kDt[in_.Int(7)];
        if (Trace()) {
          lastCall_ += " " + std::to_string(dt);
          std::fprintf(stderr, "  stepping by %g\n", dt);
        }
        ok = scene.Step(dt, error);
        if (Trace() && !ok) std::fprintf(stderr, "  %s\n", error.ToString().c_str());
        break;
      }
      case 12: {
        lastCall_ = "ForEachConstraint with destruction";
        int const every = 1 + in_.Int(3);
        int visited = 0;
        scene.ForEachConstraint([&](Constraint* c) {
          Expect(scene.GetConstraint(c->GetHandle()) == c, "ForEachConstraint visited a dead constraint");
          Error e;
          if (visited++ % every == 0) scene.DestroyConstraint(c, e);
        });
        break;
      }
      case 13: {
        lastCall_ = "ForEachActor with destruction and creation";
        int const every = 1 + in_.Int(3);
        int visited = 0;
        scene.ForEachActor([&](Actor& a) {
          Expect(scene.GetActor(a.GetHandle()) == &a, "ForEachActor visited a dead actor");
          Error e;
          if (visited++ % every == 0) {
            scene.DestroyActor(a.GetHandle(), e);
            Track(s, scene.CreateRigidActor({}, e));
          }
        });
        break;
      }
      case 14: {
        lastCall_ = "Step inside ForEachActor";
        bool first = true;
        scene.ForEachActor([&](Actor&) {
          Error e;
          if (first) scene.Step(1e-3, e);
          first = false;
        });
        break;
      }
      case 15: {
        lastCall_ = "SetLinearSolver";
        PcgParams pcg;
        pcg.preconditioner = static_cast<PcgPreconditioner>(in_.Int(10));
        if (!in_.Int(3)) pcg.relativeTolerance = in_.Real();
        if (!in_.Int(3)) pcg.maxIterations = in_.Int(256) - 16;
        LinearSolverType const type = static_cast<LinearSolverType>(in_.Int(6));
        if (Trace())
          lastCall_ += " " + std::to_string(static_cast<int>(type)) + " pc " +
                       std::to_string(static_cast<int>(pcg.preconditioner)) + " rtol " +
                       std::to_string(pcg.relativeTolerance) + " maxIt " + std::to_string(pcg.maxIterations);
        ok = scene.SetLinearSolver(type, pcg, error);
        break;
      }
    }
    if (!ok) Expect(static_cast<bool>(error), "a failed call set no Error", lastCall_);
    return ok;
  }

  /// The calls of the options that landed after the first round: thread
  /// counts, sub-stepping, PCG's truncated steps, adaptive tolerance, lag and
  /// PETSc options, a scene created anew with near-rigid caps and the other
  /// SceneParams, and articulated actors with their options.
  bool ExtendedCall(int s, int op, Error& error) {
    switch (op % 5) {
      case 0: {
        // never kMaxThreads itself (256 workers), but past it and far past it
        static int const kThreads[] = {0, 1, 2, 3, -1, kMaxThreads + 1, 1000, std::numeric_limits<int>::max()};
        int const threads = kThreads[in_.Int(std::size(kThreads))];
        lastCall_ = "SetNumThreads " + std::to_string(threads);
        return scenes_[s]->SetNumThreads(threads, error);
      }
      case 1: {
        static int const kSubsteps[] = {1, 2, 4, 8, 16, 0, -1, 3, 2 * kMaxSubsteps, 1 << 30};
        int const substeps = kSubsteps[in_.Int(std::size(kSubsteps))];
        lastCall_ = "SetSubstepParams " + std::to_string(substeps);
        return scenes_[s]->SetSubstepParams({.maxSubsteps = substeps}, error);
      }
      case 2: {
        static char const* const kOptions[] = {"", "-ksp_norm_type unpreconditioned", "-pc_gamg_no_such_option 3",
                                               "-ksp_rtol abc", "bad", "-ksp_type"};
        PcgParams pcg;
        pcg.preconditioner = static_cast<PcgPreconditioner>(in_.Int(6));
        pcg.truncatedSteps = in_.Int(2);
        pcg.adaptiveTolerance = in_.Int(2);
        if (!in_.Int(3)) pcg.adaptiveMaxTolerance = in_.Real();
        if (!in_.Int(3)) pcg.preconditionerLag = in_.Int(8) - 2;
        pcg.options = kOptions[in_.Int(std::size(kOptions))];
        lastCall_ = "SetLinearSolver PetscPcg pc " + std::to_string(static_cast<int>(pcg.preconditioner)) +
                    " options \"" + pcg.options + "\"";
        return scenes_[s]->SetLinearSolver(LinearSolverType::PetscPcg, pcg, error);
      }
      case 3: {
        lastCall_ = "Scene::Create anew";
        SceneParams params;
        params.newton.maxIterations = 1 + in_.Int(25);
        params.numThreads = in_.Int(4);
        params.substeps.maxSubsteps = 1 << in_.Int(4);
        params.integrator = static_cast<IntegratorType>(in_.Int(3));
        params.patternPolicy = static_cast<PatternPolicy>(in_.Int(3));
        if (!in_.Int(2)) params.newton.nearRigidBeta = in_.Real();
        params.newton.reuseFactorization = in_.Int(2);
        params.newton.constraintHessian = static_cast<ConstraintHessian>(in_.Int(3));
        std::unique_ptr<Scene> scene = Scene::Create(params, error);
        if (!scene) return false;
        // what the old scene issued stays in the pools: stale, foreign
        // handles and pointers for the calls that follow
        scenes_[s] = std::move(scene);
        return true;
      }
      case 4: {
        lastCall_ = "CreateArticulatedActor with options";
        ArticulatedActorParams p;
        p.blockSolve = static_cast<ArticulatedBlockSolve>(in_.Int(3));  // one past the last: invalid
        p.extrapolateFirstIterate = in_.Int(2);
        p.links.resize(1 + in_.Int(5));
        for (std::size_t i = 0; i < p.links.size(); ++i) {
          ArticulatedLinkParams& l = p.links[i];
          l.parent = in_.Int(4) ? static_cast<int>(i) - 1 : in_.Int(8) - 2;
          l.joint = static_cast<JointType>(in_.Int(5));
          l.jointToChildPosition = Real3(0.2, 0, 0);
          l.centerOfMass = Real3(0.1, 0, 0);
          if (!in_.Int(3)) l.armature = in_.Real();
          if (!in_.Int(3)) l.damping = in_.Real();
          if (!in_.Int(4)) l.mass = in_.Real();
          if (!in_.Int(4)) {
            int const count = in_.Int(7);  // read before the value
            l.initialVelocity.assign(count, in_.Real());
          }
        }
        return Track(s, scenes_[s]->CreateArticulatedActor(p, error));
      }
    }
    return true;
  }

  // every type of constraints/constraint_types.h, its params from its
  // Fields(): handles drawn from everything issued, the other fields mostly
  // at their defaults, often hostile; a working stiffness most of the time
  template <class Params>
  Params FuzzParams(int s) {
    Params p;
    for (auto const& field : Params::Fields())
      std::visit([&](auto member) { Fill(s, field.name, p.*member); }, field.member);
    return p;
  }
  void Fill(int s, std::string_view, ActorHandle& value) { value = PickActor(s); }
  void Fill(int, std::string_view, int& value) {
    if (in_.Int(3)) value = in_.Int(12) - 2;
  }
  void Fill(int, std::string_view name, real& value) {
    if (name == "stiffness") value = in_.Int(3) ? 1e4 : in_.Real();
    else if (!in_.Int(3)) value = in_.Real();
  }
  void Fill(int, std::string_view, bool& value) { value = in_.Int(2); }
  void Fill(int, std::string_view, Real3& value) {
    if (!in_.Int(3)) value = in_.Vector();
  }
  void Fill(int, std::string_view, Quat& value) {
    if (!in_.Int(3)) value = in_.Rotation();
  }
  template <class Params>
  Constraint* Create(int s, Scene& scene, Constraint* (Scene::*create)(Params const&, Error&), char const* name,
                     Error& error) {
    lastCall_ = name;
    return (scene.*create)(FuzzParams<Params>(s), error);
  }

  bool CreateConstraint(int s, Scene& scene, Error& error) {
    Constraint* c = nullptr;
    int type = in_.Int(kNumConstraintTypes);
#define SUPERDEX_FUZZ_TYPE(Name, Class, file)                                                              \
    if (type-- == 0) c = Create(s, scene, &Scene::Create##Name##Constraint, "Create" #Name "Constraint", error);
    SUPERDEX_CONSTRAINT_TYPES(SUPERDEX_FUZZ_TYPE)
#undef SUPERDEX_FUZZ_TYPE
    if (!c) return false;
    issued_[s].constraints.push_back(c->GetHandle());
    issued_[s].pointers.push_back(c);
    return true;
  }

  bool Track(int s, Actor* actor) {
    if (!actor) return false;
    issued_[s].actors.push_back(actor->GetHandle());
    return true;
  }

  /// Mostly one of this scene's handles (live or stale), else the other
  /// scene's, a null one, or one built from numbers (scene 0).
  template <class H>
  H Pick(int s, std::vector<H> Issued::*pool) {
    std::vector<H> const& from = issued_[in_.Int(8) == 0 ? 1 - s : s].*pool;
    switch (in_.Int(16)) {
      case 0: return {};
      case 1: return H{static_cast<std::uint32_t>(in_.Int(4)), 1};
      default: return from.empty() ? H{} : from[in_.Int(256) % from.size()];
    }
  }
  ActorHandle PickActor(int s) { return Pick(s, &Issued::actors); }
  ConstraintHandle PickConstraint(int s) { return Pick(s, &Issued::constraints); }

  Input& in_;
  std::unique_ptr<Scene> scenes_[2];
  Issued issued_[2];
  std::string lastCall_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  Driver driver(in);
  driver.Run();
  return 0;
}
