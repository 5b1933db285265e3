#!/bin/sh
# test_csv.sh BUILD_DIR: a file named .csv is RFC 4180 in every model (issue 34): pandas and
# Python's csv read it as users do, with the columns and numbers of the same output written as a
# mote data file (any other name); `plot` refuses a .csv before the run.
NAME=csv
. "$(dirname "$0")/lib.sh"
mote_test_start "$1"
PY=/usr/bin/python3

# same.py DAT CSV: the CSV holds the data file's "# columns:" as its header and its rows
cat > same.py <<'X'
import csv, sys
import pandas as pd
dat, cs = sys.argv[1], sys.argv[2]
cols, rows = None, []
for l in open(dat):
    if l.startswith("# columns:"):
        cols = l.split()[2:]
    elif l.strip() and not l.startswith("#"):
        rows.append(l.split())
raw = open(cs, "rb").read()
assert raw.endswith(b"\r\n") and b"#" not in raw, raw[:80]
r = list(csv.reader(open(cs, newline="")))
assert r[0] == cols, (r[0], cols)
# (a monitor's cpu_s and wall_s are the only numbers that differ between identical runs)
keep = [k for k, c in enumerate(cols) if c not in ("cpu_s", "wall_s")]
same = lambda t: [[x[k] for k in keep] for x in t]
assert same(r[1:]) == same(rows), (r[1:3], rows[:2])
d = pd.read_csv(cs)
assert list(d.columns) == cols and d.shape == (len(rows), len(cols)), d.shape
X

printf '%bclasses 10 min=30e-6 max=600e-6\nbalance b.csv 0.1\nrun 0.5\ntromp tr.csv\ntromp tr.dat\nprofiles p.csv\nprofiles p.dat\n' "$SEP_DILUTE" > sep.mote
cat > ch.mote <<'X'
model charging faithful
body sphere radius=1
run particles=1e5
evolve time=2.5e-5 dt_out=5e-6 file=ts.csv
evolve time=2.5e-5 dt_out=5e-6 file=ts.dat
X
# the same integration twice, its monitor and trajectory named .csv, then .dat
for e in csv dat; do
    printf 'model nbody gravity\ngenerate ring nb=10\nintegrator galactica dt=1e-6\nmonitor every=500 file=m.%s\ntrajectory every=500 file=t.%s\nintegrate steps=1000\n' $e $e > "nb_$e.mote"
done
printf 'new 3 0.4\nstep 2000\nprofile 1 3 10 10 pr.csv\n' > hs.mote
printf 'new 3 0.4\nstep 2000\nprofile 1 3 10 10 pr.dat\n' > hs2.mote
for s in sep ch nb_csv nb_dat hs hs2; do
    "$MOTE" run "$s.mote" > "$s.out" 2>&1 && ok || bad "$s.mote: $(tail -3 "$s.out")"
done
for f in tr p ts m t pr; do
    [ -f "$f.csv" ] || continue
    $PY same.py "$f.dat" "$f.csv" > py.txt 2>&1 && ok || bad "$f.csv: $(tail -2 py.txt)"
done
# the balance, read by pandas: the invariant holds on every row
$PY -c '
import pandas as pd
d = pd.read_csv("b.csv")
assert len(d) == 6 and (d.fed_all == d.in_all + d.fines_all + d.coarse_all + d.lost_all).all()
' > py.txt 2>&1 && ok || bad "b.csv: $(tail -2 py.txt)"
# plot reads mote's own .csv files (issue 52: it could not) with x= and y= (a CSV file keeps
# its column names, not its kind: without them, an error at check time), the same curve as the
# .dat file's; a file of several blocks, repeating its header row, gives its last block as a .dat
expect 1 "pl.mote:5:6: error: plot: m.csv is a CSV file, which keeps its column names but not what kind of file it is: give x= and y=" pl.mote \
    "model nbody gravity\ngenerate ring nb=10\nmonitor every=500 file=m.csv\nintegrate steps=1000\nplot m.csv m.png\n" check
expect 0 "" pl2.mote "model nbody gravity\ngenerate ring nb=10\nmonitor every=500 file=mm.csv\nintegrate steps=1000\nplot mm.csv to=mc.png x=T y=dE\n"
expect 0 "" pl2b.mote "model nbody gravity\ngenerate ring nb=10\nmonitor every=500 file=mm.dat\nintegrate steps=1000\nplot mm.dat to=md.png x=T y=dE\n"
[ -s mc.png ] && cmp -s mc.png md.png && ok || bad "the plot of mm.csv differs from mm.dat's"
expect 0 "" pl3.mote "new 2 0.3\nstep 10\npressure 10 pp.csv\npressure 10 pp.dat\nplot pp.csv to=pc.png x=time y=P_wall\nplot pp.dat to=pd.png x=time y=P_wall\n"
[ -s pc.png ] && ok || bad "the plot of the last block of pp.csv"
mote_test_end
