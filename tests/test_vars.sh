#!/bin/sh
# test_vars.sh BUILD_DIR: script variables and parameters (issue 35). `set NAME VALUE` and
# ${NAME} inside words, ${EXPR} arithmetic written with 15 significant digits,
# NAME=VALUE after the script's name fixing a variable over its `set`, `mote run -` reading
# standard input, data-file headers showing the values, and the errors: each names the line and
# nothing runs.
NAME=vars
. "$(dirname "$0")/lib.sh"
SRC=$(cd "$(dirname "$0")/.." && pwd)
mote_test_start "$1"

# values and arithmetic, inside words and quoted strings
cat > v.mote <<'X'
model hard-spheres
set eta 0.30
set n 2
new ${n} ${eta}
echo eta=${eta} twice=${eta*2} third=${1/3} pow=${2^10} neg=${-n+1} paren=${(eta+0.1)*10} cost=$$5
set name rho_${eta}
echo ${name}.dat "quoted ${n}" ${0.1*3} ${1e3*2} ${-2^2}
X
"$MOTE" run v.mote > out.txt 2> err.txt && ok || bad "v.mote failed: $(cat err.txt)"
grep -qx 'eta=0.30 twice=0.6 third=0.333333333333333 pow=1024 neg=-1 paren=4 cost=$5' out.txt && ok ||
    bad "expansion and arithmetic: $(grep '^eta' out.txt)"
grep -qx 'rho_0.30.dat quoted 2 0.3 2000 -4' out.txt && ok ||
    bad "a variable made of a variable, quoted words, 15 significant digits: $(grep '^rho' out.txt)"
grep -q '^N=64 .* eta=0.3 ' out.txt && ok || bad "new \${n} \${eta}: $(grep '^N=' out.txt)"

# parameters fix their variables over `set` (the defaults); the same script from standard input
"$MOTE" run v.mote eta=0.35 n=3 > out.txt 2> err.txt && [ ! -s err.txt ] && ok || bad "parameters: $(cat err.txt)"
grep -q '^N=276 .* eta=0.35 ' out.txt && grep -qx 'rho_0.35.dat quoted 3 0.3 2000 -4' out.txt && ok ||
    bad "eta=0.35 n=3: $(grep -e '^N=' -e '^rho' out.txt)"
"$MOTE" run - n=2 < v.mote > in.txt 2> err.txt && ok || bad "mote run -: $(cat err.txt)"
"$MOTE" run v.mote n=2 > file.txt 2>&1
cmp -s in.txt file.txt && ok || bad "mote run - differs from the file: $(diff in.txt file.txt | head -3)"
printf 'new 2 ${eta}\n' | "$MOTE" check - > out.txt 2> err.txt
grep -q "^<stdin>:1:7: error: undefined variable 'eta'" err.txt && ok || bad "errors in standard input are named <stdin>: $(cat err.txt)"

# the whole-script check sees the values: eta above the lattice's maximum fails before anything runs
"$MOTE" run v.mote eta=0.9 > out.txt 2> err.txt
[ $? -eq 1 ] && grep -q '^v.mote:4:10: error: new: eta = 0.9' err.txt && [ ! -s out.txt ] && ok || bad "eta=0.9 is not refused at check: $(cat err.txt out.txt)"

# a data file's header shows the command with its values
printf 'set k 2\nset f rho_${k}.dat\nnew 2 0.3\nimage ${k} 10 ${f}\n' > h.mote
"$MOTE" run h.mote > /dev/null 2> err.txt && grep -q '^# command: image 2 10 rho_2.dat ' rho_2.dat && ok ||
    bad "the header's command: $(grep '^# command' rho_2.dat) $(cat err.txt)"

