"""Helpers of bench/run: runs that may stop unconverged, contact CSVs, errors
against a reference solution, fitted rates, and the PNG plots (drawn by the
cargo example examples/bench_plot.rs from a JSON spec)."""
import csv, json, math, os, shutil, statistics, subprocess, sys, tempfile, time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from benchlib import BIN, ROOT, env, mpirun, solve_time  # noqa: E402,F401

RESULTS = os.path.join(ROOT, "bench", "results")
PLOTTER = os.path.join(ROOT, "target", "release", "examples", "bench_plot")

HERTZ_MESHES = ["meshes/hertz_442.msh", "meshes/hertz_1692.msh", "meshes/hertz_6619.msh",
                "meshes/hertz_26181.msh", "meshes/hertz_37473.msh"]


def mesh_name(mesh):
    """meshes/hertz_37473.msh -> 37473 (the paper's node count)."""
    return os.path.basename(mesh).rsplit(".", 1)[0].split("_", 1)[-1]


def run(ranks, args, contact=False):
    """Runs one scene; returns (report, contact rows or None). Exit status 3
    (not converged) is accepted, the report says converged: false; any other
    failure stops the benchmark with the command and its error output."""
    if not os.path.exists(BIN):
        sys.exit("bench: build first (cargo build --release)")
    with tempfile.TemporaryDirectory() as d:
        rep, con = os.path.join(d, "r.json"), os.path.join(d, "c.csv")
        cmd = mpirun(ranks) + [BIN] + list(args) + ["-report", rep]
        if contact:
            cmd += ["-contact_output", con]
        p = subprocess.run(cmd, cwd=ROOT, env=env(), capture_output=True, text=True)
        if p.returncode not in (0, 3) or not os.path.exists(rep):
            sys.exit(f"bench: {' '.join(cmd)} failed ({p.returncode}):\n{p.stderr}{p.stdout[-2000:]}")
        with open(rep) as f:
            report = json.load(f)
        rows = read_contact(con) if contact else None
        return report, rows


_SNAPSHOT = None


def snapshot_binary():
    """Runs of this process use a copy of target/release/ubr-petsc taken now,
    so that a rebuild during the benchmark cannot mix two versions (the
    bench/table* scripts, run as their own processes, use the live binary)."""
    global BIN, _SNAPSHOT
    if not os.path.exists(BIN):
        sys.exit("bench: build first (cargo build --release)")
    _SNAPSHOT = tempfile.TemporaryDirectory(prefix="ubr-bench-")
    src = BIN
    BIN = os.path.join(_SNAPSHOT.name, "ubr-petsc")
    shutil.copy2(src, BIN)
    when = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(os.path.getmtime(src)))
    return f"binary: {os.path.relpath(src, ROOT)} built {when} (a copy is used by steps 2-6)"


def read_contact(path):
    with open(path) as f:
        return [{k: (v if k == "status" else float(v)) for k, v in r.items()} for r in csv.DictReader(f)]


def pressure_error(rows, ref):
    """Relative weighted L2 distance of the contact pressures lambda_n of
    `rows` from those of `ref` (same mesh, matched by node tag), with the
    quadrature weights of the CSV's `weight` column."""
    pr = {r["node"]: r for r in ref}
    num = den = 0.0
    for r in rows:
        q = pr[r["node"]]
        num += q["weight"] * (r["lambda_n"] - q["lambda_n"]) ** 2
        den += q["weight"] * q["lambda_n"] ** 2
    return math.sqrt(num / den)


def contact_h(rows, half_width):
    """Mesh size at the contact: mean distance between consecutive contact
    candidates (ordered along the surface) within the Hertz half-width."""
    pts = sorted((r["x"], r["y"]) for r in rows if r["x"] <= half_width * 1.0001)
    d = [math.dist(a, b) for a, b in zip(pts, pts[1:])]
    return statistics.mean(d)


def fit_rate(xs, ys):
    """Least-squares slope and intercept of log y against log x."""
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = statistics.mean(lx), statistics.mean(ly)
    sxx = sum((a - mx) ** 2 for a in lx)
    slope = sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx
    return slope, math.exp(my - slope * mx)


def write_csv(name, rows):
    """Writes bench/results/NAME (atomically) and says so."""
    os.makedirs(RESULTS, exist_ok=True)
    path = os.path.join(RESULTS, name)
    keys = list(rows[0].keys())
    for r in rows[1:]:
        keys += [k for k in r if k not in keys]
    with open(path + ".tmp", "w") as f:
        f.write(",".join(keys) + "\n")
        for r in rows:
            f.write(",".join(fmt(r.get(k, "")) for k in keys) + "\n")
    os.replace(path + ".tmp", path)
    print(f"  written {os.path.relpath(path, ROOT)}")


def fmt(v):
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def build_plotter():
    p = subprocess.run(["cargo", "build", "--release", "--quiet", "--example", "bench_plot"], cwd=ROOT,
                       capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"bench: cannot build examples/bench_plot:\n{p.stderr}")


def plot(plots):
    """Draws a list of plot specs (see examples/bench_plot.rs); paths are
    file names in bench/results/."""
    os.makedirs(RESULTS, exist_ok=True)
    for p in plots:
        p["path"] = os.path.join(RESULTS, p["path"])
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(plots, f, allow_nan=False, default=float)
        spec = f.name
    try:
        p = subprocess.run([PLOTTER, spec], cwd=ROOT, capture_output=True, text=True)
    finally:
        os.unlink(spec)
    if p.returncode != 0:
        sys.exit(f"bench: plotting failed:\n{p.stderr}")
    for q in plots:
        print(f"  plotted {os.path.relpath(q['path'], ROOT)}")


def series(label, x, y, style="line", color=None):
    s = dict(label=label, x=[float(v) for v in x], y=[float(v) for v in y], style=style)
    if color is not None:
        s["color"] = color
    return s


def have_cargo():
    return shutil.which("cargo") is not None
