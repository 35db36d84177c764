#!/usr/bin/env bash
# The field-file test (CTest label `paraview`, tests/CMakeLists.txt): every field file
# needlesim writes opens in ParaView's default reader and in meshio; the mpm particles carry the
# region of each point and the realtime3d tets that of each cell (tests/paraview/check_regions_and_cut.py),
# every tissue file its reference points with a displacement that Warp By Vector adds once
# (tests/paraview/open_in_paraview.py), scripts/paraview/show_regions.py
# shows an inclusion's points and scripts/paraview/show_realtime3d.py cuts a realtime3d tissue open
# into a non-uniform picture.
#
#   field_files_test.sh write    NEEDLESIM SOURCE_DIR WORK_DIR   runs one small scenario per engine that writes fields
#   field_files_test.sh paraview NEEDLESIM SOURCE_DIR WORK_DIR   opens them with pvpython, one PNG per engine in WORK_DIR/png,
#                                                                then the region and cut checks (WORK_DIR/png/realtime3d_cut.png,
#                                                                WORK_DIR/png/mpm_inclusion_regions.png)
#   field_files_test.sh meshio   NEEDLESIM SOURCE_DIR WORK_DIR   reads them with meshio and h5py
#
# Packages (scripts/bootstrap.sh): python3-paraview (pvpython), xvfb, python3-meshio, python3-h5py.
# Headless: Debian's ParaView 5.11 renders through X only; pvpython --force-offscreen-rendering
# and pvbatch still open an X display and abort without one. So pvpython runs against a private
# Xvfb server (Xvfb -displayfd picks a free display; the server is stopped on exit).
set -euo pipefail
mode=$1 needlesim=$2 source_dir=$3 work=$4
here="$source_dir/tests/paraview"
results="$work/results"
engines=(explicit_2d explicit_3d realtime2d realtime2d_imported realtime3d mpm mpm_inclusion)

write_fields() {
  rm -rf "$results"
  mkdir -p "$results"
  for e in explicit_2d explicit_3d realtime2d realtime3d mpm_inclusion; do
    "$needlesim" run -q "$here/scenarios/$e.yaml" -o "$results/$e"
  done
  "$needlesim" run -q "$source_dir/examples/mpm/quick_needle_block.yaml" -o "$results/mpm"
  # an imported triangle mesh: Triangle cells (engines/realtime2d/imported_mesh.hpp)
  "$needlesim" run -q "$source_dir/examples/realtime2d/imported_block.yaml" -o "$results/realtime2d_imported"
}

need() {  # program, Debian package
  command -v "$1" > /dev/null || { echo "$1 not found: install the Debian package $2 (scripts/bootstrap.sh)"; exit 1; }
}

open_in_paraview() {
  need pvpython python3-paraview
  need Xvfb xvfb
  # pvpython that dies on a signal (Debian's 5.11 aborts now and then on its X connection, more
  # often on a loaded machine) is run again against a fresh Xvfb, up to three times in all; a file
  # that does not open (exit 1) is a failure at once.
  local rc=0 attempt
  for attempt in 1 2 3; do
    rc=0
    open_once || rc=$?
    [ "$rc" -ge 128 ] || break
    echo "pvpython died on signal $((rc - 128)) (attempt $attempt of 3); Xvfb said:"
    cat "$work/xvfb.log"
    sleep 1
  done
  return $rc
}

open_once() {
  local display_file="$work/xvfb.display"
  rm -f "$display_file"
  Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3> "$display_file" > "$work/xvfb.log" 2>&1 &
  xvfb_pid=$!
  trap 'kill "$xvfb_pid" 2> /dev/null || true' EXIT
  for _ in $(seq 300); do [ -s "$display_file" ] && break; sleep 0.1; done
  [ -s "$display_file" ] || { echo "Xvfb did not start:"; cat "$work/xvfb.log"; exit 1; }
  rm -rf "$work/png"
  cd "$results"
  local rc=0
  local display=":$(head -n1 "$display_file")"
  DISPLAY=$display pvpython "$here/open_in_paraview.py" --png-dir "$work/png" "${engines[@]}" || rc=$?
  [ "$rc" -ne 0 ] || DISPLAY=$display pvpython "$source_dir/scripts/paraview/show_realtime3d.py" realtime3d \
    --png "$work/png/realtime3d_cut.png" || rc=$?
  [ "$rc" -ne 0 ] || DISPLAY=$display pvpython "$source_dir/scripts/paraview/show_regions.py" mpm_inclusion \
    --png "$work/png/mpm_inclusion_regions.png" || rc=$?
  [ "$rc" -ne 0 ] || DISPLAY=$display pvpython "$here/check_regions_and_cut.py" mpm_inclusion \
    "$work/png/realtime3d_cut.png" "$work/png/mpm_inclusion_regions.png" realtime3d realtime2d_imported || rc=$?
  kill "$xvfb_pid"
  wait "$xvfb_pid" 2> /dev/null || true
  trap - EXIT
  return $rc
}

read_with_meshio() {
  local python=/usr/bin/python3  # Debian's interpreter, where python3-meshio and python3-h5py live
  [ -x "$python" ] || python=python3
  cd "$results"
  "$python" "$here/read_with_meshio.py" "${engines[@]}"
}

case "$mode" in
  write) write_fields ;;
  paraview) open_in_paraview ;;
  meshio) read_with_meshio ;;
  *) echo "unknown mode '$mode' (write, paraview or meshio)"; exit 2 ;;
esac
