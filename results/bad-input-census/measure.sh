#!/usr/bin/env bash
# The figures of this folder beside the census (scripts/bad-input-census.sh), issue 54's items 1, 6 and 4.
#
#   measure.sh lights OLD_BINARY NEW_BINARY [OUT_DIR]
#     heights.csv  a point and a spot light (radius 2) at heights 30..10,000 over a 53-unit scene:
#                  hard's and regular:n=3's RMSE against the continuous reference (16x16), 128²;
#     disks.csv    a disk at height 8 of radius 10..200 over the same scene: regular:n=3's and
#                  hard's RMSE, or the refusal; the angular-size check's boundary is radius 36.5.
#     HEIGHTS, RADII (space-separated) replace the heights and the radii (the CI stand-in's few).
#
#   measure.sh regions BINARY [CSV]
#     regions-range.csv  regions across its documented force (1..=128) and max_n (1..=64) range, at
#     the values around each edge of a batch (22, 23, 24: 484, 529, 576 maps against the 512 a
#     batch holds) and the ends: each must render, or be refused up front with one line. Rows:
#     setting, exit status, maps, the largest class's maps, seconds, peak resident MiB, the error.
#     FORCES, MAX_NS (space-separated, may be empty) replace the values (the CI stand-in's few).
set -u
here=$(cd "$(dirname "$0")" && pwd)
what=$1
shift
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export PENUMBRA_NO_PROGRESS=1 PENUMBRA_CACHE=$work/cache

lights() {
  local old new out
  old=$(realpath "$1") new=$(realpath "$2")
  out=${3:-$here}
  # The census's scenes: a 30 x 30 ground and a 20 x 40 occluder plane at height 3.
  source <(sed -n '/^scene_head()/,/^rect()/p' "$here/../../scripts/bad-input-census.sh")
  measure() { # build binary scene label -> "hard,regular" RMSEs, or the refusal
    local dir=$work/$1-$3
    if (cd "$work" && "$2" compare --scene "$3.toml" --methods hard,regular:n=3 --set resolution=128 --repeats 1 --samples 16 --out "$dir" >/dev/null 2>"$dir.err"); then
      python3 -c 'import json, sys
rmse = {r["label"]: r["metrics"]["rmse"] for r in map(json.loads, open(sys.argv[1]))}
print("%s,%s," % (rmse["hard"], rmse["regular:n=3"]))' "$dir/results.jsonl"
    else
      echo ",,\"$(grep -m1 '^error:' "$dir.err" | sed 's/"/'"'"'/g' | cut -c1-160)\""
    fi
  }
  echo "kind,height,build,hard_rmse,regular3_rmse,refused" > "$out/heights.csv"
  for kind in point spot; do
    for h in ${HEIGHTS:-30 100 400 10000}; do
      if [ $kind = point ]; then point_far $h > "$work/$kind$h.toml"; else spot_far $h > "$work/$kind$h.toml"; fi
      for build in old new; do
        bin=$old; [ $build = new ] && bin=$new
        echo "$kind,$h,$build,$(measure $build "$bin" $kind$h)" >> "$out/heights.csv"
      done
    done
  done
  echo "radius,height,tangent_at_middle,build,hard_rmse,regular3_rmse,refused" > "$out/disks.csv"
  for r in ${RADII:-10 20 30 36 37 42 50 100 200}; do
    disk $r 8 > "$work/disk$r.toml"
    for build in old new; do
      bin=$old; [ $build = new ] && bin=$new
      # The scene's middle is [2.5, 1.5, 0], 6.5 below the disk: the outline's tangent is (r + 2.5) / 6.5.
      echo "$r,8,$(awk -v r=$r 'BEGIN { printf "%.2f", (r + 2.5) / 6.5 }'),$build,$(measure $build "$bin" disk$r)" >> "$out/disks.csv"
    done
  done
}

regions() {
  local bin csv
  bin=$(realpath "$1")
  csv=$(realpath -m "${2:-$here/regions-range.csv}")
  echo "method,exit,shadow_maps,largest_class_maps,seconds,peak_mib,error" > "$csv"
  run_regions() {
    local spec=$1 dir=$work/run
    rm -rf "$dir"
    local start status
    start=$(date +%s.%N)
    /usr/bin/time -f '%M' -o "$work/peak" "$bin" render --scene analytic-square --set resolution=32 --method "$spec" --out "$dir" >/dev/null 2>"$work/err"
    status=$?
    local seconds maps largest err
    seconds=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
    # The maps and the largest class's maps, or nothing where the render wrote no run.json.
    read -r maps largest < <(python3 -c 'import json, sys
try:
    r = json.load(open(sys.argv[1]))
except OSError:
    print(" ")
    sys.exit()
classes = r.get("method_record", {}).get("classes") or []
print(r.get("shadow_maps", ""), max((c["maps"] for c in classes), default=""))' "$dir/run.json" 2>/dev/null)
    err=$(grep -m1 '^error:' "$work/err" | sed 's/"/'"'"'/g' | cut -c1-200)
    echo "\"$spec\",$status,$maps,$largest,$seconds,$(( $(tail -1 "$work/peak") / 1024 )),\"$err\"" >> "$csv"
  }
  for n in ${FORCES-1 2 16 22 23 24 32 64 100 128}; do run_regions "regions:force=$n,force_size=16"; done
  for m in ${MAX_NS-1 2 16 22 23 24 32 45 64}; do run_regions "regions:max_n=$m,target=0.0005,min_size=16,max_size=64"; done
}

case $what in
  lights) lights "$@" ;;
  regions) regions "$@" ;;
  *) echo "usage: measure.sh lights OLD NEW [OUT_DIR] | regions BINARY [CSV]" >&2; exit 2 ;;
esac
