#!/usr/bin/env bash
# The hooks of .pre-commit-config.yaml (`make lint`, and `git commit` after `pre-commit install`).
# Each tool comes from the development venv (the lock: requirements/tools.in), never from a
# download: VENV (set by the Makefile), else <repo>/.venv, else PATH.
#
#   scripts/lint-hook.sh ruff                 ruff check on the Python trees (pyproject.toml's rules)
#   scripts/lint-hook.sh clang-format FILE..  clang-format --dry-run --Werror on the C++ files given,
#                                             in the style of .clang-format at the root; without
#                                             that file there is no style to check: skipped, saying so
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

tool() {
  local venv="${VENV:-$root/.venv}"
  if [ -x "$venv/bin/$1" ]; then
    echo "$venv/bin/$1"
  elif command -v "$1" >/dev/null; then
    command -v "$1"
  else
    echo "lint: no $1 in $venv/bin or on PATH: run make bootstrap (the lock installs it)" >&2
    exit 1
  fi
}

hook="${1:?usage: scripts/lint-hook.sh ruff|clang-format [FILE...]}"
shift
case "$hook" in
  ruff)
    ruff=$(tool ruff)
    exec "$ruff" check pytest_rmw_introspect tests bench examples scripts ;;
  clang-format)
    if [ ! -f .clang-format ]; then
      echo "lint: no .clang-format at the root: the C++ style is not checked"
      exit 0
    fi
    [ "$#" -gt 0 ] || exit 0
    clang_format=$(tool clang-format)
    exec "$clang_format" --style=file --dry-run --Werror "$@" ;;
  *)
    echo "lint: unknown hook $hook (ruff, clang-format)" >&2
    exit 2 ;;
esac
