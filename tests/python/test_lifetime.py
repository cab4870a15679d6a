"""Object lifetime: a Python object whose C++ actor, constraint or scene is
gone raises mochi.Error when used; it never crashes the interpreter. Objects
keep their scene alive; Scene.destroy() ends it at once."""
import gc
import os
import subprocess
import sys
import textwrap
import weakref

import pytest

import mochi
from helpers import make_zoo, valid_params


def every_constraint_method(c):
    """Calls of the whole runtime interface on constraint `c` (each must raise once c is gone)."""
    return [
        c.get_num_actors, lambda: c.get_actor(0), lambda: c.get_dof_indices_for_actor(0), c.get_dimension,
        c.get_num_dofs, c.is_range, c.get_stiffness, c.get_damping, c.get_saturation,
        lambda: c.set_stiffness(1), lambda: c.set_damping(1), lambda: c.set_saturation(-1),
        lambda: c.set_target_position([0, 0, 0]), lambda: c.set_target_rotation([1, 0, 0, 0]),
        lambda: c.set_target_transform([0, 0, 0], [1, 0, 0, 0]), lambda: c.set_target_dof(0),
        c.update_old_target, c.get_deviation, lambda: c.is_query_supported(mochi.QueryType.ConstraintForce),
        lambda: c.register_query(mochi.QueryType.ConstraintForce), c.get_force, c.get_limit_min_values,
        c.get_limit_max_values,
    ]


def assert_all_raise(calls, code):
    for call in calls:
        with pytest.raises(mochi.Error) as e:
            call()
        assert e.value.code == code


def test_destroyed_constraint_raises_on_every_method():
    scene = mochi.Scene.create()
    zoo = make_zoo(scene)
    constraints = [getattr(scene, f)(**kw) for f, _, kw in valid_params(zoo)]
    for c in constraints:
        scene.destroy_constraint(c)
        assert not c.is_alive()
        assert "destroyed" in repr(c)
        assert_all_raise(every_constraint_method(c), mochi.ErrorCode.InvalidHandle)
    assert scene.get_num_constraints() == 0
    # the type-specific accessors resolve through the handle too
    with pytest.raises(mochi.Error):
        constraints[0].get_local_pos_a()


def test_destroying_an_actor_destroys_its_constraints_python_objects_raise():
    scene = mochi.Scene.create()
    zoo = make_zoo(scene)
    constraints = [getattr(scene, f)(**kw) for f, _, kw in valid_params(zoo)]
    on_a = [c for c in constraints if any(c.get_actor(i) == zoo["a"] for i in range(c.get_num_actors()))]
    assert len(on_a) == 9  # the 7 rigid-rigid and rigid-target types, node-to-rigid, rod rotation
    scene.destroy_actor(zoo["a"])
    for c in constraints:
        assert c.is_alive() == (c not in on_a)
    for c in on_a:
        with pytest.raises(mochi.Error) as e:
            c.get_deviation()
        assert e.value.code == mochi.ErrorCode.InvalidHandle
        assert "was destroyed" in e.value.message
    # the actor object itself raises, and the survivors keep working
    assert not zoo["a"].is_alive()
    with pytest.raises(mochi.Error) as e:
        zoo["a"].get_position()
    assert e.value.code == mochi.ErrorCode.InvalidHandle
    for c in constraints:
        if c not in on_a:
            assert c.get_deviation().shape == (c.get_dimension(),)
    scene.step(1e-3)


def test_stale_handle_never_names_a_new_object():
    scene = mochi.Scene.create()
    old = scene.create_rigid_actor()
    scene.destroy_actor(old)
    new = scene.create_rigid_actor(position=[0, 5, 0])
    assert new.get_handle().index == old.get_handle().index  # the slot is reused ...
    assert new.get_handle() != old.get_handle()  # ... with a new generation
    with pytest.raises(mochi.Error):
        old.get_position()
    assert new.get_position()[1] == 5


def test_objects_keep_their_scene_alive():
    scene = mochi.Scene.create()
    body = scene.create_rigid_actor()
    pin = scene.create_rigid_pivot_position_constraint(actor=body, position=[0, 0, 0], stiffness=1e4)
    other = scene.create_rigid_actor(position=[0, 3, 0])
    scene_ref = weakref.ref(scene)
    del scene
    gc.collect()
    assert scene_ref() is None  # the Python Scene object is gone ...
    # ... but the C++ scene lives on, shared by its actors and constraints
    assert body.is_alive() and pin.is_alive()
    again = pin.get_scene()
    assert again.is_alive() and again == body.get_scene() and again.get_num_actors() == 2
    again.step(0.01)
    assert other.get_position()[1] < 3  # the free body falls
    assert pin.get_deviation()[1] < 0  # the pinned one hangs below its target
    del again, body, pin
    gc.collect()
    assert other.get_scene().get_num_constraints() == 1


