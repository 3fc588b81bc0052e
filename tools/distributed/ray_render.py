#!/usr/bin/env python3
"""Render a caustica scene in shards as Ray tasks and merge them into the unsharded bytes.

    python3 ray_render.py --shards 64 -o out.exr [--png out.png] [--address auto | --num-cpus 8]
        [--cpus-per-shard 4] [--watch preview.exr] -- [SCENE] [caustica render options...]

Everything after `--` goes to `caustica render` (a scene file or built-in name, then options;
no scene for the default scene). Each shard is one Ray task that runs
`caustica render ... --shard I/N -o TMP/` in a temporary directory of its worker and returns the
part's bytes through the object store; the driver writes them to PARTS (default: OUT without
extension + .parts/, shard-IIII-of-NNNN.cpart), so the workers need no shared file system, only the
caustica binary at the same path (--caustica, default $CAUSTICA or `caustica` on PATH).

Failures: Ray runs a task again if its worker dies or caustica fails (--max-retries); a shard that
still fails is submitted again by the driver (--rounds); a usage error (exit status 2) is not
retried. A shard is idempotent by its index: a retry writes the same bytes to the same file.
--resume keeps the parts already in PARTS and renders the missing ones only.

Progress: a line per finished shard with the count, the elapsed time and an ETA (a tqdm bar if
tqdm is installed). --watch PREVIEW.exr runs `caustica merge --partial` after each finished shard,
so a preview of the shards done so far is always there. At the end `caustica merge` writes OUT.

Test hook: --inject-failure I (repeatable) makes the first attempt of shard I kill its own worker
process (os._exit) while caustica runs, or raise (--inject-mode raise); the attempt is recorded in
PARTS/.inject/, so this works on a local cluster or with a shared PARTS only.
"""

from __future__ import annotations

import argparse
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

USAGE_EXIT = 2  # clap's exit status for a bad command line: the same on every retry


class ShardFailed(RuntimeError):
    """caustica exited with an error that a retry may not repeat (retried by Ray)."""


class ShardUsageError(RuntimeError):
    """caustica rejected its command line: every retry would fail the same way."""


def shard_name(index: int, shards: int) -> str:
    return f"shard-{index:04d}-of-{shards:04d}.cpart"


def has_option(args: list[str], *flags: str) -> bool:
    return any(a == f or a.startswith(f + "=") for a in args for f in flags)


