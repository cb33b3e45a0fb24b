#!/usr/bin/env bash
# Runs every cargo-fuzz target in fuzz/ for a bounded time and summarises the results.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]     (default: 60 seconds each, all targets)
#
# Not part of `cargo test` or of CI's default path. Needs network access the first time
# (cargo-fuzz and libfuzzer-sys from crates.io). With a nightly toolchain the targets are
# built with AddressSanitizer; without one, the script falls back to the stable toolchain
# with `--sanitizer none` and RUSTC_BOOTSTRAP=1 (libFuzzer's coverage instrumentation works
# on stable; only the sanitizers need nightly). The library has no `unsafe` code, so the
# sanitizer matters little; debug assertions (integer overflow checks) are always on.
#
# Environment:
#   FUZZ_TOOLCHAIN   toolchain to use (default: nightly if installed, else stable)
#   FUZZ_SANITIZER   address, none, ... (default: address on nightly, none on stable)
#   FUZZ_TIMEOUT     seconds after which one input counts as a hang (default 5)
#   FUZZ_RSS_MB      memory limit per process in MB (default 4096)
#
# New inputs found while fuzzing go to fuzz/runs/corpus/TARGET (ignored by git); the
# committed seeds in fuzz/corpus/TARGET are only read. Crashes, hangs and out-of-memory
# inputs go to fuzz/artifacts/TARGET; the script then exits with status 1. A summary is
# printed and written to fuzz/runs/summary.tsv. Record it in RELIABILITY.md.
set -euo pipefail

secs=${1:-60}
shift || true
all_targets=(obj_reader topology refine_step limit_eval json_reader geometry_reader ply_reader)
if [ $# -gt 0 ]; then targets=("$@"); else targets=("${all_targets[@]}"); fi

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

if ! cargo fuzz --version >/dev/null 2>&1; then
    echo "fuzz.sh: installing cargo-fuzz (cargo install cargo-fuzz)" >&2
    cargo install cargo-fuzz
fi

toolchain=${FUZZ_TOOLCHAIN:-}
if [ -z "$toolchain" ]; then
    if rustup toolchain list 2>/dev/null | grep -q '^nightly'; then
        toolchain=nightly
    else
        toolchain=stable
    fi
fi
if [ "$toolchain" = nightly ] || [[ "$toolchain" == nightly-* ]]; then
    sanitizer=${FUZZ_SANITIZER:-address}
else
    sanitizer=${FUZZ_SANITIZER:-none}
    # cargo-fuzz passes -Z flags; this lets a stable compiler accept them.
    export RUSTC_BOOTSTRAP=1
fi
timeout_s=${FUZZ_TIMEOUT:-5}
rss_mb=${FUZZ_RSS_MB:-4096}

dict_for() {
    case "$1" in
        json_reader) echo "-dict=fuzz/json.dict" ;;
        *) echo "-dict=fuzz/obj.dict" ;;
    esac
}

mkdir -p fuzz/runs/logs
summary=fuzz/runs/summary.tsv
printf 'target\tseconds\texecutions\texec_per_sec\tnew_units\tcorpus_files\tpeak_rss_mb\tresult\n' >"$summary"
echo "fuzz.sh: toolchain $toolchain, sanitizer $sanitizer, $secs s per target" >&2

failed=0
for t in "${targets[@]}"; do
    work=fuzz/runs/corpus/$t
    mkdir -p "$work" "fuzz/artifacts/$t"
    log=fuzz/runs/logs/$t.log
    echo "fuzz.sh: building and running $t ..." >&2
    status=0
    # -a: debug assertions (overflow checks). Build time is not part of SECONDS.
    cargo "+$toolchain" fuzz build -a --sanitizer "$sanitizer" "$t" >&2
    cargo "+$toolchain" fuzz run -a --sanitizer "$sanitizer" "$t" "$work" "fuzz/corpus/$t" -- \
        -max_total_time="$secs" -timeout="$timeout_s" -rss_limit_mb="$rss_mb" \
        -max_len=16384 -print_final_stats=1 "$(dict_for "$t")" >"$log" 2>&1 || status=$?
    stat_of() { grep -m1 "^stat::$1:" "$log" | awk '{print $2}'; }
    execs=$(stat_of number_of_executed_units)
    rate=$(stat_of average_exec_per_sec)
    new=$(stat_of new_units_added)
    rss=$(stat_of peak_rss_mb)
    files=$(find "$work" -type f | wc -l)
    if [ "$status" -eq 0 ]; then
        result=ok
    else
        failed=1
        artifact=$(grep -o 'Test unit written to [^ ]*' "$log" | tail -1 | sed 's/Test unit written to //')
        kind=$(grep -m1 -oE 'panicked at [^ ]+' "$log" || grep -m1 -oE 'ERROR: libFuzzer: [a-z-]+' "$log" || true)
        result="FAILED (${kind:-exit $status}) ${artifact:-see $log}"
    fi
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$t" "$secs" "${execs:-?}" "${rate:-?}" "${new:-?}" \
        "$files" "${rss:-?}" "$result" >>"$summary"
done

column -t -s $'\t' "$summary" 2>/dev/null || cat "$summary"
if [ "$failed" -ne 0 ]; then
    echo "fuzz.sh: some targets failed; reproduce with" >&2
    echo "  cargo +$toolchain fuzz run -a --sanitizer $sanitizer TARGET fuzz/artifacts/TARGET/FILE" >&2
    exit 1
fi
