# Sourced by scripts/bench-vs-osd.sh and scripts/compare-osd.sh: finds or builds osd-oracle.
#
#   find_oracle WORK   sets `oracle` to $OSD_ORACLE, or builds one into WORK from
#                      $OSD_ORACLE_SRC (default ../shared/tools/osd-oracle beside the
#                      repository; its build.sh installs Debian's libosd-dev if missing).
# Needs `root` (the repository) and `log` (prints a message) from the caller; exits 2 when
# no oracle can be had.
find_oracle() {
  if [ -n "${OSD_ORACLE:-}" ]; then
    oracle="$OSD_ORACLE"
    [ -x "$oracle" ] || { log "OSD_ORACLE=$oracle is not an executable"; exit 2; }
    return
  fi
  local src="${OSD_ORACLE_SRC:-$root/../shared/tools/osd-oracle}"
  if [ ! -x "$src/build.sh" ]; then
    log "the OpenSubdiv oracle source is not available at $src (expected build.sh there)."
    log "Set OSD_ORACLE_SRC=DIR to its sources, or OSD_ORACLE=PATH to a built osd-oracle."
    exit 2
  fi
  oracle="$1/osd-oracle"
  log "building osd-oracle from $src"
  "$src/build.sh" "$oracle" >&2 || { log "building osd-oracle failed"; exit 2; }
}