def render_shard(
    caustica: str,
    render_args: list[str],
    index: int,
    shards: int,
    inject: str | None,
    inject_marker: str | None,
    inject_delay: float,
) -> dict:
    """Body of the Ray task: renders shard `index` of `shards` and returns its part's bytes."""
    start = time.monotonic()
    exe = shutil.which(caustica) or caustica
    first_of_injected = False
    if inject and inject_marker:
        try:
            fd = os.open(inject_marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
        except FileExistsError:
            pass
        else:
            os.write(fd, f"{os.getpid()}\n".encode())
            os.close(fd)
            first_of_injected = True
    if first_of_injected and inject == "raise":
        raise ShardFailed(f"shard {index}: injected failure (first attempt)")
    with tempfile.TemporaryDirectory(prefix=f"caustica-shard-{index}-") as tmp:
        cmd = [exe, "render", *render_args, "--shard", f"{index}/{shards}", "-o", tmp + "/"]
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if first_of_injected:  # inject == "kill": the worker dies mid-shard
            time.sleep(inject_delay)
            running = proc.poll() is None
            with open(inject_marker, "a") as f:
                f.write("caustica was running\n" if running else "caustica had finished\n")
            proc.kill()
            os._exit(1)
        out, err = proc.communicate()
        if proc.returncode != 0:
            msg = (
                f"shard {index}/{shards}: caustica exited with status {proc.returncode}\n"
                f"  command: {' '.join(cmd)}\n{err.strip()}"
            )
            if proc.returncode == USAGE_EXIT:
                raise ShardUsageError(msg)
            raise ShardFailed(msg)
        parts = [p for p in sorted(Path(tmp).glob("*.cpart")) if not p.name.endswith(".partial.cpart")]
        if len(parts) != 1:
            raise ShardFailed(
                f"shard {index}/{shards}: expected one .cpart in {tmp}, found "
                f"{[p.name for p in Path(tmp).iterdir()]}; caustica said:\n{out}{err}"
            )
        data = parts[0].read_bytes()
        name = parts[0].name
    return {
        "index": index,
        "name": name,
        "data": data,
        "seconds": time.monotonic() - start,
        "host": socket.gethostname(),
        "pid": os.getpid(),
    }


def write_atomic(path: Path, data: bytes) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    with open(tmp, "wb") as f:
        f.write(data)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def fmt_seconds(s: float) -> str:
    s = max(0.0, s)
    if s < 60:
        return f"{s:.1f} s"
    m, s = divmod(round(s), 60)
    if m < 60:
        return f"{m}m{s:02d}s"
    h, m = divmod(m, 60)
    return f"{h}h{m:02d}m"


class Progress:
    """One line per finished shard (count, elapsed, ETA); a tqdm bar if tqdm is installed."""

    def __init__(self, total: int, done: int, enabled_bar: bool):
        self.total = total
        self.done = done
        self.start_done = done
        self.t0 = time.monotonic()
        self.bar = None
        if enabled_bar:
            try:
                from tqdm import tqdm  # type: ignore

                self.bar = tqdm(total=total, initial=done, unit="shard", file=sys.stderr)
            except ImportError:
                pass

    def log(self, line: str) -> None:
        if self.bar is not None:
            self.bar.write(line, file=sys.stderr)
        else:
            print(line, file=sys.stderr, flush=True)

    def finished(self, line: str) -> None:
        self.done += 1
        elapsed = time.monotonic() - self.t0
        rate = (self.done - self.start_done) / elapsed if elapsed > 0 else 0.0
        remaining = self.total - self.done
        eta = remaining / rate if rate > 0 else float("inf")
        width = len(str(self.total))
        self.log(
            f"[{self.done:>{width}}/{self.total}] {line} | elapsed {fmt_seconds(elapsed)}, "
            f"ETA {fmt_seconds(eta) if remaining else '0 s'}"
        )
        if self.bar is not None:
            self.bar.update(1)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def run_merge(caustica: str, parts: Path, out: Path, extra: list[str]) -> subprocess.CompletedProcess:
    return subprocess.run(
        [caustica, "merge", str(parts), "-o", str(out), *extra],
        capture_output=True,
        text=True,
        check=False,
    )


def write_preview(caustica: str, parts: Path, preview: Path, png: Path | None) -> str:
    """`caustica merge --partial` into temporary names, then renamed: a viewer never sees half a file."""
    preview.parent.mkdir(parents=True, exist_ok=True)
    tmp = preview.with_name(f".{preview.stem}.{os.getpid()}.tmp{preview.suffix}")
    extra = ["--partial"]
    tmp_png = None
    if png is not None:
        tmp_png = png.with_name(f".{png.stem}.{os.getpid()}.tmp{png.suffix}")
        extra += ["--png", str(tmp_png)]
    r = run_merge(caustica, parts, tmp, extra)
    if r.returncode != 0:
        return f"preview failed (status {r.returncode}): {r.stderr.strip()}"
    os.replace(tmp, preview)
    if tmp_png is not None and png is not None:
        os.replace(tmp_png, png)
    return f"preview -> {preview}"


def parse_args(argv: list[str]) -> tuple[argparse.Namespace, list[str]]:
    if "--" in argv:
        cut = argv.index("--")
        argv, render_args = argv[:cut], argv[cut + 1 :]
    else:
        render_args = []
    p = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0],
        epilog="caustica render arguments (scene, options) follow a `--`.",
    )
    p.add_argument("--shards", "-n", type=int, required=True, help="number of shards N")
    p.add_argument("-o", "--output", type=Path, required=True, help="merged image (.exr)")
    p.add_argument("--png", type=Path, help="also write an sRGB PNG at the merge")
    p.add_argument("--parts", type=Path, help="directory of the parts (default: OUTPUT without extension + .parts)")
    p.add_argument(
        "--caustica",
        default=os.environ.get("CAUSTICA", "caustica"),
        help="the caustica binary, at the same path on every node (default: $CAUSTICA or caustica on PATH)",
    )
    p.add_argument("--address", help="join this Ray cluster (auto, ray://HOST:10001, ...); default: start a local one")
    p.add_argument("--num-cpus", type=int, help="CPUs of the local cluster (default: all)")
    p.add_argument(
        "--cpus-per-shard",
        type=float,
        default=1,
        help="Ray CPUs per shard task; caustica --threads follows (default 1)",
    )
    p.add_argument(
        "--max-retries",
        type=int,
        default=2,
        help="Ray's retries of a shard task (worker death or caustica error; default 2)",
    )
    p.add_argument(
        "--rounds", type=int, default=1, help="times the driver submits a shard again after Ray gave up (default 1)"
    )
    p.add_argument(
        "--resume", action="store_true", help="keep the parts already in PARTS and render the missing shards only"
    )
    p.add_argument(
        "--shards-only", help="render only these shard indices (comma-separated; e.g. to share N shards among drivers)"
    )
    p.add_argument(
        "--watch", type=Path, metavar="PREVIEW.exr", help="merge --partial into PREVIEW after each finished shard"
    )
    p.add_argument("--watch-png", type=Path, metavar="PREVIEW.png", help="with --watch: also a PNG preview")
    p.add_argument(
        "--watch-interval",
        type=float,
        default=0.0,
        help="with --watch: at least this many seconds between previews (default 0)",
    )
    p.add_argument("--no-merge", action="store_true", help="render the shards but do not merge")
    p.add_argument("--no-bar", action="store_true", help="no tqdm bar even if tqdm is installed")
    p.add_argument(
        "--inject-failure",
        type=int,
        action="append",
        default=[],
        metavar="I",
        help="test hook: the first attempt of shard I fails",
    )
    p.add_argument(
        "--inject-mode",
        choices=["kill", "raise"],
        default="kill",
        help="kill: the worker process exits (os._exit) mid-shard; raise: the task raises",
    )
    p.add_argument(
        "--inject-delay", type=float, default=0.3, help="with --inject-mode kill: seconds into the shard (default 0.3)"
    )
    args = p.parse_args(argv)
    if args.shards < 1:
        p.error(f"--shards must be at least 1, not {args.shards}")
    if args.watch_png and not args.watch:
        p.error("--watch-png goes with --watch")
    for i in args.inject_failure:
        if not 0 <= i < args.shards:
            p.error(f"--inject-failure {i}: not a shard index of 0..{args.shards - 1}")
    return args, render_args


