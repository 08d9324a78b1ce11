# levitron: `make setup` once, then `make demo`, `make derive`, `make test`, `make bench`.
PY ?= .venv/bin/python
export PYTHONHASHSEED := 0

.PHONY: setup demo derive test bench golden clean-cache

# (re)install whenever pyproject.toml changes: a new dependency or package reaches an old .venv too
.venv/.installed: pyproject.toml
	test -x .venv/bin/python || python3 -m venv .venv
	.venv/bin/pip install --quiet --upgrade pip
	.venv/bin/pip install --quiet -e '.[test]'
	touch $@

setup: .venv/.installed

# The main job: derive every scene, print the thesis scene's equilibria, draw one picture.
demo: setup derive
	.venv/bin/levitron equilibrium thesis --plot out/thesis_equilibrium.png

# Regenerate generated/<scene>/ for every scene in scenes/ (unchanged scenes are skipped by hash).
derive: setup
	$(PY) -m derive

# Regenerate everything even where the hash matches (the golden files' update command).
golden: setup
	$(PY) -m derive --force

test: setup
	$(PY) -m pytest -q

bench: setup
	.venv/bin/levitron bench thesis

clean-cache:
	rm -rf $${LEVITRON_CACHE:-$$HOME/.cache/levitron}
