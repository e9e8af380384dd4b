#!/usr/bin/env bash
# Restitution of a head-on collision of two spheres against the time step, in units of the
# critical time of docs/contact-laws.md ("Time step"): for each law, ratio and relative speed,
# three initial gaps (the phase at which the first contact step lands); prints the range of
# the measured e (sqrt of the kinetic-energy ratio) for e = 0.6.
# Usage: bash scripts/time_step_sweep.sh [RATIOS...]   (default 0.2 0.3 0.4 0.5 0.6 0.7)
# Needs build/release/bin/sable (bash scripts/build.sh release). Ratios above 0.7 are refused
# by `sable run` (kTimeStepError in src/sable/scenario/config.hpp).
set -euo pipefail
cd "$(dirname "$0")/.."
sable=${SABLE:-build/release/bin/sable}
ratios=("$@")
[ ${#ratios[@]} -gt 0 ] || ratios=(0.2 0.3 0.4 0.5 0.6 0.7)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Critical times of r = 1 mm, rho = 2500, E = 1e7, nu = 0.3: the Rayleigh time (Hertz), and
# sqrt(m / 2k) with k = 1000 N/m (linear).
t_hertz=$(/usr/bin/python3 -c "import math; print(math.pi*1e-3*math.sqrt(2500/(1e7/2.6))/(0.1631*0.3+0.8766))")
t_linear=$(/usr/bin/python3 -c "import math; print(math.sqrt(0.5*2500*4/3*math.pi*1e-9/1000))")

scenario() {  # LAW STEPS SPEED DT HALF_GAP
  cat <<EOF
[simulation]
dimension = 3
dt = $4
[domain]
lo = [-0.01, -0.01, -0.01]
hi = [0.01, 0.01, 0.01]
[[material]]
name = "g"
density = 2500
young = 1e7
poisson = 0.3
restitution = 0.6
[contact]
normal = "$1"
tangential = "none"
$([ "$1" = linear ] && printf 'kn = 1000\nkt = 1000\n')
[[grains]]
generator = "list"
material = "g"
radius = 0.001
positions = [[-$5, 0, 0]]
velocity = [$3, 0, 0]
[[grains]]
generator = "list"
material = "g"
radius = 0.001
positions = [[$5, 0, 0]]
velocity = [-$3, 0, 0]
[[stage]]
steps = $2
[output]
dir = "$work/out"
csv_interval = $2
EOF
}

for law in hertz linear; do
  t_crit=$t_hertz
  [ "$law" = linear ] && t_crit=$t_linear
  for ratio in "${ratios[@]}"; do
    for speed in 0.05 0.5 1.5; do
      es=()
      for half_gap in 0.00105 0.001071 0.0010937; do
        dt=$(/usr/bin/python3 -c "print($t_crit * $ratio)")
        steps=$(/usr/bin/python3 -c "print(int(0.004 / $dt) + 1)")
        scenario "$law" "$steps" "$speed" "$dt" "$half_gap" > "$work/s.toml"
        "$sable" run "$work/s.toml" --overwrite > /dev/null 2>&1
        es+=("$(/usr/bin/python3 -c "
import csv, math
rows = list(csv.DictReader(open('$work/out/series.csv')))
print(math.sqrt(float(rows[-1]['kinetic_energy_J']) / float(rows[0]['kinetic_energy_J'])))")")
      done
      /usr/bin/python3 -c "
e = [float(x) for x in '${es[*]}'.split()]
print(f'$law dt/t_crit = $ratio relative speed {2 * $speed:g} m/s: e in [{min(e):.3f}, {max(e):.3f}]')"
    done
  done
done
