# One command each, from a fresh Debian machine with Rust and Python 3.11:
#   make demo   set up everything, then run `python -m pomkit demo` (writes ./pomkit-out/index.html)
#   make test   set up everything, then run the tests (cargo test and pytest)
#   make check  the fast loop before every commit, once `make test` has set up (under 3 minutes; the first run builds the extension in place)
SHELL := /bin/bash
export XDG_RUNTIME_DIR ?= /tmp/pomkit-xdg-$(shell id -u)
VENV := .venv/bin
# the tests that run a second time on the GL backend in `make test`: what differs by backend
# (the shaders as naga translates them to GLSL, the formats and targets, the goldens). The
# differential suite's generated maps (test_differential: a search over maps, the same on every
# backend) run on Vulkan only; on GL its real-content cases (the same checks: every method, shadow
# mode and filtering mode against the oracle, on elevation models and photographs) and its pinned
# cases run. `make test-gl` runs the whole suite on GL
GL_TESTS := tests/test_pipelines.py tests/test_cost.py tests/test_supersampling.py tests/test_methods.py tests/test_analytic.py tests/test_differential.py tests/test_shadows.py tests/test_throughput.py tests/test_sizes.py tests/test_reference_exact.py tests/test_assets.py tests/test_golden.py tests/test_oracle_curved.py

.PHONY: setup setup-test setup-bench setup-demo demo check test test-gl bench tables tables-slow tables-all stubs wheel info clean wild

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
	VIRTUAL_ENV=$(CURDIR)/.venv $(VENV)/maturin develop --release -q --features python,test-hooks > .maturin-develop.log 2>&1 || { cat .maturin-develop.log; exit 1; }
	$(VENV)/ruff check tools python/pomkit tests scripts
	$(VENV)/python -m mypy
	$(VENV)/python -m mypy.stubtest pomkit._core --mypy-config-file pyproject.toml
	cargo test --release --features test-hooks --lib -q 2>&1 | grep -E "^(test result|error|failures|---- )|panicked" ; test $${PIPESTATUS[0]} -eq 0
	$(VENV)/python -m pytest -q -p no:cacheprovider -m "not slow and not reference and not browser" tests

test: setup-test
	@scripts/stage.sh cargo-test
	scripts/cargo_test.sh --lib --tests 2>&1 | tee .cargo-test.log | grep -E "^(test result|running|error|failures|---- )|panicked" ; test $${PIPESTATUS[0]} -eq 0
	@scripts/stage.sh stubtest-mypy-numpy-floor
	$(VENV)/python -m mypy.stubtest pomkit._core --mypy-config-file pyproject.toml
	$(VENV)/python -m mypy
	scripts/numpy_floor.sh
	@scripts/stage.sh pytest
	$(VENV)/python -m pytest tests notebooks --nbmake -n 2 --dist loadfile
	@scripts/stage.sh gl
	@echo "== the GL backend (POMKIT_BACKEND=gl): core, method, analytic, differential, shadow and target tests =="
	POMKIT_BACKEND=gl scripts/cargo_test.sh --test core_render 2>&1 | grep -E "^(test result|error|failures|---- )|panicked" ; test $${PIPESTATUS[0]} -eq 0
	POMKIT_BACKEND=gl $(VENV)/python -m pytest $(GL_TESTS) --deselect tests/test_differential.py::test_differential -q -n 2 --dist loadfile
	@scripts/stage.sh distributions
	@echo "== the distributions: the manylinux2014 wheel's tag (auditwheel), the sdist built by pip, each rendering a frame =="
	scripts/check_dist.sh

# the whole Python suite on the second adapter, the GL backend (about 8 minutes here): run before
# every stop that touches shaders or tolerances (make test runs GL_TESTS there)
test-gl: setup-test
	POMKIT_BACKEND=gl cargo test --release --features test-hooks --test core_render 2>&1 | grep -E "^(test result|error|failures|---- )|panicked" ; test $${PIPESTATUS[0]} -eq 0
	POMKIT_BACKEND=gl $(VENV)/python -m pytest tests -q

