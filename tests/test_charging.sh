#!/bin/sh
# test_charging.sh: the charging model through the `mote` program: the thesis's faithful run
# (spec 10 F1: U = -146.77 V at 0.25 ms, within 3 sigma, from the time-series file), and bad input
# (spec issue 22): each malformed command a located error before anything runs, nothing written.
# Usage: sh tests/test_charging.sh [BUILD_DIR]   (default: build)
NAME=charging
. "$(dirname "$0")/lib.sh"
top=$(cd "$(dirname "$0")/.." && pwd)
mote_test_start "$1"

F='model charging faithful\n'
printf '%bbody sphere radius=1\nrun particles=2e6\nevolve time=2.5e-4 dt_out=2.5e-5 file=ts.csv\n' "$F" > f1.mote
"$MOTE" run f1.mote > out.txt 2> err.txt && ok || bad "f1.mote failed: $(cat err.txt)"
[ "$(head -n 1 ts.csv | tr -d '\r')" = "t_s,Q_C,U_V,sigma_U_V,I_net_A,I_e_A,Nreal_e,I_H+_A,Nreal_H+,I_see_A,I_photo_A" ] && ok || bad "time-series columns (CSV header): $(head -n 1 ts.csv)"
[ "$(($(wc -l < ts.csv) - 1))" -eq 11 ] && ok || bad "time series: $(wc -l < ts.csv) lines, expected a header and 11 rows (t = 0 ... 0.25 ms)"
# U(0.25 ms) within 3 sigma of -146.77 V, and U exactly linear in t: U(t) / t the same on every row
awk -F '[,\r]' 'FNR > 1 { n++; t[n] = $1; U[n] = $3; s[n] = $4 } END { d = U[n] + 146.77; ok = n == 11 && d * d <= 9 * s[n] * s[n] + 1e-6;
     for (k = 2; k <= n; k++) { r = U[k] / t[k] - U[n] / t[n]; if (r * r > 1e-16 * (U[n] / t[n]) ^ 2) ok = 0 } exit !ok }' ts.csv && ok || bad "U(0.25 ms): $(tail -1 ts.csv)"
grep -q '^run: e    I = -6.70' out.txt && ok || bad "run line: $(grep '^run: e' out.txt)"
# dt= is the shared word for the rows' interval (dt_out=, its earlier name, gives the same rows)
sed 's/dt_out=2.5e-5 file=ts.csv/dt=2.5e-5 file=ts2.csv/' f1.mote > f2.mote
"$MOTE" run f2.mote > out2.txt 2> err.txt && cmp -s ts.csv ts2.csv && ok || bad "evolve dt= and dt_out= differ: $(cat err.txt)"
# monitor dt= file= (the word every model has): the same rows as evolve's own dt= and file=,
# FILE.partial gone once FILE is whole; an evolve with its own file= is not the monitor's
sed 's/evolve time=2.5e-4 dt_out=2.5e-5 file=ts.csv/monitor dt=2.5e-5 file=ts3.csv\nevolve time=2.5e-4\nevolve time=1e-4 file=ts4.csv/' f1.mote > f4.mote
"$MOTE" run f4.mote > out4.txt 2> err.txt && cmp -s ts.csv ts3.csv && [ ! -e ts3.csv.partial ] && ok || bad "monitor dt= file= and evolve's dt= file= differ: $(cat err.txt) $(ls ts3*)"
[ "$(($(wc -l < ts4.csv) - 1))" -eq 2 ] && ok || bad "evolve file= beside a monitor: $(wc -l < ts4.csv) lines, expected a header and 2 rows (t = 0 and T: its own file, not the monitor's rows)"
expect 1 "f3.mote:4:33: error: evolve: give dt= (the rows' interval) or dt_out= (its earlier name), not both" f3.mote "${F}body sphere radius=1\nrun particles=1e4\nevolve time=1e-4 dt=1e-5 dt_out=1e-5\n"

# legacy_stdout=on (spec 8.1): the original's four columns Q U t collisions on stdout, the same
# numbers as the time series (P_timeseries.csv after output prefix)
printf '%bbody sphere radius=1\noutput prefix=lg legacy_stdout=on png=off vtk=off triangles=off\nrun particles=1e5\nevolve time=2.5e-4 dt_out=5e-5\n' "$F" > lg.mote
"$MOTE" run lg.mote > out.txt 2> err.txt && grep -E '^-?[0-9.e+-]+ -?[0-9.e+-]+ [0-9.e+-]+ [0-9.e+-]+$' out.txt > legacy.txt &&
    awk -F '[ ,\r]' 'NR == FNR { q[NR] = $1; u[NR] = $2; t[NR] = $3; c[NR] = $4; n = NR; next } FNR > 1 { k++; d = u[k] - $3; e = c[k] - $7 - $9; if (d * d > 1e-16 * $3 * $3 || t[k] != $1 || e * e > 1e-16 * c[k] * c[k]) bad = 1 }
         END { exit !(n == 6 && k == 6 && !bad && q[1] == 0) }' legacy.txt lg_timeseries.csv && ok || bad "legacy_stdout: $(cat legacy.txt) $(cat err.txt)"

# threads give the same file (spec 5.7, S5)
printf '%bbody icosphere radius=1 level=3\nthreads 2\nrun particles=2e5\nevolve time=1e-4 file=ts2.csv\n' "$F" > t2.mote
printf '%bbody icosphere radius=1 level=3\nrun particles=2e5\nevolve time=1e-4 file=ts1.csv\n' "$F" > t1.mote
"$MOTE" run t1.mote > /dev/null 2>&1 && "$MOTE" run t2.mote > /dev/null 2>&1 && [ "$(grep -v '^# command' ts1.csv)" = "$(grep -v '^# command' ts2.csv)" ] && ok || bad "1 and 2 threads give different time series"

# bad input: located errors before anything runs
G='model charging\n'
expect 1 "b1.mote:2:15: error: plasma: expected 'geo-worst-case', 'thesis-hot' or 'single' for NAME, found 'leo'" b1.mote "${G}plasma preset leo\n"
expect 1 "b2.mote:2:15: error: plasma preset single: give n= (m^-3) and kT= (eV)" b2.mote "${G}plasma preset single n=1e6\n"
expect 1 "b3.mote:2:24: error: plasma: n must be > 0, found -1" b3.mote "${G}plasma preset single n=-1 kT=10\n"
expect 1 "b4.mote:2:1: error: body box: option size= is required (body box size=SX,SY,SZ [subdiv=1])" b4.mote "${G}body box\n"
"$MOTE" help body > bh.txt 2>&1 && [ "$(grep -c '^body ' bh.txt)" -ge 7 ] && [ "$(grep -c 'icosphere of 20' bh.txt)" = 1 ] && ok || bad "mote help body: the rows, with their shared text once: $(head -3 bh.txt)"
# one table row per kind of body: its options only
expect 1 "b5b.mote:2:6: error: body: expected sphere, icosphere, uvsphere, box, twocubes, load or capacitance, found 'cone'" b5b.mote "${G}body cone radius=1\n"
expect 1 "b5c.mote:2:15: error: body box: size=SX,SY,SZ: three lengths > 0 (m)" b5c.mote "${G}body box size=1,-1,1\n"
expect 1 "b5d.mote:2:22: error: body sphere: unknown option 'size'" b5d.mote "${G}body sphere radius=1 size=1,1,1\n"
expect 1 "b5.mote:2:15: error: body box: expected X,Y,Z (3 finite numbers separated by commas) for size, found '1,nan,1'" b5.mote "${G}body box size=1,nan,1\n"
expect 1 "b6.mote:3:1: error: run: there is no body yet" b6.mote "${G}plasma preset thesis-hot\nrun\n"
expect 1 "b7.mote:3:1: error: run: there is no plasma yet (plasma preset ..., or species and maxwellian)" b7.mote "${G}body sphere radius=1\nrun\n"
# a charged mesh (spec 6.3): curved paths; float on a level-3 icosphere in the single 1 keV
# plasma lands within 1% of the OML root -2503.9 V, with nothing lost and energy kept to 1e-6
printf '%bplasma preset single n=1e6 kT=1000\nbody icosphere radius=1 level=3\nintegrator eta=0.01 max_steps=1e5\nfloat particles=1e5\n' "$G" > fm.mote
"$MOTE" run fm.mote > out.txt 2> err.txt && awk '/^float: U_f/ { u = $4 } /^float: curved paths/ { lost = $8; e = $14 }
     END { d = u / -2503.9 - 1; exit !(d * d < 1e-4 && lost == 0 && e < 1e-6) }' out.txt && ok || bad "float on a mesh: $(grep '^float' out.txt) $(cat err.txt)"
