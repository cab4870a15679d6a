"""The second hostile-input round (one process), each reproducer as a user ran it: a valid
step sequence converges, and every bad call raises a clear mochi.Error and leaves the scene
exactly as it was (compared bit for bit). The 2-rank reproducers are in
tests/mpi/mpi_python_scene.py."""
import numpy as np
import pytest

import mochi
from helpers import make_zoo, raises, sagging_beam


def state(scene):
    """Every actor's state bits and the scene time, for 'nothing changed'."""
    parts = [np.float64(scene.get_time()).tobytes()]
    for actor in scene.get_actors():
        for name in ("get_node_positions", "get_node_velocities", "get_joint_positions",
                     "get_joint_velocities", "get_position", "get_linear_velocity"):
            if hasattr(actor, name):
                parts.append(np.asarray(getattr(actor, name)(), dtype=np.float64).tobytes())
    return b"".join(parts)


def arm(scene, **params):
    """make_zoo's arm alone: a revolute joint, then a spherical one."""
    return scene.create_articulated_actor(links=[
        mochi.ArticulatedLinkParams(parent=-1, joint=mochi.JointType.Revolute, axis=[0, 0, 1],
                                    parent_to_joint_position=[0, 4, 0], center_of_mass=[0.25, 0, 0]),
        mochi.ArticulatedLinkParams(parent=0, joint=mochi.JointType.Spherical,
                                    parent_to_joint_position=[0.5, 0, 0], center_of_mass=[0.25, 0, 0]),
    ], **params)


@pytest.mark.parametrize("max_substeps", [1, 8])
def test_a_step_after_a_tiny_one_converges(max_substeps):
    """step(0.01); step(1e-15); step(0.01) failed the third step with NewtonFailed while
    extrapolate_first_iterate was on (the default)."""
    scene = mochi.Scene.create(substeps=mochi.SubstepParams(max_substeps=max_substeps))
    arm(scene)
    for dt in (0.01, 1e-15, 0.01):
        scene.step(dt)
    assert scene.get_stats().newton_iterations <= 4


def test_thread_counts_are_bounded():
    """num_threads=1000 aborted the process under a 4 GB address-space limit;
    set_num_threads(2**31 - 1) raised MemoryError and kept the count."""
    with raises(mochi.ErrorCode.InvalidArgument, "SceneParams.numThreads must be in [0, kMaxThreads = 256]",
                "got 1000"):
        mochi.Scene.create(num_threads=1000)
    scene, beam = sagging_beam(num_threads=1)
    scene.step(1 / 60)
    before = state(scene)
    with raises(mochi.ErrorCode.InvalidArgument, "got 2147483647"):
        scene.set_num_threads(2**31 - 1)
    assert state(scene) == before and scene.get_num_threads() == 1
    scene.step(1 / 60)


def test_sub_steps_are_bounded_and_a_failing_step_reports_them():
    """SubstepParams(max_substeps=2**30) with a body at 1e300 m/s ran ~25 s and raised
    MemoryError (an int overflow in the message's loop)."""
    with raises(mochi.ErrorCode.InvalidArgument, "maxSubsteps must be a power of two in [1, kMaxSubsteps = 4096]"):
        mochi.Scene.create(substeps=mochi.SubstepParams(max_substeps=2**30))
    scene = mochi.Scene.create(substeps=mochi.SubstepParams(max_substeps=4096))
    scene.create_rigid_actor(linear_velocity=[1e300, 0, 0])
    before = state(scene)
    with raises(mochi.ErrorCode.NonFiniteState, "attempts as 1, 2, 4", "2048 and 4096 sub-steps"):
        scene.step(0.01)
    assert state(scene) == before
    with raises(mochi.ErrorCode.InvalidArgument, "SubstepParams.maxSubsteps", "got 1073741824"):
        scene.set_substep_params(max_substeps=2**30)
    assert scene.get_params().substeps.max_substeps == 4096


def test_a_dense_articulated_block_is_bounded():
    """block_solve=Dense on a 1,700-link chain (5,100 DoFs) ran for minutes per step."""
    scene = mochi.Scene.create()
    links = [mochi.ArticulatedLinkParams(parent=i - 1, joint=mochi.JointType.Spherical,
                                         parent_to_joint_position=[0.1 if i else 0, 0, 0],
                                         center_of_mass=[0.05, 0, 0]) for i in range(1700)]
    with raises(mochi.ErrorCode.InvalidArgument, "blockSolve = Dense takes at most kDenseSolverMaxUnknowns = 5000",
                "got 5100 DoFs"):
        scene.create_articulated_actor(links=links, block_solve=mochi.ArticulatedBlockSolve.Dense)
    assert scene.get_num_actors() == 0


