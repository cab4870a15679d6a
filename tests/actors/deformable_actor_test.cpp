// The deformable actor as a whole: its assembled stage gradient and Hessian
// (inertia + gravity + every element kind, scattered through the slot
// tables) against finite differences of its stage energy; recovery from an
// inverted initial state; input validation.
#include "test_support.h"
#include "white_box.h"

#include <random>

using namespace superdex;
using namespace superdex::test;
using internal::ActorTestAccess;

namespace {
// a small block of tets with a shell skin on its top face, rotated actor frame
DeformableActorParams BlockWithSkin(TetMaterialModel material) {
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(Real3::Zero(), Real3(0.3, 0.2, 0.2), {3, 2, 2}, mesh, error));
  DeformableActorParams p;
  p.nodes = mesh.nodes;
  p.tetrahedra = mesh.tetrahedra;
  // triangles over the top face (y = 0.2), nodes of the box grid
  auto node = [](int i, int j, int k) { return i + 4 * (j + 3 * k); };
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 2; ++k) {
      p.triangles.push_back({node(i, 2, k), node(i, 2, k + 1), node(i + 1, 2, k)});
      p.triangles.push_back({node(i + 1, 2, k), node(i, 2, k + 1), node(i + 1, 2, k + 1)});
    }
  p.material = material;
  p.youngModulus = 1e4;
  p.thickness = 2e-3;
  p.position = Real3(0.1, 0.5, -0.2);
  p.rotation = Quat(Eigen::AngleAxis<real>(0.4, Real3(1, 1, 0).normalized()));
  return p;
}
}  // namespace

TEST_CASE("the deformable actor's gradient and Hessian match finite differences",
          "[actors][deformable][derivatives]") {
  TetMaterialModel const material =
      GENERATE(TetMaterialModel::StableNeoHookean, TetMaterialModel::LinearElastic);
  CAPTURE(ToString(material));
  DeformableActorParams params = BlockWithSkin(material);
  // a deformed, moving start so that every term is non-trivial
  std::mt19937 rng(7);
  std::uniform_real_distribution<real> jitter(-0.01, 0.01);
  for (std::size_t i = 0; i < params.nodes.size(); ++i) {
    params.initialDisplacements.push_back(Real3(jitter(rng), jitter(rng), jitter(rng)));
    params.initialVelocities.push_back(Real3(jitter(rng), jitter(rng), jitter(rng)) * 10);
  }
  auto scene = MakeScene();
  Error error;
  DeformableActor* actor = scene->CreateDeformableActor(params, error);
  INFO(error.ToString());
  REQUIRE(actor);
  REQUIRE(actor->GetNumHinges() > 0);
  int const n = actor->GetNumDofs();

  real const h = 1e-2;
  ActorTestAccess::BeginStage(*actor, internal::MakeStage(IntegratorType::BackwardEuler, h, false),
                              Real3(0, -9.81, 0));
  // move off the stage start so the inertia term is non-zero too
  DynamicArray<real> offset(n);
  for (real& v : offset) v = jitter(rng);
  ActorTestAccess::SaveIterate(*actor);
  ActorTestAccess::ApplyIncrementFromSaved(*actor, offset, 1);

  DynamicArray<DynamicArray<int>> contributors;
  DynamicArray<int> blocks;
  ActorTestAccess::AppendContributorDofs(*actor, contributors);
  ActorTestAccess::AppendDofBlockSizes(*actor, blocks);
  internal::HessianAssembler assembler;
  REQUIRE(assembler.Analyze(n, blocks, contributors, OrderingMethod::Metis, error));
  DynamicArray<real> gradient(n, 0);
  assembler.ZeroValues();
  ActorTestAccess::AddGradientAndHessian(*actor, gradient, assembler, 0);

  // central differences of the energy along each DoF
  real const eps = 1e-7;
  ActorTestAccess::SaveIterate(*actor);
  DynamicArray<real> delta(n, 0);
  VectorX fdGradient(n);
  for (int j = 0; j < n; ++j) {
    delta[j] = eps;
    ActorTestAccess::ApplyIncrementFromSaved(*actor, delta, 1);
    real const plus = ActorTestAccess::Energy(*actor);
    ActorTestAccess::ApplyIncrementFromSaved(*actor, delta, -1);
    real const minus = ActorTestAccess::Energy(*actor);
    delta[j] = 0;
    fdGradient[j] = (plus - minus) / (2 * eps);
  }
  ActorTestAccess::RestoreIterate(*actor);
  VectorX const analytic = Eigen::Map<VectorX const>(gradient.data(), n);
  real const scale = analytic.lpNorm<Eigen::Infinity>();
  CAPTURE(scale);
  REQUIRE(scale > 1);
  // energy differences of O(1e3) J with ε = 1e-7: round-off ~1e-13·1e3/1e-7 = 1e-3
  // absolute against entries of O(1e2–1e4); 1e-5 of the largest entry covers it
  REQUIRE((analytic - fdGradient).lpNorm<Eigen::Infinity>() <= 1e-5 * scale);

  // the assembled Hessian is symmetric PSD (every block is) and positive
  // definite with the inertia; with LinearElastic (constant element Hessians,
  // already PSD) it equals the finite-difference Jacobian of the gradient
  MatrixX const hessian = DenseNaturalHessian(assembler);
  REQUIRE((hessian - hessian.transpose()).norm() == 0);
  REQUIRE(SymmetricEigenvalues(hessian).minCoeff() > 0);
}

