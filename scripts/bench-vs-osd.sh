#!/usr/bin/env bash
# Times uniform Catmull-Clark refinement (topology + double-precision positions, no output)
# of subsurf against OpenSubdiv 3.5 (through osd-oracle) side by side, and measures the
# peak memory of one run of each. Prints markdown tables (see BENCHMARKS.md).
#
# Usage: scripts/bench-vs-osd.sh [EXTRA.obj ...]
#
# Meshes: catmark_bishop and catmark_pawn from crates/subsurf/tests/shapes/osd at LEVELS,
# a "large" input (catmark_bishop refined twice by `subsurf subdivide -l 2`) at
# LARGE_LEVELS, a "huge" one (refined five times: 0.96 M quads, as users bring scans and
# film assets) at HUGE_LEVELS, and every EXTRA.obj at LEVELS.
#
# Environment:
#   REPS=7              repetitions per process (each tool prints its median)
#   ROUNDS=3            rounds of the interleaved OSD / 1-thread / 2-thread processes per
#                       mesh and level; the table shows the median over the rounds of the
#                       per-process medians, which damps bursts of load from other processes
#   LEVELS="5 6"        levels for the small meshes and the extra ones
#   LARGE_LEVELS="3 4"  levels for the large input
#   HUGE_LEVELS="1"     levels for the huge input (empty: skip it)
#   SCALING_LEVELS="3 4 5 6"  levels of the time-per-output-vertex table (catmark_bishop;
#                       empty: skip that table)
#   REPLAY_LEVELS="6"   levels of the re-posing table (catmark_bishop, catmark_pawn, the extra
#                       meshes and catmark_bishop with every quad split into two triangles,
#                       dense in extraordinary vertices: `subsurf bench --replay` against a full refinement
#                       with the same threads; the large input at LARGE_LEVELS; empty: skip
#                       that table)
#   LARGE_TRI_LEVELS="2 3"  levels of the re-posing table for the large input with every quad
#                       split into two triangles (30 k triangles; empty: skip those rows)
#   LIMIT_GRID=8        N of the limit-evaluation table: an N x N grid of limit points (position
#                       and first derivatives) on every quad of catmark_bishop, catmark_pawn, the
#                       extra meshes and the large input, and with Loop on every triangle of
#                       catmark_bishop split into triangles: `osd-oracle benchlimit IN N 1`
#                       (one-shot) and `IN N REPS` (its cache kept) against `subsurf bench IN
#                       --limit-grid N` (cold and warm; empty: skip that table)
#   OSD_ORACLE=PATH     use this osd-oracle binary instead of building one
#   OSD_STENCIL_BENCH=PATH  use this osd-stencil-bench binary (tools/osd-stencil-bench, for
#                       the re-posing table) instead of building one
#   SUBSURF=PATH        use this subsurf binary instead of building one (release)
#   OSD_ORACLE_SRC=DIR  osd-oracle sources (default: ../shared/tools/osd-oracle next to the
#                       repository); its build.sh installs Debian's libosd-dev if missing
#
# Exit status: 0 on success, 1 when the two tools disagree on a vertex count (or on any
# other error), 2 when the oracle is neither given nor buildable.
set -euo pipefail
shopt -s inherit_errexit

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/.." && pwd)"
shapes="$root/crates/subsurf/tests/shapes/osd"

REPS="${REPS:-7}"
ROUNDS="${ROUNDS:-3}"
LEVELS="${LEVELS:-5 6}"
LARGE_LEVELS="${LARGE_LEVELS:-3 4}"
HUGE_LEVELS="${HUGE_LEVELS-1}"
SCALING_LEVELS="${SCALING_LEVELS-3 4 5 6}"
REPLAY_LEVELS="${REPLAY_LEVELS-6}"
LARGE_TRI_LEVELS="${LARGE_TRI_LEVELS-2 3}"
LIMIT_GRID="${LIMIT_GRID-8}"

case "${1:-}" in
  -h|--help) sed -n '2,44p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
esac
for extra in "$@"; do
  [ -r "$extra" ] || { echo "bench-vs-osd: cannot read $extra" >&2; exit 1; }
done

log() { echo "bench-vs-osd: $*" >&2; }

# The oracle's flags for the same work as `subsurf bench`, which refines a mesh's texture
# coordinates (`vt`) with its positions: the oracle refines them too (in OpenSubdiv's
# default mode, `all`, which is subsurf's default) when the mesh has them.
oracle_fvar() { if grep -q '^vt ' "$1"; then echo "--fvar all"; fi; }

work="$(mktemp -d "${TMPDIR:-/tmp}/bench-vs-osd.XXXXXX")"
trap 'rm -rf "$work"' EXIT

# --- tools -----------------------------------------------------------------------------
as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
    log "need root to run: $*"; return 1; fi
}

# shellcheck source=scripts/oracle.sh
. "$root/scripts/oracle.sh"
find_oracle "$work"

# OpenSubdiv's re-posing path (a stencil table), for the re-posing table: our own small
# program on the same libosd-dev (tools/osd-stencil-bench).
if [ -n "$REPLAY_LEVELS" ]; then
  if [ -n "${OSD_STENCIL_BENCH:-}" ]; then
    stencil_bench="$OSD_STENCIL_BENCH"
  else
    stencil_bench="$work/osd-stencil-bench"
    log "building osd-stencil-bench"
    g++ -O2 -std=c++14 "$root/tools/osd-stencil-bench/osd_stencil_bench.cpp" -o "$stencil_bench" -losdCPU \
      || { log "building osd-stencil-bench failed (needs libosd-dev)"; exit 2; }
  fi
  [ -x "$stencil_bench" ] || { log "no osd-stencil-bench at $stencil_bench"; exit 2; }
fi

if [ ! -x /usr/bin/time ]; then
  log "installing Debian's 'time' for /usr/bin/time -v"
  (as_root apt-get update -qq && DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -qq time) >/dev/null
fi

if [ -n "${SUBSURF:-}" ]; then
  subsurf="$SUBSURF"
else
  log "building subsurf (release)"
  (cd "$root" && cargo build --release --quiet -p subsurf-cli)
  target_dir="${CARGO_TARGET_DIR:-$root/target}"
  case "$target_dir" in /*) ;; *) target_dir="$root/$target_dir" ;; esac
  # A copy, so that a rebuild during the run does not change the binary measured.
  cp "$target_dir/release/subsurf" "$work/subsurf"
  subsurf="$work/subsurf"
fi
[ -x "$subsurf" ] || { log "no subsurf binary at $subsurf"; exit 1; }

# --- inputs ----------------------------------------------------------------------------
large="$work/catmark_bishop_l2.obj"
log "writing the large input (catmark_bishop refined to level 2)"
"$subsurf" subdivide --quiet -l 2 "$shapes/catmark_bishop.obj" -o "$large"

# "path|label|levels" per row group.
runs=(
  "$shapes/catmark_bishop.obj|catmark_bishop|$LEVELS"
  "$shapes/catmark_pawn.obj|catmark_pawn|$LEVELS"
  "$large|catmark_bishop_l2 (large)|$LARGE_LEVELS"
)
if [ -n "$HUGE_LEVELS" ]; then
  huge="$work/catmark_bishop_l5.obj"
  log "writing the huge input (catmark_bishop refined to level 5)"
  "$subsurf" subdivide --quiet -l 5 "$shapes/catmark_bishop.obj" -o "$huge"
  runs+=("$huge|catmark_bishop_l5 (huge)|$HUGE_LEVELS")
fi
for extra in "$@"; do
  runs+=("$extra|$(basename "$extra" .obj)|$LEVELS")
done

# --- measurement helpers ---------------------------------------------------------------
# field NAME LINE: the value of NAME=value in LINE.
field() { sed -n "s/.*[[:space:]]$1=\([^[:space:]]*\).*/\1/p" <<<"$2"; }
# median X...: the median of the numbers X (the upper one of the middle two for an even count).
median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print v[int(NR / 2) + 1] }'; }
# ratio A B: A / B with two decimals.
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b > 0) printf "%.2f", a / b; else print "n/a" }'; }
# maxrss_mib CMD...: peak resident set size of one run of CMD, in MiB.
maxrss_mib() {
  /usr/bin/time -v -o "$work/time.txt" "$@" >/dev/null
  awk -F: '/Maximum resident set size/ { printf "%.0f", $2 / 1024 }' "$work/time.txt"
}