def test_wrongly_accepted_inputs_are_refused():
    """Block sizes that do not add up; resolve_linear_solver_type with a negative size or a
    value that is not a LinearSolverType."""
    matrix = mochi.SparseSymmetricMatrix(size=2, col_start=[0, 1, 3], row_index=[0, 0, 1],
                                         values=[2.0, -1.0, 2.0], block_sizes=[3])
    for solver_type in (mochi.LinearSolverType.Dense, mochi.LinearSolverType.PetscMumps):
        solver = mochi.create_linear_solver(solver_type)
        result = solver.analyze(matrix)
        assert result.status == mochi.LinearSolveStatus.InvalidInput, result
        assert "A.blockSizes must add up to A.size = 2 (or be empty), got 3" in result.reason
    with raises(mochi.ErrorCode.InvalidArgument, "size must be >= 0, got -1"):
        mochi.resolve_linear_solver_type(mochi.LinearSolverType.Auto, -1)
    with raises(mochi.ErrorCode.InvalidArgument, "not a LinearSolverType (99)"):
        mochi.resolve_linear_solver_type(mochi.LinearSolverType(99), 5)


def test_errors_come_early_and_name_the_field():
    scene, beam = sagging_beam(num_threads=1)
    scene.step(1 / 60)
    before = state(scene)
    # a PETSc option it does not use: refused by the call, not at the next step
    with raises(mochi.ErrorCode.InvalidArgument, "PcgParams.options", "-pc_gamg_no_such_option"):
        scene.set_linear_solver(mochi.LinearSolverType.PetscPcg,
                                mochi.PcgParams(options="-pc_gamg_no_such_option 3"))
    with raises(mochi.ErrorCode.InvalidArgument, "PcgParams.options", "-ksp_rtol"):
        scene.set_linear_solver(mochi.LinearSolverType.PetscPcg, mochi.PcgParams(options="-ksp_rtol abc"))
    with raises(mochi.ErrorCode.InvalidArgument, "PcgParams.options"):
        mochi.validate_pcg_params(mochi.PcgParams(options="-pc_gamg_no_such_option 3"))
    assert scene.get_params().linear_solver == mochi.LinearSolverType.Auto
    assert state(scene) == before
    scene.step(1 / 60)
    # None is no value: not TypeError, not False for a bool that defaults to True
    with raises(mochi.ErrorCode.InvalidArgument, "NewtonParams.constraint_hessian", "got None"):
        mochi.NewtonParams(constraint_hessian=None)
    with raises(mochi.ErrorCode.InvalidArgument, "ArticulatedActorParams.extrapolate_first_iterate",
                "must be a bool, got None"):
        mochi.ArticulatedActorParams(extrapolate_first_iterate=None)
    with raises(mochi.ErrorCode.InvalidArgument, "PcgParams.truncated_steps", "must be a bool, got None"):
        mochi.PcgParams(truncated_steps=None)
    with raises(mochi.ErrorCode.InvalidArgument, "must be a bool, got 0"):
        mochi.PcgParams(truncated_steps=0)
    assert mochi.PcgParams(truncated_steps=np.bool_(False)).truncated_steps is False
    # an integer out of range is reported as such
    with raises(mochi.ErrorCode.InvalidArgument, "DeformableNodePositionConstraintParams.node_index",
                "must be an integer in [-2147483648, 2147483647], got 4294967296"):
        mochi.DeformableNodePositionConstraintParams(node_index=4294967296)
    # a handle no scene issued
    zoo = make_zoo(scene)
    with raises(mochi.ErrorCode.InvalidHandle, "was issued by no scene (scene 0"):
        scene.create_rigid_pivot_position_constraint(actor=mochi.ActorHandle(0, 1, 0), stiffness=1)
    with raises(mochi.ErrorCode.InvalidHandle, "belongs to another scene"):
        scene.create_rigid_pivot_position_constraint(
            actor=mochi.ActorHandle(0, 1, scene.get_id() + 1000), stiffness=1)
    assert zoo["a"].get_handle().scene == scene.get_id()
