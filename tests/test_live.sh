#!/bin/sh
# test_live.sh: the live view (issue 25) through the `mote` program: the page, the frame stream
# (frames whose particle count and positions match the state), 404 for other paths, 405 for other
# methods, refused oversized requests, pause and resume, a viewer that stops reading does not stop
# the run, results bit-identical with and without the view; and a real browser (headless
# Chromium, installed by scripts/setup.sh) that draws discs of both colours and whose frame
# counter advances.
# Usage: sh tests/test_live.sh [BUILD_DIR]   (default: build)
NAME=live
. "$(dirname "$0")/lib.sh"
SRC=$(cd "$(dirname "$0")/.." && pwd)
mote_test_start "$1"

# a mixing box that runs long enough to be watched (killed when done)
mb() { # mb RUN_TIME [more commands]
    printf 'model mixing-box\nseed 7\nbox 0 2 0 1\npartition 1 0.02\nslit 0.5 0.1\nradius 0.005\ndisks 1000 1000\nv_init 1\nplace\nrun %s\n%b' "$1" "${2:-}"
}
# start SCRIPT: run it with --live=0 in the background; URL, PID
start() {
    "$MOTE" run --live=0 "$1" > live_out.txt 2> live_err.txt &
    PID=$!
    URL=
    for _ in 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20; do
        URL=$(sed -n 's/^live: open \(http[^ ]*\) .*/\1/p' live_out.txt)
        [ -n "$URL" ] && break
        sleep 0.1
    done
    [ -n "$URL" ] && ok || bad "no live address printed: $(cat live_out.txt live_err.txt)"
}
stop() { kill "$PID" 2> /dev/null; wait "$PID" 2> /dev/null; }
# frames N FILE: read the stream until N frames came (a condition, not a time: under load the
# run is slower, not wrong), within a minute
frames() { timeout 60 curl -s -N "${URL}stream" | grep -m "$1" '^data: ' > "$2"; }
# wait_for FILE: until FILE exists (made by a helper in the background), within a minute
wait_for() { for _ in $(seq 1 1200); do [ -f "$1" ] && return 0; sleep 0.05; done; return 1; }
# last_frame FILE: the JSON of the last whole frame in FILE (a frame ends in a blank line; a
# stream cut by timeout can end inside a frame, which is not a frame)
last_frame() { awk '/^data: /{d=substr($0,7);next} /^$/{if(d!="")l=d;d=""} END{print l}' "$1"; }

