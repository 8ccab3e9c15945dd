# cairn: the two commands of README, and their helpers.
#   make demo   install missing Debian packages, build, run cairn check on a bundled example
#   make test   install missing Debian packages, build, run the tests (unit, CLI cases, Python,
#               schema, install; about 4 minutes on 2 cores from a fresh clone)
#   make check-all  make test, then the slow suites: ASan+UBSan build, valgrind, determinism,
#               memory limits, the docs' slow quoted outputs (CI runs it, and fuzzing: .ci/run)
#   make gallery  regenerate docs/gallery.md from the paper's examples, and the other docs' figures
DEB_PACKAGES := build-essential cmake pkg-config libjansson-dev libqhull-dev libglpk-dev libsuitesparse-dev libopenblas0-pthread libblas3 liblapack3 libcairo2-dev jq valgrind python3-jsonschema python3-numpy python3-pytest python3-pip python3-venv python3-setuptools python3-wheel libjs-three chromium libassimp-dev libcgal-dev libgmp-dev libmpfr-dev
BUILD ?= build
BUILD_SAN ?= build-san
JOBS ?= $(shell nproc 2>/dev/null || echo 2)

.PHONY: all deps build build-san demo test test-fast check-all test-valgrind test-tsan clean fuzz fuzz-build gallery bench bench-build install docs

all: build

deps:
	@missing=""; for p in $(DEB_PACKAGES); do \
	  dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:$$missing"; \
	  SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing; \
	fi

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCAIRN_WERROR=ON >/dev/null
	cmake --build $(BUILD) -j $(JOBS)

# The libraries (shared and static), headers, pkg-config files, CMake package, the CLI, its manual
# page and bash completion, under PREFIX (default /usr/local).
PREFIX ?= /usr/local
install: build
	cmake --install $(BUILD) --prefix $(PREFIX)

# The C at -O1 (the sanitizers' advice: a fifth less time than -O0, the checks the same), asserts
# kept; the one C++ file (CGAL) at -O0, where GCC's -O1 flow analysis warns inside CGAL's headers.
build-san: deps
	cmake -S . -B $(BUILD_SAN) -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS_DEBUG="-g -O1" -DCAIRN_WERROR=ON \
	  -DCAIRN_SANITIZE=ON >/dev/null
	cmake --build $(BUILD_SAN) -j $(JOBS)

demo: build
	./$(BUILD)/cairn check examples/blocks.json; status=$$?; \
	echo "(exit status $$status: 0 stable, 1 unstable)"; [ $$status -le 1 ]

test: build
	@start=$$(date +%s); (cd $(BUILD) && ctest --output-on-failure -j $(JOBS)); st=$$?; \
	echo "make test: $$(( $$(date +%s) - start )) s of tests"; exit $$st

test-fast: test

# Each stage prints its wall time (the CI's budget is watched stage by stage).
STAGE = t=$$(date +%s); trap 'echo "check-all: $(1) $$(( $$(date +%s) - t )) s"' EXIT;
DETERMINISM = LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0 tests/determinism.sh \
	$(BUILD)/cairn $(BUILD_SAN)/cairn
check-all: test build-san
	@$(call STAGE,sanitizers) cd $(BUILD_SAN) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j $(JOBS)
	@$(call STAGE,valgrind) $(MAKE) --no-print-directory test-valgrind
	@# four single-threaded stages side by side
	@( $(call STAGE,determinism 0/2) DETERMINISM_SHARD=0/2 $(DETERMINISM) ) & d=$$!; \
	( $(call STAGE,determinism 1/2) DETERMINISM_SHARD=1/2 $(DETERMINISM) ) & e=$$!; \
	( $(call STAGE,memory limits) tests/memory_limits.sh $(BUILD)/cairn ) & m=$$!; \
	( $(call STAGE,docs) python3 tools/docs_check.py $(BUILD)/cairn --slow ) & o=$$!; \
	st=0; for p in $$d $$e $$m $$o; do wait $$p || st=1; done; exit $$st

# The unit tests and the CLI cases under valgrind's memcheck (the normal build): any invalid
# access, use of uninitialised memory or definite/indirect leak fails. The input-error cases
# (err_*) are left to the sanitizers and the fuzzers; unit_load runs the loader's errors here. The unit tests run two at
# a time, longest first; the CLI cases as two shards side by side. Inlined frames are not read
# (a fifth of each process's start, which dominates a CLI case): rerun a failure without
# --read-inline-info=no for its full stack. They run on Debian's reference BLAS and LAPACK
# (libblas3, liblapack3) instead of OpenBLAS: loading OpenBLAS's kernels under memcheck took a
# quarter of each process's start, and what memcheck checks is cairn's own code; `make test`
# and the sanitizers run on OpenBLAS.
REF_BLAS := /usr/lib/$(shell gcc -print-multiarch)
VALGRIND_ENV := LD_LIBRARY_PATH=$(REF_BLAS)/blas:$(REF_BLAS)/lapack OPENBLAS_NUM_THREADS=1
VALGRIND := valgrind -q --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite,indirect --read-inline-info=no \
	--suppressions=tests/valgrind.supp
