#!/bin/sh
# test_mpi.sh: the MPI build (make MPI=1). The charging model (spec 5.6 and S5): a script of run
# (straight paths, materials, sun), float and evolve (curved paths; then with a dielectric part,
# spec 6.10, and its map of the surface potential) gives the same files on 1
# process of the plain build, 1 rank and 2 ranks of the MPI build (timing lines excepted), and
# only rank 0 writes; so does a run on a convex body (walked over its triangles, issue 36). The N-body model (its spec 6.3, T17): 1, 2 and 3 ranks give the single
# process's bits, in scripts and Galactica jobs. Other models are refused under MPI. `make check` builds
# build-mpi/mote and names it in MOTE_MPI_BIN for its plain pass; without it this test says so
# and checks nothing (the sanitizer pass).
# Usage: MOTE_MPI_BIN=build-mpi/mote sh tests/test_mpi.sh [BUILD_DIR]
NAME=mpi
EX=$(cd "$(dirname "$0")/.." && pwd)/examples/galactica/ring30
. "$(dirname "$0")/lib.sh"
mote_test_start "$1"
if [ -z "${MOTE_MPI_BIN:-}" ]; then
    echo "test_mpi.sh: MOTE_MPI_BIN is not set (the plain pass of make check sets it): nothing checked"
    mote_test_end
    exit 0
fi
MPI_MOTE=$MOTE_MPI_BIN
[ -x "$MPI_MOTE" ] && ok || bad "no MPI build at $MPI_MOTE"
# Open MPI refuses root unless told (CI machines run as root); --oversubscribe for small machines
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
MPIRUN="mpirun --oversubscribe -np 2"

printf 'o craft\nv -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\ng bus\nf 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\ng panel\nv 1 -0.5 0\nv 4 -0.5 0\nv 4 0.5 0\nv 1 0.5 0\nf 9 10 11\nf 9 11 12\n' > craft.obj
printf 'model charging\nplasma preset geo-worst-case\nbody load file=../craft.obj\nmaterial assign part=* material=kapton\nsun direction=0.3,0.2,1\noutput prefix=c png_size=400x300\nrun particles=1e5\nintegrator eta=0.05\nfloat particles=2e4\nevolve time=0.2 dt_out=0.05 particles=1e4 file=ts.csv\ndielectric part=panel thickness=1e-4 sigma=1e-14\nevolve time=20 dt_out=5 particles=1e4 file=ts2.csv\n' > t.mote
mkdir -p p1 r1 r2
cp t.mote p1/ && cp t.mote r1/ && cp t.mote r2/
(cd p1 && "$MOTE" run t.mote > out.txt 2> err.txt) && ok || bad "plain build: $(cat p1/err.txt)"
(cd r1 && "$MPI_MOTE" run t.mote > out.txt 2> err.txt) && ok || bad "MPI build, 1 rank: $(cat r1/err.txt)"
(cd r2 && $MPIRUN "$MPI_MOTE" run t.mote > out.txt 2> err.txt) && ok || bad "MPI build, 2 ranks: $(cat r2/err.txt)"
grep -q '^mote: 2 MPI ranks share' r2/err.txt && ok || bad "no note of the ranks: $(cat r2/err.txt)"
grep -q '"ranks":2,' r2/c_summary.json && grep -q 'on 1 thread and 2 MPI ranks' r2/c_summary.txt && ok || bad "the summaries do not give the ranks"
# the same files; the summaries without their timing (traces/s)
untimed() { sed -e 's/"traces_per_s":[^,]*,//' -e 's/"ranks":[0-9]*,//' -e 's/, [0-9.e+]* traces\/s on .*//' "$1"; }
for f in c_triangles.csv c_parts.csv c_surface.vtk c_surface.png ts.csv ts2.csv c_potential.vtk c_potential.png; do
    [ -s "p1/$f" ] && cmp -s "p1/$f" "r1/$f" && cmp -s "p1/$f" "r2/$f" && ok || bad "$f differs between 1 process, 1 rank and 2 ranks"
done
for f in c_summary.txt c_summary.json; do
    [ -s "p1/$f" ] && [ "$(untimed p1/$f)" = "$(untimed r2/$f)" ] && ok || bad "$f differs beyond its timing"
