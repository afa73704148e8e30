#!/usr/bin/env bash
# realist against Mesa llvmpipe, row by row in one run: for each row the llvmpipe peer
# (../shared/peer/bench_llvmpipe.py, LP_NUM_THREADS=$THREADS) and `realist bench frame` on the
# same scene (--threads $THREADS), alternating (realist runs once before and twice after
# llvmpipe; its time is the median of the three runs' medians), then a markdown table with the speed-up
# (llvmpipe ms / realist ms) and a cross-check of the two images: the mean absolute
# difference in 8-bit units over interior pixels (`realist bench diff`: pixels whose 3x3
# neighbourhood is covered in both images; silhouettes against the background left out).
#
# Usage: benches/peer.sh [MESH/WxH/MODE ...]     e.g. benches/peer.sh bunny/640x480/phong
#   meshes: bunny spot teapot suzanne (../shared/models/obj), sphere1m sphere4m (generated)
#   modes:  phong gouraud flat tex (the peer's names)
# Environment:
#   QUICK=1          three rows only (teapot 1920x1080 phong, bunny 1920x1080 gouraud,
#                    spot 1920x1080 tex)
#   REALIST_SHARED   the shared folder (default ../shared next to this repository)
#   THREADS          threads for both renderers (default 2)
#   ROUNDS           the peer's rounds (default 5)
#   OUT              folder for the PNGs and JSON lines (default: a new folder in /tmp)
#   LLVMPIPE_VENV    the peer's Python venv (default /tmp/llvmpipe-venv; set up if missing)
#   RECORD=1         write this run's speed-ups into benches/peer-record.md (rows not run
#                    keep their recorded values)
#
# The regression guard: each row's speed-up is compared with the one recorded for that row in
# benches/peer-record.md (the last column); a row that lost more than a fifth of its recorded
# speed-up is flagged, and the script then exits with status 3 after the table. Run it (QUICK=1
# at least) before stopping whenever the render path changed.
set -euo pipefail

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
shared=$(cd "${REALIST_SHARED:-$repo/../shared}" && pwd) || {
    echo "peer.sh: no shared folder (set REALIST_SHARED)" >&2
    exit 1
}
venv=${LLVMPIPE_VENV:-/tmp/llvmpipe-venv}
threads=${THREADS:-2}
rounds=${ROUNDS:-5}
out=${OUT:-$(mktemp -d /tmp/realist-peer.XXXXXX)}
mkdir -p "$out"

if [ ! -x "$venv/bin/python" ]; then
    echo "peer.sh: setting up llvmpipe in $venv" >&2
    bash "$shared/peer/setup.sh" "$venv" >&2
fi
py=$venv/bin/python

echo "peer.sh: cargo build --release" >&2
(cd "$repo" && cargo build --release --quiet)
realist=${CARGO_TARGET_DIR:-$repo/target}/release/realist

if [ $# -gt 0 ]; then
    rows=("$@")
elif [ "${QUICK:-0}" = 1 ]; then
    rows=(teapot/1920x1080/phong bunny/1920x1080/gouraud spot/1920x1080/tex)
else
    rows=(teapot/1920x1080/phong teapot/1920x1080/gouraud
          bunny/1920x1080/phong bunny/1920x1080/gouraud bunny/640x480/phong
          spot/1920x1080/phong spot/1920x1080/flat spot/1920x1080/tex
          sphere1m/1920x1080/phong)
fi

# The peer's mesh names as realist models.
model() {
    case $1 in
        bunny) echo "$shared/models/obj/stanford-bunny.obj" ;;
        spot | teapot | suzanne) echo "$shared/models/obj/$1.obj" ;;
        sphere1m) echo sphere:1000000 ;;
        sphere4m) echo sphere:4000000 ;;
        *) echo "peer.sh: unknown mesh '$1'" >&2; return 1 ;;
    esac
}

# field NAME < one JSON line: the value, or "n/a".
field() {
    "$py" -c 'import json, sys
line = sys.stdin.readline()
v = json.loads(line).get(sys.argv[1]) if line.strip() else None
print("n/a" if v is None else v)' "$1"
}

# One realist run of the current row, appended to its JSON lines. realist runs once before
# llvmpipe and twice after, and its time is the median of the three medians: a single
# 2-second window is at the mercy of the shared machine's bursts.
bench() {
    "$realist" bench frame "$m" --size "$res" --shading "$mode" --threads "$threads" \
        --png "$out/realist_$tag.png" >>"$out/$tag.realist.json"
}

record=$repo/benches/peer-record.md
: >"$out/speedups.tsv"
echo "| mesh | size | mode | llvmpipe ms | realist ms | speed-up | mean abs diff (8-bit) | against the record |"
echo "|---|---|---|---|---|---|---|---|"
for row in "${rows[@]}"; do
    IFS=/ read -r mesh res mode <<<"$row"
    m=$(model "$mesh")
    tag=${mesh}_${res}_${mode}
    : >"$out/$tag.realist.json"
    echo "peer.sh: $row: realist" >&2
    bench
    echo "peer.sh: $row: llvmpipe" >&2
    (cd "$shared/peer" && LP_NUM_THREADS=$threads "$py" bench_llvmpipe.py --mesh "$mesh" \
        --res "$res" --shading "$mode" --rounds "$rounds" --png "$out/peer") \
        | tail -n 1 >"$out/$tag.peer.json"
    echo "peer.sh: $row: realist" >&2
    bench
    bench
    lp=$(field ms_finish_median <"$out/$tag.peer.json")
    rl=$("$py" -c 'import json, statistics, sys
print(statistics.median(json.loads(l)["median_ms"] for l in sys.stdin if l.strip()))' \
        <"$out/$tag.realist.json")
    diff=n/a
    if [ -f "$out/peer_$tag.png" ]; then
        "$realist" bench diff "$out/realist_$tag.png" "$out/peer_$tag.png" >"$out/$tag.diff.json"
        diff=$(field mean_abs_diff <"$out/$tag.diff.json")
    fi
    "$py" "$repo/benches/peer_record.py" row "$record" "$out/speedups.tsv" \
        "$mesh" "$res" "$mode" "$lp" "$rl" "$diff"
done
echo "peer.sh: PNGs and JSON lines in $out" >&2
status=0
"$py" "$repo/benches/peer_record.py" verdict "$record" "$out/speedups.tsv" || status=$?
if [ "${RECORD:-0}" = 1 ]; then
    "$py" "$repo/benches/peer_record.py" record "$record" "$out/speedups.tsv"
    status=0
fi
exit "$status"