def main(argv: list[str]) -> int:
    args, render_args = parse_args(argv)
    n = args.shards
    caustica = shutil.which(args.caustica)
    if caustica is None:
        print(f"ray_render: caustica binary not found: {args.caustica} (set --caustica or CAUSTICA)", file=sys.stderr)
        return 2
    caustica = str(Path(caustica).resolve())
    out = args.output.resolve()
    parts = (args.parts or out.with_suffix(".parts")).resolve()
    parts.mkdir(parents=True, exist_ok=True)
    if has_option(render_args, "--shard", "-o", "--output"):
        print("ray_render: give --shard and -o to ray_render.py, not after `--`", file=sys.stderr)
        return 2
    if has_option(render_args, "--png"):
        print("ray_render: give --png to ray_render.py (it goes to the merge), not after `--`", file=sys.stderr)
        return 2
    if not has_option(render_args, "--threads"):
        render_args += ["--threads", str(max(1, round(args.cpus_per_shard)))]
    if not has_option(render_args, "-q", "--quiet"):
        render_args += ["--quiet"]

    wanted = list(range(n))
    if args.shards_only:
        wanted = sorted({int(s) for s in args.shards_only.split(",") if s.strip()})
        bad = [i for i in wanted if not 0 <= i < n]
        if bad:
            print(f"ray_render: --shards-only {bad}: not shard indices of 0..{n - 1}", file=sys.stderr)
            return 2
    # A shard's temporary file (*.partial.cpart, e.g. from an engine killed mid-write) is not a
    # part: caustica merge skips it too.
    existing = [p for p in sorted(parts.glob("*.cpart")) if not p.name.endswith(".partial.cpart")]
    if existing and not args.resume:
        print(
            f"ray_render: {parts} already holds {len(existing)} part(s) (e.g. {existing[0].name}): "
            "pass --resume to keep them and render the missing shards, or remove them",
            file=sys.stderr,
        )
        return 2
    todo = [i for i in wanted if not (parts / shard_name(i, n)).exists()]
    if len(todo) < len(wanted):
        print(f"ray_render: --resume: {len(wanted) - len(todo)} shard(s) already in {parts}", file=sys.stderr)

    inject_dir = parts / ".inject"
    if args.inject_failure:
        inject_dir.mkdir(exist_ok=True)
        for i in args.inject_failure:
            (inject_dir / f"shard-{i}").unlink(missing_ok=True)

    import ray  # imported late: --help and argument errors need no Ray

    t0 = time.monotonic()
    if args.address:
        ray.init(address=args.address, logging_level="WARNING")
    else:
        ray.init(num_cpus=args.num_cpus, include_dashboard=False, logging_level="WARNING")
    cluster_cpus = ray.cluster_resources().get("CPU", 0)
    print(
        f"ray_render: {len(todo)} of {n} shards on a Ray cluster of {cluster_cpus:g} CPUs "
        f"({args.cpus_per_shard:g} per shard; started in {time.monotonic() - t0:.1f} s) -> {parts}",
        file=sys.stderr,
    )

    task = ray.remote(render_shard).options(
        num_cpus=args.cpus_per_shard,
        max_retries=args.max_retries,
        retry_exceptions=[ShardFailed],
    )

    def submit(i: int):
        inject = args.inject_mode if i in args.inject_failure else None
        marker = str(inject_dir / f"shard-{i}") if inject else None
        return task.remote(caustica, render_args, i, n, inject, marker, args.inject_delay)

    pending = {submit(i): i for i in todo}
    rounds_used = {i: 0 for i in todo}
    failed: dict[int, str] = {}
    usage_error = False
    progress = Progress(len(wanted), len(wanted) - len(todo), not args.no_bar)
    shard_seconds = 0.0
    last_preview = -1e300
    t_render = time.monotonic()
    try:
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            ref = ready[0]
            i = pending.pop(ref)
            try:
                res = ray.get(ref)
            except Exception as e:  # noqa: BLE001 - every failure of a task lands here
                cause = getattr(e, "cause", None)
                brief = str(cause or e).strip().splitlines()
                brief_text = brief[0] if brief else type(e).__name__
                if isinstance(cause, ShardUsageError) or isinstance(e, ShardUsageError):
                    progress.log(f"shard {i}: usage error, not retried:\n{cause or e}")
                    failed[i] = str(cause or e)
                    usage_error = True
                    for r in pending:
                        ray.cancel(r, force=True)
                    pending.clear()
                    break
                if rounds_used[i] < args.rounds:
                    rounds_used[i] += 1
                    progress.log(
                        f"shard {i}: failed after Ray's retries ({type(e).__name__}: {brief_text}); "
                        f"submitting it again (round {rounds_used[i]} of {args.rounds})"
                    )
                    pending[submit(i)] = i
                else:
                    progress.log(f"shard {i}: failed for good ({type(e).__name__}):\n{cause or e}")
                    failed[i] = str(cause or e)
                continue
            expected = shard_name(i, n)
            if res["name"] != expected:
                progress.log(f"ray_render: warning: shard {i} wrote {res['name']}, expected {expected}")
            write_atomic(parts / res["name"], res["data"])
            shard_seconds += res["seconds"]
            note = ""
            marker = inject_dir / f"shard-{i}"
            if i in args.inject_failure and marker.exists():
                killed = marker.read_text().split("\n")
                state = f", {killed[1]}" if len(killed) > 1 and killed[1] else ""
                note = f"; recovered from the injected failure of worker pid {killed[0]}{state}"
            progress.finished(f"shard {i} done in {res['seconds']:.2f} s on {res['host']} (pid {res['pid']}{note})")
            if args.watch and time.monotonic() - last_preview >= args.watch_interval:
                last_preview = time.monotonic()
                progress.log(write_preview(caustica, parts, args.watch.resolve(), args.watch_png))
    except KeyboardInterrupt:
        progress.close()
        print("ray_render: interrupted; the parts written so far stay (run again with --resume)", file=sys.stderr)
        return 130
    finally:
        progress.close()
        ray.shutdown()
    render_wall = time.monotonic() - t_render

    if usage_error:
        print("ray_render: caustica rejected the render options; fix them and run again", file=sys.stderr)
        return 2
    if failed:
        print(
            f"ray_render: shard(s) {sorted(failed)} failed; the other parts are in {parts}. "
            f"Run again with --resume to render the missing ones"
            + (f"; the preview {args.watch} shows the shards done" if args.watch else ""),
            file=sys.stderr,
        )
        return 1
    print(
        f"ray_render: {len(todo)} shard(s) in {fmt_seconds(render_wall)} wall, "
        f"{fmt_seconds(shard_seconds)} summed over shards",
        file=sys.stderr,
    )
    if args.no_merge or args.shards_only:
        return 0
    t_merge = time.monotonic()
    extra = ["--png", str(args.png.resolve())] if args.png else []
    r = run_merge(caustica, parts, out, extra)
    sys.stderr.write(r.stderr)
    if r.returncode != 0:
        print(f"ray_render: caustica merge failed (status {r.returncode})", file=sys.stderr)
        return r.returncode
    print(f"ray_render: merged {n} shards into {out} in {time.monotonic() - t_merge:.2f} s", file=sys.stderr)
    shutil.rmtree(inject_dir, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
