# mote build. `make` builds the library and the program (optimised, -O3); `make check` installs what
# a fresh machine lacks, then builds with warnings as errors and runs the whole test suite, plain
# and under AddressSanitizer + UndefinedBehaviorSanitizer; `make example` runs the main example.
CC      ?= cc
BUILD   ?= build
# -O3: the build every speed figure of bench/README.md and docs/ was measured on (issue 52)
OPT     ?= -O3
WERROR  ?= 0
SAN     ?=
CAIRO_CFLAGS := $(shell pkg-config --cflags cairo 2>/dev/null)
CAIRO_LIBS   := $(shell pkg-config --libs cairo 2>/dev/null || echo -lcairo)

WARN    := -Wall -Wextra -Wpedantic -Wshadow -Wstrict-prototypes -Wmissing-prototypes \
           -Wno-unused-parameter -Wformat=2
ifeq ($(WERROR),1)
WARN    += -Werror
endif
CFLAGS  ?= $(OPT) -g
# OpenMP (the N-body model's pair passes); OPENMP= builds without it
OPENMP  ?= -fopenmp
# The N-body model's real type (spec 4.6): double, long (long double) or quad (__float128, with
# glibc's _Float128 functions); build each in its own BUILD folder.
PRECISION ?= double
PREC_FLAGS_double :=
PREC_FLAGS_long   := -DMOTE_NB_PRECISION=2
PREC_FLAGS_quad   := -DMOTE_NB_PRECISION=4 -D__STDC_WANT_IEC_60559_TYPES_EXT__=1
ifeq ($(filter $(PRECISION),double long quad),)
$(error PRECISION must be double, long or quad (found '$(PRECISION)'))
endif
# MPI=1: the MPI build (Open MPI's mpicc; the charging model shares histories among ranks)
MPI ?= 0
ifeq ($(MPI),1)
CC := mpicc
MPI_FLAGS := -DMOTE_MPI
endif
# HDF5 (serial, Debian's libhdf5-dev): the H5MD trajectories and snapshots (format=h5md)
HDF5_CFLAGS := $(shell pkg-config --cflags hdf5 2>/dev/null)
HDF5_LIBS   := $(shell pkg-config --libs hdf5 2>/dev/null || echo -lhdf5)
# LAPACK through LAPACKE (Debian's liblapacke-dev; OpenBLAS's LAPACK where libopenblas is
# installed; its CBLAS for the blocked LU, the same package): the charging model's
# boundary-element solve of the body's field
LAPACKE_CFLAGS := $(shell pkg-config --cflags lapacke 2>/dev/null)
LAPACKE_LIBS   := $(shell pkg-config --libs lapacke blas 2>/dev/null || echo -llapacke -lblas)
ALL_CFLAGS := -std=c11 $(MPI_FLAGS) -D_POSIX_C_SOURCE=200809L $(PREC_FLAGS_$(PRECISION)) -Iinclude $(WARN) $(CFLAGS) $(SAN) $(OPENMP) $(CAIRO_CFLAGS) $(HDF5_CFLAGS) $(LAPACKE_CFLAGS)
# the charging model: Embree (ray tracing; no pkg-config file in Debian) and Assimp (mesh files)
ASSIMP_LIBS := $(shell pkg-config --libs assimp 2>/dev/null || echo -lassimp)
# the live view's HTTP server (libmicrohttpd)
MHD_LIBS := $(shell pkg-config --libs libmicrohttpd 2>/dev/null || echo -lmicrohttpd)
LDLIBS  := $(CAIRO_LIBS) -lembree3 $(ASSIMP_LIBS) $(MHD_LIBS) $(HDF5_LIBS) $(LAPACKE_LIBS) -lpthread -lm
# The programs (mote, the tests, the benchmarks) link libgomp statically, so that the
# constructor of MOTE_PROGRAM_THREADS (core.h) sets its spin count before libgomp reads it:
# threads that never spin on a busy machine. The libraries (libmote.so, the Python extension)
# link it as a shared library.
ifneq ($(strip $(OPENMP)),)
EXE_LIBS := -Wl,--push-state,-Bstatic -lgomp -Wl,--pop-state $(LDLIBS)
else
EXE_LIBS := $(LDLIBS)
endif
EXE_CFLAGS = $(filter-out $(OPENMP),$(ALL_CFLAGS))

