//! Issue 12 ("Trustworthy by default"), acceptance: on independent scenes
//! (tests/scenes/, made as a user would make them, not tuned to the solver),
//! the contact stresses the program reports at its defaults are within 1e-3
//! of the converged discrete solution; at `-ubr_lambda_rtol 1e-6` within 2e-6,
//! with the default direct solver and with `-ksp_type cg -pc_type gamg`, on
//! one rank and several.
//!
//! Each scene is an options file `tests/scenes/NAME.opts`; where it uses
//! Gmsh, its mesh is generated here from `NAME.geo` by the command on the
//! file's `# Mesh:` line (cached under target/tmp, keyed by the .geo and the
//! command). The reference is the same scene solved to a tight tolerance
//! (`REFERENCE`), once per test binary, and checked against the discrete
//! optimality conditions; the frictionless references are also checked
//! against PETSc's SNES VI and against SSN-C.
//!
//! Errors, over the contact candidates (rows of `-contact_output`, ordered
//! by node tag, so two runs on one mesh line up row by row):
//!   err_n = max_i |lambda_n - lambda_n_ref| / max_i lambda_n_ref,
//!   err_t = ||lambda_t - lambda_t_ref|| / ||lambda_t_ref||, with
//!           ||v||^2 = sum_i w_i |v_i|^2 (L2 on Gamma_c, nodal weights w_i).
//!
//! `UBR_ACCURACY_BIN=/path/to/ubr-petsc` runs the scenes with another binary
//! (e.g. an older build, for a before/after comparison).
mod common;
use common::{mpi_command, parse_rows, root, Row};
use serde_json::Value;
use std::collections::hash_map::DefaultHasher;
use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;
use std::time::Instant;

/// Options of the tight reference solve (one rank); the one place to change
/// them. The paper's stopping test far below the errors measured here, with
/// Anderson acceleration so that it ends; `-ubr_stop paper` is ignored by a
/// binary that does not know it. CF-FP's fixed point to 1e-11 (its change
/// of s stalled at 1.4e-12 on incline2d_coulomb at r = 4.7E: the floor of
/// its direction typed to twelve digits, normalised since). Two such
/// references with different memories and tolerances agreed to 2e-8 on
/// every scene, and SNES VI agrees with the frictionless ones to 3e-8.
const REFERENCE: &[&str] = &[
    "-ubr_stop",
    "paper",
    "-ubr_rtol",
    "1e-12",
    "-ubr_fp_rtol",
    "1e-11",
    "-ubr_anderson",
    "10",
    "-ubr_max_it",
    "100000",
    "-ubr_fp_max_it",
    "1000",
];

/// Issue 12: the defaults' stresses within this of the reference.
const DEFAULT_TOL: f64 = 1e-3;
/// A tighter request, and the error it must reach.
const TIGHT: &[&str] = &["-ubr_lambda_rtol", "1e-6"];
const TIGHT_TOL: f64 = 2e-6;
const GAMG: &[&str] = &["-ksp_type", "cg", "-pc_type", "gamg"];

/// The reference's discrete optimality conditions, relative (see `check_reference`).
const OPT_EQUILIBRIUM: f64 = 1e-9;
const OPT_SIGN: f64 = 1e-9;
const OPT_PENETRATION: f64 = 1e-8;
const OPT_COMPLEMENTARITY: f64 = 1e-8;
const OPT_FRICTION: f64 = 1e-8;
/// Agreement of the frictionless references with SNES VI (the constraint
/// held exactly) and SSN-C (a penalty method: ~compliance / ssn_r away).
const SNESVI_TOL: f64 = 2e-7;
const SSN_TOL: f64 = 1e-5;

struct Scene {
    name: &'static str,
    /// Rank counts of the runs at the defaults.
    ranks: &'static [usize],
    /// Rank count of the tight runs, MUMPS and GAMG.
    tight_ranks: usize,
    gamg_ranks: usize,
    /// Frictionless scenes with the contact direction along an axis:
    /// SSN-C's r and, for a body held along n only by the contact, the
    /// initial shift that SSN-C and SNES VI need (the paper's u^0).
    comparators: Option<(&'static str, Option<&'static str>)>,
}

