"""
A frame of the animation
========================

``celtstone.visual.animate`` draws a run in 3-D, the shaded body on the plane with the
track of its contact point and a read-out of time and spin, and writes an mp4 or a GIF.
Here one second of a rolling run (Euler angles α = β = 0.5°, ω₃ = −5 rad/s) becomes a small GIF of
a few frames in a temporary directory, and its last frame is shown.
"""

import tempfile
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from PIL import Image

import celtstone as cs
from celtstone.visual import animate

body = cs.load_body("kane_levinson_1982")
state = cs.InitialState(omega=(0.0, 0.0, -5.0), euler_angles=(0.5, 0.5))
run = cs.simulate(cs.RollingModel(), body, state, t_end=1.0)

with tempfile.TemporaryDirectory() as folder:
    info = animate(run.dataset, Path(folder) / "run.gif", fps=4, size=(480, 360))
    with Image.open(info.path) as gif:
        gif.seek(gif.n_frames - 1)
        frame = np.asarray(gif.convert("RGB"))
print(f"{info.frames} frames at {info.fps} fps, {info.bytes} bytes")

# %%
figure = Figure(figsize=(4.8, 3.6), layout="constrained")
axes = figure.add_subplot()
axes.imshow(frame)
axes.set_axis_off()
