#!/bin/sh
# Install the Debian packages mote needs, if any is missing: `setup.sh` what building mote and
# running the example need (make example), `setup.sh test` also what the tests use (make check),
# `bench` and `fuzz` what those need. Safe to re-run: a package already present is never asked
# for again, and nothing runs when everything is there. apt waits for another apt's lock (up to
# 10 minutes) instead of failing. Needs root (or sudo) only when installing.
set -e
need=""
command -v cc >/dev/null 2>&1 || need="$need gcc"
command -v make >/dev/null 2>&1 || need="$need make"
command -v pkg-config >/dev/null 2>&1 || need="$need pkg-config"
pkg-config --exists cairo 2>/dev/null || need="$need libcairo2-dev"
# the charging model: Embree (ray tracing) and Assimp (mesh files)
[ -f /usr/include/embree3/rtcore.h ] || need="$need libembree-dev" # (no pkg-config file)
pkg-config --exists assimp 2>/dev/null || need="$need libassimp-dev"
# libmicrohttpd: the live view's HTTP server (mote run --live)
pkg-config --exists libmicrohttpd 2>/dev/null || need="$need libmicrohttpd-dev"
# HDF5 (serial): the H5MD trajectories and snapshots (format=h5md)
pkg-config --exists hdf5 2>/dev/null || need="$need libhdf5-dev"
# LAPACK (LAPACKE, with OpenBLAS's fast LAPACK): the charging model's boundary-element solve.
# OpenBLAS's OpenMP build: its threads are made when it first works, by the run's own thread,
# so they keep the run's blocked signals (the pthread build starts its threads when it is
# loaded, and one of them would take a Ctrl-C that `mote run` means to stop at a safe point)
pkg-config --exists lapacke 2>/dev/null || need="$need liblapacke-dev"
dpkg-query -W -f='${Status}' libopenblas-openmp-dev 2>/dev/null | grep -q 'ok installed' ||
    need="$need libopenblas-openmp-dev"
# the Python package (make python, make install): Debian's python3 with its headers and NumPy
[ -f "$(/usr/bin/python3 -c 'import sysconfig; print(sysconfig.get_paths()["include"])' 2>/dev/null)/Python.h" ] ||
    need="$need python3-dev"
/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1 || need="$need python3-numpy"
# pip install . --no-build-isolation into a venv (pyproject.toml, setup.py): Debian's setuptools
# and venv (its pip for the venv)
/usr/bin/python3 -c 'import setuptools' >/dev/null 2>&1 || need="$need python3-setuptools"
/usr/bin/python3 -c 'import wheel' >/dev/null 2>&1 || need="$need python3-wheel"
dpkg-query -W -f='${Status}' python3-venv 2>/dev/null | grep -q 'ok installed' || need="$need python3-venv"
# `setup.sh test` (make check): also what only the tests use
if [ "${1:-}" = test ] || [ "${1:-}" = bench ]; then
    # Open MPI: the MPI build (make MPI=1), built and run with 2 ranks by make check
    command -v mpicc >/dev/null 2>&1 || need="$need libopenmpi-dev"
    command -v mpirun >/dev/null 2>&1 || need="$need openmpi-bin"
    # VTK's Python reader (Debian's python3): the charging model's VTK files read back
    /usr/bin/python3 -c 'import vtkmodules.vtkIOLegacy' >/dev/null 2>&1 || need="$need python3-vtk9"
    # ASE (Debian's python3), the independent reader of the extended XYZ files
    /usr/bin/python3 -c 'import ase.io' >/dev/null 2>&1 || need="$need python3-ase"
    # pytest (Debian's python3): the Python package's tests and examples (test_python)
    /usr/bin/python3 -c 'import pytest' >/dev/null 2>&1 || need="$need python3-pytest"
    # nbclient, nbformat and ipykernel (Debian's python3): a notebook executed headless in the
    # package's venv (test_python)
    /usr/bin/python3 -c 'import nbclient, nbformat' >/dev/null 2>&1 || need="$need python3-nbclient python3-nbformat"
    /usr/bin/python3 -c 'import ipykernel' >/dev/null 2>&1 || need="$need python3-ipykernel"
    # matplotlib (Debian's python3): pictures read back pixel by pixel (test_plot), and the
    # Python examples' plots
    /usr/bin/python3 -c 'import matplotlib.image' >/dev/null 2>&1 || need="$need python3-matplotlib"
    # h5py (Debian's python3): the H5MD files read back as users read them
    /usr/bin/python3 -c 'import h5py' >/dev/null 2>&1 || need="$need python3-h5py"
    # pandas (Debian's python3): the .csv files (RFC 4180) read back as users read them
    /usr/bin/python3 -c 'import pandas' >/dev/null 2>&1 || need="$need python3-pandas"
    # curl: the live view's protocol tests; Chromium (headless): its browser test
    command -v curl >/dev/null 2>&1 || need="$need curl"
    command -v chromium >/dev/null 2>&1 || need="$need chromium"
    # ffmpeg: the movies of the mixing-box and separator frames (made when it is on PATH; tested)
    command -v ffmpeg >/dev/null 2>&1 || need="$need ffmpeg"
fi
# `setup.sh bench`: also LIGGGHTS, the granular code the separator's benchmark runs side by side
if [ "${1:-}" = bench ]; then
    command -v liggghts >/dev/null 2>&1 || need="$need liggghts"
fi
# `setup.sh fuzz`: also clang with libFuzzer, for `make fuzz`
if [ "${1:-}" = fuzz ]; then
    command -v clang >/dev/null 2>&1 || need="$need clang"
    [ -n "$(find /usr/lib/llvm-*/lib/clang -name 'libclang_rt.fuzzer-x86_64.a' 2>/dev/null | head -n 1)" ] ||
        need="$need libclang-rt-14-dev"
    # OpenMP for clang (the build uses -fopenmp; gcc brings its own libgomp)
    [ -n "$(find /usr/lib/llvm-*/lib -name 'libomp.so' 2>/dev/null | head -n 1)" ] ||
        need="$need libomp-14-dev"
fi
[ -z "$need" ] && exit 0
echo "setup: installing Debian packages:$need"
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
LOCK="-o DPkg::Lock::Timeout=600"
# (the package lists' lock: apt-get update waits on it through the same option on Debian 12; a
# second try covers an older apt that does not)
# shellcheck disable=SC2086
$SUDO apt-get $LOCK update -qq || { sleep 30; $SUDO apt-get $LOCK update -qq; }
# shellcheck disable=SC2086
$SUDO apt-get $LOCK install -y -qq --no-install-recommends $need