# errors: each names the file, line and word; nothing runs
expect 1 "u1.mote:2:7: error: undefined variable 'eta' (define it with 'set eta VALUE' above, or give eta=VALUE after the script's name)" u1.mote 'new 2 0.3\nimage ${eta} 10 x.dat\n'
expect 1 "u2.mote:3:6: error: in '\${t*2}': variable 't' is 'hot', not a number" u2.mote 'set t hot\nnew 2 0.3\nstep ${t*2}\n'
expect 1 "u3.mote:1:6: error: '\${' without its '}' in 'x\${a'" u3.mote 'echo x${a\n'
expect 1 "u4.mote:1:6: error: in '\${1/0}': the result is not a finite number" u4.mote 'echo ${1/0}\n'
expect 1 "u5.mote:1:6: error: in '\${2)}': an operator (+ - * / ^) or the end expected" u5.mote 'echo ${2)}\n'
expect 1 "u6.mote:1:5: error: set: a variable name is a letter or '_', then letters, digits or '_', found '1x'" u6.mote 'set 1x 3\n'
expect 1 "u7.mote:1:1: error: set: too few arguments" u7.mote 'set x\n'
expect 1 "u8.mote:1:6: error: undefined variable 'later'" u8.mote 'echo ${later}\nset later 1\n'
expect 1 "u9.mote:1:6: error: in '\${(1+2}': expected ')'" u9.mote 'echo ${(1+2}\n'
printf 'echo ${a}\n' > p.mote
"$MOTE" run p.mote a=1 a=2 > out.txt 2> err.txt
[ $? -eq 1 ] && grep -q "^mote: error: parameter 'a' is given twice ('a=1' and 'a=2')" err.txt && [ ! -s out.txt ] && ok || bad "a parameter given twice: $(cat err.txt)"
"$MOTE" run p.mote 2a=1 > out.txt 2> err.txt
[ $? -eq 1 ] && grep -q "^mote: error: parameter '2a=1': expected NAME=VALUE" err.txt && ok || bad "a malformed parameter: $(cat err.txt)"
"$MOTE" run a=1 p.mote > out.txt 2> err.txt
[ $? -eq 1 ] && grep -q "^mote: error: 'a=1' looks like a parameter; parameters come after the script's name" err.txt && ok || bad "a parameter before the script: $(cat err.txt)"
"$MOTE" run p.mote a=1 b=2 > out.txt 2> err.txt
[ $? -eq 0 ] && grep -qx 'p.mote: warning: the script uses no ${NAME} of the parameter b' err.txt && grep -qx 1 out.txt && ok || bad "an unused parameter: $(cat err.txt)"

# loops: for NAME in ..., for NAME from A to B [step S] (A + kS, B included), nested, each
# pass checked as it will run; the variable keeps its last value
cat > l.mote <<'X'
new 2 0.2
for eta from 0.25 to 0.4 step 0.05
    compress_left_wall ${eta} 0.01 10
    for k in 1 two
        echo pass eta=${eta} k=${k}
    end
end
for x from 3 to 1 step -1
echo down ${x}
end
echo after ${eta} ${x}
X
"$MOTE" check l.mote > out.txt 2> err.txt && grep -qx 'l.mote: ok: 17 commands for model hard-spheres' out.txt && ok || bad "loops: $(cat out.txt err.txt)"
"$MOTE" run l.mote > out.txt 2> err.txt && ok || bad "l.mote failed: $(cat err.txt)"
[ "$(grep '^pass' out.txt | tr '\n' ' ')" = "pass eta=0.25 k=1 pass eta=0.25 k=two pass eta=0.3 k=1 pass eta=0.3 k=two pass eta=0.35 k=1 pass eta=0.35 k=two pass eta=0.4 k=1 pass eta=0.4 k=two " ] && ok ||
    bad "loop passes: $(grep '^pass' out.txt | tr '\n' ' ')"
[ "$(grep -e '^down' -e '^after' out.txt | tr '\n' ' ')" = "down 3 down 2 down 1 after 0.4 1 " ] && ok || bad "a falling loop and the last values: $(grep -e '^down' -e '^after' out.txt | tr '\n' ' ')"
grep -c '^compress_left_wall\|eta=0.4 ' out.txt > /dev/null && grep -q 'eta=0.4 ' out.txt && ok || bad "the compressions did not reach eta 0.4: $(grep '^N=' out.txt | tail -1)"
# an error names the pass; nothing runs
expect 1 "e1.mote:2:11: error: new: eta = 0.69999999999999996 is outside (0, eta_max]" e1.mote 'for eta in 0.3 0.7\n    new 2 ${eta}\nend\n' check
grep -q '(in the loop: eta=0.7)$' err.txt && ok || bad "the pass is not named: $(cat err.txt)"
expect 1 "e2.mote:3:6: error: undefined variable 'y'" e2.mote 'for a in 1 2\nfor b in 3\necho ${y}\nend\nend\n'
grep -q '(in the loop: a=1, b=3)$' err.txt && ok || bad "nested passes are not named: $(cat err.txt)"
# an error at run time names the pass too (a plot of a file that is not a data file)
printf 'not a data file\n' > plain.txt
expect 2 "e2b.mote:3:1: error: plain.txt:1: not a mote data file" e2b.mote 'new 2 0.3\nfor k in 1\nplot plain.txt o_${k}.png\nend\n'
grep -q '(in the loop: k=1)$' err.txt && ok || bad "a run-time error does not name the pass: $(cat err.txt)"
expect 1 "e3.mote:1:1: error: for: this loop has no 'end'" e3.mote 'for a in 1 2\necho ${a}\n'
expect 1 "e4.mote:2:1: error: end: no loop to end" e4.mote 'echo x\nend\n'
expect 1 "e5.mote:1:1: error: for: expected 'for NAME in V1 V2 ...' or 'for NAME from A to B [step S]'" e5.mote 'for a from 1 2\nend\n'
expect 1 "e6.mote:1:1: error: for: from 1 to 2 step 0 gives no values" e6.mote 'for a from 1 to 2 step 0\nend\n'
expect 1 "e7.mote:1:1: error: for: from 1 to 2 step -1 gives no values" e7.mote 'for a from 1 to 2 step -1\nend\n'
expect 1 "e8.mote:1:12: error: for: expected a number for A, found 'one'" e8.mote 'for a from one to 2\nend\n'
expect 1 "e9.mote:1:1: error: for: from 1 to 1e9 step 1 gives too many values" e9.mote 'for a from 1 to 1e9\nend\n'
printf 'for a from 1 to 1000\nfor b from 1 to 1001\nend\nend\n' > big.mote
"$MOTE" check big.mote > out.txt 2> err.txt; grep -q "^big.mote:1:1: error: for: the loops read more than 1000000 lines" err.txt && ok || bad "10^6 loop lines: $(cat err.txt out.txt)"
printf 'for eta in 1 2\necho ${eta}\nend\n' > pa.mote
"$MOTE" run pa.mote eta=3 > out.txt 2> err.txt
[ $? -eq 1 ] && grep -q "^pa.mote:1:5: error: for: 'eta' is a parameter given on the command line" err.txt && ok || bad "a loop over a parameter: $(cat err.txt)"