mkdir -p oms
expect 2 "ms.mote:6:1: error: run: " ms.mote "${G}plasma preset single n=1e6 kT=1000\nbody icosphere radius=1 level=2\noutput prefix=oms/x\nintegrator max_steps=2\nrun particles=1000 potential=-3000\n"
grep -q 'histories still going after 2 steps (at U = -3000 V; the spec allows 1e-6 of them): raise integrator max_steps= or eta=' err.txt && [ -z "$(ls oms)" ] && ok || bad "max_steps=2: $(cat err.txt); $(ls oms)"
expect 1 "b8.mote:2:16: error: integrator: eta must be" b8.mote "${G}integrator eta=2\n"
expect 1 "b9.mote:2:22: error: integrator: max_steps must be a whole number" b9.mote "${G}integrator max_steps=1.5\n"
expect 1 "b9b.mote:4:1: error: float: in faithful mode the currents do not depend on U" b9b.mote "${F}body sphere radius=1\nrun particles=10\nfloat\n"
printf '%bplasma preset single n=1e6 kT=1000\nbody sphere radius=1\nfloat particles=1e5\n' "$G" > fl.mote
"$MOTE" run fl.mote > out.txt 2> err.txt && awk '/^float: U_f/ { u = $4 } END { d = u / -2503.9 - 1; exit !(d * d < 1e-4) }' out.txt && ok || bad "float (single, 1 keV): $(grep U_f out.txt) $(cat err.txt)"
expect 1 "b10.mote:2:24: error: injector: expected a real number or 'auto', 'debye' or 'thesis' for radius, found 'big'" b10.mote "${G}injector sphere radius=big\n"
expect 1 "b10c.mote:2:24: error: injector: radius must be > 0, found -3" b10c.mote "${G}injector sphere radius=-3\n"
expect 1 "b10b.mote:2:10: error: injector: expected 'sphere' or 'box', found 'cone'" b10b.mote "${G}injector cone\n"
expect 1 "b10c.mote:2:21: error: injector box: radius= is for the sphere" b10c.mote "${G}injector box radius=3\n"
expect 2 "b10d.mote:5:1: error: run: the box injector is for straight paths" b10d.mote "${G}plasma preset single n=1e6 kT=1000\nbody sphere radius=1\ninjector box\nrun potential=-10 particles=10\n"
expect 1 "b11.mote:3:1: error: body sphere: the exact sphere is a body on its own (no other parts)" b11.mote "${G}body sphere radius=1\nbody sphere radius=2\n"
expect 1 "b12.mote:2:6: error: body: expected sphere, icosphere, uvsphere, box, twocubes, load or capacitance, found 'cone'" b12.mote "${G}body cone\n"
expect 1 "b13.mote:3:1: error: evolve: no currents yet: run first" b13.mote "${F}body sphere radius=1\nevolve time=1 file=x.csv\n"
[ ! -e x.csv ] && ok || bad "a failed script wrote x.csv"
expect 2 "b14.mote:5:1: error: run: the injection radius 0.5 m must exceed the body's bounding radius 1 m" b14.mote "${F}plasma preset single n=1e6 kT=1000\nbody sphere radius=1\ninjector sphere radius=0.5\nrun particles=10\n"
# body load (spec 7.1-7.3): an OBJ with two groups, repaired and run; errors name file and line
printf 'o craft\nv -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\ng bus\nf 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\ng panel\nv 1 -0.5 0\nv 4 -0.5 0\nv 4 0.5 0\nv 1 0.5 0\nf 9 10 11\nf 9 11 12\n' > craft.obj
printf '%bplasma preset geo-worst-case\nbody load file=craft.obj units=m\nrun particles=1e5\n' "$G" > ld.mote
"$MOTE" run ld.mote > out.txt 2> err.txt && ok || bad "ld.mote failed: $(cat err.txt)"
grep -q '^body load: 14 triangles read; 0 degenerate and 0 duplicate dropped, [0-9]* vertices welded, 0 turned to face outward; 1 closed and 1 open components' out.txt && ok || bad "body load report: $(grep '^body load' out.txt)"
grep -q '^mode=full species=2 triangles=14 area=30 ' out.txt && ok || bad "the cube (24 m^2) and the two-sided panel (2 x 3 m^2): $(grep triangles=14 out.txt | head -1)"
printf '0 0 0 1 0 0 0 nan 0\n' > nan.txt
expect 2 "b15.mote:2:16: error: body load: nan.txt:1: a coordinate that is not a finite number ('nan')" b15.mote "${G}body load file=nan.txt\n"
expect 1 "b16.mote:2:16: error: body load: 'missing.stl' does not exist and no earlier command writes it" b16.mote "${G}body load file=missing.stl\n"
expect 1 "b17.mote:2:1: error: body load: option file= is required (body load file=FILE [options])" b17.mote "${G}body load\n"
expect 1 "b18.mote:2:32: error: body load: expected 'm', 'cm', 'mm' or 'in' for units, found 'ft'" b18.mote "${G}body load file=craft.obj units=ft\n"
expect 1 "b19.mote:2:33: error: body load: rotate: expected AXIS,DEGREES (x, y or z), found 'w,90'" b19.mote "${G}body load file=craft.obj rotate=w,90\n"
printf 'solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n' > cut.stl
expect 2 "b20.mote:2:16: error: body load: cut.stl: not a mesh file Assimp reads" b20.mote "${G}body load file=cut.stl\n"
# output (spec 8): the tables add up to the run's currents; VTK, JSON and PNG are well formed; the
# same inputs give the same files, on 1 or 2 threads
mkdir -p o1 o2
printf '%bplasma preset geo-worst-case\nbody load file=craft.obj\noutput prefix=o1/craft png_size=400x300\nrun particles=1e5\n' "$G" > out1.mote
printf '%bplasma preset geo-worst-case\nbody load file=craft.obj\noutput prefix=o2/craft png_size=400x300\nthreads 2\nrun particles=1e5\n' "$G" > out2.mote
"$MOTE" run out1.mote > outa.txt 2> err.txt && "$MOTE" run out2.mote > outb.txt 2>> err.txt && ok || bad "output runs failed: $(cat err.txt)"
for f in triangles.csv parts.csv summary.txt summary.json surface.vtk surface.png; do
    [ -s "o1/craft_$f" ] && ok || bad "no o1/craft_$f"
done
net=$(sed -n 's/^run: net I = \([^ ]*\) A.*/\1/p' outa.txt)
awk -F '[,\r]' -v net="$net" 'FNR > 1 { s += $19; n++ } END { d = s - net; exit !(n == 16 && d * d <= 1e-18 * net * net) }' o1/craft_triangles.csv && ok || bad "the triangle rows (16: 12 closed, 2 sheets x 2 sides) do not add up to the net current $net"
awk -F '[,\r]' -v net="$net" 'FNR > 1 { s += $10 } END { d = s - net; exit !(d * d <= 1e-18 * net * net) }' o1/craft_parts.csv && ok || bad "the parts do not add up to the net current"
grep -q '^POINTS 42 double$' o1/craft_surface.vtk && grep -q '^POLYGONS 14 56$' o1/craft_surface.vtk && grep -q '^CELL_DATA 14$' o1/craft_surface.vtk && grep -q '^SCALARS J_net_back double 1$' o1/craft_surface.vtk && ok || bad "VTK structure"
/usr/bin/python3 -c "
import json, sys
d = json.load(open('o1/craft_summary.json'))
net = sum(s['I_A'] for s in d['species'])
sys.exit(not (d['mode'] == 'full' and d['area_m2'] == 30 and abs(net - d['I_net_A']) <= 1e-9 * abs(net) and len(d['species'][0]['components']) == 2
              and d['lost'] == 0 and d['ranks'] == 1 and len(d['warnings']) == 1 and 'kT/(m c^2) = 0.0538 > 0.02' in d['warnings'][0]))
" && ok || bad "summary.json: $(head -c 300 o1/craft_summary.json)"
[ "$(od -An -tu1 -j16 -N8 o1/craft_surface.png | awk '{ print $1*16777216+$2*65536+$3*256+$4, $5*16777216+$6*65536+$7*256+$8 }')" = "400 300" ] && ok || bad "the PNG is not 400 x 300"
cmp -s o1/craft_surface.png o2/craft_surface.png && cmp -s o1/craft_surface.vtk o2/craft_surface.vtk && [ "$(grep -v '^# command' o1/craft_triangles.csv)" = "$(grep -v '^# command' o2/craft_triangles.csv)" ] && ok || bad "1 and 2 threads give different files"
# ply=on: binary little-endian PLY with the vertices, coloured faces and J_net (spec 8.3),
# read back here with Python's struct: the counts, and J_net as the triangle table's (front side)
mkdir -p op
printf '%bplasma preset geo-worst-case\nbody load file=craft.obj\noutput prefix=op/c png=off vtk=off ply=on\nrun particles=1e5\n' "$G" > ply.mote
"$MOTE" run ply.mote > out.txt 2> err.txt && /usr/bin/python3 -c "
import csv, struct, sys
b = open('op/c_surface.ply', 'rb').read()
head, body = b.split(b'end_header\n', 1)
h = head.decode().split('\n')
nv = int([l for l in h if l.startswith('element vertex')][0].split()[2])
nf = int([l for l in h if l.startswith('element face')][0].split()[2])
assert h[1] == 'format binary_little_endian 1.0' and nv == 42 and nf == 14
assert len(body) == 12 * nv + 20 * nf
J = [struct.unpack_from('<f', body, 12 * nv + 20 * k + 16)[0] for k in range(nf)]
idx = [struct.unpack_from('<3i', body, 12 * nv + 20 * k + 1) for k in range(nf)]
assert all(body[12 * nv + 20 * k] == 3 and idx[k] == (3 * k, 3 * k + 1, 3 * k + 2) for k in range(nf))
rows = list(csv.reader(open('op/c_triangles.csv', newline='')))[1:]
front = {int(r[0]): float(r[19]) for r in rows if r[3] == 'front'}
sys.exit(not all(abs(J[k] - front[k]) <= 1e-6 * abs(front[k]) for k in range(nf)))
" && [ ! -e op/c_surface.png ] && ok || bad "PLY: $(cat err.txt)"
# materials (spec 6.7, 6.9): kapton on the panel; its secondaries leave it, the bus stays bare;
# the net current (printed, the parts, the triangles) is the primaries' plus the secondaries'
mkdir -p om
printf '%bplasma preset geo-worst-case\nbody load file=craft.obj\nmaterial assign part=panel material=kapton\noutput prefix=om/c png=off vtk=off\nrun particles=1e5\n' "$G" > mat.mote
"$MOTE" run mat.mote > out.txt 2> err.txt && ok || bad "mat.mote failed: $(cat err.txt)"
awk '/^run: e / { e = $5; for (i = 1; i < NF; i++) if ($i == "out:") see = $(i + 1) } /^run: H\+/ { h = $5 } /^run: net/ { net = $5 }
     END { d = e + h + see - net; exit !(see > 0 && d * d <= 1e-18 * net * net) }' out.txt && ok || bad "run lines: $(grep '^run:' out.txt)"
net=$(sed -n 's/^run: net I = \([^ ]*\) A.*/\1/p' out.txt)
awk -F '[,\r]' -v net="$net" 'FNR > 1 { s += $10; see[$1] = $8; mat[$1] = $2 } END { d = s - net
     exit !(mat["panel"] == "kapton" && mat["bus"] == "bare" && see["bus"] == 0 && see["panel"] > 0 && d * d <= 1e-18 * net * net) }' om/c_parts.csv && ok || bad "parts with kapton: $(cat om/c_parts.csv)"
awk -F '[,\r]' -v net="$net" 'FNR > 1 { s += $19; if ($2 == "bus" && $17 != 0) bus = 1 } END { d = s - net; exit !(bus == 0 && d * d <= 1e-18 * net * net) }' om/c_triangles.csv && ok || bad "the triangle rows with secondaries do not add up to $net"
# photoemission (spec 6.8): the sun on the craft; the photocurrent printed is the triangles'
# and the parts' I_photo, and it is in the net current
mkdir -p os
printf '%bplasma preset geo-worst-case\nbody load file=craft.obj\nmaterial assign part=* material=kapton\nsun direction=0.3,0.2,1\noutput prefix=os/c png=off vtk=off\nrun particles=1e5\n' "$G" > sun.mote
"$MOTE" run sun.mote > out.txt 2> err.txt && ok || bad "sun.mote failed: $(cat err.txt)"
ph=$(sed -n 's/^run: photoelectrons I = +\([^ ]*\) A.*/\1/p' out.txt)
net=$(sed -n 's/^run: net I = \([^ ]*\) A.*/\1/p' out.txt)
awk -F '[,\r]' -v ph="$ph" -v net="$net" 'FNR > 1 { p += $18; s += $19; if ($12 > 0) lit++ } END { d = p - ph; e = s - net
     exit !(ph > 0 && lit > 0 && d * d <= 1e-18 * ph * ph && e * e <= 1e-18 * net * net) }' os/c_triangles.csv && ok || bad "photocurrent $ph: the triangles do not add up"
