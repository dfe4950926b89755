#!/usr/bin/env bash
# The main job: install quatnav (with the simulation and plotting extras) and run the demo on
# built-in simulated scenarios: a printed comparison of the filters and a figure.
# On a machine without an active virtual environment it creates one in .venv (see
# tools/setup_env.sh; PYTHON=... uses that interpreter as it is). Extra arguments go to
# `quatnav demo` (for example --seed 3).
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/setup_env.sh
timed "main job: pip install .[sim,eval] (builds the extension)" pip_build ".[sim,eval]"
mkdir -p out
timed "main job: quatnav demo" "$PY" -m quatnav demo --plot out/demo.png "$@"
if [ ! -s out/demo.png ]; then
  echo "quatnav: the demo did not write out/demo.png" >&2
  exit 1
fi
echo "== done: the figure is $PWD/out/demo.png"
case "$PY" in
  "$PWD"/.venv/*) echo "   quatnav is installed in .venv: 'source .venv/bin/activate' to use it (python -c 'import quatnav', quatnav -h)";;
esac
