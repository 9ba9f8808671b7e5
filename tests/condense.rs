//! The condensed UBR solve (`-ubr_condense_max`, on by default on one rank
//! in 2D): the same iterations and the same contact state as a full sparse
//! solve per iteration, for UBR-C, UBR-TF, CF-FP and with Anderson, when
//! the iteration cap stops the run, and off where it does not apply.
mod common;
use common::*;

/// Runs `args` on one rank condensed (the default) and with
/// `-ubr_condense_max 0`; both must take the same iterations and reach the
/// same contact state, to `tol` relative. Returns the condensed report.
fn same_as_full(name: &str, args: &[&str], unknowns: f64, tol: f64) -> Report {
    let (run, c, crows) = solve_rows(&format!("{name}_condensed"), 1, args);
    let mut plain = args.to_vec();
    plain.extend_from_slice(&["-ubr_condense_max", "0"]);
    let (_, f, frows) = solve_rows(&format!("{name}_full"), 1, &plain);
    assert_eq!(c.condensed_unknowns, unknowns, "{name}");
    assert!(
        run.stdout
            .contains(&format!("condensed on the {unknowns} contact unknowns")),
        "{name}: {}",
        run.stdout
    );
    assert_eq!(f.condensed_unknowns, 0.0, "{name}");
    assert_eq!(c.converged, f.converged, "{name}");
    assert_eq!(c.iterations, f.iterations, "{name}: iterations");
    assert_eq!(
        c.fixed_point_iterations, f.fixed_point_iterations,
        "{name}: fixed_point_iterations"
    );
    assert_eq!(
        c.frictionless_iterations, f.frictionless_iterations,
        "{name}: frictionless_iterations"
    );
    assert_eq!(c.contact_nodes, f.contact_nodes, "{name}: contact_nodes");
    let (fc, ff) = (c.contact_force, f.contact_force);
    assert!(
        (fc - ff).abs() <= tol * ff.abs(),
        "{name}: force {fc} vs {ff}"
    );
    let g = field_gap(&crows, &frows, |r| r.lambda_n);
    assert!(g <= tol, "{name}: pressures differ by {g:.3e}");
    let g = field_gap(&crows, &frows, |r| r.un);
    assert!(g <= tol, "{name}: u_n differ by {g:.3e}");
    let g = field_gap(&crows, &frows, |r| r.lambda_t[0].hypot(r.lambda_t[1]));
    assert!(g <= tol, "{name}: tangential stresses differ by {g:.3e}");
    for r in &crows {
        let s = frows.iter().find(|s| s.node == r.node).unwrap();
        assert_eq!(r.status, s.status, "{name}: node {}", r.node);
    }
    c
}

const MESH: &str = "meshes/hertz_6619.msh";

#[test]
fn ubr_c_and_anderson() {
    // Frictionless along an axis: the Schur complement on u_n alone.
    let c = same_as_full("c", &hertz_args(MESH, &[]), 137.0, 1e-9);
    assert!(c.converged);
    let its = c.iterations;
    assert!((35.0..=65.0).contains(&its), "{its} iterations");
    // The least-squares extrapolation amplifies round-off differences
    // (measured 9e-8 here); still far below the 1e-5 error of this tolerance.
    same_as_full(
        "aa",
        &hertz_aa_args(MESH, &["-ubr_anderson", "10", "-ubr_rtol", "1e-8"]),
        137.0,
        1e-6,
    );
}

#[test]
fn tresca_and_coulomb() {
    for (name, file) in [
        ("tf", "options/hertz-tresca-paper"),
        ("fp", "options/hertz-coulomb-paper"),
    ] {
        let r = same_as_full(name, &["-options_file", file, "-mesh", MESH], 274.0, 1e-9);
        assert!(r.converged, "{name}");
    }
}

