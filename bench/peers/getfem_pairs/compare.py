#!/usr/bin/python3
"""Runs ubr-petsc and GetFEM on the same Hertz two-cylinder meshes and
compares them (see README.md). Called by run.sh; prints the table and writes
it to bench/results/getfem_pairs.txt.

    /usr/bin/python3 compare.py --bin target/release/ubr-petsc --work DIR
        [--hc 0.0125,0.00625,0.003125] [--repeat 3] [--out FILE]
"""
import argparse
import csv
import datetime
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
GEO = os.path.join(ROOT, "tests", "pairs", "cylinders2d.geo")

# Hertz, two cylinders, plane strain (tests/pairs.rs)
E, NU, F = 2000.0, 0.3, 20.0
R = 1.0 / (1.0 / 8.0 + 1.0 / 4.0)
ES = E / (2.0 * (1.0 - NU * NU))
B = math.sqrt(4.0 * F * R / (math.pi * ES))
P0 = 2.0 * F / (math.pi * B)

UBR_ARGS = ["-E", "2000", "-nu", "0.3", "-contact_pair", "slave,master",
            "-dirichlet_base", "uy=0", "-dirichlet_sym_lower", "ux=0",
            "-dirichlet_sym_upper", "ux=0", "-traction_top", "0,-2.5"]


def run(cmd, env=None):
    t = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t
    if p.returncode != 0:
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    return wall


def hertz(x):
    return np.where(np.abs(x) < B, P0 * np.sqrt(np.clip(1 - (x / B) ** 2, 0, None)), 0.0)


def ubr_profile(path):
    rows = list(csv.DictReader(open(path)))
    x = np.array([float(r["x"]) for r in rows])
    p = np.array([float(r["lambda_n"]) for r in rows])
    w = np.array([float(r["weight"]) for r in rows])
    ny = np.array([float(r["n_y"]) for r in rows])
    fy = float(np.sum(-w * p * ny))
    o = np.argsort(x)
    return x[o], p[o], w[o], fy


def gf_profile(path):
    rows = list(csv.DictReader(open(path)))
    x = np.array([float(r["x"]) for r in rows])
    p = np.array([float(r["lambda_n"]) for r in rows])
    o = np.argsort(x)
    return x[o], p[o]


