#!/usr/bin/env bash
# The bad inputs of issue 54, tried one at a time as a new user would, each in a fresh folder with a
# scratch cache, and judged:
#   good  the run does what it promises: a refusal is exit 1, one `error:` line that matches the
#         case's pattern (the file or flag, the key, the value) and no --out written; an accepted
#         input exits 0 and its figures pass the case's check;
#   poor  the right outcome in the wrong words: a refusal whose line misses the pattern, or several
#         error lines; an accepted input that is refused up front with one line;
#   bad   a wrong answer or no answer: exit 0 where a refusal was due, figures that fail the check
#         (a silent wrong shadow), a panic (101), killed by a signal or the time limit, or past the
#         memory limit.
#
# Usage: bash scripts/bad-input-census.sh [CSV]        (default results/bad-input-census/cases.csv)
#   PENUMBRA=path/to/penumbra   the binary (default target/release/penumbra; build it first)
#   CENSUS_ONLY=REGEX           run only the cases whose id matches
#   CENSUS_LIMIT_S=N            seconds each case may take (default 120)
# Prints the tally; the CSV has a row per case. Runs on any adapter; the committed tally names its own.
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
bin=$(realpath "${PENUMBRA:-$here/target/release/penumbra}")
csv=$(realpath -m "${1:-$here/results/bad-input-census/cases.csv}")
only=${CENSUS_ONLY:-.}
limit=${CENSUS_LIMIT_S:-120}
# Past this peak resident memory (MiB) a case is bad: the largest input here, regions' 16,384 maps
# of force=128, peaks at 2.5 GiB on lavapipe (its command buffers are host memory). Each case also
# runs under a 12 GiB address-space limit, so a build that reads /dev/zero stops there (an
# allocation failure, bad) instead of taking the machine's memory.
max_mib=4096
max_vm_kib=$((12 << 20))
work=$(mktemp -d)
chmod 755 "$work" # the read-only cache cases run as another user
trap 'rm -rf "$work"' EXIT
export PENUMBRA_NO_PROGRESS=1
mkdir -p "$(dirname "$csv")"
echo "id,item,what,expect,exit,seconds,peak_mib,verdict,message" > "$csv"
good=0 poor=0 bad=0

# A scene TOML on stdout: `point_far H`, `spot_far H`, `disk R H`, `rect SIDE H`.
scene_head() {
  cat <<EOF
name = "$1"
[camera]
eye = [-9.0, 9.0, 7.0]
target = [-1.0, 0.0, 0.0]
fov_y_deg = 50.0
[render]
width = 64
height = 64
shadow_map_size = 512
cull = "none"
[[mesh]]
builtin = "plane"
scale = [30.0, 1.0, 30.0]
[[mesh]]
builtin = "plane"
translate = [10.0, 3.0, 0.0]
scale = [20.0, 1.0, 40.0]
EOF
}
point_far() { scene_head "point-far"; printf '[light]\nkind = "point"\nposition = [1.0, %s, 0.5]\nradius = 2.0\n' "$1"; }
spot_far() { scene_head "spot-far"; printf '[light]\nkind = "spot"\nposition = [-1.0, %s, -0.5]\ndirection = [0.2, -1.0, 0.0]\ninner_cone_deg = 25.0\nouter_cone_deg = 40.0\nradius = 2.0\n' "$1"; }
disk() { scene_head "wide-disk"; printf '[light]\nkind = "disk"\ncenter = [0.0, %s, 0.0]\nnormal = [0.0, -1.0, 0.0]\nradius = %s\n' "$2" "$1"; }
rect() { scene_head "wide-rect"; printf '[light]\ncenter = [0.0, %s, 0.0]\nsize = [%s, %s]\nnormal = [0.0, -1.0, 0.0]\n' "$2" "$1" "$1"; }

# An estimate row (estimate.jsonl) with KEY=VALUE pairs replacing fields of a good one.
estimate_row() {
  local row='{"scene":"analytic-square","spec":"regular:n=3@64","layout":"lattice","map_size":64,"maps":9,"measured_rmse":0.05,"predicted_rmse":0.06,"predicted_sampling":0.05,"predicted_map":0.03,"ratio":1.2,"within":true,"bound_coverage":0.9,"measured_map":0.02,"measured_sampling":0.04,"exact":"lattice","resolution":[64,64],"reference":"continuous 8x8","adapter":"x"}'
  echo "$row" | json_set "$@"
}

