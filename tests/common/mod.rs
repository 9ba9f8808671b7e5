//! What every test file shares: running the program under mpirun (with the
//! tests' MPI environment), its JSON report read into a typed [`Report`],
//! its contact CSV read into [`Row`]s, pressure comparisons between two
//! runs, and the discrete optimality conditions checked from the CSV alone.
//!
//! `UBR_TEST_PERTURB=NAME=FACTOR` multiplies the contact stresses read back
//! from the run named NAME (the `name` given to [`solve_rows`] or
//! [`run_outputs`]) by FACTOR: a deliberately wrong answer, to see a test
//! fail (README, "Tests").
#![allow(dead_code)]

use serde::{Deserialize, Deserializer};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

pub const BIN: &str = env!("CARGO_BIN_EXE_ubr-petsc");

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The Python that reads VTK and meshio files: `UBR_PYTHON`, else the
/// first of `python3` from PATH and Debian's `/usr/bin/python3` that
/// imports both (a pyenv `python3` ahead on PATH often lacks them).
pub fn python() -> String {
    static PYTHON: OnceLock<String> = OnceLock::new();
    PYTHON
        .get_or_init(|| {
            if let Ok(p) = std::env::var("UBR_PYTHON") {
                return p;
            }
            let imports = |p: &str| {
                Command::new(p)
                    .args(["-c", "import vtk, meshio"])
                    .output()
                    .is_ok_and(|o| o.status.success())
            };
            ["python3", "/usr/bin/python3"]
                .into_iter()
                .find(|p| imports(p))
                .unwrap_or("python3")
                .to_string()
        })
        .clone()
}