def extent(x, p, frac=0.01):
    """The largest x of a node whose pressure is above frac * Hertz p0."""
    on = x[p > frac * P0]
    return float(on.max()) if len(on) else 0.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=os.path.join(ROOT, "target", "release", "ubr-petsc"))
    ap.add_argument("--work", default="/tmp/getfem_pairs")
    ap.add_argument("--hc", default="0.0125,0.00625,0.003125")
    ap.add_argument("--hf-ratio", type=float, default=40.0,
                    help="hf = RATIO * hc (40: the test's hc 0.0125, hf 0.5); 0: the .geo's hf 0.5")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "getfem_pairs.txt"))
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OPENBLAS_NUM_THREADS="1")
    gfpy = os.path.join(HERE, "getfem_cylinders.py")
    hcs = [float(h) for h in a.hc.split(",")]
    lines = []

    def out(s=""):
        print(s, flush=True)
        lines.append(s)

    t_start = time.perf_counter()
    cpu = "unknown"
    try:
        for l in open("/proc/cpuinfo"):
            if l.startswith("model name"):
                cpu = l.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    out(f"# GetFEM peer for -contact_pair: Hertz, two elastic cylinders (tests/pairs/cylinders2d.geo)")
    out(f"# date {datetime.date.today().isoformat()}; machine: {os.cpu_count()} cores, {cpu}, "
        f"{platform.system()} {platform.release()}")
    out(f"# command: bash bench/peers/getfem_pairs/run.sh  (compare.py --hc {a.hc} --hf-ratio {a.hf_ratio:g} --repeat {a.repeat})")
    out(f"# meshes: gmsh -2 -format msh22 -setnumber hc HC -setnumber hf {a.hf_ratio:g}*HC tests/pairs/cylinders2d.geo "
        "(hc 0.0125: the mesh of tests/pairs.rs)")
    out(f"# Hertz: R = {R:.6f}, E* = {ES:.4f}, F = {F} (quarter model F/2), "
        f"b = {B:.5f}, p0 = {P0:.4f}")
    out("# wall: the whole process, median of the runs (ubr: MPI start included; GetFEM: python start "
        "and import of getfem included); in-program: ubr-petsc's time_total, GetFEM's model set-up + Newton")
    out()

    results = []
    for hc in hcs:
        msh = os.path.join(a.work, f"cylinders_hc{hc}.msh")
        hf = ["-setnumber", "hf", str(a.hf_ratio * hc)] if a.hf_ratio > 0 else []
        subprocess.run(["gmsh", "-2", "-format", "msh22", "-setnumber", "hc", str(hc)] + hf +
                       ["-o", msh, GEO], check=True, capture_output=True)
        stem = os.path.join(a.work, f"hc{hc}")
        runs = {}
        # ubr-petsc: defaults, -ubr_lambda_rtol 1e-8, and 1e-8 on 2 ranks
        for key, ranks, extra in (("ubr_default_n1", 1, []),
                                  ("ubr_1e-8_n1", 1, ["-ubr_lambda_rtol", "1e-8"]),
                                  ("ubr_default_n2", 2, []),
                                  ("ubr_1e-8_n2", 2, ["-ubr_lambda_rtol", "1e-8"])):
            o = f"{stem}_{key}"
            cmd = ([a.bin] if ranks == 1 else ["mpirun", "-n", str(ranks), a.bin]) + \
                ["-mesh", msh] + UBR_ARGS + extra + ["-contact_output", o + ".csv", "-report", o + ".json"]
            walls, inner = [], []
            for _ in range(a.repeat):
                walls.append(run(cmd, env))
                rep = json.load(open(o + ".json"))
                inner.append(rep["time_total"])
            x, p, w, fy = ubr_profile(o + ".csv")
            runs[key] = dict(x=x, p=p, w=w, fy=fy, wall=statistics.median(walls),
                             inner=statistics.median(inner), its=rep["iterations"],
                             est=rep["lambda_error_estimate"], nodes=rep["nodes"],
                             conv=rep["converged"])
        for brick in ("sliding", "nodal"):
            o = f"{stem}_gf_{brick}"
            cmd = ["/usr/bin/python3", gfpy, msh, o, "--brick", brick]
            walls, inner = [], []
            for _ in range(a.repeat):
                walls.append(run(cmd, env))
                rep = json.load(open(o + ".json"))
                inner.append(rep["time_setup"] + rep["time_solve"])
            x, p = gf_profile(o + ".csv")
            runs["gf_" + brick] = dict(x=x, p=p, fy=rep["contact_force_y"],
                                       wall=statistics.median(walls),
                                       inner=statistics.median(inner),
                                       its=rep["newton_iterations"], conv=rep["converged"],
                                       nodes=rep["nodes"])
        results.append((hc, runs))

    # accuracy table
    out("## accuracy (per mesh; pressures p on the slave arc's nodes; diff: max |p - p_ref| over the arc / peak of p_ref)")
    out()
    hdr = (f"{'hc':>9} {'nodes':>5} {'solver':<18} {'force_y':>10} {'force err':>9} {'peak':>8} {'peak/p0-1':>9} "
           f"{'extent':>7} {'ext-b':>8} {'vsHertz':>7} {'vs ubr':>7} {'at x':>6} {'<0.8b':>6} {'L2 vs ubr':>9} {'its':>4}")
    out(hdr)
    out("-" * len(hdr))
    for hc, runs in results:
        ref = runs["ubr_1e-8_n1"]
        for key in ("ubr_default_n1", "ubr_1e-8_n1", "ubr_1e-8_n2", "gf_sliding", "gf_nodal"):
            r = runs[key]
            x, p = r["x"], r["p"]
            on_ref = np.interp(ref["x"], x, p)  # this one on ubr's nodes
            d = on_ref - ref["p"]
            dmax = np.max(np.abs(d)) / ref["p"].max()
            xmax = ref["x"][np.argmax(np.abs(d))]
            inner = ref["x"] < 0.8 * B
            din = np.max(np.abs(d[inner])) / ref["p"].max()
            dl2 = math.sqrt(np.sum(ref["w"] * d ** 2) / np.sum(ref["w"] * ref["p"] ** 2))
            dh = np.max(np.abs(p - hertz(x))) / P0
            ext = extent(x, p)
            out(f"{hc:>9} {r['nodes']:>5} {key:<18} {r['fy']:>10.6f} {r['fy'] / (F / 2) - 1:>9.1e} "
                f"{p.max():>8.3f} {p.max() / P0 - 1:>+9.2%} {ext:>7.4f} {ext - B:>+8.4f} {dh:>7.2%} "
                f"{dmax:>7.2%} {xmax:>6.3f} {din:>6.2%} {dl2:>9.2%} {r['its']:>4}")
        out()
    out("vsHertz: max |p - p_Hertz| / p0 over the arc's nodes; vs ubr: the max difference to ubr-petsc at")
    out("-ubr_lambda_rtol 1e-8 on one rank (this solver's pressure interpolated linearly in x onto ubr's nodes),")
    out("relative to ubr's peak, at x: where it is largest, <0.8b: the same over the nodes x < 0.8 b only;")
    out("L2 vs ubr: the same difference in the slave's weighted L2 norm (ubr's nodal weights).")
    out(f"extent: the last node with p > 1% of p0 (quantized by the mesh size hc); ext-b: against Hertz b = {B:.4f}.")
    out("force_y: ubr: sum over the slave nodes of -weight * lambda_n * n_y; GetFEM sliding: the integral of the")
    out("multiplier's y component over the slave arc; GetFEM nodal: the sum of the nodal multipliers (along the")
    out("master normals, ~vertical). force err: against F/2 = 10.")
    out()

    # solver accuracy: each against its own tighter solve
    out("## algebraic accuracy (each against its own converged solve)")
    for hc, runs in results:
        ref = runs["ubr_1e-8_n1"]
        d = np.max(np.abs(runs["ubr_default_n1"]["p"] - ref["p"])) / ref["p"].max()
        d2 = np.max(np.abs(runs["ubr_1e-8_n2"]["p"] - ref["p"])) / ref["p"].max()
        d2d = np.max(np.abs(runs["ubr_default_n2"]["p"] - runs["ubr_default_n1"]["p"])) / ref["p"].max()
        out(f"hc {hc}: ubr defaults against 1e-8: {d:.2e} of the peak (estimate {runs['ubr_default_n1']['est']:.2e}); "
            f"2 ranks against 1: {d2d:.1e} (defaults), {d2:.1e} (1e-8); GetFEM: Newton to a residual 1e-10 "
            f"(sliding {runs['gf_sliding']['its']}, nodal {runs['gf_nodal']['its']} iterations)")
    out()

    # time table
    out(f"## time (s), medians of {a.repeat} runs")
    out()
    hdr = f"{'hc':>9} {'nodes':>5} {'solver':<18} {'wall':>7} {'in-program':>10} {'its':>4}"
    out(hdr)
    out("-" * len(hdr))
    for hc, runs in results:
        for key in ("ubr_default_n1", "ubr_1e-8_n1", "ubr_default_n2", "ubr_1e-8_n2", "gf_sliding", "gf_nodal"):
            r = runs[key]
            out(f"{hc:>9} {r['nodes']:>5} {key:<18} {r['wall']:>7.3f} {r['inner']:>10.3f} {r['its']:>4}")
        out()
    out(f"# bench wall time {time.perf_counter() - t_start:.0f} s")

    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"written {a.out}")


if __name__ == "__main__":
    main()