# the corpus of other people's models (scripts/wild_manifest.toml, fetched by scripts/wild.py into
# ~/.cache/pomkit/wild, about 300 MB): every file loaded and measured against the oracle by
# tools/wild.py, written to docs/tables/wild.md (the test setup; tests/test_wild.py runs its sample);
# then issue 73's five cases on its files (tools/wild_cases.py: docs/tables/wild_cases.md), and
# the references (Mitsuba, pyrender, Cycles where set up) against the oracle on a sample of it
# (tools/wild_refs.py: docs/tables/wild_refs.md)
wild: setup-test
	$(VENV)/python tools/wild.py
	$(VENV)/python tools/wild_cases.py
	$(VENV)/python tools/wild_refs.py

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

# the measured tables of docs/tables, each under its provenance line (tools/provenance.py: writer,
# commit, adapter, date; tests/test_layout.py checks it and that this list names every file):
#   make tables       the quick ones (about 4 minutes in all on a 2-core llvmpipe machine), no extra beyond the library:
#     tools/tables.py --set quick       stability.md shadows.md timing.md
#     tools/cost_model.py               cost_model.md
#     tools/cost_refit.py               cost_refit.md (the timings of gpu/*-vulkan.json, `chain` counted here)
#   make tables-slow  the rest: longer, and they need Mitsuba, Blender or the bench's extras (the test setup):
#     tools/tables.py --set reference   references.md silhouettes.md pom_default.md seed002.md (Mitsuba)
#     tools/reference_agreement.py      reference_agreement.md (Mitsuba, pyrender)
#     tools/motion_table.py             motion.md
#     tools/cycles_agreement.py         cycles.md (Blender's Cycles)
#     tools/hybrid_table.py             hybrid.md hybrid.png (the zoo's assets: xatlas, trimesh; matplotlib)
#     tools/goals.py --tables           bench.md bench_goals.txt curved_tiling.md (the whole bench, as `make bench`)
#     scripts/gpu_check.py              gpu/llvmpipe-LLVM-15-0-6-256-bits-vulkan.md gpu/llvmpipe-LLVM-15-0-6-256-bits-vulkan.json
#                                       gpu/llvmpipe-LLVM-15-0-6-256-bits-gl.md gpu/llvmpipe-LLVM-15-0-6-256-bits-gl.json
#   make wild         the corpus of other people's models (about 300 MB fetched once; a few hours here):
#     tools/wild.py                     wild.md
#     tools/wild_cases.py               wild_cases.md
#     tools/wild_refs.py                wild_refs.md
#   a device run (scripts/gpu_check.sh on a lent GPU, not a make target here):
#     scripts/gpu_check.py              gpu/NVIDIA-H200-vulkan.md gpu/NVIDIA-H200-vulkan.json
#   make tables-all   both: the slow ones first, so that cost_refit.md reads the new gpu/ tables
tables: setup
	$(VENV)/python tools/tables.py --set quick
	$(VENV)/python tools/cost_model.py
	$(VENV)/python tools/cost_refit.py > /dev/null

tables-slow: setup-test
	$(VENV)/python tools/tables.py --set reference
	$(VENV)/python tools/reference_agreement.py
	$(VENV)/python tools/motion_table.py
	cd tests && PYTHONPATH=. ../$(VENV)/python ../tools/cycles_agreement.py > ../docs/tables/cycles.md.tmp
	mv docs/tables/cycles.md.tmp docs/tables/cycles.md
	cd tools && ../$(VENV)/python hybrid_table.py
	$(VENV)/python tools/goals.py --tables docs/tables
	$(VENV)/python scripts/gpu_check.py
	POMKIT_BACKEND=gl $(VENV)/python scripts/gpu_check.py

tables-all: tables-slow tables

# the scene classes' stub, written from the core's schema (src/scene/schema.rs)
stubs: setup
	$(VENV)/python tools/schema_stub.py

clean:
	rm -rf target .venv .venv-floor pomkit-out