# every folder of src/ but the program's: a new model's folder is built without naming it here
LIB_SRC  := $(sort $(filter-out src/cli/%,$(wildcard src/*/*.c)))
LIB_OBJ  := $(LIB_SRC:%.c=$(BUILD)/%.o)
CLI_SRC  := $(wildcard src/cli/*.c)
CLI_OBJ  := $(CLI_SRC:%.c=$(BUILD)/%.o)
TEST_SRC := $(sort $(wildcard tests/test_*.c))
TEST_BIN := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)
BENCH_SRC := $(sort $(wildcard bench/*.c))
BENCH_BIN := $(BENCH_SRC:bench/%.c=$(BUILD)/bench/%)
HDRS     := $(wildcard include/mote/*.h src/*/*.h src/*/*.inc tests/*.h)
# MPI=1 MPI_WITH=DIR: the MPI program from the objects of the plain build DIR (made with the same
# flags), but for the files that read MOTE_MPI, compiled here with mpicc: the program a full MPI
# build makes, in a fraction of its time (test-plain)
ifneq ($(MPI_WITH),)
MPI_SRC := $(shell grep -l MOTE_MPI $(LIB_SRC) $(CLI_SRC))
LIB_OBJ := $(foreach f,$(LIB_SRC),$(if $(filter $(f),$(MPI_SRC)),$(BUILD),$(MPI_WITH))/$(f:%.c=%.o))
CLI_OBJ := $(foreach f,$(CLI_SRC),$(if $(filter $(f),$(MPI_SRC)),$(BUILD),$(MPI_WITH))/$(f:%.c=%.o))
endif

.PHONY: all lib shared python test-bins tests bench check test test-plain test-san example setup setup-test clean slow seeds seeds-san fuzz fuzz-minimise install uninstall FORCE

all: $(BUILD)/mote

lib: $(BUILD)/libmote.a

# The folder's precision, rewritten only when it changes: objects built for another PRECISION in
# the same BUILD folder are rebuilt instead of linked as they are.
$(BUILD)/precision.stamp: FORCE
	@mkdir -p $(dir $@)
	@echo '$(PRECISION)' | cmp -s - $@ || echo '$(PRECISION)' > $@
FORCE:

$(BUILD)/%.o: %.c $(HDRS) $(BUILD)/precision.stamp
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -c $< -o $@

$(BUILD)/libmote.a: $(LIB_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@
	ar rcs $@ $^

# The shared library, from objects built again as position-independent code (the program and
# the tests link the static library, so their code is unchanged); its soname carries SOMAJOR.
VERSION := $(shell sed -n 's/^\#define MOTE_VERSION "\(.*\)"/\1/p' include/mote/core.h)
SOMAJOR := 0
PIC_OBJ := $(LIB_SRC:%.c=$(BUILD)/pic/%.o)
$(BUILD)/pic/%.o: %.c $(HDRS) $(BUILD)/precision.stamp
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -fPIC -c $< -o $@
$(BUILD)/libmote.so.$(VERSION): $(PIC_OBJ)
	$(CC) $(ALL_CFLAGS) -shared -Wl,-soname,libmote.so.$(SOMAJOR) $^ $(LDLIBS) -o $@
shared: $(BUILD)/libmote.so.$(VERSION)

# The Python package (python/mote): its C extension linked with the library's PIC objects, for
# Debian's python3 (PYTHON), with its headers (python3-dev) and NumPy's (python3-numpy); the
# package's build (setup.py: pip install .) makes it for the Python that runs pip.
PYTHON ?= $(shell [ -x /usr/bin/python3 ] && echo /usr/bin/python3 || echo python3)
PY_EXT = $(shell $(PYTHON) -c 'import sysconfig; print(sysconfig.get_config_var("EXT_SUFFIX"))')
PY_CFLAGS = $(shell $(PYTHON) -c 'import sysconfig, numpy; print("-I" + sysconfig.get_paths()["include"], "-I" + numpy.get_include())')
PY_VER = $(shell $(PYTHON) -c 'import sysconfig; print(sysconfig.get_python_version())')
PY_PKG := $(BUILD)/python/mote
PY_SRC := $(wildcard python/mote/*.py)
python: $(PY_PKG)/_mote$(PY_EXT) $(PY_SRC:python/mote/%=$(PY_PKG)/%)
$(PY_PKG)/_mote$(PY_EXT): python/mote/_mote.c $(PIC_OBJ) $(HDRS)
	@mkdir -p $(PY_PKG)
	$(CC) $(filter-out -Wmissing-prototypes -Wpedantic -Wstrict-prototypes,$(ALL_CFLAGS)) -fPIC -shared $(PY_CFLAGS) \
	    python/mote/_mote.c $(PIC_OBJ) $(LDLIBS) -o $@
$(PY_PKG)/%.py: python/mote/%.py
	@mkdir -p $(PY_PKG)
	cp $< $@

$(BUILD)/mote: $(CLI_OBJ) $(BUILD)/libmote.a
	$(CC) $(EXE_CFLAGS) $(CLI_OBJ) $(BUILD)/libmote.a $(EXE_LIBS) -o $@

$(BUILD)/tests/%: tests/%.c $(BUILD)/libmote.a $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -c -Itests $< -o $@.o
	$(CC) $(EXE_CFLAGS) $@.o $(BUILD)/libmote.a $(EXE_LIBS) -o $@

# the corpus replay links the fuzz targets (fuzz/targets.c)
$(BUILD)/tests/test_fuzz: tests/test_fuzz.c fuzz/targets.c fuzz/fuzz.h $(BUILD)/libmote.a $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -c -Itests -Ifuzz tests/test_fuzz.c -o $@.o
	$(CC) $(ALL_CFLAGS) -c -Itests -Ifuzz fuzz/targets.c -o $@.targets.o
	$(CC) $(EXE_CFLAGS) $@.o $@.targets.o $(BUILD)/libmote.a $(EXE_LIBS) -o $@

$(BUILD)/bench/%: bench/%.c $(BUILD)/libmote.a $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) -c $< -o $@.o
	$(CC) $(EXE_CFLAGS) $@.o $(BUILD)/libmote.a $(EXE_LIBS) -o $@

# The N-body model again in long double and in quad, for test_precision_long and _quad (spec
# 4.6; only from a double build): its objects in $(BUILD)/long and $(BUILD)/quad, linked before
# the library so that they replace its double ones.
NB_SRC := $(sort $(wildcard src/nbody/*.c))
ifeq ($(PRECISION),double)
PREC_BIN := $(BUILD)/tests/test_precision_long $(BUILD)/tests/test_precision_quad
endif
$(BUILD)/long/%.o: %.c $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(PREC_FLAGS_long) -c $< -o $@
$(BUILD)/quad/%.o: %.c $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(PREC_FLAGS_quad) -c $< -o $@
.SECONDEXPANSION:
$(BUILD)/tests/test_precision_%: tests/test_precision.c $(NB_SRC:%.c=$(BUILD)/$$*/%.o) $(BUILD)/libmote.a $(HDRS)
	@mkdir -p $(dir $@)
	$(CC) $(ALL_CFLAGS) $(PREC_FLAGS_$*) -c -Itests $< -o $@.o
	$(CC) $(EXE_CFLAGS) $@.o $(NB_SRC:%.c=$(BUILD)/$*/%.o) $(BUILD)/libmote.a $(EXE_LIBS) -o $@

# test-bins: what the tests run (the sanitized pass, which skips test_bench.sh, builds only it)
test-bins: $(BUILD)/mote $(TEST_BIN) $(PREC_BIN) python
tests: test-bins $(BENCH_BIN)
bench: $(BUILD)/mote $(BENCH_BIN)

# Install missing Debian packages (a no-op when everything is present): what the build and the
# example need; setup-test adds what the tests use.
setup:
	@sh scripts/setup.sh

setup-test:
	@sh scripts/setup.sh test

# The test command of the README: plain optimised build, then ASan+UBSan build, both -Werror.
# The builds use every processor (JOBS).
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
check: setup-test
	$(MAKE) --no-print-directory test-plain
	$(MAKE) --no-print-directory test-san

test-plain:
	$(MAKE) -j$(JOBS) --no-print-directory WERROR=1 BUILD=build tests
	$(MAKE) -j$(JOBS) --no-print-directory WERROR=1 BUILD=build-mpi MPI=1 MPI_WITH=build build-mpi/mote
	MOTE_MPI_BIN=$(CURDIR)/build-mpi/mote sh tests/run.sh build

# The sanitized pass runs every test but those that exercise no code of their own under the
# sanitizers: the terminal's progress line and its timing (test_progress.sh: the progress code
# runs in every long command of the other tests), the setup script, the documentation's text,
# `make install`'s file list and the benchmarks' tiny workloads (their code is the models'; nor are they
# built); test_live.sh leaves its screenshots (the page's own drawing) to the plain pass.
SAN_SKIP := test_progress.sh test_setup.sh test_docs.sh test_install.sh test_bench.sh
test-san:
	$(MAKE) -j$(JOBS) --no-print-directory WERROR=1 BUILD=build-san OPT=-O1 \
	    SAN="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer" test-bins
	MOTE_TEST_SKIP="$(SAN_SKIP)" MOTE_SANITIZED=1 ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp UBSAN_OPTIONS=print_stacktrace=1 sh tests/run.sh build-san

# Long validation runs (not part of `make check`).
slow: setup-test
	$(MAKE) -j$(JOBS) --no-print-directory WERROR=1 BUILD=build tests
	MOTE_SLOW=1 sh tests/run.sh build

# every test program again with MOTE_TEST_SEED = SEED_FIRST .. SEEDS (tests/seeds.sh)
SEEDS ?= 20
SEED_FIRST ?= 1
seeds: setup-test
	$(MAKE) -j$(JOBS) --no-print-directory WERROR=1 BUILD=build tests
	sh tests/seeds.sh build $(SEEDS) $(SEED_FIRST)

# the same with the sanitizer build (shorter runs where the tests allow, as in test-san)
seeds-san: setup-test
	$(MAKE) -j$(JOBS) --no-print-directory WERROR=1 BUILD=build-san OPT=-O1 \
	    SAN="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer" tests
	MOTE_SANITIZED=1 ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp UBSAN_OPTIONS=print_stacktrace=1 sh tests/seeds.sh build-san $(SEEDS) $(SEED_FIRST)

# Fuzzing with libFuzzer (clang, installed by `scripts/setup.sh fuzz`): each target runs for
# FUZZ_TIME seconds from its corpus in fuzz/corpus/<target>/, which grows with what it finds (commit
# it); a crash or leak leaves its input as fuzz/corpus/<target>/crash-... (rename it after what it
# did): `make check` then replays it through tests/test_fuzz.c until it is fixed.
# (a unit's timeout, 30 s, is above the mesh reader's own bound: 10 s of processor time, 20 of
# wall clock, after which Assimp's child is stopped and the load fails cleanly)
FUZZ_TIME ?= 60
FUZZ_TARGETS := script hs_state mb_state nb_state nb_snapshot nb_solar ch_plain plot sep_state nb_galactica nb_galctl nb_galjob ch_mesh sep_files live_http script_params csv
FUZZ_SAN := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
fuzz:
	@sh scripts/setup.sh fuzz
	$(MAKE) --no-print-directory CC=clang BUILD=build-fuzz OPT=-O1 \
	    SAN="-fsanitize=fuzzer-no-link $(FUZZ_SAN)" lib
	@set -e; for t in $(FUZZ_TARGETS); do \
	    clang $(ALL_CFLAGS) -fsanitize=fuzzer $(FUZZ_SAN) -Ifuzz -DMOTE_FUZZ_TARGET=\"$$t\" \
	        fuzz/main_libfuzzer.c fuzz/targets.c build-fuzz/libmote.a $(LDLIBS) -o build-fuzz/fuzz_$$t; \
	    echo "== fuzzing $$t for $(FUZZ_TIME) s"; \
	    ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp build-fuzz/fuzz_$$t -max_total_time=$(FUZZ_TIME) -timeout=30 \
	        -rss_limit_mb=2048 -max_len=4096 -artifact_prefix=fuzz/corpus/$$t/ fuzz/corpus/$$t; \
	done

# The corpus shrunk to the units that reach the same coverage (named files kept): after `make
# fuzz`, before committing what it found (FUZZ_TARGETS= to choose)
fuzz-minimise:
	sh scripts/fuzz-minimise.sh build-fuzz $(FUZZ_TARGETS)

# `make install PREFIX=/usr/local` (and DESTDIR= for packagers); `make uninstall` with the same
# PREFIX removes what it installed. docs/install.md lists the files.
PREFIX ?= /usr/local
bindir := $(PREFIX)/bin
libdir := $(PREFIX)/lib
includedir := $(PREFIX)/include
man1dir := $(PREFIX)/share/man/man1
docdir := $(PREFIX)/share/doc/mote
completiondir := $(PREFIX)/share/bash-completion/completions
# the Python package: where Debian's python3 looks for a prefix's packages
pythondir = $(PREFIX)/lib/python$(PY_VER)/dist-packages
$(BUILD)/mote.1: $(BUILD)/mote
	$(BUILD)/mote help --man > $@
$(BUILD)/mote.bash: $(BUILD)/mote
	$(BUILD)/mote help --bash-completion > $@
install: $(BUILD)/mote $(BUILD)/libmote.a $(BUILD)/libmote.so.$(VERSION) $(BUILD)/mote.1 $(BUILD)/mote.bash python
	install -d $(DESTDIR)$(bindir) $(DESTDIR)$(libdir)/pkgconfig $(DESTDIR)$(includedir)/mote \
	    $(DESTDIR)$(man1dir) $(DESTDIR)$(completiondir) $(DESTDIR)$(docdir)/docs \
	    $(DESTDIR)$(docdir)/examples/c
	install -m 755 $(BUILD)/mote $(DESTDIR)$(bindir)/mote
	install -m 644 $(BUILD)/libmote.so.$(VERSION) $(BUILD)/libmote.a $(DESTDIR)$(libdir)/
	ln -sf libmote.so.$(VERSION) $(DESTDIR)$(libdir)/libmote.so.$(SOMAJOR)
	ln -sf libmote.so.$(SOMAJOR) $(DESTDIR)$(libdir)/libmote.so
	printf '%s\n' 'prefix=$(PREFIX)' 'libdir=$${prefix}/lib' 'includedir=$${prefix}/include' '' \
	    'Name: mote' 'Description: particle-simulation toolkit (hard spheres, mixing box, N-body, spacecraft charging, gravitational separator)' \
	    'Version: $(VERSION)' 'Requires.private: cairo assimp libmicrohttpd hdf5 lapacke blas' \
	    'Cflags: -I$${includedir}$(if $(PREC_FLAGS_$(PRECISION)), $(PREC_FLAGS_$(PRECISION)))' \
	    'Libs: -L$${libdir} -lmote' 'Libs.private: -lembree3 -lpthread -lm $(OPENMP)' \
	    > $(DESTDIR)$(libdir)/pkgconfig/mote.pc
	install -m 644 include/mote/*.h $(DESTDIR)$(includedir)/mote/
	install -m 644 $(BUILD)/mote.1 $(DESTDIR)$(man1dir)/mote.1
	install -m 644 $(BUILD)/mote.bash $(DESTDIR)$(completiondir)/mote
	install -m 644 README.md $(DESTDIR)$(docdir)/
	install -m 644 docs/*.md $(DESTDIR)$(docdir)/docs/
	install -m 644 examples/*.mote $(DESTDIR)$(docdir)/examples/
	install -m 644 examples/c/*.c examples/c/Makefile $(DESTDIR)$(docdir)/examples/c/
	install -d $(DESTDIR)$(pythondir)/mote $(DESTDIR)$(docdir)/examples/python
	install -m 644 $(PY_SRC:python/mote/%=$(PY_PKG)/%) $(PY_PKG)/_mote$(PY_EXT) $(DESTDIR)$(pythondir)/mote/
	install -m 644 examples/python/*.py $(DESTDIR)$(docdir)/examples/python/
	install -d $(DESTDIR)$(docdir)/data
	install -m 644 data/*.dat $(DESTDIR)$(docdir)/data/
	@[ -n "$(DESTDIR)" ] || [ "$$(id -u)" != 0 ] || ldconfig 2>/dev/null || true
uninstall:
	rm -f $(DESTDIR)$(bindir)/mote $(DESTDIR)$(libdir)/libmote.so.$(VERSION) \
	    $(DESTDIR)$(libdir)/libmote.so.$(SOMAJOR) $(DESTDIR)$(libdir)/libmote.so \
	    $(DESTDIR)$(libdir)/libmote.a $(DESTDIR)$(libdir)/pkgconfig/mote.pc \
	    $(DESTDIR)$(man1dir)/mote.1 $(DESTDIR)$(completiondir)/mote
	rm -rf $(DESTDIR)$(includedir)/mote $(DESTDIR)$(docdir) $(DESTDIR)$(pythondir)/mote

example: setup
	$(MAKE) --no-print-directory all
	cd examples && ../$(BUILD)/mote run crystallization.mote

clean:
	rm -rf build build-san build-fuzz
