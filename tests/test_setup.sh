#!/bin/sh
# test_setup.sh: scripts/setup.sh (issue 33, item 11) with a fake apt-get (and sudo) first on
# PATH that records what it is asked: on this machine, where the packages are present, nothing is
# asked for; with cairo's pkg-config entry made to look missing, the example's set-up asks for
# libcairo2-dev alone (no test-only package) and `setup.sh test` asks for the same, both with
# apt's lock timeout; nothing runs apt when everything is there.
# Usage: sh tests/test_setup.sh [BUILD_DIR]
NAME=setup
. "$(dirname "$0")/lib.sh"
SETUP=$(cd "$(dirname "$0")/.." && pwd)/scripts/setup.sh
mote_test_start "$1"

mkdir fake
cat > fake/apt-get <<'EOF'
#!/bin/sh
echo "apt-get $*" >> "$APT_LOG"
EOF
cat > fake/sudo <<'EOF'
#!/bin/sh
"$@"
EOF
chmod +x fake/apt-get fake/sudo
APT_LOG=$PWD/apt.log
export APT_LOG

# everything present: apt is never asked
sh "$SETUP" test > out.txt 2>&1 && ok || bad "setup.sh test failed: $(cat out.txt)"
PATH="$PWD/fake:$PATH" sh "$SETUP" test > out.txt 2>&1 && ok || bad "setup.sh test with nothing missing failed: $(cat out.txt)"
[ ! -s apt.log ] && ok || bad "apt was asked although nothing was missing: $(cat apt.log)"

# cairo looks missing (a pkg-config that knows no cairo): only libcairo2-dev is asked for
mkdir fakepc
REAL_PC=$(command -v pkg-config)
cat > fakepc/pkg-config <<EOF
#!/bin/sh
for a in "\$@"; do [ "\$a" = cairo ] && exit 1; done
exec "$REAL_PC" "\$@"
EOF
chmod +x fakepc/pkg-config
PATH="$PWD/fakepc:$PWD/fake:$PATH" sh "$SETUP" > out.txt 2>&1 && ok || bad "setup.sh failed: $(cat out.txt)"
grep -q '^apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends  *libcairo2-dev$' apt.log &&
    ok || bad "the example's set-up did not ask for libcairo2-dev alone, with the lock timeout: $(cat apt.log)"
grep -q '^apt-get -o DPkg::Lock::Timeout=600 update' apt.log && ok || bad "apt-get update without the lock timeout: $(cat apt.log)"
: > apt.log
PATH="$PWD/fakepc:$PWD/fake:$PATH" sh "$SETUP" test > out.txt 2>&1 && ok || bad "setup.sh test failed: $(cat out.txt)"
grep -q 'install -y -qq --no-install-recommends  *libcairo2-dev$' apt.log && ok || bad "setup.sh test: $(cat apt.log)"
mote_test_end