def test_destroyed_scene_makes_every_object_raise():
    scene = mochi.Scene.create()
    zoo = make_zoo(scene)
    constraints = [getattr(scene, f)(**kw) for f, _, kw in valid_params(zoo)]
    scene.destroy()
    assert not scene.is_alive() and repr(scene) == "Scene(destroyed)"
    scene.destroy()  # idempotent
    for c in constraints:
        assert not c.is_alive()
        assert_all_raise(every_constraint_method(c), mochi.ErrorCode.InvalidState)
    for actor in zoo.values():
        assert not actor.is_alive()
        with pytest.raises(mochi.Error) as e:
            actor.get_num_dofs()
        assert e.value.code == mochi.ErrorCode.InvalidState
    assert_all_raise([lambda: scene.step(0.01), scene.get_time, scene.get_stats, scene.create_rigid_actor,
                      scene.get_num_actors, lambda: scene.destroy_actor(zoo["a"])], mochi.ErrorCode.InvalidState)


def test_with_block_destroys_the_scene():
    with mochi.Scene.create() as scene:
        body = scene.create_rigid_actor()
        scene.step(0.01)
    with pytest.raises(mochi.Error) as e:
        body.get_position()
    assert e.value.code == mochi.ErrorCode.InvalidState


def test_callbacks_may_destroy_what_they_visit():
    scene = mochi.Scene.create()
    zoo = make_zoo(scene)
    for f, _, kw in valid_params(zoo):
        getattr(scene, f)(**kw)
    visited = []

    def destroy_actor_of(c):
        visited.append(c.get_type())
        if c.get_type() == mochi.ConstraintType.RigidSphericalJoint:
            scene.destroy_actor(zoo["a"])  # takes the later constraints on `a` along

    scene.for_each_constraint(destroy_actor_of)
    assert len(visited) == 1 + (15 - 9)  # the spherical joint, then the 6 not on `a`
    scene.for_each_actor(scene.destroy_actor)
    assert scene.get_num_actors() == 0 and scene.get_num_constraints() == 0
    # an exception in the callback propagates and leaves the scene usable
    scene.create_rigid_actor()
    with pytest.raises(ZeroDivisionError):
        scene.for_each_actor(lambda a: 1 / 0)
    scene.step(0.01)


def test_scene_garbage_collected_at_exit_never_crashes():
    # a fresh interpreter that leaves objects of every kind (and a destroyed
    # scene) for the interpreter's shutdown, in an arbitrary order
    script = textwrap.dedent("""
        import mochi, sys
        sys.path.insert(0, sys.argv[1])
        from helpers import make_zoo, valid_params
        scene = mochi.Scene.create(linear_solver=mochi.LinearSolverType.PetscPcg)
        zoo = make_zoo(scene)
        cs = [getattr(scene, f)(**kw) for f, _, kw in valid_params(zoo)]
        scene.step(1e-3)
        del scene
        other = mochi.Scene.create()
        kept = other.create_rigid_actor()
        other.destroy()
        print("done")
    """)
    result = subprocess.run([sys.executable, "-c", script, os.path.dirname(__file__)],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "done"


def test_objects_and_handles_of_another_scene_are_refused():
    """Before: s1.destroy_actor(actor_of_s2) destroyed s1's actor in the same
    slot; factories and destroy_constraint did the same."""
    s1, s2 = mochi.Scene.create(), mochi.Scene.create()
    zoo1, zoo2 = make_zoo(s1), make_zoo(s2)
    assert s1.get_id() != s2.get_id()
    assert zoo2["a"].get_handle().scene == s2.get_id()
    c2 = s2.create_rigid_spherical_joint_constraint(actor_a=zoo2["a"], actor_b=zoo2["b"], stiffness=1e4)
    c1 = s1.create_rigid_spherical_joint_constraint(actor_a=zoo1["a"], actor_b=zoo1["b"], stiffness=1e4)
    assert c1.get_handle().index == c2.get_handle().index  # same slot in both scenes
    counts = (s1.get_num_actors(), s1.get_num_constraints())
    for foreign in (zoo2["a"], zoo2["a"].get_handle()):
        with pytest.raises(mochi.Error) as e:
            s1.destroy_actor(foreign)
        assert e.value.code == mochi.ErrorCode.InvalidHandle and "belongs to another scene" in e.value.message
        assert s1.get_actor(zoo2["a"].get_handle()) is None
    for foreign in (c2, c2.get_handle()):
        with pytest.raises(mochi.Error) as e:
            s1.destroy_constraint(foreign)
        assert "belongs to another scene" in e.value.message
    # every factory, with one actor of the other scene in each actor field
    for name, params_class, kwargs in valid_params(zoo1):
        fields = [k for k, v in kwargs.items() if isinstance(v, mochi.Actor)]
        for field in fields:
            bad = dict(kwargs)
            bad[field] = zoo2[next(k for k, v in zoo1.items() if v == kwargs[field])]  # its twin in s2
            with pytest.raises(mochi.Error) as e:
                getattr(s1, name)(**bad)
            assert e.value.code == mochi.ErrorCode.InvalidHandle, (name, field, e.value.message)
            assert "belongs to another scene" in e.value.message, (name, field)
    assert (s1.get_num_actors(), s1.get_num_constraints()) == counts
    assert all(a.is_alive() for a in zoo1.values()) and c1.is_alive()
    s1.step(1e-3)
    s2.step(1e-3)