/// A fresh scratch directory for one test, removed when the guard is
/// dropped unless the test is failing (a panicking test keeps its files to
/// look at). Derefs to its path.
pub fn scratch(name: &str) -> Scratch {
    // Unique per call: two tests of one binary (one process) that ask for
    // the same name at once (the converged reference of one scene) must not
    // remove each other's directory (seen in CI: "cannot write
    // .../contact.csv: No such file or directory").
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    // One directory: a name made of a mesh's path ("meshes/x.msh") made
    // the guard remove only the inner one.
    let name = name.replace(['/', '\\'], "_");
    let d = std::env::temp_dir().join(format!("ubr-test-{}-{}-{call}", name, std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    Scratch(d)
}

/// A test's scratch directory (see [`scratch`]): every run of the suite
/// left some thirty of them in the temporary folder before.
pub struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = PathBuf;
    fn deref(&self) -> &PathBuf {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// A 2D Gmsh scene meshed into a fresh scratch directory: `geo` (relative
/// to the repository) into `<scratch>/<stem>.msh`, format 2.2. Returns the
/// directory and the mesh's path.
pub fn gmsh_2d(name: &str, geo: &str) -> (Scratch, String) {
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

/// Meshes `geo` (relative to the repository) with gmsh into `out`, format
/// 4.1: `dim` is "-1", "-2" or "-3", `set` the `-setnumber` pairs.
pub fn gmsh(dim: &str, geo: &str, out: &Path, set: &[(&str, &str)]) {
    let mut cmd = Command::new("gmsh");
    cmd.args([dim, "-format", "msh41"]);
    for (k, v) in set {
        cmd.args(["-setnumber", k, v]);
    }
    let run = cmd
        .arg("-o")
        .arg(out)
        .arg(root().join(geo))
        .output()
        .expect("gmsh runs (apt-get install gmsh)");
    assert!(run.status.success() && out.exists(), "gmsh failed on {geo}");
}

pub struct Run {
    pub status: Option<i32>,
    pub stdout: String,
    pub stderr: String,
    pub seconds: f64,
}

impl Run {
    fn from_output(out: Output, t: Instant) -> Run {
        Run {
            status: out.status.code(),
            stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
            seconds: t.elapsed().as_secs_f64(),
        }
    }

    /// The exit status, stdout and stderr, for a failed assertion.
    pub fn context(&self) -> String {
        format!(
            "exit {:?}, {:.1} s\nstdout:\n{}\nstderr:\n{}",
            self.status, self.seconds, self.stdout, self.stderr
        )
    }

    /// The lines the program printed as its own errors (`error: ...`).
    pub fn error_lines(&self) -> Vec<&str> {
        self.stderr
            .lines()
            .filter(|l| l.starts_with("error:"))
            .collect()
    }

    /// The lines of stderr that contain `needle` (a warning's words).
    pub fn stderr_with(&self, needle: &str) -> Vec<&str> {
        self.stderr.lines().filter(|l| l.contains(needle)).collect()
    }

    /// A refused run (docs/DESIGN.md, "Exit status"): exit `status`, one
    /// `error:` line (printed once, whatever the rank count) carrying every
    /// one of `needles` (the option, file or reason). Returns the line.
    pub fn refused(&self, what: &str, status: i32, needles: &[&str]) -> &str {
        assert_eq!(self.status, Some(status), "{what}: {}", self.context());
        let lines = self.error_lines();
        assert_eq!(lines.len(), 1, "{what}: one error line: {}", self.context());
        for needle in needles {
            assert!(
                lines[0].contains(needle),
                "{what}: '{}' does not name '{needle}'",
                lines[0]
            );
        }
        lines[0]
    }
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
        .env_remove("PETSC_OPTIONS")
        .env_remove("SCOTCH_PTHREAD_NUMBER");
    (cmd, SessionDir(dir))
}

/// Runs `mpirun -n ranks ubr-petsc args...` from the repository root.
pub fn mpirun(ranks: usize, args: &[&str]) -> Run {
    let t = Instant::now();
    let (mut cmd, _session) = mpi_command("mpirun");
    cmd.args(["-n", &ranks.to_string(), BIN]).args(args);
    Run::from_output(cmd.output().expect("mpirun runs"), t)
}

/// A run with its outputs read back, whatever its exit status.
pub struct Outputs {
    pub name: String,
    pub run: Run,
    /// None: `timeout` killed it (exit 124 or 137).
    pub status: Option<i32>,
    pub report_text: Option<String>,
    pub csv_text: Option<String>,
}

impl Outputs {
    pub fn report(&self) -> Report {
        let text = self
            .report_text
            .as_deref()
            .unwrap_or_else(|| panic!("{}: no report\n{}", self.name, self.run.stderr));
        parse_report(text).unwrap_or_else(|e| panic!("{}: report: {e}", self.name))
    }

    pub fn rows(&self) -> Vec<Row> {
        let text = self
            .csv_text
            .as_deref()
            .unwrap_or_else(|| panic!("{}: no contact CSV\n{}", self.name, self.run.stderr));
        perturbed(&self.name, parse_rows(text))
    }

    pub fn context(&self) -> String {
        format!("{}: {}", self.name, self.run.context())
    }
}

/// `mpirun -n ranks ubr-petsc args... -report R -contact_output C` from the
/// repository root, under `timeout -k 10 SECONDS` when `seconds` is given;
/// the report and CSV read back (when written) and the scratch dir removed.
pub fn run_outputs(name: &str, ranks: usize, args: &[&str], seconds: Option<u64>) -> Outputs {
    let dir = scratch(&format!("run-{name}"));
    let (rep, csv) = (dir.join("report.json"), dir.join("contact.csv"));
    let t = Instant::now();
    let (mut cmd, _session) = match seconds {
        Some(s) => {
            let (mut c, g) = mpi_command("timeout");
            c.args(["-k", "10", &s.to_string(), "mpirun"]);
            (c, g)
        }
        None => mpi_command("mpirun"),
    };
    cmd.args(["-n", &ranks.to_string(), BIN])
        .args(args)
        .arg("-report")
        .arg(&rep)
        .arg("-contact_output")
        .arg(&csv);
    let run = Run::from_output(cmd.output().expect("mpirun runs"), t);
    let status = match run.status {
        Some(124) | Some(137) if seconds.is_some() => None,
        s => s,
    };
    let out = Outputs {
        name: name.to_string(),
        status,
        run,
        report_text: std::fs::read_to_string(&rep).ok(),
        csv_text: std::fs::read_to_string(&csv).ok(),
    };
    let _ = std::fs::remove_dir_all(&dir);
    out
}

/// Runs a scene with a report and a contact CSV; it must exit 0.
pub fn solve_rows(name: &str, ranks: usize, args: &[&str]) -> (Run, Report, Vec<Row>) {
    let out = run_outputs(name, ranks, args, None);
    assert_eq!(out.status, Some(0), "{}", out.context());
    let (report, rows) = (out.report(), out.rows());
    (out.run, report, rows)
}

pub fn within(limit: Duration, run: &Run) {
    assert!(
        run.seconds < limit.as_secs_f64(),
        "took {:.1} s",
        run.seconds
    );
}

/// The Hertz scene of options/hertz-paper (the paper's Table 1 settings)
/// with a different mesh and extra options.
pub fn hertz_args<'a>(mesh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["-options_file", "options/hertz-paper", "-mesh", mesh];
    v.extend_from_slice(extra);
    v
}

/// The block of tests/obstacles/multi_block2d.geo (tests/obstacles.rs,
/// tests/surface_obstacle.rs), held in x at its top
/// midpoint, at a tight tolerance.
pub fn block2d<'a>(msh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "-mesh",
        msh,
        "-E",
        "1e6",
        "-nu",
        "0.3",
        "-dirichlet_mid",
        "ux=0",
        "-ubr_lambda_rtol",
        "1e-9",
    ];
    v.extend_from_slice(extra);
    v
}

/// The punch pressed on the base (tests/pairs/punch3d.geo: two boxes meshed
/// apart, the punch's bottom a contact pair's slave on the base's top),
/// meshed into `dir`; returns the mesh's path.
pub fn punch3d_mesh(dir: &Path) -> String {
    let msh = dir.join("punch3d.msh");
    gmsh("-3", "tests/pairs/punch3d.geo", &msh, &[]);
    msh.to_str().unwrap().to_string()
}

/// The punch scene's options on `msh` (the base held at its bottom, the
/// punch's top moved down by 0.01), then `extra`.
pub fn punch3d_args<'a>(msh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "-mesh",
        msh,
        "-E",
        "1000",
        "-nu",
        "0.3",
        "-dirichlet_bottom",
        "ux=0,uy=0,uz=0",
        "-dirichlet_ptop",
        "ux=0,uy=0,uz=-0.01",
        "-contact_pair",
        "pbot,btop",
    ];
    v.extend_from_slice(extra);
    v
}

