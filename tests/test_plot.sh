#!/bin/sh
# test_plot.sh BUILD_DIR: the `plot` command end to end: it renders the data files of `image`
# and `profile` as PNGs of the expected size, and rejects what it cannot plot with a located
# error (validation: exit 1, nothing written; at run time: exit 2, earlier outputs kept).
build=$(cd "${1:-build}" && pwd)
mote="$build/mote"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok: $1"; }
bad() { fail=$((fail + 1)); echo "FAIL: $1"; }
check() { if eval "$2"; then ok "$1"; else bad "$1"; fi; }
# width and height of a PNG from its IHDR chunk (bytes 16..23, big-endian)
png_size() { od -An -tu1 -j16 -N8 "$1" | awk '{print $1*16777216+$2*65536+$3*256+$4 "x" $5*16777216+$6*65536+$7*256+$8}'; }
is_png() { [ "$(od -An -c -j1 -N3 "$1" | tr -d ' ')" = "PNG" ]; }

cat > good.mote <<'S'
new 2 0.4
image 5 10 prof.dat
profile 0.9 2.2 2 4 cut.dat
plot prof.dat prof.png
plot cut.dat cut.png
new_disks 4 6 0.5
profile 0.9 3 1 0 cut2d.dat
plot cut2d.dat cut2d.png
S
"$mote" run good.mote >out.txt 2>err.txt
check "a script plotting image and profile data runs" '[ $? -eq 0 ]'
check "the density plot is a PNG" 'is_png prof.png'
check "the density plot is 1000x650" '[ "$(png_size prof.png)" = 1000x650 ]'
check "the 3D cut picture is a PNG" 'is_png cut.png'
check "the 3D cut picture's longer side is the default 900 px" \
    'sz=$(png_size cut.png); w=${sz%x*}; h=${sz#*x}; [ "$w" -le 900 ] && [ "$h" -le 900 ] && { [ "$w" -eq 900 ] || [ "$h" -eq 900 ]; }'
check "the 2D cut picture is a PNG" 'is_png cut2d.png'
check "plot reports what it wrote" 'grep -q "plot: wrote prof.png" out.txt'

# a file that is not mote data: runtime error naming file and line, earlier output kept
printf 'hello world\n' > junk.dat
printf 'new 2 0.4\nimage 1 10 keep.dat\nplot junk.dat junk.png\n' > junk.mote
"$mote" run junk.mote >out.txt 2>err.txt
rc=$?
check "plot of a non-mote file fails at run time (exit 2)" '[ $rc -eq 2 ]'
check "the message names the data file and line" 'grep -q "junk.dat:1:" err.txt'
check "the message is located at the plot command" 'grep -q "^junk.mote:3:1: error:" err.txt'
check "no PNG is left behind" '[ ! -e junk.png ]'
check "the earlier output is intact" 'grep -q "^# mote image 1" keep.dat'

# a malformed data row in an image file
{ printf '# mote image 1\n# d = 3\n'; printf '0 0.1 0.05 3 0.5 0.1\n'; } > short.dat
printf 'plot short.dat short.png\n' > short.mote
"$mote" run short.mote >out.txt 2>err.txt
rc=$?
check "a short data row is a runtime error (exit 2)" '[ $rc -eq 2 ]'
check "the short row is named by line" 'grep -q "short.dat:3: malformed data row" err.txt'

# validation: a missing data file, and a state file, are rejected before anything runs
printf 'new 2 0.4\nsave s.txt\nplot nosuch.dat x.png\n' > missing.mote
"$mote" run missing.mote >out.txt 2>err.txt
rc=$?
check "plot of a missing file is a validation error (exit 1)" '[ $rc -eq 1 ]'
check "the missing file is named at its argument" 'grep -q "^missing.mote:3:6: error:.*nosuch.dat" err.txt'
check "nothing ran: the earlier save was not written" '[ ! -e s.txt ]'
printf 'new 2 0.4\nsave s2.txt\nplot s2.txt x.png\n' > state.mote
"$mote" run state.mote >out.txt 2>err.txt
rc=$?
check "plot of a state file is a validation error (exit 1)" '[ $rc -eq 1 ]'
check "the message names the data files plot accepts" 'grep -q "s2.txt. is written earlier in this script as a file of kind state; expected a file of kind image, profile, pressure, chempot, order, rdf, msd or monitor" err.txt'

# the measurement files: pressure (tensor profile), chempot (Widom profile), order (over time
# and, with one sample, across x)
cat > meas.mote <<'S'
new 3 0.35
step 20
pressure 20 p.dat
chempot 5 200 mu.dat
order 10 o.dat
order 0 o0.dat
plot p.dat p.png
plot mu.dat mu.png
plot o.dat o.png
plot o0.dat o0.png
S
"$mote" run meas.mote >out.txt 2>err.txt
check "a script plotting pressure, chempot and order data runs" '[ $? -eq 0 ]'
for f in p mu o o0; do
    check "$f.png is a 1000x650 PNG" 'is_png $f.png && [ "$(png_size $f.png)" = 1000x650 ]'
done
# a pressure file with a short row in its first block: a located runtime error, no PNG
sed '/^#/!{0,/^[0-9]/s/ [^ ]*$//}' p.dat > pshort.dat
printf 'plot pshort.dat pshort.png\n' > pshort.mote
"$mote" run pshort.mote >out.txt 2>err.txt
rc=$?
check "a short pressure row is a runtime error (exit 2)" '[ $rc -eq 2 ]'
check "the short row is named by file and line" 'grep -q "pshort.dat:[0-9]*: malformed data row (9 numbers)" err.txt'
check "no PNG is left behind" '[ ! -e pshort.png ]'