mb 100000 > long.mote
start long.mote
case "$URL" in http://127.0.0.1:*/) ok ;; *) bad "the view is not on the loopback address: $URL" ;; esac
[ "$(curl -s -o page.html -w '%{http_code}' "$URL")" = 200 ] && grep -q '<title>mote live view</title>' page.html && ok || bad "the page is not served"
grep -q "new EventSource('/stream')" page.html && ! grep -qi 'src=.http\|href=.http' page.html && ok || bad "the page fetches something from the network"
[ "$(curl -s -o /dev/null -w '%{http_code}' "${URL}etc/passwd")" = 404 ] && ok || bad "another path is not 404"
[ "$(curl -s -o /dev/null -w '%{http_code}' "${URL}../../etc/passwd")" = 404 ] && ok || bad "a path with .. is not 404"
[ "$(curl -s -o /dev/null -w '%{http_code}' -X DELETE "$URL")" = 405 ] && ok || bad "DELETE is not refused with 405"
code=$(curl -s -o /dev/null -w '%{http_code}' -H "X-Big: $(head -c 40000 /dev/zero | tr '\0' a)" "$URL")
[ "$code" -ge 400 ] && ok || bad "an oversized request was answered with $code"
printf 'GARBAGE\r\n\r\n' > bad.req
curl -s -o /dev/null --max-time 2 "telnet://${URL#http://}" < bad.req 2> /dev/null
# the stream: frames at up to 30 a second (at most 64 in 2 s, however fast the run), each with
# the state's particles; and frames keep coming
timeout 2 curl -s -N "${URL}stream" > stream.txt
n=$(grep -c '^data: {' stream.txt)
[ "$n" -ge 1 ] && [ "$n" -le 64 ] && ok || bad "frames in 2 s: $n (expected at most 30 a second)"
frames 10 stream10.txt
[ "$(grep -c '^data: {' stream10.txt)" -eq 10 ] && ok || bad "the stream stopped: $(grep -c '^data: {' stream10.txt) frames"
last_frame stream.txt > frame.json
python3 - frame.json <<'EOF' && ok || bad "the last frame is not a mixing box of 2000 disks inside the box"
import json, sys
f = json.load(open(sys.argv[1]))
assert f["model"] == "mixing-box" and f["view"] == "2d", f.get("model")
assert len(f["x"]) == len(f["y"]) == len(f["c"]) == 2000 and f["r0"] == 0.005
assert set(f["c"]) == {0, 1}
x0, y0, x1, y1 = f["box"]
assert all(x0 < x < x1 for x in f["x"]) and all(y0 < y < y1 for y in f["y"])
assert f["frame"] >= 1 and "t = " in f["status"]
EOF
# pause: no frames while paused; resume: frames again
# the page is docs/live-view.html, byte for byte
cmp -s page.html "$SRC/docs/live-view.html" && ok || bad "the served page differs from docs/live-view.html (src/http/live_page.h is its copy)"
# other sites: a Host that is not this server (DNS rebinding) gets 421; pause and resume need the
# page's own header X-Mote-Control, and an Origin, if any, that is the page's
PORT=$(echo "$URL" | sed 's|.*:\([0-9]*\)/$|\1|')
[ "$(curl -s -o /dev/null -w '%{http_code}' -H 'Host: attacker.example' "$URL")" = 421 ] && ok || bad "a foreign Host header was answered"
[ "$(curl -s -o /dev/null -w '%{http_code}' -H "Host: attacker.example:$PORT" "$URL")" = 421 ] && ok || bad "a foreign Host with our port was answered"
[ "$(curl -s -o /dev/null -w '%{http_code}' -H "Host: localhost:$PORT" "$URL")" = 200 ] && ok || bad "Host: localhost:PORT refused"
[ "$(curl -s -o /dev/null -w '%{http_code}' -X POST -H 'Content-Type: application/x-www-form-urlencoded' -d x=1 "${URL}pause")" = 403 ] && ok || bad "a form POST /pause was accepted"
[ "$(curl -s -o /dev/null -w '%{http_code}' -X POST -H 'X-Mote-Control: 1' -H 'Origin: http://evil.example' "${URL}pause")" = 403 ] && ok || bad "POST /pause from another origin was accepted"
[ "$(curl -s -o /dev/null -w '%{http_code}' -X OPTIONS "${URL}pause")" = 405 ] && ok || bad "a CORS preflight was not refused"
frames 5 notpaused.txt
[ "$(grep -c '^data: ' notpaused.txt)" -eq 5 ] && ok || bad "a refused pause paused the run"
# 64 connections (all the server's slots) that never finish their headers, each trickling a header
# line every 2 s (below the idle timeout), leave room for a new viewer: a connection whose request
# head is not in after 5 s is cut (issue 52: they held every slot for as long as they trickled)
python3 - "$URL" <<'EOF' &
import os, socket, sys, time
host, port = sys.argv[1][len("http://"):].rstrip("/").split(":")
socks = []
for _ in range(64):
    try:
        s = socket.create_connection((host, int(port)))
        s.sendall(b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n")
        socks.append(s)
    except OSError:
        pass
open("slow.ready", "w").close()
last = time.time()
for _ in range(1200):  # held, trickling, until the test is done with them
    if os.path.exists("slow.done"):
        break
    if time.time() - last >= 2:
        last = time.time()
        for s in socks:
            try:
                s.sendall(b"X-a: 1\r\n")
            except OSError:
                pass
    time.sleep(0.05)
EOF
SLOW=$!
wait_for slow.ready
got=
for _ in $(seq 1 60); do # (retried until a viewer gets in, at most 30 s)
    got=$(curl -s -o /dev/null --max-time 5 -w '%{http_code}' "$URL")
    [ "$got" = 200 ] && break
    sleep 0.5
done
[ "$got" = 200 ] && ok || bad "64 trickling connections kept a new viewer out (last answer: $got)"
touch slow.done
wait "$SLOW" 2> /dev/null
C='X-Mote-Control: 1'
[ "$(curl -s -X POST -H "$C" "${URL}pause")" = paused ] && ok || bad "pause"
# (a new viewer gets the newest frame at once, and one more if the run was publishing as the
# pause came; then nothing)
timeout 1.5 curl -s -N "${URL}stream" > paused.txt
[ "$(grep -c '^data: ' paused.txt)" -le 2 ] && ok || bad "frames while paused: $(grep -c '^data: ' paused.txt)"
[ "$(curl -s -X POST -H "$C" "${URL}resume")" = running ] && ok || bad "resume"
frames 5 resumed.txt
[ "$(grep -c '^data: ' resumed.txt)" -eq 5 ] && ok || bad "no frames after resume"
# a viewer that stops reading (its socket never read) does not stop the run
python3 - "$URL" <<'EOF' &
import os, socket, sys, time
host, port = sys.argv[1][len("http://"):].rstrip("/").split(":")
s = socket.create_connection((host, int(port)))
s.sendall(b"GET /stream HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")
open("stall.ready", "w").close()
for _ in range(1200):  # never reads, until the other viewer is done
    if os.path.exists("stall.done"):
        break
    time.sleep(0.05)
EOF
STALL=$!
wait_for stall.ready
frames 20 other.txt
touch stall.done
[ "$(grep -c '^data: ' other.txt)" -eq 20 ] && ok || bad "a stalled viewer stopped the others: $(grep -c '^data: ' other.txt) frames"
a=$(grep '"status":"t = ' other.txt | head -1 | sed 's/.*"status":"t = \([0-9.e+-]*\) s.*/\1/')
b=$(grep '"status":"t = ' other.txt | tail -1 | sed 's/.*"status":"t = \([0-9.e+-]*\) s.*/\1/')
awk -v a="$a" -v b="$b" 'BEGIN { exit !(b + 0 > a + 0) }' && ok || bad "the run did not advance with a stalled viewer: t $a -> $b"
wait "$STALL" 2> /dev/null
stop

# the same results with and without the view (a viewer reading all along)
mb 30 'snapshot end.xyz\n' > short.mote
"$MOTE" run short.mote > plain.txt 2>&1 && mv end.xyz plain.xyz && ok || bad "the plain run failed"
start short.mote
timeout 300 curl -s -N "${URL}stream" > all.txt & # (the run's end closes it; the limit only guards a hang)
CURL=$!
wait "$PID"
wait "$CURL" 2> /dev/null # the run's end closes the stream; curl reads it to the end
cmp -s plain.xyz end.xyz && ok || bad "the run differs with the live view"
# the frame after the last command is the final state: the positions of end.xyz to the
# frame's precision (5 significant digits of the 2 m box)
last_frame all.txt > last.json
python3 - last.json end.xyz <<'EOF' && ok || bad "the last frame's positions are not the state's"
import json, sys
f = json.load(open(sys.argv[1]))
lines = open(sys.argv[2]).read().split("\n")
n = int(lines[0])
pos = [tuple(map(float, l.split()[1:3])) for l in lines[2:2 + n]]
assert len(f["x"]) == n == 2000, (len(f["x"]), n)
assert "t = 30 s" in f["status"], f["status"]
worst = max(max(abs(f["x"][i] - pos[i][0]), abs(f["y"][i] - pos[i][1])) for i in range(n))
assert worst <= 1e-4, worst
EOF
[ "$(grep -v '^live:' live_out.txt | sed 's/ wall_seconds=.*//')" = "$(sed 's/ wall_seconds=.*//' plain.txt)" ] && ok || bad "the printed output differs with the live view"

# bind= and the script command; a taken port is an error at its line
printf 'model mixing-box\nlive http 0 bind=127.0.0.1\n' > cmd.mote
"$MOTE" run cmd.mote > out.txt 2> err.txt && grep -q '^live: open http://127.0.0.1:' out.txt && ok || bad "live http: $(cat out.txt err.txt)"
expect 1 "bad1.mote:2:" bad1.mote 'model mixing-box\nlive ftp\n'
expect 1 "bad2.mote:2:" bad2.mote 'model mixing-box\nlive http 70000\n'
expect 1 "bad3.mote:2:" bad3.mote 'model mixing-box\nlive http 0 host=x\n'
expect 2 "bad4.mote:2:" bad4.mote 'model mixing-box\nlive http 0 bind=999.1.1.1\n'

# a real browser: discs of both colours, and a frame counter that advances
if command -v chromium > /dev/null 2>&1; then
    # (the sanitized pass leaves the page's own behaviour, the screenshots and the frame counter,
    # to the plain pass: the browser's requests to the server, the C code, are the panel test's)
    if [ -z "${MOTE_SANITIZED:-}" ]; then
        start long.mote
        # (?frames=20: the page stops listening after 20 frames, so the headless browser's virtual
        # time can run out while the run goes on)
        # (the screenshots: the page as a user opens it, no test parameter, 4 s after it loads, in a
        # 1200 x 800 window)
        # colours.py PNG...: each screenshot shows many discs of both colours (read by Debian's
        # matplotlib, as test_plot.sh reads the PNGs)
        cat > colours.py <<'EOF'
import sys
import numpy as np
import matplotlib.image as im
for path in sys.argv[1:]:
    a = np.rint(im.imread(path)[60:, :, :3] * 255).astype(int)
    # colour 0 and colour 1 as the PNGs draw them (mote_class_colour_hex: #0072b2, #d55e00)
    near = lambda q: (np.abs(a - np.array(q)) <= 12).all(axis=2).sum()
    c0, c1 = near((0x00, 0x72, 0xb2)), near((0xd5, 0x5e, 0x00))
    assert c0 > 500 and c1 > 500, (path, c0, c1)
EOF
        # (4 s after loading; on a loaded machine the browser may start slowly: again with 8 and
        # 16 s until the discs show, a condition rather than a fixed wait)
        shot() {
            for ms in 4000 8000 16000; do
                timeout 60 chromium --headless=new --no-sandbox --disable-gpu --hide-scrollbars \
                    --window-size=1200,800 --timeout=$ms --screenshot="$PWD/$1" "$URL" > /dev/null 2>&1
                /usr/bin/python3 colours.py "$1" 2> /dev/null && return 0
            done
            return 1
        }
        dom() {
            timeout 60 chromium --headless=new --no-sandbox --disable-gpu --virtual-time-budget=3000 \
                --dump-dom "${URL}?frames=20" 2> /dev/null | sed -n 's/.*id="counter">frame \([0-9]*\)<.*/\1/p'
        }
        shot shot1.png
        c1=$(dom)
        c2=$c1
        for _ in 1 2 3 4 5; do # until the counter has moved (each load takes a few seconds)
            c2=$(dom)
            [ -n "$c1" ] && [ -n "$c2" ] && [ "$c2" -gt "$c1" ] && break
        done
        shot shot2.png
        stop
        [ -n "$c1" ] && [ -n "$c2" ] && [ "$c2" -gt "$c1" ] && ok || bad "the page's frame counter did not advance: '$c1' then '$c2'"
        /usr/bin/python3 colours.py shot1.png shot2.png && ok || bad "the screenshots do not show discs of both colours (those of the PNGs)"
        cp shot2.png "${TMPDIR:-/tmp}/mote-live-shot.png" 2> /dev/null
    fi
    # hard spheres in a 1200 x 800 window: the picture and the density panel side by side,
    # both inside the window (the canvases are sized from it; 1 px borders, 10 px padding,
    # 8 px between)
    printf 'new 3 0.4\nstep 100000000\n' > hslive.mote
    start hslive.mote
    timeout 60 chromium --headless=new --no-sandbox --disable-gpu --window-size=1200,800 \
        --virtual-time-budget=3000 --dump-dom "${URL}?frames=5" 2> /dev/null > hsdom.html
    stop
    cw=$(sed -n 's/.*<canvas id="c" width="\([0-9]*\)" height="\([0-9]*\)".*/\1 \2/p' hsdom.html)
    pw=$(sed -n 's/.*<canvas id="p" width="\([0-9]*\)" height="\([0-9]*\)" style="display: block;".*/\1 \2/p' hsdom.html)
    set -- $cw $pw
    [ $# -eq 4 ] && [ $(($1 + $3 + 4 + 8 + 20)) -le 1200 ] && [ "$2" -le 760 ] && [ "$4" -le 760 ] && [ "$3" -ge 200 ] &&
        ok || bad "the panels do not fit a 1200 x 800 window: picture '$cw', profile '$pw'"
else
    echo "test_live.sh: no chromium (scripts/setup.sh installs it): the browser test is skipped"
    bad "chromium is missing"
fi

# on a terminal a short run's page stays until Enter (issue 52: it vanished when the run ended);
# the program waits for the line, then ends (exit 0)
printf 'new 2 0.3\nstep 10\n' > short.mote
python3 - "$MOTE" short.mote <<'EOF' > short_tty.txt 2>&1 && ok || bad "the live page on a terminal: $(cat short_tty.txt)"
import os, pty, sys, time
pid, fd = pty.fork()
if pid == 0:
    os.execv(sys.argv[1], [sys.argv[1], "run", "--live=0", sys.argv[2]])
out, deadline, sent = b"", time.time() + 60, False
while time.time() < deadline:
    try:
        d = os.read(fd, 4096)
    except OSError:
        break
    if not d:
        break
    out += d
    if not sent and b"press Enter" in out:
        assert b"live: open http://" in out, out
        os.write(fd, b"\n")
        sent = True
_, st = os.waitpid(pid, 0)
assert sent and os.waitstatus_to_exitcode(st) == 0, (sent, st, out)
EOF
mote_test_end
