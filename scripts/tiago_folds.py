#!/usr/bin/env python3
"""Held-out error on the real TIAGo recording (../shared/realdata/tiago), as
its README measures FIGAROH: 5 interleaved folds (posture i held out in fold
i mod 5), calibrate on the other postures, predict point 1 of each held-out
posture from the joint readings (stac_eval --use joint), Euclidean error.

  scripts/tiago_folds.py BUILD_DIR [--markers 1|4] [--fixed-gain] [-- extra stac_calib args]

Prints per fold the iterations, convergence and verdict, then the mean, RMS
and worst held-out error over the 37 postures (mm). Plain Python, no numpy.
"""
import argparse, csv, json, math, os, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "shared", "realdata", "tiago")
URDF = os.path.join(DATA, "tiago_48_schunk.urdf")
LOG = os.path.join(DATA, "qualisys_2021-11-30_static_postures.csv")
JOINTS = ["torso_lift_joint"] + ["arm_%d_joint" % i for i in range(1, 8)]


def sensors_yaml(markers, fixed_gain):
    lines = ["mocap:", "  sigma: 0.001", "  frame: {translation: [0, 0, 0], rpy: [0, 0, 0]}",
             "  markers:"]
    for k in range(1, markers + 1):
        lines.append("    - {name: p%d, link: wrist_ft_tool_link, position: [0, 0, 0]}" % k)
    lines.append("joint_sensors:")
    fixed = ", fixed: [gain]" if fixed_gain else ""
    for j in JOINTS:
        lines.append("  - {name: %s, joint: %s, gain: 1.0, bias: 0.0, sigma: 0.001%s}" % (j, j, fixed))
    return "\n".join(lines) + "\n"


def write_log(path, rows, markers):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        head = []
        for k in range(1, markers + 1):
            head += ["p%d.x" % k, "p%d.y" % k, "p%d.z" % k]
        w.writerow(head + JOINTS)
        for r in rows:
            vals = []
            for k in range(1, markers + 1):
                vals += [r["x%d" % k], r["y%d" % k], r["z%d" % k]]
            w.writerow(vals + [r[j] for j in JOINTS])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--markers", type=int, default=1, choices=[1, 4])
    ap.add_argument("--fixed-gain", action="store_true")
    ap.add_argument("extra", nargs="*")
    a, rest = ap.parse_known_args()
    a.extra = [x for x in a.extra + rest if x != "--"]
    rows = list(csv.DictReader(open(LOG)))
    calib = os.path.join(a.build, "apps", "stac_calib")
    evalp = os.path.join(a.build, "apps", "stac_eval")
    errors = []
    with tempfile.TemporaryDirectory() as tmp:
        seed = os.path.join(tmp, "seed.yaml")
        open(seed, "w").write(sensors_yaml(a.markers, a.fixed_gain))
        one = os.path.join(tmp, "one.yaml")
        for fold in range(5):
            train = [r for i, r in enumerate(rows) if i % 5 != fold]
            test = [(i, r) for i, r in enumerate(rows) if i % 5 == fold]
            tl = os.path.join(tmp, "train.csv")
            write_log(tl, train, a.markers)
            out = os.path.join(tmp, "cal.yaml")
            p = subprocess.run([calib, "--urdf", URDF, "--log", tl, "--sensors", seed,
                                "--output", out, "--quiet"] + a.extra,
                               capture_output=True, text=True)
            if p.returncode not in (0, 4):
                sys.exit("fold %d: stac_calib exit %d\n%s" % (fold, p.returncode, p.stderr))
            text = open(out).read()
            it = next((l.split(":")[1].strip() for l in text.splitlines()
                       if l.strip().startswith("iterations:")), "?")
            conv = next((l.split(":")[1].strip() for l in text.splitlines()
                         if l.strip().startswith("converged:")), "?")
            print("fold %d: exit %d, iterations %s, converged %s" % (fold, p.returncode, it, conv))
            for line in p.stderr.splitlines():
                if "verdict" in line or "suspect" in line:
                    print("   ", line)
            # Point 1 only is predicted: the calibration's other markers are
            # dropped from the evaluation's sensors file by evaluating p1.
            for i, r in test:
                tl1 = os.path.join(tmp, "test.csv")
                write_log(tl1, [r], a.markers)
                js = os.path.join(tmp, "e.json")
                q = subprocess.run([evalp, "--urdf", URDF, "--sensors", out, "--log", tl1,
                                    "--use", "joint", "--predict", "marker", "--json", js],
                                   capture_output=True, text=True)
                if q.returncode != 0:
                    sys.exit("stac_eval exit %d\n%s" % (q.returncode, q.stderr))
                errors.append((json.load(open(js))["per_sensor"]["p1"]["mae"] * 1000, i))
    e = [x for x, _ in errors]
    worst = max(errors)
    print("held-out point 1 over %d postures: mean %.2f mm, RMS %.2f mm, worst %.2f mm (posture %d)"
          % (len(e), sum(e) / len(e), math.sqrt(sum(x * x for x in e) / len(e)), worst[0], worst[1]))


if __name__ == "__main__":
    main()
