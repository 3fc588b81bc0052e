#!/usr/bin/env bash
# Clean test-build and test-run times of the workspace under two cargo profiles, one after the
# other in fresh target directories (dependency sources cached, nothing built):
#
#   bench/test_build_time.sh [PROFILE_A] [PROFILE_B]     # default: release fast
#
# Prints one line per profile: build seconds (cargo test --no-run), run seconds, tests passed.
set -euo pipefail
cd "$(dirname "$0")/.."
for p in "${1:-release}" "${2:-fast}"; do
    dir=target/test-build-$p
    rm -rf "$dir"
    t0=$(date +%s.%N)
    CARGO_TARGET_DIR=$dir cargo test --workspace --profile "$p" --no-run -q >/dev/null 2>&1
    t1=$(date +%s.%N)
    log=$(CARGO_TARGET_DIR=$dir cargo test --workspace --profile "$p" 2>&1)
    t2=$(date +%s.%N)
    passed=$(echo "$log" | awk '/^test result/ {s += $4} END {print s}')
    failed=$(echo "$log" | awk '/^test result/ {s += $6} END {print s}')
    printf '%s: build %.0f s, run %.0f s, %s passed, %s failed\n' "$p" \
        "$(echo "$t1 - $t0" | bc -l)" "$(echo "$t2 - $t1" | bc -l)" "$passed" "$failed"
    rm -rf "$dir"
done
