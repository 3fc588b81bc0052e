# shellcheck shell=bash
# Wall-clock helpers shared by the bench scripts (source it).
# now: seconds since the epoch, with nanoseconds; elapsed T0: seconds since T0, 3 decimals.
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.3f", b - a }'; }
