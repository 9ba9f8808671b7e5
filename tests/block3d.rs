//! The paper's three-dimensional problem (section 7.2): a block pressed on a
//! rigid half-ball, P1 tetrahedra.
mod common;
use common::*;

fn block<'a>(file: &'a str, mesh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["-options_file", file, "-mesh", mesh];
    v.extend_from_slice(extra);
    v
}

const MESHES: [(&str, f64); 5] = [
    ("meshes/block3d_198.msh", 198.0),
    ("meshes/block3d_739.msh", 739.0),
    ("meshes/block3d_2357.msh", 2357.0),
    ("meshes/block3d_10761.msh", 10761.0),
    ("meshes/block3d_17887.msh", 17887.0),
];

/// Tables 5 and 6 on the five meshes, with the paper's Gamma_c (the whole
/// bottom face, -obstacle halfball): UBR-C 30-50 iterations (paper 36-40),
/// UBR-TF 35-70 (paper 45-50), CF-FP 4-12 fixed-point and 70-130 Tresca
/// iterations (paper 6 and 91-94).
#[test]
#[ignore = "slow"]
fn tables5_6_iterations() {
    for (mesh, paper_nodes) in MESHES {
        let (run, r, rows) = solve_rows("t5", 2, &block("options/block3d-paper", mesh, &[]));
        let nodes = r.nodes;
        assert!(
            (nodes - paper_nodes).abs() < 0.03 * paper_nodes,
            "{mesh}: {nodes} nodes"
        );
        // Every node of the bottom face is a candidate; few touch.
        assert!(rows.iter().all(|x| (x.x[2] + 0.5).abs() < 1e-12));
        assert!(rows.iter().filter(|x| x.status == "open").count() > rows.len() / 2);
        let its = r.iterations;
        assert!(
            (30.0..=50.0).contains(&its),
            "{mesh}: UBR-C {its}\n{}",
            run.stdout
        );

        let (run, r, _) = solve_rows("t6tf", 2, &block("options/block3d-tresca-paper", mesh, &[]));
        let its = r.iterations;
        assert!(
            (35.0..=70.0).contains(&its),
            "{mesh}: UBR-TF {its}\n{}",
            run.stdout
        );

        let (run, r, _) = solve_rows(
            "t6cf",
            2,
            &block("options/block3d-coulomb-paper", mesh, &[]),
        );
        let fp = r.fixed_point_iterations;
        let inner = r.iterations;
        assert!(
            (4.0..=12.0).contains(&fp) && (70.0..=130.0).contains(&inner),
            "{mesh}: CF-FP {fp} / {inner}\n{}",
            run.stdout
        );
    }
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
        let (run, r, _) = solve_rows("force3d", 2, &block("options/block3d-paper", mesh, &[]));
        let f = r.contact_force;
        assert!(
            (f - peer).abs() < 0.03 * peer,
            "{mesh}: force {f} vs peers {peer}\n{}",
            run.stdout
        );
        assert_eq!(r.dimension, 3.0);
    }
}

/// MUMPS and GAMG-preconditioned CG give the same pressures at a tight
/// tolerance on the 10761 mesh, and so do -n 1, 2 and 3 (MUMPS).
#[test]
fn mumps_and_gamg_cg_agree() {
    let mesh = "meshes/block3d_10761.msh";
    let (_, _, direct) = solve_rows(
        "mumps3d",
        2,
        &block("options/block3d-paper", mesh, &["-ubr_rtol", "1e-10"]),
    );
    let (run, r, gamg) = solve_rows(
        "gamg3d",
        2,
        &block(
            "options/block3d-paper",
            mesh,
            &["-ubr_rtol", "1e-10", "-ksp_type", "cg", "-pc_type", "gamg"],
        ),
    );
    assert!(run.stdout.contains("cg + gamg"), "{}", run.stdout);
    let inner = r.inner_iterations.clone();
    assert!(
        inner.iter().sum::<f64>() >= inner.len() as f64,
        "CG iterations {inner:?}"
    );
    let pmax = direct.iter().map(|x| x.lambda_n).fold(0.0, f64::max);
    for n in [1, 3] {
        let (_, _, other) = solve_rows(
            "mumps3d_n",
            n,
            &block("options/block3d-paper", mesh, &["-ubr_rtol", "1e-10"]),
        );
        assert_eq!(other.len(), direct.len());
        for (a, b) in direct.iter().zip(&other) {
            assert_eq!(a.node, b.node);
            assert!(
                (a.lambda_n - b.lambda_n).abs() <= 1e-6 * pmax,
                "-n {n}, node {}: {} vs {}",
                a.node,
                a.lambda_n,
                b.lambda_n
            );
        }
    }
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
        "options/block3d-coulomb-paper",
        "meshes/block3d_739.msh",
        &["-ubr_rtol", "1e-12", "-ubr_fp_rtol", "1e-10"],
    );
    let mut runs = Vec::new();
    for n in [1, 2, 3] {
        let (_, r, rows) = solve_rows("coul3d", n, &args);
        let excess = r.max_friction_excess;
        assert!(excess <= 1e-8 * r.max_bound, "cone violated by {excess}");
        assert!(r.equilibrium_residual_rel <= 1e-10);
        assert!(r.max_penetration <= 1e-8 * r.max_abs_gap);
        assert!(r.min_slip_alignment >= 1.0 - 1e-6);
        assert!(r.max_stick_slip <= 1e-8 * r.max_slip);
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
            "options/block3d-paper",
            "-mesh_generate",
            "block3d",
            "-mesh_h",
            "0.1",
        ],
    );
    assert_eq!(r.nodes, 2541.0, "{}", run.stdout);
    let f = r.contact_force;
    assert!((80e3..105e3).contains(&f), "force {f}");
}
