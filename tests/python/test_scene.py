"""Scenes built entirely from Python and stepped, with physically checked
results; actor state as numpy arrays; every kind of actor."""
import math
import os

import numpy as np
import pytest

import mochi
from helpers import sagging_beam

G = 9.81


def test_free_fall_for_100_steps_follows_half_g_t_squared():
    scene = mochi.Scene.create(integrator=mochi.IntegratorType.BackwardEuler,
                               newton=mochi.NewtonParams(velocity_tolerance=1e-12))
    body = scene.create_rigid_actor(mass=3, inertia=[0.1, 0.2, 0.3], position=[0, 10, 0])
    h = 0.01
    for n in range(1, 101):
        scene.step(h)
        t = n * h
        y = body.get_position()[1] - 10
        v = body.get_linear_velocity()[1]
        # backward Euler's discrete solution, v_n = -g t_n and y_n = -½ g t_n² - ½ g h t_n,
        # holds to round-off (the C++ test bounds it by 4ε(n+1)²; 1e-12 relative is above that)
        assert abs(v + G * t) <= 1e-12 * G * t
        assert abs(y + 0.5 * G * t * t + 0.5 * G * h * t) <= 1e-12 * G * t * t
        # against the exact ½ g t²: backward Euler's first-order error is ½ g h t,
        # i.e. h / t relative (1 % at t = 1 s): allow that and no more
        assert abs(y + 0.5 * G * t * t) <= 0.5 * G * h * t * (1 + 1e-9)
    assert scene.get_time() == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(body.get_position()[[0, 2]], [0, 0], atol=1e-15)  # nothing acts across
    np.testing.assert_allclose(body.get_angular_velocity(), [0, 0, 0], atol=1e-15)
    assert body.get_kinetic_energy() == pytest.approx(0.5 * 3 * (G * 1.0) ** 2, rel=1e-12)


def test_a_chain_built_from_python_obeys_momentum_balance_and_dissipates():
    # three 1 kg bodies along +x joined by spherical joints, the first pinned at
    # its left end, released horizontally; 100 steps of 10 ms
    h, k = 0.01, 1e6
    scene = mochi.Scene.create()
    bodies = [scene.create_rigid_actor(mass=1, inertia=[1e-4, 1e-3, 1e-3], position=[(i + 0.5) * 0.1, 0, 0])
              for i in range(3)]
    pin = scene.create_rigid_pivot_position_constraint(actor=bodies[0], local_pos=[-0.05, 0, 0],
                                                       stiffness=k, damping=100)
    joints = [scene.create_rigid_spherical_joint_constraint(actor_a=a, actor_b=b, local_pos_a=[0.05, 0, 0],
                                                            local_pos_b=[-0.05, 0, 0], stiffness=k, damping=100)
              for a, b in zip(bodies, bodies[1:])]
    pin.register_query(mochi.QueryType.ConstraintForce)

    def energy():  # kinetic + gravity + the constraints' springs, ½ k |g|²
        return (sum(b.get_kinetic_energy() + b.get_mass() * G * b.get_position()[1] for b in bodies)
                + sum(0.5 * k * np.dot(c.get_deviation(), c.get_deviation()) for c in [pin] + joints))

    energies = [energy()]
    for _ in range(100):
        momentum = sum(b.get_mass() * b.get_linear_velocity() for b in bodies)
        scene.step(h)
        change = sum(b.get_mass() * b.get_linear_velocity() for b in bodies) - momentum
        # backward Euler's momentum balance of the whole chain: the joints'
        # forces cancel in pairs, so Δp/h = F_pin + m_total g exactly at the
        # converged step. Newton converges quadratically: measured residual
        # 4e-11 N; 1e-6 N is far below the 3·9.81 N in play
        np.testing.assert_allclose(change / h, pin.get_force()[:3] + [0, -3 * G, 0], atol=1e-6)
        energies.append(energy())
        # the stiff joints hold: a deviation of force / k, at most ~60 N / 1e6 N/m
        assert max(np.linalg.norm(c.get_deviation()) for c in [pin] + joints) < 1e-4
    # backward Euler and the joint damping only dissipate: the energy falls at
    # every step (measured: by at least 7e-3 J; 1e-12 J is round-off margin)
    assert max(np.diff(energies)) < 1e-12
    # the chain swung down: its tip is below the pin by half the chain's length or more
    assert bodies[2].get_position()[1] < -0.15
    assert scene.get_stats().steps == 100 and scene.get_stats().pattern_builds == 1


