#!/usr/bin/env bash
# The report's viewer in a real browser: a small compare (a `regions` method adds the per-region
# viewer) and a small failure gallery, each driven by scripts/report_browser.py in headless Chromium.
#   bash scripts/report-browser-test.sh [OUT_DIR]     (default: target/report-browser; screenshots in OUT_DIR/shots*)
# Needs the release binary (cargo build --release) and chromium (scripts/setup.sh installs it).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
out=${1:-target/report-browser}
bin=${PENUMBRA_BIN:-target/release/penumbra}
rm -rf "$out"
export PENUMBRA_NO_PROGRESS=1 PENUMBRA_CACHE="$out/cache"
"$bin" compare --scene analytic-square --set resolution=96 --repeats 1 --out "$out/compare" \
    --methods hard,pcss,regular:n=3,adaptive:preset=balanced,regions:target=0.05 >/dev/null
"$bin" failures --resolution 48 --frames 0 --samples 8 --methods hard,regular:n=3 --out "$out/failures" >/dev/null
python3 scripts/report_browser.py "$out/compare/report.html" --shots "$out/shots-compare"
python3 scripts/report_browser.py "$out/failures/report.html" --shots "$out/shots-failures"
# The size and load-time figure of results/report-viewer/, once, so its code runs in CI too.
python3 scripts/report_browser.py "$out/compare/report.html" --measure 1
echo "report browser test: $(($(date +%s) - start)) s wall clock"
