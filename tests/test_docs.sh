#!/bin/sh
# test_docs.sh BUILD_DIR: the checked-in command reference docs/commands.md must be exactly what
# `mote help --markdown` prints, so the manual never drifts from the command tables.
# Regenerate with: build/mote help --markdown > docs/commands.md
# Also: every script in examples/ passes `mote check`.
build=$(cd "${1:-build}" && pwd)
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
# every example script must pass validation as shipped
for ex in "$top"/examples/*.mote; do
    if (cd "$top/examples" && "$build/mote" check "$(basename "$ex")" >/dev/null 2>&1); then
        pass=$((pass + 1))
        echo "ok: mote check $(basename "$ex")"
    else
        fail=$((fail + 1))
        echo "FAIL: mote check $(basename "$ex")"
    fi
done
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