def test_a_failed_step_retries_itself_as_substeps_when_asked():
    # six 1 kg bodies on stiff spherical joints (1e6 N/m), pinned at the left
    # end, released horizontally at dt = 0.05, with the reference page's
    # Gauss-Newton constraint Hessian and Newton capped at 30 iterations: the
    # step fails whole (it would need 38), and succeeds as two sub-steps of
    # 0.025 (6 and 13)
    def chain(params=None):
        params = params or mochi.SceneParams()
        params.newton.constraint_hessian = mochi.ConstraintHessian.GaussNewton
        params.newton.max_iterations = 30
        scene = mochi.Scene.create(params)
        bodies = [scene.create_rigid_actor(mass=1, inertia=[1e-4, 1e-3, 1e-3], position=[(i + 0.5) * 0.1, 0, 0])
                  for i in range(6)]
        scene.create_rigid_pivot_position_constraint(actor=bodies[0], local_pos=[-0.05, 0, 0], stiffness=1e6)
        for a, b in zip(bodies, bodies[1:]):
            scene.create_rigid_spherical_joint_constraint(actor_a=a, actor_b=b, local_pos_a=[0.05, 0, 0],
                                                          local_pos_b=[-0.05, 0, 0], stiffness=1e6)
        return scene, bodies

    off, off_bodies = chain()  # the default: off
    assert off.get_params().substeps.max_substeps == 1
    with pytest.raises(mochi.Error) as info:
        off.step(0.05)
    assert info.value.code == mochi.ErrorCode.NewtonFailed and "sub-step" not in info.value.message
    assert off.get_time() == 0 and off_bodies[5].get_position().tolist() == [0.55, 0, 0]

    params = mochi.SceneParams()
    params.substeps.max_substeps = 8  # nested params by reference
    on, on_bodies = chain(params=params)
    on.step(0.05)
    stats = on.get_stats()
    assert stats.substeps == 2 and stats.substepped_steps == 1 and stats.steps == 1
    assert on.get_time() == 0.05

    # the same as two steps of 0.025 taken by hand, bit for bit
    manual, manual_bodies = chain()
    manual.step(0.025)
    manual.step(0.025)
    for a, b in zip(on_bodies, manual_bodies):
        assert a.get_position().tolist() == b.get_position().tolist()
        assert a.get_linear_velocity().tolist() == b.get_linear_velocity().tolist()

    # capped at 1 again, between steps; a cap that is not a power of two is refused
    on.set_substep_params(max_substeps=1)
    assert on.get_params().substeps.max_substeps == 1
    with pytest.raises(mochi.Error) as info:
        on.set_substep_params(mochi.SubstepParams(max_substeps=3))
    assert info.value.code == mochi.ErrorCode.InvalidArgument
    assert "SubstepParams.maxSubsteps must be a power of two in [1, kMaxSubsteps = 4096]" in info.value.message
    with pytest.raises(mochi.Error, match="SceneParams.substeps.maxSubsteps .* got 0"):
        mochi.Scene.create(substeps=mochi.SubstepParams(max_substeps=0))


