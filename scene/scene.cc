#include <superdex/scene/scene.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <iterator>
#include <string_view>
#include <type_traits>

#include <superdex/core/stopwatch.h>
#include <superdex/core/validate.h>
#include <superdex/solver/newton_solver.h>

namespace superdex {

namespace {
/// Why `map` has no object for `h`: issued by another scene, or null/stale.
template <class T, class Tag>
std::string WhyMissing(internal::SlotMap<T, Tag> const& map, Handle<Tag> h, std::uint32_t sceneId) {
  // scene 0 issues nothing: such a handle was made by hand, not by a scene
  if (map.IsForeign(h) && h.scene == 0)
    return "was issued by no scene (scene 0; this is scene " + std::to_string(sceneId) + ")";
  if (map.IsForeign(h))
    return "belongs to another scene (this is scene " + std::to_string(sceneId) + ")";
  return "is null or stale";
}

/// Calls fn on each object of `order`, in order, over a snapshot of their
/// handles: each is looked up again before its turn, so that fn may create,
/// destroy or step (an object destroyed meanwhile is skipped, one created is
/// not visited).
template <class T, class Tag, class Fn>
void VisitSnapshot(internal::SlotMap<T, Tag> const& map, DynamicArray<T*> const& order, Fn const& fn) {
  DynamicArray<Handle<Tag>> handles;
  handles.reserve(order.size());
  for (T* object : order) handles.push_back(object->GetHandle());
  for (Handle<Tag> handle : handles)
    if (T* object = map.Get(handle)) fn(*object);
}

/// Scene numbers, unique in the process; 0 is never issued (null handles).
std::uint32_t NextSceneId() {
  static std::atomic<std::uint32_t> last{0};
  std::uint32_t id = ++last;
  if (id == 0) id = ++last;  // after 2^32 scenes
  return id;
}

// maxSubsteps a power of two >= 1: every attempt halves the last one's
// sub-step, so the cap is itself an attempt and dt/k is exact
bool CheckSubstepParams(SubstepParams const& p, std::string const& prefix, Error& error) {
  int const n = p.maxSubsteps;
  if (n < 1 || n > kMaxSubsteps || (n & (n - 1)) != 0) {
    error.Set(ErrorCode::InvalidArgument, prefix + "maxSubsteps must be a power of two in [1, kMaxSubsteps = " +
                                              std::to_string(kMaxSubsteps) +
                                              "] (1 turns sub-stepping off), got " + std::to_string(n));
    return false;
  }
  return true;
}

bool CheckNumThreads(int numThreads, std::string const& field, Error& error) {
  if (numThreads < 0 || numThreads > kMaxThreads) {
    error.Set(ErrorCode::InvalidArgument, field + " must be in [0, kMaxThreads = " + std::to_string(kMaxThreads) +
                                              "] (0: every CPU), got " + std::to_string(numThreads));
    return false;
  }
  return true;
}
}  // namespace

Scene::Scene(SceneParams const& params)
    : id_(NextSceneId()),
      params_(params),
      actors_(id_),
      constraints_(id_),
      solver_(std::make_unique<internal::NewtonSolver>()),
      contact_(params.contact) {}

Scene::~Scene() = default;

std::unique_ptr<Scene> Scene::Create(SceneParams const& params, Error& error) {
  using namespace internal;
  if (!CheckFinite(params.gravity, "SceneParams.gravity", error)) return nullptr;
  if (params.integrator != IntegratorType::BackwardEuler && params.integrator != IntegratorType::Bdf2) {
    error.Set(ErrorCode::InvalidArgument,
              "SceneParams.integrator must be an IntegratorType, got the value " +
                  std::to_string(static_cast<int>(params.integrator)));
    return nullptr;
  }
  if (params.ordering != OrderingMethod::Metis && params.ordering != OrderingMethod::Natural &&
      params.ordering != OrderingMethod::SolverDefault) {
    error.Set(ErrorCode::InvalidArgument,
              "SceneParams.ordering must be an OrderingMethod, got the value " +
                  std::to_string(static_cast<int>(params.ordering)));
    return nullptr;
  }
  if (params.patternPolicy != PatternPolicy::ReserveAndGrow && params.patternPolicy != PatternPolicy::RebuildWhenChanged) {
    error.Set(ErrorCode::InvalidArgument, "SceneParams.patternPolicy must be a PatternPolicy, got the value " +
                                              std::to_string(static_cast<int>(params.patternPolicy)));
    return nullptr;
  }
  if (params.newton.maxIterations <= 0) {
    error.Set(ErrorCode::InvalidArgument, "SceneParams.newton.maxIterations must be > 0, got " +
                                               std::to_string(params.newton.maxIterations));
    return nullptr;
  }
  if (!CheckPositive(params.newton.velocityTolerance, "SceneParams.newton.velocityTolerance", error))
    return nullptr;
  if (params.newton.hessianProjection != HessianProjection::WhenIndefinite &&
      params.newton.hessianProjection != HessianProjection::Always) {
    error.Set(ErrorCode::InvalidArgument,
              "SceneParams.newton.hessianProjection must be a HessianProjection, got the value " +
                  std::to_string(static_cast<int>(params.newton.hessianProjection)));
    return nullptr;
  }
  if (!CheckConstraintHessian(params.newton.constraintHessian, "SceneParams.newton.constraintHessian", false,
                              error))
    return nullptr;
  if (!ValidateContactParams(params.contact, error)) return nullptr;
  if (!CheckNonNegative(params.newton.nearRigidBeta, "SceneParams.newton.nearRigidBeta", error))
    return nullptr;
  if (!(params.newton.factorReuseTolerance > 0 && params.newton.factorReuseTolerance < 1)) {
    error.Set(ErrorCode::InvalidArgument,
              "SceneParams.newton.factorReuseTolerance must be in (0, 1), got " +
                  internal::Format(params.newton.factorReuseTolerance));
    return nullptr;
  }
  if (params.newton.maxLineSearchSteps <= 0) {
    error.Set(ErrorCode::InvalidArgument, "SceneParams.newton.maxLineSearchSteps must be > 0, got " +
                                               std::to_string(params.newton.maxLineSearchSteps));
    return nullptr;
  }
  if (!CheckSubstepParams(params.substeps, "SceneParams.substeps.", error)) return nullptr;
  if (!CheckNumThreads(params.numThreads, "SceneParams.numThreads", error)) return nullptr;
  if (!params.communicator.Check("SceneParams.communicator", error)) return nullptr;
  std::unique_ptr<Scene> scene(new Scene(params));
  scene->solver_->SetCommunicator(params.communicator);
  scene->solver_->SetNumThreads(params.numThreads);
  scene->solver_->SetPatternPolicy(params.patternPolicy);
  if (!scene->solver_->SetLinearSolver(params.linearSolver, params.pcg, error)) {
    // name the field as the caller wrote it
    std::string message = error.GetMessage();
    if (message.rfind("PcgParams.", 0) == 0) message = "SceneParams.pcg." + message.substr(10);
    error.Set(error.GetCode(), message);
    return nullptr;
  }
  return scene;
}

int Scene::GetNumDofs() const {
  int n = 0;
  for (Actor* actor : actorOrder_) n += actor->GetNumDofs();
  return n;
}

// ---- topology ----

void Scene::OnTopologyChanged() {
  int offset = 0;
  for (Actor* actor : actorOrder_) {
    actor->dofOffset_ = offset;
    offset += actor->GetNumDofs();
  }
  for (Constraint* constraint : constraintOrder_) constraint->RefreshDofs();
  topologyChanged_ = true;
  // the solver's terms may include one just destroyed: forgotten until the
  // next Analyze (SetNumThreads reserved scratch on a destroyed actor's term)
  solver_->ForgetTerms();
}

ActorHandle Scene::AddActor(std::unique_ptr<Actor> actor) {
  Actor* raw = actor.get();
  raw->handle_ = actors_.Insert(std::move(actor));
  actorOrder_.push_back(raw);
  OnTopologyChanged();
  return raw->handle_;
}

RigidActor* Scene::CreateRigidActor(RigidActorParams const& params, Error& error) {
  std::unique_ptr<RigidActor> actor = RigidActor::Create(params, error);
  if (!actor) return nullptr;
  RigidActor* raw = actor.get();
  AddActor(std::move(actor));
  return raw;
}

DeformableActor* Scene::CreateDeformableActor(DeformableActorParams const& params, Error& error) {
  std::unique_ptr<DeformableActor> actor = DeformableActor::Create(params, error);
  if (!actor) return nullptr;
  DeformableActor* raw = actor.get();
  AddActor(std::move(actor));
  return raw;
}

RodActor* Scene::CreateRodActor(RodActorParams const& params, Error& error) {
  std::unique_ptr<RodActor> actor = RodActor::Create(params, error);
  if (!actor) return nullptr;
  RodActor* raw = actor.get();
  AddActor(std::move(actor));
  return raw;
}

ArticulatedActor* Scene::CreateArticulatedActor(ArticulatedActorParams const& params, Error& error) {
  std::unique_ptr<ArticulatedActor> actor = ArticulatedActor::Create(params, error);
  if (!actor) return nullptr;
  ArticulatedActor* raw = actor.get();
  AddActor(std::move(actor));
  return raw;
}

Actor* Scene::GetActor(ActorHandle handle) const { return actors_.Get(handle); }

void Scene::VisitActors(std::function<void(Actor&)> const& fn) const {
  VisitSnapshot(actors_, actorOrder_, fn);
}

bool Scene::DestroyActor(ActorHandle handle, Error& error) {
  Actor* actor = actors_.Get(handle);
  if (!actor) {
    error.Set(ErrorCode::InvalidHandle, "DestroyActor: actor handle " + HandleText(handle) + " " +
                                             WhyMissing(actors_, handle, id_));
    return false;
  }
  // every constraint that references the actor goes with it
  DynamicArray<ConstraintHandle> doomed;
  for (Constraint* c : constraintOrder_)
    for (int i = 0; i < c->GetNumActors(); ++i)
      if (c->GetActor(i) == actor) doomed.push_back(c->GetHandle());
  for (ConstraintHandle c : doomed) RemoveConstraint(constraints_.Get(c));
  contact_.RemoveActor(handle);
  actorOrder_.erase(std::find(actorOrder_.begin(), actorOrder_.end(), actor));
  actors_.Remove(handle);
  OnTopologyChanged();
  return true;
}

// ---- contact ----

Collider* Scene::CreateCollider(ColliderParams const& params, Error& error) {
  if (int const ranks = params_.communicator.IsSet() ? params_.communicator.GetSize() : 1; ranks > 1) {
    // obstacle contact only (docs/distributed.md, "Contact across ranks"):
    // its pairs never change the pattern, so the other policy has nothing
    // to compare and is not built across ranks
    if (params_.patternPolicy == PatternPolicy::RebuildWhenChanged) {
      error.Set(ErrorCode::NotSupported, "CreateCollider: SceneParams.patternPolicy RebuildWhenChanged is not "
                                         "supported on a scene across " +
                                             std::to_string(ranks) + " MPI ranks (ReserveAndGrow is)");
      return nullptr;
    }
    contact_.SetObstacleContactOnly(ranks);
  }
  RigidActor* rigid = nullptr;
  NodalActor* nodal = nullptr;
  ArticulatedActor* articulated = nullptr;
  if (!params.actor.IsNull()) {
    Actor* actor = actors_.Get(params.actor);
    if (!actor) {
      error.Set(ErrorCode::InvalidHandle, "CreateCollider: actor handle " + HandleText(params.actor) + " " +
                                              WhyMissing(actors_, params.actor, id_));
      return nullptr;
    }
    if (actor->GetType() == ActorType::Rigid) {
      rigid = static_cast<RigidActor*>(actor);
    } else if (actor->GetType() == ActorType::Deformable || actor->GetType() == ActorType::Rod) {
      nodal = static_cast<NodalActor*>(actor);
    } else {
      articulated = static_cast<ArticulatedActor*>(actor);
    }
  }
  Collider* collider = contact_.Add(params, rigid, nodal, articulated, error);
  if (!collider) return nullptr;
  OnTopologyChanged();
  return collider;
}

// ---- constraints ----

Constraint* Scene::AddConstraint(std::unique_ptr<Constraint> constraint) {
  if (!constraint) return nullptr;  // refused by the type's Create (error set)
  Constraint* raw = constraint.get();
  raw->GetState().handle = constraints_.Insert(std::move(constraint));
  constraintOrder_.push_back(raw);
  OnTopologyChanged();
  return raw;
}

#define SUPERDEX_CONSTRAINT_FACTORY(Name, Class, file)                                               \
  Constraint* Scene::Create##Name##Constraint(Name##ConstraintParams const& params, Error& error) { \
    return AddConstraint(Class::Create(*this, params, error));                                      \
  }
