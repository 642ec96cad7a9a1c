"""A ball dropped on a bouncy ground, from Python: build the scene in code, step it, read the
numbers, compare with the closed form, and write a video. Run from a build:

    PYTHONPATH=build/python python3 examples/python_drop.py out/drop_py.mp4

The ball falls from 2 m; before the first bounce its height is 2 - g t^2 / 2 exactly (the default
integrator is exact for constant gravity), it lands at t = sqrt(2 h / g) = 0.639 s, and each bounce
returns it at `restitution` times the speed it arrived with.
"""
# %% The scene, built in code
import math
import sys

import numpy as np

import simreel

out = sys.argv[1] if len(sys.argv) > 1 else "out/drop_py.mp4"

scene = simreel.Scene("drop")
scene.set_simulation(duration=3.0, timestep=1 / 240)
scene.set_video(width=640, height=360, fps=30)
scene.set_camera(position=[0, -5, 1.2], look_at=[0, 0, 0.9], up=[0, 0, 1], fov=40)
scene.add_ground(size=6, restitution=0.7)
scene.add_body("ball", shape="sphere", radius=0.1, density=800, position=[0, 0, 2.1],
               color=[0.85, 0.35, 0.2], restitution=0.7)
sim = scene.build()

# %% Step it, read the height, write the frames
g, h0 = 9.81, 2.0  # m/s^2; the ball's lowest point starts 2 m up
print("   t (s)   height (m)   closed form (m)")
heights = []
with simreel.Renderer(sim) as renderer, simreel.VideoWriter(out, fps=30) as video:
    frame = np.zeros((renderer.height, renderer.width, 3), np.uint8)
    while sim.time < 3.0 - 1e-9:
        z = sim.positions[0, 2] - 0.1  # m, the ball's lowest point
        heights.append((sim.time, z, sim.velocities[0, 2]))
        if round(sim.time * 30) % 3 == 0 and sim.time < 0.6:
            print(f"{sim.time:8.3f} {z:12.6f} {h0 - g * sim.time**2 / 2:14.6f}")
        video.write(renderer.render(out=frame))
        sim.step(8)  # 1/30 s
# %% Compare with the closed form
land = math.sqrt(2 * h0 / g)
up = next(k for k, (t, z, vz) in enumerate(heights) if vz > 0)  # the first frame going up again
print(f"first landing: closed form {land:.4f} s; simulated: between the frames at {heights[up - 1][0]:.4f} "
      f"and {heights[up][0]:.4f} s")
print(f"highest after the first bounce: {max(z for t, z, vz in heights if t > land):.3f} m "
      f"(e^2 h = {0.7**2 * h0:.3f} m)")
print(f"wrote {out}")