def test_deformable_block_hanging_from_pins():
    # a 0.1 m soft cube (1 kg) hanging from its four top corners
    mesh = mochi.make_tet_box(origin=[0, 0, 0], size=[0.1, 0.1, 0.1], cells=[2, 2, 2])
    assert mesh.nodes.shape == (27, 3) and mesh.tetrahedra.shape == (48, 4)
    assert mesh.tetrahedra.dtype.kind == "i"
    assert all(mochi.signed_volume(mesh, t) > 0 for t in range(48))
    scene = mochi.Scene.create()
    block = scene.create_deformable_actor(nodes=mesh.nodes, tetrahedra=mesh.tetrahedra, density=1000,
                                          young_modulus=1e5, poisson_ratio=0.3)
    assert block.get_total_mass() == pytest.approx(1.0, rel=1e-12)
    assert block.get_num_nodes() == 27 and block.get_num_dofs() == 81
    top = [i for i, x in enumerate(block.get_node_reference_positions()) if x[1] == pytest.approx(0.1)
           and x[0] in (0, 0.1) and x[2] in (0, 0.1)]
    assert len(top) == 4
    pins = [scene.create_deformable_node_position_constraint(actor=block, node_index=i,
                                                             position=block.get_node_position(i),
                                                             stiffness=1e5, damping=10) for i in top]
    scene.register_query(mochi.QueryType.ConstraintForce)
    for _ in range(100):
        scene.step(0.01)
    x = block.get_node_positions()
    assert isinstance(x, np.ndarray) and x.shape == (27, 3)
    np.testing.assert_allclose(x, block.get_node_reference_positions() + block.get_node_displacements(),
                               atol=1e-15)  # identity transform: x = X + u
    # it sags: the bottom face moved down, the pinned corners barely (m g / 4k ≈ 25 µm)
    assert x[:, 1].min() < -1e-3
    for i in top:
        assert abs(block.get_node_displacement(i)[1]) < 1e-4
    # the pins carry the weight: after 1 s of backward-Euler damping at ωh ≈ 1
    # the block is at rest (measured: 7e-10 relative); 1e-6 allows for the
    # Newton tolerance and nothing more
    total = sum(p.get_force()[1] for p in pins)
    assert total == pytest.approx(G * 1.0, rel=1e-6)
    assert block.get_elastic_energy() > 0
    assert block.count_inverted_tetrahedra() == 0
    assert block.get_node_velocities().shape == (27, 3)
    assert block.get_node_masses().sum() == pytest.approx(1.0, rel=1e-12)


def test_shell_from_a_triangle_grid():
    mesh = mochi.make_triangle_grid(origin=[0, 0, 0], size_x=1, size_z=1, cells_x=4, cells_z=4)
    assert mesh.nodes.shape == (25, 3) and mesh.triangles.shape == (32, 3)
    hinges = mochi.make_hinges(mesh)
    assert hinges.shape == (40, 4)  # interior edges of a 4 × 4 grid: 2·4·3 + 16 diagonals
    scene = mochi.Scene.create()
    cloth = scene.create_deformable_actor(nodes=mesh.nodes, triangles=mesh.triangles, thickness=1e-3,
                                          young_modulus=1e6, density=200)
    assert cloth.get_num_triangles() == 32 and cloth.get_num_hinges() == 40
    np.testing.assert_array_equal(cloth.get_triangles(), mesh.triangles)
    for corner in (0, 4):
        scene.create_deformable_node_position_constraint(actor=cloth, node_index=corner,
                                                         position=cloth.get_node_position(corner), stiffness=1e4)
    for _ in range(20):
        scene.step(0.01)
    assert cloth.get_node_positions()[:, 1].min() < -0.01  # it falls away from its pins


def test_membrane_models_a_sheet_compressed_and_stretched():
    # a flat 4 x 4 sheet scaled in its plane: compressed, the tension field
    # stores nothing where StVK does; stretched, the two agree
    mesh = mochi.make_triangle_grid(origin=[0, 0, 0], size_x=1, size_z=1, cells_x=4, cells_z=4)
    energies = {}
    for scale in (0.9, 1.1):
        for model in (mochi.MembraneModel.StVK, mochi.MembraneModel.TensionField):
            scene = mochi.Scene.create()
            sheet = scene.create_deformable_actor(nodes=mesh.nodes, triangles=mesh.triangles, thickness=1e-3,
                                                  young_modulus=1e6, membrane=model,
                                                  initial_displacements=(scale - 1) * mesh.nodes)
            energies[scale, model] = sheet.get_elastic_energy()
    assert energies[0.9, mochi.MembraneModel.StVK] > 1
    assert energies[0.9, mochi.MembraneModel.TensionField] < 1e-20  # (the hinges: round-off of 0)
    assert energies[1.1, mochi.MembraneModel.StVK] > 1
    assert energies[1.1, mochi.MembraneModel.TensionField] == pytest.approx(energies[1.1, mochi.MembraneModel.StVK], rel=1e-14)
    assert str(mochi.DeformableActorParams().membrane) == "MembraneModel.StVK"

