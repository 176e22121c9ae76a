#!/usr/bin/env bash
# Run the end-to-end nodes under AddressSanitizer: builds the middleware with
# -DRMW_INTROSPECT_SANITIZE=address into build/asan, then runs every node of tests/middleware/nodes
# and the example's c_talker on it (until they settle, and once more stopped by SIGINT to exercise
# teardown). Prints one line per run; exits non-zero if ASan reported anything.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
venv="${VENV:-$root/.venv}"
build="$root/build/asan"
py="$venv/bin/python"

AMENT_PREFIX_PATH="$venv" cmake -S "$root/rmw_introspect_cpp" -B "$build" -DCMAKE_PREFIX_PATH="$venv" \
  -DRMW_INTROSPECT_SANITIZE=address -DBUILD_TESTING=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j "$(nproc)" >/dev/null

libdirs=$("$py" -c 'from pytest_rmw_introspect import ros_env; print(ros_env.detect().library_path())')
export LD_LIBRARY_PATH="$libdirs" _ROS_WHEELS_BOOTSTRAP_COMPLETE=1 ASAN_OPTIONS=detect_leaks=0
# libasan must come first; leak detection is off: the interpreter and rclpy leak by design at exit
preload="$(gcc -print-file-name=libasan.so):$build/librmw_introspect_cpp.so"
out=$(mktemp -d)
failed=0

run() {  # run NAME MODE COMMAND...
  local name=$1 mode=$2; shift 2
  local log="$out/$name.$mode.log" status
  if [ "$mode" = settle ]; then
    set +e; LD_PRELOAD="$preload" RMW_INTROSPECT_EXIT=1 RMW_INTROSPECT_OUTPUT="$out/$name.json" \
      timeout 30 "$@" >"$log" 2>&1; status=$?; set -e
  else
    LD_PRELOAD="$preload" RMW_INTROSPECT_OUTPUT="$out/$name.sigint.json" "$@" >"$log" 2>&1 &
    local pid=$!; sleep 1.5; kill -INT "$pid" 2>/dev/null || true
    set +e; wait "$pid"; status=$?; set -e
  fi
  local errors; errors=$(grep -c 'ERROR: AddressSanitizer' "$log" || true)
  printf '%-22s %-7s exit %-3s AddressSanitizer errors: %s\n' "$name" "$mode" "$status" "$errors"
  [ "$errors" = 0 ] || { failed=1; cat "$log"; }
}

for node in "$root"/tests/middleware/nodes/*.py; do
  name=$(basename "$node" .py)
  run "$name" settle "$py" "$node"
  [ "$name" = raiser ] || run "$name" sigint "$py" "$node"
done
c_talker="$venv/lib/rmw_introspect_examples/c_talker"
if [ -x "$c_talker" ]; then
  run c_talker settle "$c_talker"
  run c_talker sigint "$c_talker"
fi
rm -rf "$out"
exit $failed
