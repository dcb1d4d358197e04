#!/usr/bin/env bash
# The Python package (python/): a fresh venv, `pip install ./python` (maturin builds the extension
# in the workspace's target/, release profile, so CI reuses what `cargo test --release` built),
# then its pytest tests against the `penumbra` binary of this tree and the example script.
#   bash scripts/python-test.sh [VENV_DIR]     (default: target/python-venv)
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
venv=${1:-target/python-venv}
python3 -m venv --help >/dev/null 2>&1 || { echo "error: python3 with venv is needed (apt-get install python3-venv)" >&2; exit 1; }
python3 -m venv "$venv"
"$venv/bin/pip" install --quiet --upgrade pip
"$venv/bin/pip" install --quiet pytest numpy matplotlib ./python
# The tests compare against the command line built from the same tree.
cargo build --release --quiet -p penumbra-lab --bin penumbra
export PENUMBRA_NO_PROGRESS=1
"$venv/bin/python" -m pytest -q python/tests
"$venv/bin/python" python/examples/two_methods.py target/python-example analytic-square 128
echo "python: $(($(date +%s) - start)) s wall clock (venv, install, pytest, example)"