awk -F '[,\r]' -v ph="$ph" 'FNR > 1 { p += $9 } END { d = p - ph; exit !(d * d <= 1e-18 * ph * ph) }' os/c_parts.csv && ok || bad "photocurrent $ph: the parts do not add up"
expect 1 "s1.mote:2:15: error: sun: direction: expected X,Y,Z toward the sun, not all 0, found '0,0,0'" s1.mote "${G}sun direction=0,0,0\n"
expect 1 "s2.mote:2:15: error: sun: intensity must be >= 0, found -1" s2.mote "${G}sun intensity=-1 direction=1,0,0\n"
expect 1 "s3.mote:2:1: error: sun: give direction=X,Y,Z (or 'sun off')" s3.mote "${G}sun intensity=2\n"
expect 1 "s4.mote:2:1: error: sun: faithful mode has no emission" s4.mote "${F}sun direction=1,0,0\n"
expect 1 "s5.mote:3:1: error: material assign: faithful mode has no emission (the thesis's scope, spec 1.2); use model charging" s5.mote "${F}body sphere radius=1\nmaterial assign part=* material=gold\n"
# validity warnings (spec 3.4): a thin sheath, Larmor radii with bfield, relativistic electrons;
# field none: straight paths whatever U, and no floating potential
printf '%bplasma preset single n=1e12 kT=1\nbody sphere radius=1\nbfield B=1e-3\nrun particles=1000\n' "$G" > vw.mote
"$MOTE" run vw.mote > out.txt 2> err.txt && grep -q '^run: warning: the Debye length 0.005257 m is below 5 R_bound = 5 m: a thin sheath' err.txt &&
    grep -q '^run: warning: e component 1: Larmor radius 0.003372 m in B = 0.001 T is below 10 R_bound = 10 m' err.txt && ok || bad "validity warnings: $(cat err.txt)"
printf '%bplasma preset geo-worst-case\nbody sphere radius=1\nrun particles=1000\n' "$G" > vr.mote
"$MOTE" run vr.mote > out.txt 2> err.txt && [ "$(grep -c warning err.txt)" -eq 1 ] && grep -q '^run: warning: e component 2: kT/(m c^2) = 0.0538 > 0.02' err.txt && ok || bad "relativity warning: $(cat err.txt)"
printf '%bplasma preset geo-worst-case\nbody sphere radius=1\nfield none\nrun particles=1e4\nrun particles=1e4 potential=-5000\n' "$G" > fn.mote
"$MOTE" run fn.mote > out.txt 2> err.txt && [ "$(grep '^run: e ' out.txt | sort -u | wc -l)" -eq 1 ] && ok || bad "field none: $(grep '^run: e' out.txt)"
expect 1 "fn2.mote:5:1: error: float: with field none the currents do not depend on U" fn2.mote "${G}plasma preset geo-worst-case\nbody sphere radius=1\nfield none\nfloat\n"
expect 1 "fn3.mote:2:7: error: field: expected 'none', 'sphere' or 'solved', found 'dipole'" fn3.mote "${G}field dipole\n"
expect 1 "fn4.mote:2:7: error: field sphere: faithful mode has no field" fn4.mote "${F}field sphere\n"
# relerr (spec 5.3): histories added until every species' relative error is below it, or the
# limit; the count is whole blocks of 4096
printf '%bplasma preset thesis-hot\nbody icosphere radius=1 level=3\ninjector sphere radius=20\nrun relerr=0.005\nrun relerr=0.01 max_particles=1000\n' "$G" > re.mote
"$MOTE" run re.mote > out.txt 2> err.txt && awk '/^run: relerr 0.005 reached with/ { n = $6; ok1 = n % 4096 == 0 && n > 1e5 } /^run: [eH]/ { c++; if (c <= 2) { r = $8 / ($5 < 0 ? -$5 : $5); if (r > 0.005) bad = 1 } }
     /^run: relerr 0.01 NOT reached: max_particles with 1000 histories/ { ok2 = 1 } END { exit !(ok1 && ok2 && !bad) }' out.txt && ok || bad "relerr: $(grep '^run:' out.txt)"
expect 1 "re2.mote:4:19: error: run: max_particles is the limit of relerr=; give relerr too" re2.mote "${G}plasma preset thesis-hot\nbody sphere radius=1\nrun max_particles=10\n"
# float replicas (spec 6.5): the spread of the roots over 8 seeds agrees with sigma_U (the sample
# standard deviation of 8 normal values lies within 0.35 ... 1.75 sigma with 99% probability)
printf '%bplasma preset single n=1e6 kT=1000\nbody sphere radius=1\nfloat particles=1e5 replicas=8 U0=-5000\n' "$G" > rp.mote
"$MOTE" run rp.mote > out.txt 2> err.txt && sed -n 's/^float: 8 replicas: .*standard deviation \([0-9.e+-]*\) V, the single run.s sigma_U \([0-9.e+-]*\) V)$/\1 \2/p' out.txt |
    awk '{ m++; r = $1 / $2 } END { exit !(m == 1 && r >= 0.35 && r <= 1.75) }' && ok || bad "replicas: $(grep '^float: 8' out.txt) $(cat err.txt)"
# every replica listed (1 ... 8), and what the command reports is their mean, with the standard
# error of the mean and its 95% interval (Student's t(0.975, 7) = 2.364624), not replica 1's root
# (recomputed from the roots as printed, 6 digits: +-0.005 V on a spread of about 1.2 V moves
# the standard deviation by up to 0.5%, so 1%; the mean to 1e-5)
sed -n 's/^float: replica \([0-9]*\) (seed [0-9]*): U_f = \([0-9.e+-]*\) V +- .*/\1 \2/p' out.txt > reps.txt
sed -n 's/^float: 8 replicas: mean U_f = \([0-9.e+-]*\) V +- \([0-9.e+-]*\) (standard error of the mean; 95% confidence +- \([0-9.e+-]*\), Student.s t 2.365 with 7 degrees of freedom;.*/\1 \2 \3/p' out.txt > mean.txt
sed -n 's/^float: U_f = \([0-9.e+-]*\) V +- \([0-9.e+-]*\) (OML.*/\1 \2/p' out.txt > final.txt
awk 'FILENAME == "reps.txt" { n++; if ($1 != n) bad = 1; u[n] = $2; s += $2; next } FILENAME == "mean.txt" { pm = $1; pe = $2; pc = $3; next } { fm = $1; fe = $2 }
     END { m = s / n; for (k = 1; k <= n; k++) v += (u[k] - m) ^ 2; se = sqrt(v / (n - 1) / n)
           exit !(n == 8 && !bad && (pm - m) ^ 2 <= (1e-5 * m) ^ 2 && (pe - se) ^ 2 <= (0.01 * se) ^ 2 && (pc - 2.364624 * se) ^ 2 <= (0.01 * pc) ^ 2 && fm == pm && fe == pe) }' reps.txt mean.txt final.txt && ok ||
    bad "replicas: the mean and its error: $(cat reps.txt mean.txt final.txt | tr '\n' ' ')"
# body capacitance (spec 4.3): C and the field's radius R_f = C/(4 pi eps0), given, auto (the
# sphere of equal area, held within the rigorous bounds) or solved by boundary elements (an
# icosphere of 1280 panels: 0.9967 of the sphere's, tests/test_bem.c); a given value outside
# the bounds is refused with the bound named: above 4 pi eps0 R_bound, below the sphere of the
# body's volume
printf '%bplasma preset single n=1e6 kT=1000\nbody icosphere radius=1 level=3\nbody capacitance value=1.11e-10\nbody capacitance value=auto\nbody capacitance value=solve\n' "$G" > cap.mote
"$MOTE" run cap.mote > out.txt 2> err.txt && grep -q '^body: capacitance 1.11e-10 F (given), field radius R_f 0.99761' out.txt &&
    grep -q '^body: capacitance 1.10999604e-10 F (auto: 4 pi eps0 R_eq, within the bounds), field radius R_f 0.99761469' out.txt &&
    grep -q '^body capacitance: solved by boundary elements on 1280 panels: C = 1.10895.* F = 4 pi eps0 x 0.99668' out.txt &&
    grep -q '^body: capacitance 1.10895.* F (solved), field radius R_f 0.99668' out.txt && ok || bad "capacitance: $(grep '^body' out.txt) $(cat err.txt)"
expect 2 "cpb1.mote:3:24: error: body capacitance: C = 2.2253e-10 F is above the body's rigorous bound 4 pi eps0 R_bound = 1.11265e-10 F (the ball of R_bound = 1 m about its centre holds it" cpb1.mote "${G}body icosphere radius=1 level=3\nbody capacitance value=2.2253e-10\n"
expect 2 "cpb2.mote:3:24: error: body capacitance: C = 1e-20 F is below the body's rigorous bound 1.10945e-10 F (the sphere of its volume, which has the least capacitance of all bodies of that volume)" cpb2.mote "${G}body icosphere radius=1 level=3\nbody capacitance value=1e-20\n"
# field solved (issue 55): the body's own field, solved at the first run and kept until the body
# changes (a triangle added: solved again, 321 panels), its capacitance the body's from then on;
# theta= only with solved; none in faithful mode; too many panels refused before any work
fsn=1000; [ -n "${MOTE_SANITIZED:-}" ] && fsn=250 # (the counts below hold at any size)
printf '%bplasma preset single n=1e6 kT=1000\nbody icosphere radius=1 level=2\nfield solved\nrun particles=%s potential=1000\nrun particles=%s potential=-1000\nbody load file=far.obj\nrun particles=%s potential=1000\n' "$G" $fsn $fsn $fsn > fs.mote
printf 'v 3 0 0\nv 4 0 0\nv 3 1 0\nf 1 2 3\n' > far.obj
"$MOTE" run fs.mote > out.txt 2> err.txt && [ "$(grep -c '^field solved: ' out.txt)" -eq 2 ] &&
    grep -q '^field solved: 320 panels, C = .* F (R_f 0.98' out.txt && grep -q '^field solved: 321 panels, C = ' out.txt &&
    [ "$(grep -c '^run: curved paths: .* 0 lost' out.txt)" -eq 3 ] && ok || bad "field solved: $(cat out.txt err.txt)"
# with dielectric parts the solve takes the frame and each part as conductors (issue 55): the
# capacitance matrix printed, reciprocal, the two hemispheres' alike (mirror images), its sum
# the whole body's C; evolve's circuit takes it (# Cv_F). Under one coat (the body all one
# dielectric part, so no current reaches the conductor beneath) the conductor stays neutral:
# V_p - U = 0 (the lumped circuit of the sphere's field gives (C / C_p) U).
printf '%bseed 3\nplasma preset single n=1e6 kT=1000\nbody uvsphere radius=1 nlon=24 nlat=12 parts=hemispheres\nfield solved\ndielectric part=south thickness=1e-3 eps_r=2\nevolve time=1e-4 dt_out=5e-5 file=fsd.txt particles=200\n' "$G" > fsd.mote
"$MOTE" run fsd.mote > out.txt 2> err.txt &&
    awk '/^field solved: [0-9]+ panels, C = / { c = $7 } /^field solved: +frame / { a = $4; b = $5 } /^field solved: +south / { d = $4; e = $5 }
         END { exit !(c > 1e-10 && (b / d - 1) ^ 2 < 1e-12 && (a / e - 1) ^ 2 < 1e-12 && b < 0 && ((a + b + d + e) / c - 1) ^ 2 < 1e-12) }' out.txt &&
    grep -q '^# Cv_F = ' fsd.txt && ok || bad "the capacitance matrix of frame and south: $(grep '^field solved' out.txt) $(cat err.txt)"