# Each JSON line of stdin with KEY=VALUE pairs set (KEY dotted, VALUE JSON text), compact.
json_set() {
  python3 -c 'import json, sys
for line in sys.stdin:
    row = json.loads(line)
    for kv in sys.argv[1:]:
        key, value = kv.split("=", 1)
        *path, last = key.split(".")
        node = row
        for k in path:
            node = node[k]
        node[last] = json.loads(value)
    print(json.dumps(row, separators=(",", ":")))' "$@"
}
# Succeeds when EXPR, Python over the JSON of FILE as `j`, is true.
json_true() { python3 -c 'import json, sys; j = json.load(open(sys.argv[1])); sys.exit(0 if eval(sys.argv[2]) else 1)' "$1" "$2"; }

# The RMSE of LABEL in out/results.jsonl.
rmse() { python3 -c 'import json, sys
for line in open("out/results.jsonl"):
    r = json.loads(line)
    if r["label"] == sys.argv[1]:
        print(r["metrics"]["rmse"])' "$1"; }
# Succeeds when LABEL's RMSE in out/results.jsonl is below LIMIT.
rmse_below() { awk -v r="$(rmse "$1")" -v l="$2" 'BEGIN { exit !(r != "" && r + 0 < l + 0) }'; }
export -f json_set json_true rmse rmse_below

# case ID ITEM WHAT EXPECT PATTERN_OR_CHECK SETUP COMMAND
#   EXPECT refuse: PATTERN is an extended regex the one `error:` line must match.
#   EXPECT ok:     PATTERN is a shell check run in the case's folder after the command.
#   SETUP runs first in the case's folder (files, links, caches); COMMAND is the run judged.
case_() {
  local id=$1 item=$2 what=$3 expect=$4 pattern=$5 setup=$6 command=$7
  [[ $id =~ $only ]] || return 0
  local dir=$work/$id
  mkdir -p "$dir" && cd "$dir" || exit 1
  export PENUMBRA_CACHE=$dir/cache
  bash -c "$setup" >/dev/null 2>&1
  local start end status peak=0
  start=$(date +%s.%N)
  if [ -x /usr/bin/time ]; then
    timeout -s KILL "$limit" /usr/bin/time -f '%M' -o "$dir/.peak" bash -c "ulimit -v $max_vm_kib; $command" >"$dir/.stdout" 2>"$dir/.stderr" </dev/null
    status=$?
    peak=$(( $(tail -1 "$dir/.peak" 2>/dev/null | grep -E '^[0-9]+$' || echo 0) / 1024 ))
  else
    timeout -s KILL "$limit" bash -c "ulimit -v $max_vm_kib; $command" >"$dir/.stdout" 2>"$dir/.stderr" </dev/null
    status=$?
  fi
  end=$(date +%s.%N)
  local seconds errors first verdict
  seconds=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }')
  errors=$(grep -c '^error:' "$dir/.stderr")
  first=$(grep -m1 '^error:' "$dir/.stderr" || grep -m1 -E 'warning|waiting' "$dir/.stderr" || true)
  # Killed by a signal (the time limit's SIGKILL, an abort on a failed allocation), a panic, or
  # past the memory limit.
  if [ "$status" -ge 128 ] || [ "$status" -eq 124 ] || [ "$status" -eq 101 ] || [ "$peak" -gt "$max_mib" ]; then
    verdict=bad
  elif [ "$expect" = refuse ]; then
    if [ "$status" -eq 0 ]; then
      verdict=bad
    elif [ "$status" -eq 1 ] && [ "$errors" -eq 1 ] && [[ $first =~ $pattern ]] && [ ! -e out ]; then
      verdict=good
    else
      verdict=poor
    fi
  else
    if [ "$status" -eq 0 ] && bash -c "$pattern" >/dev/null 2>&1; then
      verdict=good
    elif [ "$status" -eq 1 ] && [ "$errors" -eq 1 ]; then
      verdict=poor
    else
      verdict=bad
    fi
  fi
  case $verdict in good) good=$((good + 1)) ;; poor) poor=$((poor + 1)) ;; bad) bad=$((bad + 1)) ;; esac
  local message=${first//\"/\'}
  printf '%s,%s,"%s",%s,%s,%s,%s,%s,"%s"\n' "$id" "$item" "$what" "$expect" "$status" "$seconds" "$peak" "$verdict" "${message:0:300}" >>"$csv"
  echo "$verdict  $id ($seconds s): ${first:0:160}"
  cd "$work" || exit 1
}

P=$bin
CMP="$P compare --set resolution=64 --repeats 1 --samples 8 --reference continuous"

