#!/usr/bin/env bash
# Install quatnav (with the plotting extra) and run the demo on built-in simulated scenarios.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
"$PY" -m pip install -q ".[sim,eval]"
mkdir -p out
quatnav demo --plot out/demo.png "$@"
