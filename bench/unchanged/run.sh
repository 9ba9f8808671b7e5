#!/usr/bin/env bash
# Behaviour-unchanged check (issue 25): every shipped scene (options/ and the
# independent scenes of tests/scenes) solved on 1 and 2 ranks, the contact CSV
# of each kept in OUTDIR. Compare two such directories with compare.py:
#   bash bench/unchanged/run.sh /tmp/before     # on the old commit
#   bash bench/unchanged/run.sh /tmp/after      # on the new one
#   python3 bench/unchanged/compare.py /tmp/before /tmp/after
# Byte-identical CSVs are reported as such; others must agree to 1e-12
# (relative to each column's largest magnitude).
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:?usage: run.sh OUTDIR}
bin=${UBR_BIN:-target/release/ubr-petsc}
mkdir -p "$out/mesh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OPENBLAS_NUM_THREADS=1
export OMPI_MCA_rmaps_base_oversubscribe=1
run() { # name ranks args...
  local name=$1 n=$2; shift 2
  if mpirun -n "$n" "$bin" "$@" -contact_output "$out/$name.n$n.csv" >"$out/$name.n$n.log" 2>&1; then
    echo "$name n$n ok"
  else
    echo "$name n$n exit $?"
  fi
}
for f in options/*; do
  name=$(basename "$f")
  case $name in *-paper) extra=(-ubr_max_it 3000) ;; *) extra=() ;; esac
  for n in 1 2; do run "$name" "$n" -options_file "$f" "${extra[@]}"; done
done
for f in tests/scenes/*.opts; do
  name=$(basename "$f" .opts)
  args=(-options_file "$f")
  if [ -f "tests/scenes/$name.geo" ]; then
    mline=$(grep -m1 '^# Mesh:' "$f" | sed 's/^# Mesh: *//')
    dim=$(echo "$mline" | grep -oE -- '-[23] ' | head -1)
    fmt=$(echo "$mline" | grep -oE -- '-format [a-z0-9]+' || true)
    gmsh $dim $fmt -o "$out/mesh/$name.msh" "tests/scenes/$name.geo" >/dev/null
    args+=(-mesh "$out/mesh/$name.msh")
  fi
  for n in 1 2; do run "$name" "$n" "${args[@]}"; done
done
# The comparators on the paper's 2D scene.
for n in 1 2; do run hertz-ssn "$n" -options_file options/hertz -contact_algorithm ssn -ssn_initial_shift 0,-0.01; done
for n in 1 2; do run hertz-snesvi "$n" -options_file options/hertz -contact_algorithm snesvi; done