# 1. A point light far above the scene: its cube faces are fitted to the scene; hard's RMSE against
#    the reference stays that of a light near by (0.05 at height 30 at 128²), not 0.44.
for h in 30 100 400 1000 10000; do
  case_ "point-h$h" 1 "point light radius 2 at height $h: hard RMSE under 0.1" ok "rmse_below hard 0.1 && rmse_below regular:n=3 0.1" \
    "$(declare -f scene_head point_far); point_far $h > s.toml" "$CMP --scene s.toml --methods hard,regular:n=3 --out out"
done
case_ spot-h400 1 "spot light radius 2 at height 400: hard RMSE under 0.1" ok "rmse_below hard 0.1" \
  "$(declare -f scene_head spot_far); spot_far 400 > s.toml" "$CMP --scene s.toml --methods hard,regular:n=3 --out out"

# 2. A value near f64's largest in a rows file.
case_ calibrate-1e308 2 "calibrate, measured_rmse 1e308" refuse 'e\.jsonl: line 1: rmse = 1e308' \
  "$(declare -f estimate_row json_set); estimate_row measured_rmse=1e308 > e.jsonl" "$P calibrate --estimates e.jsonl --out out"
# (Beside the run's pictures, which the rows name.)
case_ report-1e308 2 "report, a results.jsonl row with rmse 1e308" refuse 'r\.jsonl.*line 1: metrics\.rmse = 1e308' \
  "$P compare --scene analytic-square --methods hard --set resolution=32 --repeats 1 --samples 4 --out run && json_set metrics.rmse=1e308 < run/results.jsonl > run/r.jsonl" \
  "$P report run/r.jsonl --out out"
case_ report-time-1e308 2 "report, a results.jsonl row with frame_ms 1e308" refuse 'line 1: frame_ms = 1e308' \
  "$P compare --scene analytic-square --methods hard --set resolution=32 --repeats 1 --samples 4 --out run && json_set frame_ms=1e308 < run/results.jsonl > run/r.jsonl" \
  "$P report run/r.jsonl --out out"

# 3. Special files.
case_ scene-dev-zero 3 "render --scene, a link to /dev/zero" refuse 'z\.toml.*a link to /dev/zero.*character device' \
  "ln -s /dev/zero z.toml" "$P render --scene z.toml --out out"
case_ estimates-dev-zero 3 "calibrate --estimates /dev/zero" refuse '--estimates /dev/zero.*character device' \
  "" "$P calibrate --estimates /dev/zero --out out"
case_ results-csv-dev-zero 3 "report on a results folder whose CSV links to /dev/zero" refuse 'rows\.csv.*character device' \
  "mkdir r && echo '# r' > r/README.md && ln -s /dev/zero r/rows.csv" "$P report r --out out"
case_ cache-dev-zero 3 "a reference cache entry linked to /dev/zero: traced again" ok "grep -q 'character device, not a regular file: not used; tracing the reference again' .stderr && test -f cache/reference/*.vis && ! test -L cache/reference/*.vis" \
  "$P compare --scene analytic-square --methods hard --set resolution=32 --repeats 1 --samples 4 --out first && f=\$(ls cache/reference/*.vis) && rm \$f && ln -s /dev/zero \$f" \
  "$P compare --scene analytic-square --methods hard --set resolution=32 --repeats 1 --samples 4 --out out"
case_ scene-fifo 3 "render --scene, a FIFO with no writer: says it waits" ok "grep -q 'waiting for f.toml (a FIFO)' .stderr" \
  "mkfifo f.toml" "timeout -s INT 4 $P render --scene f.toml --out out; test \$? -ne 0"
case_ scene-pipe 3 "render --scene <(cat s.toml) works" ok "test -f out/run.json" \
  "cp $here/scenes/analytic-square.toml s.toml" "$P render --scene <(cat s.toml) --set resolution=32 --out out"

# 4. regions at documented values: render, or refuse up front naming the setting.
for f in 23 64 128; do
  case_ "regions-force-$f" 4 "regions:force=$f,force_size=16 renders" ok "test -f out/run.json" \
    "" "$P render --scene analytic-square --set resolution=64 --method regions:force=$f,force_size=16 --out out"
done
case_ regions-force-23-default 4 "regions:force=23 at the scene's map size renders" ok "test -f out/run.json" \
  "" "$P render --scene analytic-square --set resolution=64 --method regions:force=23 --out out"
for m in 32 64; do
  case_ "regions-max-n-$m" 4 "regions:max_n=$m, its top class past 512 maps, renders" ok "json_true out/run.json 'max(c[\"maps\"] for c in j[\"method_record\"][\"classes\"]) > 512'" \
    "" "$P render --scene analytic-square --set resolution=32 --method regions:max_n=$m,target=0.0005,min_size=16,max_size=64 --out out"
