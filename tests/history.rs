//! Load histories (`-load_steps`, `-load_history`): one factorization for
//! every step, frictionless steps equal to single solves at their load
//! (the frictionless problem has no memory), Hertz's laws along the
//! steps, quasi-static Coulomb friction (Cattaneo-Mindlin's stick zone and
//! the hysteresis of a tangential load cycle), rank-count independence and
//! bad input.

mod common;
use common::*;
use std::collections::HashMap;
use std::path::Path;

/// The history table: one map column -> value per step.
fn history_rows(path: &Path) -> Vec<HashMap<String, String>> {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("history table {}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            assert_eq!(v.len(), header.len(), "{l}");
            header
                .iter()
                .cloned()
                .zip(v.iter().map(|s| s.to_string()))
                .collect()
        })
        .collect()
}

fn num(row: &HashMap<String, String>, key: &str) -> f64 {
    row.get(key)
        .unwrap_or_else(|| panic!("no column {key} in {row:?}"))
        .parse()
        .unwrap()
}

/// Runs a history on `ranks`, its table into the scratch dir `dir`;
/// returns the run (exit 0 asserted) and the table's rows.
fn history(
    dir: &Path,
    name: &str,
    ranks: usize,
    args: &[&str],
) -> (Run, Vec<HashMap<String, String>>, Vec<Row>) {
    let table = dir.join(format!("{name}.csv"));
    let contact = dir.join(format!("{name}-contact.csv"));
    let mut a: Vec<&str> = args.to_vec();
    let (t, c) = (table.to_str().unwrap(), contact.to_str().unwrap());
    a.extend(["-history_output", t, "-contact_output", c]);
    let run = mpirun(ranks, &a);
    assert_eq!(run.status, Some(0), "{}", run.context());
    (run, history_rows(&table), contact_rows(&contact))
}