const SCENES: &[Scene] = &[
    Scene {
        name: "punch2d_steel",
        ranks: &[1, 2],
        tight_ranks: 1,
        gamg_ranks: 1,
        comparators: Some(("2.1e21", Some("0,-1e-6"))),
    },
    Scene {
        name: "slab2d_ball_pen",
        ranks: &[1, 2],
        tight_ranks: 1,
        gamg_ranks: 1,
        comparators: Some(("7e13", None)),
    },
    Scene {
        name: "cantilever2d_stop",
        ranks: &[1],
        tight_ranks: 1,
        gamg_ranks: 2,
        // 1e7 E: at 1e9 E the penalized matrix of this slender beam is
        // numerically singular for MUMPS.
        comparators: Some(("1e14", None)),
    },
    Scene {
        name: "quarterblock3d_ball",
        ranks: &[1],
        tight_ranks: 1,
        gamg_ranks: 2,
        comparators: Some(("1e9", Some("0,0,-0.005"))),
    },
    Scene {
        name: "tube2d_tresca",
        ranks: &[1],
        tight_ranks: 2,
        gamg_ranks: 1,
        comparators: None,
    },
    Scene {
        name: "block3d_gen_tresca",
        ranks: &[1, 2],
        tight_ranks: 1,
        gamg_ranks: 1,
        comparators: None,
    },
    Scene {
        name: "incline2d_coulomb",
        ranks: &[1, 2],
        tight_ranks: 1,
        gamg_ranks: 1,
        comparators: None,
    },
    Scene {
        name: "crowned2d_coulomb",
        ranks: &[1],
        tight_ranks: 1,
        gamg_ranks: 1,
        comparators: None,
    },
    Scene {
        name: "hemisphere3d_coulomb",
        ranks: &[1, 3],
        tight_ranks: 1,
        gamg_ranks: 1,
        comparators: None,
    },
    Scene {
        name: "disc3d_halfball_coulomb",
        ranks: &[1, 2],
        tight_ranks: 1,
        gamg_ranks: 1,
        comparators: None,
    },
    Scene {
        name: "stamp2d_gravity_coulomb",
        ranks: &[1, 2],
        tight_ranks: 2,
        gamg_ranks: 1,
        comparators: None,
    },
];

fn scene(name: &str) -> &'static Scene {
    SCENES
        .iter()
        .find(|s| s.name == name)
        .unwrap_or_else(|| panic!("no scene {name}"))
}

fn binary() -> String {
    std::env::var("UBR_ACCURACY_BIN").unwrap_or_else(|_| common::BIN.to_string())
}

/// A finished run: exit status, report, contact rows, output.
struct Solution {
    status: Option<i32>,
    report: Value,
    rows: Vec<Row>,
    stdout: String,
    stderr: String,
    seconds: f64,
}

impl Solution {
    fn num(&self, key: &str) -> Option<f64> {
        self.report.get(key).and_then(Value::as_f64)
    }

    fn converged(&self) -> bool {
        self.status == Some(0) && self.report["converged"] == Value::Bool(true)
    }

    fn friction(&self) -> bool {
        self.report["friction"].as_str().unwrap_or("none") != "none"
    }

    /// The line of stderr that says why the run did not converge ("" if none).
    fn failure_line(&self) -> &str {
        self.stderr
            .lines()
            .find(|l| l.starts_with("not converged"))
            .unwrap_or_default()
    }

    /// What the report says about the solve, for messages.
    fn summary(&self) -> String {
        let key = |k: &str| match self.report.get(k) {
            None | Some(Value::Null) => "n/a".to_string(),
            Some(v) => v.to_string(),
        };
        format!(
            "exit {:?}, converged {}, iterations {}, fixed_point_iterations {}, linear_solves {}, \
             r {} (r_source {}), lambda_error_estimate {}, time_total {} s ({:.1} s wall)",
            self.status,
            key("converged"),
            key("iterations"),
            key("fixed_point_iterations"),
            key("linear_solves"),
            key("r"),
            key("r_source"),
            key("lambda_error_estimate"),
            key("time_total"),
            self.seconds
        )
    }
}

fn scratch_root() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("accuracy")
}

/// The scene's Gmsh command (its `# Mesh:` line), None for a generated mesh.
fn mesh_command(name: &str) -> Option<Vec<String>> {
    let opts = std::fs::read_to_string(root().join("tests/scenes").join(format!("{name}.opts")))
        .unwrap_or_else(|e| panic!("tests/scenes/{name}.opts: {e}"));
    opts.lines()
        .find_map(|l| l.strip_prefix("# Mesh:"))
        .map(|c| c.split_whitespace().map(str::to_string).collect())
}

