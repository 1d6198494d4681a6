#!/usr/bin/env python3
"""Held-out error on the real TIAGo recording (../shared/realdata/tiago), as
its README measures FIGAROH: 5 interleaved folds (posture i held out in fold
i mod 5); calibrate on the other postures, predict point 1 of each held-out
posture from the joint readings (stac_eval --use joint), Euclidean error.

  scripts/tiago_folds.py BUILD_DIR [--markers 1|4] [--fixed-gain]
                         [--joint-origins] [-- extra stac_calib arguments]

The raw export is read as it is (no converter): the sensors file maps the
point columns onto markers on wrist_ft_tool_link (`columns:`) and ignores
the rest (`ignore_columns:`); each fold's log is the raw file's header and
rows. With --markers 4 the four points of the hand's rigid body are four
markers. Prints per fold the exit code, iterations, convergence and wall
time, then mean, RMS and worst held-out error over the 37 postures (mm).
Plain Python, no numpy.
"""
import argparse, csv, json, math, os, re, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.environ.get("TIAGO_DIR", os.path.join(HERE, "..", "..", "shared", "realdata", "tiago"))
URDF = os.path.join(DATA, "tiago_48_schunk.urdf")
LOG = os.path.join(DATA, "qualisys_2021-11-30_static_postures.csv")
JOINTS = ["torso_lift_joint"] + ["arm_%d_joint" % i for i in range(1, 8)]
BOOKKEEPING = ["shipped_row", "t_start_robot", "t_end_robot", "marker_std_mm"]


def sensors_yaml(markers, fixed_gain):
    lines = ["mocap:", "  sigma: 0.001", "  markers:"]
    for k in range(1, markers + 1):
        lines.append("    - {name: p%d, link: wrist_ft_tool_link, columns: [x%d, y%d, z%d]}"
                     % (k, k, k, k))
    lines.append("joint_sensors:")
    fixed = ", fixed: [gain]" if fixed_gain else ""
    for j in JOINTS:
        lines.append("  - {name: %s, joint: %s, sigma: 0.001%s}" % (j, j, fixed))
    unused = ["%s%d" % (c, k) for k in range(markers + 1, 5) for c in "xyz"]
    lines.append("ignore_columns: [%s]" % ", ".join(unused + BOOKKEEPING))
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--markers", type=int, default=1, choices=[1, 4])
    ap.add_argument("--fixed-gain", action="store_true")
    ap.add_argument("--joint-origins", action="store_true")
    a, extra = ap.parse_known_args()
    extra = [x for x in extra if x != "--"]
    if a.joint_origins:
        extra += ["--joint-origins", ",".join(JOINTS)]
    with open(LOG) as f:
        header, *rows = f.read().splitlines()
    calib = os.path.join(a.build, "apps", "stac_calib")
    evalp = os.path.join(a.build, "apps", "stac_eval")
    errors, times = [], []
    with tempfile.TemporaryDirectory() as tmp:
        seed = os.path.join(tmp, "seed.yaml")
        open(seed, "w").write(sensors_yaml(a.markers, a.fixed_gain))
        for fold in range(5):
            train = os.path.join(tmp, "train.csv")
            open(train, "w").write("\n".join([header] + [r for i, r in enumerate(rows)
                                                         if i % 5 != fold]) + "\n")
            out = os.path.join(tmp, "cal.yaml")
            p = subprocess.run([calib, "--urdf", URDF, "--log", train, "--sensors", seed,
                                "--output", out, "--quiet"] + extra,
                               capture_output=True, text=True)
            if p.returncode not in (0, 4):
                sys.exit("fold %d: stac_calib exit %d\n%s" % (fold, p.returncode, p.stderr))
            text = open(out).read()
            field = lambda k: re.search(r"^\s*%s: (\S+)" % k, text, re.M).group(1)
            times.append(float(field("wall_time")))
            print("fold %d: exit %d, iterations %s, converged %s, %.2f s"
                  % (fold, p.returncode, field("iterations"), field("converged"), times[-1]))
            for line in p.stderr.splitlines():
                if "verdict" in line or "suspect" in line:
                    print("   ", line)
            for i, r in enumerate(rows):
                if i % 5 != fold:
                    continue
                one = os.path.join(tmp, "posture.csv")
                open(one, "w").write(header + "\n" + r + "\n")
                js = os.path.join(tmp, "e.json")
                q = subprocess.run([evalp, "--urdf", URDF, "--sensors", out, "--log", one,
                                    "--use", "joint", "--predict", "marker", "--json", js],
                                   capture_output=True, text=True)
                if q.returncode != 0:
                    sys.exit("stac_eval exit %d\n%s" % (q.returncode, q.stderr))
                errors.append((json.load(open(js))["per_sensor"]["p1"]["mae"] * 1000, i))
    e = [x for x, _ in errors]
    worst = max(errors)
    print("held-out point 1 over %d postures: mean %.2f mm, RMS %.2f mm, worst %.2f mm "
          "(posture %d); fit %.2f s on average"
          % (len(e), sum(e) / len(e), math.sqrt(sum(x * x for x in e) / len(e)), worst[0],
             worst[1], sum(times) / len(times)))


if __name__ == "__main__":
    main()