SUPERDEX_CONSTRAINT_TYPES(SUPERDEX_CONSTRAINT_FACTORY)
#undef SUPERDEX_CONSTRAINT_FACTORY

std::string Scene::WhyNotFound(ActorHandle handle) const { return WhyMissing(actors_, handle, id_); }

Constraint* Scene::GetConstraint(ConstraintHandle handle) const { return constraints_.Get(handle); }

void Scene::VisitConstraints(std::function<void(Constraint&)> const& fn) const {
  VisitSnapshot(constraints_, constraintOrder_, fn);
}

void Scene::RemoveConstraint(Constraint* constraint) {
  constraintOrder_.erase(std::find(constraintOrder_.begin(), constraintOrder_.end(), constraint));
  std::unique_ptr<Constraint> removed = constraints_.Remove(constraint->GetHandle());
  if (quarantine_.size() < static_cast<std::size_t>(kPointerQuarantine)) {
    quarantine_.push_back(std::move(removed));
  } else {
    quarantine_[quarantineNext_] = std::move(removed);  // frees the oldest
    quarantineNext_ = (quarantineNext_ + 1) % kPointerQuarantine;
  }
}

bool Scene::DestroyConstraint(ConstraintHandle handle, Error& error) {
  Constraint* c = constraints_.Get(handle);
  if (!c) {
    error.Set(ErrorCode::InvalidHandle, "DestroyConstraint: constraint handle " + HandleText(handle) +
                                             " " + WhyMissing(constraints_, handle, id_));
    return false;
  }
  RemoveConstraint(c);
  OnTopologyChanged();
  return true;
}

