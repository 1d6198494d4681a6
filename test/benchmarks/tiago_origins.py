#!/usr/bin/env python3
"""TIAGo real data (../shared/realdata/tiago): 5 interleaved folds (posture i
held out in fold i mod 5), point 1 (x1, y1, z1) as a marker on
wrist_ft_tool_link, predicted on the held-out postures from the joint
readings. With and without --joint-origins, gains free and `fixed: [gain]`.

  python3 test/benchmarks/tiago_origins.py BUILD_DIR [OUT_DIR]

Converts the raw CSV itself (marker columns renamed, bookkeeping columns
dropped; the file is in metres and radians) and prints mean / RMS / worst
held-out error per configuration, in mm, the worst posture, the mean fit time
(summary.wall_time) and how many of the 5 fits failed their own checks.
ORIGIN_PRIOR=XYZ,RPY passes --origin-prior."""
import csv, math, os, re, subprocess, sys

build = sys.argv[1]
out = sys.argv[2] if len(sys.argv) > 2 else "/tmp/tiago_origins"
os.makedirs(out, exist_ok=True)
data = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../../shared/realdata/tiago")
data = os.environ.get("TIAGO_DIR", data if os.path.isdir(data) else "/work/shared/realdata/tiago")
urdf = os.path.join(data, "tiago_48_schunk.urdf")
JOINTS = ["torso_lift_joint"] + ["arm_%d_joint" % i for i in range(1, 8)]

rows = list(csv.DictReader(open(os.path.join(data, "qualisys_2021-11-30_static_postures.csv"))))

def write_log(path, rs):
    with open(path, "w") as f:
        f.write(",".join(["m1.x", "m1.y", "m1.z"] + JOINTS) + "\n")
        for r in rs:
            f.write(",".join([r["x1"], r["y1"], r["z1"]] + [r[j] for j in JOINTS]) + "\n")

def seed_yaml(fixed_gain):
    s = ["mocap:", "  sigma: 0.0005", "  markers:",
         "    - name: m1", "      link: wrist_ft_tool_link", "joint_sensors:"]
    for j in JOINTS:
        s += ["  - name: " + j, "    joint: " + j, "    sigma: 0.001"]
        if fixed_gain:
            s += ["    fixed: [gain]"]
    return "\n".join(s) + "\n"

def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0, 4):
        sys.exit("failed (%d): %s\n%s" % (p.returncode, " ".join(cmd), p.stderr))
    return p

configs = [("gains free", False, False), ("fixed: [gain]", True, False),
           ("gains free + origins", False, True), ("fixed: [gain] + origins", True, True)]
print("%-26s %8s %8s %8s %6s %8s %8s" % ("configuration", "mean", "RMS", "worst", "post.",
                                         "fit s", "suspect"))
for name, fixed_gain, origins in configs:
    seed = os.path.join(out, "seed_%d.yaml" % fixed_gain)
    open(seed, "w").write(seed_yaml(fixed_gain))
    errors, worst, times, suspect = [], (0, -1), [], 0
    for fold in range(5):
        train = [r for i, r in enumerate(rows) if i % 5 != fold]
        test = [(i, r) for i, r in enumerate(rows) if i % 5 == fold]
        log = os.path.join(out, "train_%d.csv" % fold)
        write_log(log, train)
        cal = os.path.join(out, "cal_%d_%d_%d.yaml" % (fixed_gain, origins, fold))
        cmd = [os.path.join(build, "apps/stac_calib"), "--urdf", urdf, "--log", log,
               "--sensors", seed, "--output", cal, "--quiet"]
        if origins:
            cmd += ["--joint-origins", ",".join(JOINTS)]
            if os.environ.get("ORIGIN_PRIOR"):
                cmd += ["--origin-prior", os.environ["ORIGIN_PRIOR"]]
        suspect += run(cmd).returncode == 4
        times.append(float(re.search(r"wall_time: (\S+)", open(cal).read()).group(1)))
        for i, r in test:
            one = os.path.join(out, "posture.csv")
            write_log(one, [r])
            p = run([os.path.join(build, "apps/stac_eval"), "--urdf", urdf, "--sensors", cal,
                     "--log", one, "--use", "joint", "--predict", "marker"])
            line = [l for l in p.stdout.splitlines() if l.strip().startswith("marker m1")][0]
            e = float(line.split()[2])
            errors.append(e)
            worst = max(worst, (e, i))
    mean = sum(errors) / len(errors)
    rms = math.sqrt(sum(e * e for e in errors) / len(errors))
    print("%-26s %8.3f %8.3f %8.3f %6d %8.3f %8d" % (name, 1e3 * mean, 1e3 * rms, 1e3 * worst[0],
                                                     worst[1], sum(times) / len(times), suspect))
