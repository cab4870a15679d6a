// The mochi module: SuperDex Physics for Python (docs/python.md).
#include "defines.h"

PYBIND11_MODULE(mochi, m) {
  using namespace superdex::python;
  m.doc() =
      "SuperDex Physics: implicit simulation of rigid bodies, deformable solids and shells, "
      "elastic rods and articulated mechanisms coupled by compliant constraints.\n\nThe C++ API "
      "in snake_case (Scene::CreateRigidActor -> Scene.create_rigid_actor, localPosA -> "
      "local_pos_a). Vectors are numpy arrays (any 3-sequence is accepted for a Real3), "
      "quaternions numpy arrays [w, x, y, z]; every superdex::Error raises mochi.Error. See "
      "docs/python.md.";
  DefineError(m);
  DefineHandle(m);
  DefineSo3(m);
  DefineBlasInfo(m);
  DefineConfig(m);
  DefineCommunicator(m);
  DefineSparseSymmetricMatrix(m);
  DefineLinearSolver(m);
  DefineOrdering(m);
  DefineIntegrator(m);
  DefineContact(m);
  DefineSceneParams(m);
  DefineActor(m);
  DefineNodalActor(m);
  DefineRigidActor(m);
  DefineTetElement(m);
  DefineDeformableActor(m);
  DefineMesh(m);
  DefineRodElement(m);
  DefineRodActor(m);
  DefineArticulatedActor(m);
  DefineVtkWriter(m);
  DefineConstraint(m);
  DefineConstraintTypes(m);
  DefineRigidSphericalJoint(m);
  DefineRigidPrismaticJoint(m);
  DefineJointRotationRange(m);
  DefineJointRotationTracking(m);
  DefineRigidPivotPosition(m);
  DefineRigidPivotToRigidTarget(m);
  DefineRigidPivotRotation(m);
  DefineDeformableNodePosition(m);
  DefineDeformableNodeToRigid(m);
  DefineRodElementRotationToRigid(m);
  DefineArticulatedJointConstraints(m);
  DefineScene(m);
}