bool Scene::DestroyConstraint(Constraint* constraint, Error& error) {
  // look the pointer up among live constraints instead of dereferencing it
  if (constraint == nullptr) {
    error.Set(ErrorCode::InvalidHandle, "DestroyConstraint: the constraint pointer is null");
    return false;
  }
  auto it = std::find(constraintOrder_.begin(), constraintOrder_.end(), constraint);
  if (it != constraintOrder_.end()) return DestroyConstraint((*it)->GetHandle(), error);
  bool const destroyed = std::any_of(quarantine_.begin(), quarantine_.end(),
                                     [&](auto const& dead) { return dead.get() == constraint; });
  error.Set(ErrorCode::InvalidHandle,
            destroyed ? "DestroyConstraint: the constraint pointer names a constraint that was destroyed "
                        "(directly or with one of its actors)"
                      : "DestroyConstraint: the constraint pointer is not a live constraint of this scene "
                        "(another scene's, or destroyed long ago; ConstraintHandle tells them apart)");
  return false;
}

bool Scene::DestroyConstraint(Constraint* constraint) {
  Error ignored;
  return DestroyConstraint(constraint, ignored);
}

bool Scene::DestroyConstraint(ConstraintHandle handle) {
  Error ignored;
  return DestroyConstraint(handle, ignored);
}

