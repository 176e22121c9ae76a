#!/usr/bin/env bash
# Set up everything the project needs in .venv/ at the repository root, idempotently:
#   1. a Python 3.11 virtual environment,
#   2. this package (editable) with ROS 2 Jazzy from PyPI wheels and the test extras,
#   3. the recording middleware, built once into the plugin's cache,
#   4. the example ROS 2 package, installed into the venv so `package` + `executable` resolve.
# Re-running it only redoes the steps whose inputs changed.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
venv="${VENV:-$root/.venv}"
cd "$root"

find_python() {
  for candidate in "${PYTHON:-}" python3.11 python3; do
    [ -n "$candidate" ] || continue
    if command -v "$candidate" >/dev/null 2>&1 &&
       "$candidate" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
      echo "$candidate"; return 0
    fi
  done
  echo "bootstrap: Python 3.11 is required (ROS 2 Jazzy wheels are built for it); set PYTHON=/path/to/python3.11" >&2
  return 1
}

for tool in cmake make; do
  command -v "$tool" >/dev/null 2>&1 || { echo "bootstrap: '$tool' is required: apt-get install $tool" >&2; exit 1; }
done
command -v c++ >/dev/null 2>&1 || command -v g++ >/dev/null 2>&1 ||
  { echo "bootstrap: a C++17 compiler is required: apt-get install g++" >&2; exit 1; }

if [ ! -x "$venv/bin/python" ]; then
  python=$(find_python)
  echo "bootstrap: creating $venv"
  "$python" -m venv "$venv"
fi

# Reinstall the Python side only when its metadata changed.
stamp="$venv/.pytest-rmw-introspect.stamp"
want=$(cat pyproject.toml | sha256sum | cut -c1-16)
if [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
  echo "bootstrap: installing pytest-rmw-introspect with ROS 2 Jazzy wheels into $venv"
  log="$venv/bootstrap-pip.log"
  if ! { "$venv/bin/python" -m pip install --disable-pip-version-check --upgrade pip &&
         "$venv/bin/python" -m pip install --disable-pip-version-check -e ".[ros-wheels,test]"; } >"$log" 2>&1; then
    tail -n 40 "$log" >&2
    echo "bootstrap: pip install failed; full log: $log" >&2
    exit 1
  fi
  echo "$want" > "$stamp"
fi

echo "bootstrap: recording middleware at $("$venv/bin/python" -m pytest_rmw_introspect.run.middleware)"

if [ -x scripts/install-examples.sh ] && [ -d examples ]; then
  VENV="$venv" scripts/install-examples.sh
fi
