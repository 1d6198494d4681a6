#!/usr/bin/env bash
# Renders a stac_calib --report file to PNG with headless Chromium, to look at
# it (not part of ctest: it needs a browser). Without a report argument it
# calibrates the bundled gimbal2 example first.
#
#   test/report_screenshot.sh [BUILD_DIR] [REPORT.html] [OUT.png] [WIDTH,HEIGHT]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
report="${2:-}"
out="${3:-$PWD/report.png}"
size="${4:-1200,3600}"
browser="$(command -v chromium || command -v chromium-browser || command -v google-chrome || true)"
if [ -z "$browser" ]; then
  echo "report_screenshot: no chromium found (apt-get install chromium)" >&2
  exit 2
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
if [ -z "$report" ]; then
  report="$tmp/report.html"
  "$build/apps/stac_calib" --urdf "$here/data/gimbal2.urdf" --log "$here/data/gimbal2_example.csv" \
    --sensors "$here/data/gimbal2_seed.yaml" --output "$tmp/calibration.yaml" \
    --report "$report" --quiet > /dev/null
fi
# --no-sandbox: CI containers run as root; the page has no scripts anyway.
"$browser" --headless --no-sandbox --disable-gpu --hide-scrollbars \
  --user-data-dir="$tmp/profile" --window-size="$size" \
  --screenshot="$out" "file://$(cd "$(dirname "$report")" && pwd)/$(basename "$report")" \
  > "$tmp/browser.log" 2>&1 || { cat "$tmp/browser.log" >&2; exit 1; }
echo "$out"