# reset: every model, two passes of one loop are one run each, bit for bit (the seed is back to 1)
# and equal to the same commands run alone; without reset the second pass is refused
reset_case() { # NAME MODEL_LINE SETUP_AND_RUN (\n-separated)
    printf '%b\n' "$2\n$3" > "$1_alone.mote"
    printf '%b\n' "$2\nfor pass in 1 2\nreset\n$3\nend" > "$1_loop.mote"
    "$MOTE" run "$1_alone.mote" > "$1_alone.txt" 2> err.txt || bad "$1 alone failed: $(cat err.txt)"
    "$MOTE" run "$1_loop.mote" > "$1_loop.txt" 2> err.txt || bad "$1 with reset failed: $(cat err.txt)"
    grep -v "^reset: a new .* system$\|seconds=\|[0-9] s$\|/s\b" "$1_loop.txt" > l.txt
    grep -v "seconds=\|[0-9] s$\|/s\b" "$1_alone.txt" > a.txt
    [ -s a.txt ] && [ "$(grep -c '^reset: a new' "$1_loop.txt")" = 2 ] && cat a.txt a.txt | cmp -s - l.txt && ok ||
        bad "$1: two passes with reset differ from two runs: $(cat a.txt a.txt | diff - l.txt | head -n 4)"
}
reset_case hs 'model hard-spheres' 'new 2 0.3\nstep 20'
reset_case nb 'model nbody' 'generate ring nb=12\nintegrate to=0.02'
reset_case mb 'model mixing-box' 'box 0 0.4 0 0.2\npartition 0.2 0.01\nslit 0.1 0.04\nradius 0.004\ndisks 30 20\nv_init 1\nplace\nrun 0.05'
reset_case ch 'model charging' 'plasma preset single n=1e6 kT=10\nbody sphere radius=1\nrun particles=2000'
reset_case sp 'model separator' 'channel 0.05 1\ngas 1.0\ncoupling off\ncollisions off\nspecies quartz 2500\nsize quartz loguniform min=75e-6 max=300e-6 basis=number\nfeed z=0.5\ntimestep 1e-3\ninsert quartz 200\nrun 0.2'
expect 1 "nr.mote:3:1: error: generate: the system already has bodies; a ring starts empty ('reset' gives a new one) (in the loop: k=2)" nr.mote 'model nbody\nfor k in 1 2\ngenerate ring nb=12\nend\n' check
# reset is checked like any command: the dry system is new too, so a later error is still found
expect 1 "rc.mote:4:1: error: step: no system exists yet; create one first with new, bulk, new_disks, bulk_disks or load" rc.mote 'new 2 0.3\nstep 2\nreset\nstep 2\n' check

# the sweep example: an ensemble per eta, a summary row each, Z rising with eta and within 3 %
# of Carnahan-Starling (N = 256 and short runs: the standard errors are about 0.5 %, and N = 256
# reads about 1 % high), drawn with error bars
cp "$SRC/examples/eos-sweep.mote" .
"$MOTE" run eos-sweep.mote n=4 K=50 R=2 > out.txt 2> err.txt && ok || bad "eos-sweep.mote failed: $(cat err.txt)"
grep -v '^#' out/eos-sweep/eos.dat | awk '{ n++; e = $1; z = $8; cs = (1 + e + e^2 - e^3) / (1 - e)^3; if (z <= last || (z / cs - 1)^2 > 0.03^2) bad = 1; last = z }
    END { exit !(n == 5 && !bad) }' && ok || bad "eos-sweep: $(grep -v '^#' out/eos-sweep/eos.dat)"
[ "$(grep -c '^eta=0.[0-9]*: Carnahan-Starling Z = ' out.txt)" = 5 ] && [ -s out/eos-sweep/eos.png ] && ok || bad "eos-sweep: $(grep -v '^N=' out.txt | head)"

mote_test_end
