"""Shared helpers of the bench/ scripts: run ubr-petsc under mpirun, read its report."""
import json, os, statistics, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "target", "release", "ubr-petsc")


def env():
    """The runs' environment. No OMPI_MCA_rmaps_base_oversubscribe: set, it
    makes every waiting rank yield its core (Open MPI's yield_when_idle),
    which quadrupled the per-iteration collectives of the condensed solve on
    2 ranks on 2 cores (hertz_37473: 51 Schur solves 10.9 ms -> 2.7 ms
    without it); runs with more ranks than cores get --oversubscribe
    ([`mpirun`])."""
    e = dict(os.environ)
    e.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
             OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    e.pop("PETSC_OPTIONS", None)
    e.pop("OMPI_MCA_rmaps_base_oversubscribe", None)
    return e


def cores():
    """The cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def mpirun(ranks):
    """`mpirun -n ranks`, with --oversubscribe where ranks exceed the cores."""
    cmd = ["mpirun", "-n", str(ranks)]
    if ranks > cores():
        cmd.append("--oversubscribe")
    return cmd


def run(ranks, args):
    """Runs one scene and returns its JSON report; exits on failure."""
    if not os.path.exists(BIN):
        sys.exit("bench: build first (./run.sh build)")
    with tempfile.TemporaryDirectory() as d:
        rep = os.path.join(d, "r.json")
        cmd = mpirun(ranks) + [BIN] + list(args) + ["-report", rep]
        p = subprocess.run(cmd, cwd=ROOT, env=env(), capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"bench: {' '.join(cmd)} failed ({p.returncode}):\n{p.stderr}")
        with open(rep) as f:
            return json.load(f)


def repeat(n, ranks, args):
    return [run(ranks, args) for _ in range(n)]


def median(reports, key):
    return statistics.median(r[key] for r in reports)


def solve_time(r):
    """Assembly + factorization + iterations."""
    return r["time_assembly"] + r["time_factorization"] + r["time_iterations"]


def write_csv(path, rows):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    keys = list(rows[0].keys())
    with open(path + ".tmp", "w") as f:
        f.write(",".join(keys) + "\n")
        for r in rows:
            f.write(",".join(str(r[k]) for k in keys) + "\n")
    os.replace(path + ".tmp", path)
    print(f"\nwritten {os.path.relpath(path, ROOT)}")