# One queue of JOBS workers: the unit tests (longest first) and the CLI cases in 8 shards, so that
# no core idles while the last long test runs.
# The unit modules are tests/modules.def's marked 1, in its order.
VALGRIND_UNITS := $(shell sed -n 's/^CN_TEST_MODULE(\([a-z0-9_]*\), *1).*/unit:\1/p' tests/modules.def)
VALGRIND_TASKS := $(wordlist 1,3,$(VALGRIND_UNITS)) case:0 case:1 case:2 case:3 $(word 4,$(VALGRIND_UNITS)) \
	case:4 case:5 $(wordlist 5,6,$(VALGRIND_UNITS)) case:6 case:7 $(wordlist 7,99,$(VALGRIND_UNITS))
test-valgrind: build
	@printf '%s\n' $(VALGRIND_TASKS) | $(VALGRIND_ENV) xargs -P $(JOBS) -I{} sh -c 't={}; n=$${t#*:}; \
	  if [ $${t%%:*} = unit ]; then \
	    $(VALGRIND) ./$(BUILD)/cairn_tests $$n >/dev/null 2>$(BUILD)/valgrind-$$n.log || \
	      { echo "valgrind: unit_$$n failed"; cat $(BUILD)/valgrind-$$n.log; exit 255; }; \
	  else \
	    CAIRN_WRAPPER="$(VALGRIND)" CAIRN_CASE_TIMEOUT=600 CAIRN_CASE_SHARD=$$n/8 CAIRN_CASE_EXCLUDE="err_*" \
	      tests/run_cases.sh $(BUILD)/cairn tests/cases >$(BUILD)/valgrind-cases-$$n.log 2>&1 || \
	      { cat $(BUILD)/valgrind-cases-$$n.log; exit 255; }; \
	  fi' && echo "valgrind: unit tests and CLI cases clean"

# Threads sharing assemblies under ThreadSanitizer (tests/thread_check.c): eight threads check
# and simulate the same loaded assemblies at once and must get a single thread's results; a
# race inside libcairn fails the run. (The Python package's close-while-checking races are its
# own lock's: python/tests, under make test.)
BUILD_TSAN ?= build-tsan
test-tsan: deps
	cmake -S . -B $(BUILD_TSAN) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCAIRN_WERROR=ON -DCAIRN_TSAN=ON >/dev/null
	cmake --build $(BUILD_TSAN) -j $(JOBS) --target thread_check
	OPENBLAS_NUM_THREADS=1 TSAN_OPTIONS="halt_on_error=1 exitcode=66" ./$(BUILD_TSAN)/thread_check

clean:
	rm -rf $(BUILD) $(BUILD_SAN) $(BUILD_TSAN)

# Benchmarks (bench/run.sh): LCP solvers against Siconos Numerics, scale, planning, warm-started
# paths, verdicts against MuJoCo.
# Installs the peers (libsiconos-numerics-dev, libmujoco-dev) and GNU time when missing.
# (libcairn.a's own dependencies, as its pkg-config file lists them for static linking; the
# benchmarks read meshes through Assimp, which libcairn loads when asked, so it is linked here)
BENCH_LIBS = $$(pkg-config --libs jansson assimp) -lqhull_r -lglpk -lcholmod -lmpfr -lgmp -lstdc++ -lpthread -lm
bench: bench-build
	bench/run.sh $(BUILD)/cairn $(BUILD)/lcp_vs_siconos $(BUILD)/warm_paths $(BUILD)/mujoco_verdicts \
	  $(BUILD)/gen_psd
bench-build: build
	@$(MAKE) --no-print-directory deps DEB_PACKAGES="libsiconos-numerics-dev libmujoco-dev time python3-numpy python3-cvxopt"
	$(CC) -O2 -std=c17 -D_POSIX_C_SOURCE=200809L -Iinclude -I/usr/include/siconos \
	  -I/usr/include/siconos/numerics bench/lcp_vs_siconos.c $(BUILD)/libcairn.a -lsiconos_numerics \
	  $(BENCH_LIBS) -o $(BUILD)/lcp_vs_siconos
	$(CC) -O2 -std=c17 -D_POSIX_C_SOURCE=200809L -Iinclude bench/warm_paths.c $(BUILD)/libcairn.a \
	  $(BENCH_LIBS) -o $(BUILD)/warm_paths
	$(CC) -O2 -std=c17 -D_DEFAULT_SOURCE -Iinclude bench/mujoco_verdicts.c $(BUILD)/libcairn.a \
	  -lmujoco $(BENCH_LIBS) -o $(BUILD)/mujoco_verdicts
	$(CC) -O2 -std=c17 bench/gen_psd.c -o $(BUILD)/gen_psd

