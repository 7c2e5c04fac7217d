# Every target sets up what it needs on a fresh machine: a venv per Python version, its packages.
PY_VERSION ?= 3.13
VENV ?= .venv
PYTHON_BOOT = $(shell tools/find-python $(PY_VERSION))
PY = $(VENV)/bin/python

.PHONY: test test-core lint clean

$(VENV)/.core: requirements/core.txt
	@test -n "$(PYTHON_BOOT)" || { echo "Python $(PY_VERSION) not found"; exit 1; }
	$(PYTHON_BOOT) -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check -r requirements/core.txt
	touch $@

test: $(VENV)/.core
	$(PY) -m ruff check .
	$(PY) -m pytest

test-core: $(VENV)/.core
	$(PY) -m pytest tests/core

lint: $(VENV)/.core
	$(PY) -m ruff check .

clean:
	rm -rf $(VENV) .pytest_cache .hypothesis dist out
