# celtstone: `make run` reproduces the paper, `make test` runs lint + contracts + tests.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: install run test lint bench clean

install: $(STAMP)

$(STAMP): pyproject.toml requirements.lock
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -r requirements.lock
	$(BIN)/python -m pip install --quiet --no-deps -e .
	touch $(STAMP)

# The paper's Figure 2 cases (Kane & Levinson body, w3 = -5 rad/s, tilt 0.5/0.5 deg):
# rolling, and sliding at f = 0.35, 0.25, 0.15 with eps = 1 mm and N = m g.
# Issue 3 replaces this with `celtstone reproduce` (figures and report).
FRICTIONS := 0.35 0.25 0.15
run: $(STAMP)
	mkdir -p results
	$(BIN)/celtstone run --model rolling --t-end 20 --out results/rolling.nc --json > results/rolling.json
	for f in $(FRICTIONS); do \
	  $(BIN)/celtstone run --model sliding --friction-coefficient $$f --contact-radius 0.001 \
	    --normal-force static --t-end 20 --out results/sliding_f$$f.nc --json \
	    > results/sliding_f$$f.json || exit 1; \
	done
	$(BIN)/python -c "import json,glob; [print(p, json.load(open(p))['first_reversal_time']) for p in sorted(glob.glob('results/*.json'))]"

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/ruff format --check src tests benchmarks
	$(BIN)/mypy
	$(BIN)/lint-imports

test: lint
	$(BIN)/python -m pytest -n 2 -m "not slow" tests

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_simulate.py
	$(BIN)/python benchmarks/bench_sweep.py

clean:
	rm -rf $(VENV) build *.egg-info src/*.egg-info
