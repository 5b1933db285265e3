# pytest configuration for the Python package's tests (run by tests/test_python.sh, which puts
# BUILD/python on PYTHONPATH and names the program in MOTE).
import os
import sys

import pytest


@pytest.fixture
def mote_bin():
    return os.environ["MOTE"]


@pytest.fixture
def examples():
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples")
