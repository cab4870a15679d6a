"""Every error path raises mochi.Error with the library's code and a message
naming the bad field (C++ field names, as the library writes them), and a
failed call changes nothing."""
import math
import os

import numpy as np
import pytest

import mochi
from helpers import make_zoo, raises, valid_params

NAN = math.nan
INF = math.inf


@pytest.fixture
def scene():
    return mochi.Scene.create()


@pytest.fixture
def zoo(scene):
    return make_zoo(scene)


def test_error_carries_code_and_message(scene):
    body = scene.create_rigid_actor()
    pin = scene.create_rigid_pivot_position_constraint(actor=body, stiffness=1)
    with pytest.raises(mochi.Error) as info:
        pin.set_stiffness(-1)
    e = info.value
    assert isinstance(e, Exception)
    assert isinstance(e.code, mochi.ErrorCode) and e.code.name == "InvalidArgument"
    assert e.message == "stiffness must be finite and >= 0, got -1"
    assert str(e) == "InvalidArgument: " + e.message
    assert issubclass(mochi.Error, Exception)


def test_scene_params_are_validated():
    with raises(mochi.ErrorCode.InvalidArgument, "SceneParams.gravity"):
        mochi.Scene.create(gravity=[0, NAN, 0])
    with raises(mochi.ErrorCode.InvalidArgument, "maxIterations"):
        mochi.Scene.create(newton=mochi.NewtonParams(max_iterations=0))
    params = mochi.SceneParams()
    params.newton.velocity_tolerance = 0  # nested params are edited in place
    with raises(mochi.ErrorCode.InvalidArgument, "velocityTolerance"):
        mochi.Scene.create(params)
    with raises(mochi.ErrorCode.InvalidArgument, "relativeTolerance"):
        mochi.Scene.create(linear_solver=mochi.LinearSolverType.PetscPcg,
                           pcg=mochi.PcgParams(relative_tolerance=2))
    with raises(mochi.ErrorCode.InvalidArgument, "SceneParams.newton.constraintHessian"):
        mochi.Scene.create(newton=mochi.NewtonParams(
            constraint_hessian=mochi.ConstraintHessian.SceneDefault))
    for beta in (-1.0, NAN):
        with raises(mochi.ErrorCode.InvalidArgument, "SceneParams.newton.nearRigidBeta"):
            mochi.Scene.create(newton=mochi.NewtonParams(near_rigid_beta=beta))


@pytest.mark.parametrize("field,value,fragment", [
    ("mass", 0.0, "RigidActorParams.mass"),
    ("mass", NAN, "RigidActorParams.mass"),
    ("inertia", [1, -1, 1], "RigidActorParams.inertia"),
    ("rotation", [2, 0, 0, 0], "RigidActorParams.rotation"),
    ("rotation", [0, 0, 0, 0], "RigidActorParams.rotation"),
    ("position", [INF, 0, 0], "RigidActorParams.position"),
])
def test_bad_rigid_actor_params(scene, field, value, fragment):
    with raises(mochi.ErrorCode.InvalidArgument, fragment):
        scene.create_rigid_actor(**{field: value})
    assert scene.get_num_actors() == 0


@pytest.mark.parametrize("bad", [-1.0, NAN, INF])
@pytest.mark.parametrize("field", ["stiffness", "damping"])
def test_every_constraint_factory_rejects_bad_compliance(scene, zoo, field, bad):
    for factory, params_class, kwargs in valid_params(zoo):
        params = params_class(**kwargs)
        setattr(params, field, bad)
        with raises(mochi.ErrorCode.InvalidArgument, params_class.__name__ + "." + field):
            getattr(scene, factory)(params)
    assert scene.get_num_constraints() == 0
    # and the valid ones are created, each as its own class
    for factory, params_class, kwargs in valid_params(zoo):
        c = getattr(scene, factory)(**kwargs)
        assert isinstance(c, mochi.Constraint)
    assert scene.get_num_constraints() == len(valid_params(zoo))