/// 2D Hertz in 4 proportional steps at a tight tolerance: step k equals a
/// single solve at load k/4 (contact force, peak pressure, and the final
/// step's stresses node by node to 1e-7), the peak pressure follows
/// Hertz's p0 ~ F^(1/2) and the half-width b ~ F^(1/2) within the
/// single-load accuracy of this mesh (p0 3%, b one node spacing), and the
/// table is the same on 1, 2 and 3 ranks to 1e-8.
#[test]
fn hertz_2d_steps_are_single_solves_and_follow_hertz() {
    let dir = scratch("history-hertz");
    let tight = [
        "-options_file",
        "options/hertz",
        "-ubr_lambda_rtol",
        "1e-10",
    ];
    let mut args = tight.to_vec();
    args.extend(["-load_steps", "4"]);
    let (_, steps, last) = history(&dir, "h2", 2, &args);
    assert_eq!(steps.len(), 4);
    // Hertz (plane strain, the whole cylinder F = 1600 k/4, R = 8).
    let e_star = 2000.0 / (1.0 - 0.09);
    let spacing = 0.2; // the candidates' spacing near the contact centre
    for (k, row) in steps.iter().enumerate() {
        let f = 1600.0 * (k + 1) as f64 / 4.0;
        let p0 = (f * e_star / (std::f64::consts::PI * 8.0)).sqrt();
        let b = (4.0 * f * 8.0 / (std::f64::consts::PI * e_star)).sqrt();
        let peak = num(row, "peak_pressure");
        let extent = num(row, "contact_extent");
        assert!(
            (peak / p0 - 1.0).abs() < 0.05,
            "step {}: peak {peak} vs Hertz {p0}",
            k + 1
        );
        assert!(
            (extent - b).abs() < spacing,
            "step {}: half-width {extent} vs Hertz {b}",
            k + 1
        );
        assert!((num(row, "contact_force_y") - f / 2.0).abs() < 1e-9 * f);
        assert_eq!(row["converged"], "true");
    }
    // Step 2 against a single solve at half the load.
    let dir2 = dir.join("single");
    std::fs::create_dir_all(&dir2).unwrap();
    let mut single = tight.to_vec();
    single.extend(["-traction_top", "0,-50", "-load_steps", "1"]);
    let (_, one, _) = history(&dir2, "half", 2, &single);
    let (a, b) = (
        num(&steps[1], "peak_pressure"),
        num(&one[0], "peak_pressure"),
    );
    assert!(
        (a - b).abs() < 1e-7 * b,
        "step 2 peak {a} against a single solve {b}"
    );
    // The last step against a single solve at the full load, node by node.
    let out = run_outputs("history-full", 2, &tight, None);
    assert_eq!(out.status, Some(0), "{}", out.context());
    let gap = max_pressure_gap(&last, &out.rows());
    assert!(gap < 1e-7, "last step against a single solve: {gap:e}");
    // Ranks.
    for ranks in [1, 3] {
        let (_, other, _) = history(&dir, &format!("h2-{ranks}"), ranks, &args);
        for (x, y) in steps.iter().zip(&other) {
            let (p, q) = (num(x, "peak_pressure"), num(y, "peak_pressure"));
            assert!((p - q).abs() < 1e-8 * p, "{ranks} ranks: {p} vs {q}");
        }
    }
    // A step that does not converge ends the history (exit 3), named.
    let run = mpirun(
        2,
        &[
            "-options_file",
            "options/hertz",
            "-load_steps",
            "5",
            "-ubr_max_it",
            "18",
        ],
    );
    assert_eq!(run.status, Some(3), "{}", run.context());
    let needle =
        "not converged: load step 1/5 (-load_steps 5 0.2000): UBR-C stopped after 18 iterations";
    assert!(run.stderr.contains(needle), "{}", run.context());
    // So does a step whose solve cannot go on (here a non-finite iterate
    // at an absurd factor, written as one number).
    let table = dir.join("huge.csv");
    std::fs::write(&table, "step,factor\n1,1e300\n").unwrap();
    let run = mpirun(
        2,
        &[
            "-options_file",
            "options/hertz",
            "-load_history",
            table.to_str().unwrap(),
        ],
    );
    assert_eq!(run.status, Some(3), "{}", run.context());
    let needle = "huge.csv 1.0000e300): UBR-C produced a non-finite iterate";
    assert!(
        run.stderr
            .contains("not converged: load step 1/1 (-load_history"),
        "{}",
        run.context()
    );
    assert!(run.stderr.contains(needle), "{}", run.context());
    let _ = std::fs::remove_dir_all(&dir);
}

