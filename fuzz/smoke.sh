#!/bin/sh
# CI's short fuzzing pass: builds every target (ASan, as for the hours of
# docs/results/fuzzing.md), then runs each for SECONDS (default 30) with its
# limits from run.sh, two at a time, starting from the committed corpora.
# libFuzzer first replays the whole corpus, so every input that once
# widened coverage is read again by today's readers; the seconds after that
# mutate. A crash, leak, timeout or allocation beyond the limit fails the
# pass and prints the target's log tail and the input's path.
#
#   ./smoke.sh [SECONDS]
#
# Needs cargo-fuzz (`cargo install cargo-fuzz`); `.ci/run` installs it.
set -e
cd "$(dirname "$0")"
seconds="${1:-30}"
./seed_corpus.sh > /dev/null
export RUSTC_BOOTSTRAP=1
start=$(date +%s)
cargo fuzz build
echo "fuzz smoke: targets built in $(($(date +%s) - start)) s"
logs=$(mktemp -d)
export seconds logs
failed=0
ls fuzz_targets | sed 's/\.rs$//' | xargs -P 2 -I{} sh -c '
    if ./run.sh {} "$seconds" > "$logs/{}.log" 2>&1; then
        runs=$(sed -n "s/^stat::number_of_executed_units: *//p" "$logs/{}.log")
        cov=$(grep -o "cov: [0-9]*" "$logs/{}.log" | tail -n 1)
        echo "fuzz smoke: {}: $runs inputs, $cov, no crash"
    else
        echo "fuzz smoke: {} FAILED; the end of its log:"
        tail -n 40 "$logs/{}.log"
        exit 1
    fi' || failed=1
echo "fuzz smoke: $(ls fuzz_targets | wc -l) targets in $(($(date +%s) - start)) s"
rm -rf "$logs"
exit "$failed"
