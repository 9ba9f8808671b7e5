//! The paper's three-dimensional problem (section 7.2): a block pressed on a
//! rigid half-ball, P1 tetrahedra.
mod common;
use common::*;

fn block<'a>(file: &'a str, mesh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["-options_file", file, "-mesh", mesh];
    v.extend_from_slice(extra);
    v
}

/// The total vertical contact force converges under refinement; the independent
/// peers found 98.3e3, 93.0e3, 88.2e3 on meshes of about 760, 2387, 10241 nodes.
#[test]
fn contact_force_matches_peers() {
    for (mesh, peer) in [
        ("meshes/block3d_739.msh", 98.3e3),
        ("meshes/block3d_2357.msh", 93.0e3),
        ("meshes/block3d_10761.msh", 88.2e3),
    ] {
        let (run, r, _) = solve_rows("force3d", 2, &block("options/block3d", mesh, &[]));
        let f = num(&r, "contact_force");
        assert!(
            (f - peer).abs() < 0.03 * peer,
            "{mesh}: force {f} vs peers {peer}\n{}",
            run.stdout
        );
        assert_eq!(r["dimension"], serde_json::json!(3));
    }
}

/// MUMPS and GAMG-preconditioned CG give the same pressures at a tight tolerance.
#[test]
fn mumps_and_gamg_cg_agree() {
    let mesh = "meshes/block3d_10761.msh";
    let (_, _, direct) = solve_rows(
        "mumps3d",
        2,
        &block("options/block3d", mesh, &["-ubr_rtol", "1e-10"]),
    );
    let (run, r, gamg) = solve_rows(
        "gamg3d",
        2,
        &block(
            "options/block3d",
            mesh,
            &["-ubr_rtol", "1e-10", "-ksp_type", "cg", "-pc_type", "gamg"],
        ),
    );
    assert!(run.stdout.contains("cg + gamg"), "{}", run.stdout);
    let inner: Vec<f64> = r["inner_iterations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert!(
        inner.iter().sum::<f64>() >= inner.len() as f64,
        "CG iterations {inner:?}"
    );
    let pmax = direct.iter().map(|x| x.lambda_n).fold(0.0, f64::max);
    for (a, b) in direct.iter().zip(&gamg) {
        assert_eq!(a.node, b.node);
        assert!(
            (a.lambda_n - b.lambda_n).abs() <= 1e-6 * pmax,
            "node {}: {} vs {}",
            a.node,
            a.lambda_n,
            b.lambda_n
        );
    }
}

/// -n 1, 2, 3 agree in 3D, with Coulomb friction, at a tight tolerance; the
/// optimality conditions and the Coulomb cone hold.
#[test]
fn coulomb_3d_ranks_and_optimality() {
    let args = block(
        "options/block3d-coulomb",
        "meshes/block3d_739.msh",
        &["-ubr_rtol", "1e-12", "-ubr_fp_rtol", "1e-10"],
    );
    let mut runs = Vec::new();
    for n in [1, 2, 3] {
        let (_, r, rows) = solve_rows("coul3d", n, &args);
        let excess = num(&r, "max_friction_excess");
        assert!(
            excess <= 1e-8 * num(&r, "max_bound"),
            "cone violated by {excess}"
        );
        assert!(num(&r, "equilibrium_residual_rel") <= 1e-10);
        assert!(num(&r, "max_penetration") <= 1e-8 * num(&r, "max_abs_gap"));
        assert!(num(&r, "min_slip_alignment") >= 1.0 - 1e-6);
        assert!(num(&r, "max_stick_slip") <= 1e-8 * num(&r, "max_slip"));
        runs.push(rows);
    }
    let pmax = runs[0].iter().map(|x| x.lambda_n).fold(0.0, f64::max);
    for other in &runs[1..] {
        for (a, b) in runs[0].iter().zip(other) {
            assert_eq!(a.node, b.node);
            assert!((a.lambda_n - b.lambda_n).abs() <= 1e-8 * pmax);
            for c in 0..3 {
                assert!((a.lambda_t[c] - b.lambda_t[c]).abs() <= 1e-8 * pmax);
            }
        }
    }
}

/// The built-in generator runs the same scene.
#[test]
fn generated_block() {
    let (run, r, _) = solve_rows(
        "gen3d",
        2,
        &[
            "-options_file",
            "options/block3d",
            "-mesh_generate",
            "block3d",
            "-mesh_h",
            "0.1",
        ],
    );
    assert_eq!(num(&r, "nodes"), 2541.0, "{}", run.stdout);
    let f = num(&r, "contact_force");
    assert!((80e3..105e3).contains(&f), "force {f}");
}