# ---- lines: several files in one frame, with a legend (any model) ----
# colour_px PNG R G B: the pixels within 12 of the colour (R, G, B in 0..255), read back with
# Debian's matplotlib
colour_px() {
    /usr/bin/python3 -c 'import sys, numpy as np, matplotlib.image as im
a = im.imread(sys.argv[1])[:, :, :3] * 255
c = np.array([float(v) for v in sys.argv[2:5]])
print(int((np.abs(a - c).max(axis=2) <= 12).sum()))' "$@"
}
cat > lines.mote <<'S'
for eta in 0.3 0.4
    reset
    new 3 ${eta}
    step 20
    image 10 4 rho_${eta}.dat
end
plot rho_0.3.dat rho_0.4.dat to=two.png labels=0.3,0.4
plot rho_0.3.dat to=one.png labels=0.3
plot rho_0.3.dat rho_0.4.dat to=two_again.png labels=0.3,0.4
plot rho_0.3.dat rho_0.4.dat to=relabel.png labels=0.3,other
plot rho_0.3.dat rho_0.4.dat to=v.png x=x_mid y=rho_v
S
"$mote" run lines.mote >out.txt 2>err.txt
check "a script of overlays runs" '[ $? -eq 0 ]'
check "the overlay is a 1000x650 PNG" 'is_png two.png && [ "$(png_size two.png)" = 1000x650 ]'
check "plot reports the overlay" 'grep -q "^plot: wrote two.png$" out.txt'
check "the same overlay twice: the same bytes" 'cmp -s two.png two_again.png'
check "labels= changes the legend" '! cmp -s two.png relabel.png'
check "x= and y= choose other columns" '! cmp -s two.png v.png'
# one line is blue (Okabe-Ito), the second vermillion: absent from the one-file picture
blue1=$(colour_px one.png 0 114 178) ver1=$(colour_px one.png 213 94 0) ver2=$(colour_px two.png 213 94 0)
check "one file: a blue line, no vermillion one ($blue1, $ver1 px)" '[ "$blue1" -gt 500 ] && [ "$ver1" -lt 20 ]'
check "two files: a vermillion line too ($ver2 px)" '[ "$ver2" -gt 500 ]'
# existing files are checked before anything runs (exit 1, nothing written)
lines_err() { # NAME EXIT MESSAGE COMMAND
    printf 'new 2 0.3\n%s\n' "$4" > "$1.mote"
    "$mote" run "$1.mote" > out.txt 2> err.txt
    rc=$? want=$2 msg=$3
    check "$1: exit $2, '$3'" '[ $rc -eq $want ] && grep -qF "$msg" err.txt'
}
lines_err le1 1 'le1.mote:2:46: error: plot: labels= gives 1 label for 2 data files (one per file, separated by commas)' 'plot rho_0.3.dat rho_0.4.dat to=a.png labels=a'
lines_err le2 1 "le2.mote:2:41: error: plot: rho_0.3.dat has no column zz (its columns: x_lo[R], x_hi[R], x_mid[R], count, rho[R^-3], rho_err[R^-3], rho_v)" 'plot rho_0.3.dat rho_0.4.dat to=a.png y=zz'
lines_err le3 1 "le3.mote:2:18: error: plot: p.dat holds pressure data and rho_0.3.dat image data: lines drawn by default come from files of one kind (or give x= and y=)" 'plot rho_0.3.dat p.dat to=a.png'
lines_err le4 1 "le4.mote:2:1: error: plot: name the picture: 'plot DATAFILE PNGFILE', or 'plot A.dat B.dat ... to=PNGFILE'" 'plot rho_0.3.dat'
lines_err le5 1 "le5.mote:2:18: error: plot: name the picture: 'plot DATAFILE PNGFILE', or 'plot A.dat B.dat ... to=PNGFILE' (a PNGFILE ends in .png)" 'plot rho_0.3.dat rho_0.4.dat'
lines_err le6 1 "le6.mote:2:18: error: plot: two.png is a picture, not a data file (the picture is to=a.png)" 'plot rho_0.3.dat two.png to=a.png'
lines_err le7 1 "le7.mote:2:6: error: plot: 'nothere.dat' does not exist and no earlier command writes it" 'plot nothere.dat rho_0.3.dat to=a.png'
check "no picture is left by a refused plot" '[ ! -e a.png ]'
# a model without pictures of its own draws lines: the separator's Tromp curves
cat > tromp.mote <<'S'
model separator
for u in 0.8 1.2
    reset
    channel 0.05 1
    gas ${u}
    coupling off
    collisions off
    species quartz 2500
    size quartz loguniform min=75e-6 max=300e-6 basis=number
    feed z=0.5
    classes 10 min=75e-6 max=316.2277660e-6
    timestep 1e-3
    insert quartz 300
    run 5
    tromp tromp_${u}.dat
end
plot tromp_0.8.dat tromp_1.2.dat to=tromp.png labels=0.8,1.2
plot tromp_0.8.dat tromp_one.png
S
"$mote" run tromp.mote >out.txt 2>err.txt
check "the separator draws Tromp curves as lines" '[ $? -eq 0 ] && is_png tromp.png && is_png tromp_one.png'

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
