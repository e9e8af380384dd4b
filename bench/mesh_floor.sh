#!/usr/bin/env bash
# The cost of mesh walls against a plane: the pour bed (examples/pour.toml, 20,000 spheres)
# with its floor as a plane, as a 2-triangle mesh and as a 10,000-triangle mesh (a 50 x 100
# grid of the same 30 x 30 mm square, triangles of 0.6 x 0.3 mm: smaller than the grains,
# so each grain of the bottom layer has some 30 triangles within reach). The other five sides
# stay planes. Each variant settles once (stage 1); then the dense stage (5,000 steps) is timed
# REPEATS times per variant, the variants alternating so that the machine's drift hits each
# alike. Prints "variant grain-steps/s seconds touching" per run, then each variant's median
# seconds and its ratio to the plane's.
# Usage: bench/mesh_floor.sh [-t THREADS] [-r REPEATS] [BINARY]   (default build/release/bin/sable)
set -euo pipefail
cd "$(dirname "$0")/.."
threads=1
repeats=3
while getopts "t:r:" opt; do
  case "$opt" in
    t) threads="$OPTARG" ;;
    r) repeats="$OPTARG" ;;
    *) echo "usage: bench/mesh_floor.sh [-t THREADS] [-r REPEATS] [BINARY]" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
sable="${1:-build/release/bin/sable}"
work=out/bench-mesh
mkdir -p "$work"
/usr/bin/python3 - "$work" <<'PY'
import re, sys
from pathlib import Path
work = Path(sys.argv[1])
def grid_stl(path, nx, ny):
    a = 0.030
    lines = ["solid floor"]
    for i in range(nx):
        for j in range(ny):
            x0, x1, y0, y1 = a * i / nx, a * (i + 1) / nx, a * j / ny, a * (j + 1) / ny
            for tri in (((x0, y0), (x1, y0), (x1, y1)), ((x0, y0), (x1, y1), (x0, y1))):
                lines += ["facet normal 0 0 1", "outer loop"]
                lines += [f"vertex {x!r} {y!r} 0" for x, y in tri]
                lines += ["endloop", "endfacet"]
    lines.append("endsolid floor")
    path.write_text("\n".join(lines) + "\n")
grid_stl(work / "floor2.stl", 1, 1)
grid_stl(work / "floor10k.stl", 50, 100)
base = Path("examples/pour.toml").read_text()
base = re.sub(r"^vtk_interval = .*$", "vtk_interval = 0", base, flags=re.M)
base = re.sub(r"^csv_interval = .*$", "csv_interval = 5000", base, flags=re.M)
box = re.search(r'\[\[wall\]\]\nname = "box"\n(?:.*\n)*?material = "glass"\n', base).group(0)
def plane(name, point, normal):
    return (f'[[wall]]\nname = "{name}"\ntype = "plane"\npoint = {point}\nnormal = {normal}\n'
            'material = "glass"\n\n')
sides = (plane("xlo", "[0.0, 0.0, 0.0]", "[1.0, 0.0, 0.0]") +
         plane("xhi", "[0.030, 0.0, 0.0]", "[-1.0, 0.0, 0.0]") +
         plane("ylo", "[0.0, 0.0, 0.0]", "[0.0, 1.0, 0.0]") +
         plane("yhi", "[0.0, 0.030, 0.0]", "[0.0, -1.0, 0.0]") +
         plane("zhi", "[0.0, 0.0, 0.110]", "[0.0, 0.0, -1.0]"))
floors = {
    "plane": plane("floor", "[0.015, 0.015, 0.0]", "[0.0, 0.0, 1.0]"),
    "mesh2": '[[wall]]\nname = "floor"\ntype = "mesh"\nfile = "floor2.stl"\nmaterial = "glass"\n\n',
    "mesh10k": '[[wall]]\nname = "floor"\ntype = "mesh"\nfile = "floor10k.stl"\nmaterial = "glass"\n\n',
}
for name, floor in floors.items():
    (work / f"{name}.toml").write_text(base.replace(box, floor + sides))
PY
variants="plane mesh2 mesh10k"
for v in $variants; do
  if [ ! -f "$work/$v-settled.h5" ]; then
    rm -rf "$work/settle-$v"
    "$sable" run "$work/$v.toml" --out "$work/settle-$v" --threads "$threads" 2> "$work/settle-$v.log"
    cp "$work/settle-$v/snapshots/end_of_stage_1.h5" "$work/$v-settled.h5"
  fi
done
declare -A times
for r in $(seq "$repeats"); do
  for v in $variants; do
    rm -rf "$work/run"
    "$sable" run "$work/$v.toml" --resume "$work/$v-settled.h5" --out "$work/run" \
      --threads "$threads" 2> "$work/run.log"
    line=$(grep "^stage 'dense' done: " "$work/run.log")
    rate=$(sed -n 's/.*, \([0-9.e+]*\) grain-steps\/s.*/\1/p' <<< "$line")
    secs=$(sed -n 's/.* in \([0-9.]*\) s, .*/\1/p' <<< "$line")
    touching=$(tail -1 "$work/run/series.csv" | cut -d, -f4)
    echo "$v $rate $secs $touching"
    times[$v]="${times[$v]:-} $secs"
  done
done
/usr/bin/python3 - "${times[plane]}" "${times[mesh2]}" "${times[mesh10k]}" <<'PY'
import statistics, sys
names = ["plane", "mesh2", "mesh10k"]
med = {n: statistics.median(float(x) for x in s.split()) for n, s in zip(names, sys.argv[1:])}
for n in names:
    spread = [float(x) for x in sys.argv[1 + names.index(n)].split()]
    print(f"{n}: median {med[n]:.3f} s (min {min(spread):.3f}, max {max(spread):.3f}), "
          f"ratio to the plane {med[n] / med['plane']:.3f}")
PY
