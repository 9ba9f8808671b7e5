//! The paper's frictionless Hertz problem (section 7.1), Algorithm UBR-C.
mod common;
use common::*;

const MESHES: [(&str, usize); 5] = [
    ("meshes/hertz_442.msh", 442),
    ("meshes/hertz_1692.msh", 1692),
    ("meshes/hertz_6619.msh", 6619),
    ("meshes/hertz_26181.msh", 26181),
    ("meshes/hertz_37473.msh", 37473),
];

/// Table 1: iterations at r = 0.11E on the five meshes (paper 40-47; accepted 35-65),
/// the contact force balances the load, and the pressure is within 3.5% of Hertz
/// on meshes of 1692 nodes and finer.
#[test]
fn table1_iterations_force_and_hertz_error() {
    for (mesh, paper_nodes) in MESHES {
        let (run, r, rows) = solve("table1", 2, &hertz_args(mesh, &[]));
        let nodes = num(&r, "nodes");
        assert!(
            (nodes - paper_nodes as f64).abs() < 0.03 * paper_nodes as f64,
            "{mesh}: {nodes} nodes"
        );
        let its = num(&r, "iterations");
        assert!(
            (35.0..=65.0).contains(&its),
            "{mesh}: {its} iterations\n{}",
            run.stdout
        );
        assert_eq!(r["converged"], serde_json::Value::Bool(true));
        let force = num(&r, "contact_force");
        assert!(
            (force - 800.0).abs() <= 1e-6 * 800.0,
            "{mesh}: contact force {force}"
        );
        let err = num(&r, "pressure_error_rel");
        if paper_nodes >= 1692 {
            assert!(err <= 0.035, "{mesh}: relative pressure error {err}");
        }
        assert_eq!(num(&r, "matrix_mallocs"), 0.0);
        // The pressure is the normal stress of u^k: non-negative up to the
        // iteration's tolerance (1e-5) on open nodes.
        let peak = num(&r, "peak_pressure");
        assert!(
            rows.iter().all(|(_, l, _)| *l >= -1e-4 * peak),
            "{mesh}: negative pressure {}",
            num(&r, "min_lambda_n")
        );
        assert!(
            rows.iter().any(|(_, _, s)| s == "contact") && rows.iter().any(|(_, _, s)| s == "open")
        );
        println!(
            "{mesh}: {its} iterations, error {:.3}%, {:.3} s",
            100.0 * err,
            run.seconds
        );
    }
}

/// The paper's exact setting, rho = r, also takes 35-65 iterations on every mesh.
#[test]
fn table1_iterations_with_rho_equal_r() {
    for (mesh, _) in MESHES {
        let (run, r, _) = solve("table1rho", 1, &hertz_args(mesh, &["-ubr_rho", "220"]));
        let its = num(&r, "iterations");
        assert!(
            (35.0..=65.0).contains(&its),
            "{mesh}: {its} iterations\n{}",
            run.stdout
        );
        let force = num(&r, "contact_force");
        assert!(
            (force - 800.0).abs() <= 1e-6 * 800.0,
            "{mesh}: contact force {force}"
        );
    }
}

/// At a low load (b/R = 0.085) Hertz theory holds well: on a mesh refined near
/// the contact the pressure error falls below 1%.
#[test]
fn low_load_matches_hertz_within_one_percent() {
    let (run, r, _) = solve("lowload", 2, &["-options_file", "options/hertz-lowload"]);
    let err = num(&r, "pressure_error_rel");
    assert!(err < 0.01, "relative error {err}\n{}", run.stdout);
    let force = num(&r, "contact_force");
    assert!((force - 50.0).abs() <= 1e-6 * 50.0);
}

/// At a tight tolerance the discrete optimality conditions hold.
#[test]
fn optimality_conditions_at_tight_tolerance() {
    let (run, r, _) = solve(
        "kkt",
        2,
        &hertz_args("meshes/hertz_1692.msh", &["-ubr_rtol", "1e-10"]),
    );
    let eq = num(&r, "equilibrium_residual_rel");
    assert!(eq <= 1e-8, "equilibrium {eq}\n{}", run.stdout);
    let pmax = num(&r, "peak_pressure");
    assert!(
        num(&r, "min_lambda_n") >= -1e-10 * pmax,
        "min lambda_n {}",
        num(&r, "min_lambda_n")
    );
    let pen = num(&r, "max_penetration");
    let gmax = num(&r, "max_abs_gap");
    assert!(pen <= 1e-8 * gmax, "penetration {pen} vs max|g| {gmax}");
    // complementarity at round-off relative to force * max|g|
    let c = num(&r, "complementarity").abs();
    assert!(c <= 1e-8 * 800.0 * gmax, "complementarity {c}");
}