/// options/hertz without its symmetry condition `ux = 0`, on `mesh`, with
/// `traction` on the top edge: contact and friction alone hold the quarter
/// (frictionless contact along n = -y holds nothing along x).
pub fn hertz_free_x<'a>(mesh: &'a str, traction: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "-mesh",
        mesh,
        "-E",
        "2000",
        "-nu",
        "0.3",
        "-traction_top",
        traction,
        "-contact_surface",
        "contact",
        "-contact_direction",
        "0,-1",
        "-obstacle",
        "plane",
        "-obstacle_point",
        "0,0",
    ];
    v.extend_from_slice(extra);
    v
}

/// options/hertz held by `uy = 0` on its cut instead of `ux = 0`, pushed
/// sideways by (30, -100) on its top (240 along x in all), with `extra`
/// (the friction): friction alone holds it along x.
pub fn hertz_sideways_held_y<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "-options_file",
        "options/hertz",
        "-traction_top",
        "30,-100",
        "-dirichlet_symmetry",
        "uy=0",
    ];
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

/// A tolerance far tighter than any test's: appended to a scene's options,
/// the converged discrete solution (Anderson-accelerated accuracy stop).
pub const CONVERGED: [&str; 6] = [
    "-ubr_anderson",
    "10",
    "-ubr_stop",
    "accuracy",
    "-ubr_lambda_rtol",
    "1e-9",
];

/// The contact rows of `args` + [`CONVERGED`] on one rank: the converged
/// discrete solution of a scene, computed once per test binary and key.
pub fn converged_rows(key: &str, args: &[&str]) -> Arc<Vec<Row>> {
    static CACHE: OnceLock<Mutex<HashMap<String, Arc<Vec<Row>>>>> = OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    if let Some(rows) = cache.lock().unwrap().get(key) {
        return rows.clone();
    }
    let mut a = args.to_vec();
    a.extend_from_slice(&CONVERGED);
    let (_, rep, rows) = solve_rows(&format!("converged-{key}"), 1, &a);
    assert!(rep.converged, "{key}: the reference did not converge");
    let rows = Arc::new(rows);
    cache.lock().unwrap().insert(key.to_string(), rows.clone());
    rows
}

