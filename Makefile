# levitron: `make setup` once, then `make demo`, `make derive`, `make test`, `make bench`, `make lint`.
PY ?= .venv/bin/python
export PYTHONHASHSEED := 0

.PHONY: setup demo derive test test-slow lint bench golden clean-cache fuzz docs

# (re)install whenever pyproject.toml or constraints.txt changes: a new dependency or package reaches an old
# .venv too; -c constraints.txt: the exact versions CI tests (pyproject.toml has the package's ranges)
.venv/.installed: pyproject.toml constraints.txt
	test -x .venv/bin/python || python3 -m venv .venv
	.venv/bin/pip install --quiet --upgrade pip
	# PYTHONWARNINGS: setuptools warns that generated/<scene>/ and the C templates, data folders of the
	# mapped packages (pyproject.toml), could be namespace packages; they are data, on purpose
	PYTHONWARNINGS=ignore .venv/bin/pip install --quiet -c constraints.txt -e '.[test]'
	touch $@

setup: .venv/.installed

# The main job: derive every scene, print the thesis scene's equilibria, draw one picture.
demo: setup derive
	.venv/bin/levitron equilibrium thesis --plot out/thesis_equilibrium.png

# Regenerate generated/<scene>/ for every scene in scenes/ (unchanged scenes are skipped by hash).
derive: setup
	$(PY) -m levitron.derive

# Regenerate everything even where the hash matches (the golden files' update command).
golden: setup
	$(PY) -m levitron.derive --force

lint: setup
	$(PY) -m ruff check .

# pytest-xdist: one worker per core (-n auto: the physical cores), tests handed out as workers free
# up (worksteal: the long tests do not queue behind one another on one worker)
# `make test` is the loop (under 4 minutes cold on 2 cores); the slow tier (tests/slow.txt: the
# tests of 2 s and more) runs in `make test-slow`; CI runs both (.ci/run)
TEST_WORKERS ?= auto
test: setup
	$(PY) -m pytest -q -n $(TEST_WORKERS) --dist worksteal -m "not slow"

test-slow: setup
	$(PY) -m pytest -q -n $(TEST_WORKERS) --dist worksteal -m slow

# The property-based tests (tests/battery/test_properties.py) with 20 times the CI examples, random seeds.
fuzz: setup
	HYPOTHESIS_PROFILE=fuzz $(PY) -m pytest -q tests/battery/test_properties.py --hypothesis-show-statistics

# Every benchmark of the registry runtime/bench/kinds.py on its scenes (`levitron bench SCENE
# --kind KIND`): work-precision against heyoka (the optional extra `bench`) and the other backends,
# maps, design, launches; reports in reports/.
bench: setup
	PYTHONWARNINGS=ignore .venv/bin/pip install --quiet -c constraints.txt -e '.[bench]'
	$(PY) -m levitron.runtime.bench.kinds

# The documentation site (mkdocs.yml) from docs/ into site/: `mkdocs build --strict`, so a broken internal link
# or an API name mkdocstrings cannot find fails it; the tools are pyproject's extra `docs`. Open site/index.html.
docs: .venv/.docs-installed
	NO_MKDOCS_2_WARNING=1 $(PY) -m mkdocs build --strict --site-dir site

.venv/.docs-installed: .venv/.installed
	PYTHONWARNINGS=ignore .venv/bin/pip install --quiet -c constraints.txt -e '.[test,docs]'
	touch $@

# the cache folder of runtime/model/cbuild.py resolve_cache_env on Linux (platformdirs honours XDG_CACHE_HOME)
clean-cache:
	rm -rf "$${LEVITRON_CACHE:-$${XDG_CACHE_HOME:-$$HOME/.cache}/levitron}"
