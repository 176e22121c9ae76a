# The two commands of the README. Both set up .venv/ first (idempotent; see scripts/bootstrap.sh).
VENV ?= $(CURDIR)/.venv
export VENV

.PHONY: example test test-fast typecheck fuzz lint bootstrap bench asan conformance clean

bootstrap:
	scripts/bootstrap.sh

## example: the main job: check the example package's interface contracts
example: bootstrap
	scripts/check-examples.sh

## test: type check, then the whole test suite (middleware gtests, end-to-end, plugin, unit)
test: bootstrap typecheck
	$(VENV)/bin/pytest $(PYTEST_ARGS)

## test-fast: the fast tier alone (unit tests: no node is started, no pytest subprocess), in seconds
test-fast: bootstrap
	$(VENV)/bin/pytest -m "not e2e and not plugin" $(PYTEST_ARGS)

## fuzz: the input fuzz tests with many more cases (RMWI_FUZZ_CASES, RMWI_FUZZ_SEED to vary)
fuzz: bootstrap
	RMWI_FUZZ_CASES=$${RMWI_FUZZ_CASES:-5000} $(VENV)/bin/pytest -p no:cacheprovider tests/unit/test_fuzz_inputs.py $(PYTEST_ARGS)

## typecheck: mypy on the package (configured in pyproject.toml)
typecheck: bootstrap
	$(VENV)/bin/python -m mypy

lint: bootstrap
	$(VENV)/bin/python -m pip install --quiet ruff
	$(VENV)/bin/ruff check pytest_rmw_introspect tests bench examples

bench: bootstrap
	$(VENV)/bin/python bench/bench_time_to_capture.py
	$(VENV)/bin/python bench/bench_virtual_time.py
	$(VENV)/bin/python bench/bench_warm_start.py
	$(VENV)/bin/python bench/bench_parameters_lifecycle.py

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