// ----- the JSON report -----

/// A number of the report; `null` (not finite, or not computed) reads as NaN.
fn number<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// The keys of the JSON report (docs/DESIGN.md, "-report FILE.json") that
/// the tests read. Counts are read as numbers (f64) like the other keys.
/// One entry of the report's `obstacles`.
#[derive(Clone, Debug, Deserialize)]
pub struct ObstacleForce {
    pub name: String,
    pub force: Vec<f64>,
    pub contact_nodes: usize,
}

#[derive(Clone, Debug, Deserialize)]
pub struct Report {
    #[serde(deserialize_with = "number")]
    pub dimension: f64,
    #[serde(deserialize_with = "number")]
    pub nodes: f64,
    #[serde(deserialize_with = "number")]
    pub elements: f64,
    #[serde(deserialize_with = "number")]
    pub contact_nodes: f64,
    #[serde(deserialize_with = "number")]
    pub ranks: f64,
    pub partition: String,
    pub algorithm: String,
    pub paper_algorithm: String,
    pub friction: String,
    #[serde(deserialize_with = "number")]
    pub friction_coefficient: f64,
    pub mesh: String,
    pub linear_solver: String,
    #[serde(rename = "E", deserialize_with = "number")]
    pub young: f64,
    #[serde(deserialize_with = "number")]
    pub nu: f64,
    #[serde(deserialize_with = "number")]
    pub r: f64,
    #[serde(deserialize_with = "number")]
    pub rho: f64,
    pub r_source: String,
    #[serde(deserialize_with = "number")]
    pub r_trial: f64,
    #[serde(deserialize_with = "number")]
    pub r_estimate: f64,
    pub stop: String,
    #[serde(deserialize_with = "number")]
    pub anderson_memory: f64,
    #[serde(deserialize_with = "number")]
    pub condensed_unknowns: f64,
    #[serde(deserialize_with = "number")]
    pub iterations: f64,
    #[serde(deserialize_with = "number")]
    pub fixed_point_iterations: f64,
    /// CF-FP's relative change of s at its last iteration (null elsewhere).
    #[serde(default)]
    pub fixed_point_change: Option<f64>,
    #[serde(deserialize_with = "number")]
    pub frictionless_iterations: f64,
    #[serde(deserialize_with = "number")]
    pub linear_solves: f64,
    pub inner_iterations: Vec<f64>,
    pub converged: bool,
    pub failure: Option<String>,
    #[serde(deserialize_with = "number")]
    pub lambda_error_estimate: f64,
    #[serde(deserialize_with = "number")]
    pub criterion: f64,
    #[serde(deserialize_with = "number")]
    pub contact_active: f64,
    /// `"fixed"` or `"closest"` (absent from older reports).
    #[serde(default)]
    pub contact_normal: String,
    #[serde(deserialize_with = "number")]
    pub stick_nodes: f64,
    #[serde(deserialize_with = "number")]
    pub slip_nodes: f64,
    #[serde(deserialize_with = "number")]
    pub contact_force: f64,
    pub tangential_force: Vec<f64>,
    pub contact_force_groups: BTreeMap<String, f64>,
    pub contact_force_vector: Vec<f64>,
    /// Each obstacle's force and nodes in contact (`-obstacles`).
    #[serde(default)]
    pub obstacles: Vec<ObstacleForce>,
    pub load: Vec<f64>,
    pub reactions: BTreeMap<String, Vec<f64>>,
    #[serde(deserialize_with = "number")]
    pub peak_pressure: f64,
    #[serde(deserialize_with = "number")]
    pub pressure_error_rel: f64,
    #[serde(deserialize_with = "number")]
    pub peak_pressure_hertz: f64,
    #[serde(deserialize_with = "number")]
    pub contact_half_width_hertz: f64,
    #[serde(default, deserialize_with = "number")]
    pub hertz_e_star: f64,
    #[serde(default, deserialize_with = "number")]
    pub hertz_radius: f64,
    #[serde(deserialize_with = "number")]
    pub contact_half_width: f64,
    #[serde(deserialize_with = "number")]
    pub equilibrium_residual_rel: f64,
    #[serde(deserialize_with = "number")]
    pub min_lambda_n: f64,
    #[serde(deserialize_with = "number")]
    pub min_lambda_n_rel: f64,
    #[serde(deserialize_with = "number")]
    pub max_penetration: f64,
    #[serde(deserialize_with = "number")]
    pub max_penetration_rel: f64,
    #[serde(deserialize_with = "number")]
    pub complementarity_rel: f64,
    #[serde(deserialize_with = "number")]
    pub max_abs_gap: f64,
    #[serde(deserialize_with = "number")]
    pub complementarity: f64,
    #[serde(deserialize_with = "number")]
    pub max_friction_excess: f64,
    #[serde(deserialize_with = "number")]
    pub max_friction_excess_rel: f64,
    #[serde(deserialize_with = "number")]
    pub max_bound: f64,
    #[serde(deserialize_with = "number")]
    pub max_slip: f64,
    #[serde(deserialize_with = "number")]
    pub max_stick_slip: f64,
    #[serde(deserialize_with = "number")]
    pub max_stick_slip_rel: f64,
    #[serde(deserialize_with = "number")]
    pub min_slip_alignment: f64,
    #[serde(deserialize_with = "number")]
    pub matrix_mallocs: f64,
    pub warnings: Vec<String>,
}

