"""The compound pendulum of tests/scene/pendulum_test.cpp, built and stepped
from Python: a rigid body hung from a RigidPivotPosition swings at the
analytic period 2π sqrt((I_z + m a²)/(m g a)), and hangs at rest with the
static deviation m g / k. Same scene, step and tolerances as the C++ test."""
import math

import numpy as np
import pytest

import mochi

MASS = 2.0
ARM = 0.5  # pivot to centre of mass [m]
INERTIA = [0.1, 0.2, 0.3]
STIFFNESS = 1e8
DT = 1e-3
G = 9.81


def make_pendulum(angle, integrator):
    """Pivot at the world origin, body rotated by `angle` about z."""
    scene = mochi.Scene.create(integrator=integrator, newton=mochi.NewtonParams(velocity_tolerance=1e-9))
    rotation = mochi.exp([0, 0, angle])
    local_pivot = np.array([0, ARM, 0])
    body = scene.create_rigid_actor(mass=MASS, inertia=INERTIA, rotation=rotation,
                                    position=-(mochi.exp_matrix([0, 0, angle]) @ local_pivot))
    pivot = scene.create_rigid_pivot_position_constraint(actor=body, local_pos=local_pivot,
                                                         position=[0, 0, 0], stiffness=STIFFNESS)
    return scene, body, pivot


@pytest.mark.parametrize("integrator", [mochi.IntegratorType.BackwardEuler, mochi.IntegratorType.Bdf2])
def test_compound_pendulum_swings_at_its_analytic_period(integrator):
    expected = 2 * math.pi * math.sqrt((INERTIA[2] + MASS * ARM * ARM) / (MASS * G * ARM))
    scene, body, _ = make_pendulum(0.02, integrator)
    # upward zero crossings of the swing angle, linearly interpolated
    crossings = []
    previous = mochi.log(body.get_rotation())[2]
    for _ in range(int(3.5 * expected / DT)):
        scene.step(DT)
        angle = mochi.log(body.get_rotation())[2]
        if previous < 0 <= angle:
            crossings.append(scene.get_time() - DT * angle / (angle - previous))
        previous = angle
    assert len(crossings) >= 3
    measured = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    # the C++ test's tolerance: 1 % of the period (small-angle swing, 0.02 rad:
    # the amplitude correction θ₀²/16 is 2.5e-5; the integrators' period error
    # at dt = 1e-3 is far below 1 %)
    assert abs(measured - expected) <= 0.01 * expected, (measured, expected)


def test_a_body_hanging_at_rest_deviates_by_m_g_over_k():
    scene, body, pivot = make_pendulum(0, mochi.IntegratorType.BackwardEuler)
    for _ in range(50):
        scene.step(DT)
    deviation = pivot.get_deviation()
    expected = MASS * G / STIFFNESS
    assert np.linalg.norm(deviation) > 0
    # the C++ test's tolerance: 1 % (after 50 steps the transient of the
    # release is damped by backward Euler to well below that)
    assert abs(np.linalg.norm(deviation) - expected) <= 0.01 * expected
    # the body hangs below the pivot: the pivot point sits below its target
    assert deviation[1] < 0
