#!/usr/bin/env bash
# `make lock`: write the lock files the development environment is installed from.
#
#   requirements/jazzy.txt   every package `make bootstrap` installs (ROS 2 Jazzy wheels, the
#                            package's dependencies and extras, mypy, the tools), at the newest
#                            releases, each with the hashes of its files
#   requirements/kilted.txt  the same with ROS 2 Kilted's wheels (`make bootstrap DISTRO=kilted`)
#   requirements/lowest.txt  the same with the package's own dependencies (and the test extra)
#                            at the lowest versions pyproject.toml allows: `make lowest` runs the
#                            fast tier on it, so a floor that no longer works is found here
#   requirements/overlay.txt what the C++ and launch overlay (`make overlay`) installs from PyPI
#                            beyond the venv (requirements/overlay.in), with jazzy.txt's
#                            versions as constraints
#   requirements/docs.txt    what `make docs` builds the site with, in .venv-docs: MkDocs,
#                            Material and the package's own dependencies (requirements/docs.in),
#                            with jazzy.txt's versions as constraints; no ROS 2
#
# UPGRADE=1 (the default) moves every package to its newest release; UPGRADE=0 keeps the pins
# of the current lock where pyproject.toml still allows them (after adding a dependency).
# Needs uv, which the lock itself installs into the venv (VENV, default <repo>/.venv).
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
venv="${VENV:-$root/.venv}"
cd "$root"
uv="${UV:-$venv/bin/uv}"
[ -x "$uv" ] || { echo "lock: no uv at $uv: run make bootstrap first (the lock installs it), or set UV" >&2; exit 1; }

upgrade=()
[ "${UPGRADE:-1}" = 1 ] && upgrade=(--upgrade)
common=(--generate-hashes --python-version 3.11 --quiet)

"$uv" pip compile pyproject.toml requirements/tools.in --extra ros-wheels --extra jazzy --extra test \
  "${common[@]}" "${upgrade[@]}" --custom-compile-command "make lock" -o requirements/jazzy.txt
"$uv" pip compile pyproject.toml requirements/tools.in --extra kilted --extra test \
  "${common[@]}" "${upgrade[@]}" --custom-compile-command "make lock" -o requirements/kilted.txt

# The lowest set keeps the ROS 2 wheels and the installer at the versions just locked (the
# distribution decides those, not a range of ours) and takes the lowest of everything else.
# (a fixed relative path: the lock names it in its comments, which must not change from run to run)
pins=build/lock/distribution-pins.txt
mkdir -p build/lock
grep -E '^(ros-[a-z0-9-]+|pip|setuptools|wheel)==' requirements/jazzy.txt | sed 's/ *\\$//' > "$pins"
"$uv" pip compile pyproject.toml requirements/build.in --extra ros-wheels --extra jazzy --extra test \
  --resolution lowest-direct --constraint "$pins" "${common[@]}" \
  --custom-compile-command "make lock" -o requirements/lowest.txt

# The overlay's lock: every package jazzy.txt also names keeps jazzy.txt's version (the overlay
# installs only the others, beside the venv that has these).
grep -E '^[A-Za-z0-9._-]+==' requirements/jazzy.txt | sed 's/ *\\$//' > build/lock/jazzy-pins.txt
"$uv" pip compile requirements/overlay.in --constraint build/lock/jazzy-pins.txt \
  "${common[@]}" "${upgrade[@]}" --custom-compile-command "make lock" -o requirements/overlay.txt

# The documentation's lock: the same versions as jazzy.txt for every package both name.
"$uv" pip compile pyproject.toml requirements/docs.in --constraint build/lock/jazzy-pins.txt \
  "${common[@]}" "${upgrade[@]}" --custom-compile-command "make lock" -o requirements/docs.txt

# One lock serves Python 3.11 and 3.12 (PYTHON_VERSION=3.12): the hashes cover every file of each
# pinned version, and the resolution must be the same on both; a package that only one of them
# needs would make them differ, and the lock would then have to be split per version.
for lock in jazzy kilted; do
  "$uv" pip compile pyproject.toml requirements/tools.in --extra test \
    $([ "$lock" = jazzy ] && echo --extra ros-wheels) --extra "$lock" \
    --generate-hashes --python-version 3.12 --quiet --constraint "requirements/$lock.txt" \
    --custom-compile-command "make lock" -o "build/lock/$lock-py312.txt"
  if ! diff <(grep -E '^[A-Za-z0-9._-]+==' "requirements/$lock.txt") \
            <(grep -E '^[A-Za-z0-9._-]+==' "build/lock/$lock-py312.txt") >/dev/null; then
    echo "lock: requirements/$lock.txt resolves differently on Python 3.12 (build/lock/$lock-py312.txt): split the lock per Python version" >&2
    exit 1
  fi
done

for lock in jazzy kilted lowest overlay docs; do
  echo "lock: wrote requirements/$lock.txt ($(grep -cE '^[a-z0-9]' "requirements/$lock.txt") packages)"
done
echo "lock: make test, make test DISTRO=kilted and make lowest try them"
