#!/usr/bin/env bash
# Installs what Penumbra needs on Debian/Ubuntu, and only what is missing: the Vulkan loader and a
# Vulkan driver (Mesa's lavapipe CPU device when no Vulkan driver is present), a C/C++ compiler for
# crates that build C, python3 for the Python package and the results folders' drivers, DejaVu fonts so chart text renders,
# and Chromium, in which CI drives the report's viewer (scripts/report-browser-test.sh). Needs a Rust toolchain (rustup).
set -euo pipefail
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
need=()
ldconfig -p 2>/dev/null | grep -q 'libvulkan\.so\.1' || need+=(libvulkan1)
if ! ls /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json >/dev/null 2>&1; then
    need+=(mesa-vulkan-drivers)
fi
# Charts carry their own font; this one is for reading the HTML report in a browser.
[ -f /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf ] || need+=(fonts-dejavu-core)
# The Python package's tests and the results folders' drivers (penumbra.analysis) run on python3.
command -v python3 >/dev/null 2>&1 || need+=(python3)
# The report's viewer is tested in a real browser, headless.
command -v chromium >/dev/null 2>&1 || need+=(chromium)
command -v cc >/dev/null 2>&1 || need+=(gcc)
command -v c++ >/dev/null 2>&1 || need+=(g++)
if [ "${#need[@]}" -gt 0 ]; then
    echo "setup: installing ${need[*]}" >&2
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${need[@]}" >/dev/null
fi
if ! command -v cargo >/dev/null 2>&1; then
    echo "setup: no Rust toolchain found; install one with rustup (https://rustup.rs), Rust 1.85 or newer" >&2
    exit 1
fi
# CI's lint gates run rustfmt and clippy (.ci/run); a minimal toolchain profile lacks them.
if ! cargo fmt --version >/dev/null 2>&1 || ! cargo clippy --version >/dev/null 2>&1; then
    command -v rustup >/dev/null 2>&1 || { echo "setup: cargo fmt and cargo clippy are needed (rustup component add rustfmt clippy)" >&2; exit 1; }
    rustup component add rustfmt clippy
fi
