#!/bin/sh
# test_python.sh BUILD_DIR: the Python package (BUILD_DIR/python, `make python`) with Debian's
# python3 and pytest: tests/python (the package against the program, errors, arrays, views,
# data files, progress, the GIL) and the examples of examples/python with short settings.
# Under the sanitizers the extension needs their runtimes loaded first into python3.
NAME=test_python
. "$(dirname "$0")/lib.sh"
SRC=$(cd "$(dirname "$0")/.." && pwd)
mote_test_start "$1"
PY=/usr/bin/python3
BUILD=$(cd "$(dirname "$MOTE")" && pwd)
[ -f "$BUILD/python/mote/__init__.py" ] && ok || { bad "no Python package in $BUILD/python (make python)"; mote_test_end; exit 1; }
preload=
if [ -n "${MOTE_SANITIZED:-}" ]; then
    preload="$(cc -print-file-name=libasan.so):$(cc -print-file-name=libubsan.so)"
    export ASAN_OPTIONS=detect_leaks=0 # (python itself keeps memory to the end)
fi
PYTHONPATH="$BUILD/python" MOTE="$MOTE" LD_PRELOAD="$preload" "$PY" -m pytest -q -p no:cacheprovider \
    "$SRC/tests/python" > pytest.txt 2>&1
rc=$?
tail -n 15 pytest.txt
[ $rc -eq 0 ] && ok || bad "pytest failed: $(grep -E '^(FAILED|ERROR)' pytest.txt | head -n 10)"
grep -q ' passed' pytest.txt && ! grep -q ' skipped' pytest.txt && ok || bad "pytest ran nothing, or skipped: $(tail -n 1 pytest.txt)"
mote_test_end
