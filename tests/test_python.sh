#!/bin/sh
# test_python.sh BUILD_DIR: the Python package with Debian's python3 and pytest: tests/python (the
# package against the program, errors, arrays, views, data files, progress, the GIL) and the
# examples of examples/python with short settings.
#
# The plain pass installs the package as a user does (issue 54): a venv made from scratch by
# Debian's python3 (--system-site-packages: its NumPy, setuptools and pytest; nothing is
# downloaded, --no-index), `pip install --no-build-isolation` of a copy of the source tree, and
# then, in that venv and outside the tree: the tests, `python -m mote` and the `mote` command as
# the program (the same output and files, byte for byte, the same exit status), and `pip wheel`.
# The copy keeps the files' times and MOTE_BUILD_DIR is BUILD_DIR, so nothing is compiled
# again: setup.py's `make python` finds the extension made for this python3 up to date.
# The sanitized pass runs the tests on BUILD_DIR/python directly, the sanitizers' runtimes
# loaded first into python3 (a venv adds nothing there: the extension's code is the same).
NAME=test_python
. "$(dirname "$0")/lib.sh"
SRC=$(cd "$(dirname "$0")/.." && pwd)
mote_test_start "$1"
PY=/usr/bin/python3
BUILD=$(cd "$(dirname "$MOTE")" && pwd)
[ -f "$BUILD/python/mote/__init__.py" ] && ok || { bad "no Python package in $BUILD/python (make python)"; mote_test_end; exit 1; }

pytest_in() { # pytest_in PYTHON [ENV...]: tests/python with that python; ok or bad
    py=$1
    shift
    env "$@" MOTE="$MOTE" "$py" -m pytest -q -p no:cacheprovider "$SRC/tests/python" > pytest.txt 2>&1
    rc=$?
    tail -n 15 pytest.txt
    [ $rc -eq 0 ] && ok || bad "pytest failed: $(grep -E '^(FAILED|ERROR)' pytest.txt | head -n 10)"
    grep -q ' passed' pytest.txt && ! grep -q ' skipped' pytest.txt && ok || bad "pytest ran nothing, or skipped: $(tail -n 1 pytest.txt)"
}

if [ -n "${MOTE_SANITIZED:-}" ]; then
    preload="$(cc -print-file-name=libasan.so):$(cc -print-file-name=libubsan.so)"
    # (python itself keeps memory to the end)
    pytest_in "$PY" PYTHONPATH="$BUILD/python" LD_PRELOAD="$preload" ASAN_OPTIONS=detect_leaks=0
    mote_test_end
    exit
fi

# the source tree as a user has it (what git tracks or would, or the folder without its builds)
mkdir tree
if git -C "$SRC" rev-parse --is-inside-work-tree > /dev/null 2>&1; then
    (cd "$SRC" && git ls-files -z --cached --others --exclude-standard | xargs -0 tar cf - 2> /dev/null) | tar xf - -C tree
else
    (cd "$SRC" && tar cf - --exclude='./build*' --exclude=./.git .) | tar xf - -C tree
fi
[ -f tree/pyproject.toml ] && [ -f tree/setup.py ] && ok || bad "the copy of the source tree has no pyproject.toml and setup.py"
"$PY" -m venv --system-site-packages venv > venv.txt 2>&1 && ok || bad "python3 -m venv: $(cat venv.txt)"
touch before_pip
MOTE_BUILD_DIR="$BUILD" venv/bin/pip install --no-build-isolation --no-index ./tree > pip.txt 2>&1 &&
    ok || bad "pip install: $(tail -n 20 pip.txt)"
# (what the build folder holds is reused: nothing compiled again)
[ -z "$(find "$BUILD" -name '*.o' -newer before_pip)" ] && ok || bad "pip install compiled again: $(find "$BUILD" -name '*.o' -newer before_pip | head -n 3)"
# imported from the venv, not the tree or BUILD_DIR
here=$PWD
where=$(cd / && "$here/venv/bin/python" -c 'import mote; print(mote.__file__)' 2>&1)
case "$where" in "$PWD"/venv/lib/python3*/site-packages/mote/__init__.py) ok ;; *) bad "import mote in the venv: $where" ;; esac
pytest_in "$PWD/venv/bin/python"

