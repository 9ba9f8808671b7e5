#!/usr/bin/env bash
# Bodies that friction alone holds (no Dirichlet condition or contact along n
# restrains a rigid motion): failures and iterations over three grids of the
# Hertz quarter, at the default r or at a multiple of the spectral estimate.
#   bash bench/friction_held/run.sh            # the defaults
#   FACTOR=1 bash bench/friction_held/run.sh   # r = 1 x the spectral estimate
#   FACTOR=0.1 ...                             # (explicit -ubr_r per scene)
# Grids (1 rank): the quarter without ux = 0 (it rolls), Tresca s 2-20 under
# sideways tractions 0.5-8 against 100 down; the same, Coulomb 0.28-0.32
# under 10-28; the quarter held by uy = 0 only, Coulomb 0.1-1 under 5-40;
# a ring on a plane under its weight (tests/edges/ring2d.geo, meshed by
# gmsh), sideways 0-1.5 against 5 down, Coulomb 0.1-0.6, pressure in its
# hole -20, 0, 20.
# Scenes the well-posedness check refuses (exit 2) are not counted.
set -uo pipefail
cd "$(dirname "$0")/../.."
bin=${UBR_BIN:-target/release/ubr-petsc}
factor=${FACTOR:-}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OPENBLAS_NUM_THREADS=1
roll="-mesh meshes/hertz_1692.msh -E 2000 -nu 0.3 -contact_surface contact -contact_direction 0,-1 -obstacle plane -obstacle_point 0,0"
heldy="-options_file options/hertz -dirichlet_symmetry uy=0"
solve() { # args...: prints "rc iterations" (Tresca iterations in total for CF-FP)
  local extra=() out rc its
  if [ -n "$factor" ]; then
    local est rep
    rep=$(mktemp --suffix=.json)
    "$bin" "$@" -report "$rep" >/dev/null 2>&1
    est=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['r_estimate'] * $factor)" "$rep" 2>/dev/null)
    rm -f "$rep"
    [ -n "$est" ] && extra=(-ubr_r "$est")
  fi
  out=$(timeout 300 "$bin" "$@" "${extra[@]}" 2>&1); rc=$?
  its=$(echo "$out" | sed -n 's/.*iterations, \([0-9]*\) Tresca iterations in total.*/\1/p')
  [ -z "$its" ] && its=$(echo "$out" | sed -n 's/^  iterations *\([0-9]*\),.*/\1/p')
  echo "$rc ${its:-0}"
}
grid() { # name, then lines "args" on stdin
  local name=$1 fails=0 total=0 its=0 rc n
  while read -r args; do
    # shellcheck disable=SC2086
    read -r rc n < <(solve $args)
    [ "$rc" = 2 ] && continue
    total=$((total + 1)); its=$((its + n)); [ "$rc" = 0 ] || fails=$((fails + 1))
  done
  printf '%-34s %2d of %2d failed, %6d iterations\n' "$name" "$fails" "$total" "$its"
}
if [ -n "$factor" ]; then echo "r: $factor x the spectral estimate"; else echo "r: the default"; fi
for t in 0.5 1 2 3 5 8; do for s in 2 5 10 20; do
  echo "$roll -traction_top $t,-100 -friction tresca -tresca_bound $s"; done; done | grid "rolling quarter, Tresca"
for t in 10 15 20 22 23 24 24.5 25 25.5 26 27 28; do for nu in 0.28 0.3 0.32; do
  echo "$roll -traction_top $t,-100 -friction coulomb -friction_coefficient $nu"; done; done | grid "rolling quarter, Coulomb"
for t in 5 10 20 30 40; do for nu in 0.1 0.15 0.2 0.3 0.5 1; do
  echo "$heldy -traction_top $t,-100 -friction coulomb -friction_coefficient $nu"; done; done | grid "quarter held by uy = 0, Coulomb"
ring=$(mktemp -d)
gmsh -2 -format msh41 -o "$ring/ring2d.msh" tests/edges/ring2d.geo >/dev/null
for bx in 0 0.3 1 1.5; do for nu in 0.1 0.3 0.6; do for p in 0 -20 20; do
  echo "-mesh $ring/ring2d.msh -E 1000 -nu 0.3 -body_force $bx,-5 -pressure_inner $p -contact_surface outer -contact_direction 0,-1 -obstacle plane -obstacle_point 0,0 -friction coulomb -friction_coefficient $nu"
done; done; done | grid "ring under its weight, Coulomb"
rm -rf "$ring"
