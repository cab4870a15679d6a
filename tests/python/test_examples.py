"""The Python examples run and do what they say: tour.py checks every call
itself (exit 0), plot_tour.py writes its PNG."""
import math
import os
import subprocess
import sys

import pytest

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python")


def run(script, *args):
    return subprocess.run([sys.executable, os.path.join(EXAMPLES, script), *args], capture_output=True,
                          text=True, timeout=300)


def test_tour_runs_every_call_as_documented():
    result = run("tour.py")
    assert result.returncode == 0, result.stdout + result.stderr
    assert "FAILED" not in result.stdout
    assert "tour.py: every call returned what was expected" in result.stdout
    # one line per section of the reference page's runtime interface
    for section in ["1. scene", "2. constraints", "3. handles and introspection", "4. parameters",
                    "5. targets", "6. methods that do not apply", "7. limits", "8. force queries",
                    "9. destruction"]:
        assert section in result.stdout


def test_plot_tour_writes_a_png(tmp_path):
    result = run("plot_tour.py", os.fspath(tmp_path / "out"))
    assert result.returncode == 0, result.stdout + result.stderr
    png = tmp_path / "out" / "plot_tour.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # the printed final state (2 s, both settled): static equilibria
    line = result.stdout.splitlines()[0]
    swing = float(line.split("arm swing ")[1].split(" rad")[0])
    violation = float(line.split("range violation ")[1].split(" rad")[0])
    wrist = float(line.split("wrist ")[1].split(" rad")[0])
    # the arm (1 kg, centre 0.5 m from the joint) rests on the -0.5 rad limit,
    # which gives way by its torque over k = 1e3 N·m/rad: m g (L/2) cos θ / k.
    # 1e-4 rad: the base's own compliant holders (k = 1e4 .. 1e5) shift it by less
    assert abs(swing + 0.5 + violation) < 1e-6  # g_z is the overshoot past the limit (printed to 1e-6)
    assert violation == pytest.approx(1.0 * 9.81 * 0.5 * math.cos(swing) / 1e3, abs=1e-4)
    # the wrist: target spring 50 (0.6 - θ) = range spring 1e3 (θ - 0.4) + gravity
    # torque 0.5 · 9.81 · 0.25 cos θ, solved for θ; 1e-5 rad ≈ the solver tolerance's reach
    expected = (50 * 0.6 + 1e3 * 0.4 - 0.5 * 9.81 * 0.25 * math.cos(wrist)) / 1050
    assert wrist == pytest.approx(expected, abs=1e-5)


def test_arm_gripper_writes_vtk_and_a_plot(tmp_path):
    out = tmp_path / "out"
    result = run("arm_gripper.py", os.fspath(out))
    assert result.returncode == 0, result.stdout + result.stderr
    assert (out / "arm_gripper.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    for name in ("arm", "gripper", "block", "rod"):
        pvd = (out / f"arm_gripper_{name}.pvd").read_text()
        assert pvd.count("<DataSet") == 41  # t = 0 and every 5th of 200 steps
        assert (out / f"{name}_0040.vtu").exists()
    line = result.stdout.splitlines()[-1]

    def value(label, unit):
        return float(line.split(label + " ")[1].split(" " + unit)[0])

    # the yaw axis is vertical: gravity has no torque about it, and the target
    # (k = 2e3 N·m/rad, d = 50) has settled 1 s after its ramp (measured 1.2e-5 off)
    assert value("yaw", "rad") == pytest.approx(1.0, abs=1e-3)
    # the block hangs still from the gripper: the holds' vertical force is its
    # weight (measured within 2e-4 relative at t = 2 s)
    assert value("hold lift", "N") == pytest.approx(value("block weight", "N"), rel=1e-2)
    # the weld on the articulated link stretches by the load over k = 1e6 N/m
    assert value("weld deviation", "m") < 1e-4
    # links coupled to other actors: the tree still solves the arm (the
    # couplings through its Schur complement)
    assert "tree solve True" in line


def test_contact_scenes_draw_their_output(tmp_path):
    result = run(os.path.join("..", "contact", "contact_scenes.py"), os.fspath(tmp_path / "out"))
    assert result.returncode == 0, result.stdout + result.stderr
    assert (tmp_path / "out" / "contact_scenes.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    lines = result.stdout.splitlines()
    # the paddle's speed, within 2 %, once it pushes the box
    assert float(lines[0].split("box speed ")[1].split(" m/s")[0]) == pytest.approx(0.5, rel=0.02)
    # the ball never reaches the ground, and bounces back up
    ball = lines[1]
    assert float(ball.split("lowest node ")[1].split(" m")[0]) > 0
    assert float(ball.split("bounce peak ")[1].split(" m")[0]) > 0.9  # scene 3: 0.93 (docs/contact.md)
    # the stack rests: below the 1e-4 m of docs/contact.md's bar
    assert float(lines[2].split("drift ")[1].split(" m")[0]) < 1e-4
    # the cloth lies on the sphere: never through it nor the ground, and its
    # middle within its thickness and the barrier's layer of the sphere
    # (1.8 mm measured)
    clearance = float(lines[3].split("clearance ")[1].split(" m")[0])
    assert 0 < clearance < 5e-3