// ---- stepping ----

bool Scene::SetLinearSolver(LinearSolverType type, PcgParams const& pcg, Error& error) {
  if (type == LinearSolverType::Dense && GetNumDofs() > kDenseSolverMaxUnknowns) {
    error.Set(ErrorCode::InvalidArgument,
              "linearSolver Dense takes at most kDenseSolverMaxUnknowns = " +
                  std::to_string(kDenseSolverMaxUnknowns) + " unknowns, this scene has " +
                  std::to_string(GetNumDofs()) + " DoFs; use Cholmod or PetscPcg");
    return false;
  }
  if (!solver_->SetLinearSolver(type, pcg, error)) return false;
  params_.linearSolver = type;
  params_.pcg = pcg;
  return true;
}

bool Scene::SetSubstepParams(SubstepParams const& substeps, Error& error) {
  if (!CheckSubstepParams(substeps, "SubstepParams.", error)) return false;
  params_.substeps = substeps;
  return true;
}

bool Scene::SetNumThreads(int numThreads, Error& error) {
  if (!CheckNumThreads(numThreads, "numThreads", error)) return false;
  solver_->SetNumThreads(numThreads);
  params_.numThreads = numThreads;
  return true;
}

int Scene::GetNumThreads() const { return solver_->GetNumThreads(); }

