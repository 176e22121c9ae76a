#!/usr/bin/env bash
# Build the example ROS 2 package (examples/rmw_introspect_examples) with CMake and install it
# into the venv, which the ROS 2 PyPI wheels have made a ROS prefix: afterwards
# `package: rmw_introspect_examples` + `executable: talker` resolve like `ros2 run` to
# <venv>/lib/rmw_introspect_examples/talker.
#
# Idempotent: the package's sources, this script and the venv are hashed into a stamp in the
# venv; when nothing changed the script does nothing. Files an earlier install put into the
# venv but this one no longer installs are removed.
#
# Environment: VENV (default <repo>/.venv), EXAMPLES_BUILD_DIR (default <repo>/build/examples
# for that venv, <repo>/build/examples-<venv name> for another: each venv, e.g. one per ROS
# distribution, keeps its own build), FORCE=1 to rebuild even when the stamp matches.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
package=rmw_introspect_examples
src="$root/examples/$package"

die() { echo "install-examples: $*" >&2; exit 1; }

venv="${VENV:-$root/.venv}"
[ -x "$venv/bin/python" ] ||
  die "no Python at $venv/bin/python: run scripts/bootstrap.sh first (or set VENV to the venv with the ROS 2 wheels)"
venv=$(cd "$venv" && pwd)
default_build="$root/build/examples"
[ "$venv" = "$root/.venv" ] || default_build="$root/build/examples-$(basename "$venv")"
build_root="${EXAMPLES_BUILD_DIR:-$default_build}"
build="$build_root/$package"
stamp="$venv/.$package.stamp"
manifest="$venv/.$package.install_manifest.txt"

[ -f "$src/package.xml" ] || die "no ROS 2 package at $src (package.xml missing)"
[ -d "$venv/share/rcl/cmake" ] ||
  die "$venv is not a ROS 2 prefix (no share/rcl/cmake): install the ROS 2 Jazzy wheels (scripts/bootstrap.sh)"
"$venv/bin/python" -c 'import rclpy' 2>/dev/null ||
  die "$venv/bin/python cannot import rclpy: install the ROS 2 Jazzy wheels (scripts/bootstrap.sh)"
for tool in cmake make; do
  command -v "$tool" >/dev/null 2>&1 || die "'$tool' is required: apt-get install $tool"
done
command -v cc >/dev/null 2>&1 || command -v gcc >/dev/null 2>&1 ||
  die "a C compiler is required for the C node: apt-get install gcc"

want=$(
  {
    (cd "$src" && find . -type f ! -path '*/__pycache__/*' ! -name '*.pyc' -print0 |
      LC_ALL=C sort -z | xargs -0 sha256sum)
    sha256sum < "$0"
    echo "$venv"
  } | sha256sum | cut -c1-16
)
installed() {
  [ -f "$venv/share/ament_index/resource_index/packages/$package" ] &&
    [ -x "$venv/lib/$package/talker" ] && [ -x "$venv/lib/$package/c_talker" ]
}
if [ "${FORCE:-0}" != 1 ] && [ "$(cat "$stamp" 2>/dev/null)" = "$want" ] && installed; then
  echo "install-examples: $package is up to date in $venv"
  exit 0
fi

# A build directory configured for another venv or source tree caches the wrong paths.
if [ -f "$build/CMakeCache.txt" ] && [ "$(cat "$build/.configured-for" 2>/dev/null)" != "$venv $src" ]; then
  echo "install-examples: $build was configured for another venv or source tree; starting afresh"
  rm -rf "$build"
fi
mkdir -p "$build"

echo "install-examples: building $package into $venv"
log="$build/install-examples.log"
run() {
  if ! "$@" >>"$log" 2>&1; then
    tail -n 40 "$log" >&2
    die "failed: $* (full log: $log)"
  fi
}
: > "$log"
# find_package() of message packages reads the ament index from the environment; only the
# venv's prefix, so that a sourced /opt/ros cannot mix in.
export AMENT_PREFIX_PATH="$venv"
# Some wheels (foonathan_memory) install CMake configs under lib64/. python -m venv makes lib64 a
# link to lib, but virtualenv (tox) makes it a directory CMake does not search: add it as a prefix.
prefix_path="$venv"
[ -d "$venv/lib64" ] && [ ! -L "$venv/lib64" ] && prefix_path="$venv;$venv/lib64"
run cmake -S "$src" -B "$build" \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_PREFIX_PATH="$prefix_path" \
  -DCMAKE_INSTALL_PREFIX="$venv" \
  -DPython3_EXECUTABLE="$venv/bin/python" \
  -DBUILD_TESTING=OFF
echo "$venv $src" > "$build/.configured-for"
run cmake --build "$build" --parallel "$(nproc 2>/dev/null || echo 2)"
run cmake --install "$build"

# Remove what an earlier install put into the venv and this one did not.
if [ -f "$manifest" ]; then
  LC_ALL=C comm -23 <(LC_ALL=C sort -u "$manifest") <(LC_ALL=C sort -u "$build/install_manifest.txt") |
    while IFS= read -r stale; do
      case "$stale" in
        "$venv"/*) rm -f "$stale" && echo "install-examples: removed stale $stale" ;;
      esac
    done
fi
cp "$build/install_manifest.txt" "$manifest"

installed || die "the install did not produce $venv/lib/$package/{talker,c_talker} and the ament index entry"
echo "$want" > "$stamp"
echo "install-examples: installed $package: $(ls "$venv/lib/$package" | tr '\n' ' ')"
