"""setup.py: the Python package's extension, made by the project's Makefile (`make python`) for
the Python that runs this (its headers, its NumPy), then copied where setuptools puts it;
pyproject.toml holds the rest. The library is compiled into MOTE_BUILD_DIR (default
build/pip beside this file), so a second install reuses what the first compiled; `make` and a C
compiler are needed, and the libraries scripts/setup.sh installs."""
import os
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


def version():
    with open(os.path.join(ROOT, "include", "mote", "core.h"), encoding="utf-8") as f:
        return re.search(r'#define MOTE_VERSION "([^"]+)"', f.read()).group(1)


class MakeExtension(build_ext):
    def build_extension(self, ext):
        try:
            import numpy  # noqa: F401 (its headers: the Makefile asks this Python for them)
        except ImportError:
            sys.exit("mote: the Python that builds the package (%s) has no NumPy; install it "
                     "first (Debian: python3-numpy; in a venv made with "
                     "--system-site-packages it is Debian's)" % sys.executable)
        build = os.path.abspath(os.environ.get("MOTE_BUILD_DIR") or
                                os.path.join(ROOT, "build", "pip"))
        jobs = "-j%d" % (os.cpu_count() or 2)
        subprocess.check_call(["make", "-C", ROOT, jobs, "--no-print-directory",
                               "BUILD=" + build, "PYTHON=" + sys.executable, "python"])
        built = os.path.join(build, "python", "mote",
                             "_mote" + sysconfig.get_config_var("EXT_SUFFIX"))
        dest = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(dest), exist_ok=True)
        shutil.copyfile(built, dest)


setup(version=version(),
      ext_modules=[Extension("mote._mote", sources=[])],
      cmdclass={"build_ext": MakeExtension})
