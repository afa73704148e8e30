"""The regression guard of benches/peer.sh: compares each row's speed-up over llvmpipe with
the one recorded in benches/peer-record.md, and rewrites that record on request.

    peer_record.py row RECORD TSV MESH RES MODE LLVMPIPE_MS REALIST_MS DIFF
        prints the row of peer.sh's table (with the comparison) and appends it to TSV
    peer_record.py record RECORD TSV
        writes the speed-ups in TSV into RECORD (rows not in TSV keep their values)
    peer_record.py verdict RECORD TSV
        exits with status 3, naming the rows, if a row lost more than a fifth of its record

A speed-up is a ratio of two times measured in one run, so it is what compares between runs
on this shared machine; the absolute times are kept in the record for reference only.
"""

import datetime
import re
import subprocess
import sys

# A row is flagged when its speed-up is below this fraction of the recorded one.
KEEP = 0.8

ROW = re.compile(r"^\|\s*([a-z0-9]+/[0-9]+x[0-9]+/[a-z]+)\s*\|\s*([0-9.]+)x?\s*\|(.*)$")


def read_record(path):
    """The recorded rows of `path`: {row: (speed-up, the rest of the line)}."""
    rows = {}
    try:
        with open(path, encoding="utf-8") as f:
            for line in f:
                m = ROW.match(line.strip())
                if m:
                    rows[m.group(1)] = (float(m.group(2)), m.group(3))
    except FileNotFoundError:
        pass
    return rows


def num(s, fmt):
    try:
        return fmt % float(s)
    except ValueError:
        return s


def row(record, tsv, mesh, res, mode, lp, rl, diff):
    name = f"{mesh}/{res}/{mode}"
    try:
        speedup = float(lp) / float(rl)
    except (ValueError, ZeroDivisionError):
        speedup = None
    recorded = read_record(record).get(name)
    flagged = False
    if speedup is None:
        against = "n/a"
    elif recorded is None:
        against = "not recorded"
    else:
        change = speedup / recorded[0] - 1
        flagged = speedup < KEEP * recorded[0]
        against = "%.2fx recorded, %+.0f%%%s" % (
            recorded[0],
            100 * change,
            " **LOST MORE THAN A FIFTH**" if flagged else "",
        )
    shown = "n/a" if speedup is None else "%.2fx" % speedup
    print(
        "| %s | %s | %s | %s | %s | %s | %s | %s |"
        % (mesh, res, mode, num(lp, "%.1f"), num(rl, "%.1f"), shown, num(diff, "%.2f"), against)
    )
    with open(tsv, "a", encoding="utf-8") as f:
        f.write("%s\t%s\t%s\t%s\t%d\n" % (name, "" if speedup is None else speedup, lp, rl, flagged))


def runs(tsv):
    with open(tsv, encoding="utf-8") as f:
        for line in f:
            name, speedup, lp, rl, flagged = line.rstrip("\n").split("\t")
            yield name, speedup, lp, rl, flagged == "1"


def record(path, tsv):
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=False
    ).stdout.strip() or "unknown commit"
    today = datetime.date.today().isoformat()
    new = {
        name: " %s | %s | %s, %s |" % (num(lp, "%.1f"), num(rl, "%.1f"), today, commit)
        for name, speedup, lp, rl, _ in runs(tsv)
        if speedup
    }
    speedups = {name: float(s) for name, s, _, _, _ in runs(tsv) if s}
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    out, seen = [], set()
    for line in lines:
        m = ROW.match(line.strip())
        if m and m.group(1) in new:
            name = m.group(1)
            seen.add(name)
            out.append("| %s | %.2fx |%s" % (name, speedups[name], new[name]))
        else:
            out.append(line)
    for name in new:
        if name not in seen:
            out.append("| %s | %.2fx |%s" % (name, speedups[name], new[name]))
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")
    print("peer.sh: recorded %d row(s) in %s" % (len(new), path), file=sys.stderr)


def verdict(path, tsv):
    lost = [name for name, _, _, _, flagged in runs(tsv) if flagged]
    if not lost:
        print("peer.sh: no row lost more than a fifth of its recorded speed-up", file=sys.stderr)
        return 0
    print(
        "peer.sh: %d row(s) lost more than a fifth of the speed-up recorded in %s: %s "
        "(a regression to fix or to justify; run the row again to rule out a burst on the "
        "shared machine)" % (len(lost), path, ", ".join(lost)),
        file=sys.stderr,
    )
    return 3


def main(argv):
    cmd = argv[1] if len(argv) > 1 else ""
    if cmd == "row" and len(argv) == 10:
        row(*argv[2:])
        return 0
    if cmd == "record" and len(argv) == 4:
        record(argv[2], argv[3])
        return 0
    if cmd == "verdict" and len(argv) == 4:
        return verdict(argv[2], argv[3])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
