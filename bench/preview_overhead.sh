#!/usr/bin/env bash
# Issue 25, live preview: the render's image and time with and without `--preview`. Each round
# runs, one after the other on this shared machine, every render
#   plain   without a preview,
#   idle    with --preview (default interval, 1 s) and no page open,
#   watched with --preview and a page open: a curl loop long-polling /wait and fetching
#           /image.png at each new version, as the page does,
#   fast    as watched, with --preview-interval 0.1 (ten snapshots a second: the cost per
#           snapshot, magnified),
# and compares each image's bytes with a reference render without preview (made first, untimed,
# which also warms the caches). Times are the render's own ("in X s" of the
# summary line, which excludes loading the scene and the wait for the page after the end), the
# process's wall time, and its CPU time (user + system, all threads: the server's PNG encoding
# included; less sensitive than wall time to other jobs on a shared machine). Prints, per render and variant, the median time ratio to plain over
# the rounds with its spread (min–max of the per-round ratios), and whether every image was
# byte-identical.
#   bash bench/preview_overhead.sh [rounds (default 5)]
# Environment: PROFILE (cargo profile, default release), PORT (default 18457), THREADS (2).
set -euo pipefail
cd "$(dirname "$0")/.."
rounds="${1:-5}"
profile="${PROFILE:-release}"
port="${PORT:-18457}"
threads="${THREADS:-2}"
target="${CARGO_TARGET_DIR:-target}"
cargo build --profile "$profile" -q -p caustica-cli
bin="$target/$profile/caustica"
[ "$profile" = dev ] && bin="$target/debug/caustica"
work="$target/bench/preview-overhead"; rm -rf "$work"; mkdir -p "$work"
csv="$work/overhead.csv"
# shellcheck source=bench/timing_lib.sh
source bench/timing_lib.sh
renders=(
  "path|cornell-box --integrator path --spp 48 --width 256 --height 256"
  "pds|glass-sphere --integrator pds --spp 2 --light-paths 2000000 --smoothing 4 --width 256 --height 256"
  "pppm|caustic-box --integrator pppm --iterations 16 --photons-per-iteration 20000 --width 192 --height 192"
)

# The page's loop: long-poll /wait, fetch the image at each new version, stop at "done" (or
# when the server is gone).
watch() {
  local url="http://127.0.0.1:$port" after=0 s v
  for _ in $(seq 1 500); do curl -sf -o /dev/null "$url/status" && break; sleep 0.01; done
  while s=$(curl -sf "$url/wait?after=$after"); do
    v=$(printf '%s' "$s" | sed -n 's/.*"version":\([0-9]*\).*/\1/p')
    if [ "${v:-0}" -gt "$after" ]; then
      curl -sf -o "$work/page.png" "$url/image.png?exposure=0" || true
      after=$v
    fi
    case "$s" in *'"done":true'*) break ;; esac
  done
}

# run NAME VARIANT ARGS...: renders to $work/NAME-VARIANT.exr; appends a CSV row.
run() {
  local name=$1 variant=$2; shift 2
  local out="$work/$name-$variant.exr" t wall secs cpu same watcher=""
  local extra=()
  case "$variant" in
    idle) extra=(--preview "$port") ;;
    watched) extra=(--preview "$port") ;;
    fast) extra=(--preview "$port" --preview-interval 0.1) ;;
  esac
  t=$(now)
  (
    TIMEFORMAT='%U %S'
    time "$bin" render "$@" --threads "$threads" -q -o "$out" "${extra[@]}" > "$work/summary.txt" 2> "$work/stderr.txt"
  ) 2> "$work/time.txt" &
  local pid=$!
  case "$variant" in watched|fast) watch & watcher=$! ;; esac
  wait "$pid"
  wall=$(elapsed "$t")
  [ -n "$watcher" ] && wait "$watcher"
  secs=$(sed -n 's/.* in \([0-9.]*\) s.*/\1/p' "$work/summary.txt" | head -1)
  cpu=$(awk '{ printf "%.3f", $1 + $2 }' "$work/time.txt")
  same=yes
  cmp -s "$work/$name-ref.exr" "$out" || same=no
  echo "$round,$name,$variant,$secs,$wall,$cpu,$same" >> "$csv"
}

echo "round,render,variant,render_seconds,wall_seconds,cpu_seconds,identical" > "$csv"
for entry in "${renders[@]}"; do
  # shellcheck disable=SC2086
  "$bin" render ${entry#*|} --threads "$threads" -q -o "$work/${entry%%|*}-ref.exr" > /dev/null 2>&1
done
for round in $(seq 1 "$rounds"); do
  for entry in "${renders[@]}"; do
    name="${entry%%|*}"
    # shellcheck disable=SC2086
    set -- ${entry#*|}
    # The variants in an order rotating with the round: none always runs first or after another.
    variants=(plain idle watched fast)
    for k in 0 1 2 3; do
      run "$name" "${variants[$(( (k + round) % 4 ))]}" "$@"
    done
  done
done
echo "rows: $csv"
python3 - "$csv" <<'PY'
import csv, sys
from collections import defaultdict
rows = list(csv.DictReader(open(sys.argv[1])))
t = defaultdict(dict)
same = defaultdict(lambda: True)
for r in rows:
    t[(r["render"], r["round"])][r["variant"]] = tuple(
        float(r[k]) for k in ["render_seconds", "wall_seconds", "cpu_seconds"])
    same[(r["render"], r["variant"])] &= r["identical"] == "yes"
def med(xs):
    xs = sorted(xs); n = len(xs)
    return xs[n // 2] if n % 2 else 0.5 * (xs[n // 2 - 1] + xs[n // 2])
renders = sorted({k[0] for k in t}, key=[r["render"] for r in rows].index)
print("| render | variant | plain render s (median) | render-time ratio: median [min–max] | wall-time ratio | CPU-time ratio | identical |")
print("|---|---|---:|---:|---:|---:|---|")
for name in renders:
    runs = [v for (n, _), v in t.items() if n == name]
    plain = med([r["plain"][0] for r in runs])
    for variant in ["idle", "watched", "fast"]:
        cells = []
        for i in range(3):
            q = [r[variant][i] / r["plain"][i] for r in runs]
            cells.append(f"{med(q):.3f} [{min(q):.3f}–{max(q):.3f}]")
        print(f"| {name} | {variant} | {plain:.2f} | " + " | ".join(cells)
              + f" | {'yes' if same[(name, variant)] else 'NO'} |")
# The noise floor: plain against plain, round to round.
for name in renders:
    p = [v["plain"][0] for (n, _), v in t.items() if n == name]
    c = [v["plain"][2] for (n, _), v in t.items() if n == name]
    print(f"{name}: plain over the rounds: render time {min(p):.2f}–{max(p):.2f} s "
          f"(spread {100 * (max(p) - min(p)) / med(p):.1f} % of the median), CPU time "
          f"{min(c):.2f}–{max(c):.2f} s ({100 * (max(c) - min(c)) / med(c):.1f} %)")
PY
