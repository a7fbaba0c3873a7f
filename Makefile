# Two entry points, each doing all of its own set-up on a fresh machine:
#   make demo   install, then fill the holes of the bundled default mesh and draw before/after
#   make test   install with the test extras, then run the test suite
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
OUT    ?= demo-out

.PHONY: demo test lint bench clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed: $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install --quiet -e .
	touch $@

# the tests also check the benchmark's reference peers (CGAL, MeshLib), so they get them too
$(VENV)/.installed-test: $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install --quiet -e ".[test,peers]"
	touch $@

$(VENV)/.installed-bench: $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install --quiet -e ".[bench]"
	touch $@

demo: $(VENV)/.installed
	$(BIN)/surfinpaint demo -o $(OUT)

test: $(VENV)/.installed-test
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/python -m pytest -n 2 -q

# the validation benchmark also reads Debian's assimp-testmodels (Wuson); without them
# (no apt-get, not root) it skips that mesh with a note
bench: $(VENV)/.installed-bench
	-command -v apt-get >/dev/null && [ "$$(id -u)" = 0 ] && [ ! -d /usr/share/assimp/models ] \
		&& apt-get update -q && apt-get install -y -q assimp-testmodels
	$(BIN)/python benchmarks/accuracy.py
	$(BIN)/python benchmarks/validation.py --out validation.json

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache .ruff_cache
