#!/usr/bin/env bash
# Issue 4's figures: humanoid38, 24 markers, 25,000 frames (250 s at 100 Hz),
# the paper's seeding; wall time and peak memory of stac_calib for
# --method stac and joint with 1 and 2 threads, outer iterations and final
# RMS per group. Usage: calibration_bench.sh BUILD_DIR [FRAMES]
set -euo pipefail
build="${1:-build}"
frames="${2:-25000}"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$build/apps/stac_simulate" --urdf "$here/data/humanoid38.urdf" \
  --sensors "$here/data/humanoid38_truth.yaml" --frames "$frames" --log "$tmp/log.csv" --seed 7
printf "%-6s %-7s %9s %10s %6s  %s\n" method threads wall_s peak_MB iters "final RMS (marker m, joint, tendon)"
for method in stac joint; do
  for threads in 1 2; do
    /usr/bin/time -f "%e %M" -o "$tmp/time" "$build/apps/stac_calib" \
      --urdf "$here/data/humanoid38.urdf" --log "$tmp/log.csv" \
      --sensors "$here/data/humanoid38_seed.yaml" --method "$method" --threads "$threads" \
      --output "$tmp/cal_${method}_${threads}.yaml" --quiet > "$tmp/out" 2>&1 || true
    read -r wall kb < "$tmp/time"
    iters=$(grep -E "^  iterations:" "$tmp/cal_${method}_${threads}.yaml" | awk '{print $2}')
    rms=$(grep -E "^  rms_after:" "$tmp/cal_${method}_${threads}.yaml" | sed 's/  rms_after: //')
    printf "%-6s %-7s %9s %10d %6s  %s\n" "$method" "$threads" "$wall" "$((kb / 1024))" "$iters" "$rms"
  done
done
