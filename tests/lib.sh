# lib.sh: the harness shared by the shell tests that drive the `mote` program (sourced, not run).
# The caller sets NAME and calls mote_test_start "$1"; then ok, bad, expect; mote_test_end last.

# mote_test_start [BUILD_DIR]: MOTE = the absolute path of the program, a fresh temporary
# directory (removed on exit) as the working directory, counters at zero.
mote_test_start() {
    MOTE=$(cd "$(dirname "${1:-build}/mote")" && pwd)/mote
    [ -x "$MOTE" ] || { echo "$NAME: no $MOTE"; echo "0 passed, 1 failed"; exit 1; }
    TMP=$(mktemp -d "${TMPDIR:-/tmp}/mote-$NAME.XXXXXX") || exit 1
    trap 'rm -rf "$TMP"' EXIT
    cd "$TMP" || exit 1
    passed=0
    failed=0
}

# The head of a small dilute separator script (one species fed at mid-height), for printf '%b'.
SEP_DILUTE='model separator\nchannel 0.05 1\ngas 1.5\ncollisions off\ntimestep 1e-3\nspecies quartz 2650\nsize quartz lognormal d50=150e-6 sigma=1.6 min=30e-6 max=600e-6\nfeed z=0.5 rate=2e-5\n'

ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAILED: $*"; }

# expect STATUS STDERR-PREFIX SCRIPT-NAME SCRIPT-TEXT [mote-subcommand]: write the script, run
# it, and check the exit status and the start of what it wrote to stderr.
expect() {
    status=$1 want=$2 name=$3 text=$4 sub=${5:-run}
    printf '%b' "$text" > "$name"
    "$MOTE" "$sub" "$name" > out.txt 2> err.txt
    got=$?
    [ "$got" -eq "$status" ] && ok || bad "$name: exit status $got, expected $status ($(cat err.txt))"
    case "$(cat err.txt)" in
        "$want"*) ok ;;
        *) bad "$name: stderr '$(cat err.txt)', expected it to start with '$want'" ;;
    esac
}

mote_test_end() {
    echo "$passed passed, $failed failed"
    [ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]
}

# sigint_after_rows SCRIPT PARTIAL N OUT: run SCRIPT in the background and stop it with SIGINT
# once PARTIAL holds N data rows (or after 2 minutes); its exit status is left in $sigint_rc.
# (A background job of a script ignores SIGINT unless told otherwise: env --default-signal.)
sigint_after_rows() {
    env --default-signal=INT "$MOTE" run "$1" > "$4" 2>&1 &
    sigint_pid=$!
    sigint_i=0
    # (grep -c prints 0 and fails when the file has only its header: no "|| echo 0" there)
    while [ "$sigint_i" -lt 1200 ]; do
        sigint_n=$(grep -vc '^#' "$2" 2>/dev/null)
        [ "${sigint_n:-0}" -ge "$3" ] && break
        sleep 0.1
        sigint_i=$((sigint_i + 1))
    done
    kill -INT "$sigint_pid"
    wait "$sigint_pid"
    sigint_rc=$?
}
