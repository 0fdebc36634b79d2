# augcut: one non-recursive Makefile.
#   make deps      install missing Debian packages (does nothing when all are there)
#   make           library and tools in bin/
#   make check     deps, build (also the ASan+UBSan and the TSan tools and the fuzz targets), every test; ends with "N passed, N failed"
#   make demo      deps, build, the bundled progressive cut
#   make bench     the papers' figures as CSV + PNG in bench/out/
#   make check-asan    ASan+UBSan unit tests and every shell test with the ASan+UBSan tools
#   make check-valgrind  every tool under valgrind memcheck on a small pipeline
#   make check-fuzz (the fuzz targets build and run 200 inputs)
#   make fuzz (FUZZ_TIME s per target) / make fuzz-cov (line coverage of lib/)

CC      ?= cc
CFLAGS  ?= -O2 -g
CFLAGS  += -std=c11 -Wall -Wextra -D_GNU_SOURCE -I/usr/include/suitesparse -Ilib
LDLIBS_NUM = -lcholmod -lsuitesparseconfig -lgsl -llapacke -llapack -lopenblas -larpack -lgomp -lz -lm -lpthread
LDLIBS_GMSH = -lgmsh

B := build
COMMA := ,
LIB_SRC := $(filter-out lib/cli/%,$(wildcard lib/*/*.c))
LIB_OBJ := $(LIB_SRC:lib/%.c=$(B)/lib/%.o)
CLI_SRC := $(wildcard lib/cli/*.c)
CLI_OBJ := $(CLI_SRC:lib/cli/%.c=$(B)/cli/%.o)
HDRS    := $(wildcard lib/*.h lib/cli/*.h)
TEST_HDRS := $(wildcard tests/unit/*.h)
NPROC   := $(shell getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)
TOOLS   := $(patsubst %.c,%,$(wildcard bin/*.c))
UNIT_SRC := $(wildcard tests/unit/*.c)
UNIT    := $(UNIT_SRC:tests/unit/%.c=$(B)/tests/%)

# Debian packages: header or program that proves each is installed
DEPS = /usr/include/suitesparse/cholmod.h:libsuitesparse-dev \
       /usr/include/gsl/gsl_poly.h:libgsl-dev \
       /usr/include/gmshc.h:libgmsh-dev \
       /usr/bin/gmsh:gmsh \
       /usr/include/zlib.h:zlib1g-dev \
       /usr/include/lapacke.h:liblapacke-dev \
       /usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h:libopenblas-dev \
       /usr/lib/x86_64-linux-gnu/libarpack.so:libarpack2-dev \
       /usr/bin/gnuplot:gnuplot-nox \
       /usr/bin/clang:clang \
       /usr/lib/llvm-14/lib/clang/14.0.6/lib/linux/libclang_rt.fuzzer-x86_64.a:libclang-rt-14-dev \
       /usr/lib/llvm-14/bin/llvm-profdata:llvm-14 \
       /usr/lib/llvm-14/bin/llvm-cov:llvm-14 \
       /usr/bin/python3:python3 \
       /usr/lib/python3/dist-packages/vtk.py:python3-vtk9 \
       /usr/bin/valgrind:valgrind \
       /usr/include/valgrind/valgrind.h:valgrind

.PHONY: all deps check demo bench check-asan check-valgrind check-fuzz fuzz fuzz-build fuzz-cov clean scenes mutate
all: $(TOOLS) $(UNIT)

deps:
	@missing=""; for d in $(DEPS); do f=$${d%%:*}; p=$${d##*:}; \
	  [ -e "$$f" ] || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "deps: installing$$missing"; \
	  if [ "$$(id -u)" != 0 ]; then echo "deps: need root to install$$missing" >&2; exit 1; fi; \
	  apt-get update -q >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y -q $$missing >/dev/null || exit 1; \
	fi

$(B)/lib/%.o: lib/%.c $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -c -o $@ $<

$(B)/cli/%.o: lib/cli/%.c $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -c -o $@ $<

lib/libaugcut.a: $(LIB_OBJ)
	rm -f $@ && ar rcs $@ $^

$(B)/libaugcli.a: $(CLI_OBJ)
	rm -f $@ && ar rcs $@ $^

bin/meshload: bin/meshload.c $(B)/libaugcli.a lib/libaugcut.a $(HDRS)
	$(CC) $(CFLAGS) -o $@ $< $(B)/libaugcli.a lib/libaugcut.a $(LDLIBS_GMSH) $(LDLIBS_NUM)
# cut --surface reads gmsh surface meshes
bin/cut: bin/cut.c $(B)/libaugcli.a lib/libaugcut.a $(HDRS)
	$(CC) $(CFLAGS) -o $@ $< $(B)/libaugcli.a lib/libaugcut.a $(LDLIBS_GMSH) $(LDLIBS_NUM)

bin/%: bin/%.c $(B)/libaugcli.a lib/libaugcut.a $(HDRS)
	$(CC) $(CFLAGS) -o $@ $< $(B)/libaugcli.a lib/libaugcut.a $(LDLIBS_NUM)

$(B)/tests/%: tests/unit/%.c $(B)/libaugcli.a lib/libaugcut.a $(HDRS) $(TEST_HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -Itests/unit -o $@ $< $(B)/libaugcli.a lib/libaugcut.a $(LDLIBS_NUM)

# Sanitizer build of the library, its cli part and the unit tests (ASan + UBSan).
ASAN_FLAGS = -O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
$(B)/asan/lib/%.o: lib/%.c $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(ASAN_FLAGS) -c -o $@ $<
$(B)/asan/libaugcut.a: $(LIB_SRC:lib/%.c=$(B)/asan/lib/%.o)
	rm -f $@ && ar rcs $@ $^
$(B)/asan/libaugcli.a: $(CLI_SRC:lib/%.c=$(B)/asan/lib/%.o)
	rm -f $@ && ar rcs $@ $^
$(B)/asan/tests/%: tests/unit/%.c $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(HDRS) $(TEST_HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(ASAN_FLAGS) -Itests/unit -o $@ $< $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(LDLIBS_NUM)
ASAN_UNIT := $(UNIT_SRC:tests/unit/%.c=$(B)/asan/tests/%)
# ... and of the tools, for the shell tests' second pass (tests/run.sh)
$(B)/asan/bin/meshload: bin/meshload.c $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(ASAN_FLAGS) -o $@ $< $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(LDLIBS_GMSH) $(LDLIBS_NUM)
$(B)/asan/bin/cut: bin/cut.c $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(ASAN_FLAGS) -o $@ $< $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(LDLIBS_GMSH) $(LDLIBS_NUM)
$(B)/asan/bin/%: bin/%.c $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(ASAN_FLAGS) -o $@ $< $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(LDLIBS_NUM)
ASAN_TOOLS := $(TOOLS:bin/%=$(B)/asan/bin/%)

# ThreadSanitizer build of the tools that start threads (factor, modal,
# solve-aug: --threads, --background) for tests/threads_tsan.test. The ifunc
# resolvers of target_clones run before TSan is up and crash instrumented,
# so the three files that have them are built without it.
TSAN_FLAGS = -O1 -g -fsanitize=thread
TSAN_PLAIN := $(B)/tsan/lib/solve/amps_memo.o $(B)/tsan/lib/cut/constrain_spec.o $(B)/tsan/lib/refine/refine_mem3_region.o
$(TSAN_PLAIN): TSAN_FLAGS = -O1 -g
$(B)/tsan/lib/%.o: lib/%.c $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(TSAN_FLAGS) -c -o $@ $<
$(B)/tsan/libaugcut.a: $(LIB_SRC:lib/%.c=$(B)/tsan/lib/%.o)
	rm -f $@ && ar rcs $@ $^
$(B)/tsan/libaugcli.a: $(CLI_SRC:lib/%.c=$(B)/tsan/lib/%.o)
	rm -f $@ && ar rcs $@ $^
$(B)/tsan/bin/%: bin/%.c $(B)/tsan/libaugcli.a $(B)/tsan/libaugcut.a $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) -O1 -g -fsanitize=thread -o $@ $< $(B)/tsan/libaugcli.a $(B)/tsan/libaugcut.a $(LDLIBS_NUM)
TSAN_TOOLS := $(B)/tsan/bin/factor $(B)/tsan/bin/modal $(B)/tsan/bin/solve-aug

# Bundled scenes, meshed by gmsh from scenes/*.geo
SCENES := $(B)/scenes/beam_h4.msh $(B)/scenes/beam_h16.msh $(B)/scenes/beam_h64.msh \
          $(B)/scenes/brick_n4.msh $(B)/scenes/brick_n8.msh $(B)/scenes/square.msh \
          $(B)/scenes/plank.msh $(B)/scenes/cube.msh $(B)/scenes/hexbrick_n2.msh \
          $(B)/scenes/hexbrick_n4.msh $(B)/scenes/cube_n4.msh $(B)/scenes/cube_n8.msh \
          $(B)/scenes/steak.msh $(B)/scenes/dome.msh
$(B)/scenes/beam_h%.msh: scenes/beam.geo
	@mkdir -p $(dir $@)
	gmsh -3 -setnumber h $* -format msh41 -v 0 -o $@ $< >/dev/null
$(B)/scenes/brick_n%.msh: scenes/brick.geo
	@mkdir -p $(dir $@)
	gmsh -3 -setnumber N $* -format msh41 -v 0 -o $@ $< >/dev/null
$(B)/scenes/square.msh: scenes/square.geo
	@mkdir -p $(dir $@)
	gmsh -2 -format msh41 -v 0 -o $@ $< >/dev/null
$(B)/scenes/plank.msh: scenes/plank.geo
	@mkdir -p $(dir $@)
	gmsh -3 -format msh41 -v 0 -o $@ $< >/dev/null
$(B)/scenes/cube.msh: scenes/cube.geo
	@mkdir -p $(dir $@)
	gmsh -3 -format msh41 -v 0 -o $@ $< >/dev/null
$(B)/scenes/steak.msh: scenes/steak.geo
	@mkdir -p $(dir $@)
	gmsh -3 -format msh41 -v 0 -o $@ $< >/dev/null
$(B)/scenes/cube_n%.msh: scenes/cube.geo
	@mkdir -p $(dir $@)
	gmsh -3 -setnumber N $* -format msh41 -v 0 -o $@ $< >/dev/null
$(B)/scenes/hexbrick_n%.msh: scenes/hexbrick.geo
	@mkdir -p $(dir $@)
	gmsh -3 -setnumber N $* -format msh41 -v 0 -o $@ $< >/dev/null
$(B)/scenes/dome.msh: scenes/dome.geo
	@mkdir -p $(dir $@)
	gmsh -2 -format msh41 -v 0 -o $@ $< >/dev/null
scenes: $(SCENES)

check: deps
	@$(MAKE) -j$(NPROC) --no-print-directory all scenes $(ASAN_UNIT) $(ASAN_TOOLS) $(TSAN_TOOLS) fuzz-build >$(B).log 2>&1 || { mkdir -p $(B); cat $(B).log; exit 1; }
	@sh tests/run.sh

check-asan: deps
	@$(MAKE) -j$(NPROC) --no-print-directory all scenes $(ASAN_UNIT) $(ASAN_TOOLS)
	@sh tests/run.sh --asan-only

check-valgrind: deps
	@$(MAKE) -j$(NPROC) --no-print-directory all scenes >$(B).log 2>&1 || { cat $(B).log; exit 1; }
	@sh tests/valgrind.sh

demo: deps
	@$(MAKE) -j$(NPROC) --no-print-directory all scenes >$(B).log 2>&1 || { cat $(B).log; exit 1; }
	@sh bench/demo.sh

bench: deps
	@$(MAKE) -j$(NPROC) --no-print-directory all scenes >$(B).log 2>&1 || { cat $(B).log; exit 1; }
	@sh bench/run.sh

# Hand-written source mutants against the tests (tests/mutate/mutants.txt);
# MUTATE_FULL=1 runs every shell test for each.
mutate: deps
	@$(MAKE) -j$(NPROC) --no-print-directory all scenes >$(B).log 2>&1 || { cat $(B).log; exit 1; }
	@sh tests/mutate/run.sh

FUZZ_TIME ?= 60
# The fuzz targets fuzz/fuzz_*.c link the whole library, built with clang's
# coverage hooks and, in lib/stream/stream.c only, -DAUG_FUZZ_NO_CRC: the CRC
# is not compared, so mutations reach the codecs and the tools' checks behind
# it (no other build defines it). Seeds: fuzz/corpus (sh fuzz/make_corpus.sh);
# what each target finds goes to build/fuzz/corpus-TARGET.
FUZZ_TARGETS := $(patsubst fuzz/%.c,%,$(wildcard fuzz/fuzz_*.c))
FUZZ_TARGETS := $(filter-out fuzz_util,$(FUZZ_TARGETS))
FUZZ_BASE = -std=c11 -g -D_GNU_SOURCE -Ilib -I/usr/include/suitesparse -Wall -Wextra
FUZZ_FLAGS = $(FUZZ_BASE) -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
FUZZ_NOCRC = -DAUG_FUZZ_NO_CRC -DFUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
$(B)/fuzz/lib/%.o: lib/%.c $(HDRS)
	@mkdir -p $(dir $@)
	clang $(subst fuzzer$(COMMA),fuzzer-no-link$(COMMA),$(FUZZ_FLAGS)) \
	  $(if $(filter lib/stream/stream.c,$<),$(FUZZ_NOCRC)) -c -o $@ $<
$(B)/fuzz/libaugcut.a: $(LIB_SRC:lib/%.c=$(B)/fuzz/lib/%.o)
	rm -f $@ && ar rcs $@ $^
$(B)/fuzz/fuzz_%: fuzz/fuzz_%.c fuzz/fuzz_util.c fuzz/fuzz_util.h $(B)/fuzz/libaugcut.a
	clang $(FUZZ_FLAGS) -Ifuzz -o $@ $< fuzz/fuzz_util.c $(B)/fuzz/libaugcut.a $(LDLIBS_NUM)
fuzz-build: $(FUZZ_TARGETS:%=$(B)/fuzz/%)
check-fuzz: deps fuzz-build
	@sh tests/fuzz_smoke.sh
fuzz: deps fuzz-build
	@for t in $(FUZZ_TARGETS); do mkdir -p $(B)/fuzz/corpus-$$t; \
	  echo "fuzz: $$t for $(FUZZ_TIME) s"; \
	  $(B)/fuzz/$$t -max_total_time=$(FUZZ_TIME) -rss_limit_mb=2048 -timeout=30 \
	    -print_final_stats=1 $(B)/fuzz/corpus-$$t fuzz/corpus 2>$(B)/fuzz/$$t.log || \
	    { tail -40 $(B)/fuzz/$$t.log; exit 1; }; \
	  grep '^stat::number_of_executed_units' $(B)/fuzz/$$t.log; done

# Line coverage of lib/ by what the fuzz targets found: the same targets built
# with -fprofile-instr-generate -fcoverage-mapping (no sanitizers) run once
# over fuzz/corpus and build/fuzz/corpus-TARGET; the table per file goes to
# build/cov/report.txt.
COV_FLAGS = $(FUZZ_BASE) -O0 -fprofile-instr-generate -fcoverage-mapping
LLVM_BIN = /usr/lib/llvm-14/bin
$(B)/cov/lib/%.o: lib/%.c $(HDRS)
	@mkdir -p $(dir $@)
	clang $(COV_FLAGS) -fsanitize=fuzzer-no-link $(if $(filter lib/stream/stream.c,$<),$(FUZZ_NOCRC)) -c -o $@ $<
$(B)/cov/libaugcut.a: $(LIB_SRC:lib/%.c=$(B)/cov/lib/%.o)
	rm -f $@ && ar rcs $@ $^
$(B)/cov/fuzz_%: fuzz/fuzz_%.c fuzz/fuzz_util.c fuzz/fuzz_util.h $(B)/cov/libaugcut.a
	clang $(COV_FLAGS) -fsanitize=fuzzer -Ifuzz -o $@ $< fuzz/fuzz_util.c $(B)/cov/libaugcut.a $(LDLIBS_NUM)
fuzz-cov: deps $(FUZZ_TARGETS:%=$(B)/cov/%)
	@rm -f $(B)/cov/*.profraw
	@for t in $(FUZZ_TARGETS); do mkdir -p $(B)/fuzz/corpus-$$t; \
	  LLVM_PROFILE_FILE=$(B)/cov/$$t.profraw $(B)/cov/$$t -runs=0 -rss_limit_mb=2048 \
	    $(B)/fuzz/corpus-$$t fuzz/corpus > $(B)/cov/$$t.log 2>&1 || { tail -20 $(B)/cov/$$t.log; exit 1; }; done
	$(LLVM_BIN)/llvm-profdata merge -o $(B)/cov/fuzz.profdata $(B)/cov/*.profraw
	$(LLVM_BIN)/llvm-cov report -instr-profile=$(B)/cov/fuzz.profdata $(B)/cov/$(firstword $(FUZZ_TARGETS)) \
	  $(patsubst %,-object $(B)/cov/%,$(wordlist 2,99,$(FUZZ_TARGETS))) $(LIB_SRC) > $(B)/cov/report.txt
	@cat $(B)/cov/report.txt

clean:
	rm -rf $(B) $(B).log lib/libaugcut.a $(TOOLS) bench/out
