#!/bin/sh
# test_docs.sh BUILD_DIR: the checked-in command reference docs/commands.md must be exactly what
# `mote help --markdown` prints, so the manual never drifts from the command tables.
# Regenerate with: build/mote help --markdown > docs/commands.md
build=${1:-build}
top=$(cd "$(dirname "$0")/.." && pwd)
pass=0
fail=0
tmp=$(mktemp)
if "$build/mote" help --markdown >"$tmp" && cmp -s "$tmp" "$top/docs/commands.md"; then
    pass=$((pass + 1))
    echo "ok: docs/commands.md matches mote help --markdown"
else
    fail=$((fail + 1))
    echo "FAIL: docs/commands.md differs from mote help --markdown (regenerate it)"
    diff "$tmp" "$top/docs/commands.md" | head -20
fi
rm -f "$tmp"
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
