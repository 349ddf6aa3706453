# tyrefit: two commands set everything up on a fresh machine.
#   make demo   create .venv, install, run the main job on bundled data -> reports/demo/index.html
#   make test   create .venv, install with test extras, run the test suite
PYTHON ?= python3.11
VENV   ?= .venv
PY      = $(VENV)/bin/python
STAMP   = $(VENV)/.installed

.PHONY: demo test test-all bench data clean

$(VENV)/bin/python:
	@command -v $(PYTHON) >/dev/null 2>&1 || { echo "need $(PYTHON) (Python 3.11+) on PATH, or make PYTHON=python3"; exit 2; }
	$(PYTHON) -m venv $(VENV)

$(STAMP): $(VENV)/bin/python pyproject.toml
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e ".[test]"
	@touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/tyrefit demo --out reports/demo --force
	@echo "open reports/demo/index.html"

test: $(STAMP)
	$(PY) -m pytest -q

test-all: $(STAMP)
	$(PY) -m pytest -q -m "slow or not slow"

bench: $(STAMP)
	$(PY) -m benchmarks.run --out reports/bench

data: $(STAMP)
	$(PY) -m tyrefit.synthetic --out data

clean:
	rm -rf $(VENV) reports/demo reports/bench .pytest_cache
