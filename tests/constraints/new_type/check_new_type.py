"""After add_type_test.sh added RigidCenterOnPlane to a copy of the tree:
everything a type gets from its line in constraints/constraint_types.h is
there and works — the enum value, the factory and its validation (through
mochi), the params class with the type's fields, the class and the
downcast, and the docs table.

usage: check_new_type.py TREE (with the copy's build/python on PYTHONPATH)
"""
import subprocess
import sys

import mochi


def expect(condition, what):
    if not condition:
        print(f"check_new_type: FAILED: {what}")
        sys.exit(1)


def main():
    tree = sys.argv[1]
    expect(hasattr(mochi.ConstraintType, "RigidCenterOnPlane"), "ConstraintType.RigidCenterOnPlane")
    params = mochi.RigidCenterOnPlaneConstraintParams(offset=0.5)
    for field in ("actor", "link", "normal", "offset", "stiffness", "damping", "saturation"):
        expect(hasattr(params, field), f"RigidCenterOnPlaneConstraintParams.{field}")

    scene = mochi.Scene.create()
    body = scene.create_rigid_actor(mass=1, position=[0, 1, 0])
    # validation: the type's own Create, through the generated factory
    for bad, field in ((dict(actor=body, normal=[0, 0, 0]), "normal"),
                       (dict(actor=body, offset=float("nan")), "offset"),
                       (dict(actor=body, stiffness=-1), "stiffness"),
                       (dict(actor=mochi.ActorHandle(), offset=0), "actor")):
        try:
            scene.create_rigid_center_on_plane_constraint(**bad)
            expect(False, f"{bad} accepted")
        except mochi.Error as error:
            expect(f"RigidCenterOnPlaneConstraintParams.{field}" in str(error), f"{field} named in: {error}")
    expect(scene.get_num_constraints() == 0, "a refused call created nothing")

    # the factory, the class, the downcast; a spring to the plane y = 0.5
    # holds the body against gravity at y = 0.5 − m g / k
    k, d = 1e4, 200.0
    c = scene.create_rigid_center_on_plane_constraint(actor=body, normal=[0, 2, 0], offset=0.5, stiffness=k,
                                                       damping=d)
    expect(type(c).__name__ == "RigidCenterOnPlaneConstraint", f"the class: {type(c).__name__}")
    expect(c.get_type() == mochi.ConstraintType.RigidCenterOnPlane, "get_type")
    expect(type(scene.get_constraints()[0]).__name__ == "RigidCenterOnPlaneConstraint", "the downcast")
    expect(abs(c.get_deviation()[0] - 0.5) < 1e-15, f"g at creation: {c.get_deviation()}")
    for _ in range(240):
        scene.step(1 / 60)
    y = body.get_position()[1]
    expected = 0.5 - 9.81 / k
    expect(abs(y - expected) < 1e-6, f"equilibrium y = {y}, expected {expected}")

    # the docs table, made from the list
    table = subprocess.run([sys.executable, f"{tree}/scripts/constraint_table.py"], check=True,
                           capture_output=True, text=True).stdout
    expect("| RigidCenterOnPlane | `CreateRigidCenterOnPlaneConstraint` | `create_rigid_center_on_plane_constraint`"
           in table, "the docs table's row")
    print(f"check_new_type: RigidCenterOnPlane created, validated, bound, stepped (y = {y:.9f} m) and listed")


if __name__ == "__main__":
    main()