pub fn parse_report(text: &str) -> Result<Report, serde_json::Error> {
    serde_json::from_str(text)
}

pub fn report(path: &Path) -> Report {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    parse_report(&text).unwrap_or_else(|e| panic!("{}: {e}\n{text}", path.display()))
}

// ----- the contact CSV -----

pub const CSV_HEADER: &str =
    "node,x,y,z,weight,gap,un,ut_x,ut_y,ut_z,lambda_n,lambda_t_x,lambda_t_y,lambda_t_z,status,n_x,n_y,n_z";

/// A contact CSV row (docs/DESIGN.md, "-contact_output FILE.csv").
#[derive(Clone, Debug)]
pub struct Row {
    pub node: u64,
    pub x: [f64; 3],
    pub weight: f64,
    pub gap: f64,
    pub un: f64,
    pub ut: [f64; 3],
    pub lambda_n: f64,
    pub lambda_t: [f64; 3],
    pub status: String,
    /// The candidate's unit normal (the columns appended last).
    pub normal: [f64; 3],
}

pub fn contact_rows(path: &Path) -> Vec<Row> {
    parse_rows(&std::fs::read_to_string(path).unwrap())
}

/// The rows of a contact CSV's text, its header checked.
pub fn parse_rows(text: &str) -> Vec<Row> {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(CSV_HEADER), "contact CSV header");
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 18, "{l}");
            let v = |i: usize| -> f64 {
                f[i].parse()
                    .unwrap_or_else(|e| panic!("column {i} of '{l}': {e}"))
            };
            Row {
                node: f[0].parse().unwrap(),
                x: [v(1), v(2), v(3)],
                weight: v(4),
                gap: v(5),
                un: v(6),
                ut: [v(7), v(8), v(9)],
                lambda_n: v(10),
                lambda_t: [v(11), v(12), v(13)],
                status: f[14].to_string(),
                normal: [v(15), v(16), v(17)],
            }
        })
        .collect()
}

/// The rows of run `name` with `UBR_TEST_PERTURB=name=FACTOR` applied.
fn perturbed(name: &str, mut rows: Vec<Row>) -> Vec<Row> {
    let Ok(spec) = std::env::var("UBR_TEST_PERTURB") else {
        return rows;
    };
    let (target, factor) = spec.split_once('=').expect("UBR_TEST_PERTURB=NAME=FACTOR");
    if target == name {
        let f: f64 = factor.parse().expect("UBR_TEST_PERTURB: FACTOR a number");
        eprintln!("UBR_TEST_PERTURB: contact stresses of '{name}' multiplied by {f}");
        for r in &mut rows {
            r.lambda_n *= f;
            r.lambda_t.iter_mut().for_each(|t| *t *= f);
        }
    }
    rows
}

pub fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

// ----- pressure comparisons -----

