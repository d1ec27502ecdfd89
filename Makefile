# Two commands for a fresh machine (Python 3.11, pip, make):
#   make run    set up .venv and run the main job
#   make test   set up .venv and run the test suite
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT ?= out

.PHONY: run test test-slow lint bench clean

$(BIN)/rubdiag: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[dev]'
	touch $@

run: $(BIN)/rubdiag
	$(BIN)/rubdiag modal
	$(BIN)/rubdiag campbell --out $(OUT)
	$(BIN)/rubdiag unbalance --case 1 --out $(OUT)
	$(BIN)/rubdiag unbalance --case 2 --out $(OUT)

test: $(BIN)/rubdiag
	$(BIN)/python -m pytest -n 2

test-slow: $(BIN)/rubdiag
	$(BIN)/python -m pytest -n 2 -m slow

lint: $(BIN)/rubdiag
	$(BIN)/ruff check .

bench: $(BIN)/rubdiag
	$(BIN)/python benchmarks/bench_modal.py

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache
