#!/usr/bin/env bash
# Regenerates crates/subsurf-cli/hot-text.txt, the list of functions the release binary runs
# on common jobs, which the linker places together at the start of the binary's code (see
# crates/subsurf-cli/build.rs).
#
# Why: the kernel maps a program's code 64 KiB at a time around each page it touches
# ("fault-around"), so code spread over the whole 4 MB binary is almost all resident even
# when a job runs 1 MB of it. On small meshes that code is most of the process's memory:
# grouped, the peak resident memory of `subsurf bench catmark_cube.obj --limit-grid 8
# --threads 1` falls from 6.5 to 4.5 MiB (osd-oracle benchlimit: 5.3 MiB; BENCHMARKS.md,
# "Repetitions and small jobs under OpenSubdiv's peak").
#
# Usage: scripts/hot-text.sh           regenerate the list (builds the release binary, runs
#                                      the jobs below under callgrind: about a minute)
#        scripts/hot-text.sh --check   print how many listed functions the release binary
#                                      has; after code changes, regenerate when few remain
#
# The names are the linker's (mangled, with a hash of the crate and toolchain), so the list
# is tied to the toolchain and Cargo.lock it was made with: with another, the linker finds
# few of its names and lays the code out as it would without the list. Nothing else changes.
#
# Environment: SUBSURF=PATH  use this release binary instead of building one (it must be
# the one the list is for: `--check` reads its symbols).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/.." && pwd)"
shapes="$root/crates/subsurf/tests/shapes/osd"
list="$root/crates/subsurf-cli/hot-text.txt"

log() { echo "hot-text: $*" >&2; }

bin="${SUBSURF:-}"
if [ -z "$bin" ]; then
  (cd "$root" && cargo build --release -q -p subsurf-cli)
  bin="$root/target/release/subsurf"
fi

# The binary's function symbols, one per line.
symbols() { nm --defined-only "$bin" | awk '$2 ~ /^[tTwW]$/ { print $3 }' | sort -u; }

if [ "${1:-}" = "--check" ]; then
  have=$(symbols | comm -12 - <(grep -v '^#' "$list" | sort -u) | wc -l)
  total=$(grep -vc '^#' "$list")
  echo "hot-text: the binary has $have of the $total functions in $(basename "$list")"
  exit 0
fi

if ! command -v valgrind >/dev/null; then
  log "installing valgrind (Debian package)"
  sudo=; [ "$(id -u)" -eq 0 ] || sudo=sudo
  ($sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq valgrind) >/dev/null
fi

work="$(mktemp -d "${TMPDIR:-/tmp}/hot-text.XXXXXX")"
trap 'rm -rf "$work"' EXIT

# The jobs, most common first: each one's functions that earlier jobs did not run follow
# those of the earlier jobs, so a job's code is in as few places as possible.
# Limit evaluation, uniform refinement and re-posing as `bench` times them, on meshes with
# creases, corners, boundaries, n-gons, triangles and non-manifold vertices, with the
# default threads (one per core) and with one; then the file-writing subcommands.
jobs=()
limit_shapes="catmark_cube catmark_pawn catmark_bishop catmark_cube_creases1 catmark_edgecorner
  catmark_nonquads catmark_smoothtris0 catmark_chaikin1 catmark_nonman_verts"
for threads in 0 1; do
  for shape in $limit_shapes; do
    jobs+=("bench $shapes/$shape.obj --limit-grid 8 --reps 2 --threads $threads")
  done
done
for threads in 0 1; do
  for shape in catmark_cube catmark_pawn catmark_cube_creases1 catmark_nonquads catmark_smoothtris0; do
    jobs+=("bench $shapes/$shape.obj -l 3 --reps 2 --threads $threads")
  done
done
for threads in 0 1; do
  for shape in catmark_pawn catmark_smoothtris0; do
    jobs+=("bench $shapes/$shape.obj -l 3 --replay --reps 2 --threads $threads")
  done
done
jobs+=("subdivide $shapes/catmark_pawn.obj -l 2 -o $work/out.obj")
jobs+=("limit $shapes/catmark_pawn.obj --grid 4 -o $work/out.txt")
jobs+=("tessellate $shapes/catmark_pawn.obj --rate 3 -o $work/out.obj")
jobs+=("info $shapes/catmark_pawn.obj")

symbols >"$work/symbols"
: >"$work/order"
i=0
for job in "${jobs[@]}"; do
  i=$((i + 1))
  log "[$i/${#jobs[@]}] subsurf $job"
  # --fair-sched: threads take turns, so that workers steal jobs as they do outside
  # valgrind (a stolen job runs code that a job run inline does not).
  # shellcheck disable=SC2086 # the job is a word list
  valgrind -q --tool=callgrind --fair-sched=yes --demangle=no --callgrind-out-file="$work/cg.$i" "$bin" $job >/dev/null
  # Callgrind names each function it ran once, as "fn=(id) name" or "cfn=(id) name".
  sed -n 's/^c\{0,1\}fn=([0-9]*) //p' "$work/cg.$i" >>"$work/order"
done

# First appearance wins; keep only the binary's own functions (not libc's).
awk 'NR == FNR { ours[$0] = 1; next } ($0 in ours) && !seen[$0]++' "$work/symbols" "$work/order" \
  >"$work/hot"
# Valgrind runs no AVX-512 code (the processor it emulates has none), so our kernels that
# processors with AVX-512 run instead of the AVX2 ones are added by name.
grep '^_ZN7subsurf.*avx512' "$work/symbols" | grep -vxF -f "$work/hot" >>"$work/hot" || true

{
  echo "# Functions the release binary runs on common jobs, in the order the linker places them"
  echo "# at the start of its code (lld --symbol-ordering-file; see build.rs)."
  echo "# Generated by scripts/hot-text.sh with $(rustc --version); regenerate it there."
  cat "$work/hot"
} >"$list"
log "wrote $(wc -l <"$work/hot") functions to $list"
