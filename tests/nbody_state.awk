# nbody_state.awk: an nbody state file of version 4 rewritten in the layout of version `to` (awk
# -v to=1|2|3), for the tests that older files still load and that old fixtures come back
# field for field. Version 3 held the scheme's order on the scheme line and the Taylor, map and
# softening values on one taylor line, before the doubling line; version 2 had no map values
# (they must be the defaults a version-2 file loads with, 0: otherwise a line that matches no
# fixture is written) and no map block; version 1 no doubling line and no body names.
/^mote-state 4$/ { print "mote-state " to; next }
/^step / { split($0, st, " "); print "step", st[2], st[3], st[4], st[5]; next }
/^scheme / { split($0, sc, " "); next }
/^galactica / { order = $2; next }
/^doubling / { dbl = $0; next }
/^taylor / { tord = $2; tmem = $3; next }
/^wh / {
    print "scheme", order, sc[3], sc[5], sc[6]
    t = "taylor " sc[2] " " tord " " tmem " " st[6] " " st[7] " " st[8] " " st[9] " " st[10] " " st[11]
    if (to >= 3)
        t = t " " $2 " " $3 " " $4 " " $5 " " sc[4]
    else if ($2 != 0 || $3 != 0 || $4 != 0 || $5 != 0 || sc[4] != 0)
        t = t " (map or softening values that a version-" to " file cannot hold)"
    print t
    if (to >= 2)
        print dbl
    next
}
to < 3 && /^map:/ { print "(a map block: not a version-" to " state)"; next }
to < 2 && / -$/ { sub(/ -$/, "") }
{ print }