/// The scene's mesh (`-mesh PATH`), generated once per test binary and
/// cached under target/tmp by a hash of the .geo file and the command.
fn mesh_args(name: &'static str) -> &'static [String] {
    static MESHES: OnceLock<HashMap<&'static str, OnceLock<Vec<String>>>> = OnceLock::new();
    let cells = MESHES.get_or_init(|| SCENES.iter().map(|s| (s.name, OnceLock::new())).collect());
    cells[name].get_or_init(|| {
        let Some(mut cmd) = mesh_command(name) else {
            return Vec::new();
        };
        let geo = std::fs::read_to_string(root().join("tests/scenes").join(format!("{name}.geo")))
            .unwrap_or_else(|e| panic!("tests/scenes/{name}.geo: {e}"));
        let mut h = DefaultHasher::new();
        (&geo, &cmd).hash(&mut h);
        let dir = scratch_root().join("meshes");
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join(format!("{name}-{:016x}.msh", h.finish()));
        if !out.exists() {
            let tmp = dir.join(format!("{name}-{}.tmp.msh", std::process::id()));
            assert_eq!(
                cmd[0], "gmsh",
                "{name}: the # Mesh: line must be a gmsh command"
            );
            let o = cmd.iter().position(|a| a == "-o").expect("gmsh -o OUT") + 1;
            cmd[o] = tmp.to_str().unwrap().to_string();
            let run = Command::new(&cmd[0])
                .args(&cmd[1..])
                .current_dir(root())
                .output()
                .expect("gmsh runs (apt-get install gmsh)");
            assert!(
                run.status.success() && tmp.exists(),
                "{name}: {} failed:\n{}{}",
                cmd.join(" "),
                String::from_utf8_lossy(&run.stdout),
                String::from_utf8_lossy(&run.stderr)
            );
            std::fs::rename(&tmp, &out).unwrap();
        }
        vec!["-mesh".to_string(), out.to_str().unwrap().to_string()]
    })
}

/// Runs the scene with extra options on `ranks` ranks; exit 0 and 3 (not
/// converged, report written) are returned, anything else fails here.
fn run(name: &'static str, ranks: usize, extra: &[&str]) -> Solution {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = scratch_root().join(format!(
        "run-{}-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::SeqCst),
        name
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let (rep, csv) = (dir.join("report.json"), dir.join("contact.csv"));
    let opts = format!("tests/scenes/{name}.opts");
    let mut args: Vec<&str> = vec!["-options_file", &opts];
    args.extend(mesh_args(name).iter().map(String::as_str));
    args.extend_from_slice(extra);
    args.extend_from_slice(&["-report", rep.to_str().unwrap()]);
    args.extend_from_slice(&["-contact_output", csv.to_str().unwrap()]);
    let t = Instant::now();
    let (mut cmd, _session) = mpi_command("mpirun");
    let out = cmd
        .args(["-n", &ranks.to_string(), &binary()])
        .args(&args)
        .output()
        .expect("mpirun runs");
    let seconds = t.elapsed().as_secs_f64();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let status = out.status.code();
    let (rep_text, csv_text) = (std::fs::read_to_string(&rep), std::fs::read_to_string(&csv));
    let _ = std::fs::remove_dir_all(&dir);
    let (Some(0) | Some(3), Ok(rep_text), Ok(csv_text)) = (status, rep_text, csv_text) else {
        panic!(
            "{name} -n {ranks} {}: exit {status:?}\nstdout:\n{stdout}\nstderr:\n{stderr}",
            extra.join(" ")
        );
    };
    let report: Value = serde_json::from_str(&rep_text).unwrap();
    let rows = parse_rows(&csv_text);
    Solution {
        status,
        report,
        rows,
        stdout,
        stderr,
        seconds,
    }
}

/// The scene's tight reference (one rank), computed once per test binary
/// and checked against the optimality conditions.
fn reference(name: &'static str) -> &'static Solution {
    static REFS: OnceLock<HashMap<&'static str, OnceLock<Solution>>> = OnceLock::new();
    let cells = REFS.get_or_init(|| SCENES.iter().map(|s| (s.name, OnceLock::new())).collect());
    cells[name].get_or_init(|| {
        let r = run(name, 1, REFERENCE);
        if let Err(e) = check_reference(&r) {
            panic!(
                "{name}: the reference ({}) fails the optimality conditions: {e}\n{}\n{}",
                REFERENCE.join(" "),
                r.summary(),
                r.stdout
            );
        }
        r
    })
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// The discrete optimality conditions of a solution, relative to its scales
/// (lambda_max: largest pressure; L: largest displacement component on
/// Gamma_c): equilibrium (report), lambda_n >= 0, u_n <= g,
/// lambda_n (g - u_n) = 0 pointwise, and with friction |lambda_t| <= s,
/// u_t = 0 where sticking, u_t along lambda_t where slipping (report), and
/// for Coulomb |lambda_t| <= nu_f lambda_n (= where slipping) from the CSV.
fn check_reference(r: &Solution) -> Result<String, String> {
    if !r.converged() {
        return Err("not converged".into());
    }
    let lmax = r.rows.iter().map(|x| x.lambda_n).fold(0.0, f64::max);
    let scale_u = r
        .rows
        .iter()
        .map(|x| x.un.abs().max(norm(&x.ut)))
        .fold(0.0, f64::max);
    if !(lmax > 0.0 && scale_u > 0.0) {
        return Err(format!(
            "nothing touches (max lambda_n {lmax}, max |u| {scale_u})"
        ));
    }
    let eq = r
        .num("equilibrium_residual_rel")
        .ok_or("no equilibrium_residual_rel")?;
    let sign = -r
        .rows
        .iter()
        .map(|x| x.lambda_n)
        .fold(f64::INFINITY, f64::min)
        / lmax;
    let pen = r
        .rows
        .iter()
        .map(|x| x.un - x.gap)
        .fold(f64::NEG_INFINITY, f64::max)
        / scale_u;
    let compl = r
        .rows
        .iter()
        .map(|x| (x.lambda_n * (x.gap - x.un)).abs())
        .fold(0.0, f64::max)
        / (lmax * scale_u);
    let mut errs = Vec::new();
    let mut say = |ok: bool, what: String| {
        if !ok {
            errs.push(what)
        }
    };
    say(eq <= OPT_EQUILIBRIUM, format!("equilibrium {eq:.2e}"));
    say(
        sign <= OPT_SIGN,
        format!("min lambda_n / max = {:.2e}", -sign),
    );
    say(
        pen <= OPT_PENETRATION,
        format!("max (u_n - g) / max |u| = {pen:.2e}"),
    );
    say(
        compl <= OPT_COMPLEMENTARITY,
        format!("max |lambda_n (g - u_n)| = {compl:.2e} (relative)"),
    );
    let mut text = format!(
        "equilibrium {eq:.1e}, min lambda_n / max {:.1e}, penetration {pen:.1e}, complementarity {compl:.1e}",
        -sign
    );
    if r.friction() {
        let excess = r
            .num("max_friction_excess")
            .ok_or("no max_friction_excess")?
            / r.num("max_bound").ok_or("no max_bound")?;
        let stick = r.num("max_stick_slip").ok_or("no max_stick_slip")?
            / r.num("max_slip")
                .ok_or("no max_slip")?
                .max(f64::MIN_POSITIVE);
        let align = r.num("min_slip_alignment").ok_or("no min_slip_alignment")?;
        say(
            excess <= OPT_FRICTION,
            format!("max (|lambda_t| - s) / max s = {excess:.2e}"),
        );
        say(
            stick <= OPT_FRICTION,
            format!("slip at stick nodes / max slip = {stick:.2e}"),
        );
        say(
            align >= 1.0 - OPT_FRICTION,
            format!("min cos(u_t, lambda_t) = {align:.12}"),
        );
        text += &format!(
            ", friction excess {excess:.1e}, stick slip {stick:.1e}, alignment {align:.12}"
        );
        let st = |s: &str| r.rows.iter().filter(|x| x.status == s).count();
        say(
            st("stick") > 0 && st("slip") > 0,
            format!(
                "{} stick, {} slip nodes: want both",
                st("stick"),
                st("slip")
            ),
        );
        if r.report["friction"] == "coulomb" {
            let nu = r
                .num("friction_coefficient")
                .ok_or("no friction_coefficient")?;
            let worst = r
                .rows
                .iter()
                .map(|x| {
                    let d = norm(&x.lambda_t) - nu * x.lambda_n;
                    if x.status == "slip" {
                        d.abs()
                    } else {
                        d
                    }
                })
                .fold(0.0, f64::max)
                / lmax;
            say(
                worst <= OPT_FRICTION,
                format!("Coulomb law off by {worst:.2e} (relative)"),
            );
            text += &format!(", Coulomb law {worst:.1e}");
        }
    }
    let contact = r.rows.iter().filter(|x| x.status != "open").count();
    say(contact >= 5, format!("only {contact} nodes in contact"));
    if errs.is_empty() {
        Ok(text)
    } else {
        Err(errs.join("; "))
    }
}

/// (err_n, err_t) of a solution against a reference on the same mesh.
fn errors(a: &[Row], reference: &[Row]) -> (f64, f64) {
    assert_eq!(
        a.len(),
        reference.len(),
        "contact CSVs of different lengths"
    );
    let lmax = reference.iter().map(|x| x.lambda_n).fold(0.0, f64::max);
    let (mut en, mut num, mut den) = (0.0f64, 0.0, 0.0);
    for (x, y) in a.iter().zip(reference) {
        assert_eq!(x.node, y.node, "contact CSV rows do not line up");
        en = en.max((x.lambda_n - y.lambda_n).abs());
        for c in 0..3 {
            num += y.weight * (x.lambda_t[c] - y.lambda_t[c]).powi(2);
            den += y.weight * y.lambda_t[c].powi(2);
        }
    }
    let et = if den > 0.0 { (num / den).sqrt() } else { 0.0 };
    (en / lmax, et)
}

/// Runs the scene with `extra` on each rank count and requires err_n, and
/// err_t with friction, within `tol` of the reference. All runs are made
/// before the verdict, so that the message lists every failure.
fn require_accuracy(name: &'static str, ranks: &[usize], extra: &[&str], tol: f64) {
    let reference = reference(name);
    let mut failures = Vec::new();
    for &n in ranks {
        let s = run(name, n, extra);
        let (en, et) = errors(&s.rows, &reference.rows);
        let friction = reference.friction();
        let line = format!(
            "{name} -n {n} [{}]: err_n {en:.3e}{} (limit {tol:.0e}); {}",
            if extra.is_empty() {
                "defaults".to_string()
            } else {
                extra.join(" ")
            },
            if friction {
                format!(", err_t {et:.3e}")
            } else {
                String::new()
            },
            s.summary()
        );
        println!("{line}");
        if !s.converged()
            || en > tol
            || (friction && et > tol)
            || !en.is_finite()
            || !et.is_finite()
        {
            failures.push(format!(
                "{line}\n--- stdout:\n{}--- stderr:\n{}",
                s.stdout, s.stderr
            ));
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

fn defaults(name: &'static str) {
    require_accuracy(name, scene(name).ranks, &[], DEFAULT_TOL);
}

fn tight_mumps(name: &'static str) {
    require_accuracy(name, &[scene(name).tight_ranks], TIGHT, TIGHT_TOL);
}

fn tight_gamg(name: &'static str) {
    let extra: Vec<&str> = TIGHT.iter().chain(GAMG).copied().collect();
    require_accuracy(name, &[scene(name).gamg_ranks], &extra, TIGHT_TOL);
}

/// Three tests per scene: `NAME::defaults`, `NAME::tight_mumps`, `NAME::tight_gamg`.
macro_rules! scene_tests {
    ($($scene:ident),* $(,)?) => {$(
        mod $scene {
            #[test]
            fn defaults() {
                super::defaults(stringify!($scene));
            }
            #[test]
            fn tight_mumps() {
                super::tight_mumps(stringify!($scene));
            }
            #[test]
            fn tight_gamg() {
                super::tight_gamg(stringify!($scene));
            }
        }
    )*};
}

scene_tests!(
    punch2d_steel,
    slab2d_ball_pen,
    cantilever2d_stop,
    quarterblock3d_ball,
    tube2d_tresca,
    block3d_gen_tresca,
    incline2d_coulomb,
    crowned2d_coulomb,
    hemisphere3d_coulomb,
    disc3d_halfball_coulomb,
    stamp2d_gravity_coulomb,
);

/// Every scene has tests, and every tests/scenes/*.opts is a scene here.
#[test]
fn every_scene_file_is_tested() {
    let mut files: Vec<String> = std::fs::read_dir(root().join("tests/scenes"))
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "opts").then(|| p.file_stem().unwrap().to_str().unwrap().to_string())
        })
        .collect();
    files.sort();
    let mut names: Vec<String> = SCENES.iter().map(|s| s.name.to_string()).collect();
    names.sort();
    assert_eq!(files, names);
    for s in SCENES {
        if let Some(cmd) = mesh_command(s.name) {
            assert!(
                cmd.last()
                    .map(|g| Path::new(g).exists() || root().join(g).exists())
                    == Some(true),
                "{}: the .geo of its # Mesh: line is missing",
                s.name
            );
        }
    }
}

/// The references are converged discrete solutions: the optimality
/// conditions hold to round-off (checked when each is made; listed here).
#[test]
fn references_satisfy_the_optimality_conditions() {
    for s in SCENES {
        let r = reference(s.name);
        let text = check_reference(r).unwrap();
        println!(
            "{}: {} nodes, {} candidates, {} in contact; {text}; {}",
            s.name,
            r.report["nodes"],
            r.rows.len(),
            r.rows.iter().filter(|x| x.status != "open").count(),
            r.summary()
        );
    }
}

/// The frictionless references against two independent algorithms: SNES VI
/// (reduced-space active set on the bound u.n <= g) and SSN-C (semi-smooth
/// Newton on the penalized problem, r large).
#[test]
fn frictionless_references_agree_with_snesvi_and_ssn() {
    let mut failures = Vec::new();
    for s in SCENES {
        let Some((ssn_r, shift)) = s.comparators else {
            continue;
        };
        let reference = reference(s.name);
        let mut shift_args = Vec::new();
        if let Some(sh) = shift {
            shift_args = vec!["-ssn_initial_shift", sh];
        }
        let mut vi_args = vec!["-contact_algorithm", "snesvi"];
        vi_args.extend_from_slice(&shift_args);
        let mut ssn_args = vec!["-contact_algorithm", "ssn", "-ssn_r", ssn_r];
        ssn_args.extend_from_slice(&shift_args);
        for (what, args, tol) in [
            ("SNES VI", vi_args, SNESVI_TOL),
            ("SSN-C", ssn_args, SSN_TOL),
        ] {
            let r = run(s.name, 1, &args);
            let (en, _) = errors(&r.rows, &reference.rows);
            let line = format!(
                "{}: {what} vs reference: {en:.2e} (limit {tol:.0e}); {}",
                s.name,
                r.summary()
            );
            println!("{line}");
            if !r.converged() || en > tol || en.is_nan() {
                failures.push(line);
            }
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

/// Inexact inner solves (CG + GAMG at the defaults, each solve to 0.1 of its
/// initial residual) must not stall Anderson: on the two scenes where they
/// did (tube2d_tresca: 1759 UBR-TF iterations against 87 with MUMPS, 81
/// rejected Anderson steps), the iteration count stays within twice the
/// direct solver's (plus 20), and the answer within the default tolerance.
#[test]
fn inexact_solves_do_not_stall_anderson() {
    for name in ["tube2d_tresca", "cantilever2d_stop"] {
        let direct = run(name, 1, &[]);
        let iterative = run(name, 1, GAMG);
        let its = |s: &Solution| s.num("iterations").unwrap();
        assert!(
            iterative.converged() && its(&iterative) <= 2.0 * its(&direct) + 20.0,
            "{name}: CG+GAMG {}; MUMPS {}",
            iterative.summary(),
            direct.summary()
        );
        let (en, et) = errors(&iterative.rows, &reference(name).rows);
        assert!(
            en <= DEFAULT_TOL && et <= DEFAULT_TOL,
            "{name}: err_n {en:.2e}, err_t {et:.2e}"
        );
    }
}

/// The paper's plain iteration where it is slow: stamp2d_gravity_coulomb
/// (friction alone holds the body sideways) contracts by about 0.9995 per
/// iteration in CF-FP's second Tresca solve. It was called stalled after
/// 500 iterations ("the residual stays flat"; its best was the warm start's
/// first evaluation, before the new bound acted) and told to try
/// -ubr_anderson 0, which it ran. Now it runs to -ubr_max_it, says so, and
/// names the Anderson acceleration; the default converges. (At the
/// spectral estimate of r: a third of it, the default where friction alone
/// holds a rigid motion, lets the plain iteration converge in 12969.)
#[test]
fn a_slow_plain_iteration_is_not_called_stalled() {
    let name = "stamp2d_gravity_coulomb";
    let default = run(name, 1, &[]);
    assert!(default.converged(), "{}", default.summary());
    let estimate = format!("{}", default.num("r_estimate").unwrap());
    let plain = run(name, 1, &["-ubr_anderson", "0", "-ubr_r", &estimate]);
    assert_eq!(plain.status, Some(3), "{}", plain.summary());
    let why = plain.failure_line();
    assert!(
        why.contains("(-ubr_max_it)")
            && why.contains("the default Anderson acceleration (-ubr_anderson 10)")
            && !why.contains("stalled")
            && !why.contains("try -ubr_anderson 0"),
        "{why}"
    );
    // At -ubr_r 1e6 (31x the trial r) a Tresca solve's residual floor is
    // 2e-12, above what counts as round-off (1e-12): it stalled there, its
    // estimate 6.9e-11 within the outer target 2.5e-10 but not the inner
    // one, and CF-FP ended with exit 3. Such a solve is now kept as one at
    // round-off is; the answer is within the target of the reference.
    let reference = reference(name);
    for n in [1, 2] {
        let s = run(name, n, &["-ubr_r", "1e6", "-ubr_lambda_rtol", "1e-9"]);
        assert!(s.converged(), "-n {n}: {}", s.summary());
        let (en, et) = errors(&s.rows, &reference.rows);
        assert!(
            en <= 1e-9 && et <= 1e-9,
            "-n {n}: err_n {en:.2e}, err_t {et:.2e}"
        );
    }
}

/// A load history of a body that friction alone holds sideways: each step
/// starts CF-FP sticking, as the first does. From the previous step's
/// bound, which need not hold the larger load (a Tresca problem without
/// solution), step 2 of stamp2d_gravity_coulomb on CG + GAMG slid away
/// (exit 3 on 1 rank, converged on 3). The quasi-static law makes the
/// answer depend on the path (one step: 9 stick and 7 slip nodes; three
/// steps: 12 and 4; two: 14 and 2), so the runs are compared with the
/// same history solved tightly on one rank, within the default target.
#[test]
fn friction_held_history_steps_start_sticking() {
    let name = "stamp2d_gravity_coulomb";
    let tight = run(name, 1, &["-load_steps", "3", "-ubr_lambda_rtol", "1e-9"]);
    assert!(tight.converged(), "{}", tight.summary());
    let gamg = ["-load_steps", "3", "-ksp_type", "cg", "-pc_type", "gamg"];
    for (n, extra) in [(1, &gamg[..]), (2, &gamg[..]), (2, &gamg[..2])] {
        let s = run(name, n, extra);
        assert!(s.converged(), "-n {n} {extra:?}: {}", s.summary());
        let (en, et) = errors(&s.rows, &tight.rows);
        assert!(
            en <= 1e-3 && et <= 1e-3,
            "-n {n} {extra:?}: err_n {en:.2e}, err_t {et:.2e}"
        );
    }
}

/// A -ubr_r far from the trial r0 is named before a body "not held": a
/// load step of tube2d_tresca at -ubr_r 1e6 (3.7e3 times r0) stalled with
/// a tensile contact stress of 11%, and was told to check its Dirichlet
/// conditions, the iteration's own message (naming r) dropped.
#[test]
fn a_far_r_is_named_in_a_history() {
    let extra = [
        "-load_steps",
        "2",
        "-ubr_r",
        "1e6",
        "-ubr_lambda_rtol",
        "1e-6",
    ];
    let s = run("tube2d_tresca", 1, &extra);
    assert_eq!(s.status, Some(3), "{}", s.summary());
    let why = s.failure_line();
    assert!(
        why.contains("load step 1/2")
            && why.contains("times the trial r0")
            && !why.contains("not held"),
        "{why}"
    );
}

/// A tight request on a tilted normal: incline2d_coulomb's direction is
/// typed to twelve digits (norm 1 - 2.5e-13). Used as given, it left a
/// normal part of 1e-12 in every tangential displacement, a floor under the
/// residual: at -ubr_lambda_rtol 1e-10 the Tresca solve stalled at 1.5e-12
/// and the run failed (exit 3), and Anderson's steps along the normal part
/// of the tangential multiplier (which the map leaves as it is) moved
/// lambda_n and lambda_t by 1e-5 with the traction unchanged. Now it
/// converges on 1 and 2 ranks, its normals are unit and its tangential
/// stresses tangential to round-off, and it agrees with the reference.
#[test]
fn tilted_normal_reaches_a_tight_tolerance() {
    let name = "incline2d_coulomb";
    let reference = reference(name);
    for n in [1, 2] {
        let s = tight_run(name, n, &reference.rows);
        let lmax = s.rows.iter().map(|r| r.lambda_n.abs()).fold(0.0, f64::max);
        for r in &s.rows {
            let unit = (common::norm(&r.normal) - 1.0).abs();
            let along: f64 = r.lambda_t.iter().zip(&r.normal).map(|(t, n)| t * n).sum();
            assert!(
                unit <= 1e-15 && along.abs() <= 1e-12 * lmax,
                "{name} -n {n}, node {}: |n| - 1 = {unit:.1e}, lambda_t . n = {along:.3e} (max lambda_n {lmax:.3e})",
                r.node
            );
        }
    }
}

/// `name` on `n` ranks at -ubr_lambda_rtol 1e-10: converged, and within
/// 1e-8 of the reference rows `reference`.
fn tight_run(name: &'static str, n: usize, reference: &[Row]) -> Solution {
    let s = run(name, n, &["-ubr_lambda_rtol", "1e-10"]);
    assert!(
        s.converged(),
        "{name} -n {n}: {}\n{}\n{}",
        s.summary(),
        s.stdout,
        s.stderr
    );
    let (en, et) = errors(&s.rows, reference);
    assert!(
        en <= 1e-8 && et <= 1e-8,
        "{name} -n {n}: err_n {en:.2e}, err_t {et:.2e}; {}",
        s.summary()
    );
    s
}

/// CF-FP's Tresca solves aim ten times tighter than the outer target: at
/// -ubr_lambda_rtol 1e-10 stamp2d_gravity_coulomb's reach round-off (their
/// residual flat at 6e-14 to 1.5e-13, estimates 6e-12 to 2e-11 against
/// 2.5e-12). A solve stopped there is kept and the later ones aim at that
/// floor (never looser than the outer target): converged on 1, 2 and 3
/// ranks, as before the round-off stop (which alone failed 2 and 3 ranks),
/// where such a solve wandered until its estimate dipped (1743 iterations
/// on 2 ranks against 870 now).
///
/// Where that floor sits against the target depends on the round-off
/// itself, and on several ranks MUMPS sums in the order messages arrive:
/// the same 3-rank run gave 872 to 948 Tresca iterations over 24 runs on a
/// loaded machine, and once in CI (2026-11-28) two solves in a row stopped
/// at round-off above their target. That run may end with the documented
/// round-off message (exit 3, "ask for a looser -ubr_lambda_rtol"), but its
/// answer must still be within 1e-8 of the reference and it must not
/// wander (under 1500 Tresca iterations).
#[test]
fn tresca_solves_at_round_off_keep_cf_fp_going() {
    let name = "stamp2d_gravity_coulomb";
    let reference = reference(name);
    for n in [1, 2, 3] {
        let s = run(name, n, &["-ubr_lambda_rtol", "1e-10"]);
        if !s.converged() {
            let failure = s.report["failure"].as_str().unwrap_or_default();
            assert!(
                s.status == Some(3)
                    && failure.contains("reached round-off")
                    && failure.contains("ask for a looser -ubr_lambda_rtol"),
                "{name} -n {n}: {}\n{failure}\n{}",
                s.summary(),
                s.stderr
            );
        }
        let its = s.num("iterations").unwrap_or(f64::INFINITY);
        assert!(its < 1500.0, "{name} -n {n}: {}", s.summary());
        let (en, et) = errors(&s.rows, &reference.rows);
        assert!(
            en <= 1e-8 && et <= 1e-8,
            "{name} -n {n}: err_n {en:.2e}, err_t {et:.2e}; {}",
            s.summary()
        );
    }
}
