# augcut: one non-recursive Makefile.
#   make deps      install missing Debian packages (does nothing when all are there)
#   make           library and tools in bin/
#   make check     deps, build, every test; ends with "N passed, N failed"
#   make demo      deps, build, the bundled progressive cut
#   make bench     the papers' figures as CSV + PNG in bench/out/
#   make check-asan    ASan+UBSan unit tests and every shell test with the ASan+UBSan tools
#   make check-valgrind  every tool under valgrind memcheck on a small pipeline
#   make fuzz

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
       /usr/bin/python3:python3 \
       /usr/lib/python3/dist-packages/vtk.py:python3-vtk9 \
       /usr/bin/valgrind:valgrind \
       /usr/include/valgrind/valgrind.h:valgrind

.PHONY: all deps check demo bench check-asan check-valgrind fuzz clean scenes mutate
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

bin/%: bin/%.c $(B)/libaugcli.a lib/libaugcut.a $(HDRS)
	$(CC) $(CFLAGS) -o $@ $< $(B)/libaugcli.a lib/libaugcut.a $(LDLIBS_NUM)

$(B)/tests/%: tests/unit/%.c $(B)/libaugcli.a lib/libaugcut.a $(HDRS)
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
$(B)/asan/tests/%: tests/unit/%.c $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(ASAN_FLAGS) -Itests/unit -o $@ $< $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(LDLIBS_NUM)
ASAN_UNIT := $(UNIT_SRC:tests/unit/%.c=$(B)/asan/tests/%)
# ... and of the tools, for the shell tests' second pass (tests/run.sh)
$(B)/asan/bin/meshload: bin/meshload.c $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(ASAN_FLAGS) -o $@ $< $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(LDLIBS_GMSH) $(LDLIBS_NUM)
$(B)/asan/bin/%: bin/%.c $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS) $(ASAN_FLAGS) -o $@ $< $(B)/asan/libaugcli.a $(B)/asan/libaugcut.a $(LDLIBS_NUM)
ASAN_TOOLS := $(TOOLS:bin/%=$(B)/asan/bin/%)

# Bundled scenes, meshed by gmsh from scenes/*.geo
SCENES := $(B)/scenes/beam_h4.msh $(B)/scenes/beam_h16.msh $(B)/scenes/beam_h64.msh \
          $(B)/scenes/brick_n4.msh $(B)/scenes/brick_n8.msh $(B)/scenes/square.msh
$(B)/scenes/beam_h%.msh: scenes/beam.geo
	@mkdir -p $(dir $@)
	gmsh -3 -setnumber h $* -format msh41 -v 0 -o $@ $< >/dev/null
$(B)/scenes/brick_n%.msh: scenes/brick.geo
	@mkdir -p $(dir $@)
	gmsh -3 -setnumber N $* -format msh41 -v 0 -o $@ $< >/dev/null
$(B)/scenes/square.msh: scenes/square.geo
	@mkdir -p $(dir $@)
	gmsh -2 -format msh41 -v 0 -o $@ $< >/dev/null
scenes: $(SCENES)

check: deps
	@$(MAKE) --no-print-directory all scenes $(ASAN_UNIT) $(ASAN_TOOLS) >$(B).log 2>&1 || { mkdir -p $(B); cat $(B).log; exit 1; }
	@sh tests/run.sh

check-asan: deps
	@$(MAKE) --no-print-directory all scenes $(ASAN_UNIT) $(ASAN_TOOLS)
	@sh tests/run.sh --asan-only

check-valgrind: deps
	@$(MAKE) --no-print-directory all scenes >$(B).log 2>&1 || { cat $(B).log; exit 1; }
	@sh tests/valgrind.sh

demo: deps
	@$(MAKE) --no-print-directory all scenes >$(B).log 2>&1 || { cat $(B).log; exit 1; }
	@sh bench/demo.sh

bench: deps
	@$(MAKE) --no-print-directory all scenes >$(B).log 2>&1 || { cat $(B).log; exit 1; }
	@sh bench/run.sh

# Hand-written source mutants against the tests (tests/mutate/mutants.txt);
# MUTATE_FULL=1 runs every shell test for each.
mutate: deps
	@$(MAKE) --no-print-directory all scenes >$(B).log 2>&1 || { cat $(B).log; exit 1; }
	@sh tests/mutate/run.sh

FUZZ_TIME ?= 60
# The fuzz targets link the whole library, built with clang's coverage hooks.
FUZZ_FLAGS = -std=c11 -g -O1 -D_GNU_SOURCE -Ilib -I/usr/include/suitesparse -fsanitize=fuzzer,address,undefined
$(B)/fuzz/lib/%.o: lib/%.c $(HDRS)
	@mkdir -p $(dir $@)
	clang $(subst fuzzer$(COMMA),fuzzer-no-link$(COMMA),$(FUZZ_FLAGS)) -c -o $@ $<
$(B)/fuzz/libaugcut.a: $(LIB_SRC:lib/%.c=$(B)/fuzz/lib/%.o)
	rm -f $@ && ar rcs $@ $^
fuzz: deps $(B)/tests/stream_io $(B)/fuzz/libaugcut.a
	@mkdir -p $(B)/fuzz/corpus
	AUG_WRITE_SEED=$(B)/fuzz/corpus/seed_all_records.aug $(B)/tests/stream_io
	clang $(FUZZ_FLAGS) -o $(B)/fuzz/fuzz_stream fuzz/fuzz_stream.c $(B)/fuzz/libaugcut.a $(LDLIBS_NUM)
	$(B)/fuzz/fuzz_stream -max_total_time=$(FUZZ_TIME) -rss_limit_mb=2048 $(B)/fuzz/corpus

clean:
	rm -rf $(B) $(B).log lib/libaugcut.a $(TOOLS) bench/out
