#!/usr/bin/env bash
# How spread out a study is in the lab, counted from the source (issue 44, "adding a study"):
# - per study, the files that hold it or list it: every file under cli/, studies/, report/ and
#   record/ whose path carries the study's name (cli/S.rs, studies/S/, report/charts/S.rs, ...),
#   and every file that registers it (`mod S;`, or its arguments type in the command list):
#   what adding one more study touches;
# - the files that declare each common flag (`--set`, `--out`, `--repeats`) as a clap field.
# Usage: scripts/count-study-layout.sh [LAB_SRC]   (default lab/src, from the repository root)
set -euo pipefail
src=${1:-lab/src}
studies="bench cascades compare environment estimate failures framing frontier hybrid seams sequence convergence"

printf '%-12s %5s %7s  %s\n' study files folders where
total=0; n=0
for s in $studies; do
    # A study that is not in this tree (convergence before it was added) is skipped.
    by_path=$(find "$src"/cli "$src"/studies "$src"/report "$src"/record -type f \( -path "*/$s.rs" -o -path "*/$s/*" \) | sort)
    [ -z "$by_path" ] && continue
    # Registration: `mod S;` in the study layers, or the study's arguments type in the command list.
    by_name=$(grep -rlE "(^|[^a-z_])mod $s;|(cli|studies)::$s::(command::)?[A-Za-z]*Args" "$src"/cli "$src"/studies "$src"/report "$src"/record "$src"/main.rs | sort || true)
    files=$(printf '%s\n%s\n' "$by_path" "$by_name" | grep -v '^$' | sort -u)
    count=$(printf '%s\n' "$files" | wc -l)
    folders=$(printf '%s\n' "$files" | xargs -n1 dirname | sort -u | wc -l)
    printf '%-12s %5d %7d  %s\n' "$s" "$count" "$folders" "$(printf '%s\n' "$files" | sed "s|^$src/||" | tr '\n' ' ')"
    total=$((total + count)); n=$((n + 1))
done
echo "mean files per study: $(awk -v t=$total -v n=$n 'BEGIN { printf "%.1f", t / n }') over $n studies"

# A clap field for the flag: `set: Vec<String>` / `out: PathBuf` / `repeats: u32` under an #[arg]
# (a flattened common struct, `sets: SetArgs`, is not a declaration).
for flag in set out repeats; do
    files=$(grep -rlE "^\s*(pub )?$flag: (Vec<String>|PathBuf|u32)," "$src" --include='*.rs' | xargs grep -lE "derive\((clap::)?(Args|Parser)" | sort || true)
    count=$(printf '%s' "$files" | grep -c . || true)
    echo "--$flag declared in $count files: $(printf '%s\n' "$files" | sed "s|^$src/||" | tr '\n' ' ')"
done
