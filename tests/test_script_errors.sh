#!/bin/sh
# script_errors.sh: the `mote` program end to end with the real hard-spheres model: exit statuses
# (0 ok, 1 usage/validation, 2 runtime), exact FILE:LINE:COL messages, nothing written when a
# script is invalid, `mote run` defaulting to program.txt, and help output.
# Usage: sh tests/script_errors.sh [BUILD_DIR]   (default: build)
ROOT=$(cd "$(dirname "$0")/.." && pwd)
NAME=script-errors
. "$(dirname "$0")/lib.sh"
mote_test_start "$1"

expect 1 "t1.mote:2:34: error: compressl: too many arguments: expected 'compress_left_wall eta dLmax K' (3 arguments), found 4" \
    t1.mote 'new 2 0.3\ncompressl 0.49 0.503423 0.000001 10\n'
expect 1 "t2.mote:3:1: error: unknown command 'stpe'; did you mean 'step'?" \
    t2.mote '# typo\nnew 2 0.3\nstpe 10\n'
expect 1 "t3.mote:2:6: error: step: expected an integer for K, found '1e3'" \
    t3.mote 'new 2 0.3\nstep 1e3\n'
expect 1 "t4.mote:2:6: error: unterminated quoted string" \
    t4.mote 'new 2 0.3\nsave "a b\n'
expect 1 "t5.mote:2:1: error: model:" t5.mote 'new 2 0.3\nmodel hard-spheres\n'
expect 1 "t6.mote:1:7: error: model: unknown model 'nosuch'" t6.mote 'model nosuch\n'

# a bad last line: nothing runs and nothing is written
expect 1 "t7.mote:3:6: error: step:" t7.mote 'new 2 0.3\nsave early.mote\nstep 0\n'
[ ! -e early.mote ] && ok || bad "t7.mote: early.mote was written before validation finished"
[ ! -s out.txt ] && ok || bad "t7.mote: something ran: $(cat out.txt)"

# valid scripts, CRLF, comments, output_dir
expect 0 "" t8.mote '# ok\r\n\r\nmodel hard-spheres\r\nnew 2 0.3   # seed\r\noutput_dir "res/a b"\r\nsave "st ate.mote"\r\necho done\r\n'
[ -f "res/a b/st ate.mote" ] && ok || bad "t8.mote: res/a b/st ate.mote missing"
grep -q '^done$' out.txt && ok || bad "t8.mote: echo output missing"

# relative file names start from the script's folder, whatever the current directory: a script
# in sub/ reads sub/in.mote and writes into sub/res2/ when run as `mote run sub/s.mote`, and
# `output_dir .` is the script's folder
mkdir -p sub
printf 'new 2 0.3\nsave sub/in.mote\n' > mk.mote
"$MOTE" run mk.mote > /dev/null 2>&1 && [ -f sub/in.mote ] && ok || bad "mk.mote did not write sub/in.mote"
printf 'load in.mote\noutput_dir res2\nsave out.mote\noutput_dir .\nsave here.mote\n' > sub/s.mote
"$MOTE" run sub/s.mote > out.txt 2> err.txt && [ -f sub/res2/out.mote ] && [ -f sub/here.mote ] &&
    [ ! -e res2 ] && [ ! -e here.mote ] && ok || bad "sub/s.mote from its parent: $(cat err.txt; ls -R)"
(cd sub && "$MOTE" run s.mote > ../out.txt 2> ../err.txt) && cmp -s sub/res2/out.mote sub/here.mote && ok ||
    bad "sub/s.mote from its folder: $(cat err.txt)"

# check only: validates, runs nothing
expect 0 "" t9.mote 'new 2 0.3\nsave nine.mote\n' check
[ ! -e nine.mote ] && ok || bad "t9.mote: check wrote a file"

# a runtime error: located at the command, exit status 2, earlier outputs intact
expect 2 "t10.mote:3:1: error: " t10.mote 'new 2 0.3\nsave ten.mote\nsave /proc/mote-cannot-write.mote\n'
[ -f ten.mote ] && ok || bad "t10.mote: the output of an earlier command is missing"

# `mote run` alone runs program.txt
printf 'new 2 0.3\r\nstep 1\r\n' > program.txt
"$MOTE" run > out.txt 2> err.txt && ok || bad "mote run (program.txt): $(cat err.txt)"
rm -f program.txt
"$MOTE" run > out.txt 2> err.txt
[ $? -eq 1 ] && grep -q "program.txt" err.txt && ok || bad "mote run without program.txt"

# usage and help
"$MOTE" > out.txt 2> err.txt; [ $? -eq 1 ] && grep -q '^Usage:' err.txt && ok || bad "no arguments"
[ "$("$MOTE" --version)" = "mote $(sed -n 's/^#define MOTE_VERSION "\(.*\)"$/\1/p' "$ROOT/include/mote/core.h" 2>/dev/null)" ] \
    && ok || bad "--version: $("$MOTE" --version)"
"$MOTE" help compresst > out.txt 2>&1 && grep -q '^compress_two_walls' out.txt && ok || bad "help compresst"
"$MOTE" help stpe > out.txt 2> err.txt; [ $? -eq 1 ] && grep -q "did you mean 'step'" err.txt && ok || bad "help stpe"
"$MOTE" help --markdown > out.txt && grep -q '^### `compress_left_wall`$' out.txt && ok || bad "help --markdown"

# the measuring commands: ranges checked before anything runs, located at the argument
expect 1 "m1.mote:2:10: error: pressure: K must be >= 1, found 0" \
    m1.mote 'new 2 0.3\npressure 0 p.dat\n'
expect 1 "m2.mote:2:12: error: chempot: TRIALS must be >= 1, found 0" \
    m2.mote 'new 2 0.3\nchempot 10 0 mu.dat\n'
expect 1 "m3.mote:1:1: error: order: no system exists yet" m3.mote 'order 5 o.dat\n'
expect 1 "m4.mote:1:6: error: bins: p must be in [1, 10000], found 0" m4.mote 'bins 0\n'
expect 1 "m5.mote:2:12: error: pressure: the directory of output file 'nodir/p.dat' does not exist" \
    m5.mote 'new 2 0.3\npressure 5 nodir/p.dat\n'
[ ! -e p.dat ] && [ ! -e mu.dat ] && ok || bad "m*.mote: a data file was written by an invalid script"
# and a valid one prints the key=value summaries and writes its files
expect 0 "" m6.mote 'new 2 0.35\nbins 5\npressure 5 p.dat\nchempot 2 50 mu.dat\norder 0 o.dat\n'
grep -q "^pressure: omega=.* P_left=.* P_right=.* P_wall=" out.txt && ok || bad "m6.mote: no pressure summary"
grep -q "^chempot: mu_ex=" out.txt && ok || bad "m6.mote: no chempot summary"
grep -q "^order: xtal_fraction=" out.txt && ok || bad "m6.mote: no order summary"
grep -q "^bins: 5 per R" out.txt && ok || bad "m6.mote: no bins line"
[ -s p.dat ] && [ -s mu.dat ] && [ -s o.dat ] && ok || bad "m6.mote: data files missing"
grep -q "^# bin_width = 0.2" p.dat && ok || bad "m6.mote: bins 5 not applied to pressure"

mote_test_end
