#!/bin/sh
# test_install.sh BUILD_DIR: `make install` as a user or a packager does it, from the build in
# BUILD_DIR (make install adds what that lacks: the shared library, the man page): every file in
# place (program, shared library with its soname and links, static library, headers, pkg-config
# file, man page, bash completion, docs, examples, the Python package); the C examples built with
# `pkg-config --cflags --libs mote` and run (the ring's error against the exact solution, a
# script sweep); libmote.a linked with what mote.pc names; the Python package imported from the
# prefix; DESTDIR staging; `make uninstall` leaving nothing behind. The install is of the plain
# build, so under the sanitizers (MOTE_SANITIZED) it is not repeated.
NAME=test_install
. "$(dirname "$0")/lib.sh"
SRC=$(cd "$(dirname "$0")/.." && pwd)
mote_test_start "$1"
if [ -n "${MOTE_SANITIZED:-}" ]; then
    echo "test_install: the installation is tested with the plain build"
    ok
    mote_test_end
    exit
fi
P=$TMP/prefix
B=$(cd "$(dirname "$MOTE")" && pwd)
make -s -C "$SRC" -j2 BUILD="$B" PREFIX="$P" install > make.txt 2>&1 && ok ||
    { bad "make install failed: $(tail -n 5 make.txt)"; mote_test_end; exit 1; }
version=$(sed -n 's/^#define MOTE_VERSION "\(.*\)"/\1/p' "$SRC/include/mote/core.h")
[ "$("$P/bin/mote" --version)" = "mote $version" ] && ok || bad "bin/mote --version: $("$P/bin/mote" --version)"
[ -f "$P/lib/libmote.so.$version" ] && [ "$(readlink "$P/lib/libmote.so.0")" = "libmote.so.$version" ] &&
    [ "$(readlink "$P/lib/libmote.so")" = libmote.so.0 ] && ok || bad "the shared library and its links: $(ls -l "$P/lib")"
objdump -p "$P/lib/libmote.so.$version" | grep -q 'SONAME *libmote\.so\.0$' && ok || bad "soname: $(objdump -p "$P/lib/libmote.so.$version" | grep SONAME)"
[ -f "$P/lib/libmote.a" ] && ok || bad "no lib/libmote.a"
[ "$(ls "$P/include/mote" | tr '\n' ' ')" = "$(ls "$SRC/include/mote" | tr '\n' ' ')" ] && ok || bad "headers: $(ls "$P/include/mote")"
export PKG_CONFIG_PATH="$P/lib/pkgconfig"
[ "$(pkg-config --modversion mote)" = "$version" ] && ok || bad "pkg-config --modversion mote: $(pkg-config --modversion mote 2>&1)"
# the man page: the tables' commands, every model; without warnings where groff is there
man1=$P/share/man/man1/mote.1
head -n 2 "$man1" | grep -q '^\.TH MOTE 1 ' && grep -q '^\.SH "MODEL SEPARATOR"$' "$man1" && grep -q '^\.B plot DATAFILE' "$man1" && ok ||
    bad "man page: $(head -n 3 "$man1")"
if command -v groff > /dev/null 2>&1; then
    groff -man -Tutf8 -ww -z "$man1" > groff.txt 2>&1 && [ ! -s groff.txt ] && ok || bad "groff warns: $(head -n 3 groff.txt)"
fi
# bash completion: verbs, commands (from every model's table) and rows
comp() { bash -c '. "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _mote; echo "${COMPREPLY[*]}"' _ "$P/share/bash-completion/completions/mote" "$@"; }
[ "$(comp mote ch)" = check ] && [ "$(comp mote help tro)" = tromp ] && [ "$(comp mote help generate pl)" = plummer ] &&
    [ "$(comp mote help reset_)" = "reset_stats" ] && ok ||
    bad "completion: 'mote ch' $(comp mote ch), 'help tro' $(comp mote help tro), 'help generate pl' $(comp mote help generate pl), 'help reset_' $(comp mote help reset_)"