done
case_ regions-force-size-4096 4 "regions:force=6,force_size=4096, a budget of 100000 MiB" refuse 'shadow_map_budget_mib = 100000: .*4096x4096.*largest memory heap' \
  "" "$P render --scene analytic-square --set resolution=64 --set shadow_map_budget_mib=100000 --method regions:force=6,force_size=4096 --out out"
case_ auto-texels 4 "auto:cost=texels,target=0.0005, a budget of 100000 MiB: its run-time array through the heap check" refuse 'shadow_map_budget_mib = 100000: the shadow-map array \(.* a map size the method chose at run time\) needs .*largest memory heap' \
  "" "$P render --scene analytic-square --set resolution=64 --set shadow_map_budget_mib=100000 --method auto:cost=texels,target=0.0005 --out out"

# 5. A reference lock left by a run whose pid now belongs to a live process (pid 1).
case_ stale-lock 5 "a lock file naming a live pid (1) is taken over" ok "test -f out/results.jsonl" \
  "$P compare --scene analytic-square --methods hard --set resolution=32 --repeats 1 --samples 4 --out first && f=\$(ls cache/reference/*.vis) && rm \$f && echo \"1 \$(cat /proc/sys/kernel/hostname)\" > \${f%.vis}.lock" \
  "timeout 60 $P compare --scene analytic-square --methods hard --set resolution=32 --repeats 1 --samples 4 --out out"

# 6. Lights inside the 10-diagonal bound whose angular size breaks the maps.
case_ disk-200 6 "disk of radius 200 at height 8" refuse 'light\.center = \[0\.0, 8\.0, 0\.0\], light\.radius = 200: .*past the 80\.5' \
  "$(declare -f scene_head disk); disk 200 8 > s.toml" "$CMP --scene s.toml --methods hard,regular:n=3 --out out"
case_ rect-290 6 "rectangle 290 x 290 at height 10" refuse 'light\.edge_u = .*past the 80\.5' \
  "$(declare -f scene_head rect); rect 290 10 > s.toml" "$CMP --scene s.toml --methods hard,regular:n=3 --out out"

# 7. calibrate --out the estimate's own folder.
case_ calibrate-own-folder 7 "calibrate --out the folder holding its --estimates" refuse '--estimates est/estimate\.jsonl: lies inside the set --out est replaces' \
  "$P estimate --scenes analytic-square --settings regular:n=2@64 --samples 4 --out est" \
  "cp -a est est.before; $P calibrate --estimates est/estimate.jsonl --out est; r=\$?; diff -r est est.before >/dev/null || exit 99; exit \$r"

# 8. calibrate on absurd rows.
case_ calibrate-empty 8 "calibrate, an empty file" refuse '--estimates e\.jsonl: holds no estimate row' ": > e.jsonl" "$P calibrate --estimates e.jsonl --out out"
case_ calibrate-failed 8 "calibrate, only failed rows" refuse 'all 1 rows are failed settings' \
  "$(declare -f estimate_row json_set); estimate_row 'failed=\"out of memory\"' > e.jsonl" "$P calibrate --estimates e.jsonl --out out"
case_ calibrate-zero 8 "calibrate, measured_rmse 0" refuse 'line 1: rmse = 0:' "$(declare -f estimate_row json_set); estimate_row measured_rmse=0 > e.jsonl" "$P calibrate --estimates e.jsonl --out out"
case_ calibrate-negative 8 "calibrate, measured_rmse -0.5" refuse 'line 1: rmse = -0\.5:' "$(declare -f estimate_row json_set); estimate_row measured_rmse=-0.5 > e.jsonl" "$P calibrate --estimates e.jsonl --out out"
case_ calibrate-sampling 8 "calibrate, predicted_sampling -1" refuse 'line 1: predicted_sampling = -1:' "$(declare -f estimate_row json_set); estimate_row predicted_sampling=-1 > e.jsonl" "$P calibrate --estimates e.jsonl --out out"
case_ calibrate-map-size 8 "calibrate, map_size 0" refuse 'line 1: map_size = 0' "$(declare -f estimate_row json_set); estimate_row map_size=0 > e.jsonl" "$P calibrate --estimates e.jsonl --out out"
case_ calibrate-twice 8 "calibrate --estimates E,E" refuse '--estimates `e\.jsonl`: listed twice' "$(declare -f estimate_row json_set); estimate_row > e.jsonl" "$P calibrate --estimates e.jsonl,e.jsonl --out out"

