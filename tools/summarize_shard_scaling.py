#!/usr/bin/env python3
"""Summarise bench/shard_scaling.sh: per method, the unsharded render, the shards' times for each
shard count, the merge, and the scaling model of docs/distributed.md fitted to them.

Model (one machine per shard, all starting together): a shard's wall time is
    t(N) = a + b / N
where `a` is what every shard pays whatever N (process start, scene load and BVH, and the setup
every shard repeats: photon maps for pm, the eye pass and the count for pds) and `b` the work
split N ways; the render ends with the slowest shard, then the merge, which reads every part:
    T(N) = max_i t_i(N) + m0 + B(N) / R
with B(N) the parts' bytes (one film for row-split methods, N films for the others) and R the
merge's measured read rate. The speed-up is S(N) = T_whole / T(N). Fitted by least squares on
the mean shard wall time per N; the slowest shard is modelled as the mean (shards are balanced
to within one unit), which the measured max/mean column checks.

    python3 tools/summarize_shard_scaling.py docs/results/distributed
"""

import csv
import sys
from collections import defaultdict
from pathlib import Path


def fit(points):
    """Least-squares a, b of t = a + b x over (x, t) points, with a >= 0 and b >= 0."""
    n = len(points)
    sx = sum(x for x, _ in points)
    st = sum(t for _, t in points)
    sxx = sum(x * x for x, _ in points)
    sxt = sum(x * t for x, t in points)
    den = n * sxx - sx * sx
    if n < 2 or den == 0:
        return st / max(n, 1), 0.0
    b = (n * sxt - sx * st) / den
    a = (st - b * sx) / n
    if a < 0:  # noise: the fixed cost is below what the timings resolve
        return 0.0, sxt / sxx
    if b < 0:
        return st / n, 0.0
    return a, b


def main(out_dir):
    out = Path(out_dir)
    rows = list(csv.DictReader(open(out / "results.csv")))
    whole = {}
    shards = defaultdict(lambda: defaultdict(list))
    merges = {}
    for r in rows:
        m, n = r["method"], int(r["shards"])
        if n == 0:
            whole[m] = (float(r["wall_seconds"]), float(r["render_seconds"] or 0))
        elif r["shard"] == "merge":
            merges[(m, n)] = (float(r["part_bytes"]), float(r["merge_seconds"]), r["identical"])
        else:
            shards[m][n].append(
                (float(r["wall_seconds"]), float(r["render_seconds"] or 0), int(r["part_bytes"]))
            )
    lines = [
        "# Sharded renders: measurements and the scaling model",
        "",
        "Measured by `bash bench/shard_scaling.sh` (each shard run alone with `--threads 2`, one",
        "after another, as a 2-core machine would run it; this machine is shared, so single",
        "timings carry a few per cent of noise). Summarised by `tools/summarize_shard_scaling.py`.",
        "",
        "## Shards against the unsharded render",
        "",
        "| method | N | identical bytes | mean shard wall (s) | max/mean | sum of shard walls / unsharded | merge (s) | parts (MB) | merge read rate (MB/s) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    models = {}
    rates = []
    for m in whole:
        w, _ = whole[m]
        pts = []
        for n in sorted(shards[m]):
            walls = [s[0] for s in shards[m][n]]
            mean = sum(walls) / len(walls)
            pts.append((1.0 / n, mean))
            b, ms, same = merges.get((m, n), (0.0, 0.0, "?"))
            if ms > 0 and b > 0:
                rates.append(b / 1e6 / ms)
            lines.append(
                f"| {m} | {n} | {same} | {mean:.2f} | {max(walls) / mean:.2f} | "
                f"{sum(walls) / w:.2f} | {ms:.2f} | {b / 1e6:.1f} | "
                f"{(b / 1e6 / ms) if ms > 0 else 0:.0f} |"
            )
        a, bb = fit(pts)
        part1 = shards[m][1][0][2] if 1 in shards[m] else 0
        per_film = part1
        row_split = m in ("path", "pm", "pm-auto")
        models[m] = (a, bb, w, per_film, row_split)
    # Merge time against the bytes read, over every merge: m0 + bytes / rate.
    mpts = [(b / 1e6, ms) for (b, ms, _) in merges.values()]
    m0, per_mb = fit(mpts)
    rate = 1.0 / per_mb if per_mb > 0 else float("inf")
    lines += [
        "",
        "## The model fitted",
        "",
        f"Merge, fitted over every merge above: {m0:.3f} s (process start, the image written) plus",
        f"the parts' bytes at {rate:.0f} MB/s (read, checksum, decode, add). Row-split methods (path, pm and the other",
        "one-shot photon methods) store only their rows' camera sums: their parts add up to one",
        "film whatever N. The others store a whole film per shard (100 bytes per pixel at most; a",
        "light tracer's 48), so their merge reads N films.",
        "",
        "| method | a: per shard whatever N (s) | b: split work (s) | a / unsharded | predicted speed-up at N = 2 | 8 | 64 | 256 | 1000 | N where efficiency falls below 50 % | at N = 1000 the time goes to | N = 1000 with a two-level merge |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for m, (a, bb, w, per_film, row_split) in models.items():
        def total(n):
            parts = per_film if row_split else per_film * n
            return a + bb / n + m0 + parts / 1e6 / rate

        def speedup(n):
            return w / total(n)

        half = next((n for n in range(1, 100001) if speedup(n) / n < 0.5), None)
        cells = " | ".join(f"{speedup(n):.1f}" for n in (2, 8, 64, 256, 1000))
        n = 1000
        parts = per_film if row_split else per_film * n
        terms = {
            "per-shard setup": a,
            "the split work": bb / n,
            "the merge": m0 + parts / 1e6 / rate,
        }
        tot = sum(terms.values())
        where = ", ".join(f"{k} {100 * v / tot:.0f} %" for k, v in terms.items())
        # A two-level merge (not implemented): √N merges of √N parts in parallel, then one of
        # √N merged parts; each reads √N films.
        k = n ** 0.5
        tree = (
            m0 + per_film / 1e6 / rate
            if row_split  # one film in all: nothing to gain
            else 2 * (m0 + per_film * k / 1e6 / rate)
        )
        tree_speedup = w / (a + bb / n + tree)
        lines.append(
            f"| {m} | {a:.2f} | {bb:.2f} | {a / w:.2f} | {cells} | "
            f"{half if half else '> 10^5'} | {where} | {tree_speedup:.1f} |"
        )
    wpath = out / "workers.csv"
    if wpath.exists():
        lines += [
            "",
            "## Two local workers against one process",
            "",
            "| method | setup | seconds (mean of rounds) | identical to the 1-thread render |",
            "|---|---|---|---|",
        ]
        groups = defaultdict(list)
        same = {}
        for r in csv.DictReader(open(wpath)):
            groups[(r["method"], r["setup"])].append(float(r["seconds"]))
            if r["identical"]:
                same[(r["method"], r["setup"])] = r["identical"]
        for (m, setup), secs in groups.items():
            lines.append(
                f"| {m} | {setup} | {sum(secs) / len(secs):.2f} | {same.get((m, setup), '')} |"
            )
    (out / "README.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/results/distributed")