/// -n 1, 2, 3 agree: iterations within +-1 at the default tolerance; pressures to
/// 1e-8 relative at -ubr_rtol 1e-10.
#[test]
fn rank_count_independence() {
    let mut its = Vec::new();
    for n in [1, 2, 3] {
        let (_, r, _) = solve("ranks", n, &hertz_args("meshes/hertz_6619.msh", &[]));
        its.push(num(&r, "iterations"));
    }
    assert!(
        its.iter().all(|&i| (i - its[0]).abs() <= 1.0),
        "iterations {its:?}"
    );
    let mut pressures: Vec<Vec<(u64, f64, String)>> = Vec::new();
    for n in [1, 2, 3] {
        let (_, _, rows) = solve(
            "ranks_tight",
            n,
            &hertz_args("meshes/hertz_6619.msh", &["-ubr_rtol", "1e-10"]),
        );
        pressures.push(rows);
    }
    let pmax = pressures[0].iter().map(|r| r.1).fold(0.0, f64::max);
    for other in &pressures[1..] {
        assert_eq!(other.len(), pressures[0].len());
        for (a, b) in pressures[0].iter().zip(other) {
            assert_eq!(a.0, b.0);
            assert!(
                (a.1 - b.1).abs() <= 1e-8 * pmax,
                "node {}: {} vs {}",
                a.0,
                a.1,
                b.1
            );
        }
    }
}

/// The UBR matrix is factorized once: -log_view shows one numeric
/// factorization, MUMPS called directly (MUMPSFactorNum) or through PETSc
/// (MatCholFctrNum).
#[test]
fn one_numeric_factorization() {
    for (event, extra) in [
        ("MUMPSFactorNum", &["-log_view"][..]),
        (
            "MatCholFctrNum",
            &["-log_view", "-ubr_mumps_direct", "0"][..],
        ),
    ] {
        let run = mpirun(2, &hertz_args("meshes/hertz_1692.msh", extra));
        assert_eq!(run.status, Some(0), "{}", run.stderr);
        let line = run
            .stdout
            .lines()
            .find(|l| l.starts_with(event))
            .unwrap_or_else(|| panic!("no {event} in -log_view:\n{}", run.stdout));
        let count: usize = line.split_whitespace().nth(1).unwrap().parse().unwrap();
        assert_eq!(count, 1, "{line}");
    }
    let run = mpirun(2, &hertz_args("meshes/hertz_1692.msh", &["-log_view"]));
    for stage in [
        "Mesh",
        "Partition",
        "Assembly",
        "Factorization",
        "Iterations",
        "Output",
    ] {
        let found = run.stdout.lines().any(|l| {
            let t = l.trim_start();
            t.starts_with(|c: char| c.is_ascii_digit()) && t.contains(&format!(" {stage}:"))
        });
        assert!(found, "no stage {stage} in -log_view");
    }
}

/// The 2.2 and 4.1 files of the same mesh give the same answer, and the
/// built-in generator runs the same scene.
#[test]
fn msh22_msh41_and_generated_meshes() {
    let (_, a, ra) = solve("v41", 2, &hertz_args("meshes/hertz_442.msh", &[]));
    let (_, b, rb) = solve("v22", 2, &hertz_args("meshes/hertz_442_v22.msh", &[]));
    assert_eq!(num(&a, "iterations"), num(&b, "iterations"));
    assert_eq!(ra.len(), rb.len());
    for (x, y) in ra.iter().zip(&rb) {
        assert!((x.1 - y.1).abs() <= 1e-10 * (1.0 + x.1.abs()));
    }
    let args = [
        "-options_file",
        "options/hertz-paper",
        "-mesh_generate",
        "hertz2d",
        "-mesh_h",
        "0.2",
    ];
    let (run, g, _) = solve("generated", 2, &args);
    let its = num(&g, "iterations");
    assert!((35.0..=65.0).contains(&its), "{its}\n{}", run.stdout);
    assert!((num(&g, "contact_force") - 800.0).abs() < 1e-6 * 800.0);
    // 1552 nodes: below the 1692-node bar of 3.5%
    assert!(num(&g, "pressure_error_rel") < 0.05);
}
