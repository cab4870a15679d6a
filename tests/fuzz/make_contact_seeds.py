#!/usr/bin/env python3
"""Writes the named seeds of tests/fuzz/corpus/contact/ from the byte layout
that fuzz_contact.cpp reads (each value one byte, read in the order written
here; Input::Int(n) is byte % n; Input::Real() a table value for a byte
below 240: 0 is 0, 1 is 1). The scenes: a box dropped on the ground and
left to rest, a kinematic paddle pushing a box, a rod and a tet cube dropped
on the ground, an arm's capsule landing on the ground, a chain with
capsules on two links that may touch each other. Run it after changing what fuzz_contact.cpp reads:

    /usr/bin/python3 tests/fuzz/make_contact_seeds.py
"""
from pathlib import Path

CORPUS = Path(__file__).resolve().parent / "corpus" / "contact"

# Driver::Call's choice (in_.Int(9))
CREATE_RIGID, CREATE_OBSTACLE, CREATE_NODAL, MOVE_OBSTACLE, KICK, STEP, CREATE_ARM = 0, 1, 3, 4, 6, 7, 8
REVOLUTE, PRISMATIC, FIXED = 0, 1, 4
PLANE, SPHERE, BOX, CAPSULE = 0, 1, 2, 3


def size(k):
    """Size(): 0.02 (1 + k), k in [0, 10)."""
    return [1, k]


def place(x, y, z):
    """Place(): (0.1 (x − 5), 0.1 y, 0.1 (z − 5))."""
    return [1, x, y, z]


def shape(kind, obstacle, half=4, radius=4):
    """Shape(): the shape (an obstacle's from Plane on, a body's from Sphere on),
    radius, half length, half extents (all Size()), the identity rotation, no
    hostile thickness, friction, group, mask or normal."""
    out = [kind if obstacle else kind - 1]
    out += size(radius) + size(half) + size(half) * 3
    out += [1, 3, 3, 3]  # Rotation(): an axis of zeros is the identity
    out += [1] * 5
    return out


def step(rate=1):
    """Step(): dt = 1 / (30, 60, 120, 240)[rate]."""
    return [STEP, 1, rate]


def ground():
    return [CREATE_OBSTACLE] + shape(PLANE, True) + place(5, 5, 5)  # y = 0.5 − 0.5


def rigid_box(x, y, z, half=4):
    return [CREATE_RIGID] + place(x, y, z) + [1] + shape(BOX, False, half=half) + [1]


def seeds():
    params = [1]  # default ContactParams
    yield "ground_box_steps", params + ground() + rigid_box(5, 2, 5) + step() * 20
    # a paddle (a static box) beside a resting box, moved 5 cm toward it
    # over each of the next steps
    paddle = [CREATE_OBSTACLE] + shape(BOX, True, half=2) + place(2, 7, 5)
    push = [MOVE_OBSTACLE, 2, 1, 3, 2, 1, 1]  # collider 2, +5 cm in x, kept rotation, target
    yield "kinematic_push", params + ground() + rigid_box(5, 2, 5) + paddle + (push + step()) * 9
    # a 7-node rod and a tet cube, each with its Surface, onto the ground
    rod = [CREATE_NODAL] + place(3, 4, 5) + size(2) + [0, 5] + [0] * 7 + [1, 1, 0]
    cube = [CREATE_NODAL] + place(6, 2, 5) + size(4) + [1, 1, 1, 1]
    yield "rod_and_cube", params + ground() + rod + cube + step() * 20
    # a two-link arm: a carriage sliding along y from 0.4 m up, a link
    # hanging on a revolute joint, a capsule on that link: it falls and
    # lands on the ground
    carriage = [PRISMATIC, 0, 0, 1, 0] + place(5, 4, 5) + [1]  # axis (0, 1, 0), at (0, 0.4, 0), default mass
    hanging = [REVOLUTE, 1] + size(4) + [1]           # axis z, 0.1 m below
    capsule = shape(CAPSULE, False, half=1, radius=0) + [1, 1]  # on link 1
    yield "arm_capsule", params + ground() + [CREATE_ARM, 1] + carriage + hanging + capsule + step() * 20
    # a three-link chain hanging from a fixed root 0.6 m up, a capsule on
    # link 0 and (the byte after it 0: a second shape) one on link 2, two
    # links away: a mechanism's links that may touch each other
    root = [FIXED, 1] + place(5, 6, 5) + [1]
    chain = root + hanging * 2
    on_link0 = shape(CAPSULE, False, half=1, radius=0) + [1, 0]
    yield "arm_self_pair", params + ground() + [CREATE_ARM, 2] + chain + on_link0 + [0] + \
        shape(CAPSULE, False, half=1, radius=0) + step() * 20


def main():
    for name, data in seeds():
        assert all(0 <= b < 256 for b in data), name
        (CORPUS / f"{name}.bin").write_bytes(bytes(data))
        print(f"{name}.bin: {len(data)} bytes")


if __name__ == "__main__":
    main()