printf '\nTimes: median over %s interleaved rounds of the median of %s repetitions per process.\n' "$ROUNDS" "$REPS"
printf 'ratio = subsurf time / OSD time (< 1: subsurf faster).\n'
printf 'Max RSS: one run (1 repetition) of `osd-oracle bench IN L 1` and `subsurf bench IN -l L --reps 1 --threads 1`.\n\n'
printf '| mesh | level | output verts | OSD median s | subsurf 1T median s | 1T/OSD | subsurf 2T median s | 2T/OSD | OSD max RSS MiB | subsurf max RSS MiB |\n'
printf '|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n'

status=0
for run in "${runs[@]}"; do
  IFS='|' read -r path label levels <<<"$run"
  for level in $levels; do
    log "$label level $level"
    # Interleaved: OSD, subsurf 1 thread, subsurf 2 threads, one after the other, ROUNDS times.
    osd_t=() t1_t=() t2_t=()
    for _ in $(seq "$ROUNDS"); do
      osd_line="$("$oracle" bench "$path" "$level" "$REPS" $(oracle_fvar "$path"))"
      t1_line="$("$subsurf" bench "$path" -l "$level" --reps "$REPS" --threads 1)"
      t2_line="$("$subsurf" bench "$path" -l "$level" --reps "$REPS" --threads 2)"
      osd_t+=("$(field median_s "$osd_line")")
      t1_t+=("$(field median_s "$t1_line")")
      t2_t+=("$(field median_s "$t2_line")")
    done
    osd_s="$(median "${osd_t[@]}")"
    t1_s="$(median "${t1_t[@]}")"
    t2_s="$(median "${t2_t[@]}")"
    verts="$(field verts "$t1_line")"
    osd_verts="$(field verts "$osd_line")"
    if [ "$verts" != "$osd_verts" ]; then
      log "WARNING: $label level $level: subsurf has $verts vertices, OSD $osd_verts"
      verts="$verts (OSD: $osd_verts)"
      status=1
    fi
    osd_rss="$(maxrss_mib "$oracle" bench "$path" "$level" 1 $(oracle_fvar "$path"))"
    sub_rss="$(maxrss_mib "$subsurf" bench "$path" -l "$level" --reps 1 --threads 1)"
    printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' \
      "$label" "$level" "$verts" "$osd_s" "$t1_s" "$(ratio "$t1_s" "$osd_s")" \
      "$t2_s" "$(ratio "$t2_s" "$osd_s")" "$osd_rss" "$sub_rss"
  done
done

if [ -n "$SCALING_LEVELS" ]; then
  printf '\nTime per output vertex, catmark_bishop (1 thread, measured as above):\n\n'
  printf '| level | output verts | subsurf 1T median s | subsurf ns/vertex | OSD median s | OSD ns/vertex |\n'
  printf '|---:|---:|---:|---:|---:|---:|\n'
  for level in $SCALING_LEVELS; do
    log "catmark_bishop level $level (time per vertex)"
    t1_t=() osd_t=()
    for _ in $(seq "$ROUNDS"); do
      t1_line="$("$subsurf" bench "$shapes/catmark_bishop.obj" -l "$level" --reps "$REPS" --threads 1)"
      osd_line="$("$oracle" bench "$shapes/catmark_bishop.obj" "$level" "$REPS" \
        $(oracle_fvar "$shapes/catmark_bishop.obj"))"
      t1_t+=("$(field median_s "$t1_line")")
      osd_t+=("$(field median_s "$osd_line")")
    done
    verts="$(field verts "$t1_line")"
    t1_s="$(median "${t1_t[@]}")"
    osd_s="$(median "${osd_t[@]}")"
    printf '| %s | %s | %s | %s | %s | %s |\n' "$level" "$verts" \
      "$t1_s" "$(awk -v t="$t1_s" -v n="$verts" 'BEGIN { printf "%.1f", t * 1e9 / n }')" \
      "$osd_s" "$(awk -v t="$osd_s" -v n="$verts" 'BEGIN { printf "%.1f", t * 1e9 / n }')"
  done
fi
# The meshes of the re-posing and limit tables: the two shapes and the extra ones.
small_runs=("$shapes/catmark_bishop.obj|catmark_bishop" "$shapes/catmark_pawn.obj|catmark_pawn")
for extra in "$@"; do
  small_runs+=("$extra|$(basename "$extra" .obj)")
done
# Re-posing also on a mesh dense in extraordinary vertices: catmark_bishop with every quad
# split into two triangles (one level later every vertex and face centre is extraordinary).
split_quads() {
  awk '$1 == "f" && NF == 5 { print "f", $2, $3, $4; print "f", $2, $4, $5; next } { print }' "$1" >"$2"
}
all_tri="$work/catmark_bishop_tri.obj"
split_quads "$shapes/catmark_bishop.obj" "$all_tri"
# And a large all-triangle mesh, like a scan or a CAD tessellation: the large input split.
large_tri="$work/catmark_bishop_l2_tri.obj"
split_quads "$large" "$large_tri"
replay_runs=()
for run in "${small_runs[@]}" "$all_tri|catmark_bishop_tri (all triangles)"; do
  replay_runs+=("$run|$REPLAY_LEVELS")
done
replay_runs+=("$large|catmark_bishop_l2 (large)|$LARGE_LEVELS")
replay_runs+=("$large_tri|catmark_bishop_l2_tri (large, all triangles)|$LARGE_TRI_LEVELS")
if [ -n "$REPLAY_LEVELS" ]; then
  printf '\nRe-posing (`subsurf bench --replay`: a precomputed plan applied to the base positions)\n'
  printf 'against full refinement (`subsurf bench`), same threads, and against OpenSubdiv'"'"'s stencil table\n'
  printf '(`osd-stencil-bench IN L REPS`: `Far::StencilTableReal<double>` of the last level, intermediate\n'
  printf 'levels factorized, `UpdateValues` from the base positions; one thread), interleaved as above:\n\n'
  printf '| mesh | level | full 1T s | replay 1T s | full/replay 1T | full 2T s | replay 2T s | full/replay 2T | OSD stencils s | OSD stencils/replay 1T |\n'
  printf '|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n'
  for run in "${replay_runs[@]}"; do
    IFS='|' read -r path label levels <<<"$run"
    for level in $levels; do
      log "$label level $level (re-posing)"
      f1=() r1=() f2=() r2=() st=()
      for _ in $(seq "$ROUNDS"); do
        st+=("$(field median_s "$("$stencil_bench" "$path" "$level" "$REPS")")")
        for t in 1 2; do
          f_line="$("$subsurf" bench "$path" -l "$level" --reps "$REPS" --threads "$t")"
          r_line="$("$subsurf" bench "$path" -l "$level" --reps "$REPS" --threads "$t" --replay)"
          if [ "$t" = 1 ]; then
            f1+=("$(field median_s "$f_line")"); r1+=("$(field median_s "$r_line")")
          else
            f2+=("$(field median_s "$f_line")"); r2+=("$(field median_s "$r_line")")
          fi
        done
      done
      f1_s="$(median "${f1[@]}")"; r1_s="$(median "${r1[@]}")"
      f2_s="$(median "${f2[@]}")"; r2_s="$(median "${r2[@]}")"; st_s="$(median "${st[@]}")"
      printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$label" "$level" \
        "$f1_s" "$r1_s" "$(ratio "$f1_s" "$r1_s")" "$f2_s" "$r2_s" "$(ratio "$f2_s" "$r2_s")" \
        "$st_s" "$(ratio "$st_s" "$r1_s")"
    done
  done