/// A run that the cap stops reports the state of its last iteration, the
/// same as without condensation.
#[test]
fn stopped_by_the_cap() {
    for cap in ["3", "37"] {
        let args = hertz_args(MESH, &["-ubr_max_it", cap]);
        let dir = scratch(&format!("cap{cap}"));
        let mut out = Vec::new();
        for extra in [&[][..], &["-ubr_condense_max", "0"][..]] {
            let csv = dir.join(format!("c{}.csv", extra.len()));
            let cs = csv.to_str().unwrap().to_string();
            let mut a = args.clone();
            a.extend_from_slice(extra);
            a.extend_from_slice(&["-contact_output", &cs]);
            let run = mpirun(1, &a);
            assert_eq!(
                run.status,
                Some(3),
                "cap {cap}: {}\n{}",
                run.stdout,
                run.stderr
            );
            out.push(contact_rows(&csv));
        }
        let g = field_gap(&out[0], &out[1], |r| r.lambda_n);
        assert!(g <= 1e-9, "cap {cap}: pressures differ by {g:.3e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// On several ranks too (the Schur complement on rank 0), in 3D too; not
/// when every change of the paper's test is printed, not through PETSc's
/// MUMPS interface; bad values are bad input.
#[test]
fn where_it_does_not_apply() {
    let (_, r, _) = solve_rows("n2", 2, &hertz_args(MESH, &[]));
    assert_eq!(r.condensed_unknowns, 137.0);
    let (_, r, _) = solve_rows("petsc", 1, &hertz_args(MESH, &["-ubr_mumps_direct", "0"]));
    assert_eq!(r.condensed_unknowns, 0.0);
    let (run, r, _) = solve_rows("monitor", 1, &hertz_args(MESH, &["-ubr_monitor"]));
    assert_eq!(r.condensed_unknowns, 0.0);
    assert!(run.stdout.contains("UBR-C    38"), "{}", run.stdout);
    let block = [
        "-options_file",
        "options/block3d-paper",
        "-mesh",
        "meshes/block3d_739.msh",
    ];
    // 3D too: u_n alone, 123 candidates.
    same_as_full("block", &block, 123.0, 1e-9);
    let run = mpirun(2, &hertz_args(MESH, &["-ubr_condense_max", "-1"]));
    assert_eq!(run.status, Some(2), "{}", run.stderr);
    assert!(run.stderr.contains("-ubr_condense_max"), "{}", run.stderr);
}

/// In 3D the condensation is declined where MUMPS' analysis with the Schur
/// complement predicts fewer sparse factorization flops than half the cube
/// of the Schur block's order (`CONDENSE_DENSE_SHARE`): a 1 x 1 x 0.1 plate
/// pressed on a large ball, its whole bottom face the contact surface
/// (tests/edges/plate3d.geo: 1539 contact unknowns, a third of the mesh's,
/// 4.6e8 flops against m^3 = 3.6e9), measured 0.28 s condensed against
/// 0.11 s with full solves (at h 0.033, 1.82 against 0.68 s). The summary
/// says so and names the option that condenses; an explicit
/// `-ubr_condense_max` condenses as before, and so does a given
/// `-ubr_schur_distributed`; the two answers agree at a tight tolerance,
/// on 1 and 2 ranks.
#[test]
fn a_3d_schur_block_heavier_than_the_sparse_factorization_is_declined() {
    let dir = scratch("plate3d");
    let msh = dir.join("plate3d.msh");
    gmsh("-3", "tests/edges/plate3d.geo", &msh, &[]);
    let msh = msh.to_str().unwrap();
    let args = [
        "-mesh",
        msh,
        "-E",
        "1e4",
        "-nu",
        "0.3",
        "-pressure_top",
        "10",
        "-dirichlet_top",
        "ux=0,uy=0",
        "-contact_surface",
        "bottom",
        "-obstacle",
        "ball",
        "-obstacle_center",
        "0.5,0.5,-5",
        "-obstacle_radius",
        "5",
        "-ubr_lambda_rtol",
        "1e-10",
    ];
    for ranks in [1, 2] {
        let (run, rep, rows) = solve_rows(&format!("plate3d_{ranks}"), ranks, &args);
        assert!(rep.converged, "{}", run.context());
        assert_eq!(rep.condensed_unknowns, 0.0, "{}", run.stdout);
        let said = "not condensed: the dense Schur complement on the ";
        let at = run
            .stdout
            .find(said)
            .unwrap_or_else(|| panic!("{}", run.stdout));
        let m: usize = run.stdout[at + said.len()..]
            .split(' ')
            .next()
            .and_then(|w| w.parse().ok())
            .unwrap_or_else(|| panic!("{}", run.stdout));
        assert!(m > 1000, "{m} contact unknowns");
        let m = m.to_string();
        let mut forced = args.to_vec();
        forced.extend_from_slice(&["-ubr_condense_max", &m]);
        let (frun, frep, frows) = solve_rows(&format!("plate3d_{ranks}_forced"), ranks, &forced);
        assert!(frep.converged, "{}", frun.context());
        assert_eq!(frep.condensed_unknowns.to_string(), m, "{}", frun.stdout);
        assert!(!frun.stdout.contains("not condensed"), "{}", frun.stdout);
        let g = field_gap(&rows, &frows, |r| r.lambda_n);
        assert!(g <= 1e-7, "{ranks} ranks: pressures differ by {g:.3e}");
    }
    // The user who places the Schur complement wants it.
    let mut placed = args.to_vec();
    placed.extend_from_slice(&["-ubr_schur_distributed", "1"]);
    let (run, rep, _) = solve_rows("plate3d_placed", 2, &placed);
    assert!(rep.condensed_unknowns > 1000.0, "{}", run.stdout);
    assert!(run.stdout.contains("by ScaLAPACK"), "{}", run.stdout);
}