/// max over the nodes of |field(a) - field(b)|, rows matched by node,
/// relative to max |field(b)| (absolute where b vanishes everywhere).
pub fn field_gap(a: &[Row], b: &[Row], field: impl Fn(&Row) -> f64) -> f64 {
    assert_eq!(a.len(), b.len(), "not the same candidates");
    let bm: HashMap<u64, f64> = b.iter().map(|r| (r.node, field(r))).collect();
    let peak = b.iter().map(|r| field(r).abs()).fold(0.0, f64::max);
    a.iter()
        .map(|r| {
            let other = bm
                .get(&r.node)
                .unwrap_or_else(|| panic!("node {} not in both", r.node));
            (field(r) - other).abs()
        })
        .fold(0.0, f64::max)
        / if peak > 0.0 { peak } else { 1.0 }
}

/// Asserts that the normals of the rows on the symmetry planes x = 0 and
/// y = 0 lie in them, and returns how many rows lie on each.
pub fn normals_in_symmetry_planes<'a>(rows: impl Iterator<Item = &'a Row>) -> (usize, usize) {
    let (mut on_x0, mut on_y0) = (0, 0);
    for r in rows {
        if r.x[0].abs() < 1e-12 {
            on_x0 += 1;
            assert_eq!(r.normal[0], 0.0, "node {} on x = 0", r.node);
        }
        if r.x[1].abs() < 1e-12 {
            on_y0 += 1;
            assert_eq!(r.normal[1], 0.0, "node {} on y = 0", r.node);
        }
    }
    (on_x0, on_y0)
}

/// max |lambda_n(a) - lambda_n(b)| / max |lambda_n(b)|, rows matched by node.
pub fn max_pressure_gap(a: &[Row], b: &[Row]) -> f64 {
    field_gap(a, b, |r| r.lambda_n)
}

/// max over the nodes of max(|lambda_n(a) - lambda_n(b)|, |lambda_t(a) -
/// lambda_t(b)|) / max |lambda_n(b)|: normal and tangential stresses.
pub fn max_stress_gap(a: &[Row], b: &[Row]) -> f64 {
    let peak = b.iter().map(|r| r.lambda_n.abs()).fold(0.0, f64::max);
    let bm: HashMap<u64, &Row> = b.iter().map(|r| (r.node, r)).collect();
    assert_eq!(a.len(), b.len(), "not the same candidates");
    a.iter()
        .map(|x| {
            let y = bm[&x.node];
            let dt: Vec<f64> = (0..3).map(|k| x.lambda_t[k] - y.lambda_t[k]).collect();
            (x.lambda_n - y.lambda_n).abs().max(norm(&dt))
        })
        .fold(0.0, f64::max)
        / peak
}

/// max |lambda_t(a) - lambda_t(b)| / max |lambda_t(b)|, rows matched by
/// node (0 where both are frictionless).
pub fn max_tangential_gap(a: &[Row], b: &[Row]) -> f64 {
    let bm: HashMap<u64, &Row> = b.iter().map(|r| (r.node, r)).collect();
    assert_eq!(a.len(), b.len(), "not the same candidates");
    let peak = b.iter().map(|r| norm(&r.lambda_t)).fold(0.0, f64::max);
    let worst = a
        .iter()
        .map(|x| {
            let y = bm[&x.node];
            let d: Vec<f64> = (0..3).map(|k| x.lambda_t[k] - y.lambda_t[k]).collect();
            norm(&d)
        })
        .fold(0.0, f64::max);
    if worst == 0.0 {
        0.0
    } else {
        worst / peak
    }
}

// ----- the optimality conditions, from the CSV alone -----

/// The scales of the optimality conditions: stresses relative to `s`,
/// displacements relative to `u`.
#[derive(Clone, Copy, Debug)]
pub struct Scales {
    pub s: f64,
    pub u: f64,
}

impl Scales {
    /// The peak pressure (or `s0` if larger) and the largest |u_n| (or
    /// `u0` if larger).
    pub fn of(rows: &[Row], s0: f64, u0: f64) -> Scales {
        let s = rows.iter().map(|r| r.lambda_n.abs()).fold(s0, f64::max);
        let u = rows.iter().map(|r| r.un.abs()).fold(u0, f64::max);
        Scales { s, u }
    }
}