# python -m mote and the installed `mote` command are the program
printf 'model nbody\ngenerate ring nb=12\nintegrator galactica dt=1e-6\nintegrate steps=40\nsave ring.state\n' > ring.mote
mkdir a b c
cp ring.mote a/ && cp ring.mote b/ && cp ring.mote c/
(cd a && "$MOTE" run ring.mote > out.txt 2>&1)
(cd b && ../venv/bin/python -m mote run ring.mote > out.txt 2>&1) && ok || bad "python -m mote run: $(cat b/out.txt)"
(cd c && ../venv/bin/mote run ring.mote > out.txt 2>&1) && ok || bad "the venv's mote command: $(cat c/out.txt)"
for d in b c; do
    cmp -s a/ring.state $d/ring.state && [ "$(sed 's/ wall_seconds=.*//' a/out.txt)" = "$(sed 's/ wall_seconds=.*//' $d/out.txt)" ] &&
        ok || bad "$d: not the program's output and state: $(diff a/out.txt $d/out.txt | head -n 4)"
done
printf 'model nbody\nintegrate stepz=3\n' > bad.mote
"$MOTE" check bad.mote > p.txt 2>&1
prc=$?
venv/bin/python -m mote check bad.mote > q.txt 2>&1
qrc=$?
[ "$prc" -eq 1 ] && [ "$qrc" -eq "$prc" ] && cmp -s p.txt q.txt && ok || bad "python -m mote check: exit $qrc (the program's $prc), $(cat q.txt)"
venv/bin/python -m mote help > h.txt 2>&1 && grep -q 'mote' h.txt && ok || bad "python -m mote help: $(head -n 3 h.txt)"

# a notebook executed headless in the venv's own kernel (nbclient, ipykernel from Debian): the
# simulation shows as its picture and status table (and a PNG), integrate as a progress bar
# that ends at 100 %, the orbits as a PNG
venv/bin/python -m ipykernel install --sys-prefix > kernel.txt 2>&1 && ok || bad "ipykernel install: $(cat kernel.txt)"
mkdir nb && cp "$SRC/examples/python/orbits.ipynb" nb/
(cd nb && ../venv/bin/python - orbits.ipynb > nb.txt 2>&1 <<'PYEOF'
import sys
import nbclient
import nbformat
nb = nbformat.read(sys.argv[1], as_version=4)
nbclient.NotebookClient(nb, timeout=120, kernel_name="python3").execute()
outs = [[o for o in c.get("outputs", [])] for c in nb.cells if c.cell_type == "code"]
html = [o["data"]["text/html"] for o in outs[0] if "text/html" in o.get("data", {})]
assert html and "<b>mote nbody</b>" in html[0] and "<img src='data:image/png" in html[0], outs[0]
assert any("image/png" in o.get("data", {}) for o in outs[0]), outs[0]
result = [o for o in outs[1] if o["output_type"] == "execute_result"]
assert result and "{1: 1.0" in result[0]["data"]["text/plain"], outs[1]
bars = [o for o in outs[1] if o["output_type"] in ("display_data", "update_display_data")
        and "<progress value='1.0000'" in o.get("data", {}).get("text/html", "")]
assert bars, outs[1]  # integrate's progress bar, ended at 100 %
assert any("image/png" in o.get("data", {}) for o in outs[2]), outs[2]
print("notebook ok")
PYEOF
) && grep -q "notebook ok" nb/nb.txt && [ -s nb/orbits.png ] && ok || bad "the notebook: $(tail -n 15 nb/nb.txt)"

# the wheel: the extension (libmote inside it) and the modules, installable offline
MOTE_BUILD_DIR="$BUILD" venv/bin/pip wheel --no-build-isolation --no-index --no-deps -w wheels ./tree > wheel.txt 2>&1 &&
    ok || bad "pip wheel: $(tail -n 20 wheel.txt)"
venv/bin/python - wheels/mote-*.whl <<'PYEOF' && ok || bad "the wheel lacks the extension or a module: $(unzip -l wheels/*.whl 2>&1 | tail -n 12)"
import sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
assert any(n.startswith("mote/_mote.") and n.endswith(".so") for n in names), names
assert "mote/__init__.py" in names and "mote/__main__.py" in names, names
PYEOF
mote_test_end