bool Scene::Step(real dt, Error& error) {
  if (!internal::CheckPositive(dt, "dt", error)) return false;
  if (solver_->IsDistributed() && !CheckRanksAgree(dt, error)) return false;
  auto const start = std::chrono::steady_clock::now();

  // reset the per-step figures
  stats_.newtonIterations = 0;
  stats_.linearIterations = 0;
  stats_.linearSolves = 0;
  stats_.projectionFallbacks = 0;
  stats_.separateCouplingRetries = 0;
  stats_.roundOffConvergences = 0;
  stats_.lineSearchExpansions = 0;
  stats_.limitedSteps = 0;
  stats_.diagonalShifts = 0;
  stats_.secondOrderCorrections = 0;
  stats_.truncatedSolves = 0;
  stats_.factorizations = 0;
  stats_.reusedFactorSolves = 0;
  stats_.singlePrecisionSolves = 0;
  stats_.nearRigidConstraints = 0;
  stats_.stageContributors = 0;
  stats_.contactRecenterings = 0;
  contact_.ResetTimes();
  stats_.analysisSeconds = stats_.assemblySeconds = stats_.factorizationSeconds = 0;
  stats_.orderingSeconds = stats_.patternSeconds = stats_.slotTableSeconds = stats_.symbolicSeconds = 0;
  stats_.solveSeconds = stats_.lineSearchSeconds = 0;

  // no actor, nothing to integrate (and no system to solve): time advances
  if (actorOrder_.empty()) {
    time_ += dt;
    ++stats_.steps;
    stats_.substeps = 1;
    stats_.stepSeconds = internal::SecondsSince(start);
    return true;
  }

  if (topologyChanged_) {
    auto const analysisStart = std::chrono::steady_clock::now();
    // the stage's DoF owners (the actors, in DoF order) and terms (each
    // actor's inertia and elastic energy, then the constraints)
    DynamicArray<internal::StageDofs*> dofs;
    DynamicArray<internal::StageTerm*> terms;
    for (Actor* actor : actorOrder_) {
      dofs.push_back(&actor->GetStageDofs());
      terms.push_back(&actor->GetStageTerm());
    }
    constraintTerm_.SetConstraints(constraintOrder_);
    terms.push_back(&constraintTerm_);
    terms.insert(terms.end(), attachedTerms_.begin(), attachedTerms_.end());
    if (!contact_.Empty()) terms.push_back(&contact_);
    if (!solver_->Analyze(std::move(dofs), std::move(terms), params_.ordering, stats_, error)) return false;
    topologyChanged_ = false;
    stats_.analysisSeconds +=
        internal::SecondsSince(analysisStart);
  }

  // snapshot for a transactional step
  actorSnapshots_.resize(actorOrder_.size());
  for (std::size_t i = 0; i < actorOrder_.size(); ++i) actorOrder_[i]->SaveSnapshot(actorSnapshots_[i]);
  constraintSnapshots_.resize(constraintOrder_.size());
  for (std::size_t i = 0; i < constraintOrder_.size(); ++i)
    constraintSnapshots_[i] = constraintOrder_[i]->GetState().oldTarget;
  contact_.SaveState();

  // the step whole; if it fails, again from the exact pre-step state as 2,
  // 4, ... sub-steps, up to the policy's cap (SubstepParams)
  real historyStep = historyStep_;
  int substeps = 1, failedSubstep = 0;
  Error stageError;
  bool ok = AdvanceSubsteps(dt, substeps, historyStep, failedSubstep, stageError);
  while (!ok && substeps < params_.substeps.maxSubsteps) {
    RestorePreStepState();
    SaveOrRestoreSubstepState(/*save=*/substeps == 1);
    substeps *= 2;
    historyStep = historyStep_;
    ok = AdvanceSubsteps(dt, substeps, historyStep, failedSubstep, stageError);
  }
  stats_.substeps = substeps;
  internal::ContactSystem::PhaseTimes const& contactTimes = contact_.GetTimes();
  stats_.contactBroadPhaseSeconds = contactTimes.broadPhase;
  stats_.contactNarrowPhaseSeconds = contactTimes.narrowPhase;
  stats_.contactCcdSeconds = contactTimes.ccd;
  stats_.contactAssemblySeconds = contactTimes.assembly;
  if (!ok) {
    RestorePreStepState();
    if (substeps > 1) SaveOrRestoreSubstepState(/*save=*/false);
    std::string where = stageError.GetMessage();
    if (substeps > 1) {
      std::string attempts = "1";
      for (int k = 1; k < substeps;) {  // (k doubles up to substeps, never past it)
        k *= 2;
        attempts += (k == substeps ? " and " : ", ") + std::to_string(k);
      }
      real const h = dt / substeps;
      where = "sub-step " + std::to_string(failedSubstep) + " of " + std::to_string(substeps) +
              " (dt/" + std::to_string(substeps) + " = " + internal::Format(h) +
              " from t = " + internal::Format(time_ + (failedSubstep - 1) * h) +
              "), the last of the attempts as " + attempts +
              " sub-steps (SceneParams.substeps.maxSubsteps = " +
              std::to_string(params_.substeps.maxSubsteps) + "): " + where;
    }
    error.Set(stageError.GetCode(), "Step(dt = " + internal::Format(dt) + ") at t = " +
                                        internal::Format(time_) + " failed in " + where +
                                        "; the scene is unchanged");
    return false;
  }
  historyStep_ = historyStep;
  time_ += dt;
  ++stats_.steps;
  contact_.CommitStep();
  stats_.contactCandidates = contact_.GetNumCandidates();
  stats_.activeContacts = contact_.GetNumActive();
  stats_.minContactDistance = contact_.GetMinDistance();
  if (substeps > 1) ++stats_.substeppedSteps;
  stats_.stepSeconds = internal::SecondsSince(start);
  return true;
}

