#!/usr/bin/env bash
# GetFEM peer for -contact_pair (issue 27): Hertz between two elastic
# cylinders, ubr-petsc against GetFEM's contact bricks on the same meshes.
#   bash bench/peers/getfem_pairs/run.sh [--hc 0.0125,0.00625,0.003125] [--repeat 3]
# Env: UBR (the binary; default target/release/ubr-petsc of this checkout),
# WORK (scratch folder; default /tmp/getfem_pairs).
# Needs gmsh, mpirun, and GetFEM for /usr/bin/python3 (python3-getfem).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
UBR="${UBR:-$root/target/release/ubr-petsc}"
WORK="${WORK:-/tmp/getfem_pairs}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OPENBLAS_NUM_THREADS=1
[ -x "$UBR" ] || { echo "no binary $UBR (./run.sh build, or UBR=...)" >&2; exit 2; }
/usr/bin/python3 -c "import getfem" || { echo "GetFEM missing for /usr/bin/python3 (apt-get install python3-getfem)" >&2; exit 2; }
exec /usr/bin/python3 "$here/compare.py" --bin "$UBR" --work "$WORK" "$@"
