#!/usr/bin/env bash
# Build the documentation site (Sphinx, furo, MyST) into build/docs/html, warnings as errors.
#   bash tools/docs.sh [extra sphinx-build options]
# 1. installs the packages of the `docs` extra (pyproject.toml) that are missing;
# 2. documents the source tree (PYTHONPATH=python) when its compiled module
#    python/quatnav/_core*.so imports (in-tree build, docs/DEVELOPING.md), else the installed
#    quatnav (pip install .); QUATNAV_DOCS_FROM=tree|installed forces one;
# 3. runs sphinx-build -W --keep-going; the figures are made during the build by quatnav's own
#    commands (docs/_ext/quatnav_figures.py) into build/docs/figures, never into the sources.
# Environment: PYTHON (default python3).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
PY=${PYTHON:-python3}
OUT=build/docs/html

# --- the docs extra, read from pyproject.toml (one list of requirements) ---------------------
mapfile -t reqs < <("$PY" - <<'EOF'
import ast, re
text = open("pyproject.toml").read()
m = re.search(r"^docs\s*=\s*(\[.*?\])", text, re.M | re.S)
print("\n".join(ast.literal_eval(m.group(1))))
EOF
)
if ! "$PY" - "${reqs[@]}" <<'EOF'
import sys
from importlib.metadata import PackageNotFoundError, version
try:
    from packaging.requirements import Requirement
except ImportError:  # no packaging to compare versions with: let pip decide
    sys.exit(1)
missing = []
for r in map(Requirement, sys.argv[1:]):
    try:
        if not r.specifier.contains(version(r.name), prereleases=True):
            missing.append(str(r))
    except PackageNotFoundError:
        missing.append(str(r))
if missing:
    print("missing: " + " ".join(missing))
    sys.exit(1)
EOF
then
  echo "== installing the docs extra: ${reqs[*]}"
  "$PY" -m pip install -q "${reqs[@]}"
fi

# --- which quatnav to document -----------------------------------------------------------------
from=${QUATNAV_DOCS_FROM:-}
if [ -z "$from" ]; then
  if PYTHONPATH="$ROOT/python" "$PY" -c "import quatnav._core" >/dev/null 2>&1; then
    from=tree
  else
    from=installed
  fi
fi
case "$from" in
  tree) export PYTHONPATH="$ROOT/python${PYTHONPATH:+:$PYTHONPATH}" ;;
  installed) ;;
  *) echo "QUATNAV_DOCS_FROM must be tree or installed, not '$from'" >&2; exit 2 ;;
esac
if ! where=$(cd /tmp && "$PY" -c "import quatnav._core, quatnav, os; print(os.path.dirname(quatnav.__file__))" 2>&1); then
  echo "tools/docs.sh: no importable quatnav with its compiled module ($from):" >&2
  echo "$where" | tail -3 >&2
  echo "install it (pip install .) or build it in-tree (docs/DEVELOPING.md)" >&2
  exit 1
fi
echo "== documenting quatnav from $where"

# A different package than last time: read every page again (autodoc output is cached).
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