printf '%bseed 3\nplasma preset single n=1e6 kT=1000\nbody icosphere radius=1 level=2\nfield solved\ndielectric part=icosphere thickness=0.5 eps_r=1\nevolve time=1e-4 dt_out=5e-5 file=fsc.txt particles=200\n' "$G" > fsc.mote
"$MOTE" run fsc.mote > out.txt 2> err.txt &&
    awk '!/^#/ && NF > 1 { n++; if (($6 - $3) ^ 2 > 1e-18 * $3 * $3) bad = 1; u = $3 } END { exit !(n == 3 && !bad && u < -5) }' fsc.txt &&
    ok || bad "one coat in the solved field: V_p - U not 0: $(cat fsc.txt err.txt)"
# Barrier-limited charging (issue 55): the split sphere of examples/charging-differential.mote
# (sunlit aluminium north the frame, shaded 127 um kapton south) in geo-worst-case, in the
# solved field. At first the frame's photoelectrons hold both a few volts positive; the kapton
# then charges negative against the frame, and its field closes a barrier over the frame that
# turns the frame's photoelectrons back, so the frame follows it down. The frame then sits where
# the barrier opens at the sunlit pole: for a sphere whose halves are at V_n and V_s the radial
# field at the pole vanishes at V_n / V_s = 3 - 2 sqrt(2) = 0.1716 (the Poisson integral on the
# axis; Besse and Rubin's monopole-dipole model, J. Geophys. Res. 85 (1980) 2324, gives 1/3).
# The photocurrent balance needs the barrier open over part of the sunlit side, so V_n / V_s
# lies just past the threshold: the slow suite evolves two minutes (V_s about -650 V at one,
# -1300 V at two) and asks for 0.95 to 1.25 times it at both (the coarse mesh's error at the
# pole a few per cent; measured 0.167 and 0.181). The regular suite takes two seconds: both
# start positive, the kapton falls below the frame (under the sanitizers 25 histories a run and a
# coarser sphere, 12 x 6: the photoelectrons, at least two a sunlit panel, take the time).
bs="nlon=16 nlat=8"
if [ -n "${MOTE_SLOW:-}" ]; then bt=120; bd=60; bn=300; elif [ -n "${MOTE_SANITIZED:-}" ]; then bt=2; bd=2; bn=25; bs="nlon=12 nlat=6"; else bt=2; bd=2; bn=50; fi
printf '%bseed 3\nplasma preset geo-worst-case\nbody uvsphere radius=1 %s parts=hemispheres\nmaterial assign part=north material=aluminium\nmaterial assign part=south material=kapton\nsun direction=0,0,1\nfield solved\ndielectric part=south thickness=127e-6\nevolve time=%s dt=%s file=bar.txt particles=%s\n' "$G" "$bs" "$bt" "$bd" "$bn" > bar.mote
"$MOTE" run bar.mote > out.txt 2> err.txt &&
    grep -q '^evolve: the conductors at their own potentials in the solved field' out.txt &&
    awk -v slow="${MOTE_SLOW:-}" '!/^#/ && NF > 1 { n++; if (n == 1) { u0 = $3; v0 = $6 } else if ($6 > -300 || $3 / $6 < 0.95 * t || $3 / $6 > 1.25 * t) far++; u = $3; v = $6 }
         BEGIN { t = 3 - 2 * sqrt(2) } END { if (slow) exit !(n == 3 && !far)
               exit !(n == 2 && u0 > 0 && v0 == u0 && v < u - 10) }' bar.txt &&
    ok || bad "barrier-limited charging of the split sphere: $(grep -v '^#' bar.txt) $(cat err.txt)"
# the steady state (float) of the same sphere: the frame settles at the barrier's threshold,
# U / V_s = 3 - 2 sqrt 2 within 3 sigma (from the printed errors of U and V_s - U) and 5 % for
# the coarse mesh (measured 0.1733 +- 0.016 with 600 histories, 2.3 minutes: the slow suite)
if [ -n "${MOTE_SLOW:-}" ]; then
    sed 's/^evolve .*/float particles=600/; s/^seed 3$/seed 3\nthreads 2/' bar.mote > bars.mote
    "$MOTE" run --quiet bars.mote > bars.txt 2> err.txt &&
        u=$(sed -n 's/^float: the steady state of .*: U = \([^ ]*\) V +- \([^;]*\);.*/\1 \2/p' bars.txt) &&
        dv=$(sed -n 's/^float: dielectric south: V_p = [^ ]* V, V_p - U = \([^ ]*\) V +- \([^;]*\);.*/\1 \2/p' bars.txt) &&
        echo "$u $dv" | awk '{ t = 3 - 2 * sqrt(2); U = $1; V = $1 + $3; r = U / V; sV = sqrt($2 * $2 + $4 * $4)
            sr = sqrt(($2 / V) ^ 2 + (U * sV / V / V) ^ 2); exit !(NF == 4 && V < -1e4 && (r - t) ^ 2 <= (3 * sr + 0.05 * t) ^ 2) }' &&
        ok || bad "the barrier's steady state: $(grep '^float' bars.txt) $(cat err.txt)"
fi
# the barrier run on two threads gives the same time series as on one (the runs' Philox streams
# and the float's order do not depend on the threads)
sed 's/^seed 3$/seed 3\nthreads 2/; s/file=bar.txt/file=bar2.txt/' bar.mote > bar2.mote
"$MOTE" run bar2.mote > /dev/null 2> err.txt && [ "$(grep -v '^# command' bar.txt)" = "$(grep -v '^# command' bar2.txt)" ] &&
    ok || bad "the barrier run: 1 and 2 threads differ: $(diff bar.txt bar2.txt | head -n 6) $(cat err.txt)"
# `field sphere` after a solved run: evolve is the sphere field's circuit again (the tree kept
# for a later `field solved` is not used)
printf '%bseed 3\nplasma preset single n=1e6 kT=1000\nbody icosphere radius=1 level=2\ndielectric part=icosphere thickness=0.5 eps_r=1\nfield solved\nrun particles=200 potential=-100\nfield sphere\nevolve time=1e-4 dt=5e-5 file=fss.txt particles=200\n' "$G" > fss.mote
"$MOTE" run fss.mote > out.txt 2> err.txt && ! grep -q 'conductors at their own potentials' out.txt &&
    ! grep -q '^# Cv_F' fss.txt && grep -q '^# mode = full with 1 dielectric part (spec 6.10' fss.txt &&
    ok || bad "field sphere after field solved: evolve still in the solved field: $(grep evolve out.txt) $(cat err.txt)"
expect 1 "fs1.mote:2:20: error: field sphere: theta= is the solved field's (field solved theta=)" fs1.mote "${G}field sphere theta=0.3\n"
expect 1 "fs2.mote:2:20: error: field: theta must be in (0, 1), found 1" fs2.mote "${G}field solved theta=1\n"
expect 1 "fs3.mote:2:7: error: field solved: faithful mode has no field (the thesis's scope, spec 1.2); use model charging" fs3.mote "model charging faithful\nfield solved\n"
expect 2 "fs4.mote:5:1: error: run: the solved field (field solved): 327680 panels are more than the field's solve takes (at most 16384" fs4.mote "${G}plasma preset single n=1e6 kT=1000\nbody icosphere radius=1 level=7\nfield solved\nrun particles=1000 potential=1\n"
# a sheet (no volume): the disk inscribed in its largest triangle bounds it below
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > tri.obj
expect 2 "cpb3.mote:3:24: error: body capacitance: C = 1e-20 F is below the body's rigorous bound 2.07467e-11 F (8 eps0 r_in of the disk inscribed in its largest triangle, which it holds)" cpb3.mote "${G}body load file=tri.obj\nbody capacitance value=1e-20\n"
# a dielectric layer thicker than the body; an injector beyond the range that traces
expect 2 "dth.mote:3:34: error: dielectric: thickness 2 m is not smaller than the body (R_bound 1 m)" dth.mote "${G}body sphere radius=1\ndielectric part=sphere thickness=2 eps_r=2\n"
expect 2 "inj.mote:5:1: error: run: the injection radius 1e+13 m is beyond 1e+12 m, where the rays' coordinates no longer trace" inj.mote "${G}plasma preset single n=1e6 kT=1000\nbody icosphere radius=1 level=1\ninjector sphere radius=1e13\nrun particles=1000\n"
expect 2 "injb.mote:5:1: error: run: the box injector's margin 1e+300 m is beyond 1e+12 m" injb.mote "${G}plasma preset single n=1e6 kT=1000\nbody icosphere radius=1 level=1\ninjector box margin_m=1e300\nrun particles=1000\n"
expect 1 "cp1.mote:3:24: error: body capacitance: value must be > 0, found -1" cp1.mote "${G}body icosphere radius=1\nbody capacitance value=-1\n"
expect 1 "cp2.mote:2:1: error: body capacitance: give the body first" cp2.mote "${G}body capacitance value=auto\n"
expect 1 "cp3.mote:3:1: error: body capacitance: the exact sphere's capacitance is 4 pi eps0 a (its field is exact)" cp3.mote "${G}body sphere radius=1\nbody capacitance value=1e-10\n"
# test hitprob (spec 10 M3, the original's -t): a unit cube from R = 2 m, 6/(16 pi) = 0.119366,
# and in a box of margin 0.5 m, 6/24
printf '%bbody box size=1,1,1\ninjector sphere radius=2\ntest hitprob particles=1e6\ninjector box margin_m=0.5\ntest hitprob\n' "$G" > hp.mote
"$MOTE" run hp.mote > out.txt 2> err.txt && awk '/^test hitprob/ { n++; s = $NF == "sigma" ? $(NF - 1) : 99; sub("sigma", "", s); if (s * s > 9) bad = 1; w[n] = $(NF - 7) }
     END { exit !(n == 2 && !bad && w[1] == "0.119366" && w[2] == "0.25") }' out.txt && ok || bad "test hitprob: $(grep '^test' out.txt) $(cat err.txt)"
expect 1 "hp2.mote:2:6: error: test: expected 'hitprob', found 'speed'" hp2.mote "${G}test speed\n"
expect 1 "m7.mote:2:32: error: material define: expected 'universal', 'sternglass' or 'range' for see_law, found 'linear'" m7.mote "${G}material define name=x see_law=linear\n"
expect 1 "m8.mote:2:34: error: material define: expected 'none' or 'sec' for see_angle, found 'cos'" m8.mote "${G}material define name=x see_angle=cos\n"
expect 1 "m9.mote:2:1: error: material define: see_angle=sec is the universal law's angular form, not Sternglass's" m9.mote "${G}material define name=x see_law=sternglass see_angle=sec\n"
# NASCAP's range law (issue 55): te2k switched to it floats far more negative in the worst-case
# GEO plasma than with the universal curve (its yield at 27.5 keV 0.115 against 0.687:
# docs/charging.md: -15.7 kV against -5.6 kV; here 1e4 histories); rows without a range, a range
# with no peak and see_angle=sec refused
printf '%bplasma preset geo-worst-case\nbody sphere radius=1\nmaterial assign part=sphere material=te2k\nfloat particles=1e4\nmaterial define name=te2k see_law=range\nmaterial assign part=sphere material=te2k\nfloat particles=1e4\n' "$G" > rl.mote
"$MOTE" run rl.mote > out.txt 2> err.txt && sed -n 's/^float: U_f = \([0-9.e+-]*\) V.*/\1/p' out.txt > uf.txt &&
    awk 'NR == 1 { u = $1 } NR == 2 { r = $1 } END { exit !(NR == 2 && u < -4000 && u > -8000 && r < 2 * u) }' uf.txt && ok || bad "range law: floats $(cat uf.txt) $(cat err.txt)"
