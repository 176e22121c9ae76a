# The two commands of the README. Both set up .venv/ first (idempotent; see scripts/bootstrap.sh).
# DISTRO=kilted runs any target on ROS 2 Kilted instead of Jazzy: its own venv (.venv-kilted)
# from its own lock (requirements/kilted.txt); the middleware's cache keeps one build per distribution.
# PYTHON_VERSION=3.12 runs any target on Python 3.12 instead of 3.11 (the wheels exist for both):
# its own venv (.venv-py312, .venv-kilted-py312), from the same lock (its hashes cover both Pythons).
DISTRO ?= jazzy
PYTHON_VERSION ?= 3.11
ifeq ($(PYTHON_VERSION),3.11)
PY_SUFFIX :=
else
PY_SUFFIX := -py$(subst .,,$(PYTHON_VERSION))
endif
ifeq ($(DISTRO),jazzy)
VENV ?= $(CURDIR)/.venv$(PY_SUFFIX)
else
VENV ?= $(CURDIR)/.venv-$(DISTRO)$(PY_SUFFIX)
endif
LOCK_FILE ?= $(CURDIR)/requirements/$(DISTRO).txt
export VENV LOCK_FILE PYTHON_VERSION

.PHONY: example test test-fast test-slow test-cost coverage dist typecheck fuzz lint bootstrap lock lowest newest bench asan conformance overlay docs precision-table soak clean

## bootstrap: .venv/ with exactly the packages of requirements/jazzy.txt (hash-checked), the
## package editable, the middleware built and the example package installed
bootstrap:
	scripts/bootstrap.sh

## lock: refresh the lock files to the newest releases (UPGRADE=0: keep today's pins where
## pyproject.toml allows them); then `make test lowest` and commit requirements/ (CONTRIBUTING.md)
lock: bootstrap
	scripts/lock.sh

## lowest: the fast and plugin tiers on the lowest versions pyproject.toml allows
## (requirements/lowest.txt: pytest 7.4, PyYAML 6.0.1, ...)
lowest:
	VENV=$(CURDIR)/.venv-lowest LOCK_FILE=$(CURDIR)/requirements/lowest.txt scripts/bootstrap.sh
	$(CURDIR)/.venv-lowest/bin/pytest -m "not e2e" $(PYTEST_ARGS)

## newest: the fast and plugin tiers on the newest releases, without the lock: finds the next
## upstream release that breaks us before a lock refresh does (not in CI, on purpose: CI stays locked)
newest:
	VENV=$(CURDIR)/.venv-newest LOCK_FILE=none scripts/bootstrap.sh
	$(CURDIR)/.venv-newest/bin/pytest -m "not e2e" $(PYTEST_ARGS)

## example: the main job: check the example package's interface contracts
example: bootstrap
	scripts/check-examples.sh

## test: type check, then the whole test suite (middleware gtests, end-to-end, plugin, unit)
test: bootstrap typecheck
	$(VENV)/bin/pytest $(PYTEST_ARGS)

## test-fast: the fast tier alone (unit tests: no node is started, no pytest subprocess), in seconds
test-fast: bootstrap
	$(VENV)/bin/pytest -m "not e2e and not plugin" $(PYTEST_ARGS)

## test-slow: the slow tier alone (tests/dist: the wheels of `make dist` installed into fresh venvs,
## a new user's first hour); deselected from every other run (tests/conftest.py)
test-slow: bootstrap
	$(VENV)/bin/pytest -m slow $(PYTEST_ARGS)

## test-cost: what each test costs (issue 48; docs/development.md, "What a test costs"): per tier the
## totals and the 30 slowest tests with the target processes each started; writes
## build/test-cost/<venv>-<TIER>/report.json. TIER=all (default), unit, plugin, e2e or slow; PYTEST_ARGS
## as for `make test` (-n 2, a path); DISTRO and PYTHON_VERSION as everywhere
TIER ?= all
TIER_all :=
TIER_unit := -m "not e2e and not plugin"
TIER_plugin := -m plugin
TIER_e2e := -m e2e
TIER_slow := -m slow
TIER_MARKS = $(if $(filter $(TIER),all unit plugin e2e slow),$(TIER_$(TIER)),$(error TIER=$(TIER): one of all, unit, plugin, e2e, slow))
RUN_NAME = $(notdir $(VENV))-$(TIER)
test-cost: bootstrap
	RMWI_TEST_COST=$(CURDIR)/build/test-cost/$(RUN_NAME) $(VENV)/bin/pytest $(TIER_MARKS) $(PYTEST_ARGS)

## coverage: line coverage of pytest_rmw_introspect/ over TIER (as test-cost), its subprocesses
## included, and the rules, commands, report formats and contract kinds exercised end to end;
## writes build/coverage/<venv>-<TIER>/summary.json (COVERAGE_COMPARE=<an older summary.json> says
## what is less now, exit 1). docs/development.md, "Line coverage and the exercised set"
COVERAGE_DIR = $(CURDIR)/build/coverage/$(RUN_NAME)
coverage: bootstrap
	rm -rf $(COVERAGE_DIR) && mkdir -p $(COVERAGE_DIR)
	@# the report is written whatever the tests' outcome; the target then fails as they did
	export COVERAGE_FILE=$(COVERAGE_DIR)/.coverage COVERAGE_RCFILE=$(CURDIR)/pyproject.toml; status=0; \
	RMWI_TEST_COST=$(COVERAGE_DIR)/cost $(VENV)/bin/python -m coverage run -m pytest $(TIER_MARKS) $(PYTEST_ARGS) || status=$$?; \
	$(VENV)/bin/python -m coverage combine --quiet && \
	$(VENV)/bin/python -m coverage report --sort=cover | tail -25 && \
	$(VENV)/bin/python -m coverage json --quiet -o $(COVERAGE_DIR)/coverage.json && \
	$(VENV)/bin/python scripts/coverage_summary.py $(COVERAGE_DIR) $(if $(COVERAGE_COMPARE),--compare $(COVERAGE_COMPARE)) \
	  && exit $$status