def test_bad_handles(scene, zoo):
    with raises(mochi.ErrorCode.InvalidHandle, "actor"):
        scene.create_rigid_pivot_position_constraint(stiffness=1)  # a null handle
    with raises(mochi.ErrorCode.InvalidHandle, "actor"):  # a deformable actor where a rigid one is needed
        scene.create_rigid_pivot_position_constraint(actor=zoo["soft"], stiffness=1)
    with raises(mochi.ErrorCode.InvalidArgument, "actorB"):  # the same body twice
        scene.create_rigid_spherical_joint_constraint(actor_a=zoo["a"], actor_b=zoo["a"])
    stale = zoo["b"].get_handle()
    scene.destroy_actor(zoo["b"])
    with raises(mochi.ErrorCode.InvalidHandle, "actorB"):
        scene.create_rigid_spherical_joint_constraint(actor_a=zoo["a"], actor_b=stale)
    with raises(mochi.ErrorCode.InvalidHandle, "DestroyActor"):
        scene.destroy_actor(stale)
    assert scene.get_actor(stale) is None
    with raises(mochi.ErrorCode.InvalidArgument, "actor must be an ActorHandle or an actor"):
        scene.destroy_actor("b")


def test_bad_indices_in_params(scene, zoo):
    with raises(mochi.ErrorCode.InvalidArgument, "nodeIndex"):
        scene.create_deformable_node_position_constraint(actor=zoo["soft"], node_index=99, stiffness=1)
    with raises(mochi.ErrorCode.InvalidArgument, "elementIndex"):
        scene.create_rod_element_rotation_to_rigid_constraint(rigid_actor=zoo["a"], rod_actor=zoo["rod"],
                                                              element_index=2)
    with raises(mochi.ErrorCode.InvalidArgument, "jointIndex"):
        scene.create_articulated_single_dof_target_constraint(actor=zoo["arm"], joint_index=5)
    # a single-DoF type on a spherical joint: the 3D types apply there
    with raises(mochi.ErrorCode.InvalidArgument, "ArticulatedSingleDofTargetConstraintParams"):
        scene.create_articulated_single_dof_target_constraint(actor=zoo["arm"], joint_index=1)
    with raises(mochi.ErrorCode.InvalidArgument, "lowerLimit"):
        scene.create_articulated_single_dof_range_constraint(actor=zoo["arm"], lower_limit=1, upper_limit=0)
    # an articulated link in a rigid type: in range on an articulated actor, -1 on a rigid one
    with raises(mochi.ErrorCode.InvalidArgument, "RigidPivotPositionConstraintParams.link must be a link"):
        scene.create_rigid_pivot_position_constraint(actor=zoo["arm"], link=2, stiffness=1)
    with raises(mochi.ErrorCode.InvalidArgument, "RigidSphericalJointConstraintParams.linkA must be -1"):
        scene.create_rigid_spherical_joint_constraint(actor_a=zoo["a"], link_a=0, actor_b=zoo["b"])
    with raises(mochi.ErrorCode.InvalidArgument, "rigidLink must be a link"):
        scene.create_deformable_node_to_rigid_constraint(deformable_actor=zoo["soft"], rigid_actor=zoo["arm"])


def test_bad_dt_changes_nothing(scene):
    body = scene.create_rigid_actor()
    scene.step(1e-3)
    position, time = body.get_position(), scene.get_time()
    for dt in [0.0, -1e-3, NAN, INF]:
        with raises(mochi.ErrorCode.InvalidArgument, "dt"):
            scene.step(dt)
    assert scene.get_time() == time
    np.testing.assert_array_equal(body.get_position(), position)


def test_runtime_setters(scene):
    body = scene.create_rigid_actor()
    pin = scene.create_rigid_pivot_position_constraint(actor=body, stiffness=100, damping=1)
    for bad in [-1.0, NAN, INF]:
        with raises(mochi.ErrorCode.InvalidArgument, "stiffness"):
            pin.set_stiffness(bad)
        with raises(mochi.ErrorCode.InvalidArgument, "damping"):
            pin.set_damping(bad)
    with raises(mochi.ErrorCode.InvalidArgument, "saturation"):
        pin.set_saturation(NAN)
    assert pin.has_curvature()
    assert pin.get_hessian_approximation() == mochi.ConstraintHessian.SceneDefault
    pin.set_hessian_approximation(mochi.ConstraintHessian.GaussNewton)
    assert pin.get_hessian_approximation() == mochi.ConstraintHessian.GaussNewton
    assert (pin.get_stiffness(), pin.get_damping()) == (100, 1)
    with raises(mochi.ErrorCode.InvalidArgument, "position"):
        pin.set_target_position([NAN, 0, 0])
    hold = scene.create_rigid_pivot_rotation_constraint(actor=body, stiffness=1)
    with raises(mochi.ErrorCode.InvalidArgument, "rotation"):
        hold.set_target_rotation([0.5, 0, 0, 0])
    with raises(mochi.ErrorCode.InvalidArgument, "rotation"):
        body.set_pose([0, 0, 0], [2, 0, 0, 0])
    np.testing.assert_array_equal(body.get_rotation(), [1, 0, 0, 0])
    with raises(mochi.ErrorCode.InvalidArgument, "angular"):
        body.set_velocity([0, 0, 0], [0, NAN, 0])


