//! Scenes run under mpirun: an options set, a rank count, and the numbers
//! the run must reproduce (read back from its JSON report and contact CSV).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

pub const BIN: &str = env!("CARGO_BIN_EXE_ubr-petsc");

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A fresh scratch directory for one test.
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ubr-test-{}-{}", name, std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A 2D Gmsh scene meshed into a fresh scratch directory: `geo` (relative
/// to the repository) into `<scratch>/<stem>.msh`, format 2.2. Returns the
/// directory and the mesh's path.
pub fn gmsh_2d(name: &str, geo: &str) -> (PathBuf, String) {
    let dir = scratch(name);
    let stem = Path::new(geo).file_stem().unwrap().to_str().unwrap();
    let msh = dir.join(format!("{stem}.msh"));
    let run = Command::new("gmsh")
        .args(["-2", "-format", "msh22", "-o"])
        .arg(&msh)
        .arg(root().join(geo))
        .output()
        .expect("gmsh runs (apt-get install gmsh)");
    assert!(run.status.success() && msh.exists(), "gmsh failed on {geo}");
    let msh = msh.to_str().unwrap().to_string();
    (dir, msh)
}

pub struct Run {
    pub status: Option<i32>,
    pub stdout: String,
    pub stderr: String,
    pub seconds: f64,
}

/// An Open MPI session directory of one run, removed when dropped.
pub struct SessionDir(PathBuf);

impl Drop for SessionDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// `program` (mpirun, or a wrapper of it) from the repository root with the
/// tests' MPI environment and an Open MPI session directory of its own,
/// kept while the guard lives. Open MPI 4.1 keeps every session under one
/// `/tmp/ompi.HOST.UID`, which runs starting and ending together race to
/// create and remove (seen in CI: "A call to mkdir was unable to create the
/// desired directory ... File exists", orte_init failed, exit 1).
pub fn mpi_command(program: &str) -> (Command, SessionDir) {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "ubr-ompi-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::SeqCst)
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let mut cmd = Command::new(program);
    cmd.current_dir(root())
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
        .env("OMPI_MCA_orte_tmpdir_base", &dir)
        .env("OPENBLAS_NUM_THREADS", "1")
        .env("OMP_NUM_THREADS", "1")
        .env_remove("PETSC_OPTIONS");
    (cmd, SessionDir(dir))
}

/// Runs `mpirun -n ranks ubr-petsc args...` from the repository root.
pub fn mpirun(ranks: usize, args: &[&str]) -> Run {
    let t = Instant::now();
    let (mut cmd, _session) = mpi_command("mpirun");
    cmd.args(["-n", &ranks.to_string(), BIN]).args(args);
    let out: Output = cmd.output().expect("mpirun runs");
    Run {
        status: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        seconds: t.elapsed().as_secs_f64(),
    }
}

/// The Hertz scene of options/hertz-paper (the paper's Table 1 settings)
/// with a different mesh and extra options.
pub fn hertz_args<'a>(mesh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["-options_file", "options/hertz-paper", "-mesh", mesh];
    v.extend_from_slice(extra);
    v
}

/// The Hertz scene with the paper's r and stopping test, Anderson-accelerated
/// (`-ubr_anderson M` in `extra`; the paper's rho = 1.5 r is for the plain
/// iteration only).
pub fn hertz_aa_args<'a>(mesh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "-options_file",
        "options/hertz",
        "-mesh",
        mesh,
        "-ubr_r",
        "220",
        "-ubr_stop",
        "paper",
    ];
    v.extend_from_slice(extra);
    v
}

pub fn report(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

pub fn num(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("report has no number '{key}': {v}"))
}

/// Contact CSV rows as (node, lambda_n, status).
pub fn contact_csv(path: &Path) -> Vec<(u64, f64, String)> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    assert_eq!(
        header,
        "node,x,y,z,weight,gap,un,ut_x,ut_y,ut_z,lambda_n,lambda_t_x,lambda_t_y,lambda_t_z,status"
    );
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 15, "{l}");
            (
                f[0].parse().unwrap(),
                f[10].parse().unwrap(),
                f[14].to_string(),
            )
        })
        .collect()
}

/// Runs a scene with a report and a contact CSV in a scratch dir.
pub fn solve(
    name: &str,
    ranks: usize,
    args: &[&str],
) -> (Run, serde_json::Value, Vec<(u64, f64, String)>) {
    let dir = scratch(name);
    let rep = dir.join("report.json");
    let csv = dir.join("contact.csv");
    let (rs, cs) = (
        rep.to_str().unwrap().to_string(),
        csv.to_str().unwrap().to_string(),
    );
    let mut a: Vec<&str> = args.to_vec();
    a.extend_from_slice(&["-report", &rs, "-contact_output", &cs]);
    let run = mpirun(ranks, &a);
    assert_eq!(
        run.status,
        Some(0),
        "{name}: stdout:\n{}\nstderr:\n{}",
        run.stdout,
        run.stderr
    );
    let r = report(&rep);
    let c = contact_csv(&csv);
    let _ = std::fs::remove_dir_all(&dir);
    (run, r, c)
}

pub fn within(limit: Duration, run: &Run) {
    assert!(
        run.seconds < limit.as_secs_f64(),
        "took {:.1} s",
        run.seconds
    );
}

/// A full contact CSV row.
#[derive(Clone, Debug)]
pub struct Row {
    pub node: u64,
    pub x: [f64; 3],
    pub un: f64,
    pub ut: [f64; 3],
    pub lambda_n: f64,
    pub lambda_t: [f64; 3],
    pub status: String,
}

pub fn contact_rows(path: &Path) -> Vec<Row> {
    parse_rows(&std::fs::read_to_string(path).unwrap())
}

/// The rows of a contact CSV's text (the header line skipped).
pub fn parse_rows(text: &str) -> Vec<Row> {
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let v = |i: usize| -> f64 { f[i].parse().unwrap() };
            Row {
                node: f[0].parse().unwrap(),
                x: [v(1), v(2), v(3)],
                un: v(6),
                ut: [v(7), v(8), v(9)],
                lambda_n: v(10),
                lambda_t: [v(11), v(12), v(13)],
                status: f[14].to_string(),
            }
        })
        .collect()
}

/// Like `solve`, returning the full CSV rows.
pub fn solve_rows(name: &str, ranks: usize, args: &[&str]) -> (Run, serde_json::Value, Vec<Row>) {
    let dir = scratch(name);
    let rep = dir.join("report.json");
    let csv = dir.join("contact.csv");
    let (rs, cs) = (
        rep.to_str().unwrap().to_string(),
        csv.to_str().unwrap().to_string(),
    );
    let mut a: Vec<&str> = args.to_vec();
    a.extend_from_slice(&["-report", &rs, "-contact_output", &cs]);
    let run = mpirun(ranks, &a);
    assert_eq!(
        run.status,
        Some(0),
        "{name}: stdout:\n{}\nstderr:\n{}",
        run.stdout,
        run.stderr
    );
    let r = report(&rep);
    let c = contact_rows(&csv);
    let _ = std::fs::remove_dir_all(&dir);
    (run, r, c)
}

/// max |lambda_n(a) - lambda_n(b)| / max lambda_n(b), rows matched by node.
pub fn max_pressure_gap(a: &[Row], b: &[Row]) -> f64 {
    assert_eq!(a.len(), b.len());
    let peak = b.iter().map(|r| r.lambda_n).fold(0.0, f64::max);
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            assert_eq!(x.node, y.node);
            (x.lambda_n - y.lambda_n).abs()
        })
        .fold(0.0, f64::max)
        / peak
}
