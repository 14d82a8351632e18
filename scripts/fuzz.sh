#!/usr/bin/env bash
# Fuzz the scene parser and validator, the CSV reader, a tiny render, the environment-map
# readers and the frames folder's resume logic (fuzz/, cargo-fuzz).
#
#   scripts/fuzz.sh            each target for 60 s (CI)
#   scripts/fuzz.sh 3600       each target for an hour (the documented long run)
#   scripts/fuzz.sh 60 scene   one target
#
# Needs the nightly toolchain; installs cargo-fuzz if it is missing. New inputs go to
# target/fuzz-corpus/TARGET (the seeds in fuzz/corpus/TARGET are only read); a crash is
# written to fuzz/artifacts/TARGET and fails the script.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(scene csv render maps frames)
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
for target in "${targets[@]}"; do
    work="target/fuzz-corpus/$target"
    mkdir -p "$work"
    echo "fuzz $target for ${seconds} s"
    (cd fuzz && cargo +nightly fuzz run "$target" "../$work" "corpus/$target" -- \
        -max_total_time="$seconds" -rss_limit_mb=4096 -max_len=8192 -print_final_stats=1)
done
