"""python -m mote ARGS: the mote program (`run SCRIPT`, `check`, `help`, `galactica`, ...), from
the package's own libmote: the same output, files and exit status as `mote ARGS`. The package
installs it as the command `mote` too."""
import sys

from . import _mote


def main():
    sys.stdout.flush()
    sys.stderr.flush()
    return _mote.main(["mote"] + sys.argv[1:])


if __name__ == "__main__":
    sys.exit(main())
