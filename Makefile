# Two commands for a fresh machine (Python 3.11, pip, make):
#   make run    set up .venv and run the main job (the study's Table 2 and Figures 5-10)
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
	$(BIN)/rubdiag table2 --out $(OUT)

test: $(BIN)/rubdiag
	$(BIN)/python -m pytest -n 2 --dist loadfile

test-slow: $(BIN)/rubdiag
	$(BIN)/python -m pytest -n 2 --dist loadfile -m slow

lint: $(BIN)/rubdiag
	$(BIN)/ruff check .

bench: $(BIN)/rubdiag
	$(BIN)/python benchmarks/bench_modal.py
	$(BIN)/python benchmarks/bench_kernel.py
	$(BIN)/python benchmarks/bench_table2.py
	$(BIN)/python benchmarks/bench_features.py

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache
