#!/bin/sh
# test_script_limits.sh BUILD_DIR: what fuzzing and a tester found in the script language (issue
# 52), each a clear error or a quick answer: 20 000 nested parentheses or signs in ${...} (a
# stack overflow), a sum of 10^5 terms, a 2*10^5-character name and 40 000 variables (quadratic
# time; each must finish in a few seconds), a loop that would expand to gigabytes, a count of
# 2^32 (wrapped to a negative int), 16-digit loop values (kept 15 digits), a parameter holding a
# line break (a fake header line), `end foo`, a loop of the documented 10^6 passes, the math
# functions of ${...}, 10^5 saves to one file (a warning each); and that the programs tell libgomp not to spin (threads on a busy
# machine). Each run has a time limit, so a hang or a quadratic slowdown fails.
NAME=script_limits
. "$(dirname "$0")/lib.sh"
mote_test_start "$1"

# run_limited SECONDS STATUS NAME [PARAMS...]: run script NAME (mote check with SUB=check),
# check its exit status
run_limited() {
    secs=$1 status=$2 name=$3
    shift 3
    timeout "$secs" "$MOTE" "${SUB:-run}" "$name" "$@" > out.txt 2> err.txt
    got=$?
    [ "$got" -eq "$status" ] && ok || bad "$name: exit status $got, expected $status ($(head -c 300 err.txt))"
}
# has PATTERN FILE WHAT: grep -q, or a failure saying WHAT
has() { grep -q -- "$1" "$2" && ok || bad "$3: $(head -c 400 "$2")"; }

# nesting: an error naming the bound, not a crash
awk 'BEGIN { s = ""; for (k = 0; k < 20000; k++) s = s "("; s = s "1"; for (k = 0; k < 20000; k++) s = s ")"
             print "model hard-spheres"; print "echo ${" s "}" }' > paren.mote
run_limited 60 1 paren.mote
has "paren.mote:2:6: error: in '\${(((.*\.\.\.}': nested more than 200 levels deep" err.txt "20 000 parentheses"
awk 'BEGIN { s = ""; for (k = 0; k < 20000; k++) s = s "-"; print "model hard-spheres"; print "echo ${" s "1}" }' > signs.mote
run_limited 60 1 signs.mote
has "nested more than 200 levels deep" err.txt "20 000 signs"
awk 'BEGIN { s = "1"; for (k = 0; k < 150; k++) s = "(" s ")"; print "model hard-spheres"; print "echo ${" s "+sqrt(4)}" }' > ok150.mote
run_limited 60 0 ok150.mote
has '^3$' out.txt "150 parentheses are fine"

# linear time: a sum of 10^5 terms, a long name, 40 000 variables (each was 3 s to minutes)
awk 'BEGIN { s = "1"; for (k = 1; k < 100000; k++) s = s "+1"; print "model hard-spheres"; print "echo ${" s "}" }' > sum.mote
run_limited 20 0 sum.mote
has '^100000$' out.txt "a sum of 10^5 terms"
awk 'BEGIN { s = ""; for (k = 0; k < 200000; k++) s = s "a"; print "model hard-spheres"; print "echo ${1+" s "}" }' > name.mote
run_limited 20 1 name.mote
has "undefined variable 'aaaa*\.\.\.'$" err.txt "a name of 2*10^5 characters, shown cut"
awk 'BEGIN { print "model hard-spheres"; for (k = 0; k < 40000; k++) print "set v" k " " k; print "echo ${v39999+v1}" }' > vars.mote
run_limited 20 0 vars.mote
has '^40000$' out.txt "40 000 variables"

# bytes: a loop whose lines add up to more than 64 MiB is refused before it takes the memory
awk 'BEGIN { s = ""; for (k = 0; k < 1000; k++) s = s "x"; print "model hard-spheres"; print "set w " s
             print "for i from 1 to 100000"; print "echo ${w}${w}${w}"; print "end" }' > big.mote
SUB=check
run_limited 60 1 big.mote
SUB=run
has "big.mote:4:1: error: the script's commands, with every pass of its loops and its variables replaced, exceed 64 MiB" err.txt "a loop expanding to 300 MB"

# counts: 2^32 is refused, not wrapped
printf 'model hard-spheres\nnew 4294967296 0.3\n' > count.mote
run_limited 60 1 count.mote
has "count.mote:2:5: error: new: NN is too large (at most 2147483647), found '4294967296'" err.txt "new 2^32"
printf 'model charging\nbody sphere radius=1\nfloat replicas=4294967296\n' > count2.mote
run_limited 60 1 count2.mote
has "float: replicas is too large (at most 2147483647)" err.txt "float replicas=2^32"

# numbers: whole numbers keep every digit up to 2^53, and seed takes them
printf 'model hard-spheres\nfor x from 1234567890123450 to 1234567890123459\necho ${x}\nend\n' > digits.mote
run_limited 60 0 digits.mote
[ "$(sort -u out.txt | wc -l)" -eq 10 ] && has '^1234567890123459$' out.txt "16-digit loop values" ||
    bad "16-digit loop values: $(sort -u out.txt | head -3)"
printf 'model hard-spheres\nset s 1234567890123456\nseed ${s+1}\necho ${2^53} ${0.1*3} ${1/3}\n' > seed.mote
run_limited 60 0 seed.mote
has '^seed: 1234567890123457' out.txt "seed \${s+1}"
has '^9007199254740992 0.3 0.333333333333333$' out.txt "2^53, 0.1*3, 1/3"

# a value with a line break never reaches a file name or a header
printf 'model hard-spheres\nnew 2 0.3\nstep 1\npressure 1 ${tag}.dat\n' > tag.mote
run_limited 60 1 tag.mote tag="$(printf 'a\nfake 1 2 3')"
has "parameter 'tag': the value holds a line break" err.txt "a parameter with a line break"
[ -z "$(ls ./*.dat 2>/dev/null)" ] && ok || bad "a file was written: $(ls)"

# end takes nothing; 10^6 passes of a one-line body are allowed (end is not a line of the body)
printf 'model hard-spheres\nfor i in 1 2\necho ${i}\nend foo\n' > endfoo.mote
run_limited 60 1 endfoo.mote
has "endfoo.mote:4:5: error: end: expected nothing after 'end', found 'foo'" err.txt "end foo"
printf 'model hard-spheres\nfor i from 1 to 1000000\nset x ${i}\nend\necho last=${x}\n' > million.mote
SUB=check
run_limited 120 0 million.mote
printf 'model hard-spheres\nfor i from 1 to 1000001\nset x ${i}\nend\n' > million1.mote
run_limited 120 1 million1.mote
has "too many" err.txt "10^6 + 1 passes"
SUB=run

# the functions of ${...}
printf 'model hard-spheres\necho ${sqrt(2)} ${atan2(1,1)*4} ${pi} ${min(3,max(1,2))} ${floor(2.7)} ${ceil(2.1)} ${abs(-3)} ${exp(1)} ${log(10)} ${sin(pi/2)} ${cos(0)} ${tan(0)}\n' > fn.mote
run_limited 60 0 fn.mote
has '^1.4142135623731 3.14159265358979 3.14159265358979 2 2 3 3 2.71828182845905 2.30258509299405 1 1 0$' out.txt "math functions"
printf 'model hard-spheres\nset pi 3\necho ${pi*2}\n' > mypi.mote
run_limited 60 0 mypi.mote
has '^6$' out.txt "a variable pi wins over the constant"
printf 'model hard-spheres\necho ${sqrt(-1)}\n' > nan.mote
run_limited 60 1 nan.mote
has "in '\${sqrt(-1)}': the result is not a finite number" err.txt "sqrt(-1)"
printf 'model hard-spheres\necho ${hypot(1,2)}\n' > unk.mote
run_limited 60 1 unk.mote
has "unknown function 'hypot' (sqrt exp" err.txt "an unknown function"
printf 'model hard-spheres\necho ${max(1)}\n' > arity.mote
run_limited 60 1 arity.mote
has "max takes 2 arguments" err.txt "max(1)"

# 10^5 saves to one file: one warning, not 99 999
awk 'BEGIN { print "new 2 0.3"; for (k = 0; k < 100000; k++) print "save s.state" }' > saves.mote
SUB=check
run_limited 60 0 saves.mote
SUB=run
[ "$(grep -c "is written more than once" err.txt)" -eq 1 ] && ok || bad "10^5 saves: $(grep -c warning err.txt) warnings"

# threads never spin: the programs set libgomp's spin count unless the user set one
OMP_DISPLAY_ENV=VERBOSE "$MOTE" --version > out.txt 2>&1
has "GOMP_SPINCOUNT = '1000'" out.txt "mote sets GOMP_SPINCOUNT=1000 before libgomp starts"
GOMP_SPINCOUNT=5000 OMP_DISPLAY_ENV=VERBOSE "$MOTE" --version > out.txt 2>&1
has "GOMP_SPINCOUNT = '5000'" out.txt "the user's GOMP_SPINCOUNT wins"

mote_test_end