done
# the numbers printed, without speeds and without progress lines (mpirun gives the ranks a
# pseudo-terminal, so rank 0 shows progress: "\rfloat: run 3, 42.0%  ~0 s left", wiped by "\r  \r")
nums() { tr '\r' '\n' < "$1" | grep -E '^(run|float|evolve):' | grep -v -E '^[a-z_]+(: run [0-9]+,)? [0-9.]+%' | sed -e 's/[0-9.e+]* traces\/s//'; }
[ -n "$(nums p1/out.txt)" ] && [ "$(nums p1/out.txt)" = "$(nums r2/out.txt)" ] && ok || bad "the printed results differ: $(nums r2/out.txt | head -3)"
grep -q '^float: U_f = ' r2/out.txt && ok || bad "2 ranks: no float line"
# only rank 0 writes: no temporary or second copies
[ "$(ls r2 | sort | tr '\n' ' ')" = "$(ls p1 | sort | tr '\n' ' ')" ] && ok || bad "files of 2 ranks: $(ls r2)"
# a convex body, walked over its triangles (issue 36) rather than traced by Embree: the same
# tallies and pictures on 1 process and 2 ranks
printf 'model charging\nplasma preset geo-worst-case\nbody icosphere radius=1 level=3\noutput prefix=v png_size=400x300\nrun particles=1e5\n' > v.mote
mkdir -p v1 v2
cp v.mote v1/ && cp v.mote v2/
(cd v1 && "$MOTE" run v.mote > out.txt 2> err.txt) && ok || bad "convex body, plain build: $(cat v1/err.txt)"
(cd v2 && $MPIRUN "$MPI_MOTE" run v.mote > out.txt 2> err.txt) && ok || bad "convex body, 2 ranks: $(cat v2/err.txt)"
for f in v_triangles.csv v_parts.csv v_surface.vtk v_surface.png; do
    [ -s "v1/$f" ] && cmp -s "v1/$f" "v2/$f" && ok || bad "convex body: $f differs between 1 process and 2 ranks"
done
# an ensemble on 2 ranks: its replicas one after another, each sharing its work among the
# ranks: the means of the single process
printf 'model charging\nensemble 3 file=e.dat\nplasma preset single n=1e6 kT=10\nbody sphere radius=1\nfloat particles=2000\nend\n' > ens.mote
mkdir -p e1 e2 && cp ens.mote e1/ && cp ens.mote e2/
(cd e1 && "$MOTE" run ens.mote > out.txt 2> err.txt) && (cd e2 && $MPIRUN "$MPI_MOTE" run ens.mote > out.txt 2> err.txt) && ok ||
    bad "an ensemble on 2 ranks failed: $(cat e2/err.txt)"
[ -n "$(grep '^ensemble: float.U_f' e1/out.txt)" ] && [ "$(grep '^ensemble: float.U_f' e1/out.txt)" = "$(tr '\r' '\n' < e2/out.txt | grep '^ensemble: float.U_f')" ] && cmp -s e1/e.dat e2/e.dat && ok ||
    bad "the ensemble differs on 2 ranks: $(grep '^ensemble: float' e1/out.txt e2/out.txt)"
# a model that does not share its work (hard spheres) under 2 ranks: its commands run in rank 0
# and its ensemble's replicas are spread over the ranks: the single process's output and files,
# bit for bit (the replicas of rank 1 write their own files)
printf 'ensemble 5 file=z.dat\nbulk 108 0.3\nstep 100\npressure 100 p_${replica}.dat\nend\nplot p_1.dat p_2.dat to=l.png\nnew 2 0.3\nstep 10\nsave s.state\n' > hs.mote
mkdir -p h1 h2 && cp hs.mote h1/ && cp hs.mote h2/
(cd h1 && "$MOTE" run hs.mote > out.txt 2> err.txt) && (cd h2 && $MPIRUN "$MPI_MOTE" run hs.mote > out.txt 2> err.txt) && ok ||
    bad "hard spheres on 2 ranks failed: $(cat h2/err.txt)"
grep -q '^ensemble: 5 replicas (seeds 1 ... 5) on [0-9]* threads\{0,1\} in each of 2 MPI ranks$' h2/out.txt && ok || bad "2 ranks: $(head -n 1 h2/out.txt)"
plain() { tr '\r' '\n' < "$1" | grep -v 'seconds=\|^ensemble: 5 replicas\|[0-9.]*%'; }
[ "$(plain h1/out.txt)" = "$(plain h2/out.txt)" ] && ok || bad "the hard-sphere ensemble prints otherwise on 2 ranks: $(plain h2/out.txt | head -n 3)"
for f in z.dat p_1.dat p_2.dat p_5.dat l.png s.state; do
    cmp -s "h1/$f" "h2/$f" && ok || bad "$f differs on 2 ranks"
