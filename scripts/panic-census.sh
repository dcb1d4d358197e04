#!/bin/bash
# The panic census: runs the test suite (or the tests named, e.g. `--test bad_input`) with every
# panic of the penumbra binary appended to one log (PENUMBRA_PANIC_LOG, lab/src/panic_log.rs), then
# prints the count. The tests drive the command line with every bad input they hold; a panic there
# is a bug whether or not the test that saw it looked at stderr.
#
#   scripts/panic-census.sh [cargo test arguments…]
set -uo pipefail
cd "$(dirname "$0")/.."
log=$(mktemp /tmp/penumbra-panics.XXXXXX)
PENUMBRA_PANIC_LOG=$log PENUMBRA_NO_PROGRESS=1 cargo test --release "$@" 2>&1 | grep -E '^test result|FAILED|^error' 
status=${PIPESTATUS[0]}
echo "binary panics: $(grep -c '^panicked' "$log") (log: $log)"
exit "$status"