def test_rod_hanging_from_a_pin():
    # a 0.5 m steel-like rod of 10 elements, hanging down from its top node
    nodes = [[0, -0.05 * i, 0] for i in range(11)]
    scene = mochi.Scene.create()
    rod = scene.create_rod_actor(nodes=nodes, radius=0.005, young_modulus=1e9, density=1000)
    assert rod.get_num_elements() == 10 and rod.get_num_dofs() == 44
    assert rod.get_node_dof_stride() == 4
    assert rod.get_node_position_dofs(2).tolist() == [8, 9, 10]
    mass = 1000 * math.pi * 0.005 ** 2 * 0.5
    assert rod.get_total_mass() == pytest.approx(mass, rel=1e-12)
    stiffness = rod.get_stiffness()
    assert stiffness.stretch == pytest.approx(1e9 * math.pi * 0.005 ** 2, rel=1e-12)
    pin = scene.create_deformable_node_position_constraint(actor=rod, node_index=0, position=[0, 0, 0],
                                                           stiffness=1e5)
    pin.register_query(mochi.QueryType.ConstraintForce)
    for _ in range(100):
        scene.step(0.01)
    assert rod.get_node_positions().shape == (11, 3)
    assert rod.get_twists().shape == (11,)
    frame = rod.get_material_frame(0)
    np.testing.assert_allclose(frame.T @ frame, np.eye(3), atol=1e-12)  # orthonormal
    assert rod.get_material_frame_jacobian(0).shape == (3, 8)
    # a straight rod hanging along gravity does not bend or twist: its strain
    # stays the (zero) rest strain, to round-off
    np.testing.assert_allclose(rod.get_strain(5), rod.get_rest_strain(5), atol=1e-12)
    # and the pin carries its weight (at rest after 1 s: measured 3e-14 relative;
    # 1e-9 allows for the Newton tolerance)
    assert pin.get_force()[1] == pytest.approx(mass * G, rel=1e-9)


