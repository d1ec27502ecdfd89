# Two commands for a fresh machine (Python 3.11, pip, make):
#   make run    set up .venv with what running needs and run the main job (Table 2, Figs 5-10)
#   make test   add the test tools (and Dask) to .venv, check the layers, run the test suite
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT ?= out

.PHONY: run test test-slow test-nojit lint bench docs docs-check clean

# one stamp per set of dependencies: `make run` never installs the test tools
$(VENV)/.runtime: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e .
	touch $@

$(VENV)/.dev: $(VENV)/.runtime
	$(BIN)/python -m pip install --quiet -e '.[dev,dask]'
	touch $@

# the docs extra, and dask: the Dask how-to page is executed
$(VENV)/.docs: $(VENV)/.runtime
	$(BIN)/python -m pip install --quiet -e '.[docs,dask]'
	touch $@

run: $(VENV)/.runtime
	$(BIN)/rubdiag table2 --out $(OUT)

test: $(VENV)/.dev
	$(BIN)/lint-imports
	$(BIN)/python -m pytest -n 2 --dist loadfile

test-slow: $(VENV)/.dev
	$(BIN)/python -m pytest -n 2 --dist loadfile -m slow

# the kernels as plain Python (NUMBA_DISABLE_JIT=1: the same source on the same arrays, to
# the same bits): the kernel tests with their NumPy twins, the element seam, the dense
# products, and the unit tests of the long steps' parts and of the crack's and pedestal's
# laws (their runs take minutes as Python). NumPy scalars warn where Numba's
# error_model="numpy" makes inf and nan silently: not errors here
NOJIT_TESTS := tests/kernels tests/simulation/test_element_seam.py tests/reduce/test_modal_tail.py \
	tests/simulation/test_long_steps.py::test_interpolation_is_exact_for_a_cubic_motion \
	tests/simulation/test_long_steps.py::test_error_estimate_is_zienkiewicz_xie \
	tests/simulation/test_crack.py::test_mayes_law_open_at_zero_shut_at_pi_and_turned_between \
	tests/simulation/test_crack.py::test_gasch_law_opens_when_the_moment_stretches_the_mouth \
	tests/simulation/test_pedestal_looseness.py::test_law_force_jacobian_and_lift_off \
	tests/simulation/test_pedestal_looseness.py::test_law_on_the_seam_records_and_books
test-nojit: $(VENV)/.dev
	NUMBA_DISABLE_JIT=1 $(BIN)/python -m pytest -n 2 --dist loadfile $(NOJIT_TESTS) \
		-W "ignore:overflow encountered:RuntimeWarning" \
		-W "ignore:invalid value encountered:RuntimeWarning" \
		-W "ignore:divide by zero encountered:RuntimeWarning" $(PYTEST_ARGS)

# the documentation site into docs/_build/html, warnings as errors; the notebooks and the
# pages with code cells are executed on small inputs, one per core at a time, and their outputs
# cached in docs/_build/jupyter_cache
docs: $(VENV)/.docs
	$(BIN)/python docs/execute_pages.py
	$(BIN)/python -m sphinx -b html -W --keep-going docs docs/_build/html

# the built site opened in headless Chromium (/usr/bin/chromium: apt-get install chromium):
# every figure loaded, no dead internal link; screenshots in docs/_build/screenshots
docs-check: docs
	$(BIN)/python docs/check_site.py

lint: $(VENV)/.dev
	$(BIN)/ruff check .

bench: $(VENV)/.runtime
	$(BIN)/python benchmarks/bench_modal.py
	$(BIN)/python benchmarks/bench_kernel.py
	$(BIN)/python benchmarks/bench_table2.py
	$(BIN)/python benchmarks/bench_features.py

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache
