#!/usr/bin/env bash
# Build times of the test programs at two commits, measured on this machine: the crate and its
# test programs rebuilt after an edit of src/lib.rs (dependencies already built, shared by both
# trees), interleaved A, B, A, B... so that machine noise falls on both alike.
#
#   bash docs/scripts/build_times.sh BEFORE_COMMIT AFTER_COMMIT [ROUNDS]
#
# Prints one line per build and a summary (median seconds of each). Run it on a quiet machine:
# it is a timing, and other work on the two cores moves it.
set -euo pipefail
before=${1:?before commit}
after=${2:?after commit}
rounds=${3:-3}
repo=$(git -C "$(dirname "$0")/../.." rev-parse --show-toplevel)
work=$(mktemp -d /tmp/granflow-build-times.XXXXXX)
export CARGO_TARGET_DIR="$work/target"
for side in before after; do
    git clone -q "$repo" "$work/$side"
    git -C "$work/$side" checkout -q "${!side}"
done
# dependencies once (the same Cargo.lock versions are shared through the one target directory)
for side in before after; do
    (cd "$work/$side" && cargo test --release --no-run -q >/dev/null 2>&1)
done
declare -A times
for ((r = 1; r <= rounds; r++)); do
    for side in before after; do
        touch "$work/$side/src/lib.rs"
        start=$(date +%s.%N)
        (cd "$work/$side" && cargo test --release --no-run -q >/dev/null 2>&1)
        secs=$(echo "$(date +%s.%N) - $start" | bc)
        programs=$(find "$CARGO_TARGET_DIR/release/deps" -maxdepth 1 -type f -executable -newer "$work/$side/src/lib.rs" | wc -l)
        printf 'round %d %-6s %s: %.1f s (%d executables linked)\n' "$r" "$side" "${!side:0:7}" "$secs" "$programs"
        times[$side]+="$secs "
    done
done
for side in before after; do
    median=$(printf '%s\n' ${times[$side]} | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}')
    printf 'median %-6s %s: %.1f s\n' "$side" "${!side:0:7}" "$median"
done
rm -rf "$work"
