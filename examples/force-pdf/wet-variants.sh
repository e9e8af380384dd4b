#!/usr/bin/env bash
# Which of the preparation, the liquid distribution and the contact stiffness moves the wet
# force PDF of Richefeu et al. (2009) (examples/force-pdf/wet.toml, their S6 and S7) towards
# the paper's alpha_w ~ 4 and z = 2.97 + 3.13? Each variant is wet.toml with one thing
# changed, run by run.sh wet in its own tree; the table at the end puts them side by side.
# Usage: examples/force-pdf/wet-variants.sh [VARIANT...]   (default: all; 80-430 s each on one core)
#   baseline        wet.toml as it is
#   prep-1pa        compacted dry at 1 Pa instead of 10 Pa before wetting
#   prep-100pa      compacted dry at 100 Pa (denser, more locked-in compressive forces)
#   prep-mu0        compacted dry at 10 Pa without friction (mu = 0; a denser, better
#                   coordinated packing), friction 0.4 from the wetting stage on
#   damping-100     background damping 100 /s instead of 10 /s in every stage (a faster quench)
#   contacts-only   the liquid put into bridges at contacts only (liquid_pairs = "contacts")
#                   instead of every pair within the debonding distance
#   lost            the liquid of a ruptured bridge leaves the sample (ruptured_liquid =
#                   "lost"): bridges formed later have no liquid and break on separation
#   water-0.0035    half the paper's water content (shorter bridges: lambda ~ V^(1/2),
#                   delta_max ~ V^(1/3))
#   water-0.014     twice the paper's water content
#   water-0.0028    0.007 read as a volume fraction of the grains' volume (0.007 / 2.5, the
#                   grains' density over the liquid's): the paper says "gravimetric"
#   stiff           kn = kt = 1500 N/m instead of 150 (f0 / kn = 3e-7 m = 2e-4 <d>)
#   mu0-contacts    prep-mu0 and contacts-only together
# Environment: SABLE (default build/release/bin/sable), SABLE_OUT (default out): writes
# SABLE_OUT/force-pdf/wet-variants/VARIANT/ (a copy of this folder, the run, its summary.json)
# and SABLE_OUT/force-pdf/wet-variants/summary.json (every variant's numbers).
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
SABLE="$(realpath "${SABLE:-build/release/bin/sable}")"
out="$(realpath -m "${SABLE_OUT:-out}")/force-pdf/wet-variants"
all="baseline prep-1pa prep-100pa prep-mu0 damping-100 contacts-only lost water-0.0035
  water-0.014 water-0.0028 stiff mu0-contacts"
variants="${*:-$all}"
if [ ! -x "$SABLE" ]; then bash scripts/build.sh release > /dev/null; fi

# The sed expressions that make VARIANT's wet.toml from the example's (none: baseline).
edits() {
  case "$1" in
    baseline | prep-mu0) ;;
    prep-1pa) echo 's/^wall_stress = { box = 10.0 }/wall_stress = { box = 1.0 }/' ;;
    prep-100pa) echo 's/^wall_stress = { box = 10.0 }/wall_stress = { box = 100.0 }/' ;;
    damping-100) echo 's/^viscous_damping = 10.0/viscous_damping = 100.0/' ;;
    contacts-only | mu0-contacts) printf '%s\n' 's/^water_content = 0.007/water_content = 0.007\nliquid_pairs = "contacts"/' ;;
    lost) echo 's/^ruptured_liquid = "grains"/ruptured_liquid = "lost"/' ;;
    water-0.0035) echo 's/^water_content = 0.007/water_content = 0.0035/' ;;
    water-0.014) echo 's/^water_content = 0.007/water_content = 0.014/' ;;
    water-0.0028) echo 's/^water_content = 0.007/water_content = 0.0028/' ;;
    stiff) printf '%s\n' 's/^k\([nt]\) = 150.0/k\1 = 1500.0/' ;;
    *)
      echo "unknown variant '$1' (expected one of: $(tr -s ' \n' ' ' <<< "$all"))" >&2
      exit 2
      ;;
  esac
}

# prep-mu0, mu0-contacts: wet.toml's first stage alone, frictionless, run first; the variant
# resumes from its end (run.sh's SABLE_WET_RESUME).
frictionless_prep() {
  local dir="$1"
  awk '/^\[\[stage\]\]/ { ++n } /^\[output\]/ { n = 0 } n <= 1' "$dir/examples/force-pdf/wet.toml" |
    sed 's/^friction = 0.4/friction = 0.0/' > "$dir/prep-mu0.toml"
  "$SABLE" run "$dir/prep-mu0.toml" --out "$dir/prep" --threads 1 2> "$dir/prep.log" ||
    { tail -5 "$dir/prep.log" >&2; exit 1; }
  echo "$dir/prep/snapshots/end_of_stage_1.h5"
}

for v in $variants; do
  ex=$(edits "$v")
  dir="$out/$v"
  rm -rf "$dir"
  mkdir -p "$dir/examples/force-pdf"
  cp "$root"/examples/force-pdf/{run.sh,wet.toml,report.py,wet_report.py} "$dir/examples/force-pdf/"
  if [ -n "$ex" ]; then
    sed -i -e "$ex" "$dir/examples/force-pdf/wet.toml"
    if cmp -s "$root/examples/force-pdf/wet.toml" "$dir/examples/force-pdf/wet.toml"; then
      echo "variant $v changed nothing in wet.toml (sed: $ex)" >&2
      exit 1
    fi
  fi
  resume=""
  case "$v" in prep-mu0 | mu0-contacts) resume=$(frictionless_prep "$dir") ;; esac
  echo "== $v"
  (cd "$dir" && SABLE="$SABLE" SABLE_OUT="$dir/out" SABLE_WET_RESUME="$resume" \
    bash examples/force-pdf/run.sh wet > "$dir/report.txt")
done

/usr/bin/python3 - "$out" $variants <<'EOF'
import json, os, sys
out, names = sys.argv[1], sys.argv[2:]
rows, table = {}, []
for n in names:
    s = json.load(open(os.path.join(out, n, "out", "force-pdf", "wet", "summary.json")))
    rows[n] = {k: s[k] for k in ("0pa", "100pa", "run_seconds")}
    a, b = s["0pa"], s["100pa"]
    table.append(f"{n:14s} {a['alpha_w_tensile']:5.2f} {a['alpha_w_compressive']:5.2f} "
                 f"{a['z_compressive']:5.2f} {a['z_tensile']:5.2f} "
                 f"{a['tensile_at_gaps_fraction']:5.2f} {a['max_compressive_over_f0']:5.2f} | "
                 f"{b['alpha_w_tensile']:5.2f} {b['alpha_w_compressive']:5.2f} "
                 f"{b['z_compressive']:5.2f} {b['z_tensile']:5.2f} | {s['run_seconds']:4.0f}")
json.dump(rows, open(os.path.join(out, "summary.json"), "w"), indent=2)
print(f"{'':14s} 0 Pa (S6): alpha_w t, c; z c, t; gap share of t; max f/f0 | "
      "100 Pa (S7): alpha_w t, c; z c, t | run s")
print("\n".join(table))
print(f"{'paper':14s} {4.0:5.2f} {4.0:5.2f} {2.97:5.2f} {3.13:5.2f} {'':5s} {2.0:5.2f}")
print(f"wrote {os.path.join(out, 'summary.json')}")
EOF
