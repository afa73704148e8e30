#!/usr/bin/env bash
# Times the real viewer window under Xvfb with Mesa, from the viewer's own log
# (REALIST_VIEWER_LOG): the time from launch to the first frame of the model, the CPU an
# idle window uses over 5 s, and frame times while the model is orbited by a mouse drag
# (xdotool), for a 1280x720 viewport by default (side panels hidden).
#
#   cargo build --release
#   benches/viewer-timings.sh ../shared/models/obj/stanford-bunny.obj [ignored] [SECONDS]
# (an untextured model is shown in Phong mode by default)
#
# Needs: xvfb xauth libgl1-mesa-dri libegl1 ... (see README), xdotool, python3.
set -euo pipefail
model=$1
secs=${3:-5}
root=$(cd "$(dirname "$0")/.." && pwd)
bin=$root/target/release/realist
display=:97
log=$(mktemp)
Xvfb $display -screen 0 1600x1000x24 >/dev/null 2>&1 &
xpid=$!
trap 'kill $vpid $xpid 2>/dev/null || true; rm -f $log' EXIT
sleep 1
export DISPLAY=$display
# 1280 x (720 + menu bar + status bar) points: a 1280x720 viewport.
REALIST_VIEWER_LOG=$log "$bin" view "$model" --window 1280x770 --no-panels >/dev/null 2>&1 &
vpid=$!
clk=$(getconf CLK_TCK)
ticks() { awk '{print $14 + $15}' /proc/$vpid/stat; }
# Wait for the model's final frame (the first job whose scene is not empty ends with
# a "last" frame; here: no new frame for 1.5 s after the first one).
for _ in $(seq 1 300); do
    grep -q '"event":"frame"' "$log" && break
    sleep 0.1
done
settle() {
    local n=0 last
    while true; do
        last=$(grep -c '"event":"frame"' "$log" || true)
        sleep 1.5
        [ "$(grep -c '"event":"frame"' "$log" || true)" = "$last" ] && break
        n=$((n + 1)); [ $n -gt 40 ] && break
    done
}
settle
t0=$(ticks); sleep 5; t1=$(ticks)
idle=$(python3 -c "print(f'{($t1 - $t0) / $clk / 5 * 100:.2f}')")
# Orbit: drag right across the viewport centre for $secs seconds, 125 moves a second (faster
# than frames can come, so the renderer, not the mouse, sets the pace), in one xdotool run.
drag_start=$(python3 -c "import json;print(max(json.loads(l)['t_ms'] for l in open('$log')))")
moves=$(python3 -c "print(' '.join(['mousemove_relative 2 0 sleep 0.008'] * int($secs * 125)))")
# shellcheck disable=SC2086
xdotool mousemove 640 400 mousedown 1 $moves mouseup 1
sleep 2
python3 - "$log" "$drag_start" "$idle" <<'EOF'
import json, statistics, sys
log, start, idle = sys.argv[1], float(sys.argv[2]), sys.argv[3]
ev = [json.loads(l) for l in open(log)]
frames = [e for e in ev if e["event"] == "frame"]
model = [f for f in frames if f["job"] >= 2] or frames
first = min(f["t_ms"] for f in frames)
first_model = min(f["t_ms"] for f in model if f["level"].startswith("full"))
drag = [f for f in frames if f["t_ms"] > start]
moving = [f for f in drag if "moving" in f["level"]] or drag
gaps = [b["t_ms"] - a["t_ms"] for a, b in zip(drag, drag[1:])]
ui = [e["ui_ms"] for e in ev if e["event"] == "ui" and e["t_ms"] > start]
levels = sorted({f["level"] for f in drag})
print(json.dumps({
    "first_frame_ms": round(first, 1),
    "first_model_frame_ms": round(first_model, 1),
    "idle_cpu_percent": float(idle),
    "orbit_frames": len(drag),
    "orbit_levels": levels,
    "orbit_frame_size": f'{moving[0]["width"]}x{moving[0]["height"]}' if moving else None,
    "orbit_render_ms_median": round(statistics.median(f["render_ms"] for f in moving), 2) if moving else None,
    "orbit_frame_interval_ms_median": round(statistics.median(gaps), 2) if gaps else None,
    "ui_pass_ms_median": round(statistics.median(ui), 3) if ui else None,
}, indent=1))
EOF
