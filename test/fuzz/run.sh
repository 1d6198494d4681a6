#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang, ASan + UBSan; build-fuzz/) and runs
# the four of them at once for SECONDS each, seeded with data/, the
# third-party robots (../shared/robots or $STAC_ROBOTS_DIR) and the saved
# corpus (test/fuzz/corpus/<target>/). Crashes, hangs (> 5 s) and
# allocations over 2 GB are kept in build-fuzz/fuzz-work/<target>/artifacts/
# and the run goes on. At the end each target's corpus is minimised
# (-merge=1) back into test/fuzz/corpus/<target>/, which the default test
# suite replays (fuzz_replay_test); only inputs up to 3 KB are kept there, so
# that the saved corpus stays small (under 1 MB).
# SECONDS=0 only re-minimises the last run's corpus.
#
#   bash test/fuzz/run.sh 1800            # the issue's 30 minutes each
#   STAC_FUZZ_NICE=19 bash test/fuzz/run.sh 600
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
seconds="${1:?usage: test/fuzz/run.sh SECONDS}"
build="$here/build-fuzz"
work="$build/fuzz-work"
robots="${STAC_ROBOTS_DIR:-$here/../shared/robots}"
targets=(log_reader sensors_reader urdf_loader urdf_patcher)

CC=clang CXX=clang++ cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSTAC_FUZZ=ON >/dev/null
cmake --build "$build" -j "${STAC_FUZZ_JOBS:-2}"

seeds() {  # target -> the files it starts from
  case "$1" in
    log_reader) ls "$here"/data/*.csv ;;
    sensors_reader) ls "$here"/data/*.yaml ;;
    *) ls "$here"/data/*.urdf; ls "$robots"/*.urdf 2>/dev/null || true ;;
  esac
}
max_len() { case "$1" in urdf_*) echo 16384 ;; *) echo 8192 ;; esac; }
saved_max() { echo 3072; }

for t in "${targets[@]}"; do
  [ "$seconds" -gt 0 ] || break
  rm -rf "$work/$t"
  mkdir -p "$work/$t/corpus" "$work/$t/seeds" "$work/$t/artifacts" "$here/test/fuzz/corpus/$t"
  seeds "$t" | xargs -r cp -t "$work/$t/seeds"
  cp -r "$here/test/fuzz/corpus/$t/." "$work/$t/seeds/"
  # -fork=1 with -ignore_*: a finding is saved and the run goes on.
  nice -n "${STAC_FUZZ_NICE:-19}" "$build/test/fuzz/fuzz_$t" -fork=1 -ignore_crashes=1 \
    -ignore_timeouts=1 -ignore_ooms=1 -max_total_time="$seconds" -rss_limit_mb=2048 \
    -malloc_limit_mb=2048 -timeout=5 -max_len="$(max_len "$t")" \
    -artifact_prefix="$work/$t/artifacts/" "$work/$t/corpus" "$work/$t/seeds" \
    >"$work/$t/log" 2>&1 &
done
wait || true

for t in "${targets[@]}"; do
  saved="$here/test/fuzz/corpus/$t"
  rm -rf "$work/$t/merged" "$work/$t/small" && mkdir -p "$work/$t/merged" "$work/$t/small"
  for from in "$saved" "$work/$t/corpus"; do  # (one cp each: both may hold a file)
    find "$from" -type f -size -"$(saved_max "$t")"c -exec cp -t "$work/$t/small" {} +
  done
  "$build/test/fuzz/fuzz_$t" -merge=1 -max_len="$(max_len "$t")" -timeout=5 \
    -rss_limit_mb=2048 "$work/$t/merged" "$work/$t/small" >"$work/$t/merge.log" 2>&1
  rm -rf "$saved" && mv "$work/$t/merged" "$saved"
  echo "$t: $(grep -E '^#[0-9]+' "$work/$t/log" | tail -1)"
  echo "$t: saved corpus $(ls "$saved" | wc -l) files, $(cat "$saved"/* | wc -c) bytes;" \
    "findings: $(ls "$work/$t/artifacts" | wc -l) (in $work/$t/artifacts)"
done
