#!/usr/bin/env bash
# Build the documentation site (Sphinx, furo, MyST) into build/docs/html, warnings as errors.
#   bash tools/docs.sh [extra sphinx-build options]
# 1. uses the Python environment of tools/demo.sh and tools/test.sh (tools/setup_env.sh: .venv
#    unless one is active, or PYTHON=...) and installs the packages of the `docs` extra
#    (pyproject.toml) that are missing;
# 2. documents the source tree (PYTHONPATH=python) when it holds a compiled module for this
#    interpreter (python/quatnav/_core*.so, the in-tree build of docs/DEVELOPING.md), else the
#    installed quatnav (pip install ., or tools/demo.sh); QUATNAV_DOCS_FROM=tree|installed
#    forces one;
# 3. runs sphinx-build -W --keep-going; the figures are made during the build by quatnav's own
#    commands (docs/_ext/quatnav_figures.py) into build/docs/figures, never into the sources.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
source tools/setup_env.sh   # $PY, pip_quiet
# A relative interpreter (PYTHON=.venv/bin/python) is the repository's: the checks below run it
# from other folders.
case "$PY" in
  /*) ;;
  */*) PY="$ROOT/$PY" ;;
esac
OUT=build/docs/html

# Requirement lists of pyproject.toml: "docs" (the extra) or "dependencies".
requirements() {
  "$PY" - "$1" <<'PYEOF'
import ast, re, sys
text = open("pyproject.toml").read()
m = re.search(r"^" + sys.argv[1] + r"\s*=\s*(\[.*?\])", text, re.M | re.S)
print("\n".join(ast.literal_eval(m.group(1))))
PYEOF
}
# pip install the given requirements when one of them is absent or too old.
install_missing() {
  [ $# -gt 0 ] || return 0
  if ! "$PY" - "$@" <<'PYEOF'
import sys
from importlib.metadata import PackageNotFoundError, version
try:
    from packaging.requirements import Requirement
except ImportError:  # nothing to compare versions with: let pip decide
    sys.exit(1)
for r in map(Requirement, sys.argv[1:]):
    if r.marker is not None and not r.marker.evaluate():
        continue
    try:
        if not r.specifier.contains(version(r.name), prereleases=True):
            sys.exit(1)
    except PackageNotFoundError:
        sys.exit(1)
PYEOF
  then
    pip_quiet "$@"
  fi
}
mapfile -t docs_reqs < <(requirements docs)
install_missing "${docs_reqs[@]}"

# --- which quatnav to document -----------------------------------------------------------------
from=${QUATNAV_DOCS_FROM:-}
if [ -z "$from" ]; then
  if "$PY" -c "import importlib.machinery as m, os, sys
sys.exit(0 if any(os.path.exists('python/quatnav/_core' + s) for s in m.EXTENSION_SUFFIXES) else 1)"; then
    from=tree
  else
    from=installed
  fi
fi
case "$from" in
  tree)
    export PYTHONPATH="$ROOT/python${PYTHONPATH:+:$PYTHONPATH}"
    mapfile -t deps < <(requirements dependencies)
    install_missing "${deps[@]}" ;;
  installed) ;;
  *) echo "QUATNAV_DOCS_FROM must be tree or installed, not '$from'" >&2; exit 2 ;;
esac
if ! where=$(cd /tmp && "$PY" -c "import quatnav._core, quatnav, os; print(os.path.dirname(quatnav.__file__))" 2>&1); then
  echo "tools/docs.sh: no importable quatnav with its compiled module (from: $from):" >&2
  echo "$where" | tail -3 >&2
  echo "install it (bash tools/demo.sh, or pip install .) or build it in-tree (docs/DEVELOPING.md)" >&2
  exit 1
fi
echo "== documenting quatnav from $where"

# Another package than last time: read every page again (autodoc's output is cached).
fresh=()
stamp=build/docs/.documented-from
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$where" ]; then fresh=(-E); fi
mkdir -p build/docs
echo "$where" >"$stamp"

# --- build ----------------------------------------------------------------------------------------
start=$SECONDS
if ! "$PY" -m sphinx -W --keep-going -q -b html "${fresh[@]}" docs "$OUT" "$@"; then
  echo "tools/docs.sh: the documentation build failed (warnings are errors; see above)" >&2
  exit 1
fi
echo "== documentation built in $((SECONDS - start)) s: $ROOT/$OUT/index.html"
