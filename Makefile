# Every target sets up what it needs on a fresh machine: a venv per Blender version, its packages.
#   .venv      Python 3.13: bpy 5.2 (primary), the core's tools, OpenImageIO
#   .venv-4.5  Python 3.11: bpy 4.5 LTS, numpy<2, OpenImageIO 3.0.x
VENV ?= .venv
VENV45 ?= .venv-4.5
PY = $(VENV)/bin/python
PY45 = $(VENV45)/bin/python
PIP = -m pip install --quiet --disable-pip-version-check

.PHONY: test test-5.2 test-4.5 test-fast test-core test-blender test-blender-4.5 lint package demo bench stress \
	clean

define make_venv
	@py="$$(tools/find-python $(1))" && test -n "$$py" || { echo "Python $(1) not found"; exit 1; }; \
	  test -x $(2)/bin/python || "$$py" -m venv $(2)
endef

$(VENV)/.core: requirements/core.txt
	$(call make_venv,3.13,$(VENV))
	$(PY) $(PIP) -r requirements/core.txt
	touch $@

$(VENV)/.blender: $(VENV)/.core requirements/blender.txt
	$(PY) $(PIP) -r requirements/blender.txt
	touch $@

$(VENV)/.bench: $(VENV)/.blender requirements/bench.txt
	$(PY) $(PIP) -r requirements/bench.txt
	touch $@

# The demo needs Blender alone: no test tools.
$(VENV)/.demo: requirements/demo.txt
	$(call make_venv,3.13,$(VENV))
	@echo "make demo: downloading Blender 5.2 as a Python module (about 1 GB) into $(VENV);" \
	  "the first run only"
	$(PY) $(PIP) -r requirements/demo.txt
	touch $@

$(VENV45)/.blender: requirements/blender-4.5.txt
	$(call make_venv,3.11,$(VENV45))
	$(PY45) $(PIP) -r requirements/blender-4.5.txt
	touch $@

# Every test: lint and the Blender tests on 5.2; the Blender tests again on 4.5 LTS but the
# renders not marked lts, and the core's. On CI's two cores, two lanes of about equal length
# side by side, each installing its own Blender first (the two downloads overlap): 5.2's (lint,
# the Blender tests that render no shots, then the shots) and 4.5's (its Blender tests and the
# lts renders: its references, its sky, its bake export; then the whole core suite, on 4.5's
# numpy<2). Each lane's output is printed whole when it ends.
test:
	$(MAKE) --no-print-directory -j2 --output-sync=target test-4.5 test-5.2

test-5.2: lint
	$(PY) -m pytest -m "not slow" tests/blender
	$(PY) -m pytest -m slow tests/blender

test-4.5: $(VENV45)/.blender
	$(PY45) -m pytest -m "not slow or lts" tests/blender
	$(PY45) -m pytest tests/core

# The inner loop: everything but the slow tests (EEVEE renders, the 7,000-pose suite, the largest
# grid, the tiling check) on 5.2: about four minutes on a 2-core machine, under three of them the
# Blender tests that render nothing.
test-fast: $(VENV)/.blender
	$(PY) -m pytest -m "not slow"

test-core: $(VENV)/.core
	$(PY) -m pytest tests/core

test-blender: $(VENV)/.blender
	$(PY) -m pytest tests/blender

test-blender-4.5: $(VENV45)/.blender
	$(PY45) -m pytest tests/blender

lint: $(VENV)/.blender
	$(PY) -m ruff check .

package: $(VENV)/.blender
	$(PY) tools/package.py dist

demo: $(VENV)/.demo
	$(PY) tools/demo.py out/ocean.png

# Benchmarks: docs/benchmarks.md and docs/bench_*.png (QUICK=1: a short smoke run;
# ONLY=accuracy,render: re-measure those steps, keep the rest from docs/benchmarks.json).
bench: $(VENV)/.bench
	$(PY) -m tools.bench $(if $(QUICK),--quick) $(if $(ONLY),--only=$(ONLY))

# The stability suite's checks on 100,000 fresh poses (several minutes): the worst error-to-tolerance
# ratio of each check and the pose that gave it (SEED=n: a given seed; POSES=n: another count).
stress: $(VENV)/.core
	$(PY) -m tools.stress $(if $(POSES),--poses=$(POSES)) $(if $(SEED),--seed=$(SEED))

clean:
	rm -rf $(VENV) $(VENV45) .pytest_cache .hypothesis dist out
