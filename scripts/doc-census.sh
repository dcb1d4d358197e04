#!/usr/bin/env bash
# The docs' size and their dated sections, for issue 44's before/after: the lines of docs/*.md and
# the headings that carry a date (2026-11-27) or a clock time (05:14), i.e. a measurement diary.
# Usage: scripts/doc-census.sh [DOCS_DIR]   (default: docs/ of the repository)
set -euo pipefail
dir="${1:-$(dirname "$0")/../docs}"
shopt -s nullglob
files=("$dir"/*.md)
lines=$(cat "${files[@]}" | wc -l)
dated=$(grep -hE '^#{1,6} .*([0-9]{4}-[0-9]{2}-[0-9]{2}|[0-9]{1,2}:[0-9]{2})' "${files[@]}" | wc -l || true)
echo "docs: ${#files[@]} files, $lines lines"
echo "dated sections: $dated"
