#!/usr/bin/env python3
"""Scale benchmark (issue 17): humanoid38 logs of N frames, calibrated with
the default method on --threads 2; per size the median wall time and peak
RSS over --runs runs, and the worst error against the simulation truth.

    python3 scripts/scale_timing.py --build build --frames 25000 250000 --runs 3

Quote the medians from one sitting (the machine is shared and noisy). A
timing script, not a test: nothing here asserts a speed.
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run_timed(cmd):
    """Runs cmd under GNU time; returns (wall s, peak RSS MB, exit code)."""
    with tempfile.NamedTemporaryFile("r", suffix=".time") as t:
        proc = subprocess.run(["/usr/bin/time", "-f", "%e %M", "-o", t.name] + cmd,
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        wall, rss_kb = t.read().split()[-2:]
    return float(wall), float(rss_kb) / 1024.0, proc.returncode, proc.stderr


def worst_errors(calib_path, truth_path):
    """Worst |gain|, |bias| error over the joint sensors and worst marker
    position error (m) over the free markers, against the truth."""
    calib, truth = (yaml.safe_load(open(p)) for p in (calib_path, truth_path))
    tj = {s["name"]: s for s in truth["joint_sensors"]}
    gain = max(abs(s["gain"] - tj[s["name"]]["gain"]) for s in calib["joint_sensors"])
    bias = max(abs(s["bias"] - tj[s["name"]]["bias"]) for s in calib["joint_sensors"])
    tm = {m["name"]: m for m in truth["mocap"]["markers"]}
    marker = max(
        sum((a - b) ** 2 for a, b in zip(m["position"], tm[m["name"]]["position"])) ** 0.5
        for m in calib["mocap"]["markers"])
    return gain, bias, marker


def iterations(stderr):
    its = [int(l.split()[1]) for l in stderr.splitlines() if l.startswith("stac ")]
    return max(its) if its else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--frames", type=int, nargs="+", default=[25000, 250000])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--workdir", default=tempfile.gettempdir())
    a = ap.parse_args()
    apps = os.path.join(a.build, "apps")
    urdf = os.path.join(ROOT, "data", "humanoid38.urdf")
    truth = os.path.join(ROOT, "data", "humanoid38_truth.yaml")
    seed = os.path.join(ROOT, "data", "humanoid38_seed.yaml")
    rows = []
    for n in a.frames:
        log = os.path.join(a.workdir, "scale_h%d.csv" % n)
        out = os.path.join(a.workdir, "scale_h%d_calib.yaml" % n)
        subprocess.run([os.path.join(apps, "stac_simulate"), "--urdf", urdf, "--sensors", truth,
                        "--frames", str(n), "--log", log], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        walls, rsss, its = [], [], []
        for r in range(a.runs):
            wall, rss, rc, err = run_timed([os.path.join(apps, "stac_calib"), "--urdf", urdf,
                                            "--sensors", seed, "--log", log, "--threads", "2",
                                            "--output", out])
            walls.append(wall)
            rsss.append(rss)
            its.append(iterations(err))
            print("%7d frames run %d: %.1f s, %.0f MB, %d iterations, exit %d"
                  % (n, r + 1, wall, rss, its[-1], rc), flush=True)
            if rc != 0:
                sys.stderr.write(err)
        gain, bias, marker = worst_errors(out, truth)
        rows.append((n, statistics.median(walls), max(rsss), statistics.median(its), gain, bias,
                     marker))
        os.remove(log)
    print("\n| frames | median wall (s) | peak RSS (MB) | iterations | worst gain err "
          "| worst bias err (rad) | worst marker err (µm) |")
    print("|---|---|---|---|---|---|---|")
    for n, wall, rss, it, gain, bias, marker in rows:
        print("| %d | %.1f | %.0f | %g | %.4f | %.4f | %.0f |"
              % (n, wall, rss, it, gain, bias, marker * 1e6))
    if len(rows) >= 2:
        print("\ntime ratio %d/%d frames: %.2f (frames ratio %.0f)"
              % (rows[-1][0], rows[0][0], rows[-1][1] / rows[0][1], rows[-1][0] / rows[0][0]))


if __name__ == "__main__":
    main()
