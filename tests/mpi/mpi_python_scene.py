"""A scene built from Python on the 2 ranks of `mpiexec -n 2` (SceneParams.communicator =
mochi.Communicator.world()) agrees with the same scene in one process, with MUMPS and with
PCG + GAMG; CHOLMOD across the ranks is refused with a mochi.Error naming it; the beam
landing on a static plane agrees too, and a self-touching surface is refused.

ctest starts it through mpiexec (tests/mpi/CMakeLists.txt). Every rank steps the one-process
scene too, and compares its distributed result with its own reference: an assertion failure
exits that rank with status 1, and mpiexec reports the job failed."""
import sys

import numpy as np

import mochi
from helpers import sagging_beam

DT = 1 / 60
LENGTH = 0.6  # helpers.sagging_beam's length L [m]


def beam_on(communicator, solver):
    """helpers.sagging_beam (tests/python) on `communicator` with `solver`: Newton to well
    below the compared 1e-8 L (a step as a velocity of 1e-9 m/s moves the nodes by < 2e-11 m),
    PCG to rtol 1e-12."""
    return sagging_beam(communicator=communicator, linear_solver=solver, num_threads=1,
                        newton=mochi.NewtonParams(velocity_tolerance=1e-9),
                        pcg=mochi.PcgParams(relative_tolerance=1e-12,
                                            preconditioner=mochi.PcgPreconditioner.Gamg))


def main():
    world = mochi.Communicator.world()
    assert world.is_set() and world.get_size() == 2, repr(world)
    assert 0 <= world.get_rank() < 2
    assert mochi.SceneParams().communicator.get_size() == 1  # the default: one process

    for solver in (mochi.LinearSolverType.PetscMumps, mochi.LinearSolverType.PetscPcg):
        reference, reference_beam = beam_on(mochi.Communicator(), solver)
        distributed, beam = beam_on(world, solver)
        assert distributed.get_params().communicator.get_size() == 2
        initial = reference_beam.get_node_positions()
        for _ in range(20):
            reference.step(DT)
            distributed.step(DT)
        stats = distributed.get_stats()
        # the rows were divided and the solver ran across both ranks
        assert stats.ranks == 2 and 0 < stats.owned_dofs < stats.num_dofs, stats
        assert "2 ranks" in stats.linear_solver, stats.linear_solver
        assert reference.get_stats().ranks == 1
        expected = reference_beam.get_node_positions()
        worst = np.max(np.linalg.norm(beam.get_node_positions() - expected, axis=1))
        moved = np.max(np.linalg.norm(expected - initial, axis=1))
        assert moved > 1e-4 * LENGTH, moved
        assert worst <= 1e-8 * LENGTH, (str(solver), worst)

    # a direct solver of one process is refused on 2 ranks, naming it
    try:
        beam_on(world, mochi.LinearSolverType.Cholmod)
    except mochi.Error as error:
        assert error.code == mochi.ErrorCode.InvalidArgument, error
        assert "Cholmod" in str(error) and "2 ranks" in str(error), str(error)
    else:
        raise AssertionError("CHOLMOD on 2 ranks was not refused")
    check_disagreement(world)
    check_obstacle_contact(world)
    print(f"rank {world.get_rank()}: ok")


def check_obstacle_contact(world):
    """Contact with a static obstacle runs across ranks (docs/distributed.md, "Contact across
    ranks"): the sagging beam lands on a plane 2 cm below it, on 2 ranks as in one process;
    a surface that would touch itself is refused there with a mochi.Error naming why."""
    def landing(communicator):
        scene, beam = beam_on(communicator, mochi.LinearSolverType.PetscMumps)
        scene.create_collider(shape=mochi.ShapeType.Plane, position=[0, -0.02, 0])
        scene.create_collider(actor=beam, group=2, mask=~2 & 0xFFFFFFFF)  # no self contact
        return scene, beam

    reference, reference_beam = landing(mochi.Communicator())
    distributed, beam = landing(world)
    touched = 0
    for _ in range(20):
        reference.step(DT)
        distributed.step(DT)
        assert distributed.get_stats().active_contacts == reference.get_stats().active_contacts
        touched += distributed.get_stats().active_contacts > 0
    assert touched > 0  # it landed
    stats = distributed.get_stats()
    assert stats.ranks == 2 and stats.pattern_builds == 1 and stats.contact_pattern_builds == 0, stats
    worst = np.max(np.linalg.norm(beam.get_node_positions() - reference_beam.get_node_positions(), axis=1))
    assert worst <= 1e-8 * LENGTH, worst
    assert beam.get_node_positions()[:, 1].min() > -0.02  # above the plane

    scene, beam = beam_on(world, mochi.LinearSolverType.PetscMumps)
    try:
        scene.create_collider(actor=beam)  # its group in its mask: self contact
    except mochi.Error as error:
        assert error.code == mochi.ErrorCode.NotSupported, error
        assert "2 MPI ranks" in str(error) and "would touch itself" in str(error), str(error)
    else:
        raise AssertionError("a self-touching surface was accepted on 2 ranks")
    assert scene.get_num_colliders() == 0


def check_disagreement(world):
    """Every rank must make the same calls with the same arguments: a dt, or a sub-stepping
    policy, that differs between the ranks fails the step on both with one mochi.Error and
    changes nothing (a different dt was accepted and the scene times drifted apart; sub-stepping
    on one rank only deadlocked). A Fortran handle that names no communicator is refused
    (it ran as one rank)."""
    rank = world.get_rank()
    scene, beam = beam_on(world, mochi.LinearSolverType.PetscMumps)
    scene.step(DT)
    before, time = beam.get_node_positions(), scene.get_time()

    def refused(what):
        try:
            scene.step(DT * (1 + rank) if what == "dt" else DT)
        except mochi.Error as error:
            assert error.code == mochi.ErrorCode.InvalidArgument, error
            assert f"ranks of SceneParams.communicator disagree on {what}" in str(error), str(error)
            assert "the scene is unchanged" in str(error), str(error)
        else:
            raise AssertionError(f"a step with a different {what} per rank was accepted")
        assert np.array_equal(beam.get_node_positions(), before) and scene.get_time() == time

    refused("dt")
    if rank == 1:
        scene.set_substep_params(max_substeps=8)
    refused("SceneParams.substeps.maxSubsteps")
    scene.set_substep_params(max_substeps=8)
    scene.step(DT)  # agreeing again: both step
    assert scene.get_time() == time + DT

    try:
        mochi.Communicator.from_fortran_handle(12345)
    except mochi.Error as error:
        assert error.code == mochi.ErrorCode.InvalidArgument, error
        assert "not a communicator of this process" in str(error), str(error)
    else:
        raise AssertionError("a Fortran handle that names no communicator was accepted")


if __name__ == "__main__":
    try:
        main()
    except Exception as failure:  # noqa: BLE001 - any failure fails this rank
        print(f"rank failed: {failure!r}", file=sys.stderr)
        sys.exit(1)