## dist: the sdist, the platform-independent wheel and the Linux x86_64 wheel with the middleware
## prebuilt for each of DIST_DISTROS (each built with its own venv: `make bootstrap DISTRO=<d>`)
DIST_DISTROS ?= jazzy,kilted
dist: bootstrap
	for distro in $$(echo $(DIST_DISTROS) | tr , ' '); do \
	  [ "$$distro" = jazzy ] || $(MAKE) bootstrap DISTRO=$$distro VENV=$(CURDIR)/.venv-$$distro LOCK_FILE=$(CURDIR)/requirements/$$distro.txt || exit 1; \
	done
	$(VENV)/bin/python scripts/dist.py --distros $(DIST_DISTROS)

## fuzz: the input fuzz tests with many more cases (RMWI_FUZZ_CASES, RMWI_FUZZ_SEED to vary)
fuzz: bootstrap
	RMWI_FUZZ_CASES=$${RMWI_FUZZ_CASES:-5000} $(VENV)/bin/pytest -p no:cacheprovider tests/unit/test_fuzz_inputs.py $(PYTEST_ARGS)

## typecheck: mypy on the package (configured in pyproject.toml)
typecheck: bootstrap
	$(VENV)/bin/python -m mypy

## lint: the hooks of .pre-commit-config.yaml on every file: ruff on the Python, clang-format on
## the C++ (all local hooks, tools from the venv: nothing is downloaded). pre-commit keeps its
## store in build/pre-commit, not in ~/.cache
lint: bootstrap
	PRE_COMMIT_HOME=$(CURDIR)/build/pre-commit $(VENV)/bin/pre-commit run --all-files --show-diff-on-failure

bench: bootstrap
	$(VENV)/bin/python bench/bench_time_to_capture.py
	$(VENV)/bin/python bench/bench_virtual_time.py
	$(VENV)/bin/python bench/bench_warm_start.py
	$(VENV)/bin/python bench/bench_parameters_lifecycle.py
	$(VENV)/bin/python bench/bench_cpp_talker.py
	$(VENV)/bin/python bench/bench_quiescence.py
	$(VENV)/bin/python bench/bench_cold_capture.py
	$(VENV)/bin/python bench/bench_system_rules.py
	$(VENV)/bin/python bench/bench_system_scale.py --pytest --plot docs/system-scale.png
	$(VENV)/bin/python bench/bench_gate.py

## soak: the example package's contracts checked SOAK_RUNS times (default 1000; -n 2, warm and cold
## alternating): every run's outcomes identical, no process, fd, shared memory segment or temporary
## directory left behind (scripts/soak/soak.py; hours: not in CI; SOAK_ARGS="--minutes 90" stops early, counted)
SOAK_RUNS ?= 1000
soak: bootstrap
	VENV=$(VENV) scripts/install-examples.sh
	$(VENV)/bin/python scripts/soak/soak.py --runs $(SOAK_RUNS) $(SOAK_ARGS)

## asan: the end-to-end nodes on an AddressSanitizer build of the middleware
asan: bootstrap
	scripts/asan-e2e.sh

## conformance: the official RMW API suite (test_rmw_implementation) on the middleware; needs
## RMW_CONFORMANCE_SRC=<dir with rmw_implementation and osrf_testing_tools_cpp checkouts>,
## see docs/conformance.md. CONFORMANCE_ARGS passes options (e.g. --details, --baseline-memcheck)
conformance: bootstrap
	$(VENV)/bin/python scripts/conformance/run.py $(CONFORMANCE_ARGS)

## overlay: rclcpp, components, launch_ros and RMW_IMPLEMENTATION selection over the wheels, built
## once into the cache from ROS_OVERLAY_SRC=<dir with the upstream checkouts>; see
## docs/overlay.md
overlay: bootstrap
	$(VENV)/bin/python scripts/overlay/build.py $(OVERLAY_ARGS)

## docs: the documentation site into site/ (mkdocs.yml): warnings are errors, and among them every
## broken internal link or anchor (MkDocs' validation and scripts/docs/site_hooks.py); external
## links are not checked (no network here). Open site/index.html. Built in a venv of its own,
## .venv-docs, from requirements/docs.txt alone (MkDocs, Material, the package's dependencies:
## no ROS 2, no middleware build), so it takes seconds once that venv exists
DOCS_VENV ?= $(CURDIR)/.venv-docs
docs:
	VENV=$(DOCS_VENV) LOCK_FILE=$(CURDIR)/requirements/docs.txt PYTHON_ONLY=1 scripts/bootstrap.sh
	NO_MKDOCS_2_WARNING=1 $(DOCS_VENV)/bin/mkdocs build --strict

## precision-table: run every modelled bring-up of tests/precision and its seeded bugs through the
## default system gate (minutes), record tests/precision/results.json and write the precision and
## recall table into docs/drift-rules.md (PRECISION_ARGS: e.g. --jobs 2, --system nav2_bringup)
precision-table: bootstrap
	$(VENV)/bin/python scripts/precision_table.py --run $(PRECISION_ARGS)

clean:
	rm -rf $(VENV) $(CURDIR)/.venv-lowest $(CURDIR)/.venv-newest $(CURDIR)/.venv-kilted $(CURDIR)/.venv-py312 $(CURDIR)/.venv-kilted-py312 $(DOCS_VENV) build dist .pytest_cache