def test_rod_clamped_to_a_rigid_body():
    scene = mochi.Scene.create()
    hub = scene.create_rigid_actor(mass=1, position=[0, 0, 0])
    rod = scene.create_rod_actor(nodes=[[0.1 * i, 0, 0] for i in range(6)], radius=0.01)
    scene.create_rigid_pivot_to_rigid_target_constraint(actor=hub, stiffness=1e7)
    scene.create_rigid_pivot_rotation_constraint(actor=hub, stiffness=1e7)
    scene.create_deformable_node_to_rigid_constraint(deformable_actor=rod, rigid_actor=hub,
                                                     deformable_node_index=0, stiffness=1e6)
    clamp = scene.create_rod_element_rotation_to_rigid_constraint(rigid_actor=hub, rod_actor=rod,
                                                                  element_index=0, stiffness=1e4)
    assert clamp.get_num_dofs() == 11 and clamp.get_element_index() == 0
    # the target starts as the creation-time rotation of the element's material
    # frame relative to the hub (identity): R̂ = R_e = [d₁ d₂ t], t along x
    frame = rod.get_material_frame(0)
    np.testing.assert_allclose(frame[:, 2], [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(mochi.exp_matrix(mochi.log(clamp.get_target_rotation())), frame, atol=1e-12)
    np.testing.assert_allclose(clamp.get_deviation(), [0, 0, 0], atol=1e-12)
    for _ in range(10):
        scene.step(0.01)
    tip = rod.get_node_position(5)
    # a clamped cantilever sags, but far less than a free fall of 0.1 s (4.9 cm)
    assert -0.049 < tip[1] < 0


def test_articulated_pendulum_mass_matrix_and_motion():
    # one uniform rod (m, L) on a revolute joint about z at the origin, released horizontally
    m, length = 1.0, 0.5
    izz = m * length ** 2 / 12
    scene = mochi.Scene.create()
    link = mochi.ArticulatedLinkParams(parent=-1, joint=mochi.JointType.Revolute, axis=[0, 0, 1], mass=m,
                                       inertia=[1e-4, izz, izz], center_of_mass=[length / 2, 0, 0])
    arm = scene.create_articulated_actor(
        mochi.ArticulatedActorParams(links=[link], block_solve=mochi.ArticulatedBlockSolve.Tree))
    assert arm.get_num_links() == 1 and arm.get_num_dofs() == 1 and not arm.is_floating_base()
    assert arm.get_joint_type(0) == mochi.JointType.Revolute and mochi.joint_dofs(mochi.JointType.Free) == 6
    # M = I_zz + m (L/2)² = m L²/3 (parallel axis), to round-off
    mass_matrix = arm.compute_mass_matrix()
    assert mass_matrix.shape == (1, 1)
    assert mass_matrix[0, 0] == pytest.approx(m * length ** 2 / 3, rel=1e-12)
    # bias = -τ_g = m g L/2 at rest and horizontal
    assert arm.compute_bias_forces([0, -G, 0])[0] == pytest.approx(m * G * length / 2, rel=1e-12)
    for _ in range(100):
        scene.step(1e-3)
    # after 0.1 s the angle is close to the small-time expansion θ ≈ -½ α t²,
    # α = m g (L/2) / (m L²/3) = 3g/(2L); the cos θ drop over 0.1 s is < 0.1 %
    # and backward Euler's first-order error is h/t = 1 %: allow 2 %
    theta = arm.get_joint_positions()[0]
    assert theta == pytest.approx(-0.5 * 3 * G / (2 * length) * 0.1 ** 2, rel=0.02)
    assert arm.get_joint_coordinate(0) == theta
    assert arm.get_joint_velocities().shape == (1,)
    com = arm.get_link_center_of_mass(0)
    np.testing.assert_allclose(com, [length / 2 * math.cos(theta), length / 2 * math.sin(theta), 0], atol=1e-12)
    # solved by the tree recursion (the default); the dense block steps the same motion
    assert arm.get_block_solve() == mochi.ArticulatedBlockSolve.Tree and arm.is_solved_on_tree()
    # a link falling from rest: the exact Hessian stays positive definite, nothing modified
    assert arm.get_num_modified_tree_factorizations() == 0
    assert arm.get_num_gauss_newton_tree_factorizations() == 0
    dense_scene = mochi.Scene.create()
    dense = dense_scene.create_articulated_actor(mochi.ArticulatedActorParams(
        links=[link], block_solve=mochi.ArticulatedBlockSolve.Dense))
    assert dense.get_block_solve() == mochi.ArticulatedBlockSolve.Dense
    for _ in range(100):
        dense_scene.step(1e-3)
    assert not dense.is_solved_on_tree()
    assert dense.get_joint_positions()[0] == pytest.approx(theta, abs=1e-12)
    # from the constant-velocity prediction instead of the extrapolated
    # velocity: the same motion to the Newton tolerance (1e-6 m/s x 1 ms per
    # step, 100 steps)
    plain_scene = mochi.Scene.create()
    params = mochi.ArticulatedActorParams(links=[link], extrapolate_first_iterate=False)
    assert params.extrapolate_first_iterate is False
    plain = plain_scene.create_articulated_actor(params)
    for _ in range(100):
        plain_scene.step(1e-3)
    assert plain.get_joint_positions()[0] == pytest.approx(theta, abs=1e-7)


def test_an_articulated_link_holds_a_rigid_body():
    # a two-link revolute arm (rods of L = 0.5 m, 1 kg) released along +x
    # holding a 0.5 kg ball at its tip by a stiff spherical joint on link 1
    length = 0.5
    scene = mochi.Scene.create(gravity=[0, -G, 0])
    links = [mochi.ArticulatedLinkParams(parent=i - 1, joint=mochi.JointType.Revolute, axis=[0, 0, 1],
                                         parent_to_joint_position=[0 if i == 0 else length, 0, 0],
                                         center_of_mass=[length / 2, 0, 0]) for i in range(2)]
    arm = scene.create_articulated_actor(links=links)
    ball = scene.create_rigid_actor(mass=0.5, position=[2 * length, 0, 0])
    joint = scene.create_rigid_spherical_joint_constraint(actor_a=arm, link_a=1, local_pos_a=[length, 0, 0],
                                                          actor_b=ball, stiffness=1e7)
    # the constraint's DoFs on the arm are both joints (the path to link 1)
    assert list(joint.get_dof_indices_for_actor(0)) == [arm.get_dof_offset(), arm.get_dof_offset() + 1]
    for _ in range(50):
        scene.step(0.01)
    # the ball stays at the tip: the joint's stretch under the ball's load
    # (~m g/k plus the swing's centripetal load) is below 1e-5 m
    assert np.linalg.norm(joint.get_deviation()) < 1e-5
    assert ball.get_position()[1] < -0.5  # it swung down
    # the coupling through the tree's Schur complement: the ball's six DoFs
    assert arm.is_solved_on_tree()
    assert arm.get_num_coupled_constraints() == 1 and arm.get_num_coupled_dofs() == 6


def test_articulated_targets_and_ranges_drive_a_spherical_joint():
    scene = mochi.Scene.create(gravity=[0, 0, 0])
    ball = scene.create_articulated_actor(links=[mochi.ArticulatedLinkParams(
        parent=-1, joint=mochi.JointType.Spherical, center_of_mass=[0.5, 0, 0])])
    target = scene.create_articulated_3d_rotation_target_constraint(
        actor=ball, joint_index=0, target_from_current=False, rotation=mochi.exp([0, 0, 0.2]),
        stiffness=100, damping=5)
    limit = scene.create_articulated_3d_rotation_range_constraint(
        actor=ball, joint_index=0, lower_limits=[-1, -1, -0.1], upper_limits=[1, 1, 0.1], stiffness=1e4)
    for _ in range(300):
        scene.step(0.01)
    # the target pulls toward 0.2 rad about z, the range stops it near 0.1: the
    # equilibrium 100 (0.2 - φ) = 1e4 (φ - 0.1) gives φ = 0.1 + 0.1/101. At rest
    # after 3 s (measured: exact to 1e-14); 1e-9 allows for the Newton tolerance
    phi = target.get_joint_rotation_vector()
    assert phi[2] == pytest.approx(0.1 + 0.1 / 101, rel=1e-9)
    assert limit.get_deviation()[2] == pytest.approx(0.1 / 101, rel=1e-9)
    np.testing.assert_allclose(ball.get_joint_positions(), phi, atol=1e-12)


def test_every_linear_solver_gives_the_same_motion():
    def run(solver):
        scene = mochi.Scene.create(linear_solver=solver, pcg=mochi.PcgParams(
            preconditioner=mochi.PcgPreconditioner.Jacobi, relative_tolerance=1e-12))
        a = scene.create_rigid_actor(position=[0, 0, 0])
        b = scene.create_rigid_actor(position=[1, 0, 0])
        scene.create_rigid_pivot_position_constraint(actor=a, local_pos=[-0.5, 0, 0], position=[-0.5, 0, 0],
                                                     stiffness=1e6)
        scene.create_rigid_spherical_joint_constraint(actor_a=a, actor_b=b, local_pos_a=[0.5, 0, 0],
                                                      local_pos_b=[-0.5, 0, 0], stiffness=1e6)
        for _ in range(10):
            scene.step(0.01)
        assert scene.get_params().linear_solver == solver
        return scene, b.get_position()

    solvers = mochi.available_linear_solvers()
    assert mochi.LinearSolverType.Cholmod in solvers and mochi.LinearSolverType.Dense in solvers
    assert mochi.LinearSolverType.PetscMumps in solvers  # Debian's PETSc has MUMPS
    reference_scene, reference = run(mochi.LinearSolverType.Dense)
    for solver in solvers:
        scene, position = run(solver)
        assert scene.get_stats().linear_solver  # what really ran, as the backend reports it
        # the same Newton iterates up to the linear solves' accuracy (direct: round-off;
        # PCG: rtol 1e-12), amplified by 10 steps of Newton: 1e-9 m of a 1 m swing
        np.testing.assert_allclose(position, reference, atol=1e-9)
    # switching between steps keeps the state and changes what runs
    reference_scene.set_linear_solver(mochi.LinearSolverType.Cholmod)
    reference_scene.step(0.01)
    assert "CHOLMOD" in reference_scene.get_stats().linear_solver
    assert mochi.resolve_linear_solver_type(mochi.LinearSolverType.Auto, 12) == mochi.LinearSolverType.Dense
    assert mochi.resolve_linear_solver_type(mochi.LinearSolverType.Auto, 97) == mochi.LinearSolverType.Cholmod
    assert mochi.DENSE_SOLVER_MAX_SIZE == 96


def test_standalone_linear_solver():
    # A = [[4, 1], [1, 3]] by its upper triangle
    a = mochi.SparseSymmetricMatrix(size=2, col_start=[0, 1, 3], row_index=[0, 0, 1], values=[4.0, 1.0, 3.0],
                                    pattern_version=1)
    assert a.num_nonzeros() == 3
    for solver_type in [mochi.LinearSolverType.Dense, mochi.LinearSolverType.Cholmod, mochi.LinearSolverType.PetscMumps]:
        solver = mochi.create_linear_solver(solver_type)
        assert solver.get_type() == solver_type
        result, _ = solver.solve([1.0, 2.0])
        assert result.status == mochi.LinearSolveStatus.InvalidState  # out of order: no factorization
        assert solver.analyze(a).ok() and solver.factorize(a).ok()
        result, x = solver.solve([1.0, 2.0])
        assert result.ok()
        np.testing.assert_allclose(x, np.linalg.solve([[4, 1], [1, 3]], [1, 2]), rtol=1e-14)


def test_so3_maps():
    phi = np.array([0.1, -0.2, 0.3])
    q = mochi.exp(phi)
    assert q.shape == (4,) and np.linalg.norm(q) == pytest.approx(1)
    np.testing.assert_allclose(mochi.log(q), phi, atol=1e-15)
    np.testing.assert_allclose(mochi.log(mochi.exp_matrix(phi)), phi, atol=1e-15)
    np.testing.assert_allclose(mochi.hat(phi) @ [1, 2, 3], np.cross(phi, [1, 2, 3]), atol=1e-15)
    np.testing.assert_allclose(mochi.left_jacobian(phi) @ mochi.left_jacobian_inverse(phi), np.eye(3),
                               atol=1e-14)
    np.testing.assert_allclose(mochi.right_jacobian(phi) @ mochi.right_jacobian_inverse(phi), np.eye(3),
                               atol=1e-14)
    # quaternions are [w, x, y, z]: a half turn about z
    np.testing.assert_allclose(mochi.exp([0, 0, math.pi]), [0, 0, 0, 1], atol=1e-15)


def test_vtk_output(tmp_path):
    mesh = mochi.make_tet_box(origin=[0, 0, 0], size=[1, 1, 1], cells=[1, 1, 1])
    path = os.fspath(tmp_path / "box_0000.vtu")
    speed = mochi.VtkPointData(name="speed", components=1, values=np.arange(8.0))
    mochi.write_vtu(path, mesh.nodes, tetrahedra=mesh.tetrahedra, point_data=[speed])
    text = open(path).read()
    assert 'NumberOfPoints="8"' in text and 'NumberOfCells="6"' in text and 'Name="speed"' in text
    series = mochi.VtkSeries(os.fspath(tmp_path / "box.pvd"))
    series.add_frame(0.0, "box_0000.vtu")
    assert series.get_num_frames() == 1 and os.path.exists(series.get_path())
    scene = mochi.Scene.create()
    rod = scene.create_rod_actor(nodes=[[0, 0, 0], [1, 0, 0], [2, 0, 0]])
    mochi.write_rods_vtu(os.fspath(tmp_path / "rod.vtu"), [rod])
    assert 'Name="twist"' in open(tmp_path / "rod.vtu").read()
    with pytest.raises(mochi.Error) as e:
        mochi.write_vtu(path, mesh.nodes, point_data=[mochi.VtkPointData(name="x", values=[1.0])])
    assert e.value.code == mochi.ErrorCode.InvalidArgument


def test_params_objects():
    p = mochi.RigidSphericalJointConstraintParams(local_pos_a=(1, 2, 3), stiffness=1e6)
    assert isinstance(p.local_pos_a, np.ndarray) and p.local_pos_a.tolist() == [1, 2, 3]
    p.local_pos_a[1] = 5  # vector fields are views into the struct
    assert p.local_pos_a.tolist() == [1, 5, 3]
    assert repr(p) == ("RigidSphericalJointConstraintParams(actor_a=ActorHandle(), actor_b=ActorHandle(), link_a=-1, link_b=-1, "
                       "local_pos_a=[1.0, 5.0, 3.0], local_pos_b=[0.0, 0.0, 0.0], stiffness=1000000.0, "
                       "damping=0.0, saturation=-1.0)")
    import copy
    q = copy.copy(p)
    q.stiffness = 1
    assert p.stiffness == 1e6
    s = mochi.SceneParams(integrator=mochi.IntegratorType.Bdf2)
    s.newton.max_iterations = 7  # nested structs by reference
    assert s.newton.max_iterations == 7 and "IntegratorType.Bdf2" in repr(s)
    scene = mochi.Scene.create(s)
    assert scene.get_params().newton.max_iterations == 7
    assert scene.get_params().integrator == mochi.IntegratorType.Bdf2
    body = scene.create_rigid_actor()
    assert mochi.RigidPivotPositionConstraintParams(actor=body).actor == body.get_handle()
    h = body.get_handle()
    assert {h: 1}[mochi.ActorHandle(index=h.index, generation=h.generation, scene=h.scene)] == 1
    assert h.scene == scene.get_id() and h.scene > 0
    assert mochi.ActorHandle().is_null() and repr(mochi.ActorHandle()) == "ActorHandle()"


def test_threads_and_reused_factorizations():
    # assembly threads: results bit-identical for any count
    runs = {}
    for threads in (1, 2):
        scene, beam = sagging_beam(num_threads=threads, linear_solver=mochi.LinearSolverType.Cholmod)
        assert scene.get_num_threads() == threads
        assert scene.get_params().num_threads == threads
        for _ in range(3):
            scene.step(1 / 60)
        runs[threads] = beam.get_node_positions()
    assert np.array_equal(runs[1], runs[2])
    scene.set_num_threads(0)
    assert scene.get_num_threads() >= 1
    with pytest.raises(mochi.Error, match="numThreads"):
        scene.set_num_threads(-1)
    # above kMaxThreads: refused, nothing changed (2**31 - 1 raised MemoryError
    # and kept the count); 1000 at creation aborted under a 4 GB address limit
    scene.set_num_threads(2)
    before = beam.get_node_positions()
    with pytest.raises(mochi.Error, match=r"numThreads must be in \[0, kMaxThreads = 256\].*got 2147483647"):
        scene.set_num_threads(2**31 - 1)
    assert scene.get_num_threads() == 2 and scene.get_params().num_threads == 2
    assert np.array_equal(beam.get_node_positions(), before)
    scene.step(1 / 60)
    with pytest.raises(mochi.Error, match=r"SceneParams.numThreads must be in \[0, kMaxThreads = 256\].*got 1000"):
        sagging_beam(num_threads=1000)

    # reused factorizations: fewer factorizations, full Newton's state within its tolerance
    stats = {}
    for reuse in (False, True, "fixed"):
        # dense: at 624 DoFs its n³/3 factorization is worth ~10 CG iterations;
        # "fixed": every reused-factor CG to factor_reuse_tolerance
        newton_params = mochi.NewtonParams(reuse_factorization=bool(reuse),
                                           reuse_forcing_terms=reuse is True)
        assert newton_params.reuse_forcing_terms == (reuse is True)
        scene, beam = sagging_beam(linear_solver=mochi.LinearSolverType.Dense,
                                    newton=newton_params)
        factorizations = reused = newton = 0
        for _ in range(5):
            scene.step(1 / 60)
            s = scene.get_stats()
            factorizations += s.factorizations
            reused += s.reused_factor_solves
            newton += s.newton_iterations
        stats[reuse] = (factorizations, reused, newton, beam.get_node_positions())
    assert stats[False][0] == stats[False][2] and stats[False][1] == 0
    assert stats[True][1] > 0 and stats[True][0] < stats[False][0]
    # 5 steps of the Newton tolerance (1e-6 m/s) times dt
    assert np.abs(stats[True][3] - stats[False][3]).max() <= 5 * 1e-6 / 60
    assert stats["fixed"][1] > 0
    assert np.abs(stats["fixed"][3] - stats[False][3]).max() <= 5 * 1e-6 / 60
    with pytest.raises(mochi.Error, match="factorReuseTolerance"):
        mochi.Scene.create(newton=mochi.NewtonParams(factor_reuse_tolerance=0))

    # the single-precision copy of a CHOLMOD factor: the same states within the tolerance
    positions = {}
    for single in (True, False):
        newton_params = mochi.NewtonParams(single_precision_reused_factor=single)
        assert newton_params.single_precision_reused_factor == single
        scene, beam = sagging_beam(linear_solver=mochi.LinearSolverType.Cholmod,
                                    newton=newton_params)
        for _ in range(5):
            scene.step(1 / 60)
            if not single:
                assert scene.get_stats().single_precision_solves == 0
        positions[single] = beam.get_node_positions()
    assert np.abs(positions[True] - positions[False]).max() <= 5 * 1e-6 / 60
