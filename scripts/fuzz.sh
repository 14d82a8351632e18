#!/usr/bin/env bash
# Fuzz the scene parser and validator, the CSV reader, a tiny render, the environment-map
# readers and the frames folder's resume logic (fuzz/, cargo-fuzz).
#
#   scripts/fuzz.sh            each target for 60 s (CI)
#   scripts/fuzz.sh 3600       each target for an hour (the documented long run)
#   scripts/fuzz.sh 60 scene   one target
#
# Needs the nightly toolchain; installs cargo-fuzz if it is missing. Every target is built
# first, then the targets run side by side, as many at a time as there are cores
# (FUZZ_JOBS to choose): each fuzzer is one process on one core, for its full time. New inputs
# go to target/fuzz-corpus/TARGET (the seeds in fuzz/corpus/TARGET are only read); a target's
# output goes to target/fuzz-logs/TARGET.log, its last lines printed when it ends; a crash is
# written to fuzz/artifacts/TARGET and fails the script.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(scene csv render maps frames)
jobs="${FUZZ_JOBS:-$(nproc 2>/dev/null || echo 1)}"
if ! [[ $jobs =~ ^[1-9][0-9]*$ ]]; then
    echo "FUZZ_JOBS=$jobs: give a whole number of fuzzers at a time, 1 or more" >&2
    exit 2
fi
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked

# One build at a time: parallel cargo commands would wait on each other's build lock.
for target in "${targets[@]}"; do
    (cd fuzz && cargo +nightly fuzz build "$target")
done

logs=target/fuzz-logs
mkdir -p "$logs"
run() {
    local target=$1 work="target/fuzz-corpus/$1"
    mkdir -p "$work"
    local status=0
    (cd fuzz && cargo +nightly fuzz run "$target" "../$work" "corpus/$target" -- \
        -max_total_time="$seconds" -rss_limit_mb=4096 -max_len=8192 -print_final_stats=1) \
        >"$logs/$target.log" 2>&1 || status=$?
    echo "$status" >"$logs/$target.status.part"
    mv "$logs/$target.status.part" "$logs/$target.status"
}

failed=()
report() {
    local target=$1 status
    status=$(cat "$logs/$target.status")
    if [ "$status" -ne 0 ]; then
        echo "fuzz $target FAILED (exit $status); the end of $logs/$target.log:"
        tail -n 60 "$logs/$target.log"
        failed+=("$target")
    else
        echo "fuzz $target done:"
        tail -n 12 "$logs/$target.log"
    fi
}

pending=("${targets[@]}")
running=()
while [ ${#pending[@]} -gt 0 ] || [ ${#running[@]} -gt 0 ]; do
    while [ ${#pending[@]} -gt 0 ] && [ ${#running[@]} -lt "$jobs" ]; do
        target=${pending[0]}
        pending=("${pending[@]:1}")
        rm -f "$logs/$target.status"
        echo "fuzz $target for ${seconds} s"
        run "$target" &
        running+=("$target")
    done
    sleep 1
    still=()
    for target in "${running[@]}"; do
        if [ -f "$logs/$target.status" ]; then
            report "$target"
        else
            still+=("$target")
        fi
    done
    running=("${still[@]+"${still[@]}"}")
done
wait
if [ ${#failed[@]} -gt 0 ]; then
    echo "fuzzing failed: ${failed[*]}" >&2
    exit 1
fi