/// 3D Hertz in 4 steps: a quarter plate (E 1, nu 0.3) pressed onto a
/// rigid ball of radius 1 (closest-point normals) by a traction growing to
/// T = 0.00125 on its top (the whole sphere's load F = 4T): at every step
/// the contact radius follows a = (3FR/(4E*))^(1/3) to one element (0.02)
/// and the peak pressure p0 = 3F/(2 pi a^2) to 8%, the single-load
/// accuracy of this mesh (measured: a 0.0918, 0.1186, 0.1353, 0.1495
/// against 0.0948, 0.1195, 0.1368, 0.1506; p0 +2.4% to +2.8%).
#[test]
fn hertz_3d_steps_follow_the_cube_root_law() {
    let dir = scratch("history-ball3d");
    let msh = dir.join("ballplate3d.msh");
    gmsh("-3", "tests/normals/ballplate3d.geo", &msh, &[]);
    let msh = msh.to_str().unwrap().to_string();
    let args = [
        "-mesh",
        &msh,
        "-E",
        "1",
        "-nu",
        "0.3",
        "-dirichlet_symx",
        "ux=0",
        "-dirichlet_symy",
        "uy=0",
        "-traction_top",
        "0,0,-0.00125",
        "-contact_surface",
        "bottom",
        "-obstacle",
        "ball",
        "-obstacle_center",
        "0,0,-1",
        "-obstacle_radius",
        "1",
        "-load_steps",
        "4",
        "-ubr_lambda_rtol",
        "1e-6",
    ];
    let (_, steps, _) = history(&dir, "ball", 2, &args);
    let e_star = 1.0 / (1.0 - 0.09);
    for (k, row) in steps.iter().enumerate() {
        let f = 4.0 * 0.00125 * (k + 1) as f64 / 4.0;
        let a = (3.0 * f / (4.0 * e_star)).cbrt();
        let p0 = 3.0 * f / (2.0 * std::f64::consts::PI * a * a);
        let (extent, peak) = (num(row, "contact_extent"), num(row, "peak_pressure"));
        eprintln!(
            "step {}: a {extent:.4} (Hertz {a:.4}), p0 {peak:.4e} (Hertz {p0:.4e})",
            k + 1
        );
        assert!(
            (extent - a).abs() < 0.02,
            "step {}: a {extent} against {a}",
            k + 1
        );
        assert!(
            (peak / p0 - 1.0).abs() < 0.08,
            "step {}: p0 {peak} against {p0}",
            k + 1
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The paper's 3D block, its top pushed down 0.2 in 5 steps: exactly one
/// numeric factorization in `-log_view`, each step's contact force equal
/// to a single solve at that displacement.
#[test]
fn block3d_steps_share_one_factorization() {
    let dir = scratch("history-block3d");
    let base = [
        "-options_file",
        "options/block3d",
        "-ubr_lambda_rtol",
        "1e-9",
    ];
    let mut args = base.to_vec();
    args.extend(["-load_steps", "5", "-log_view"]);
    let (run, steps, _) = history(&dir, "b3", 2, &args);
    let line = run
        .stdout
        .lines()
        .find(|l| l.starts_with("MUMPSFactorNum"))
        .unwrap_or_else(|| panic!("no MUMPSFactorNum in -log_view\n{}", run.stdout));
    let count: usize = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    assert_eq!(count, 1, "{line}");
    let mut single = base.to_vec();
    single.extend(["-dirichlet_top", "ux=0,uy=0,uz=-0.08", "-load_steps", "1"]);
    let (_, one, _) = history(&dir, "b3-single", 2, &single);
    let (a, b) = (
        num(&steps[1], "contact_force_z"),
        num(&one[0], "contact_force_z"),
    );
    assert!(
        (a - b).abs() < 1e-6 * b.abs(),
        "step 2 force {a} against a single solve {b}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Cattaneo-Mindlin with quasi-static Coulomb friction: the crowned block
/// (R = 30, nu_f = 0.4) pressed onto a rigid plane by its top edge (uy),
/// then loaded tangentially by a traction Q on that edge in steps up to
/// Q = 0.5 nu_f P: the stick zone's half-width c against the contact's a
/// follows c/a = sqrt(1 - Q / (nu_f P)) = 0.707 within two node spacings
/// of a (nu = 0.45: the normal-tangential coupling of a rigid flat,
/// Dundurs' beta = 0.09, stays small). Then a cycle Q -> -Q -> Q: the
/// tangential force-displacement loop encloses a positive area (friction
/// dissipates) of the order of Q times the loop's width (measured: c/a
/// 0.7038 against 0.7072; loop 1.1e-3, 2% of Q x width).
#[test]
fn cattaneo_mindlin_stick_zone_and_hysteresis() {
    let (dir, msh) = gmsh_2d("history-cm", "tests/scenes/crowned2d_coulomb.geo");
    let scene = [
        "-mesh",
        &msh,
        "-E",
        "1000",
        "-nu",
        "0.45",
        "-contact_surface",
        "crown",
        "-contact_direction",
        "0,-1",
        "-obstacle",
        "plane",
        "-obstacle_point",
        "0,0",
        "-friction",
        "coulomb",
        "-friction_coefficient",
        "0.4",
        "-dirichlet_top",
        "uy=-0.02",
        "-ubr_lambda_rtol",
        "1e-6",
    ];
    // P: the reaction of the normal load alone.
    let mut normal = scene.to_vec();
    normal.extend(["-load_steps", "1"]);
    let (_, one, _) = history(&dir, "normal", 2, &normal);
    let p = num(&one[0], "reaction_top_y").abs();
    let q = 0.5 * 0.4 * p / 6.0; // the traction on the 6-wide top edge
    let table = dir.join("steps.csv");
    let mut text = String::from("step,dirichlet_top,traction_top\n");
    let path = [0.25, 0.5, 0.75, 1.0];
    let tangential = [0.25, 0.5, 0.75, 1.0];
    let mut k = 0;
    for f in path {
        k += 1;
        text.push_str(&format!("{k},{f},0\n"));
    }
    for t in tangential {
        k += 1;
        text.push_str(&format!("{k},1,{t}\n"));
    }
    std::fs::write(&table, &text).unwrap();
    let traction = format!("{q},0");
    let mut args = scene.to_vec();
    args.extend([
        "-traction_top",
        &traction,
        "-history_curve",
        "traction_top,ux",
    ]);
    args.extend(["-load_history", table.to_str().unwrap()]);
    let (_, steps, rows) = history(&dir, "cm", 2, &args);
    // Without a per-step output the steps skip their whole displacement
    // and take y0 as a combination of the parts' responses: the same
    // answer.
    let lean = run_outputs("history-cm-lean", 2, &args, None);
    assert_eq!(lean.status, Some(0), "{}", lean.context());
    let gap = max_stress_gap(&lean.rows(), &rows);
    assert!(
        gap < 1e-8,
        "steps without outputs: stresses {gap:e} from the steps with"
    );
    let last = steps.last().unwrap();
    assert_eq!(last["converged"], "true");
    let p_last = num(last, "reaction_top_y").abs();
    let q_total = num(last, "curve_force_traction_top_ux").abs();
    let ratio = q_total / (0.4 * p_last);
    let xs = |status: &[&str]| -> (f64, f64) {
        rows.iter()
            .filter(|r| status.contains(&r.status.as_str()))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
                (a.min(r.x[0]), b.max(r.x[0]))
            })
    };
    let (c0, c1) = xs(&["stick"]);
    let (a0, a1) = xs(&["stick", "slip"]);
    let (c, a) = ((c1 - c0) / 2.0, (a1 - a0) / 2.0);
    let expected = (1.0 - ratio).sqrt();
    let spacing = 0.02;
    eprintln!(
        "Q/(nu_f P) = {ratio:.4}, c/a = {:.4} (Cattaneo-Mindlin {expected:.4}), a = {a:.4}",
        c / a
    );
    assert!(
        (c / a - expected).abs() < 2.0 * spacing / a,
        "c/a = {} against {expected} (a = {a})",
        c / a
    );
    // The cycle: Q up, down to -Q, up again.
    let mut text = String::from("step,dirichlet_top,traction_top\n");
    let cycle: Vec<f64> = [0.5, 1.0, 0.5, 0.0, -0.5, -1.0, -0.5, 0.0, 0.5, 1.0].to_vec();
    let mut k = 0;
    for f in [0.5, 1.0] {
        k += 1;
        text.push_str(&format!("{k},{f},0\n"));
    }
    for t in &cycle {
        k += 1;
        text.push_str(&format!("{k},1,{t}\n"));
    }
    std::fs::write(&table, &text).unwrap();
    let (_, steps, _) = history(&dir, "cycle", 2, &args);
    let pts: Vec<(f64, f64)> = steps[3..]
        .iter()
        .map(|r| {
            (
                num(r, "curve_displacement_traction_top_ux"),
                num(r, "curve_force_traction_top_ux"),
            )
        })
        .collect();
    // From Q at step 3 (the first +Q) round to the last +Q: a closed loop.
    let mut area = 0.0;
    for w in pts.windows(2) {
        area += 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0);
    }
    let width = pts.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max)
        - pts.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    let qmax = pts.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    eprintln!(
        "loop area {area:e}, Q {qmax:e} x width {width:e} = {:e}",
        qmax * width
    );
    // The work done on the body over the closed cycle, the loop integral
    // of Q dx: friction dissipates it, so it is positive.
    let dissipated = area;
    assert!(
        dissipated > 1e-3 * qmax * width && dissipated < 0.5 * qmax * width,
        "dissipated {dissipated:e} against Q x width {:e}",
        qmax * width
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Mindlin in 3D: half a plate (symmetry plane y = 0) pressed onto a rigid
/// ball (uz = -0.02 on its top, in 2 steps), then pulled along x by a top
/// traction up to Q = 0.5 nu_f P (2 steps): the stick zone's radius c
/// against the contact's a follows c/a = (1 - Q/(nu_f P))^(1/3) = 0.794
/// within one element (h = 0.025 near the contact, h/a = 0.17; measured
/// 0.832 here, 0.809 against 0.788 at h = 0.0125: converging). nu = 0.45:
/// the normal-tangential coupling of a rigid ball (Dundurs' beta 0.09)
/// stays small; it still slips a rim under the normal load alone.
#[test]
fn mindlin_3d_stick_zone() {
    let dir = scratch("history-mindlin");
    let msh = dir.join("halfplate3d.msh");
    gmsh("-3", "tests/obstacles/halfplate3d.geo", &msh, &[]);
    let table = dir.join("t.csv");
    std::fs::write(
        &table,
        "step,dirichlet_top,traction_top\n1,0.5,0\n2,1,0\n3,1,0.5\n4,1,1\n",
    )
    .unwrap();
    let msh = msh.to_str().unwrap().to_string();
    let args = [
        "-mesh",
        &msh,
        "-E",
        "1",
        "-nu",
        "0.45",
        "-dirichlet_symy",
        "uy=0",
        "-dirichlet_top",
        "uz=-0.02",
        "-contact_surface",
        "bottom",
        "-obstacle",
        "ball",
        "-obstacle_center",
        "0,0,-1",
        "-obstacle_radius",
        "1",
        "-friction",
        "coulomb",
        "-friction_coefficient",
        "0.4",
        "-ubr_lambda_rtol",
        "1e-5",
        "-traction_top",
        "2.78e-4,0,0",
        "-load_history",
        table.to_str().unwrap(),
    ];
    let (_, steps, rows) = history(&dir, "mindlin", 2, &args);
    let last = steps.last().unwrap();
    let (p, q) = (
        num(last, "reaction_top_z").abs(),
        num(last, "contact_force_x").abs(),
    );
    let expected = (1.0 - q / (0.4 * p)).cbrt();
    let radius = |status: &[&str]| -> f64 {
        rows.iter()
            .filter(|r| status.contains(&r.status.as_str()))
            .map(|r| r.x[0].hypot(r.x[1]))
            .fold(0.0, f64::max)
    };
    let (c, a) = (radius(&["stick"]), radius(&["stick", "slip"]));
    eprintln!(
        "Q/(nu_f P) = {:.4}, c/a = {:.4} (Mindlin {expected:.4}), a = {a:.4}",
        q / (0.4 * p),
        c / a
    );
    assert!(
        (q / (0.4 * p) - 0.5).abs() < 0.01,
        "Q/(nu_f P) = {}",
        q / (0.4 * p)
    );
    assert!(
        (c / a - expected).abs() < 0.025 / a,
        "c/a = {} against {expected}",
        c / a
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The crowned block's quasi-static Coulomb history (press, pull
/// sideways, release the pull) at a tight tolerance: its scratch dir and
/// arguments.
fn coulomb_history(name: &str) -> (Scratch, Vec<String>) {
    let (dir, msh) = gmsh_2d(name, "tests/scenes/crowned2d_coulomb.geo");
    let table = dir.join("t.csv");
    std::fs::write(
        &table,
        "step,dirichlet_top,traction_top\n1,0.5,0\n2,1,0\n3,1,0.5\n4,1,1\n5,1,0\n",
    )
    .unwrap();
    let args = [
        "-mesh",
        &msh,
        "-E",
        "1000",
        "-nu",
        "0.45",
        "-contact_surface",
        "crown",
        "-contact_direction",
        "0,-1",
        "-obstacle",
        "plane",
        "-obstacle_point",
        "0,0",
        "-friction",
        "coulomb",
        "-friction_coefficient",
        "0.4",
        "-dirichlet_top",
        "uy=-0.02",
        "-traction_top",
        "0.3,0",
        "-load_history",
        table.to_str().unwrap(),
        "-ubr_lambda_rtol",
        "1e-10",
    ];
    (dir, args.iter().map(|a| a.to_string()).collect())
}

/// The history on 1, 2 and 3 ranks: the final stresses agree to 1e-8 of
/// the peak (measured 1.1e-13).
#[test]
fn quasi_static_coulomb_ranks_agree() {
    let (dir, args) = coulomb_history("history-ranks");
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let runs: Vec<Vec<Row>> = (1..=3)
        .map(|n| solve_rows(&format!("history-ranks-{n}"), n, &args).2)
        .collect();
    assert!(runs[0].iter().any(|r| r.status == "slip"), "nothing slips");
    for (n, rows) in runs.iter().enumerate().skip(1) {
        let gap = max_stress_gap(rows, &runs[0]);
        assert!(
            gap < 1e-8,
            "1 and {} ranks: stresses differ by {gap:e}",
            n + 1
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Asking for every step's outputs (`-history_output`, `-vtk`) leaves the
/// answer as it is: to the last bit on one rank, and within the run-to-run
/// spread of MUMPS on 2 ranks (its parallel factorization is not bitwise
/// repeatable). (A step with outputs took its condensed load from a solve
/// of its own, the others from the parts' responses, and the slip of the
/// next step from the whole displacement: the same to round-off, but a
/// sliding history at -ubr_lambda_rtol 1e-9 converged without
/// -history_output and ended with exit 3 with it.)
#[test]
fn history_outputs_leave_the_answer_unchanged() {
    let (dir, args) = coulomb_history("history-outputs");
    let table = dir.join("steps.csv");
    let vtk = dir.join("u.vtu");
    for ranks in [1, 2] {
        let mut plain: Vec<&str> = args.iter().map(String::as_str).collect();
        let bare = run_outputs(&format!("history-bare-{ranks}"), ranks, &plain, None);
        plain.extend([
            "-history_output",
            table.to_str().unwrap(),
            "-vtk",
            vtk.to_str().unwrap(),
        ]);
        let full = run_outputs(&format!("history-full-{ranks}"), ranks, &plain, None);
        for out in [&bare, &full] {
            assert_eq!(out.status, Some(0), "{}", out.context());
        }
        assert!(table.exists(), "no history table");
        if ranks == 1 {
            assert!(
                bare.csv_text.is_some() && bare.csv_text == full.csv_text,
                "the contact CSV changed with -history_output and -vtk"
            );
        } else {
            let gap = max_stress_gap(&full.rows(), &bare.rows());
            assert!(gap < 1e-8, "{ranks} ranks: stresses differ by {gap:e}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad histories end with exit 2 and one line naming the option.
#[test]
fn bad_histories_are_refused() {
    let dir = scratch("history-bad");
    let table = dir.join("h.csv");
    std::fs::write(&table, "step,traction_side\n1,1\n").unwrap();
    let t = table.to_str().unwrap();
    let h = dir.join("out.csv");
    let ho = h.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["-load_steps", "0"], "option -load_steps: 0 steps"),
        (
            vec!["-load_steps", "x"],
            "option -load_steps: 'x' is not a non-negative integer",
        ),
        (
            vec!["-load_history", t],
            "line 1: column 'traction_side' is not a load group of this run",
        ),
        (
            vec!["-load_history", "/nonexistent/h.csv"],
            "option -load_history: cannot read",
        ),
        (
            vec!["-load_steps", "2", "-load_history", t],
            "give one of them, not both",
        ),
        (
            vec!["-history_output", ho],
            "option -history_output needs a load history",
        ),
        (
            vec!["-load_steps", "2", "-history_curve", "traction_side"],
            "option -history_curve: 'traction_side' is not a load group",
        ),
        (
            vec!["-load_steps", "2", "-contact_algorithm", "ssn"],
            "load histories (-load_steps, -load_history) run with UBR",
        ),
        // (It took 12 GB in 20 s, before the first solve.)
        (
            vec!["-load_steps", "100000000"],
            "option -load_steps 100000000: a load history has at most 1000000 steps",
        ),
    ];
    for (extra, needle) in cases {
        for ranks in [1, 2] {
            let mut args = vec!["-options_file", "options/hertz"];
            args.extend(&extra);
            let run = mpirun(ranks, &args);
            run.refused(&format!("{extra:?}"), 2, &[needle]);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The check before the factorization judges the loads the steps apply,
/// not the whole load (which a history may never apply): a pulling
/// traction applied by negative factors presses the body and is solved;
/// a step that pulls the body off is refused (exit 2) and named, on every
/// rank count, also with a Tresca bound. A history that stops early still
/// names its curve's columns.
#[test]
fn history_steps_are_judged_by_their_own_loads() {
    let dir = scratch("history-steps-judged");
    let table = dir.join("h.csv");
    let t = table.to_str().unwrap();
    // -traction_top 0,100 pulls; the factors -0.5, -1 press with 50, 100.
    std::fs::write(&table, "step,factor\n1,-0.5\n2,-1\n").unwrap();
    let pull = ["-options_file", "options/hertz", "-traction_top", "0,100"];
    let mut args = pull.to_vec();
    args.extend(["-load_history", t]);
    let (_, rows, _) = history(&dir, "negative", 2, &args);
    let force: Vec<f64> = rows.iter().map(|r| num(r, "contact_force_y")).collect();
    assert!(
        (force[0] - 400.0).abs() < 1e-6 && (force[1] - 800.0).abs() < 1e-6,
        "{force:?}"
    );
    // Pressed, then pulled off at step 2: refused before the factorization.
    std::fs::write(&table, "step,factor\n1,1\n2,-1\n").unwrap();
    for ranks in [1, 2, 3] {
        let run = mpirun(
            ranks,
            &["-options_file", "options/hertz", "-load_history", t],
        );
        let step =
            format!("load step 2/2 (-load_history {t} -1.0000): the loads pull the body off");
        run.refused("a step that pulls off", 2, &[&step]);
    }
    // So with a Tresca bound (it ran step 2 to exit 3 before).
    let run = mpirun(
        2,
        &["-options_file", "options/hertz-tresca", "-load_history", t],
    );
    let step = format!("load step 2/2 (-load_history {t} -1.0000): the loads pull the body off");
    run.refused("a Tresca step that pulls off", 2, &[&step]);
    // A step whose solve fails (a factor beyond double precision): the
    // table of the step before it names the curve.
    let huge = dir.join("huge.csv");
    std::fs::write(&huge, "step,factor\n1,1\n2,1e300\n").unwrap();
    let out = dir.join("tresca.csv");
    let run = mpirun(
        2,
        &[
            "-options_file",
            "options/hertz-tresca",
            "-load_history",
            huge.to_str().unwrap(),
            "-history_output",
            out.to_str().unwrap(),
        ],
    );
    assert_eq!(run.status, Some(3), "{}", run.context());
    assert!(
        run.stderr.contains("load step 2/2") && run.stderr.contains("non-finite iterate"),
        "{}",
        run.context()
    );
    // Its summary shows no answer (the zero start) and says so.
    assert!(
        run.stdout
            .contains("answer          none: the run stopped with the error below"),
        "{}",
        run.context()
    );
    let rows = history_rows(&out);
    assert_eq!(rows.len(), 1);
    assert!(
        num(&rows[0], "curve_force_traction_top_uy") < 0.0,
        "{rows:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
