#!/usr/bin/env bash
# Refactoring guard (issue 12): the calibration YAML of every method on the
# bundled robots, with the wall time blanked, so that two builds can be
# compared byte for byte:
#   test/regression/outputs.sh BUILD_DIR OUT_DIR [small|full]
# Logs are simulated by BUILD_DIR's stac_simulate with fixed seeds (so two
# builds whose simulators agree see the same logs; compare the logs too).
# small: gimbal2 (bundled log), hand24 and humanoid38 at 2,000 frames;
# full: also humanoid38 at 25,000 frames (minutes: the joint method).
set -euo pipefail
build="$(cd "${1:?BUILD_DIR}" && pwd)"
out="${2:?OUT_DIR}"
size="${3:-small}"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
mkdir -p "$out"
out="$(cd "$out" && pwd)"
data="$here/data"
"$build/apps/stac_simulate" --urdf "$data/hand24.urdf" --sensors "$data/hand24_truth.yaml" \
  --frames 2000 --log "$out/hand24.csv" --seed 3
"$build/apps/stac_simulate" --urdf "$data/humanoid38.urdf" --sensors "$data/humanoid38_truth.yaml" \
  --frames 2000 --log "$out/humanoid38.csv" --seed 5
cp "$data/gimbal2_example.csv" "$out/gimbal2.csv"
cases="gimbal2 hand24 humanoid38"
if [ "$size" = full ]; then
  "$build/apps/stac_simulate" --urdf "$data/humanoid38.urdf" \
    --sensors "$data/humanoid38_truth.yaml" --frames 25000 --log "$out/humanoid38_25k.csv" --seed 7
  cases="$cases humanoid38_25k"
fi
for c in $cases; do
  robot="${c%_25k}"
  for method in stac joint ekf classical; do
    f="$out/${c}_${method}.yaml"
    rc=0
    "$build/apps/stac_calib" --urdf "$data/$robot.urdf" --log "$out/$c.csv" \
      --sensors "$data/${robot}_seed.yaml" --method "$method" --threads 2 --quiet \
      --output "$f" --joint-angles "$out/${c}_${method}_q.csv" > "$out/${c}_${method}.stdout" \
      2> "$out/${c}_${method}.stderr" || rc=$?
    echo "$c $method exit $rc" >> "$out/exit_codes.txt"
    [ -f "$f" ] && sed -i -E 's/^(  wall_time: ).*/\1-/' "$f"
    sed -i -E 's/[0-9.]+ s\b/- s/g' "$out/${c}_${method}.stdout" || true
  done
done
echo "outputs in $out" >&2
