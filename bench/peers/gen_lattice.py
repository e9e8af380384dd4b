#!/usr/bin/python3
# Adapted copy of shared/peers/liggghts/gen_lattice.py for bench/peers/compare.sh.
# Changed: this header and an optional SEED argument (default 12345, the peer's). The lattice
# (20,000 spheres, 18 x 18 per layer, spacing 30/18 mm, +-0.06 mm jitter from numpy's
# default_rng(SEED)) is the peer's, byte for byte for SEED = 12345; Sable's
# examples/pour.toml reproduces the same positions with its own numpy-PCG64 generator.
# Needs numpy: run it with /usr/bin/python3 (Debian's python3-numpy).
"""Generate the initial configuration for benchmark A/B ("pour").

20,000 monodisperse spheres (d = 1.5 mm, rho = 2500 kg/m^3) on a simple-cubic
lattice of spacing s = 30 mm / 18 = 1.6667 mm (1.111 d), 18 x 18 per layer,
in a 30 mm x 30 mm (20 d x 20 d) box, with a uniform random jitter of
+-0.06 mm (0.04 d) on every coordinate (fixed seed).  No initial overlaps,
no initial overlap with the walls at x,y = 0 / 0.03 and z = 0.

Writes a LAMMPS/LIGGGHTS data file (atom_style granular / sphere:
  id type diameter density x y z)
Usage: gen_lattice.py OUTFILE [N] [SEED]
"""
import sys
import numpy as np

out = sys.argv[1]
N = int(sys.argv[2]) if len(sys.argv) > 2 else 20000
d = 1.5e-3
rho = 2500.0
L = 0.030          # box side (x and y)
H = 0.110          # box height (z)
n = 18
s = L / n
jit = 0.06e-3
seed = int(sys.argv[3]) if len(sys.argv) > 3 else 12345
rng = np.random.default_rng(seed)

pos = []
k = 0
while len(pos) < N:
    for j in range(n):
        for i in range(n):
            if len(pos) >= N:
                break
            pos.append(((i + 0.5) * s, (j + 0.5) * s, (k + 0.5) * s))
    k += 1
pos = np.array(pos) + rng.uniform(-jit, jit, size=(N, 3))
assert pos[:, 2].max() + d / 2 < H
assert pos[:, :2].min() > d / 2 and pos[:, :2].max() < L - d / 2 and pos[:, 2].min() > d / 2

with open(out, "w") as f:
    f.write("pour benchmark initial lattice, N=%d d=%g rho=%g\n\n" % (N, d, rho))
    f.write("%d atoms\n1 atom types\n\n" % N)
    f.write("0 %.6f xlo xhi\n0 %.6f ylo yhi\n0 %.6f zlo zhi\n\n" % (L, L, H))
    f.write("Atoms\n\n")
    for a, (x, y, z) in enumerate(pos, 1):
        f.write("%d 1 %.6e %.6e %.9e %.9e %.9e\n" % (a, d, rho, x, y, z))
print("wrote", out, N, "particles, layers:", k, "top z = %.4f m" % pos[:, 2].max())
