#!/usr/bin/env bash
# Checks that a report.html is self-contained and renders cleanly in headless Chromium.
# Usage: scripts/check_report.sh path/to/report.html [screenshot.png]
# Needs: chromium (apt-get install -y chromium). Exit status 0 = all checks passed.
set -euo pipefail

html=${1:?usage: $0 report.html [screenshot.png]}
shot=${2:-/tmp/report_check.png}
chrome=${CHROMIUM:-chromium}
[[ -f $html ]] || { echo "no such file: $html" >&2; exit 2; }
command -v "$chrome" >/dev/null || { echo "$chrome not found: apt-get install -y chromium" >&2; exit 2; }
html=$(realpath "$html")
fail=0

# 1. Static: nothing may reference an external resource. The one script is the viewer's, inline.
for pat in 'src="http' "src='http" 'href="http' '<script src' '<link' 'http://' 'https://' '@import' 'url(' 'fetch(' 'XMLHttpRequest'; do
  if grep -qiF -- "$pat" "$html"; then echo "FAIL: contains $pat"; fail=1; fi
done
scripts=$(grep -o '<script' "$html" | wc -l || true)
[[ $scripts -le 1 ]] || { echo "FAIL: $scripts scripts, at most the viewer's one"; fail=1; }
imgs=$(grep -o '<img ' "$html" | wc -l || true)   # a page without pictures (a results folder) has none
data=$(grep -o '<img src="data:image/' "$html" | wc -l || true)
[[ $imgs -eq $data ]] || { echo "FAIL: $imgs <img>, only $data with data:image/ src"; fail=1; }
echo "static: $imgs images, all data URIs: $([[ $imgs -eq $data ]] && echo yes || echo no)"

# 2. Chromium, offline (every host resolves to nothing) with a throw-away profile.
profile=$(mktemp -d)
log=$(mktemp)
dom=$(mktemp)
trap 'rm -rf "$profile" "$log" "$dom"' EXIT
flags=(--headless --no-sandbox --disable-gpu --disable-background-networking --disable-component-update
  --disable-sync --no-first-run --user-data-dir="$profile" --host-resolver-rules="MAP * ~NOTFOUND"
  --enable-logging=stderr)
timeout 120 "$chrome" "${flags[@]}" --v=0 --window-size=1200,2000 --screenshot="$shot" "file://$html" 2>"$log" >/dev/null || true
# --v=1 also logs every URL request (NotifyBeforeURLRequest), which shows any fetch the page makes.
timeout 120 "$chrome" "${flags[@]}" --v=1 --dump-dom "file://$html" 2>>"$log" >"$dom" || true

[[ -s $shot ]] || { echo "FAIL: no screenshot written"; fail=1; }
# Console messages, failed loads and blocked requests all land in the log (google_apis/ lines
# are Chromium's own sign-in fetch failing offline, not the page).
if grep -E 'CONSOLE|Uncaught|net::ERR|Failed to load|Refused to' "$log" | grep -v 'google_apis/'; then
  echo "FAIL: console errors or failed loads above"; fail=1
fi
# Chromium's own background calls (sign-in, updater, clock) are not the page's; all resolve to nothing.
own='^https?://(accounts\.google\.com|update\.googleapis\.com|clients2\.google\.com)/'
requests=$(grep -o 'NotifyBeforeURLRequest: [^ ]*' "$log" | cut -d' ' -f2 | grep -Ev '^(file|data):' | grep -Ev "$own" || true)
if [[ -n $requests ]]; then echo "FAIL: the page requested:"; echo "$requests"; fail=1; fi
# The viewer adds a stage and an overlay image per viewer (class v-img, v-over): the page's own are the rest.
dom_imgs=$(grep -o '<img ' "$dom" | wc -l || true)
viewer_imgs=$(grep -o '<img class="v-' "$dom" | wc -l || true)
dom_imgs=$((dom_imgs - viewer_imgs))
[[ $dom_imgs -eq $imgs ]] || { echo "FAIL: DOM has $dom_imgs images, file has $imgs"; fail=1; }
grep -q '</html>' "$dom" || { echo "FAIL: DOM dump incomplete"; fail=1; }
echo "chromium: screenshot $shot ($(stat -c %s "$shot" 2>/dev/null || echo 0) bytes), DOM images $dom_imgs"
[[ $fail -eq 0 ]] && echo "OK: $html" || echo "FAILED: $html"
exit $fail
