#!/usr/bin/env bash
# A ball on a block (tests/pairs/ball_block3d.geo) against Hertz, as a pair
# (ball the slave, then the block the slave) and as the same ball on a
# rigid plane with the same E* (E halved): peak pressure and contact radius
# per mesh size at the contact. From the project root:
#   bash bench/pairs/ball_block.sh [hc ...]        (default 0.02 0.015)
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${UBR_BIN:-target/release/ubr-petsc}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OPENBLAS_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
common="-nu 0.3 -dirichlet_base uz=0 -dirichlet_x0_ball ux=0 -dirichlet_y0_ball uy=0 -dirichlet_x0_block ux=0 -dirichlet_y0_block uy=0 -traction_top 0,0,-1.574 -ubr_lambda_rtol 1e-8"
[ $# -gt 0 ] || set -- 0.02 0.015
for hcv in "$@"; do
  {
    gmsh -3 -setnumber hc "$hcv" -format msh22 tests/pairs/ball_block3d.geo -o "$work/m.msh" > /dev/null
    for case in "pair-ball-slave:-E 2000 -contact_pair slave,master" \
                "pair-block-slave:-E 2000 -contact_pair master,slave" \
                "rigid-plane:-E 1000 -contact_surface slave -obstacle plane -obstacle_point 0,0,0 -contact_direction 0,0,-1"; do
      name=${case%%:*}; opts=${case#*:}
      mpirun -n 2 "$bin" -mesh "$work/m.msh" $opts $common -contact_output "$work/c.csv" > "$work/log" 2>&1 || { cat "$work/log"; exit 1; }
      python3 - "$work/c.csv" "$hcv" "$name" <<'PY'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
pts = [(math.hypot(float(r['x']), float(r['y'])), float(r['lambda_n']), float(r['weight']), float(r['n_z'])) for r in rows]
F = 4 * abs(sum(w * p * nz for _, p, w, nz in pts))
es = 2000 / (2 * 0.91)
a = (3 * F / (4 * es)) ** (1 / 3)
p0 = 3 * F / (2 * math.pi * a * a)
peak = max(p for _, p, _, _ in pts)
edge = max(r for r, p, _, _ in pts if p > 1e-6 * p0)
print("hc %-6s %-17s F %.4f  peak %.3f vs p0 %.3f (%+.2f%%)  radius %.4f vs a %.4f (%+.2f%%)" % (
    sys.argv[2], sys.argv[3], F, peak, p0, 100 * (peak / p0 - 1), edge, a, 100 * (edge / a - 1)))
PY
    done
  }
done
