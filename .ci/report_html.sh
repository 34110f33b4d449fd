#!/usr/bin/env bash
# Headless-browser test of report.html: `rocking analyze -o DIR` on the bundled stone,
# then Debian's Chromium opens DIR/report.html with no network and
#  * --dump-dom: the page's own check must have run (#status data-status="drawn", set after the
#    3D canvas is drawn; "error" if window.onerror fired), #errors must be empty, the canvas
#    must have non-blank pixels (data-nonblank, counted by the page with getImageData), and a
#    synthetic hover on a mark must show its kind, R and flock (data-tooltip);
#  * --screenshot: written to results/report_html/report_screenshot.png.
# Usage: .ci/report_html.sh [path/to/rocking] (default target/debug/rocking).
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-target/debug/rocking}"
test -x "$bin" || { echo "report_html: $bin not built" >&2; exit 1; }
browser="$(command -v chromium || command -v chromium-browser || true)"
test -n "$browser" || { echo "report_html: chromium is not installed" >&2; exit 1; }
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
"$bin" analyze --unit mm -o "$dir/out" > "$dir/summary.txt"
page="file://$dir/out/report.html"
# a private profile; --proxy-server to a closed port: the page must not need the network
flags=(--headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir="$dir/profile"
       --proxy-server=127.0.0.1:9 --virtual-time-budget=10000)
"$browser" "${flags[@]}" --dump-dom "$page" > "$dir/dom.html" 2> "$dir/browser.log"
status="$(grep -o '<div id="status"[^>]*>' "$dir/dom.html" || true)"
errors="$(sed -n 's:.*<pre id="errors">\([^<]*\)</pre>.*:\1:p' "$dir/dom.html")"
nonblank="$(echo "$status" | sed -n 's/.*data-nonblank="\([0-9]*\)".*/\1/p')"
echo "report_html: $status"
if ! echo "$status" | grep -q 'data-status="drawn"'; then
  echo "report_html: FAILED: the page did not finish drawing (errors: ${errors:-none})" >&2
  grep -i "console\|uncaught" "$dir/browser.log" >&2 || true
  exit 1
fi
if [ -n "$errors" ]; then
  echo "report_html: FAILED: script errors: $errors" >&2
  exit 1
fi
# hovering a mark (the page dispatches a mouse event on the first visible one) shows its kind,
# R with the unit, and its flock
if ! echo "$status" | grep -Eq 'data-tooltip="(stable|unstable|saddle) micro-equilibrium [^"]*R = [0-9.]+ mm [^"]*flock F[0-9]+'; then
  echo "report_html: FAILED: no tooltip with kind, R and flock on hovering a mark" >&2
  exit 1
fi
# the 760 × 620 canvas: the stone covers well over 5 % of it
if [ "${nonblank:-0}" -lt 20000 ]; then
  echo "report_html: FAILED: the 3D canvas is (nearly) blank: $nonblank non-white pixels" >&2
  exit 1
fi
mkdir -p results/report_html
"$browser" "${flags[@]}" --window-size=1250,1400 --screenshot="$PWD/results/report_html/report_screenshot.png" \
  "$page" 2>> "$dir/browser.log"
test -s results/report_html/report_screenshot.png
echo "report_html: OK ($nonblank non-blank canvas pixels, no script error); screenshot in results/report_html/"
