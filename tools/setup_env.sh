# Sourced by tools/demo.sh and tools/test.sh: choose the Python environment and install what a
# fresh Debian machine lacks. After sourcing, $PY is the Python to use (inside a virtual
# environment unless one was already active or PYTHON was given) and these functions exist:
#   apt_install PKG...        install Debian packages that are missing (root or sudo)
#   pip_quiet ARGS...         pip install, printing one line per package set
#   timed, in_background, wait_background, print_timings: the stage timings of tools/stages.sh
#   pip_build ARGS...         pip install that builds quatnav: prints the compiler's progress
#                             lines ([n/N] Building ...) and a status line every 15 s. The build
#                             requirements go into the environment and the build runs there
#                             (--no-build-isolation): its CMake cache in build/ then names the
#                             same Eigen and pybind11 every time, so a second pip_build (tools/test.sh
#                             after tools/demo.sh) recompiles nothing. An isolated build would
#                             name a new temporary prefix each time and recompile every file.
# Environment: PYTHON (use this interpreter as it is, no virtual environment), QUATNAV_CXX (the
#              extension's compiler, default the system's c++; CXX, when set, wins),
#              QUATNAV_VENV (default .venv in the repository).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/stages.sh"
export PIP_DISABLE_PIP_VERSION_CHECK=1

QUATNAV_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$(dirname "${BASH_SOURCE[0]}")/apt.sh"   # apt_install

_in_venv() {
  "$1" -c 'import sys, os; sys.exit(0 if (sys.prefix != sys.base_prefix or os.environ.get("CONDA_PREFIX")) else 1)'
}

# --- the interpreter ---------------------------------------------------------------------------
if ! command -v "${PYTHON:-python3}" >/dev/null; then
  apt_install python3
fi
if [ -n "${PYTHON:-}" ]; then
  PY=$PYTHON
  echo "== using $PY as given by PYTHON"
elif _in_venv python3; then
  PY=$(command -v python3)
  echo "== using the active environment $("$PY" -c 'import sys; print(sys.prefix)')"
else
  VENV=${QUATNAV_VENV:-$QUATNAV_ROOT/.venv}
  if [ ! -x "$VENV/bin/python" ]; then
    echo "== creating a virtual environment in $VENV (quatnav and its dependencies go there, not into the system Python)"
    if ! python3 -m venv "$VENV" >/dev/null 2>&1; then
      rm -rf "$VENV"
      # Debian ships venv's pip wheels separately (python3-venv, or python3.X-venv).
      pyver=$(python3 -c 'import sys; print(f"{sys.version_info[0]}.{sys.version_info[1]}")')
      apt_install python3-venv "python$pyver-venv" || apt_install python3-venv
      python3 -m venv "$VENV"
    fi
  else
    echo "== using the virtual environment $VENV"
  fi
  PY=$VENV/bin/python
fi
# Console scripts and pip-installed tools (cmake, ninja, quatnav) of that environment come first.
PATH="$(dirname "$("$PY" -c 'import sys; print(sys.executable)')"):$PATH"
export PATH

# --- the compiler and Python headers that building the extension needs ---------------------------
# The extension is compiled by the system's c++ (GCC), or by QUATNAV_CXX (a CXX already set wins).
# QUATNAV_CXX=clang++ builds it in about 72 % of GCC's CPU time with the same bits, but its float32
# QuaternionEKF batch runs 25 % slower (bench/README.md, "The extension compiled by clang").
QUATNAV_CXX=${QUATNAV_CXX:-}
_need=()
command -v g++ >/dev/null || command -v c++ >/dev/null || _need+=(g++)
if [ -z "${CXX:-}" ] && [ "$QUATNAV_CXX" = clang++ ] && ! command -v clang++ >/dev/null; then
  _need+=(clang)
fi
if ! "$PY" -c 'import sysconfig, os, sys; sys.exit(0 if os.path.exists(os.path.join(sysconfig.get_paths()["include"], "Python.h")) else 1)'; then
  _need+=(python3-dev)
fi
[ ${#_need[@]} -eq 0 ] || apt_install "${_need[@]}" || command -v c++ >/dev/null || exit 1
_ext_cxx=${CXX:-}   # the compiler of pip_build only (the other builds choose their own)
if [ -z "$_ext_cxx" ] && [ -n "$QUATNAV_CXX" ] && command -v "$QUATNAV_CXX" >/dev/null; then _ext_cxx=$QUATNAV_CXX; fi

pip_quiet() {
  echo "== pip install $*"
  "$PY" -m pip install -q "$@"
}

pip_build() {
  local log start rc hb
  log=$(mktemp "${TMPDIR:-/tmp}/quatnav-build.XXXXXX.log")
  start=$SECONDS
  # build-system.requires of pyproject.toml, with cmake and ninja
  pip_quiet "scikit-build-core>=0.10" "pybind11>=2.12" "cmeel-eigen>=3.4" cmake ninja
  echo "== pip install $* (compiles the C++ extension with ${_ext_cxx:-c++}: about 4 minutes on 2 cores the first time; log $log)"
  ( while sleep 15; do echo "   ... still building ($((SECONDS - start)) s)"; done ) &
  hb=$!
  set +e
  env ${_ext_cxx:+CXX=$_ext_cxx} "$PY" -m pip install -v --no-build-isolation "$@" 2>&1 | tee "$log" \
    | sed -u -n -E -e 's/^ *(\[[0-9]+\/[0-9]+\] )/   \1/p' \
                   -e '/^ *(ERROR|error):|: error:|Successfully installed/ s/^/   /p'
  rc=${PIPESTATUS[0]}
  set -e
  kill "$hb" 2>/dev/null; wait "$hb" 2>/dev/null || true
  if [ "$rc" != 0 ]; then
    echo "quatnav: pip install failed (exit $rc); the last lines of $log:" >&2
    tail -n 40 "$log" >&2
    return "$rc"
  fi
  echo "   built and installed in $((SECONDS - start)) s"
  rm -f "$log"
}

