#!/usr/bin/env python3
"""Compare two directories written by bench/unchanged/run.sh: every CSV
byte-identical, or equal to 1e-12 relative to its column's largest value.
Runs on more than one rank are held to 1e-3, the stopping test's target
(-ubr_lambda_rtol), instead: two runs of the same binary on 2 ranks
differed by up to 1.9e-4 (cantilever2d_stop: 159 and 160 iterations,
2026-11-26), because MUMPS' parallel factorization is not reproducible bit
for bit and the stopping test may then end one iteration apart."""
import csv, pathlib, sys

def load(p):
    with open(p) as f:
        return list(csv.reader(f))

def main(a, b, tol=1e-12):
    a, b = pathlib.Path(a), pathlib.Path(b)
    bad = same = close = 0
    for fa in sorted(a.glob("*.csv")):
        fb = b / fa.name
        if not fb.exists():
            print(f"{fa.name}: missing in {b}"); bad += 1; continue
        if fa.read_bytes() == fb.read_bytes():
            same += 1; continue
        if [r[:len(load(fa)[0])] for r in load(fb)] == load(fa):
            same += 1; continue
        ra, rb = load(fa), load(fb)
        # Columns appended since (n_x,n_y,n_z) are left out: the old ones are compared.
        rb = [r[:len(ra[0])] for r in rb]
        if len(ra) != len(rb) or ra[0] != rb[0]:
            print(f"{fa.name}: shape or header differs"); bad += 1; continue
        worst = 0.0
        for j, col in enumerate(ra[0]):
            try:
                xa = [float(r[j]) for r in ra[1:]]; xb = [float(r[j]) for r in rb[1:]]
            except ValueError:
                if [r[j] for r in ra[1:]] != [r[j] for r in rb[1:]]:
                    worst = float("inf")
                continue
            scale = max([abs(x) for x in xa] + [1e-300])
            worst = max([worst] + [abs(x - y) / scale for x, y in zip(xa, xb)])
        limit = tol if ".n1." in fa.name else 1e-3
        if worst <= limit:
            close += 1; print(f"{fa.name}: within {worst:.1e}")
        else:
            bad += 1; print(f"{fa.name}: differs by {worst:.1e}")
    for fb in sorted(b.glob("*.csv")):
        if not (a / fb.name).exists():
            print(f"{fb.name}: missing in {a}"); bad += 1
    print(f"{same} identical, {close} within tolerance (1e-12 on one rank, 1e-3 on more), {bad} different")
    return 1 if bad else 0

if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
