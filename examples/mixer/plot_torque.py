#!/usr/bin/python3
"""The torque on the mixer's paddle against time (examples/mixer/run.sh).

    /usr/bin/python3 examples/mixer/plot_torque.py OUT

reads OUT/series.csv (the run's time series: wall_paddle_tz_Nm is the torque the beads exert
on the paddle about its turning axis z, N m), OUT/run.log (where the settling stage ended)
and mixer.toml (dt, the stirring rate), and writes OUT/torque.png (the torque against time
and turns) and OUT/torque.json: the mean torque over the second half of the stirring stage,
its standard deviation there, and the drag force it stands for at the paddle's mid-radius
(M / r, r = 9 mm: half the paddle's 18 mm arm).
"""
import json
import re
import sys
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

MID_RADIUS = 0.009  # m
SCENARIO = Path(__file__).resolve().parent / "mixer.toml"


def main() -> int:
    if len(sys.argv) != 2:
        print("usage: plot_torque.py OUT", file=sys.stderr)
        return 2
    out = Path(sys.argv[1])
    data = np.genfromtxt(out / "series.csv", delimiter=",", names=True)
    for column in ("time_s", "wall_paddle_tz_Nm"):
        if column not in data.dtype.names:
            print(f"{out / 'series.csv'}: no column {column}", file=sys.stderr)
            return 1
    t, tz = data["time_s"], data["wall_paddle_tz_Nm"]
    scenario = tomllib.loads(SCENARIO.read_text())
    dt = scenario["simulation"]["dt"]
    rate = scenario["stage"][1]["wall_rotation"]["paddle"]["rate"]
    settled = re.search(r"^stage 'settle' done: (\d+) steps", (out / "run.log").read_text(), re.M)
    if not settled:
        print(f"{out / 'run.log'}: no line \"stage 'settle' done\"", file=sys.stderr)
        return 1
    start = int(settled.group(1)) * dt
    late = t >= start + 0.5 * (t[-1] - start)
    mean, std = float(np.mean(tz[late])), float(np.std(tz[late]))
    summary = {"mean_torque_Nm": mean, "std_torque_Nm": std, "samples": int(late.sum()),
               "drag_at_mid_radius_N": mean / MID_RADIUS, "stir_start_s": float(start)}
    (out / "torque.json").write_text(json.dumps(summary, indent=2) + "\n")
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(t, tz * 1e3, lw=0.8, label="torque on the paddle about z")
    ax.axhline(mean * 1e3, color="k", ls="--", lw=0.8, label=f"mean, second half: {mean*1e3:.3g} mN m")
    ax.axvline(start, color="grey", lw=0.6)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("torque (mN m)")
    top = ax.twiny()
    top.set_xlim(ax.get_xlim())
    ticks = [start + k * 0.25 for k in range(5) if start + k * 0.25 <= t[-1]]
    top.set_xticks(ticks)
    top.set_xticklabels([f"{(x - start) * rate / (2 * np.pi):.2g}" for x in ticks])
    top.set_xlabel("turns")
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "torque.png", dpi=120)
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
