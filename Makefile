# The two commands of the README. Both set up .venv/ first (idempotent; see scripts/bootstrap.sh).
VENV ?= $(CURDIR)/.venv
export VENV

.PHONY: example test lint bootstrap bench asan conformance clean

bootstrap:
	scripts/bootstrap.sh

## example: the main job: check the example package's interface contracts
example: bootstrap
	scripts/check-examples.sh

## test: the whole test suite (middleware gtests, end-to-end, plugin, unit)
test: bootstrap
	$(VENV)/bin/pytest $(PYTEST_ARGS)

lint: bootstrap
	$(VENV)/bin/python -m pip install --quiet ruff
	$(VENV)/bin/ruff check pytest_rmw_introspect tests bench examples

bench: bootstrap
	$(VENV)/bin/python bench/bench_time_to_capture.py
	$(VENV)/bin/python bench/bench_virtual_time.py

## asan: the end-to-end nodes on an AddressSanitizer build of the middleware
asan: bootstrap
	scripts/asan-e2e.sh

## conformance: the official RMW API suite (test_rmw_implementation) on the middleware; needs
## RMW_CONFORMANCE_SRC=<dir with rmw_implementation and osrf_testing_tools_cpp checkouts>,
## see README.md, "Conformance". CONFORMANCE_ARGS passes options (e.g. --details, --baseline-memcheck)
conformance: bootstrap
	$(VENV)/bin/python scripts/conformance/run.py $(CONFORMANCE_ARGS)

clean:
	rm -rf $(VENV) build .pytest_cache
