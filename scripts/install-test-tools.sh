#!/usr/bin/env bash
# System packages some tests use, installed when missing: Chromium (the HTML drawing of
# `rmw-introspect graph` is tested in a real headless browser) and Graphviz (`dot` reads the
# DOT drawing). Both come from the distribution's packages; nothing is downloaded otherwise.
# Without root or apt-get this only says what to install: those tests are then skipped, saying so.
set -uo pipefail

# The official SARIF 2.1.0 JSON schema, which tests/unit/test_sarif.py validates the
# `--format sarif` logs against. No Python package ships it; Microsoft's SARIF SDK does, in the
# npm package @microsoft/jest-sarif (lib/schemas/sarif-2.1.0-rtm.5.json). Without npm the
# test is skipped, saying so.
sarif_package=@microsoft/jest-sarif@1.0.0-beta.0
if command -v npm >/dev/null 2>&1 &&
   [ ! -f "$(npm root -g)/@microsoft/jest-sarif/lib/schemas/sarif-2.1.0-rtm.5.json" ]; then
  if [ "$(id -u)" = 0 ]; then
    echo "install-test-tools: installing $sarif_package (the SARIF 2.1.0 schema)"
    npm install -g --no-fund --no-audit "$sarif_package" >/dev/null 2>&1 ||
      echo "install-test-tools: could not install $sarif_package; the SARIF schema test is skipped" >&2
  else
    echo "install-test-tools: the SARIF schema is missing; install with: npm install -g $sarif_package" >&2
  fi
fi

missing=()
command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 || missing+=(chromium)
command -v dot >/dev/null 2>&1 || missing+=(graphviz)
[ ${#missing[@]} -eq 0 ] && exit 0

if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
  echo "install-test-tools: installing ${missing[*]}"
  if apt-get update -qq >/dev/null 2>&1 &&
     DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null 2>&1; then
    exit 0
  fi
  echo "install-test-tools: could not install ${missing[*]}; the tests that need them are skipped" >&2
else
  echo "install-test-tools: ${missing[*]} missing; install with: sudo apt-get install ${missing[*]}" \
       "(the tests that need them are skipped until then)" >&2
fi
exit 0
