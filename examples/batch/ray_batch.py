"""Render a turntable of every model in a folder with Ray: one task per shard, each task
running `realist batch --shard I/N` as a subprocess, all writing into one output folder
(on a shared file system when the cluster has several machines).

    python examples/batch/ray_batch.py /shared/models /shared/renders --shards 8 --cpus 4

realist must be on the PATH of every worker (or pass --realist /path/to/realist). Running the
script again skips the models already done (status ok in a manifest of the output folder).
"""

import argparse
import json
import pathlib
import subprocess

import ray


def run_shard(realist, models, out, index, count, threads, extra):
    """Runs shard index/count (1-based); returns (index, exit status, ok, failed)."""
    cmd = [
        realist, "batch", models,
        "--shard", f"{index}/{count}",
        "--threads", str(threads),
        "--out", out,
        *extra,
    ]
    # Exit status 3: some models failed (the manifest says which); anything else non-zero is
    # a mistake in the command or the folder.
    status = subprocess.run(cmd, check=False).returncode
    manifest = pathlib.Path(out) / f"manifest.shard-{index}-of-{count}.jsonl"
    # The manifest keeps the lines of earlier runs too: an item's last line is its status.
    last = {}
    if manifest.exists():
        for line in manifest.read_text().splitlines():
            if line.strip():
                record = json.loads(line)
                last[record["item"]] = record["status"]
    ok = sum(1 for s in last.values() if s == "ok")
    return index, status, ok, len(last) - ok


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("models", help="folder of models (searched recursively)")
    p.add_argument("out", help="output folder, shared by every task")
    p.add_argument("--shards", type=int, default=8, help="number of Ray tasks")
    p.add_argument("--cpus", type=int, default=4, help="cores (render threads) per task")
    p.add_argument("--realist", default="realist", help="the realist program")
    p.add_argument("--address", default=None, help="Ray cluster address (default: local)")
    args = p.parse_args()

    ray.init(address=args.address)
    # Each task reserves --cpus cores and renders with that many threads.
    task = ray.remote(num_cpus=args.cpus)(run_shard)
    extra = ["--turntable", "36", "--size", "640x480", "--timeout", "300"]
    models = str(pathlib.Path(args.models).resolve())
    out = str(pathlib.Path(args.out).resolve())
    futures = [
        task.remote(args.realist, models, out, i, args.shards, args.cpus, extra)
        for i in range(1, args.shards + 1)
    ]
    errors = 0
    for index, status, ok, failed in ray.get(futures):
        print(f"shard {index}/{args.shards}: exit status {status}, {ok} ok, {failed} failed")
        if status not in (0, 3):
            errors += 1
    raise SystemExit(1 if errors else 0)


if __name__ == "__main__":
    main()