expect 1 "rl1.mote:2:1: error: material define: material gr2k: the range law needs its range see_r1=, see_n1=, see_r2=, see_n2=" rl1.mote "${G}material define name=gr2k see_law=range\n"
expect 1 "rl2.mote:2:1: error: material define: material x: its range law gives no peak of the yield at see_emax = 0.3 keV" rl2.mote "${G}material define name=x see_dmax=2 see_emax=0.3 see_law=range see_r1=100 see_n1=0.8\n"
expect 1 "rl3.mote:2:1: error: material define: see_angle=sec is the universal law's angular form, not the range law's (its angle is its own)" rl3.mote "${G}material define name=te2k see_law=range see_angle=sec\n"
# several roots (spec 6.5): a cold and a hot population on teflon (yield above 1 for the cold
# electrons, below for the hot) give three: stable near +2 V (from U0 = 0), unstable near
# -0.8 kV, stable near -5.2 kV, which float from U0 = -10 kV reaches (spec 6.7's emission:
# backscatter off; with it the hot electrons' emission keeps only the root near +3 V)
printf '%bbackscatter off\nspecies clear\nspecies name=e charge=-1 mass=electron\nmaxwellian species=e density=1e6 temperature=500\nmaxwellian species=e density=2e5 temperature=20000\nspecies name=H+ charge=1 mass=proton\nmaxwellian species=H+ density=1e6 temperature=500\nmaxwellian species=H+ density=2e5 temperature=20000\nbody sphere radius=1\nmaterial assign part=* material=teflon\nfloat particles=1e5 roots=all\nfloat particles=1e5 U0=-10000\n' "$G" > rt.mote
"$MOTE" run rt.mote > out.txt 2> err.txt && awk '/^float: a root/ { n++; st[n] = $(NF - 3); u[n] = $(NF - 5) } /^float: U_f/ { f++; uf[f] = $4 }
     END { exit !(n == 3 && st[1] == "stable" && st[2] == "unstable" && st[3] == "stable" && u[1] < -4000 && u[1] > -6400 && u[2] < -400 && u[2] > -800 &&
                  uf[1] > 0 && uf[1] < 50 && uf[1] == u[3] && uf[2] < -4900 && uf[2] > -5400) }' out.txt && ok || bad "three roots: $(grep '^float: [aU]' out.txt) $(cat err.txt)"
expect 1 "rt2.mote:4:13: error: float: expected 'one' or 'all' for roots, found 'some'" rt2.mote "${G}plasma preset thesis-hot\nbody sphere radius=1\nfloat roots=some\n"
expect 1 "m1.mote:3:33: error: material assign: no material 'steel'" m1.mote "${G}body sphere radius=1\nmaterial assign part=* material=steel\n"
expect 1 "m2b.mote:2:10: error: material: expected define or assign, found 'remove'" m2b.mote "${G}material remove part=*\n"
expect 1 "m2.mote:3:1: error: material assign: option part= is required (material assign part=NAME|* material=NAME)" m2.mote "${G}body sphere radius=1\nmaterial assign material=gold\n"
expect 1 "m3.mote:2:1: error: material assign: give the body first (the parts are its parts)" m3.mote "${G}material assign part=* material=gold\n"
expect 2 "m4.mote:4:22: error: material assign: the body has no part 'pannel'" m4.mote "${G}plasma preset geo-worst-case\nbody load file=craft.obj\nmaterial assign part=pannel material=kapton\n"
expect 1 "m5.mote:2:10: error: material: expected define or assign, found 'set'" m5.mote "${G}material set\n"
expect 1 "m6.mote:2:33: error: material define: see_dmax must be >= 0, found -1" m6.mote "${G}material define name=x see_dmax=-1\n"
# a defined material, then assigned: a yield curve of the user's own
printf '%bplasma preset geo-worst-case\nbody sphere radius=1\nmaterial define name=mine see_dmax=3 see_emax=0.3\nmaterial assign part=sphere material=mine\nrun particles=1e5\n' "$G" > md.mote
"$MOTE" run md.mote > out.txt 2> err.txt && grep -q '^run: e .*secondaries it knocks out: +' out.txt && ok || bad "a defined material: $(grep '^run: e' out.txt) $(cat err.txt)"
# backscatter (issue 37): named where it is in the emission, on the terminal, in the summaries
for bs in on off; do
    printf '%bplasma preset single n=1e6 kT=10000\nbody sphere radius=1\nmaterial assign part=* material=aluminium\nbackscatter %s\noutput prefix=bs_%s\nrun particles=2e4\n' "$G" "$bs" "$bs" > bs_$bs.mote
    "$MOTE" run bs_$bs.mote > bs_$bs.txt 2> err.txt || bad "backscatter $bs: $(cat err.txt)"
done
grep -q '^run: e .*; secondaries and backscattered electrons it knocks out: +' bs_on.txt && grep -q '^run: e .*; secondaries it knocks out: +' bs_off.txt &&
    grep -q 'secondary and backscattered electrons it knocks out: +' bs_on_summary.txt && grep -q 'secondary electrons it knocks out: +' bs_off_summary.txt &&
    grep -q '"backscatter":true' bs_on_summary.json && grep -q '"backscatter":false' bs_off_summary.json && ok || bad "backscatter not named: $(grep '^run: e' bs_on.txt bs_off.txt)"
on=$(sed -n 's/.*knocks out: +\([^ ]*\) A.*/\1/p' bs_on.txt) off=$(sed -n 's/.*knocks out: +\([^ ]*\) A.*/\1/p' bs_off.txt)
awk -v a="$on" -v b="$off" 'BEGIN { exit !(a > b * 1.2) }' && ok || bad "backscatter added nothing: on $on, off $off"
# the VTK files read back by VTK itself (python3-vtk9, ParaView's library): ASCII and binary
# give the same mesh and arrays
mkdir -p ov
printf '%bplasma preset geo-worst-case\nbody load file=craft.obj\nmaterial assign part=panel material=kapton\nsun direction=0,0,1\noutput prefix=ov/a png=off\nrun particles=1e4\noutput prefix=ov/b png=off vtk_format=binary\nrun particles=1e4\n' "$G" > vtk.mote
"$MOTE" run vtk.mote > out.txt 2> err.txt && /usr/bin/python3 -c "
import sys
from vtkmodules.vtkIOLegacy import vtkPolyDataReader
def load(path):
    r = vtkPolyDataReader()
    r.SetFileName(path)
    r.ReadAllScalarsOn()
    r.Update()
    d = r.GetOutput()
    cd = d.GetCellData()
    arr = {cd.GetArrayName(k): [cd.GetArray(k).GetValue(i) for i in range(d.GetNumberOfCells())] for k in range(cd.GetNumberOfArrays())}
    pts = [d.GetPoint(i) for i in range(d.GetNumberOfPoints())]
    return d.GetNumberOfPoints(), d.GetNumberOfCells(), arr, pts
na, ca, A, pa = load('ov/a_surface.vtk')
nb, cb, B, pb = load('ov/b_surface.vtk')
want = {'J_net', 'J_net_front', 'J_net_back', 'sigma_J', 'relerr', 'J_e', 'J_H+', 'J_see', 'J_photo', 'sunlit_fraction', 'hits_total', 'part_id'}
ok = na == nb == 42 and ca == cb == 14 and set(A) == want and set(B) == want
ok = ok and all(abs(x - y) <= 1e-9 * max(abs(x), abs(y), 1e-30) for k in want for x, y in zip(A[k], B[k]))
ok = ok and all(abs(p - q) <= 1e-9 for u, v in zip(pa, pb) for p, q in zip(u, v))
ok = ok and sum(A['J_photo']) > 0 and max(A['sunlit_fraction']) == 1 and sorted(set(A['part_id'])) == [0, 1]
sys.exit(not ok)
" && ok || bad "VTK read back: $(cat err.txt)"
expect 1 "b21b.mote:2:28: error: output: expected 'ascii' or 'binary' for vtk_format, found 'xml'" b21b.mote "${G}output prefix=x vtk_format=xml\n"
# png_quantity (spec 8.4): another quantity in the picture; a species of the plasma or an error
mkdir -p opq
printf '%bplasma preset geo-worst-case\nbody load file=craft.obj\nsun direction=0.3,0.2,1\nmaterial assign part=* material=kapton\noutput prefix=opq/a png_quantity=J_net png_size=200x150 vtk=off\nrun particles=1e4\noutput prefix=opq/b png_quantity=J_H+ png_size=200x150 vtk=off\nrun particles=1e4\noutput prefix=opq/c png_quantity=sunlit_fraction png_size=200x150 vtk=off\nrun particles=1e4\n' "$G" > pq.mote
"$MOTE" run pq.mote > out.txt 2> err.txt && [ -s opq/a_surface.png ] && [ -s opq/b_surface.png ] && [ -s opq/c_surface.png ] &&
    ! cmp -s opq/a_surface.png opq/b_surface.png && ! cmp -s opq/b_surface.png opq/c_surface.png && ok || bad "png_quantity: $(cat err.txt)"
expect 1 "b21c.mote:3:30: error: output: png_quantity must be J_net, J_<species> (of the plasma so far), J_see, J_photo, sigma_J, relerr, sunlit_fraction or hits, found 'J_O+'" b21c.mote "${G}plasma preset thesis-hot\noutput prefix=x png_quantity=J_O+\n"
expect 1 "b21.mote:2:15: error: output: the directory that would hold prefix 'nodir/sub/x' does not exist" b21.mote "${G}output prefix=nodir/sub/x\n"
# OBJ object names with blanks stay apart (issue 52: `o panel left` and `o panel right` were
# cut and merged into one part `panel`): the blanks become '_'
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 2 0 0\nv 2 1 0\nv 2 0 1\nv 3 0 0\no panel left\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\no  panel right \nf 5 6 8\nf 5 8 7\nf 5 7 6\nf 6 7 8\n' > parts.obj
printf '%bbody load file=parts.obj\nmaterial assign part=panel_left material=aluminium\nmaterial assign part=panel_right material=gold\n' "$G" > obj1.mote
"$MOTE" run obj1.mote > out.txt 2> err.txt && ok || bad "OBJ names with blanks: $(cat err.txt)"
expect 2 "obj2.mote:3:22: error: material assign: the body has no part 'panel'" obj2.mote "${G}body load file=parts.obj\nmaterial assign part=panel material=aluminium\n"
# the prefix's folder is made, as every prefix= and dir= (issue 52)
printf '%bplasma preset single n=1e6 kT=10\nbody sphere radius=1\noutput prefix=made/x png=off vtk=off\nrun particles=1000\n' "$G" > b22.mote
"$MOTE" run b22.mote > out.txt 2> err.txt && [ -s made/x_summary.txt ] && ok || bad "output prefix=made/x: $(cat err.txt)"
expect 1 "b22.mote:2:26: error: output: png_view must be iso, +x, -x, +y, -y, +z, -z or X,Y,Z, or up to 8 of them as V1/V2/..., found 'top'" b22.mote "${G}output prefix=x png_view=top\n"
expect 1 "b22b.mote:2:26: error: output: png_view must be iso, +x, -x, +y, -y, +z, -z or X,Y,Z, or up to 8 of them as V1/V2/..., found '0,0,0'" b22b.mote "${G}output prefix=x png_view=iso/0,0,0\n"
# several views: one picture each, named by the view (spec 8.4)
mkdir -p mv
printf '%bplasma preset geo-worst-case\nbody load file=craft.obj\noutput prefix=mv/c png_view=iso/+z/-x/1,-1,0.5 png_size=200x150 vtk=off\nrun particles=1e4\n' "$G" > mv.mote
"$MOTE" run mv.mote > out.txt 2> err.txt && [ "$(ls mv/*.png | tr '\n' ' ')" = "mv/c_surface_iso.png mv/c_surface_mx.png mv/c_surface_pz.png mv/c_surface_view4.png " ] &&
    ! cmp -s mv/c_surface_iso.png mv/c_surface_pz.png && ok || bad "several views: $(ls mv) $(cat err.txt)"
