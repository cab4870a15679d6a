// Uses an installed SuperDex through find_package(SuperDex): builds a scene
// with the reference page's ball-and-socket example, steps it, and checks
// the results. Exits non-zero when a result is wrong.
//
// It also exercises the library boundary where the two sides' Eigen layouts
// must agree. The ctest tests build it with the default flags, with
// -march=x86-64 (baseline SSE2) and with -march=native, while the library
// is built with -march=native: fixed-size Eigen values (Real3, Quat, Real33)
// go into the library and come back by value, a DynamicArray of structs
// holding Quat members is read by the library, and heap blocks allocated
// inside the library (MatrixX and VectorX from Eigen's aligned allocator,
// DynamicArray of Real3) are destroyed here. With a mismatch (16-byte
// alignment here, 32 or 64 in the library) Quat values may be misread and
// Eigen's heap blocks are freed with the wrong allocator.
#include <superdex/superdex.h>

#include <cmath>
#include <cstdio>

namespace {

// the instruction set this file was compiled for, printed so that the test
// can check that its -march reached the compiler
char const* InstructionSet() {
#if defined(__AVX512F__)
  return "AVX-512";
#elif defined(__AVX2__)
  return "AVX2";
#elif defined(__AVX__)
  return "AVX";
#else
  return "SSE2";
#endif
}

}  // namespace

