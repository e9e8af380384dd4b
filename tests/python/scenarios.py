"""The small scenarios of the Python tests: a box of 300 spheres, a box of 60 disks.

box_3d(seed, tail) and box_2d(tail): the model and the grains, then `tail` (the stages and
[output]), as a template for str.format: the model's braces are escaped, the tail's fields
({steps}, {out}, ...) are the caller's to fill.
"""

BOX_3D = """
[simulation]
dimension = 3
seed = {seed}
gravity = [0, 0, -9.81]

[domain]
lo = [0, 0, 0]
hi = [0.02, 0.02, 0.04]

[[material]]
name = "g"
density = 2500.0
young = 5e6
poisson = 0.45
restitution = 0.6
friction = 0.5

[[grains]]
generator = "lattice"
arrangement = "hexagonal"
material = "g"
radius = {{ distribution = "uniform", mean = 1e-3, spread = 0.2 }}
jitter = 0.1e-3
spacing = 2.6e-3
region = {{ box = {{ lo = [0, 0, 0], hi = [0.02, 0.02, 0.04] }} }}
count = 300

[[wall]]
name = "box"
type = "box"
material = "g"
lo = [0, 0, 0]
hi = [0.02, 0.02, 0.04]
"""

BOX_2D = """
[simulation]
dimension = 2
seed = 3
gravity = [0.0, -9.81]
thickness = 0.002

[domain]
lo = [0.0, 0.0]
hi = [0.02, 0.04]

[[material]]
name = "g"
density = 2500.0
young = 5e6
poisson = 0.45
restitution = 0.6
friction = 0.5

[[grains]]
generator = "random"
material = "g"
radius = {{ distribution = "uniform", mean = 1e-3, spread = 0.2 }}
region = {{ box = {{ lo = [0.0, 0.0], hi = [0.02, 0.04] }} }}
count = 60

[[wall]]
name = "box"
type = "box"
material = "g"
lo = [0.0, 0.0]
hi = [0.02, 0.04]
"""


def escape(text):
    return text.replace("{", "{{").replace("}", "}}")


def box_3d(seed, tail):
    return escape(BOX_3D.format(seed=seed)) + tail


def box_2d(tail):
    return BOX_2D + tail