TEST_CASE("an inverted initial state recovers to a non-inverted rest state", "[actors][deformable]") {
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(Real3::Zero(), Real3(0.1, 0.1, 0.1), {2, 2, 2}, mesh, error));
  DeformableActorParams p;
  p.nodes = mesh.nodes;
  p.tetrahedra = mesh.tetrahedra;
  p.youngModulus = 1e5;
  // push the top layer through the bottom: every element of the upper half inverts
  p.initialDisplacements.assign(p.nodes.size(), Real3::Zero());
  for (std::size_t i = 0; i < p.nodes.size(); ++i)
    if (p.nodes[i].y() > 0.09) p.initialDisplacements[i] = Real3(0, -0.15, 0);
  SceneParams params;
  params.gravity = Real3::Zero();
  auto scene = MakeScene(params);
  DeformableActor* actor = scene->CreateDeformableActor(p, error);
  REQUIRE(actor);
  int const invertedAtStart = actor->CountInvertedTetrahedra();
  real const energyAtStart = actor->GetElasticEnergy();
  REQUIRE(invertedAtStart > 0);
  REQUIRE(energyAtStart > 1);
  // backward Euler with 0.05 s steps (ω h ≳ 5 for the block's modes) damps
  // the recoil; it recovers within the first few steps
  StepOk(*scene, 5e-2, 100);
  CAPTURE(invertedAtStart, energyAtStart, actor->GetElasticEnergy(), actor->GetKineticEnergy());
  REQUIRE(actor->CountInvertedTetrahedra() == 0);
  // back in its reference shape (up to a rigid motion) and at rest: the
  // energy released by the recovery is gone, to 1e-9 (strain) and 1e-6
  // (motion: a slow rigid drift from the violent recoil is all that is left)
  REQUIRE(actor->GetElasticEnergy() <= 1e-9 * energyAtStart);
  REQUIRE(actor->GetKineticEnergy() <= 1e-6 * energyAtStart);
}

TEST_CASE("bad deformable input gives an Error naming the element and changes nothing",
          "[actors][deformable][input]") {
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(Real3::Zero(), Real3(0.1, 0.1, 0.1), {1, 1, 1}, mesh, error));
  auto scene = MakeScene();
  auto expectError = [&](DeformableActorParams const& p, std::string const& mention) {
    RequireActorRefused(*scene, p, mention);
  };
  DeformableActorParams good;
  good.nodes = mesh.nodes;
  good.tetrahedra = mesh.tetrahedra;

  SECTION("inverted reference element") {
    DeformableActorParams p = good;
    std::swap(p.tetrahedra[2][0], p.tetrahedra[2][1]);
    expectError(p, "tetrahedra[2]");
  }
  SECTION("degenerate reference element") {
    DeformableActorParams p = good;
    p.nodes.push_back(Real3(0.05, 0, 0));  // on the edge between nodes 0 and 1
    p.tetrahedra.push_back({0, 1, static_cast<int>(p.nodes.size()) - 1, 2});
    expectError(p, "tetrahedra[6]");
  }
  SECTION("out-of-range node index") {
    DeformableActorParams p = good;
    p.tetrahedra[1][3] = 99;
    expectError(p, "99");
  }
  SECTION("repeated node index") {
    DeformableActorParams p = good;
    p.tetrahedra[4][2] = p.tetrahedra[4][0];
    expectError(p, "4");
  }
  SECTION("non-positive material parameters") {
    DeformableActorParams p = good;
    p.youngModulus = 0;
    expectError(p, "youngModulus");
    p = good;
    p.density = -1;
    expectError(p, "density");
    p = good;
    p.poissonRatio = 0.5;
    expectError(p, "poissonRatio");
    p = good;
    p.triangles = {{0, 1, 2}};
    p.thickness = 0;
    expectError(p, "thickness");
  }
  SECTION("a material or membrane model out of its enum") {
    DeformableActorParams p = good;
    p.material = static_cast<TetMaterialModel>(7);
    expectError(p, "material");
    p = good;
    p.membrane = static_cast<MembraneModel>(-1);
    expectError(p, "membrane");
  }
  SECTION("a node in no element") {
    DeformableActorParams p = good;
    p.nodes.push_back(Real3(1, 1, 1));
    expectError(p, "nodes[8]");
  }
  SECTION("a density whose masses underflow or overflow is blamed, not the mesh") {
    // before: "nodes[0] belongs to no element"
    DeformableActorParams p = good;
    p.density = 5e-324;
    expectError(p, "gets mass 0 from density 4.94065645841246");
    p.density = 1e308;
    p.nodes = mesh.nodes;
    for (Real3& x : p.nodes) x *= 1e4;  // volumes of ~1e9 m³: masses overflow
    expectError(p, "gets mass inf from density 1e+308");
  }
  SECTION("a tetrahedron listed twice") {
    // before: accepted with twice its mass and stiffness
    DeformableActorParams p = good;
    p.tetrahedra.push_back(p.tetrahedra[3]);
    expectError(p, "tetrahedra[6] = {");
  }
  SECTION("bad node index in a constraint") {
    DeformableActor* actor = scene->CreateDeformableActor(good, error);
    REQUIRE(actor);
    DeformableNodePositionConstraintParams c;
    c.actor = actor->GetHandle();
    c.nodeIndex = 8;
    Error e;
    REQUIRE_FALSE(scene->CreateDeformableNodePositionConstraint(c, e));
    REQUIRE(e.GetMessage().find("nodeIndex") != std::string::npos);
    REQUIRE(scene->GetNumConstraints() == 0);
  }
}