def test_queries_and_limits_out_of_order(scene):
    body = scene.create_rigid_actor()
    pin = scene.create_rigid_pivot_position_constraint(actor=body, stiffness=1)
    with raises(mochi.ErrorCode.InvalidState, "ConstraintForce"):
        pin.get_force()
    with raises(mochi.ErrorCode.NotSupported, "GetLimitMinValues"):
        pin.get_limit_min_values()


def test_field_conversion_errors_name_the_field():
    with raises(mochi.ErrorCode.InvalidArgument, "RigidSphericalJointConstraintParams.local_pos_a",
                "3-sequence"):
        mochi.RigidSphericalJointConstraintParams(local_pos_a=[1, 2])
    with raises(mochi.ErrorCode.InvalidArgument, "RigidActorParams.mass", "number"):
        mochi.RigidActorParams(mass="heavy")
    with raises(mochi.ErrorCode.InvalidArgument, "RigidActorParams.rotation", "(w, x, y, z)"):
        mochi.RigidActorParams(rotation=[1, 0, 0])
    with raises(mochi.ErrorCode.InvalidArgument, "DeformableNodePositionConstraintParams.node_index",
                "integer"):
        mochi.DeformableNodePositionConstraintParams(node_index=1.5)
    with raises(mochi.ErrorCode.InvalidArgument, "DeformableActorParams.tetrahedra", "(n, 4)"):
        mochi.DeformableActorParams(tetrahedra=[[0, 1, 2]])
    with raises(mochi.ErrorCode.InvalidArgument, "DeformableActorParams.tetrahedra", "integers"):
        mochi.DeformableActorParams(tetrahedra=[[0.0, 1.0, 2.0, 3.0]])
    with raises(mochi.ErrorCode.InvalidArgument, "RodActorParams.nodes", "(n, 3)"):
        mochi.RodActorParams(nodes=[0, 1, 2])
    with raises(mochi.ErrorCode.InvalidArgument, "RigidPivotPositionConstraintParams.actor"):
        mochi.RigidPivotPositionConstraintParams(actor=3)
    with raises(mochi.ErrorCode.InvalidArgument, "ArticulatedActorParams.links[1]"):
        mochi.ArticulatedActorParams(links=[mochi.ArticulatedLinkParams(), "link"])
    # an unknown keyword is Python's TypeError, listing the fields
    with pytest.raises(TypeError, match="has no field 'stifness'.*stiffness"):
        mochi.RigidPivotPositionConstraintParams(stifness=1)
    with pytest.raises(TypeError, match="masss"):
        mochi.Scene.create().create_rigid_actor(masss=1)
    # a params object of the wrong type too
    with pytest.raises(TypeError, match="params must be a RodActorParams or None"):
        mochi.Scene.create().create_rod_actor(mochi.RigidActorParams())


