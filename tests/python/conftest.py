# pytest configuration for the Python package's tests (run by tests/test_python.sh in a venv the
# package was pip-installed into, or under the sanitizers with BUILD/python on PYTHONPATH; MOTE
# names the program).
import os
import sys

import pytest


@pytest.fixture
def mote_bin():
    return os.environ["MOTE"]


@pytest.fixture
def examples():
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples")
