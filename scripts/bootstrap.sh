#!/usr/bin/env bash
# Set up everything the project needs in .venv/ at the repository root, idempotently:
#   1. a Python 3.11 (or PYTHON_VERSION=3.12) virtual environment,
#   2. exactly the packages of the lock file (requirements/jazzy.txt: ROS 2 Jazzy from PyPI
#      wheels, the test extras, mypy, the build backend; every file checked against its hash),
#      then this package, editable, on top of them,
#   3. the recording middleware, built once into the plugin's cache,
#   4. the example ROS 2 package, installed into the venv so `package` + `executable` resolve.
# Re-running it only redoes the steps whose inputs changed. A venv whose installed packages
# differ from the lock (an upgrade or install by hand, a package removed) is brought back to it.
# Environment: VENV (default <repo>/.venv), LOCK_FILE (default requirements/jazzy.txt; `none`:
# no lock, the newest releases pyproject.toml allows, as a user's `pip install` gets them:
# `make newest`), PYTHON_ONLY=1 (steps 1 and 2 alone, no CMake or compiler needed: `make docs`
# sets up .venv-docs from requirements/docs.txt this way).
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
venv="${VENV:-$root/.venv}"
lock="${LOCK_FILE:-$root/requirements/jazzy.txt}"
cd "$root"
[ "$lock" = none ] || [ -f "$lock" ] || { echo "bootstrap: no lock file at $lock (make lock writes it)" >&2; exit 1; }

# PYTHON_VERSION: 3.11 (default) or 3.12, the two Pythons ROS 2 Jazzy's and Kilted's wheels are built for
version="${PYTHON_VERSION:-3.11}"
case "$version" in
  3.11|3.12) ;;
  *) echo "bootstrap: PYTHON_VERSION=$version: the ROS 2 wheels exist for Python 3.11 and 3.12 only" >&2; exit 1 ;;
esac

find_python() {
  local candidate
  # on PATH first; then pyenv's installs, whose shims answer only for the selected version
  for candidate in "${PYTHON:-}" "python$version" python3 \
      "${PYENV_ROOT:-$HOME/.pyenv}"/versions/"$version".*/bin/"python$version"; do
    [ -n "$candidate" ] || continue
    if command -v "$candidate" >/dev/null 2>&1 &&
       "$candidate" -c "import sys; sys.exit(sys.version_info[:2] != tuple(map(int, '$version'.split('.'))))" 2>/dev/null; then
      echo "$candidate"; return 0
    fi
  done
  echo "bootstrap: Python $version is required (PYTHON_VERSION=$version; the ROS 2 wheels are built for 3.11 and 3.12); set PYTHON=/path/to/python$version" >&2
  return 1
}

python_only="${PYTHON_ONLY:-0}"
if [ "$python_only" != 1 ]; then
  for tool in cmake make; do
    command -v "$tool" >/dev/null 2>&1 || { echo "bootstrap: '$tool' is required: apt-get install $tool" >&2; exit 1; }
  done
  command -v c++ >/dev/null 2>&1 || command -v g++ >/dev/null 2>&1 ||
    { echo "bootstrap: a C++17 compiler is required: apt-get install g++" >&2; exit 1; }
fi

if [ ! -x "$venv/bin/python" ]; then
  python=$(find_python)
  echo "bootstrap: creating $venv"
  "$python" -m venv "$venv"
fi
if ! "$venv/bin/python" -c "import sys; sys.exit(sys.version_info[:2] != tuple(map(int, '$version'.split('.'))))"; then
  echo "bootstrap: $venv is Python $("$venv/bin/python" -c 'import sys; print("%d.%d" % sys.version_info[:2])'), not $version: remove it, or set VENV to another directory (make picks .venv-py312 for PYTHON_VERSION=3.12)" >&2
  exit 1
fi

pip=("$venv/bin/python" -m pip --disable-pip-version-check)
log="$venv/bootstrap-pip.log"
fail() { tail -n 40 "$log" >&2; echo "bootstrap: $1; full log: $log" >&2; exit 1; }

# Unlocked, on purpose (`make newest`): every run moves the venv to the newest releases that
# pyproject.toml allows, as a user's `pip install` gets them.
install_newest() {
  echo "bootstrap: installing the newest releases of pytest-rmw-introspect's dependencies into $venv (no lock)"
  "${pip[@]}" install --upgrade --upgrade-strategy eager pip setuptools wheel -e ".[ros-wheels,test]" \
    >"$log" 2>&1 || fail "pip install failed"
  echo "bootstrap: newest: $("${pip[@]}" list --format=freeze 2>/dev/null |
    grep -iE '^(pytest|pyyaml|jsonschema|deepdiff|filelock|ros-jazzy-rclpy)==' | tr '\n' ' ')"
}

# Exactly the lock's packages: reinstalled when the lock or the package's metadata changed (the
# stamp), or when what is installed is no longer the lock's set (scripts/lock_status.py says how).
install_locked() {
  local stamp="$venv/.pytest-rmw-introspect.stamp" want extra
  want=$(cat pyproject.toml "$lock" | sha256sum | cut -c1-16)
  status() { "$venv/bin/python" scripts/lock_status.py "$lock" --require pytest-rmw-introspect; }
  if [ "$(cat "$stamp" 2>/dev/null)" = "$want" ] && status >/dev/null 2>&1; then
    return 0
  fi
  echo "bootstrap: installing the locked packages ($(basename "$lock")) and pytest-rmw-introspect into $venv"
  : > "$log"
  # what pip or uv installed that the lock does not name goes first (a package added by hand,
  # one the lock dropped); pip install then moves every other package to its locked version
  extra=$(status 2>>"$log" | sed -n 's/^extra \([^=]*\)==.*/\1/p' || true)
  if [ -n "$extra" ]; then
    echo "bootstrap: removing packages the lock does not name: $(echo $extra)"
    # shellcheck disable=SC2086
    "${pip[@]}" uninstall --yes $extra >>"$log" 2>&1 || fail "pip uninstall failed"
  fi
  { "${pip[@]}" install --require-hashes -r "$lock" &&
    "${pip[@]}" install --no-deps --no-build-isolation -e . &&
    status; } >>"$log" 2>&1 || fail "installing the lock failed"
  echo "$want" > "$stamp"
}

if [ "$lock" = none ]; then install_newest; else install_locked; fi
[ "$python_only" = 1 ] && exit 0

# (a variable first: a failed build inside `echo "$(...)"` would not stop the script)
library=$("$venv/bin/python" -m pytest_rmw_introspect.run.middleware) ||
  { echo "bootstrap: building the recording middleware failed (above)" >&2; exit 1; }
echo "bootstrap: recording middleware at $library"

if [ -x scripts/install-examples.sh ] && [ -d examples ]; then
  VENV="$venv" scripts/install-examples.sh
fi
