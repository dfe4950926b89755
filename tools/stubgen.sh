#!/usr/bin/env bash
# Regenerate the type stubs of the compiled module (python/quatnav/_core/*.pyi) from a built
# quatnav._core (installed, or in-tree with PYTHONPATH=python). Run after changing a binding;
# tests/python/test_stubs.py fails when the stubs miss a public name.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
"$PY" -m pip install -q pybind11-stubgen
out=$(mktemp -d)
"$PY" -m pybind11_stubgen quatnav._core -o "$out"
cp "$out"/quatnav/_core/*.pyi python/quatnav/_core/
rm -rf "$out"
echo "stubs written to python/quatnav/_core/"