# The API reference, from the public headers (Doxygen from Debian): build/docs/html/index.html
docs:
	@$(MAKE) --no-print-directory deps DEB_PACKAGES=doxygen
	doxygen docs/Doxyfile
	@echo "API reference: build/docs/html/index.html"

# docs/gallery.md and its figures, from the paper's examples
gallery: build
	tools/gallery.sh $(BUILD)/cairn
	tools/docs_figures.sh $(BUILD)/cairn

# libFuzzer targets (clang from Debian), run on the seed corpus kept in fuzz/corpus/<target>:
#   make fuzz                 FUZZ_SECONDS (default 60) per target, JOBS targets at a time;
#                             part of CI (.ci/run)
#   make fuzz FUZZ_SECONDS=3600 FUZZ_CORPUS=build-fuzz/corpus   a long run that grows a
#                             working corpus outside the repository
# Every input that crashed once is kept in fuzz/regressions/<target>/ and replayed by `make test`.
FUZZ_SECONDS ?= 60
# An input slower than this many seconds is a finding (a hang); sim's is 60: a 3-D plan whose
# checks each find contacts again for every corner reading is slow under the fuzz build's
# instrumentation (fuzz/regressions/sim/slow-plan-3d-readings) until contacts are found once
# per check.
FUZZ_TARGETS := load lcp sim geom invariance mesh names
# the library's sources, the interactive report's inlined scripts among them (generated into
# the CMake build)
FUZZ_SOURCES := $(wildcard src/*/*.c) $(BUILD)/html_assets.c
FUZZ_CORPUS ?= build-fuzz/run
FUZZ_SEED ?= 0
FUZZ_CFLAGS := -g -O1 -ffp-contract=off -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all \
	-D_POSIX_C_SOURCE=200809L -Iinclude $(addprefix -I,$(wildcard src/*))
# the library is compiled once (in parallel) and linked into each target
fuzz-build: deps build
	@$(MAKE) --no-print-directory deps DEB_PACKAGES=clang
	mkdir -p build-fuzz/obj
	rm -f build-fuzz/obj/*.o
	@# the C++ file first (CGAL's templates: the longest compile by far), the C files beside it
	printf '%s\n' src/model/decompose3.cpp $(FUZZ_SOURCES) fuzz/fuzz_*.c | xargs -P $(JOBS) -I{} sh -c 'case {} in \
	  *.cpp) [ build-fuzz/decompose3.o -nt {} ] || clang++ -std=c++17 -g -O1 -fsanitize=address,undefined \
	    -fno-sanitize-recover=all -Iinclude $(addprefix -I,$(wildcard src/*)) -c {} -o build-fuzz/decompose3.o ;; \
	  *) clang $(FUZZ_CFLAGS) $$(pkg-config --cflags jansson cairo) -c {} -o build-fuzz/obj/$$(echo {} | tr / _).o ;; \
	  esac'
	for t in $(FUZZ_TARGETS); do \
	  clang++ -fsanitize=fuzzer,address,undefined $$(ls build-fuzz/obj/src_*.o build-fuzz/obj/*html_assets*.o) build-fuzz/obj/fuzz_fuzz_$$t.c.o \
	    build-fuzz/decompose3.o -ljansson -lqhull_r -lglpk -lcholmod -lassimp -lmpfr -lgmp $$(pkg-config --libs cairo) -lm \
	    -o build-fuzz/fuzz_$$t || exit 1; done

fuzz: fuzz-build
	@mkdir -p build-fuzz/artifacts
	@printf '%s\n' $(FUZZ_TARGETS) | xargs -P $(JOBS) -I{} sh -c '\
	  t={}; mkdir -p $(FUZZ_CORPUS)/$$t; \
	  len="-max_len=4096"; [ $$t = invariance ] && len="-max_len=64 -len_control=0"; \
	  to=20; [ $$t = sim ] && to=60; \
	  LSAN_OPTIONS=suppressions=$(CURDIR)/fuzz/lsan.supp:print_suppressions=0 ./build-fuzz/fuzz_$$t -max_total_time=$(FUZZ_SECONDS) -timeout=$$to -rss_limit_mb=4096 \
	    $$len -print_final_stats=1 -seed=$(FUZZ_SEED) -artifact_prefix=build-fuzz/artifacts/$$t- \
	    $(FUZZ_CORPUS)/$$t fuzz/corpus/$$t >build-fuzz/$$t.log 2>&1; st=$$?; \
	  grep -E "^(stat::|==|SUMMARY|Done)" build-fuzz/$$t.log | sed "s/^/$$t: /"; \
	  [ $$st = 0 ] || { tail -n 40 build-fuzz/$$t.log; exit 255; }'