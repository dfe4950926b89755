# Debian packages: sourced by tools/setup_env.sh and tools/test.sh; run on its own
# (`bash tools/apt.sh test`) it installs what tools/test.sh will need, so that .ci/run can fetch and
# unpack them (about 0.6 GB to unpack on a fresh machine: mostly I/O) beside the main job's build.
#   apt_install PKG...     install the Debian packages that are missing (root or sudo); one apt
#                          run at a time (a lock), so that a run in the background and one in
#                          the foreground wait for each other instead of failing
#   test_system_packages   the packages tools/test.sh needs, one per line (from CXX_TESTS,
#                          QUATNAV_SANITIZE, CXX_SANITIZE and QUATNAV_FUZZ_SECONDS as it reads them)
export DEBIAN_FRONTEND=noninteractive
SUDO=""
if [ "$(id -u)" != 0 ] && command -v sudo >/dev/null; then SUDO=sudo; fi
_apt_updated=0

apt_install() {
  local missing=() p
  for p in "$@"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
  [ ${#missing[@]} -eq 0 ] && return 0
  if [ "$(id -u)" != 0 ] && [ -z "$SUDO" ]; then
    echo "quatnav: missing Debian packages ${missing[*]}; install them as root (apt-get install ${missing[*]})" >&2
    return 1
  fi
  echo "== installing Debian packages: ${missing[*]}"
  (
    # One apt run at a time: flock waits for another holder of the lock (util-linux, always there).
    if command -v flock >/dev/null; then flock -w 1800 9 || true; fi
    if [ "$_apt_updated" = 0 ]; then $SUDO apt-get update -qq; fi
    $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  ) 9>"${TMPDIR:-/tmp}/quatnav-apt.lock"
  _apt_updated=1
}

test_system_packages() {
  local cxx_tests=${CXX_TESTS:-clang++} sanitize=${QUATNAV_SANITIZE:-0} fuzz=${QUATNAV_FUZZ_SECONDS:-0}
  local cxx_sanitize=${CXX_SANITIZE:-clang++}
  # The Cortex-M4F check: the cross compiler, newlib, the C++ headers (the images link no C++
  # runtime library, so not the 1.6 GB libstdc++-arm-none-eabi-newlib), and QEMU.
  printf '%s\n' gcc-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-dev qemu-system-arm
  [ -f /usr/include/gtest/gtest.h ] || echo libgtest-dev
  if [ "$cxx_tests" = clang++ ] || [ "$fuzz" -gt 0 ] || { [ "$sanitize" = 1 ] && [ "$cxx_sanitize" = clang++ ]; }; then
    command -v clang++ >/dev/null || echo clang
  fi
  if [ "$fuzz" -gt 0 ] || [ "$sanitize" = 1 ]; then   # the sanitizers' and libFuzzer's runtimes
    ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1 \
      || [ "$(uname -m)" != x86_64 ] || echo libclang-rt-dev
  fi
}

if [ "${BASH_SOURCE[0]}" = "$0" ]; then   # run, not sourced
  set -euo pipefail
  case "${1:-}" in
    test) mapfile -t _pkgs < <(test_system_packages); apt_install "${_pkgs[@]}" ;;
    *) echo "usage: bash tools/apt.sh test" >&2; exit 2 ;;
  esac
fi