/// Signorini's conditions at every candidate, to `tol` of the scales:
/// lambda_n >= 0, u_n <= g, and lambda_n (g - u_n) = 0 (the smaller of the
/// two relative to its scale at most `tol`).
pub fn check_signorini(rows: &[Row], sc: Scales, tol: f64) -> Result<(), String> {
    for r in rows {
        let (p, open) = (r.lambda_n / sc.s, (r.gap - r.un) / sc.u);
        if p < -tol {
            return Err(format!("node {}: lambda_n {:e} < 0", r.node, r.lambda_n));
        }
        if open < -tol {
            return Err(format!(
                "node {}: penetration u_n - g = {:e}",
                r.node,
                r.un - r.gap
            ));
        }
        if p.min(open) > tol {
            return Err(format!(
                "node {}: lambda_n {:e} on an open node (g - u_n {:e})",
                r.node,
                r.lambda_n,
                r.gap - r.un
            ));
        }
    }
    Ok(())
}

/// The friction law with the bound `bound(row)` (Tresca: s; Coulomb:
/// nu_f lambda_n) at every candidate, stresses to `tol` of the scale
/// `sc.s`: |lambda_t| <= s; a node marked `slip` at the bound; a node that
/// slips (|u_t| over `slip_tol` of the largest slip) and presses at the
/// bound, lambda_t along u_t (the contract's convention, lambda = -sigma:
/// both point the way the body slides), and not marked `stick`.
pub fn check_friction(
    rows: &[Row],
    sc: Scales,
    tol: f64,
    slip_tol: f64,
    bound: impl Fn(&Row) -> f64,
) -> Result<(), String> {
    let slip_scale = rows.iter().map(|r| norm(&r.ut)).fold(0.0, f64::max);
    for r in rows {
        let (lt, ut, s) = (norm(&r.lambda_t), norm(&r.ut), bound(r));
        if lt > s + tol * sc.s {
            return Err(format!(
                "node {}: |lambda_t| {lt:e} over the bound {s:e}",
                r.node
            ));
        }
        if r.status == "slip" && lt < s - tol * sc.s {
            return Err(format!(
                "node {}: 'slip' with |lambda_t| {lt:e} under the bound {s:e}",
                r.node
            ));
        }
        let slipping = ut > slip_tol * slip_scale && r.lambda_n > tol * sc.s;
        if !slipping {
            continue;
        }
        if lt < s - tol * sc.s {
            return Err(format!(
                "node {}: slips ({ut:e}) with |lambda_t| {lt:e} under the bound {s:e}",
                r.node
            ));
        }
        if lt > tol * sc.s && dot(&r.lambda_t, &r.ut) < (1.0 - tol) * lt * ut {
            return Err(format!(
                "node {}: lambda_t {:?} not along the slip u_t {:?}",
                r.node, r.lambda_t, r.ut
            ));
        }
        if r.status == "stick" {
            return Err(format!("node {}: 'stick' with a slip of {ut:e}", r.node));
        }
    }
    Ok(())
}

/// The Tresca bound of `-tresca_bound hertz` on the 2D Hertz scenes,
/// computed here from Hertz's formula (docs/DESIGN.md, "Reference"):
/// nu_f p(x), x the distance along the surface from the candidate with the
/// smallest gap (the default -reference_center).
pub fn hertz_bound_2d(
    rows: &[Row],
    nu_f: f64,
    force: f64,
    radius: f64,
    young: f64,
    nu: f64,
) -> HashMap<u64, f64> {
    let centre = rows
        .iter()
        .min_by(|a, b| a.gap.total_cmp(&b.gap))
        .expect("candidates")
        .x[0];
    rows.iter()
        .map(|r| {
            let p = hertz_pressure_2d(force, radius, young, nu, r.x[0] - centre);
            (r.node, nu_f * p)
        })
        .collect()
}

/// Hertz's 2D pressure at distance `x` from the centre (plane strain):
/// b = 2 sqrt(F R / (pi E*)), p = 2F/(pi b^2) sqrt(b^2 - x^2), E* = E/(1-nu^2).
pub fn hertz_pressure_2d(force: f64, radius: f64, young: f64, nu: f64, x: f64) -> f64 {
    let e_star = young / (1.0 - nu * nu);
    let b = 2.0 * (force * radius / (std::f64::consts::PI * e_star)).sqrt();
    if x.abs() >= b {
        0.0
    } else {
        2.0 * force / (std::f64::consts::PI * b * b) * (b * b - x * x).sqrt()
    }
}