expect 1 "b23.mote:2:26: error: output: png_size must be WxH, 64 to 8192 pixels each, found '10x10'" b23.mote "${G}output prefix=x png_size=10x10\n"
# drift (spec 5.4, M5): a 1 m sphere in a plasma flowing at u = sigma collects q n pi a^2 <|v|>,
# <|v|> = 1.8493 sigma; the electron sigma at 1 keV is sqrt(kT/m)
printf '%bplasma preset single n=1e6 kT=1000 drift=13262051.164,0,0\nbody sphere radius=1\ninjector sphere radius=1.5\nrun particles=1e6\n' "$G" > dr.mote
"$MOTE" run dr.mote > out.txt 2> err.txt && awk '/^run: e / { I = $5; s = $8 } END { sig = sqrt(1000 * 1.602176634e-19 / 9.1093837015e-31); want = -1.602176634e-19 * 1e6 * 3.14159265358979 * 1.8493 * sig; d = I - want; exit !(d * d <= 9 * s * s + (1e-4 * want) ^ 2) }' out.txt && ok || bad "drift: $(grep '^run: e' out.txt) $(cat err.txt)"
expect 1 "b24.mote:2:32: error: plasma: expected X,Y,Z (3 finite numbers separated by commas) for drift, found 'fast'" b24.mote "${G}plasma preset thesis-hot drift=fast\n"
expect 1 "b24b.mote:2:32: error: plasma: expected X,Y,Z (3 finite numbers separated by commas) for drift, found '1,2'" b24b.mote "${G}plasma preset thesis-hot drift=1,2\n"
expect 1 "b24c.mote:2:32: error: plasma: expected X,Y,Z (3 finite numbers separated by commas) for drift, found '1,2,3,'" b24c.mote "${G}plasma preset thesis-hot drift=1,2,3,\n"
expect 1 "b24d.mote:2:32: error: plasma: expected X,Y,Z (3 finite numbers separated by commas) for drift, found '1,,3'" b24d.mote "${G}plasma preset thesis-hot drift=1,,3\n"
expect 0 "" b24e.mote "${G}plasma preset thesis-hot drift=-4e5,0,+1.5\n" check
# species and maxwellian (spec 3.1, 7.4): the thesis-hot preset written out gives the same run
printf '%bspecies clear\nspecies name=e charge=-1 mass=electron\nmaxwellian species=e density=1.2e6 temperature=27500\nspecies name=H+ charge=1 mass=proton\nmaxwellian species=H+ density=1.3e6 temperature=28000\nbody sphere radius=1\nrun particles=1e5\n' "$G" > sp1.mote
printf '%bplasma preset thesis-hot\nbody sphere radius=1\nrun particles=1e5\n' "$G" > sp2.mote
"$MOTE" run sp1.mote > o1.txt 2> err.txt && "$MOTE" run sp2.mote > o2.txt 2>> err.txt && [ -n "$(grep '^run:' o1.txt)" ] && [ "$(grep '^run:' o1.txt | sed 's/ [0-9.e+]* traces.s//')" = "$(grep '^run:' o2.txt | sed 's/ [0-9.e+]* traces.s//')" ] && ok || bad "species/maxwellian differ from the preset: $(grep '^run: net' o1.txt) / $(grep '^run: net' o2.txt) $(cat err.txt)"
printf '%bspecies name=O+ charge=1 amu=16\nmaxwellian species=O+ density=1e6 temperature=1000\nbody sphere radius=1\nrun particles=1e5\n' "$G" > sp3.mote
"$MOTE" run sp3.mote > o3.txt 2> err.txt && awk '/^run: O\+/ { I = $5; s = $8 } END { want = 1.602176634e-19 * 1e6 * 4 * 3.14159265358979 * sqrt(1000 * 1.602176634e-19 / (2 * 3.14159265358979 * 16 * 1.66053906660e-27)); d = I - want; exit !(d * d <= 9 * s * s) }' o3.txt && ok || bad "O+ current: $(grep '^run: O' o3.txt) $(cat err.txt)"
expect 1 "sp4b.mote:3:46: error: maxwellian: temperature must be > 0" sp4b.mote "${G}species name=X charge=1 mass=proton\nmaxwellian species=X density=1e6 temperature=-5\n"
expect 1 "sp4c.mote:5:1: error: run: there is no plasma yet" sp4c.mote "${G}plasma preset thesis-hot\nspecies clear\nbody sphere radius=1\nrun\n"
expect 1 "sp4.mote:2:20: error: maxwellian: no species 'Xe'" sp4.mote "${G}maxwellian species=Xe density=1 temperature=1\n"
expect 1 "sp5.mote:2:1: error: species: give name=, charge= and mass=" sp5.mote "${G}species name=Xe charge=1\n"
expect 1 "sp6.mote:2:23: error: species: charge must be a whole number of elementary charges, not 0" sp6.mote "${G}species name=n charge=0 mass=proton\n"
expect 1 "sp7.mote:2:30: error: species: expected a real number or 'electron' or 'proton' for mass, found 'heavy'" sp7.mote "${G}species name=X charge=1 mass=heavy\n"
expect 1 "sp8.mote:4:1: error: run: species 'X' has no component" sp8.mote "${G}species name=X charge=1 mass=proton\nbody sphere radius=1\nrun\n"
expect 1 "sp10.mote:2:1: error: species clear: takes no options ('clear' is no species name)" sp10.mote "${G}species clear charge=1 amu=2\n"
expect 1 "sp11.mote:2:1: error: species: give name=, charge= and mass= or amu=" sp11.mote "${G}species name=X charge=1 mass=proton amu=1\n"
expect 0 "" sp12.mote "${G}species O+ charge=1 amu=16\nspecies name=e2 charge=-1 mass=9.1093837e-31 drift=1,0,0\nsun on direction=0,0,1\nsun off\n" check
expect 1 "sun5.mote:2:5: error: sun: expected 'on' or 'off' for light, found 'dim'" sun5.mote "${G}sun dim\n"
expect 1 "sun6.mote:2:1: error: sun off: takes no options" sun6.mote "${G}sun off direction=1,0,0\n"
expect 1 "sp9.mote:3:1: error: species: 'e' exists already" sp9.mote "${G}plasma preset thesis-hot\nspecies name=e charge=-1 mass=electron\n"
# evolve in full mode writes P_timeseries.csv after `output prefix=P` (spec 8.1): the species',
# secondary and photo currents add up to the net current (their interpolations agree within 1%
# of the largest current), Nreal grows, Q = C U
mkdir -p ots
printf '%bplasma preset geo-worst-case\nbody sphere radius=1\nmaterial assign part=* material=aluminium\nsun direction=1,0,0 intensity=0.05\noutput prefix=ots/s\nevolve time=0.5 dt_out=0.1 particles=1e5\n' "$G" > tsf.mote
"$MOTE" run tsf.mote > out.txt 2> err.txt && [ "$(head -n 1 ots/s_timeseries.csv | tr -d '\r')" = "t_s,Q_C,U_V,sigma_U_V,I_net_A,I_e_A,Nreal_e,I_H+_A,Nreal_H+,I_see_A,I_photo_A" ] &&
    awk -F '[,\r]' 'FNR > 1 { n++; d = $6 + $8 + $10 + $11 - $5; m = ($6 < 0 ? -$6 : $6); if (d * d > (0.01 * m) ^ 2 || $7 < n7 || $9 < n9 || $11 <= 0) bad = 1; n7 = $7; n9 = $9
         q = $2 - 1.112650055e-10 * $3; if (q * q > 1e-18 * $2 * $2) bad = 1 } END { exit !(n == 6 && !bad) }' ots/s_timeseries.csv && ok || bad "full-mode time series: $(tail -2 ots/s_timeseries.csv) $(cat err.txt)"
