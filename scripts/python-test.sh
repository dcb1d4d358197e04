#!/usr/bin/env bash
# The Python package (python/): a fresh venv, `pip install ./python` (maturin builds the extension
# in the workspace's target/, release profile, so CI reuses what `cargo test --release` built),
# then its pytest tests against the `penumbra` binary of this tree, `mypy --strict` on the example
# script (through the package's stubs) and the example itself.
#   bash scripts/python-test.sh [VENV_DIR]     (default: target/python-venv)
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
venv=${1:-target/python-venv}
command -v python3 >/dev/null || { echo "error: python3 (3.9 or newer) is needed" >&2; exit 1; }
if ! python3 -m venv "$venv" >/dev/null 2>&1; then
    # Debian's python3 ships venv without ensurepip: python3-venv adds it.
    command -v apt-get >/dev/null || { echo "error: python3 -m venv $venv failed and there is no apt-get to install python3-venv" >&2; exit 1; }
    sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq python3-venv >/dev/null
    rm -rf "$venv"
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet --upgrade pip
# pandas (and its stubs) for compare's rows as a DataFrame; mypy for the stubs' check.
"$venv/bin/pip" install --quiet pytest numpy matplotlib pandas pandas-stubs mypy ./python
# The tests compare against the command line built from the same tree.
cargo build --release --quiet -p penumbra-lab --bin penumbra
export PENUMBRA_NO_PROGRESS=1
"$venv/bin/python" -m pytest -q python/tests
"$venv/bin/python" -m mypy --strict --no-incremental python/examples/two_methods.py
"$venv/bin/python" python/examples/two_methods.py target/python-example analytic-square 128
echo "python: $(($(date +%s) - start)) s wall clock (venv, install, pytest, example)"
