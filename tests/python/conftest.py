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


@pytest.fixture
def ctrl_c():
    """A maker of (report, sent): a progress callback that sends SIGINT to this process at its
    first call only, as one Ctrl-C while a command runs (a second, sent by a later report before
    the command has stopped, would be raised after the test's `with` block), and the fractions
    it was called with."""
    import signal

    def once():
        sent = []

        def report(label, fraction):
            if not sent:
                sent.append(fraction)
                os.kill(os.getpid(), signal.SIGINT)
        return report, sent
    return once