done

# an error in rank 0 before an ensemble: every rank stops (none waits at the ensemble forever)
printf 'not data\n' > junk.txt
printf 'new 2 0.3\nplot junk.txt j.png\nensemble 2\nbulk 32 0.3\nend\necho after\n' > stop.mote
timeout 120 $MPIRUN "$MPI_MOTE" run stop.mote > out.txt 2> err.txt
rc=$?
[ $rc -ne 0 ] && [ $rc -ne 124 ] && grep -q '^stop.mote:2:1: error: junk.txt:1: not a mote data file' err.txt && ! grep -q '^after$' out.txt && ok ||
    bad "an error in rank 0 before an ensemble: exit $rc, $(head -n 3 err.txt)"

# ---- the N-body model (spec 6.3, T17): 1, 2 and 3 ranks (3 oversubscribed on small machines)
# give the single process's bits: the Galactica scheme, then the Taylor integrator, the state
# and a Galactica result file; and a Galactica job run by `mote galactica` on 2 ranks
export OMPI_MCA_mpi_yield_when_idle=1
printf 'model nbody gravity\nunits solar\ngenerate ring nb=30\nintegrator galactica dt=1e-6\nmonitor every=100 file=g.mon\nintegrate steps=300\nwrite galactica file=g.dat info_line=off\nintegrator taylor order=12 tol=1e-16\nintegrate steps=5\nsave s.state\n' > nb.mote
mkdir -p nb0 nb1 nb2 nb3
for d in nb0 nb1 nb2 nb3; do cp nb.mote $d/; done
(cd nb0 && "$MOTE" run nb.mote > out.txt 2> err.txt) && ok || bad "nbody, plain build: $(cat nb0/err.txt)"
for r in 1 2 3; do
    (cd nb$r && mpirun --oversubscribe -np $r "$MPI_MOTE" run nb.mote > out.txt 2> err.txt) && ok || bad "nbody on $r ranks: $(cat nb$r/err.txt)"
    cmp -s nb0/g.dat nb$r/g.dat && cmp -s nb0/s.state nb$r/s.state && ok || bad "T17: nbody on $r MPI ranks differs from the single process"
    [ "$(grep -v '_s ' nb0/g.mon | grep -v '^#' | cut -d' ' -f1-33)" = "$(grep -v '^#' nb$r/g.mon | cut -d' ' -f1-33)" ] && ok || bad "T17: the monitor on $r ranks differs"
    [ "$(ls nb$r | sort | tr '\n' ' ')" = "$(ls nb0 | sort | tr '\n' ' ')" ] && ok || bad "files of $r ranks: $(ls nb$r)"
done
# forces tree and ranks: refused
printf 'model nbody gravity\ngenerate plummer n=100\nforces tree\nintegrate steps=1\n' > tr.mote
$MPIRUN "$MPI_MOTE" run tr.mote > out.txt 2> err.txt
[ $? -eq 2 ] && grep -q 'forces tree and MPI ranks do not go together' err.txt && ok || bad "tree under MPI: $(cat err.txt)"
mkdir -p gj0 gj2
for d in gj0 gj2; do cp "$EX/galacf26.dat" "$EX/axsymb30.dat" $d/; sed -i '24s/^\(.\{59\}\).*/\12000/' $d/galacf26.dat; done
(cd gj0 && "$MOTE" galactica > out.txt 2> err.txt) && ok || bad "galactica, plain: $(cat gj0/err.txt)"
(cd gj2 && $MPIRUN "$MPI_MOTE" galactica > out.txt 2> err.txt) && ok || bad "galactica on 2 ranks: $(cat gj2/err.txt)"
for f in garez28.dat traekt.prn dice.dat 2; do
    cmp -s gj0/$f gj2/$f && ok || bad "T17: the Galactica job's $f differs on 2 ranks"
done
sed -i '26s/^\(.\{59\}\).*/\17/' gj2/galacf26.dat
(cd gj2 && $MPIRUN "$MPI_MOTE" galactica > out.txt 2> err.txt)
[ "$(grep -c '^\*02G' gj2/ErrGlctca)" -eq 1 ] && ok || bad "2 ranks: ErrGlctca has $(grep -c . gj2/ErrGlctca) lines for one error (rank 0 writes it)"
mote_test_end
