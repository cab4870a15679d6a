# A rigid body hung from a pivot, stepped for one second.
import mochi

scene = mochi.Scene.create()
body = scene.create_rigid_actor(position=[0.5, 0, 0])
scene.create_rigid_pivot_position_constraint(actor=body, local_pos=[-0.5, 0, 0], stiffness=1e6)
for _ in range(60):
    scene.step(1 / 60)
print(f"ok: the body swung to y = {body.get_position()[1]:.3f} m")