int main() {
  using namespace superdex;
  // line by line, so that a crash at the boundary shows the last check passed
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  int failures = 0;
  auto check = [&](bool ok, char const* what) {
    std::printf("%-58s %s\n", what, ok ? "ok" : "WRONG");
    failures += ok ? 0 : 1;
  };
  auto near = [](auto const& a, auto const& b, real tol) { return (a - b).norm() <= tol; };

  std::printf("SuperDex %s\n", SUPERDEX_VERSION_STRING);
  std::printf("consumer instruction set: %s, Eigen max alignment %d (static %d), alignof(Quat) %zu\n",
              InstructionSet(), EIGEN_MAX_ALIGN_BYTES, EIGEN_MAX_STATIC_ALIGN_BYTES, alignof(Quat));
  BlasInfo const blas = GetBlasInfo();
  std::printf("BLAS: %s, core %s, %d threads\n", blas.library.c_str(),
              blas.coreName.empty() ? "-" : blas.coreName.c_str(), blas.numThreads);

  Error error;
  std::unique_ptr<Scene> scene = Scene::Create(SceneParams{}, error);
  if (!scene) {
    std::printf("Scene::Create failed: %s\n", error.ToString().c_str());
    return 1;
  }

  // two bodies, A pinned at its centre, B hanging from A by a ball joint
  RigidActorParams a;
  a.mass = 1;
  RigidActorParams b = a;
  b.position = Real3{1_r, 0_r, 0_r};
  RigidActor* bodyA = scene->CreateRigidActor(a, error);
  RigidActor* bodyB = scene->CreateRigidActor(b, error);
  check(bodyA && bodyB, "create two rigid actors");
  if (!bodyA || !bodyB) return 1;

  RigidPivotPositionConstraintParams pin;
  pin.actor = bodyA->GetHandle();
  pin.position = Real3{0_r, 0_r, 0_r};
  pin.stiffness = 1e6_r;
  check(scene->CreateRigidPivotPositionConstraint(pin, error) != nullptr, "create RigidPivotPosition");

  RigidSphericalJointConstraintParams p;
  p.actorA = bodyA->GetHandle();  p.actorB = bodyB->GetHandle();
  p.localPosA = Real3{0.5_r, 0_r, 0_r};  p.localPosB = Real3{-0.5_r, 0_r, 0_r};
  p.stiffness = 1e6_r;
  Constraint* j = scene->CreateRigidSphericalJointConstraint(p, error);
  check(j != nullptr, "create RigidSphericalJoint (the reference page's example)");
  if (!j) return 1;

  for (int i = 0; i < 100; ++i)
    if (!scene->Step(1e-3_r, error)) {
      std::printf("Step failed: %s\n", error.ToString().c_str());
      return 1;
    }
  std::printf("after 0.1 s: B at (%.4f, %.4f, %.4f), solver %s\n", bodyB->GetPosition().x(),
              bodyB->GetPosition().y(), bodyB->GetPosition().z(),
              scene->GetStats().linearSolver.c_str());
  check(bodyB->GetPosition().y() < -1e-3_r, "B swings down under gravity");
  DynamicArray<real> const g = j->GetDeviation();
  real const deviation = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  check(g.size() == 3 && deviation < 1e-4_r, "joint deviation stays at the compliance scale");
  check(scene->GetStats().patternBuilds == 1, "pattern built once");

  // bad input is an Error, not a crash
  check(!j->SetStiffness(-1_r, error) && error.GetCode() == ErrorCode::InvalidArgument,
        "negative stiffness is rejected");

  // ---- the library boundary: fixed-size Eigen values both ways ----------
  // Quat is 32 bytes: its alignment follows EIGEN_MAX_STATIC_ALIGN_BYTES
  // (16 with SSE2, 32 with AVX when not pinned); Real3 and Real33 are not
  // multiples of 16 bytes and are never over-aligned.
  Real3 const phi{0.3_r, -0.2_r, 0.5_r};
  Quat const expected(Eigen::AngleAxis<real>(phi.norm(), phi.normalized()));
  Quat const q = Exp(phi);  // returned by value from the library
  check(near(q.coeffs(), expected.coeffs(), 1e-14_r), "so3: Exp(phi) (a Quat from the library)");
  check(near(Log(expected), phi, 1e-14_r), "so3: Log(q) (a Quat into the library)");
  check(near(ExpMatrix(phi), expected.toRotationMatrix(), 1e-14_r), "so3: ExpMatrix(phi) (a Real33 back)");
  check(near(Log(expected.toRotationMatrix()), phi, 1e-12_r), "so3: Log(R) (a Real33 into the library)");
  Real3 const other{-1_r, 2_r, 0.5_r};
  check(near(Hat(phi) * other, phi.cross(other), 1e-15_r), "so3: Hat(a) b = a x b");
  check(near(LeftJacobian(phi) * LeftJacobianInverse(phi), Real33::Identity(), 1e-13_r),
        "so3: J_l(phi) J_l(phi)^-1 = I");

  // a rigid body's pose: set with a Quat made here, read from the library's
  // object by reference
  RigidActorParams turned;
  turned.mass = 2;
  turned.position = Real3{0_r, 5_r, 0_r};
  turned.rotation = expected;
  turned.angularVelocity = Real3{0_r, 0_r, 0_r};
  RigidActor* body = scene->CreateRigidActor(turned, error);
  check(body && near(body->GetRotation().coeffs(), expected.coeffs(), 1e-15_r),
        "rigid actor: rotation from RigidActorParams");
  if (!body) return 1;
  Quat const second = Exp(Real3{0_r, 0_r, 1_r}) * expected;
  check(body->SetPose(Real3{1_r, 2_r, 3_r}, second, error) &&
            near(body->GetRotation().coeffs(), second.coeffs(), 1e-15_r) &&
            near(body->GetPosition(), Real3(1_r, 2_r, 3_r), 0_r),
        "rigid actor: SetPose(Real3, Quat) and the pose read back");
  Real3 const local{0.1_r, 0.2_r, -0.3_r};
  check(near(body->TransformPoint(local), Real3(1_r, 2_r, 3_r) + second * local, 1e-14_r),
        "rigid actor: TransformPoint(Real3)");

  // ---- a DynamicArray of structs with Quat members into the library, and
  // heap blocks from Eigen's aligned allocator back out -------------------
  // one revolute link about z, its centre of mass 0.5 m from the joint along
  // the link's x: M = I_zz + m 0.5^2, bias = -tau_gravity = m g 0.5 at q = 0
  ArticulatedActorParams arm;
  ArticulatedLinkParams link;
  link.joint = JointType::Revolute;
  link.axis = Real3::UnitZ();
  link.parentToJointPosition = Real3{0_r, 10_r, 0_r};
  link.jointToChildPosition = Real3{0.5_r, 0_r, 0_r};
  link.mass = 2;
  link.inertia = Real3{1_r, 2_r, 3_r};
  arm.links.push_back(link);
  // a second link on a spherical joint, its frames turned, at a joint
  // rotation given by a rotation vector
  ArticulatedLinkParams ball;
  ball.parent = 0;
  ball.joint = JointType::Spherical;
  ball.parentToJointPosition = Real3{1_r, 0_r, 0_r};
  ball.parentToJointRotation = Exp(Real3{0_r, 0.4_r, 0_r});
  ball.jointToChildRotation = Exp(Real3{0.1_r, 0_r, 0.2_r});
  ball.jointToChildPosition = Real3{0.25_r, 0_r, 0_r};
  ball.mass = 1;
  ball.initialPosition = {0.2_r, -0.1_r, 0.3_r};
  arm.links.push_back(ball);
  ArticulatedActor* chain = scene->CreateArticulatedActor(arm, error);
  check(chain != nullptr, "articulated actor from DynamicArray<ArticulatedLinkParams>");
  if (!chain) {
    std::printf("CreateArticulatedActor failed: %s\n", error.ToString().c_str());
    return 1;
  }
  check(chain->GetNumDofs() == 4, "articulated actor: 1 + 3 DoFs");
  Quat const jointRotation(Eigen::AngleAxis<real>(Real3(0.2_r, -0.1_r, 0.3_r).norm(),
                                                  Real3(0.2_r, -0.1_r, 0.3_r).normalized()));
  check(near(chain->GetJointRotation(1).coeffs(), jointRotation.coeffs(), 1e-14_r),
        "articulated actor: GetJointRotation (a Quat member, by value)");
  Quat const linkRotation = ball.parentToJointRotation * jointRotation * ball.jointToChildRotation;
  check(near(chain->GetLinkRotation(1).coeffs(), linkRotation.coeffs(), 1e-14_r),
        "articulated actor: GetLinkRotation = X_pj J X_jc (a Quat back)");
  {
    MatrixX const mass = chain->ComputeMassMatrix();  // allocated in the library, freed here
    VectorX const bias = chain->ComputeBiasForces(Real3{0_r, -9.81_r, 0_r});
    check(mass.rows() == 4 && mass.cols() == 4 && near(mass, mass.transpose(), 1e-12_r) &&
              mass.llt().info() == Eigen::Success,
          "articulated actor: ComputeMassMatrix is 4x4, symmetric, SPD");
    check(bias.size() == 4 && bias.allFinite(), "articulated actor: ComputeBiasForces has 4 entries");
    std::printf("mass matrix diagonal (%.6f, %.6f, %.6f, %.6f), bias[0] %.6f\n", mass(0, 0), mass(1, 1),
                mass(2, 2), mass(3, 3), bias[0]);
  }
  {
    // the first link alone: the closed forms above
    ArticulatedActorParams single;
    single.links.push_back(link);
    std::unique_ptr<ArticulatedActor> lone = ArticulatedActor::Create(single, error);
    check(lone != nullptr, "articulated actor: one revolute link (Create, owned here)");
    if (!lone) return 1;
    MatrixX const mass = lone->ComputeMassMatrix();
    VectorX const bias = lone->ComputeBiasForces(Real3{0_r, -9.81_r, 0_r});
    check(mass.size() == 1 && std::abs(mass(0, 0) - 3.5_r) < 1e-12_r, "revolute link: M = I_zz + m r^2 = 3.5");
    check(bias.size() == 1 && std::abs(bias[0] - 9.81_r) < 1e-12_r, "revolute link: bias = m g r = 9.81");
  }  // the actor, allocated by the library, is destroyed here

  // DynamicArray<Real3> filled and returned by the library, freed here
  TetMesh mesh;
  check(MakeTetBox(Real3{0_r, 0_r, 0_r}, Real3{1_r, 0.5_r, 0.25_r}, {2, 1, 1}, mesh, error) &&
            mesh.nodes.size() == 12 && mesh.tetrahedra.size() == 12 &&
            near(mesh.nodes.back(), Real3(1_r, 0.5_r, 0.25_r), 0_r),
        "MakeTetBox: 12 nodes, 12 tetrahedra, the far corner");
  DeformableActorParams block;
  block.nodes = mesh.nodes;
  block.tetrahedra = mesh.tetrahedra;
  block.position = Real3{0_r, 3_r, 0_r};
  block.rotation = second;
  DeformableActor* soft = scene->CreateDeformableActor(block, error);
  check(soft != nullptr, "deformable actor from the box");
  if (!soft) return 1;
  {
    DynamicArray<Real3> const nodes = soft->GetNodePositions();
    bool same = nodes.size() == mesh.nodes.size();
    for (std::size_t i = 0; same && i < nodes.size(); ++i)
      same = near(nodes[i], block.position + second * mesh.nodes[i], 1e-14_r);
    check(same, "deformable actor: GetNodePositions = T X (a Quat in the params)");
  }

  for (int i = 0; i < 10; ++i)
    if (!scene->Step(1e-3_r, error)) {
      std::printf("Step with every actor failed: %s\n", error.ToString().c_str());
      return 1;
    }
  check(soft->GetNodePositions()[0].allFinite() && chain->GetLinkRotation(1).coeffs().allFinite() &&
            std::abs(chain->GetLinkRotation(1).norm() - 1_r) < 1e-12_r,
        "10 steps with every actor: finite, unit link rotation");
  scene.reset();  // everything the library allocated, freed from here

  std::printf("%s\n", failures == 0 ? "consumer: ok" : "consumer: WRONG RESULTS");
  return failures == 0 ? 0 : 1;
}