# float after run under the same output prefix overwrites run's files: the check says so, at
# float; so does evolve writing P_timeseries.csv after an earlier evolve
mkdir -p ov
expect 0 "ov.mote:6:1: warning: float: 'ov/s_summary.txt' is written more than once in this script" ov.mote "${G}plasma preset geo-worst-case\nbody sphere radius=1\noutput prefix=ov/s\nrun particles=1e4\nfloat particles=1e4\n" check
expect 0 "ov2.mote:6:1: warning: evolve: 'ov/t_timeseries.csv' is written more than once" ov2.mote "${G}plasma preset geo-worst-case\nbody sphere radius=1\noutput prefix=ov/t\nevolve time=1e-3 particles=1e4\nevolve time=1e-3 particles=1e4\n" check
expect 0 "" ov3.mote "${G}plasma preset geo-worst-case\nbody sphere radius=1\noutput prefix=ov/a\nrun particles=1e4\noutput prefix=ov/b\nfloat particles=1e4\n" check
# float writes the files at U_f, the summary with the root, its error and the OML estimate
mkdir -p of
printf '%bplasma preset geo-worst-case\nbody sphere radius=1\noutput prefix=of/s\nfloat particles=1e5\n' "$G" > fo.mote
"$MOTE" run fo.mote > out.txt 2> err.txt && /usr/bin/python3 -c "
import json, sys
d = json.load(open('of/s_summary.json'))
sys.exit(not (abs(d['U_f_V'] / -38060 - 1) < 0.02 and d['sigma_U_V'] > 0 and abs(d['U_f_OML_V'] / -38061.7 - 1) < 1e-4 and d['potential_V'] == d['U_f_V']))
" && grep -q '^floating potential: U_f = -3' of/s_summary.txt && ok || bad "float summary: $(head -c 300 of/s_summary.json) $(cat err.txt)"
# issue 33: meshes that stopped or misled mote
python3 -c "
v=[(0,0,0),(1,0,0),(1,1,0),(0,1,0),(0,0,1),(1,0,1),(1,1,1),(0,1,1)]
f=[(0,2,1),(0,3,2),(4,5,6),(4,6,7),(0,1,5),(0,5,4),(1,2,6),(1,6,5),(2,3,7),(2,7,6),(3,0,4),(3,4,7)]
open('cube.txt','w').write(''.join(' '.join('%g %g %g' % v[i] for i in t) + '\n' for t in f))
# ten parallel unit squares 0.01 apart: area 20 (two-sided), R_eq 1.26 m > R_bound 0.71 m
open('stack.txt','w').write(''.join('0 0 %g 1 0 %g 1 1 %g\n0 0 %g 1 1 %g 0 1 %g\n' % ((k / 100,) * 6) for k in range(10)))
# an OFF header asking for 10^9 faces (Assimp allocated 15 GB, then aborted mote)
open('big.off','w').write('OFF\n4 1000000000 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n')
open('nul.off','wb').write(b'OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 \x001 3\n')
open('flat.off','w').write('OFF\n3 1 0\n0 0 0\n0 0 0\n0 0 0\n3 0 1 2\n')
# 30 000 identical triangles and one real one: welding took over a minute
open('dup.txt','w').write('0 0 0 1e-9 0 0 0 1e-9 0\n' * 30000 + '0 0 0 1 0 0 0 1 0\n')
open('cut.txt','w').write(open('cube.txt').read() + '0 0 0 1 1\n')
n = 'left_wing_' + 'x' * 40
open('parts.obj','w').write('v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\ng %sA\nf 1 2 3\ng %sB\nf 1 2 4\n' % (n, n))
"
expect 1 "m1.mote:2:16: error: body load: big.off: the header declares 4 vertices and 1000000000 faces, more than a file of 51 bytes holds" m1.mote "${G}body load file=big.off\n" check
expect 1 "m2.mote:2:16: error: body load: nul.off: a NUL byte in the header (not a text file)" m2.mote "${G}body load file=nul.off\n"
printf 'ply\nformat ascii 1.0\n' > cut.ply
expect 1 "m2b.mote:2:16: error: body load: cut.ply: a PLY header without end_header" m2b.mote "${G}body load file=cut.ply\n"
expect 2 "m3.mote:2:16: error: body load: flat.off: no triangle with a non-zero extent" m3.mote "${G}body load file=flat.off\n"
expect 2 "m4.mote:2:1: error: body load: the body's size R_bound = 8.66025e-16 m is outside 1e-09 ... 1e+12 m" m4.mote "${G}body load file=cube.txt scale=1e-15\n"
expect 2 "m5.mote:2:1: error: body load: the body's size R_bound = 8.66025e+18 m is outside" m5.mote "${G}body load file=cube.txt scale=1e19\n"
expect 1 "m6.mote:2:1: error: body uvsphere: 2e+10 triangles (at most 1e+08, about 6.6e+03 GB)" m6.mote "${G}body uvsphere radius=1 nlon=100000 nlat=100000\n" check
printf '%bbody load file=stack.txt\n' "$G" > m7.mote
"$MOTE" run m7.mote > out.txt 2>&1 && grep -q '^body: warning: the sphere of equal area (R_eq = 1.26.* m) is larger than the ball of R_bound = 0.70.* m that holds the body' out.txt &&
    grep -q '^body: .* C 7.8.*e-11 F$' out.txt && ok || bad "R_eq > R_bound: C held at the bound: $(cat out.txt)"
printf '%bbody load file=cube.txt\n' "$G" > m8.mote
"$MOTE" run m8.mote > out.txt 2>&1 && ! grep -q 'warning' out.txt && ok || bad "a cube warned: $(cat out.txt)"
printf '%bbody load file=cut.txt\n' "$G" > m9.mote
"$MOTE" run m9.mote > out.txt 2>&1 && grep -q '^body load: warning: cut.txt ends inside a triangle (5 of 9 numbers' out.txt && ok || bad "a cut plain file: $(cat out.txt)"
printf '%bbody load file=dup.txt\n' "$G" > m10.mote
timeout 20 "$MOTE" run m10.mote > out.txt 2>&1 && grep -q '^body: 1 triangles' out.txt && ok || bad "duplicates: $(tail -2 out.txt)"
# part names kept whole: two parts, and material assign by the full name
printf '%bbody load file=parts.obj\nmaterial assign part=left_wing_%sB material=gold\n' "$G" "$(printf 'x%.0s' $(seq 1 40))" > m11.mote
"$MOTE" run m11.mote > out.txt 2> err.txt && ok || bad "long part names (cut to 31 characters, the two parts became one): $(cat err.txt)"
expect 2 "m12.mote:2:16: error: body load: cube.txt: the part name 'yyyyy" m12.mote "${G}body load file=cube.txt part=$(printf 'y%.0s' $(seq 1 300))\n"

# Differential charging (spec 6.10, issue 37). (a) Faithful mode, known constant currents: the
# south hemisphere a dielectric (C_p = eps0 eps_r A / d, R_p = d / (sigma A)) over the body;
# V_p - U = I_p R_p (1 - exp(-t / (R_p C_p))) exactly, against the implicit integrator's rows
# (its tolerance 1e-7 relative; 1e-6 allowed for the accumulated error), I_p the part's current
# from the run's parts table; U = I t / C unchanged.
printf '%bplasma preset geo-worst-case\nbody uvsphere radius=1 nlon=40 nlat=20 parts=hemispheres\noutput prefix=dc png=off triangles=off\nrun particles=1e5\ndielectric part=south thickness=1e-4 eps_r=3.5 sigma=1e-12\nevolve time=60 dt_out=5 file=dc.txt\n' "$F" > dc1.mote
"$MOTE" run dc1.mote > out.txt 2> err.txt && ok || bad "dc1.mote failed: $(cat err.txt)"
[ "$(grep '^# columns:' dc.txt | tr -d '\r')" = "# columns: t_s Q_C U_V sigma_U_V I_net_A V_south_V dV_max_V" ] && ok || bad "the time series' columns with a dielectric: $(grep '^# columns' dc.txt)"
Ip=$(awk -F '[,\r]' '$1 == "south" { print $10 }' dc_parts.csv)
A=$(awk '/^body: 1520 triangles, area/ { printf "%.12g", $5 / 2 }' out.txt)
awk -v Ip="$Ip" -v A="$A" '/^# A_south_m2 =/ { a = $4 } /^# C_p_south_F =/ { cp = $4 } /^# R_p_south_ohm =/ { rp = $4 }
  END { e0 = 8.8541878128e-12; c = e0 * 3.5 * A / 1e-4; r = 1e-4 / (1e-12 * A); d1 = cp / c - 1; d2 = rp / r - 1; d3 = a / A - 1
        exit !(Ip < 0 && d1 * d1 < 1e-16 && d2 * d2 < 1e-16 && d3 * d3 < 1e-16) }' dc.txt && ok || bad "C_p, R_p of the dielectric (I_p = $Ip, A = $A): $(grep '_south_' dc.txt)"
cp=$(awk '/^# C_p_south_F =/ { print $4 }' dc.txt); rp=$(awk '/^# R_p_south_ohm =/ { print $4 }' dc.txt)
awk -F '[ \r]' -v Ip="$Ip" -v cp="$cp" -v rp="$rp" '!/^#/ && NF > 1 { n++; dv = -$7; ex = Ip * rp * (1 - exp(-$1 / (rp * cp))); u = $1 * $5 / 1.109791275e-10
    if ((dv - ex) ^ 2 > 1e-12 * (Ip * rp) ^ 2 || (u - $3) ^ 2 > 1e-14 * u * u || ($6 - $3 - dv) ^ 2 > 1e-18 * $3 * $3) bad = 1 }
    END { exit !(n == 13 && !bad) }' dc.txt && ok || bad "faithful V_p - U against I_p R_p (1 - exp(-t/tau)): $(tail -n 2 dc.txt)"
# (b) Full mode, the exact sphere under a dielectric coat (thickness 0.5 m, eps_r 1: C_p = 2 C),
# sigma = 0: both equations carry the same current, so V_p - U = (C / C_p) U exactly, and with OML
# currents (electrons repelled by U, and by the coat's V_p - U through the share (1 + x) e^-x of
# their impact energies E e^(-E/kT) above |V_p - U| = x kT; ions attracted, all collected)
# C dU/dt = I(U) integrated by RK4 (1 us steps) gives U(t): each row within 4 sigma_U.
printf '%bseed 11\nplasma preset single n=1e6 kT=1000\nbody sphere radius=1\ndielectric part=sphere thickness=0.5 eps_r=1\nevolve time=0.5 dt_out=0.05 file=dcs.csv particles=1e5\n' "$G" > dc2.mote
"$MOTE" run dc2.mote > out.txt 2> err.txt && ok || bad "dc2.mote failed: $(cat err.txt)"
awk -F '[,\r]' 'function cur(U, x) { x = -U * r / kT; return -Ie * exp(U / kT) * (1 + x) * exp(-x) + Ii * (1 - U / kT) }
  BEGIN { e = 1.602176634e-19; pi = 3.14159265358979; n = 1e6; kT = 1000; A = 4 * pi; eps0 = 8.8541878128e-12
          Ie = e * n * sqrt(kT * e / (2 * pi * 9.1093837015e-31)) * A; Ii = e * n * sqrt(kT * e / (2 * pi * 1.67262192369e-27)) * A
          C = 4 * pi * eps0; r = C / (eps0 * A / 0.5); U = 0; t = 0; h = 1e-6 }
  FNR > 1 && !/^#/ { while (t < $1 - 1e-12) { k1 = cur(U) / C; k2 = cur(U + 0.5 * h * k1) / C; k3 = cur(U + 0.5 * h * k2) / C; k4 = cur(U + h * k3) / C
                       U += h * (k1 + 2 * k2 + 2 * k3 + k4) / 6; t += h }
    n2++; d = $3 - U; c = ($6 - $3) - r * $3; if (d * d > 16 * $4 * $4 + 1e-12 || c * c > 1e-12 * $3 * $3) { bad = 1; print "row", $1, $3, U, $4, $6 > "/dev/stderr" } }
  END { exit !(n2 == 11 && !bad && U < -2000) }' dcs.csv 2> why.txt && ok || bad "the coated sphere against OML: $(cat why.txt)"
printf '%bseed 11\nthreads 2\nplasma preset single n=1e6 kT=1000\nbody sphere radius=1\ndielectric part=sphere thickness=0.5 eps_r=1\nevolve time=0.5 dt_out=0.05 file=dcs2.csv particles=1e5\n' "$G" > dc3.mote
"$MOTE" run dc3.mote > /dev/null 2>&1 && [ "$(grep -v '^# command' dcs.csv)" = "$(grep -v '^# command' dcs2.csv)" ] && ok || bad "differential charging: 1 and 2 threads give different time series"
# the map of the surface potential at the end: V_south on the south's triangles, U on the rest
awk '!/^#/ && NF > 1 { u = $3; v = $6 } END { printf "%s %s\n", u, v }' dc.txt > last.txt
awk 'NR == FNR { u = $1; v = $2; next } /^SCALARS/ { f = $2 } f == "V_surface" && NF == 1 && $1 ~ /^-/ { n++; if ((($1 - u) / u) ^ 2 < 1e-16) nu++; else if ((($1 - v) / v) ^ 2 < 1e-16) nv++ }
     f == "part_id" && NF == 1 && $1 ~ /^[01]$/ { p[$1]++ } END { exit !(n == 1520 && nu == 760 && nv == 760 && p[0] == 760 && p[1] == 760) }' last.txt dc_potential.vtk && ok || bad "dc_potential.vtk: $(grep -c . dc_potential.vtk) lines, last row $(cat last.txt)"
