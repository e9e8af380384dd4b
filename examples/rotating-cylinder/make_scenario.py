#!/usr/bin/python3
"""Write the scenario of the rotating cylinder of Guillard, Forterre & Pouliquen (2015) for one
size, depth and stiffness (examples/rotating-cylinder/, docs/examples.md).

    /usr/bin/python3 examples/rotating-cylinder/make_scenario.py OUT.toml \
        [--length-d 20] [--depth 1.0] [--young 5e6] [--turns 2] [--facets 32] [--segments 12] \
        [--dt-fraction 0.2] [--snapshots-per-turn 16] [--out-dir out/cyl] [--seed 1]

Lengths are in grain diameters d = 1.5 mm and follow the cylinder's length L = LENGTH_D d:
cylinder diameter D = L / 6, container diameter 2.5 L (50 d at the paper's L = 20 d), container
height and filling height 6.5 L (130 d), the cylinder's centre on the container's axis at DEPTH
L below the planned free surface. The rotation rate follows the scaling rule of docs/examples.md
(same inertial number as the paper's 0.5 rev/s at L = 20 d): omega = pi sqrt(L / 20 d) rad/s.
Everything the run needs later (dt, omega, L, the planned depth...) goes into the header and
into OUT.json beside the scenario.
"""
import argparse
import json
import math
import sys
from pathlib import Path

D_GRAIN = 1.5e-3  # m
RHO = 2500.0  # kg/m^3
NU = 0.45
RESTITUTION = 0.6
FRICTION = 0.5
G = 9.81
PHI_POURED = 0.60  # solid fraction the pour is planned with (measured after it: run.sh)
PAPER_LENGTH_D = 20.0
PAPER_RATE = math.pi  # 0.5 rev/s


def rayleigh_time(young: float) -> float:
    shear = young / (2.0 * (1.0 + NU))
    return math.pi * 0.5 * D_GRAIN * math.sqrt(RHO / shear) / (0.1631 * NU + 0.8766)