fi
if [ -n "$LIMIT_GRID" ]; then
  printf '\nLimit evaluation: a %sx%s grid (position, first derivatives) on every quad face (with Loop,\n' "$LIMIT_GRID" "$LIMIT_GRID"
  printf 'a grid of %s points a side on every triangle), interleaved as above.\n' "$LIMIT_GRID"
  printf -- '- One-shot, what a run that evaluates once waits for: Bfr = `osd-oracle benchlimit IN N 1` (the\n'
  printf '  factory with its cache empty, then every face), subsurf cold = `cold_s` of `subsurf bench IN\n'
  printf '  --limit-grid N` (the surface built, then every face); best of %s rounds.\n' "$ROUNDS"
  printf -- '- Bfr cached pass = the median of `osd-oracle benchlimit IN N %s`: its factory and cache of\n' "$REPS"
  printf '  irregular patches are kept across repetitions, so every pass but the first finds them built\n'
  printf '  (each face is still initialised and its patch points prepared); subsurf warm = the median of\n'
  printf '  its repetitions (the surface kept, re-posed and evaluated again); medians of %s rounds.\n' "$ROUNDS"
  printf -- '- × = Bfr time / subsurf time (> 1: subsurf faster). Peak memory: one one-shot run of each\n'
  printf '  (subsurf on one thread).\n\n'
  printf '| mesh | points | Bfr one-shot s | subsurf cold 1T s | × | subsurf cold 2T s | × | Bfr cached pass s | cold 1T × | subsurf warm 1T s | × | subsurf warm 2T s | × | configurations | OSD peak MiB | subsurf peak MiB |\n'
  printf '|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n'
  # best X...: the smallest of the numbers X.
  best() { printf '%s\n' "$@" | sort -g | head -n 1; }
  # And the large input: mostly regular faces, the bulk of a refined or modelled mesh; and
  # the all-triangle bishop with Loop.
  limit_runs=()
  for run in "${small_runs[@]}" "$large|catmark_bishop_l2 (large)"; do
    limit_runs+=("$run|catmark")
  done
  limit_runs+=("$all_tri|catmark_bishop_tri (Loop)|loop")
  for run in "${limit_runs[@]}"; do
    IFS='|' read -r path label scheme <<<"$run"
    log "$label limit grid $LIMIT_GRID"
    sub_scheme=(); osd_scheme=()
    if [ "$scheme" = loop ]; then sub_scheme=(--scheme loop); osd_scheme=(--scheme loop); fi
    one_t=() osd_t=() c1_t=() c2_t=() w1_t=() w2_t=()
    for _ in $(seq "$ROUNDS"); do
      one_line="$("$oracle" benchlimit "$path" "$LIMIT_GRID" 1 "${osd_scheme[@]}")"
      osd_line="$("$oracle" benchlimit "$path" "$LIMIT_GRID" "$REPS" "${osd_scheme[@]}")"
      t1_line="$("$subsurf" bench "$path" "${sub_scheme[@]}" --limit-grid "$LIMIT_GRID" --reps "$REPS" --threads 1)"
      t2_line="$("$subsurf" bench "$path" "${sub_scheme[@]}" --limit-grid "$LIMIT_GRID" --reps "$REPS" --threads 2)"
      one_t+=("$(field median_s "$one_line")")
      osd_t+=("$(field median_s "$osd_line")")
      c1_t+=("$(field cold_s "$t1_line")"); c2_t+=("$(field cold_s "$t2_line")")
      w1_t+=("$(field median_s "$t1_line")"); w2_t+=("$(field median_s "$t2_line")")
    done
    points="$(field points "$t1_line")"
    osd_points="$(field points "$osd_line")"
    if [ "$points" != "$osd_points" ]; then
      log "WARNING: $label: subsurf evaluated $points points, OSD $osd_points"
      points="$points (OSD: $osd_points)"
      status=1
    fi
    if [ "$points" = 0 ]; then
      # No faces of the scheme's kind: both tools time an empty evaluation.
      printf '| %s | 0 | — | — | — | — | — | — | — | — | — | — | — | — | — | — |\n' "$label"
      continue
    fi
    one_s="$(best "${one_t[@]}")"; c1_s="$(best "${c1_t[@]}")"; c2_s="$(best "${c2_t[@]}")"
    osd_s="$(median "${osd_t[@]}")"; w1_s="$(median "${w1_t[@]}")"; w2_s="$(median "${w2_t[@]}")"
    osd_rss="$(maxrss_mib "$oracle" benchlimit "$path" "$LIMIT_GRID" 1 "${osd_scheme[@]}")"
    sub_rss="$(maxrss_mib "$subsurf" bench "$path" "${sub_scheme[@]}" --limit-grid "$LIMIT_GRID" --reps 1 --threads 1)"
    printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' \
      "$label" "$points" "$one_s" "$c1_s" "$(ratio "$one_s" "$c1_s")" "$c2_s" "$(ratio "$one_s" "$c2_s")" \
      "$osd_s" "$(ratio "$osd_s" "$c1_s")" "$w1_s" "$(ratio "$osd_s" "$w1_s")" "$w2_s" "$(ratio "$osd_s" "$w2_s")" \
      "$(field configurations "$t1_line")" "$osd_rss" "$sub_rss"
  done
fi
exit "$status"
