# Two commands do everything on a fresh clone:
#   make demo   set up .venv and run the main job (vslsp demo on the embedded pybullet scene)
#   make test   set up .venv and run the whole test suite
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: install system-deps demo test test-fast test-read-only check bench clean

$(STAMP): pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -c constraints.txt -e '.[dev,pddl21]'
	touch $(STAMP)

install: $(STAMP)

# tmux and chromium for the terminal and browser tests (root only; see the script).
system-deps:
	@bash tools/system-deps.sh

demo: $(STAMP)
	$(BIN)/vslsp demo --out out/demo

test: $(STAMP) system-deps
	$(BIN)/python -m pytest -n 2 --dist loadfile -q

# Lint, format and types (run by .ci/run before the tests).
check: $(STAMP)
	$(BIN)/ruff check vslsp tests benchmarks experiments examples
	$(BIN)/ruff format --check vslsp tests benchmarks experiments examples
	$(BIN)/mypy

# The suite where nothing but its temporary folders can be written (docs/testing.md).
test-read-only: $(STAMP) system-deps
	PYTHON=$(abspath $(BIN))/python tools/read-only-suite.sh -n 2 --dist loadfile -q

test-fast: $(STAMP)
	$(BIN)/python -m pytest -n 2 --dist loadfile -q -m "not slow"

bench: $(STAMP)
	for b in benchmarks/bench_*.py; do $(BIN)/python $$b || exit 1; done

clean:
	rm -rf $(VENV) build *.egg-info
