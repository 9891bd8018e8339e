# Developer entry points. Needs only Python 3.11 (`python3`) on a fresh machine.
#   make demo   install into .venv (if needed) and run the slider-crank verification case
#               (installing also compiles the packages' bytecode and numba's kernel cache:
#               python -m compileall, python -m loadcases.warmup)
#   make test   install with the test extra (if needed), then lint (ruff check, ruff format
#               --check), type-check (mypy) and run the whole test suite
#   make test-quick  the same without the tests marked slow (a few minutes less)
#   make bench  the speed comparison with Exudyn (the test extra installs Exudyn)
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
# The project's packages, compiled to bytecode at install as pip compiles a regular (not
# editable) install: without it a shell with PYTHONDONTWRITEBYTECODE set compiled every
# module again at each command (0.3 s of CPU of a set's start, 2026-11-30).
PACKAGES := cli loadcases mechlib benchmarks
# Stamps: reinstall only when pyproject.toml changes.
STAMP := $(VENV)/.installed
TEST_STAMP := $(VENV)/.installed-test
DEMO_CASE ?= loadcases/library/verification/slider_crank.case.yaml
DEMO_OUT ?= results
PYTEST_ARGS ?= -n 2

.PHONY: demo test test-quick lint bench install clean

demo: $(STAMP)
	$(BIN)/loads run $(DEMO_CASE) -o $(DEMO_OUT) --xlsx
	@echo "results are in $(abspath $(DEMO_OUT))/"

test: lint
	$(BIN)/python -m pytest $(PYTEST_ARGS)

test-quick: lint
	$(BIN)/python -m pytest $(PYTEST_ARGS) -m "not slow"

lint: $(TEST_STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy

bench: $(TEST_STAMP)
	$(BIN)/loads bench

install: $(STAMP)

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -e .
	$(BIN)/python -m compileall -q $(PACKAGES)
	$(BIN)/python -m loadcases.warmup
	@touch $@

$(TEST_STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -e '.[test]'
	$(BIN)/python -m compileall -q $(PACKAGES)
	$(BIN)/python -m loadcases.warmup
	@touch $@ $(STAMP)

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache
