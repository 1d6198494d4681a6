#!/usr/bin/env bash
# The Python module's overhead against stac_calib (issue 16): the same
# calibration (humanoid38, 25,000 frames, paper seeding, defaults) run by
# the command and by `stac.calibrate` + `write_sensors`, alternating, each
# timed as a whole process (read, calibrate, write); prints every run and
# the medians.
#   test/benchmarks/python_overhead.sh BUILD_DIR [FRAMES] [RUNS]
set -euo pipefail
build="$(cd "${1:?BUILD_DIR}" && pwd)"
frames="${2:-25000}"
runs="${3:-3}"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
data="$here/data"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
"$build/apps/stac_simulate" --urdf "$data/humanoid38.urdf" --sensors "$data/humanoid38_truth.yaml" \
  --frames "$frames" --log "$out/log.csv" --seed 7 2>/dev/null
cat > "$out/calibrate.py" <<PY
import stac
robot = stac.RobotModel.from_urdf("$data/humanoid38.urdf")
seed = stac.read_sensors("$data/humanoid38_seed.yaml", robot)
log = stac.read_log("$out/log.csv")
stac.write_sensors("$out/py.yaml", stac.calibrate(robot, seed, log))
PY
seconds() { local t0 t1; t0=$(date +%s.%N); "$@" >/dev/null 2>&1; t1=$(date +%s.%N); echo "$t1 - $t0" | bc; }
cli=() py=()
for i in $(seq "$runs"); do
  cli+=("$(seconds "$build/apps/stac_calib" --urdf "$data/humanoid38.urdf" --log "$out/log.csv" \
    --sensors "$data/humanoid38_seed.yaml" --output "$out/cli.yaml" --quiet)")
  py+=("$(PYTHONPATH="$build/python" seconds /usr/bin/python3 "$out/calibrate.py")")
  echo "run $i: stac_calib ${cli[-1]} s, python ${py[-1]} s"
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
mc="$(median "${cli[@]}")" mp="$(median "${py[@]}")"
echo "median of $runs: stac_calib $mc s, python $mp s, overhead $(echo "scale=2; 100 * ($mp - $mc) / $mc" | bc) %"
if diff <(sed 's/^  wall_time: .*//' "$out/cli.yaml") <(sed 's/^  wall_time: .*//' "$out/py.yaml") >/dev/null; then
  echo "outputs identical but for wall_time"
else
  echo "outputs DIFFER"
fi
