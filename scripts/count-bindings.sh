#!/usr/bin/env bash
# The passes' hand-written plumbing, counted (issue 44, "passes that say what they read and write"):
#  (a) `clippy::too_many_arguments` allows in src/stages/ (passes and their CPU twins);
#  (b) hand-written binding pairs in src/: a tuple `("NAME", ...)` (its `(` not the call of a
#      function or macro) whose NAME is a binding variable of some kernel (`@binding(N) var... NAME`
#      in kernels/), in a file that makes bind groups (calls `.dispatch(` or `bind_group(`). The
#      stage table (src/gpu/stages.rs), which declares the bindings, is not counted.
# Run from anywhere in the repository: scripts/count-bindings.sh
set -euo pipefail
cd "$(dirname "$0")/.."
allows=$( (grep -rho 'clippy::too_many_arguments' src/stages || true) | wc -l)
names=$(grep -rhoE '@binding\([0-9]+\) *var(<[^>]*>)? *[a-z_0-9]+' kernels | sed -E 's/.* ([a-z_0-9]+)$/\1/' | sort -u)
files=$(grep -rlE '\.dispatch\(|bind_group\(' src --include='*.rs' | grep -v '^src/gpu/stages.rs$' | sort)
pairs=0
per_file=""
for f in $files; do
  n=$(grep -oE '(^|[^A-Za-z0-9_!])\("[a-z_0-9]+", ' "$f" | sed -E 's/^.?\("([a-z_0-9]+)", $/\1/' | grep -cxF -f <(echo "$names") || true)
  if [ "$n" -gt 0 ]; then per_file+=$(printf '  %4d %s' "$n" "$f")$'\n'; fi
  pairs=$((pairs + n))
done
echo "too_many_arguments allows in src/stages: $allows"
echo "hand-written binding pairs in src: $pairs"
printf '%s' "$per_file"