# 9. A read-only reference cache (a cache folder this user cannot write: run as nobody when root).
as_user=""
[ "$(id -u)" -eq 0 ] && command -v setpriv >/dev/null && as_user="setpriv --reuid=65534 --regid=65534 --clear-groups"
case_ cache-read-only-no-cache 9 "a read-only cache with --no-cache: not touched" ok "test -f out/results.jsonl && ! grep -q 'cache' .stderr" \
  "mkdir -p cache/reference && chmod 555 cache cache/reference && chmod 777 ." \
  "$as_user $P compare --scene analytic-square --methods hard --set resolution=32 --repeats 1 --samples 4 --no-cache --out out"
case_ cache-read-only 9 "a read-only cache: traced, not stored, the folder named" ok "test -f out/results.jsonl && grep -q 'warning: reference cache folder .*cache/reference: ' .stderr" \
  "mkdir -p cache/reference && chmod 555 cache cache/reference && chmod 777 ." \
  "$as_user $P compare --scene analytic-square --methods hard --set resolution=32 --repeats 1 --samples 4 --out out"

# 10. report on a results folder: links, sub-folders, an RMSE of -1.
case_ report-links 10 "report: README images and links out of the page" ok "! grep -qE '(src|href)=\"(http|javascript|//)' out/report.html && grep -q 'sub/rows.csv' out/report.html && grep -q 'rmse = -1' .stderr" \
  "mkdir -p r/sub && printf '# r\n\n![x](http://example.com/p.png) [click](javascript:alert(1))\n' > r/README.md && printf 'a,rmse\n1,0.5\n' > r/rows.csv && printf 'a,rmse\n1,-1\n' > r/sub/rows.csv" \
  "$P report r --out out"

# 11. Smaller ones.
case_ convergence-fails 11 "convergence: one value fails at run time, the study goes on" ok "grep -q -- '--values 1 ' .stderr && json_true out/convergence.json 'j[\"rows\"][0].get(\"failed\")'" \
  "cp $here/scenes/analytic-square.toml s.toml" \
  "$P convergence --scene s.toml --method adaptive:scope=local,items_grow=off --key items --values 1,4000000 --set resolution=32 --samples 4 --out out"
case_ method-unknown 11 "convergence --method nosuch" refuse '--method nosuch: unknown method `nosuch`' "" "$P convergence --method nosuch --out out"
case_ regions-hybrid 11 "regions with --set maps=hybrid" refuse 'regions: maps = hybrid is not supported' "" "$P render --scene analytic-square --method regions --set maps=hybrid --out out"
case_ frontier-4096 11 "frontier --sizes 4096: the announced time within 2x of the run" ok \
  "awk -v a=\"\$(grep -oE 'about [0-9]+ (s|min)' .stderr | head -1 | awk '{print (\$3 == \"min\" ? \$2 * 60 : \$2)}')\" -v t=\"\$(cat .seconds)\" 'BEGIN { exit !(a > 0 && a < 2 * t && t < 2 * a) }'" \
  "" "s=\$(date +%s.%N); $P frontier --scene analytic-square --sizes 4096 --n 2 --hybrid none --set resolution=32 --samples 4 --repeats 1 --out out; r=\$?; awk -v a=\$s -v b=\$(date +%s.%N) 'BEGIN { print b - a }' > .seconds; exit \$r"
case_ frontier-16384 11 "frontier --sizes 16384: failures known before the run are left out" ok "grep -q 'left out' .stderr && ! grep -q 'failed:' .stderr" \
  "" "$P frontier --scene analytic-square --sizes 16384 --n 2 --hybrid none --set resolution=32 --samples 4 --repeats 1 --out out"
case_ fetch-offline 11 "assets fetch with no registry: npm's own reason" ok "grep -qE 'ECONNREFUSED|ENOTFOUND|ENOTCACHED' .stderr" \
  "mkdir -p npmcache" "npm_config_registry=http://127.0.0.1:9/ npm_config_cache=\$PWD/npmcache PENUMBRA_FETCH_TIMEOUT=10 $P assets fetch --group meshes --cache c; true"
case_ fetch-stale-partial 11 "assets fetch removes a killed run's .partial-PID/" ok "! test -e c/.partial-999999" \
  "mkdir -p c/.partial-999999/x npmcache" "npm_config_registry=http://127.0.0.1:9/ npm_config_cache=\$PWD/npmcache PENUMBRA_FETCH_TIMEOUT=10 $P assets fetch --group meshes --cache c; true"

echo "good $good, poor $poor, bad $bad (of $((good + poor + bad)); rows: $csv)"