def positive(kind):
    def parse(text):
        value = kind(text)
        if not value > 0:
            raise argparse.ArgumentTypeError(f"'{text}' must be > 0")
        return value
    return parse


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", help="scenario file to write (.toml); OUT.json gets the settings")
    ap.add_argument("--length-d", type=positive(float), default=20.0,
                    help="cylinder length L in grain diameters (paper: 20)")
    ap.add_argument("--depth", type=positive(float), default=1.0, help="h / L")
    ap.add_argument("--young", type=positive(float), default=5e6, help="E (Pa)")
    ap.add_argument("--turns", type=positive(float), default=2.0, help="turns of the cylinder")
    ap.add_argument("--facets", type=int, default=32, help="flat sides round the cylinder")
    ap.add_argument("--segments", type=int, default=12,
                    help="rows along the cylinder (12 with 32 facets and caps: the paper's 832)")
    ap.add_argument("--dt-fraction", type=positive(float), default=0.2,
                    help="dt / Rayleigh time (0.2, LIGGGHTS' advice)")
    ap.add_argument("--inertial", type=positive(float),
                    help="set omega from this inertial number omega d / sqrt(phi g h) instead "
                         "of the scaling rule (quick study: 0.016, the paper's largest)")
    ap.add_argument("--snapshots-per-turn", type=int, default=16)
    ap.add_argument("--rows-per-turn", type=int, default=400, help="series.csv rows per turn")
    ap.add_argument("--out-dir", default="out/rotating-cylinder", help="[output].dir")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--fill-L", type=positive(float), default=6.5,
                    help="container and filling height / L (6.5: the paper's 130 d at L = 20 d; "
                         "the CI test's tiny version uses less)")
    ap.add_argument("--pour-seconds", type=positive(float), default=1.5,
                    help="cap of the pour stage in simulated seconds")
    a = ap.parse_args()
    if a.facets < 3 or a.segments < 1 or a.snapshots_per_turn < 2 or a.rows_per_turn < 2:
        ap.error("need facets >= 3, segments >= 1, snapshots-per-turn >= 2, rows-per-turn >= 2")
    if a.length_d < 6.0:
        ap.error("--length-d below 6 makes the cylinder thinner than a grain (D = L / 6)")
    if a.depth > a.fill_L - 0.5:
        ap.error(f"--depth {a.depth:g} leaves less than L / 2 below the cylinder (filling height "
                 f"{a.fill_L:g} L)")

    d = D_GRAIN
    L = a.length_d * d
    D = L / 6.0
    rc = 1.25 * L  # container radius: diameter 2.5 L
    height = a.fill_L * L  # container height, filled to the top
    h = a.depth * L
    zc = height - h
    omega = PAPER_RATE * math.sqrt(a.length_d / PAPER_LENGTH_D)
    if a.inertial:
        omega = a.inertial * math.sqrt(PHI_POURED * G * h) / d
    t_r = rayleigh_time(a.young)
    dt = a.dt_fraction * t_r
    steps_per_turn = round(2.0 * math.pi / omega / dt)
    turn_steps = round(a.turns * steps_per_turn)
    v_grain = math.pi * d**3 / 6.0
    mass = RHO * v_grain
    count = round(PHI_POURED * math.pi * rc**2 * height / v_grain)
    # Hexagonal lattice, 1.05 d apart: solid fraction ~0.52, so the bed falls ~15 % of its
    # height while settling; the sites inside the cylinder are skipped.
    spacing = 1.05 * d
    r_sites = rc - 0.6 * d
    per_layer = math.pi * r_sites**2 / (spacing * spacing * math.sqrt(3.0) / 2.0)
    zhi = 1.2 * spacing * count / per_layer + 2.0 * d
    # "At rest": a mean speed of 1 mm/s, well below the cylinder's slowest point (omega D / 2).
    ke_rest = count * 0.5 * mass * 1e-3**2
    pour_steps = round(a.pour_seconds / dt)
    check = max(100, round(0.01 / dt))
    e_star = a.young / (RHO * G * d)
    inertial = omega * d / math.sqrt(PHI_POURED * G * h)
    snap_every = max(1, steps_per_turn // a.snapshots_per_turn)
    rows_every = max(1, steps_per_turn // a.rows_per_turn)
    triangles = 2 * a.facets * a.segments + 2 * a.facets
    settings = {
        "d_m": d, "rho_kg_m3": RHO, "young_Pa": a.young, "E_star": e_star, "poisson": NU,
        "restitution": RESTITUTION, "friction": FRICTION, "L_m": L, "D_m": D,
        "L_over_d": a.length_d, "container_radius_m": rc, "container_height_m": height,
        "h_planned_m": h, "h_over_L_planned": a.depth, "cylinder_center_z_m": zc,
        "omega_rad_s": omega, "rev_per_s": omega / (2.0 * math.pi), "dt_s": dt,
        "rayleigh_time_s": t_r, "dt_fraction": a.dt_fraction, "steps_per_turn": steps_per_turn,
        "turns": a.turns, "turn_steps": turn_steps, "grains": count, "facets": a.facets,
        "segments": a.segments, "triangles": triangles, "inertial_number": inertial,
        "phi_planned": PHI_POURED, "snapshot_interval": snap_every, "csv_interval": rows_every,
    }
    inertial_arg = f" --inertial {a.inertial:g}" if a.inertial else ""
    rate_rule = (f"set by --inertial {a.inertial:g}" if a.inertial else
                 "the paper's 0.5 rev/s at L = 20 d times sqrt(L / 20 d),\n# which keeps the "
                 "paper's inertial number at each h / L")
    header = f"""\
# The rotating cylinder of Guillard, Forterre & Pouliquen (2015), written by
# examples/rotating-cylinder/make_scenario.py --length-d {a.length_d:g} --depth {a.depth:g} \\
#     --young {a.young:g} --turns {a.turns:g} --facets {a.facets} --segments {a.segments} \\
#     --dt-fraction {a.dt_fraction:g} --snapshots-per-turn {a.snapshots_per_turn} --seed {a.seed}{inertial_arg} \\
#     --fill-L {a.fill_L:g} --rows-per-turn {a.rows_per_turn} --pour-seconds {a.pour_seconds:g}
# (docs/examples.md, "Rotating cylinder": set-up, choices and scaling rule).
#
# Grains: d = 1.5 mm spheres, rho = 2500 kg/m^3, Hertz-Mindlin with history, E = {a.young:.4g} Pa
# (E* = E / (rho g d) = {e_star:.3g}), nu = 0.45, e = 0.6, mu = 0.5. Container walls, floor and
# cylinder are the same material (the paper's particle-cylinder k_n is Hertz against a body of
# the grains' E and nu; its wall friction is not stated: 0.5, our choice).
# Geometry, in L = {a.length_d:g} d = {L * 1e3:.4g} mm: cylinder D = L / 6 = {D * 1e3:.4g} mm, a mesh
# of {a.facets} facets round x {a.segments} rows + caps = {triangles} triangles, its axis along x,
# its centre on the container's axis at z = {zc * 1e3:.5g} mm, h = {a.depth:g} L = {h * 1e3:.5g} mm
# below the planned free surface; container diameter 2.5 L = {2 * rc * 1e3:.5g} mm, filled to
# {a.fill_L:g} L = {height * 1e3:.5g} mm: {count} grains at a poured solid fraction of {PHI_POURED}
# (run.sh measures the real surface and depth after the pour).
# Preparation: the grains start on a hexagonal lattice (1.05 d) that skips the sites the
# cylinder takes, and are poured around the cylinder held at rest (the paper pours to h,
# places the cylinder and pours on: a lattice cannot be added to in mid-run, and pouring the
# whole bed around the placed cylinder gives the same packing above and around it).
# Turning: {omega:.5g} rad/s ({omega / (2 * math.pi):.4g} rev/s) about the vertical axis through
# the container's axis: {rate_rule};
# inertial number omega d / sqrt(phi g h) = {inertial:.3g}.
# dt = {a.dt_fraction:g} x the Rayleigh time {t_r:.4g} s = {dt:.4g} s; {steps_per_turn} steps per turn.
# series.csv: wall_cylinder_tz_Nm is the torque M the grains exert on the cylinder about the
# vertical axis; the drag is F = 4 M / L.
"""
    body = f"""
[simulation]
dimension = 3
seed = {a.seed}
dt = {dt:.6g}
gravity = [0.0, 0.0, -9.81]
skin = {0.5 * d:.6g}
overlap_warning = 0.2           # a fall of up to ~{(zhi - height) * 1e3:.0f} mm onto the bed
track_orientation = false       # a sphere's orientation enters no force

[domain]
lo = [{-rc - d:.6g}, {-rc - d:.6g}, 0.0]
hi = [{rc + d:.6g}, {rc + d:.6g}, {zhi + d:.6g}]

[[material]]
name = "glass"
density = {RHO}
young = {a.young:.6g}
poisson = {NU}
restitution = {RESTITUTION}
friction = {FRICTION}

[contact]
normal = "hertz"
tangential = "history"

[[grains]]
generator = "lattice"
arrangement = "hexagonal"
material = "glass"
radius = {0.5 * d:.6g}
region = {{ cylinder = {{ center = [0.0, 0.0], radius = {r_sites:.6g}, zlo = 0.0, zhi = {zhi:.6g} }} }}
count = {count}
spacing = {spacing:.6g}
jitter = {0.02 * d:.6g}

[[wall]]
name = "floor"
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
material = "glass"

[[wall]]
name = "container"
type = "cylinder"
center = [0.0, 0.0]
radius = {rc:.6g}
material = "glass"

[[wall]]
name = "cylinder"
type = "mesh"
material = "glass"
shape = {{ cylinder = {{ center = [0.0, 0.0, {zc:.6g}], axis = [1.0, 0.0, 0.0], radius = {0.5 * D:.6g}, length = {L:.6g}, facets = {a.facets}, segments = {a.segments}, caps = true }} }}
rotation = {{ point = [0.0, 0.0, {zc:.6g}], axis = [0.0, 0.0, 1.0], rate = 0.0 }}

# The bed settles around the cylinder at rest (a mean speed of 1 mm/s).
[[stage]]
name = "pour"
kinetic_energy_below = {ke_rest:.4g}
max_steps = {pour_steps}
check_interval = {check}

[[stage]]
name = "turn"
steps = {turn_steps}
wall_rotation = {{ cylinder = {{ point = [0.0, 0.0, {zc:.6g}], axis = [0.0, 0.0, 1.0], rate = {omega:.10g} }} }}

[output]
dir = "{a.out_dir}"
vtk_interval = 0
vtk_contacts = false
csv_interval = {rows_every}
snapshot_interval = {snap_every}
log_interval = {max(1000, steps_per_turn // 20)}
"""
    out = Path(a.out)
    out.write_text(header + body)
    out.with_suffix(".json").write_text(json.dumps(settings, indent=2) + "\n")
    print(json.dumps(settings))
    return 0


if __name__ == "__main__":
    sys.exit(main())