def test_mesh_and_actor_errors(scene, tmp_path):
    with raises(mochi.ErrorCode.InvalidArgument, "cells"):
        mochi.make_tet_box(origin=[0, 0, 0], size=[1, 1, 1], cells=[0, 1, 1])
    with raises(mochi.ErrorCode.InvalidState, "cannot open"):
        mochi.read_obj(os.fspath(tmp_path / "missing.obj"))
    (tmp_path / "bad.obj").write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    with raises(mochi.ErrorCode.InvalidArgument, "bad.obj:3"):
        mochi.read_obj(os.fspath(tmp_path / "bad.obj"))
    mesh = mochi.make_tet_box(origin=[0, 0, 0], size=[1, 1, 1], cells=[1, 1, 1])
    tets = mesh.tetrahedra
    tets[0, 0] = 42
    with raises(mochi.ErrorCode.InvalidArgument, "42"):
        scene.create_deformable_actor(nodes=mesh.nodes, tetrahedra=tets)
    with raises(mochi.ErrorCode.InvalidArgument, "poissonRatio"):
        scene.create_deformable_actor(nodes=mesh.nodes, tetrahedra=mesh.tetrahedra, poisson_ratio=0.5)
    with raises(mochi.ErrorCode.InvalidArgument, "RodActorParams"):
        scene.create_rod_actor(nodes=[[0, 0, 0]])
    with raises(mochi.ErrorCode.InvalidArgument, "links"):
        scene.create_articulated_actor()
    assert scene.get_num_actors() == 0
    bad = mochi.TetMesh(nodes=mesh.nodes, tetrahedra=tets)
    with raises(mochi.ErrorCode.InvalidArgument, "42"):
        mochi.signed_volume(bad, 0)  # validated before the unchecked C++ call
    with raises(mochi.ErrorCode.InvalidArgument, "tet"):
        mochi.signed_volume(mesh, 6)


def test_accessor_indices_are_checked(scene, zoo):
    # the C++ accessors state their index ranges as preconditions; mochi checks them
    with raises(mochi.ErrorCode.InvalidArgument, "node index must be in [0, 8), got 8"):
        zoo["soft"].get_node_position(8)
    with raises(mochi.ErrorCode.InvalidArgument, "node index"):
        zoo["soft"].get_node_displacement(-1)
    with raises(mochi.ErrorCode.InvalidArgument, "element index"):
        zoo["rod"].get_material_frame(2)
    with raises(mochi.ErrorCode.InvalidArgument, "interior node index must be in [1, 2)"):
        zoo["rod"].get_strain(0)
    with raises(mochi.ErrorCode.InvalidArgument, "link"):
        zoo["arm"].get_link_position(2)
    with raises(mochi.ErrorCode.NotSupported, "Spherical"):
        zoo["arm"].get_joint_coordinate(1)
    with raises(mochi.ErrorCode.InvalidArgument, "dof"):
        zoo["arm"].get_joint_coordinate(0, 1)


def test_linear_solver_errors(scene):
    with raises(mochi.ErrorCode.InvalidArgument, "Auto"):
        mochi.create_linear_solver(mochi.LinearSolverType.Auto)
    with raises(mochi.ErrorCode.InvalidArgument, "maxIterations"):
        scene.set_linear_solver(mochi.LinearSolverType.Cholmod, mochi.PcgParams(max_iterations=0))
    with raises(mochi.ErrorCode.InvalidArgument, "iccLevels"):
        mochi.validate_pcg_params(mochi.PcgParams(icc_levels=-1))
    assert scene.get_params().linear_solver == mochi.LinearSolverType.Auto  # unchanged


def test_64_bit_indices_are_never_truncated(scene):
    """Before: [0, 1, 2, 2**32 + 3] became [0, 1, 2, 3]."""
    mesh = mochi.make_tet_box(origin=[0, 0, 0], size=[1, 1, 1], cells=[1, 1, 1])
    tets = np.array(mesh.tetrahedra, dtype=np.int64)
    tets[2, 3] = 2**32 + 3
    with raises(mochi.ErrorCode.InvalidArgument, "tetrahedra[2][3] = 4294967299", "32-bit index"):
        scene.create_deformable_actor(nodes=mesh.nodes, tetrahedra=tets)
    with raises(mochi.ErrorCode.InvalidArgument, "4294967299"):
        mochi.TetMesh(nodes=mesh.nodes, tetrahedra=tets)
    big = np.array(mesh.tetrahedra, dtype=np.uint64)
    big[0, 0] = 2**63 + 5
    with raises(mochi.ErrorCode.InvalidArgument, "tetrahedra[0][0] = 9223372036854775813"):
        scene.create_deformable_actor(nodes=mesh.nodes, tetrahedra=big)
    negative = np.array(mesh.tetrahedra, dtype=np.int64)
    negative[1, 1] = -(2**40)
    with raises(mochi.ErrorCode.InvalidArgument, "tetrahedra[1][1] = -1099511627776"):
        scene.create_deformable_actor(nodes=mesh.nodes, tetrahedra=negative)
    assert scene.get_num_actors() == 0
    # int64 indices in range are fine
    scene.create_deformable_actor(nodes=mesh.nodes, tetrahedra=np.array(mesh.tetrahedra, dtype=np.int64))
