#!/bin/sh
# test_progress.sh BUILD_DIR: every model's long commands show their progress on a terminal
# ("\rLABEL 42.0%  ~3 s left", rising, wiped at the end) and print nothing extra when the output
# is not a terminal (issue 34). A pseudo-terminal (Python's pty) stands in for the terminal;
# MOTE_PROGRESS_INTERVAL=0 shows every update, so a command that ends fast still shows some.
NAME=progress
. "$(dirname "$0")/lib.sh"
EX=$(cd "$(dirname "$0")/.." && pwd)/examples/galactica
mote_test_start "$1"

cat > hs.mote <<'X'
model hard-spheres
new 3 0.4
step 20000
compress_left_wall 0.43 0.001 10
X
cat > mb.mote <<'X'
model mixing-box
box 0 2 0 1
partition 1 0.02
slit 0.5 0.1
radius 0.005
disks 300 300
v_init 1
place
run 3
X
cat > nb.mote <<'X'
model nbody gravity
generate ring nb=20
integrator galactica dt=1e-6
integrate steps=3000
X
# a Galactica job (its monitor blocks print between progress lines, each on a clean line)
cp -r "$EX/ring30" ring30
printf 'model nbody gravity\nrun galactica control=ring30/galacf26.dat\n' > gal.mote
printf '%brun 0.5\n' "$SEP_DILUTE" > sep.mote
cat > ch.mote <<'X'
model charging faithful
body sphere radius=1
run particles=2e5

X
# the boundary-element solve of a body's field (issue 55): the assembly, then the LU by panels
printf 'model charging\nbody icosphere radius=1 level=3\nbody capacitance value=solve\n' > bem.mote
# commands of several runs keep one line for all of them: "float: run 3, 42.0%"
cat > chf.mote <<'X'
model charging
plasma preset geo-worst-case
body sphere radius=1
float particles=8192
evolve time=1e-3 dt_out=5e-4 particles=8192
X

# onterm.py MOTE SCRIPT: run `mote run SCRIPT` on a pseudo-terminal, print what it wrote
cat > onterm.py <<'X'
import os, pty, sys
pid, fd = pty.fork()
if pid == 0:
    os.execv(sys.argv[1], [sys.argv[1], "run", sys.argv[2]])
out = b""
while True:
    try:
        d = os.read(fd, 65536)
    except OSError:
        break
    if not d:
        break
    out += d
_, st = os.waitpid(pid, 0)
sys.stdout.buffer.write(out)
sys.exit(os.waitstatus_to_exitcode(st))
X
# check.py FILE LABEL...: each label shows percentages, never falling, reaching above 0 (the
# mixing box's event runs once showed 0.0% throughout) and at most 100, and the
# last progress line of each command is wiped before the status line that follows it. A label
# written LABEL+ is a command of several runs: one line for all of them ("LABEL: run K, P%"),
# the runs counted up from 1 to more than 1, each one's percentages rising, wiped once.
cat > check.py <<'X'
import re, sys
t = open(sys.argv[1], encoding="utf-8", errors="replace", newline="").read()
bad = []
for label in sys.argv[2:]:
    several = label.endswith("+")
    label = label.rstrip("+")
    run = r": run [0-9]+," if several else ""
    runs = re.findall(r"((?:\r%s%s [0-9.]+%%[^\r\n]*)+)(\r *\r)?" % (re.escape(label), run), t)
    if not runs:
        bad.append("%s: no progress line" % label)
        continue
    if several and len(runs) != 1:
        bad.append("%s: %d progress lines, not one for all the runs" % (label, len(runs)))
    for lines, wiped in runs:
        if several:
            p = [(int(k), float(x)) for k, x in
                 re.findall(r"\r%s: run ([0-9]+), ([0-9.]+)%%" % re.escape(label), lines)]
            if p[0][0] != 1 or not p[-1][0] > 1:
                bad.append("%s: runs %d to %d" % (label, p[0][0], p[-1][0]))
            # the time left is the run's, said so, beside the time so far (issue 52: "~0 s
            # left" for the whole command)
            for l in re.findall(r"\r[^\r]*", lines):
                if "left" in l and not re.search(r"left in this run, [0-9.]+ (s|min|h) so far", l):
                    bad.append("%s: %r" % (label, l.strip()))
                    break
        else:
            p = [float(x) for x in re.findall(r"\r%s ([0-9.]+)%%" % re.escape(label), lines)]
        if any(b < a for a, b in zip(p, p[1:])) or not (0 < (p[-1][1] if several else p[-1]) <= 100):
            bad.append("%s: percentages %s" % (label, p[:20]))
        if not wiped:
            bad.append("%s: the progress line is not wiped" % label)
print("; ".join(bad) if bad else "ok")
X

# strip.py FILE: what a terminal showed, without the progress lines and their wipes
cat > strip.py <<'X'
import re, sys
t = open(sys.argv[1], encoding="utf-8", errors="replace", newline="").read()
t = re.sub(r"\r[A-Za-z_]+(: run [0-9]+,)? [0-9.]+%[^\r\n]*", "", t)
t = re.sub(r"\r +\r", "", t).replace("\r\n", "\n")
sys.stdout.write(t)
X

for m in "hs step compress_left_wall" "mb run" "nb integrate" "gal galactica" "sep run" "ch run" "chf float+ evolve+" "bem solve"; do
    set -- $m
    s=$1
    shift
    if MOTE_PROGRESS_INTERVAL=0 python3 onterm.py "$MOTE" "$s.mote" > "$s.tty" 2>&1; then ok; else
        bad "$s: exit status $? on a terminal: $(tail -c 400 "$s.tty")"; fi
    r=$(python3 check.py "$s.tty" "$@")
    [ "$r" = ok ] && ok || bad "$s: $r"
    # not a terminal: no carriage return, no progress, and the same output otherwise
    if MOTE_PROGRESS_INTERVAL=0 "$MOTE" run "$s.mote" > "$s.out" 2>&1; then ok; else
        bad "$s: exit status $? into a file"; fi
    if grep -q "$(printf '\r')" "$s.out" || grep -q '%  ~' "$s.out"; then
        bad "$s: progress written into a file: $(head -c 300 "$s.out")"; else ok; fi
    python3 strip.py "$s.tty" > a.txt
    # (wall-clock figures and rates differ between the two runs; into a file, hard spheres'
    # compressions log every 1000 moves, as the original program did)
    sed -i 's/seconds=[0-9.e+-]*//; s/_per_second=[0-9.e+-]*//; s/[0-9.e+]* traces\/s//;
            /^compress[a-z_]*: [0-9]* moves, eta=/d' a.txt "$s.out"
    cmp -s a.txt "$s.out" && ok || bad "$s: the output differs on a terminal: $(diff a.txt "$s.out" | head -5)"
done
mote_test_end
