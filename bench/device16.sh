#!/bin/bash
# Strong scaling on a lent 16-core machine in one prepared call (issue "Scaling studies"):
# the 2D (-mesh_h 0.01) and 3D (-mesh_h 0.0333) direct scenes at 1..16 ranks, the 1M-node
# GAMG block at 16, and variants. Needs the relocatable bundle (../shared/tools/bundle) in
# bundle/ (or $BUNDLE). From the project root:  DEADLINE=530 bash bench/device16.sh [full|partition|local|final|repeat|gamg|ptscotch|current|lease5|lease6|split]
# MAP="mpirun options" replaces the default one rank per core (hybrid runs with BLAS threads).
# Writes $OUT/dev.log (summary lines) and $OUT/runs.txt (every run's whole output).
set -u
OUT=${OUT:-/tmp/out}; mkdir -p "$OUT"
B=$(cd "${BUNDLE:-bundle}" && pwd)
LOG=$OUT/dev.log; RUNS=$OUT/runs.txt
exec > >(tee -a "$LOG") 2>&1
T0=$(date +%s)
echo "== $(nproc) cores"; lscpu | grep -E "Model name|Socket|NUMA node\(s\)|Thread"; free -g | head -2
if grep -qw avx512f /proc/cpuinfo; then export OPENBLAS_CORETYPE=SkylakeX; elif grep -qw avx2 /proc/cpuinfo; then export OPENBLAS_CORETYPE=Haswell; fi
echo "OPENBLAS_CORETYPE=${OPENBLAS_CORETYPE:-}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OPENBLAS_NUM_THREADS=1
bash "$B/run.sh" true || { echo "bundle failed"; exit 1; }
DEADLINE=${DEADLINE:-540}
one() {  # one RANKS TAG options...
  local n=$1 tag=$2; shift 2
  local el=$(( $(date +%s) - T0 ))
  if [ $el -gt $DEADLINE ]; then echo "SKIP tag=$tag n=$n (elapsed $el s)"; return; fi
  local lim=$(( DEADLINE + 40 - el )); [ $lim -gt 240 ] && lim=240
  local s=$(date +%s%N)
  timeout $lim bash "$B/run.sh" mpirun -n "$n" ${MAP:---bind-to core --map-by core} ubr-petsc "$@" > /tmp/o 2>&1
  local rc=$? e=$(( ($(date +%s%N) - s) / 1000000 ))
  echo "RUN tag=$tag n=$n rc=$rc wall_ms=$e  [$*]"
  grep -E "nodes,|linear solver|iterations  |r      |time \(s\)|memory \(MiB\)" /tmp/o | sed 's/^/    /'
  [ $rc -ne 0 ] && tail -5 /tmp/o | sed 's/^/    ERR /'
  { echo "######## tag=$tag n=$n rc=$rc wall_ms=$e [$*]"; cat /tmp/o; } >> "$RUNS"
}
H2="-options_file options/hertz -mesh_generate hertz2d -mesh_h 0.01"
H3="-options_file options/block3d -mesh_generate block3d -mesh_h 0.0333"
G3="-options_file options/block3d -mesh_generate block3d -mesh_h 0.0125 -ksp_type cg -pc_type gamg"
case "${1:-full}" in
full)
echo "== 2D direct"; for n in 1 2 4 8; do one $n d2 $H2; done; one 16 d2 $H2 -log_view
echo "== 3D direct"; for n in 1 2 4 8; do one $n d3 $H3; done; one 16 d3 $H3 -log_view
echo "== 1M GAMG"; one 16 g3 $G3 -log_view
echo "== variants"
one 16 d3dist $H3 -ubr_schur_distributed 1 -log_view
one 16 d2metis0 $H2 -mat_mumps_icntl_7 1
one 8 g3 $G3
one 8 d3dist $H3 -ubr_schur_distributed 1
;;
partition)  # RCB (the default since 2026-11-26) against METIS k-way
echo "== 2D direct"; for n in 1 2 4 8; do one $n d2 $H2; done; one 16 d2 $H2 -log_view; one 16 d2metis $H2 -partition metis
echo "== 3D direct"; for n in 1 2 4 8; do one $n d3 $H3; done; one 16 d3 $H3 -log_view; one 16 d3metis $H3 -partition metis
echo "== 1M GAMG"; one 16 g3 $G3 -log_view; one 16 g3metis $G3 -partition metis
;;
local)  # each rank generating its part (RCB), and MUMPS' column-count symbolic factorization
echo "== 2D direct"; one 1 d2 $H2; one 16 d2 $H2 -log_view; one 16 d2s58 $H2 -mat_mumps_icntl_58 2 -log_view; one 8 d2 $H2
echo "== 3D direct"; one 1 d3 $H3; one 16 d3 $H3 -log_view; one 16 d3s58 $H3 -mat_mumps_icntl_58 2
echo "== 1M GAMG"; one 16 g3rcb $G3 -partition rcb -log_view; one 16 g3 $G3 -log_view
;;
final)  # the table of the README after the per-rank generated meshes and ICNTL(58) = 2
echo "== 2D direct"; for n in 1 2 4 8; do one $n d2 $H2; done; one 16 d2 $H2 -log_view
echo "== 3D direct"; for n in 1 2 4 8; do one $n d3 $H3; done; one 16 d3 $H3 -log_view
echo "== 1M GAMG"; one 16 g3rcb $G3 -partition rcb -log_view; one 16 g3 $G3 -log_view
echo "== variants"; one 16 d3full $H3 -ubr_condense_max 0 -log_view; one 16 d2 $H2
;;
repeat)  # more samples of the final table's end points, for medians
echo "== 2D direct"; for r in 1 2; do one 1 d2 $H2; done; for r in 1 2 3; do one 16 d2 $H2; done
echo "== 3D direct"; for r in 1 2; do one 1 d3 $H3; done; for r in 1 2 3; do one 16 d3 $H3; done
echo "== 1M GAMG"; one 16 g3rcb $G3 -partition rcb; one 16 g3 $G3
;;
gamg)  # the end points of the current binary, and GAMG's threshold and smoothing at 1M nodes, 16 ranks
echo "== 2D direct"; one 1 d2 $H2; one 16 d2 $H2; one 16 d2 $H2
echo "== 3D direct"; one 1 d3 $H3; one 16 d3 $H3; one 16 d3 $H3
echo "== 1M GAMG"; one 16 g3rcb $G3 -partition rcb; one 16 g3t05 $G3 -partition rcb -pc_gamg_threshold 0.05
one 16 g3m1 $G3 -partition rcb -mg_levels_ksp_max_it 1; one 16 g3t05metis $G3 -pc_gamg_threshold 0.05
;;
ptscotch)  # the graph partitioned in parallel (PT-Scotch) against METIS on rank 0 and RCB, 16 ranks
echo "== 1M GAMG"; one 16 g3pt $G3 -partition ptscotch -log_view; one 16 g3metis $G3 -partition metis
one 16 g3rcb $G3 -partition rcb; one 16 g3pt $G3 -partition ptscotch
echo "== 2D direct"; one 16 d2pt $H2 -partition ptscotch; one 16 d2 $H2
;;
current)  # the end points of the current binary, then the parallel partition at 1M nodes (16 ranks)
echo "== 2D direct"; one 1 d2 $H2; one 16 d2 $H2 -log_view; one 16 d2 $H2; one 16 d2pt $H2 -partition ptscotch
echo "== 3D direct"; one 1 d3 $H3; one 16 d3 $H3 -log_view; one 16 d3 $H3; one 8 d3 $H3
echo "== 1M GAMG"; one 16 g3pt $G3 -partition ptscotch -log_view; one 16 g3rcb $G3 -partition rcb -log_view
one 16 g3 $G3; one 16 g3pt $G3 -partition ptscotch; one 1 d2 $H2; one 1 d3 $H3
;;
lease5)  # the scaling curve, MUMPS' statistics at 16 ranks, Coulomb friction at scale, BLAS threads
echo "== 2D direct"; for n in 1 2 4 8; do one $n d2 $H2; done; one 16 d2 $H2 -log_view; one 16 d2 $H2
echo "== 3D direct"; for n in 1 2 4 8; do one $n d3 $H3; done; one 16 d3 $H3 -log_view; one 16 d3 $H3
one 16 d3stats $H3 -mat_mumps_icntl_3 6 -mat_mumps_icntl_4 2
echo "== 3D Coulomb"; C3="-options_file options/block3d-coulomb -mesh_generate block3d -mesh_h 0.0333"
one 16 c3 $C3 -log_view; one 1 c3 $C3
echo "== BLAS threads (8 x 2, 4 x 4 cores)"
export OPENBLAS_NUM_THREADS=2; MAP="--map-by slot:PE=2 --bind-to core" one 8 d3t2 $H3; MAP="--map-by slot:PE=2 --bind-to core" one 8 d2t2 $H2
export OPENBLAS_NUM_THREADS=4; MAP="--map-by slot:PE=4 --bind-to core" one 4 d3t4 $H3; export OPENBLAS_NUM_THREADS=1
echo "== 1M GAMG"; one 16 g3rcb $G3 -partition rcb -log_view
echo "== medians"; one 1 d2 $H2; one 1 d3 $H3; one 16 d2 $H2; one 16 d3 $H3
;;
lease6)  # friction condensed by default (CONDENSE_MAX), the Schur complement on ScaLAPACK, more end points
C3="-options_file options/block3d-coulomb -mesh_generate block3d -mesh_h 0.0333"
C2="-options_file options/hertz-coulomb -mesh_generate hertz2d -mesh_h 0.01"
echo "== 3D Coulomb"; one 16 c3 $C3 -log_view; one 16 c3sd $C3 -ubr_schur_distributed 1 -log_view
one 16 c3old $C3 -ubr_condense_max 4000; one 16 c3sd $C3 -ubr_schur_distributed 1; one 8 c3 $C3; one 8 c3sd $C3 -ubr_schur_distributed 1
echo "== 2D Coulomb"; one 16 c2 $C2 -log_view; one 16 c2sd $C2 -ubr_schur_distributed 1; one 16 c2old $C2 -ubr_condense_max 2000; one 1 c2 $C2
echo "== frictionless, ScaLAPACK"; one 16 d3sd $H3 -ubr_schur_distributed 1 -log_view; one 16 d2sd $H2 -ubr_schur_distributed 1 -log_view
echo "== medians"; one 1 d2 $H2; one 16 d2 $H2; one 16 d2 $H2; one 1 d3 $H3; one 16 d3 $H3; one 16 d3 $H3; one 1 d2 $H2; one 16 d2 $H2
one 1 c3 $C3
;;
split)  # MUMPS' pre-splitting of large fronts (3D default since 2026-11-29) on and off, 8 and 16 ranks, and in 2D
echo "== 3D direct"; one 16 d3 $H3 -log_view; one 16 d3s0 $H3 -ubr_mumps_split 0 -log_view; one 8 d3 $H3; one 8 d3s0 $H3 -ubr_mumps_split 0
one 1 d3 $H3; one 16 d3 $H3; one 16 d3s0 $H3 -ubr_mumps_split 0
echo "== 2D direct"; one 16 d2 $H2; one 16 d2s1 $H2 -ubr_mumps_split 1; one 1 d2 $H2; one 16 d2 $H2; one 16 d2s1 $H2 -ubr_mumps_split 1
echo "== 3D Coulomb"; C3="-options_file options/block3d-coulomb -mesh_generate block3d -mesh_h 0.0333"; one 16 c3 $C3; one 16 c3s0 $C3 -ubr_mumps_split 0
;;
esac
echo "== done after $(( $(date +%s) - T0 )) s"