expect 2 "dc4.mote:3:17: error: dielectric: the body has no part 'nose'" dc4.mote "${G}body sphere radius=1\ndielectric part=nose thickness=1e-4 eps_r=2\n"
expect 1 "dc5.mote:3:1: error: dielectric: faithful mode has no materials: give eps_r=" dc5.mote "${F}body sphere radius=1\ndielectric part=sphere thickness=1e-4\n"
expect 2 "dc6.mote:5:1: error: evolve: dielectric part 'sphere' has no permittivity" dc6.mote "${G}plasma preset single n=1e6 kT=1000\nbody sphere radius=1\ndielectric part=sphere thickness=1e-4\nevolve time=1\n"
expect 2 "dc7.mote:2:1: error: body uvsphere: parts=hemispheres needs an even nlat" dc7.mote "${G}body uvsphere radius=1 nlat=5 parts=hemispheres\n"

# The material library (issue 37): data/materials.dat is its one source; the compiled table is
# what scripts/materials.sh makes of it, and every row names a source the file's header lists.
sh "$top/scripts/materials.sh" > lib.inc 2> err.txt && cmp -s lib.inc "$top/src/charging/materials.inc" && ok || bad "src/charging/materials.inc is not scripts/materials.sh's output for data/materials.dat: $(cat err.txt)"
awk '/^#   [A-Z]+:ID / { split($2, a, ":"); known[a[1]] = 1; next } /^#/ || NF == 0 { next }
     { n++; split($14, a, ":"); if (!(a[1] in known) || a[2] != toupper($1)) bad++ } END { exit !(n == 8 && !bad) }' "$top/data/materials.dat" && ok || bad "data/materials.dat: a row without a listed source"
# a row that the script cannot read is an error naming the line
printf '# x\nal2k 0.97 0.3\n' > bad.dat
mkdir -p badlib/scripts badlib/data && cp "$top/scripts/materials.sh" badlib/scripts/ && cp bad.dat badlib/data/materials.dat
sh badlib/scripts/materials.sh > /dev/null 2> err.txt; [ $? -ne 0 ] && grep -q 'data/materials.dat line 2: 14 columns expected, found 3' err.txt && ok || bad "materials.sh on a short row: $(cat err.txt)"
printf 'x2k 0.97 0.3 13 4.0e-5 - - 0.2x 230 - - - - SPIS:X2K\n' > badlib/data/materials.dat
sh badlib/scripts/materials.sh > /dev/null 2> err.txt; [ $? -ne 0 ] && grep -q 'data/materials.dat line 1: column 8: a number expected, found 0.2x' err.txt && ok || bad "materials.sh on a bad number: $(cat err.txt)"
# A library dielectric's bulk conductivity is the default of `dielectric`: ka2k (1e-16 S/m, eps_r
# 3.5) under 0.1 mm on the exact sphere of radius 1: R_p = d / (sigma 4 pi), C_p = eps0 3.5 4 pi / d;
# sigma= still wins (1e-12)
for sg in "" " sigma=1e-12"; do
    printf '%bplasma preset single n=1e6 kT=1000\nbody sphere radius=1\nmaterial assign part=sphere material=ka2k\ndielectric part=sphere thickness=1e-4%s\nevolve time=1e-3 dt_out=1e-3 file=dk.txt particles=1e4\n' "$G" "$sg" > dk.mote
    "$MOTE" run dk.mote > out.txt 2> err.txt || bad "dk.mote ($sg) failed: $(cat err.txt)"
    s=1e-16; [ -n "$sg" ] && s=1e-12
    awk -v s="$s" '/^# R_p_sphere_ohm =/ { r = $4 } /^# C_p_sphere_F =/ { c = $4 }
        END { pi = 3.141592653589793; rr = 1e-4 / (s * 4 * pi); cc = 8.8541878128e-12 * 3.5 * 4 * pi / 1e-4
              exit !((r / rr - 1) ^ 2 < 1e-20 && (c / cc - 1) ^ 2 < 1e-16) }' dk.txt && ok || bad "ka2k dielectric ($sg): $(grep '_sphere_' dk.txt)"
done
# the photoemission of a sunlit sphere is j_ph pi a^2 (spec 6.8): graphite's 7.2e-6 A/m^2 (to the
# 10 digits printed)
printf '%bplasma preset single n=1e6 kT=1000\nbody sphere radius=1\nmaterial assign part=sphere material=gr2k\nsun direction=1,0,0\nrun particles=1e4\n' "$G" > gr.mote
"$MOTE" run gr.mote > out.txt 2> err.txt || bad "gr.mote failed: $(cat err.txt)"
ph=$(sed -n 's/^run: photoelectrons I = +\([^ ]*\) A.*/\1/p' out.txt)
awk -v p="$ph" 'BEGIN { w = 7.2e-6 * 3.141592653589793; exit !(p != "" && (p / w - 1) ^ 2 < 1e-18) }' && ok || bad "gr2k photocurrent $ph (expected 7.2e-6 pi): $(cat out.txt)"
expect 1 "lm.mote:3:38: error: material assign: no material 'KA2K' (the presets bare" lm.mote "${G}body sphere radius=1\nmaterial assign part=sphere material=KA2K\n"
# tracer embree (Embree alone) and the default (early-exit boxes on a body that is not convex)
# give the same hits: the same run lines, straight and curved paths
for pot in 0 -3000; do
    printf '%bplasma preset geo-worst-case\nbody twocubes side=1 gap=0.5\n%srun particles=4000 potential=%s\n' "$G" "" "$pot" > tr1.mote
    printf '%bplasma preset geo-worst-case\nbody twocubes side=1 gap=0.5\ntracer embree\nrun particles=4000 potential=%s\n' "$G" "$pot" > tr2.mote
    "$MOTE" run --quiet tr1.mote > tr1.txt 2> err.txt && "$MOTE" run --quiet tr2.mote > tr2.txt 2>> err.txt &&
        [ -n "$(grep '^run: net' tr1.txt)" ] && [ "$(grep '^run: ' tr1.txt | sed 's/[0-9.e+]* traces\/s//')" = "$(grep '^run: ' tr2.txt | sed 's/[0-9.e+]* traces\/s//')" ] && ok || bad "tracer embree and auto differ at U = $pot: $(cat tr1.txt tr2.txt err.txt)"
done
expect 1 "tr3.mote:2:8: error: tracer: expected 'auto' or 'embree', found 'optix'" tr3.mote "${G}tracer optix\n"
# float with a dielectric part (issue 55): the steady state of the conductor and the part.
# A part that conducts well (sigma = 1 S/m: V_p - U = R_p I_p, micro-volts) floats with the body:
# U equals the one-conductor float within 3 sigma, in the patches' circuit (the sphere's field)
# and in the solved field (each conductor at its own potential: its errors printed); the whole
# net current there within 3 sigma of zero. (The barrier's steady state: the slow suite, below.)
for fld in sphere solved; do
    pt=20000; [ -n "${MOTE_SANITIZED:-}" ] && pt=5000 # (3 sigma of the printed errors at any size)
    [ "$fld" = solved ] && pt=200 && [ -n "${MOTE_SANITIZED:-}" ] && pt=30
    printf '%bseed 3\nthreads 2\nplasma preset geo-worst-case\nbody uvsphere radius=1 nlon=12 nlat=6 parts=hemispheres\nmaterial assign part=north material=aluminium\nmaterial assign part=south material=kapton\nfield %s\nfloat particles=%s\ndielectric part=south thickness=127e-6 sigma=1\nfloat particles=%s\n' "$G" "$fld" "$pt" "$pt" > fd_$fld.mote
    "$MOTE" run --quiet fd_$fld.mote > fd.txt 2> err.txt || bad "fd_$fld.mote failed: $(cat err.txt)"
    u1=$(sed -n 's/^float: U_f = \([^ ]*\) V +- \([^ ]*\) .*/\1 \2/p' fd.txt)
    u2=$(sed -n 's/^float: the steady state of the conductor and 1 dielectric part .*: U = \([^ ]*\) V +- \([^;]*\);.*/\1 \2/p' fd.txt)
    dv=$(sed -n 's/^float: dielectric south: V_p = [^ ]* V, V_p - U = \([^ ;]*\) V.*/\1/p' fd.txt)
    net=$(sed -n 's/^float: conductor: .*the whole net current \([^ ]*\) A +- \([^ ]*\)$/\1 \2/p' fd.txt)
    echo "$u1 $u2 $dv $net" | awk '{ d = $1 - $3; exit !(NF == 7 && $1 < -1e4 && d * d <= 9 * ($2 * $2 + $4 * $4) && $5 * $5 < 1e-6 && $6 * $6 <= 9 * $7 * $7) }' && ok ||
        bad "float with a conducting part ($fld field): one conductor '$u1', the steady state '$u2', V_p - U '$dv', net '$net': $(cat fd.txt)"
    [ "$fld" = sphere ] || grep -q '^float: dielectric south: V_p = .*, V_p - U = .* V +- .*; its current .*, its leak .* A$' fd.txt && ok || bad "float's part line ($fld field): $(grep '^float: dielectric' fd.txt)"
done
expect 1 "fr.mote:5:16: error: float: replicas= and roots= are for a body that is one conductor" fr.mote "${G}plasma preset geo-worst-case\nbody uvsphere radius=1 nlon=12 nlat=6 parts=hemispheres\ndielectric part=south thickness=1e-4 eps_r=3\nfloat replicas=3\n"
# field solved cache= (the paths' cache of the field): on builds it (its cells printed), off (the
# default) none; on the spacecraft at -5 kV the run lines are the same with and without it (400
# histories: common random numbers, and the cache's 1e-3 changes no history's fate here). (Not
# under the sanitizers: the build takes a minute there; test_bem runs fcache.c under them.)
[ -n "${MOTE_SANITIZED:-}" ] || for cm in off on; do
    printf '%bseed 3\nthreads 2\nplasma preset geo-worst-case\nbody load file=%s/examples/data/spacecraft.obj\nfield solved cache=%s\nrun particles=400 potential=-5000\n' "$G" "$top" "$cm" > fc_$cm.mote
    "$MOTE" run --quiet fc_$cm.mote > fc_$cm.txt 2> err.txt || bad "fc_$cm.mote failed: $(cat err.txt)"
done
[ -n "${MOTE_SANITIZED:-}" ] || { grep -q "^field solved: the paths' cache: [0-9]* cells interpolated, [0-9]* left to the tree" fc_on.txt &&
    ! grep -q "paths' cache" fc_off.txt &&
    [ "$(grep '^run: net' fc_on.txt | sed 's/[0-9.e+]* traces\/s//')" = "$(grep '^run: net' fc_off.txt | sed 's/[0-9.e+]* traces\/s//')" ] &&
    ok || bad "field solved cache=: $(cat fc_on.txt fc_off.txt)"; }
mote_test_end
