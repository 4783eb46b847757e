#!/usr/bin/env bash
# Create .venv and install simlab into it.
#   bash scripts/setup.sh          # simlab with the RL libraries (train and play)
#   bash scripts/setup.sh dev      # the same plus the test and documentation tools
# torch is pinned by constraints.txt in every install path, so pip never swaps in a CUDA build
# (on this project's CPU machines `pip install torch==2.13.0` takes a local CPU wheel).
set -euo pipefail
cd "$(dirname "$0")/.."
extras="train,rsl_rl,skrl,sb3,render,viewer,teleop,datasets"  # datasets: simlab record / replay (h5py)
[ "${1:-}" = "dev" ] && extras="$extras,dev,docs"
# Offscreen rendering: simlab tries EGL (GPU drivers), then OSMesa (software); install OSMesa where we can.
if ! ldconfig -p 2>/dev/null | grep -q libOSMesa; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libosmesa6 >/dev/null) \
      || echo "note: could not install libosmesa6; rendering tests will be skipped"
  else
    echo "note: install libosmesa6 (Debian/Ubuntu) for offscreen rendering on the CPU"
  fi
fi
# dev: the web viewer's tests drive Debian's headless Chromium, the native viewer's run under Xvfb.
if [ "${1:-}" = "dev" ] && ! command -v chromium >/dev/null; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium xvfb >/dev/null) \
      || echo "note: could not install chromium and xvfb; the browser tests of the web viewer will be skipped"
  else
    echo "note: install chromium and xvfb (Debian/Ubuntu) to run the web and native viewer tests"
  fi
fi
# dev: the teleoperation test types keys into MuJoCo's window under Xvfb with xdotool.
if [ "${1:-}" = "dev" ] && ! command -v xdotool >/dev/null; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq xdotool >/dev/null) \
      || echo "note: could not install xdotool; the native viewer's teleoperation test will be skipped"
  else
    echo "note: install xdotool (Debian/Ubuntu) to run the native viewer's teleoperation test"
  fi
fi
[ -d .venv ] || python3 -m venv .venv
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -c constraints.txt torch==2.13.0
.venv/bin/python -m pip install -q -c constraints.txt -e ".[$extras]"
# rl_games pins psutil<6 and pulls pygame-ce: an optional extra, installed for the full setup.
.venv/bin/python -m pip install -q -c constraints.txt -e ".[rl_games]" || echo "note: rl_games not installed"
# skrl on JAX (CPU wheels): an optional extra, installed for the full setup.
.venv/bin/python -m pip install -q -c constraints.txt -e ".[jax]" || echo "note: jax (skrl --ml_framework jax) not installed"
# dev: MuJoCo Warp and Warp (CPU wheels here): tests run the GPU path's code on Warp's CPU device.
if [ "${1:-}" = "dev" ]; then
  .venv/bin/python -m pip install -q -c constraints.txt -e ".[gpu]" || echo "note: mujoco-warp not installed; its CPU-device tests will be skipped"
fi
echo "simlab installed in .venv"
