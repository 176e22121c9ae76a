#!/usr/bin/env bash
# `make example`: check the example package against the package as installed into the venv by
# scripts/install-examples.sh: its tests (test/: marker tests and a smoke test of every
# executable) and its contract files as bare pytest items (contracts/*.interfaces.yaml, and
# contracts/robot.system.yaml: every process of launch/robot.launch.xml captured and checked as
# one system), then the system check across all its node contracts (types, hashes, QoS, missing peers).
# Extra arguments go to pytest.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
venv="${VENV:-$root/.venv}"
tests="$root/examples/rmw_introspect_examples/test"

[ -x "$venv/bin/pytest" ] ||
  { echo "check-examples: no pytest in $venv: run scripts/bootstrap.sh (or make bootstrap) first" >&2; exit 1; }
# (re)install the package if its sources changed since the last install; a no-op otherwise
VENV="$venv" "$root/scripts/install-examples.sh"

cd "$root/examples/rmw_introspect_examples"
"$venv/bin/pytest" -p no:cacheprovider "$tests" contracts "$@"
echo
exec "$venv/bin/rmw-introspect" compat contracts/*.interfaces.yaml