bool Scene::CheckRanksAgree(real dt, Error& error) {
  // every rank must make the same calls with the same arguments
  // (docs/distributed.md): what steers the step's collective control flow,
  // as bits, compared in one reduction before anything collective runs. A
  // rank stepping another dt, with sub-stepping on alone or with other
  // tolerances would drift apart silently or wait forever for the others
  auto bits = [](auto value) {
    std::uint64_t out = 0;
    if constexpr (std::is_floating_point_v<decltype(value)>)
      std::memcpy(&out, &value, sizeof value);
    else
      out = static_cast<std::uint64_t>(value);
    return out;
  };
  auto hash = [&](std::initializer_list<std::uint64_t> values, std::string_view text = {}) {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a
    auto add = [&](std::uint64_t word) {
      for (int b = 0; b < 8; ++b) h = (h ^ ((word >> (8 * b)) & 0xff)) * 1099511628211ull;
    };
    for (std::uint64_t v : values) add(v);
    for (char c : text) add(static_cast<unsigned char>(c));
    return h;
  };
  NewtonParams const& n = params_.newton;
  PcgParams const& p = params_.pcg;
  std::uint64_t const values[] = {
      bits(dt),
      bits(time_),
      bits(params_.substeps.maxSubsteps),
      hash({bits(params_.integrator), bits(params_.gravity.x()), bits(params_.gravity.y()),
            bits(params_.gravity.z()), bits(params_.ordering), bits(params_.patternPolicy)}),
      hash({bits(n.maxIterations), bits(n.velocityTolerance), bits(n.maxLineSearchSteps),
            bits(n.hessianProjection), bits(n.constraintHessian), bits(n.nearRigidBeta),
            bits(n.reuseFactorization), bits(n.factorReuseTolerance), bits(n.reuseForcingTerms),
            bits(n.singlePrecisionReusedFactor)}),
      hash({bits(params_.linearSolver), bits(p.preconditioner), bits(p.relativeTolerance),
            bits(p.absoluteTolerance), bits(p.maxIterations), bits(p.adaptiveTolerance),
            bits(p.adaptiveMaxTolerance), bits(p.truncatedSteps), bits(p.preconditionerLag),
            bits(p.reuseAmgInterpolation), bits(p.blockJacobiBlocks), bits(p.iccLevels)},
           p.options),
      bits(actorOrder_.size()),
      bits(constraintOrder_.size()),
  };
  static constexpr char const* kWhat[] = {
      "dt",
      "the scene time",
      "SceneParams.substeps.maxSubsteps",
      "SceneParams.integrator, gravity, ordering or patternPolicy",
      "SceneParams.newton",
      "SceneParams.linearSolver or pcg",
      "the number of actors",
      "the number of constraints",
  };
  static_assert(std::size(values) == std::size(kWhat));
  int const first = solver_->FirstRankDisagreement(Span<std::uint64_t const>(values, std::size(values)));
  if (first < 0) return true;
  error.Set(ErrorCode::InvalidArgument,
            "Step: the " + std::to_string(solver_->GetNumRanks()) +
                " ranks of SceneParams.communicator disagree on " + kWhat[first] +
                " (every rank must make the same calls with the same arguments: docs/distributed.md); "
                "the scene is unchanged");
  return false;
}

