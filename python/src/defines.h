// One Define…(module) per binding file; python/src mirrors the C++ tree
// (core/error.cpp binds core/error.h, ...). module.cpp calls them in
// dependency order: a type is registered before the signatures that use it.
#pragma once

#include "support/casters.h"

namespace superdex::python {

// core/
void DefineError(py::module_& m);
void DefineHandle(py::module_& m);
void DefineSo3(py::module_& m);
void DefineBlasInfo(py::module_& m);
void DefineConfig(py::module_& m);
void DefineCommunicator(py::module_& m);
// linsolve/
void DefineSparseSymmetricMatrix(py::module_& m);
void DefineLinearSolver(py::module_& m);
// assembly/
void DefineOrdering(py::module_& m);
// scene/ (parameters; the Scene class comes last)
void DefineIntegrator(py::module_& m);
void DefineContact(py::module_& m);
void DefineSceneParams(py::module_& m);
// actors/
void DefineActor(py::module_& m);
void DefineNodalActor(py::module_& m);
void DefineRigidActor(py::module_& m);
void DefineTetElement(py::module_& m);
void DefineDeformableActor(py::module_& m);
void DefineMesh(py::module_& m);
void DefineRodElement(py::module_& m);
void DefineRodActor(py::module_& m);
void DefineArticulatedActor(py::module_& m);
void DefineVtkWriter(py::module_& m);
// constraints/
void DefineConstraint(py::module_& m);
/// Every type of constraints/constraint_types.h: params, class, downcast
/// (types.cpp); the per-type files below add their own accessors.
void DefineConstraintTypes(py::module_& m);
void DefineRigidSphericalJoint(py::module_& m);
void DefineRigidPrismaticJoint(py::module_& m);
void DefineJointRotationRange(py::module_& m);
void DefineJointRotationTracking(py::module_& m);
void DefineRigidPivotPosition(py::module_& m);
void DefineRigidPivotToRigidTarget(py::module_& m);
void DefineRigidPivotRotation(py::module_& m);
void DefineDeformableNodePosition(py::module_& m);
void DefineDeformableNodeToRigid(py::module_& m);
void DefineRodElementRotationToRigid(py::module_& m);
void DefineArticulatedJointConstraints(py::module_& m);
// scene/
void DefineScene(py::module_& m);

}  // namespace superdex::python
