#!/usr/bin/env bash
# The issue "Scaling studies" on a 2-core machine: the 2D (hertz2d h 0.01)
# and 3D (block3d h 0.0333) generated scenes at the defaults on 1 and 2
# ranks, REPEAT times (each pair back to back), then hertz_37473 and
# block3d_17887 on 1 and 2 ranks, interleaved with an older binary OLD when
# given (the "no slower" check). Prints the summary's total time of each run;
# take the medians. From the project root:
#   REPEAT=3 OLD=/path/to/old/ubr-petsc bash bench/twocore.sh
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OPENBLAS_NUM_THREADS=1
NEW=${NEW:-target/release/ubr-petsc}
OLD=${OLD:-}
REPEAT=${REPEAT:-3}
t() { local bin=$1 n=$2; shift 2; mpirun -n "$n" "$bin" "$@" 2>&1 | grep 'time (s)' | sed 's/.*total //'; }
H2=(-options_file options/hertz -mesh_generate hertz2d -mesh_h 0.01)
H3=(-options_file options/block3d -mesh_generate block3d -mesh_h 0.0333)
for _ in $(seq "$REPEAT"); do echo "2D n1 $(t "$NEW" 1 "${H2[@]}") n2 $(t "$NEW" 2 "${H2[@]}")"; done
for _ in $(seq "$REPEAT"); do echo "3D n1 $(t "$NEW" 1 "${H3[@]}") n2 $(t "$NEW" 2 "${H3[@]}")"; done
for _ in $(seq "$REPEAT"); do
  for scene in "hertz meshes/hertz_37473.msh" "block3d meshes/block3d_17887.msh"; do
    set -- $scene
    for n in 1 2; do
      line="$2 n$n new $(t "$NEW" "$n" -options_file "options/$1" -mesh "$2")"
      [ -n "$OLD" ] && line="$line old $(t "$OLD" "$n" -options_file "options/$1" -mesh "$2")"
      echo "$line"
    done
  done
done