bool Scene::AdvanceSubsteps(real dt, int substeps, real& historyStep, int& failedSubstep,
                            Error& error) {
  real const h = dt / substeps;
  for (int index = 1; index <= substeps; ++index) {
    if (substeps > 1) SetSubstepTargets(index, substeps);
    contact_.SetStepFraction(static_cast<real>(index - 1) / substeps,
                             index == substeps ? real(1) : static_cast<real>(index) / substeps);
    // BDF2 uses the history only when it spans a step of this size
    internal::StageContext stage;
    stage.coefficients = internal::MakeStage(params_.integrator, h, internal::IsHistoryUsable(historyStep, h));
    stage.gravity = params_.gravity;
    bool const solved = solver_->Solve(0, stage, params_.newton, stats_, error);
    stats_.nearRigidConstraints = std::max(stats_.nearRigidConstraints, constraintTerm_.GetNumNearRigid());
    if (!solved) {
      failedSubstep = index;
      return false;
    }
    historyStep = h;
  }
  return true;
}

void Scene::RestorePreStepState() {
  for (std::size_t i = 0; i < actorOrder_.size(); ++i)
    actorOrder_[i]->RestoreSnapshot(*actorSnapshots_[i]);
  for (std::size_t i = 0; i < constraintOrder_.size(); ++i)
    constraintOrder_[i]->GetState().oldTarget = constraintSnapshots_[i];
  contact_.RestoreState();
}

void Scene::SaveOrRestoreSubstepState(bool save) {
  std::size_t const n = constraintOrder_.size();
  if (save) {
    targetSnapshots_.resize(n);
    forceSnapshots_.resize(n);
    forceValidSnapshots_.resize(n);
  }
  for (std::size_t i = 0; i < n; ++i) {
    internal::ConstraintState& c = constraintOrder_[i]->GetState();
    if (save) {
      targetSnapshots_[i] = c.target;
      forceSnapshots_[i] = c.force;
      forceValidSnapshots_[i] = c.forceValid;
    } else {
      c.target = targetSnapshots_[i];
      c.force = forceSnapshots_[i];
      c.forceValid = forceValidSnapshots_[i];
    }
  }
}

void Scene::SetSubstepTargets(int index, int substeps) {
  real const s = static_cast<real>(index) / substeps;
  for (std::size_t i = 0; i < constraintOrder_.size(); ++i) {
    // from the old target p̂ᵢ⁰ to the target as the caller set it
    Constraint& c = *constraintOrder_[i];
    c.GetState().target = internal::InterpolateTarget(c.GetTargetKind(), constraintSnapshots_[i], targetSnapshots_[i],
                                                      index == substeps ? real(1) : s);
  }
}

namespace internal {
void SetFaultInjectionForTesting(Scene& scene, FaultInjection const& fault) {
  scene.solver_->SetFaultInjection(fault);
}

void AttachStageTerm(Scene& scene, StageTerm& term) {
  scene.attachedTerms_.push_back(&term);
  scene.topologyChanged_ = true;
  scene.solver_->ForgetTerms();
}
}  // namespace internal

}  // namespace superdex
