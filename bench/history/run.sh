#!/usr/bin/env bash
# Load histories against single solves (issue 26: "total time for 20 steps at
# most 2x one single-load run at the defaults", medians of 3, one numeric
# factorization). Usage: bash bench/history/run.sh [RANKS] [REPEAT]
# Prints, per scene, the median wall time (mpirun included) and the median
# of the program's own total, single and 20 steps (without and with
# -history_output, which makes every step's whole displacement), and ratios.
# BIN=path overrides the binary (a copy, so that a build does not change it).
set -euo pipefail
cd "$(dirname "$0")/../.."
RANKS=${1:-2}
REPEAT=${2:-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OPENBLAS_NUM_THREADS=1
BIN=${BIN:-target/release/ubr-petsc}
scenes=(
  "hertz|-options_file options/hertz"
  "block3d|-options_file options/block3d"
  "hertz2d_h0.02|-options_file options/hertz -mesh_generate hertz2d -mesh_h 0.02"
  "block3d_h0.05|-options_file options/block3d -mesh_generate block3d -mesh_h 0.05"
)
printf "%-16s %9s %9s %6s %9s %9s %6s %9s %6s %8s\n" scene wall_1 wall_20 ratio total_1 total_20 ratio total_20o ratio factor#
for entry in "${scenes[@]}"; do
  name=${entry%%|*}; args=${entry#*|}
  w1=(); w20=(); t1=(); t20=(); t20o=(); nf=0
  for _ in $(seq "$REPEAT"); do
    for mode in single steps outputs; do
      extra=""
      [ "$mode" = steps ] && extra="-load_steps 20 -log_view"
      [ "$mode" = outputs ] && extra="-load_steps 20 -history_output /tmp/bench-history-$$.csv"
      s=$(date +%s.%N)
      # shellcheck disable=SC2086
      out=$(mpirun -n "$RANKS" $BIN $args $extra 2>&1)
      e=$(date +%s.%N)
      wall=$(python3 -c "print($e-$s)")
      total=$(echo "$out" | sed -n 's/.*time (s).*total \([0-9.e+-]*\).*/\1/p')
      case $mode in
        single) w1+=("$wall"); t1+=("$total") ;;
        steps) w20+=("$wall"); t20+=("$total")
          nf=$(echo "$out" | awk '/^MUMPSFactorNum/ {print $2; exit}') ;;
        outputs) t20o+=("$total") ;;
      esac
    done
  done
  python3 - "$name" "$nf" "${w1[*]}" "${w20[*]}" "${t1[*]}" "${t20[*]}" "${t20o[*]}" <<'PY'
import sys, statistics as st
name, nf = sys.argv[1], sys.argv[2]
m = [st.median(map(float, a.split())) for a in sys.argv[3:8]]
print(f"{name:<16} {m[0]:9.3f} {m[1]:9.3f} {m[1]/m[0]:6.2f} {m[2]:9.3f} {m[3]:9.3f} {m[3]/m[2]:6.2f} {m[4]:9.3f} {m[4]/m[2]:6.2f} {nf:>8}")
PY
done
