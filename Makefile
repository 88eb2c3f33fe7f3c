# celtstone: `make run` reproduces the paper, `make test` runs lint + contracts + tests.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
BYTECODE := $(VENV)/.bytecode

.PHONY: install run test test-slow lint compile bytecode bench clean e2e docs

install: $(STAMP) $(BYTECODE)

# pip installs uv (pinned), uv the locked dependencies: 25 s against pip's 99 s on a fresh
# 2-core machine with no download cache (docs/decisions.md §35)
UV_VERSION := 0.13.9
UV := UV_LINK_MODE=copy $(BIN)/uv pip install --quiet --python $(BIN)/python

$(STAMP): pyproject.toml requirements.lock
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check uv==$(UV_VERSION)
	$(UV) -r requirements.lock
	$(UV) --no-deps -e .
	touch $(STAMP)

# Python's bytecode (.pyc) of the environment and of src, written once. uv does not write
# it (pip does), and where PYTHONDONTWRITEBYTECODE is set, as on CI's machines, every
# Python process would compile from source each module it imports: 2.5 s of the 5 s of a
# short `celtstone run --json` there (docs/decisions.md §40)
BYTECODE_JOBS ?= 0
bytecode: $(BYTECODE)

$(BYTECODE): $(STAMP)
	$(BIN)/python -m compileall -q -j $(BYTECODE_JOBS) \
		$$($(BIN)/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])') src
	touch $(BYTECODE)

# The paper's findings: Figures 2 and 3, the friction threshold, results/report.md
# (bodies: kane_levinson_1982 and toy_rattleback_10cm; see docs/bodies.md).
run: $(STAMP)
	$(BIN)/celtstone reproduce all --out results

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks docs
	$(BIN)/ruff format --check src tests benchmarks docs
	$(BIN)/mypy
	$(BIN)/lint-imports

# the solvers' first compile (about a minute of one core on a fresh clone) runs beside
# the linters and then the bytecode on the other core; without it both test workers would
# compile the same drivers at once
test: $(STAMP)
	$(MAKE) --no-print-directory -j2 compile lint bytecode BYTECODE_JOBS=1
	$(BIN)/python -m pytest -n 2 --dist loadgroup -m "not slow" tests

# compile every model's and method's run loop into numba's cache (`celtstone compile`;
# 2–3 s once cached)
compile: $(STAMP)
	$(BIN)/celtstone compile

# the tests marked `slow` (long oracle runs, a 64-point sweep store, full-length videos,
# the atlas search): not in `make test`'s 10 minutes; 9 min 33 s on the 2-core machine
test-slow: $(STAMP)
	$(BIN)/python -m pytest -n 2 --dist loadgroup -m slow tests

# the documentation site, warnings as errors: docs/_build/html/index.html (`make test`
# builds it too, in tests/test_docs.py)
docs: $(STAMP)
	$(BIN)/sphinx-build -W --keep-going -q -b html docs docs/_build/html

# the viewer in headless Chromium alone (also part of `make test`; skipped without /usr/bin/chromium)
e2e: $(STAMP)
	$(BIN)/python -m pytest tests/e2e -rs

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_cold_start.py
	$(BIN)/python benchmarks/bench_simulate.py
	$(BIN)/python benchmarks/bench_precision.py --ensemble
	$(BIN)/python benchmarks/bench_sweep.py
	$(BIN)/python benchmarks/bench_fit.py

clean:
	rm -rf $(VENV) build *.egg-info src/*.egg-info
	find src -name "*.nbi" -delete -o -name "*.nbc" -delete -o -name "*.pyc" -delete \
		-o -name "celtstone-numba-cache.lock" -delete
