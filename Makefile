# One command each, from a fresh Debian machine with Rust and Python 3.11:
#   make demo   set up everything, then run `python -m pomkit demo` (writes ./pomkit-out/index.html)
#   make test   set up everything, then run the tests (cargo test and pytest)
#   make check  the fast loop before every commit, once `make test` has set up (under 3 minutes; the first run builds the extension in place)
SHELL := /bin/bash
export XDG_RUNTIME_DIR ?= /tmp/pomkit-xdg-$(shell id -u)
VENV := .venv/bin
# the tests that run a second time on the GL backend in `make test` (about five minutes)
GL_TESTS := tests/test_pipelines.py tests/test_cost.py tests/test_supersampling.py tests/test_methods.py tests/test_analytic.py tests/test_differential.py tests/test_shadows.py tests/test_throughput.py tests/test_sizes.py tests/test_reference_exact.py tests/test_assets.py tests/test_golden.py tests/test_oracle_curved.py

.PHONY: setup setup-test setup-bench setup-demo demo check test test-gl bench tables stubs wheel info clean

setup:
	scripts/setup.sh

setup-test:
	scripts/setup.sh test reference notebooks bench distributed browser blender

setup-bench:
	scripts/setup.sh bench

setup-demo:
	scripts/setup.sh demo

demo: setup-demo
	$(VENV)/python -m pomkit demo

# lint, types, the Rust unit tests and the tests not marked slow, reference or browser; it builds
# the extension in place first (`maturin develop`: seconds when only Python changed)
check:
	VIRTUAL_ENV=$(CURDIR)/.venv $(VENV)/maturin develop --release -q > .maturin-develop.log 2>&1 || { cat .maturin-develop.log; exit 1; }
	$(VENV)/ruff check tools python/pomkit tests scripts
	$(VENV)/python -m mypy
	$(VENV)/python -m mypy.stubtest pomkit._core --mypy-config-file pyproject.toml
	cargo test --release --lib -q 2>&1 | grep -E "^(test result|error|failures|---- )|panicked" ; test $${PIPESTATUS[0]} -eq 0
	$(VENV)/python -m pytest -q -p no:cacheprovider -m "not slow and not reference and not browser" tests

test: setup-test
	cargo test --release --lib --tests 2>&1 | tee .cargo-test.log | grep -E "^(test result|running|error|failures|---- )|panicked" ; test $${PIPESTATUS[0]} -eq 0
	$(VENV)/python -m mypy.stubtest pomkit._core --mypy-config-file pyproject.toml
	$(VENV)/python -m mypy
	scripts/numpy_floor.sh
	$(VENV)/python -m pytest tests notebooks --nbmake
	@echo "== the GL backend (POMKIT_BACKEND=gl): core, method, analytic, differential, shadow and target tests =="
	POMKIT_BACKEND=gl cargo test --release --test core_render 2>&1 | grep -E "^(test result|error|failures|---- )|panicked" ; test $${PIPESTATUS[0]} -eq 0
	POMKIT_BACKEND=gl $(VENV)/python -m pytest $(GL_TESTS) -q
	@echo "== the distributions: the manylinux2014 wheel's tag (auditwheel), the sdist built by pip, each rendering a frame =="
	scripts/check_dist.sh

# the whole Python suite on the second adapter, the GL backend (about 8 minutes here): run before
# every stop that touches shaders or tolerances (make test runs GL_TESTS there)
test-gl: setup-test
	POMKIT_BACKEND=gl cargo test --release --test core_render 2>&1 | grep -E "^(test result|error|failures|---- )|panicked" ; test $${PIPESTATUS[0]} -eq 0
	POMKIT_BACKEND=gl $(VENV)/python -m pytest tests -q

# one abi3 wheel (CPython 3.10 and later, manylinux2014: glibc 2.17 and later) in target/wheels,
# and the sdist in target/sdist; setup reuses the wheel while the sources match
wheel: setup
	.venv/bin/maturin sdist -o target/sdist >/dev/null
	@ls target/wheels/pomkit-*-abi3-*.whl target/sdist/pomkit-*.tar.gz

info: setup
	$(VENV)/python -m pomkit info

# the bench's sweep and charts (python -m pomkit bench), then the project's goals over suites of
# scenes (tools/goals.py): goals.txt and goals.csv beside them in pomkit-out/bench
bench: setup-bench
	$(VENV)/python tools/goals.py

# the measured tables of docs/tables (tools/tables.py; the reference tables need the test setup's Mitsuba)
tables: setup
	$(VENV)/python tools/tables.py

# the scene classes' stub, written from the core's schema (src/scene/schema.rs)
stubs: setup
	$(VENV)/python tools/schema_stub.py

clean:
	rm -rf target .venv .venv-floor pomkit-out