[ -f "$P/share/doc/mote/README.md" ] && [ -f "$P/share/doc/mote/docs/commands.md" ] && [ -f "$P/share/doc/mote/examples/ring.mote" ] && ok ||
    bad "docs: $(ls -R "$P/share/doc/mote" | head)"
# the C examples, as installed, built by their Makefile with pkg-config
cp -r "$P/share/doc/mote/examples/c" cx
(cd cx && LD_LIBRARY_PATH="$P/lib" make -s run > out.txt 2> err.txt) && ok || bad "examples/c: make run failed: $(cat cx/err.txt | tail -n 5)"
grep -q '^ring: 30 bodies, T = 0.00999001 after 1000 steps: largest relative error [0-9.]*e-1[1-9]' cx/out.txt && ok || bad "ring: $(grep ring cx/out.txt)"
[ "$(grep -c '^reset: a new hard-spheres system$' cx/out.txt)" = 2 ] && [ -s cx/p_0.2.dat ] && [ -s cx/p_0.3.dat ] && ok || bad "script example: $(tail -n 3 cx/out.txt)"
objdump -p cx/ring | grep -q 'NEEDED *libmote\.so\.0$' && ok || bad "the example does not use the shared library"
# libmote.a: the library's own dependencies are those of Requires.private and Libs.private
pc=$P/lib/pkgconfig/mote.pc
cc -O2 cx/ring.c $(pkg-config --cflags mote) "$P/lib/libmote.a" $(pkg-config --libs $(sed -n 's/^Requires.private: //p' "$pc")) \
    $(sed -n 's/^Libs.private: //p' "$pc") -o ring_static 2> cc.txt &&
    ! objdump -p ring_static | grep -q libmote && ./ring_static > /dev/null && ok || bad "static link: $(head -n 5 cc.txt)"
# the Python package from the prefix: imported, runs a script and a session, the installed
# example runs with the installed data
pyver=$(/usr/bin/python3 -c 'import sysconfig; print(sysconfig.get_python_version())')
export PYTHONPATH="$P/lib/python$pyver/dist-packages"
[ "$(/usr/bin/python3 -c 'import mote; print(mote.__file__)')" = "$PYTHONPATH/mote/__init__.py" ] && ok ||
    bad "python3 -c 'import mote' does not find the installed package: $(/usr/bin/python3 -c 'import mote' 2>&1 | tail -n 1)"
/usr/bin/python3 -c 'import mote; s = mote.Simulation("nbody"); s.command("generate ring nb=30\nintegrate steps=100"); print(s.status()["N"], mote.run("echo ${x}\n", x=7), end="")' > py.txt 2>&1 &&
    [ "$(cat py.txt)" = "30 7" ] && ok || bad "the installed package: $(cat py.txt)"
(mkdir ex && cd ex && /usr/bin/python3 "$P/share/doc/mote/examples/python/ring.py" --quick --out o > out.txt 2>&1) && grep -q '^ring: error' ex/out.txt && ok ||
    bad "the installed ring.py: $(tail -n 3 ex/out.txt)"
unset PYTHONPATH
# uninstall removes every file it installed
make -s -C "$SRC" BUILD="$B" PREFIX="$P" uninstall > make.txt 2>&1 && ok || bad "make uninstall: $(tail -n 3 make.txt)"
left=$(find "$P" ! -type d)
[ -z "$left" ] && ok || bad "left after uninstall: $left"
# DESTDIR: staged under it, with the final prefix inside the pkg-config file
make -s -C "$SRC" BUILD="$B" PREFIX=/opt/mote DESTDIR="$TMP/stage" install > make.txt 2>&1 &&
    [ -x "$TMP/stage/opt/mote/bin/mote" ] && grep -qx 'prefix=/opt/mote' "$TMP/stage/opt/mote/lib/pkgconfig/mote.pc" && ok ||
    bad "DESTDIR install: $(tail -n 3 make.txt)"
mote_test_end
