#!/usr/bin/env bash
# The capture console's cost per shot (issue 53; figures in docs/benchmarks.md, "Capture
# console"): `mesocap capture` from the fake camera, a shot every 0.5 s, against `mesocap console
# --no-guide` on the same photos with 20 event-stream clients (plain sockets) watching while a
# script presses the shot button every 0.5 s. A shot's overhead is mesocap's own time for it:
# capture's checks, fsync, rename, EXIF read-back and journal, and with the console its hook (the
# state's update and the event to every stream); the target is within 20 ms of capture alone.
# Also checks that every client received every shot's event.
#
#   bench/console_bench.sh [BUILD_DIR] [SHOTS]      (defaults: build, 40)
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$repo/build}" && pwd)"
shots="${2:-40}"
mesocap="$build/app/mesocap"
work="$(mktemp -d)"
console_pid=""
trap '[ -n "$console_pid" ] && kill "$console_pid" 2>/dev/null; rm -rf "$work"' EXIT

# Full-size JPEGs, as a 24 MP body writes them.
mkdir -p "$work/photos"
for i in 1 2 3; do
  oiiotool --pattern noise:type=gaussian:mean=0.5:stddev=0.05 6000x4000 3 --attrib:type=int Exif:Flash 1 -d uint8 \
    -o:quality=85 "$work/photos/p$i.jpg"
done
echo "console bench: $shots shots of $(stat -c %s "$work/photos/p1.jpg") bytes (6000x4000 JPEG), one every 0.5 s"

"$mesocap" capture --out "$work/plain" --camera fake --port "$work/photos" --shots "$shots" --interval 0.5 --no-progress > /dev/null
/usr/bin/python3 - "$work/plain/capture_report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
o = [s["overhead_s"] * 1000 for s in r["shots"]]
print(f"console bench: capture alone: overhead per shot mean {sum(o) / len(o):.1f} ms, max {max(o):.1f} ms")
PY

"$mesocap" console "$work/console" --camera fake --port "$work/photos" --no-guide --listen 127.0.0.1:0 > "$work/console.log" 2>&1 &
console_pid=$!
for _ in $(seq 100); do grep -q "on http" "$work/console.log" && break; sleep 0.1; done
port=$(grep -o "127.0.0.1:[0-9]*" "$work/console.log" | head -1 | cut -d: -f2)
/usr/bin/python3 - "$port" "$shots" "$work/plain/capture_report.json" <<'PY'
import json, socket, sys, threading, time, urllib.request
port, shots = int(sys.argv[1]), int(sys.argv[2])
base = f"http://127.0.0.1:{port}"
received = [set() for _ in range(20)]

def watch(k):
    s = socket.create_connection(("127.0.0.1", port))
    s.sendall(f"GET /api/events HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n".encode())
    text = ""
    while len(received[k]) < shots:
        data = s.recv(65536)
        if not data:
            break
        text += data.decode(errors="replace")
        while "\n\n" in text:
            block, text = text.split("\n\n", 1)
            for line in block.splitlines():
                if line.startswith("data: "):
                    event = json.loads(line[6:])
                    if event.get("type") == "shot":
                        received[k].add(event["file"])
    s.close()

watchers = [threading.Thread(target=watch, args=(k,)) for k in range(20)]
for w in watchers:
    w.start()
time.sleep(0.5)
start = time.time()
for i in range(shots):
    time.sleep(max(0.0, start + 0.5 * i - time.time()))
    urllib.request.urlopen(urllib.request.Request(base + "/api/shot", data=b"", method="POST"))
for w in watchers:
    w.join(60)
state = json.load(urllib.request.urlopen(base + "/api/state"))
o = [s["overhead_s"] * 1000 for s in state["shots"] if "overhead_s" in s]
plain = json.load(open(sys.argv[3]))
p = [s["overhead_s"] * 1000 for s in plain["shots"]]
print(f"console bench: console, 20 streams watching: overhead per shot mean {sum(o) / len(o):.1f} ms, "
      f"max {max(o):.1f} ms ({len(o)} shots): {sum(o) / len(o) - sum(p) / len(p):+.1f} ms against capture alone "
      f"(target within 20 ms)")
complete = sum(1 for r in received if len(r) == shots)
print(f"console bench: {complete} of 20 streams received every shot's event")
PY
kill "$console_pid"
wait "$console_pid" || true
console_pid=""
