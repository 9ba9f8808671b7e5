//! Linear-solver choices a user makes through PETSc's options, around the
//! factorization: each gives the default's answer, or a one-line refusal.

mod common;
use common::*;
use std::process::Command;

/// The Hertz scene at the defaults (automatic r, Anderson, the accuracy
/// stop) on the 1692-node mesh, tighter than the default tolerance so
/// that the answers compare closely.
fn hertz(extra: &[&'static str]) -> Vec<&'static str> {
    let mut v = vec!["-options_file", "options/hertz", "-ubr_lambda_rtol", "1e-7"];
    v.extend_from_slice(extra);
    v
}

/// The generated block (h 0.1) with CG + GAMG, then `extra`.
fn block3d_gamg(extra: &[&'static str]) -> Vec<&'static str> {
    let mut v = vec![
        "-options_file",
        "options/block3d",
        "-mesh_generate",
        "block3d",
        "-mesh_h",
        "0.1",
        "-ksp_type",
        "cg",
        "-pc_type",
        "gamg",
    ];
    v.extend_from_slice(extra);
    v
}

/// A Krylov method around the factorization (`-ksp_type gmres`, `cg -pc_type
/// cholesky`, `richardson`) gets the inexact inner solves of the iterative
/// solvers, measured against the residual each solve starts from: measured
/// against the whole load, a solve started from the previous iterate did 0
/// iterations once UBR changed u by less than a tenth, and UBR stalled
/// (hertz2d h 0.1: 588 iterations, "not converged", exit 3).
#[test]
fn krylov_around_the_factorization_converges() {
    let (_, _, reference) = solve_rows("default", 1, &hertz(&[]));
    for (ranks, extra) in [
        (1, &["-ksp_type", "gmres"][..]),
        (2, &["-ksp_type", "cg", "-pc_type", "cholesky"][..]),
        (1, &["-ksp_type", "richardson"][..]),
        (
            2,
            &[
                "-ksp_type",
                "gmres",
                "-pc_type",
                "lu",
                "-ubr_mumps_direct",
                "0",
            ][..],
        ),
    ] {
        let (run, report, rows) = solve_rows("krylov", ranks, &hertz(extra));
        assert!(report.converged, "{extra:?}: {}", run.stdout);
        let gap = max_pressure_gap(&rows, &reference);
        assert!(
            gap < 1e-5,
            "{extra:?} on {ranks} ranks: {gap:.2e} from the default"
        );
    }
}

/// `ubr-petsc` itself (no mpirun, which binds a rank to a core on 2 ranks
/// and hid it) with SuperLU_DIST: one OpenMP thread unless OMP_NUM_THREADS
/// asks for more, which with OpenBLAS is refused (its solves were wrong:
/// "moves without bound" at every run with 2 threads).
#[test]
fn superlu_dist_runs_one_thread() {
    let run = |threads: Option<&str>| {
        let t = std::time::Instant::now();
        let (mut cmd, _session) = mpi_command(BIN);
        cmd.env_remove("OMP_NUM_THREADS");
        if let Some(n) = threads {
            cmd.env("OMP_NUM_THREADS", n);
        }
        let mut args = hertz(&[
            "-pc_type",
            "lu",
            "-pc_factor_mat_solver_type",
            "superlu_dist",
        ]);
        args.extend(["-mesh", "meshes/hertz_442.msh"]);
        let out = cmd.args(&args).output().expect("ubr-petsc runs");
        Run {
            status: out.status.code(),
            stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
            seconds: t.elapsed().as_secs_f64(),
        }
    };
    let cores = Command::new("nproc").output().map_or(1, |o| {
        String::from_utf8_lossy(&o.stdout)
            .trim()
            .parse()
            .unwrap_or(1)
    });
    let unset = run(None);
    assert_eq!(unset.status, Some(0), "{cores} cores: {}", unset.context());
    assert!(
        unset.stdout.contains("converged: estimated error"),
        "{}",
        unset.stdout
    );
    let two = run(Some("2"));
    two.refused(
        "2 threads",
        2,
        &[
            "-pc_factor_mat_solver_type superlu_dist",
            "OMP_NUM_THREADS=2",
            "OMP_NUM_THREADS=1",
        ],
    );
    assert_eq!(run(Some("1")).status, Some(0));
}

/// MUMPS' own failures through PETSc's interface (`-ubr_mumps_direct 0`)
/// ended as "DIVERGED_PC_FAILED (preconditioner failure reason 4)", exit 3,
/// with nothing of what MUMPS said. Now its INFOG(1) and meaning are in the
/// line, and a failure for memory (here ICNTL(23), a 1 MB cap per rank,
/// INFOG(1) = -19) ends with exit 4, as with MUMPS driven by the program.
#[test]
fn mumps_failure_through_petsc_says_infog() {
    let run = mpirun(
        2,
        &hertz(&["-ubr_mumps_direct", "0", "-mat_mumps_icntl_23", "1"]),
    );
    run.refused(
        "ICNTL(23) 1 MB",
        4,
        &["MUMPS: INFOG(1) = -19", "-mat_mumps_icntl_23"],
    );
}

/// An ordering `-mat_mumps_icntl_7 K` asked for that MUMPS replaced in
/// silence (read back in INFOG(7)): with the Schur complement of the
/// condensed contact unknowns MUMPS orders with AMD whatever K, and the
/// summary used to name "ICNTL(7) = 4". Now the summary names what MUMPS
/// used, a warning says why, and one honoured (QAMD, without condensation)
/// is named without one. The answers stay the default's.
#[test]
fn mumps_ordering_replaced_is_named() {
    let (_, _, reference) = solve_rows("default", 1, &hertz(&[]));
    let (run, report, rows) = solve_rows("pord", 2, &hertz(&["-mat_mumps_icntl_7", "4"]));
    assert!(report.converged, "{}", run.context());
    assert!(
        run.stdout
            .contains("MUMPS' AMD in place of PORD (-mat_mumps_icntl_7 4; INFOG(7) = 0)"),
        "{}",
        run.context()
    );
    let warned = run.stderr_with("warning: -mat_mumps_icntl_7 4 asks for MUMPS' PORD ordering");
    assert_eq!(warned.len(), 1, "{}", run.context());
    assert!(warned[0].contains("Schur complement"), "{}", warned[0]);
    assert!(max_pressure_gap(&rows, &reference) < 1e-5);

    let (run, report, rows) = solve_rows(
        "qamd",
        1,
        &hertz(&["-mat_mumps_icntl_7", "6", "-ubr_condense_max", "0"]),
    );
    assert!(report.converged, "{}", run.context());
    assert!(
        run.stdout.contains("MUMPS' QAMD (-mat_mumps_icntl_7 6)"),
        "{}",
        run.context()
    );
    assert!(
        run.stderr_with("-mat_mumps_icntl_7").is_empty(),
        "{}",
        run.context()
    );
    assert!(max_pressure_gap(&rows, &reference) < 1e-5);
}

/// A preconditioner that fails inside (GAMG with SOR smoothers, which meet
/// zero pivots on a coarse level of the generated block) said only
/// "preconditioner failure reason 6"; the reason is now in words.
#[test]
fn preconditioner_failure_in_words() {
    let run = mpirun(1, &block3d_gamg(&["-mg_levels_pc_type", "sor"]));
    run.refused(
        "SOR smoothers",
        3,
        &["preconditioner failure reason 6: a preconditioner inside it failed"],
    );
}

/// A stall of an iterative solver's run on a body that Dirichlet conditions
/// hold is not blamed on sliding: the generated block (pressed by its top
/// face) with a Tresca bound far below its pressures slips at every contact
/// node, and CG + GAMG cannot reach a tangential error of 1e-10 relative to
/// that bound (flat at about 1e-9; the message said "the body slides or
/// rolls", which the top face's condition forbids). It names the solves.
#[test]
fn a_stall_of_iterative_solves_is_not_called_sliding() {
    let run = mpirun(
        1,
        &block3d_gamg(&[
            "-friction",
            "tresca",
            "-tresca_bound",
            "0.05",
            "-ubr_lambda_rtol",
            "1e-10",
        ]),
    );
    assert_eq!(run.status, Some(3), "{}", run.context());
    let lines = run.stderr_with("not converged:");
    assert_eq!(lines.len(), 1, "{}", run.context());
    for needle in [
        "stalled",
        "the iterative solver's solves",
        "the direct solver",
    ] {
        assert!(lines[0].contains(needle), "'{needle}' not in {}", lines[0]);
    }
    assert!(!lines[0].contains("slides or rolls"), "{}", lines[0]);
}

/// Krylov tolerances that leave nothing to solve: `-ksp_rtol 1` ended every
/// solve before its first iteration (PETSc 3.18 takes it) and UBR ran
/// 10,000 iterations on a displacement that never changed, exit 3 with an
/// error estimate of 4e137; refused now (exit 2, one line), with a
/// negative `-ksp_rtol` or `-ksp_atol` and a `-ksp_max_it` below 1. A
/// `-ksp_atol` above the model's residuals did the same, a value that can
/// be right in other units: the run stops after 20 such solves in a row,
/// naming the tolerances (exit 3), and an answer of such solves that
/// violates equilibrium is no answer (exit 3); a small one converges.
#[test]
fn krylov_tolerances_that_solve_nothing() {
    let gamg = |extra: &[&'static str]| {
        let mut v = hertz(&["-ksp_type", "cg", "-pc_type", "gamg"]);
        v.extend_from_slice(extra);
        v
    };
    for (ranks, option, value, needle) in [
        (1, "-ksp_rtol", "1", "is not in [0, 1)"),
        (2, "-ksp_rtol", "-0.1", "is not in [0, 1)"),
        (1, "-ksp_atol", "-1", "is not a non-negative number"),
        (
            2,
            "-ksp_max_it",
            "0",
            "is not a positive number of iterations",
        ),
    ] {
        let run = mpirun(ranks, &gamg(&[option, value]));
        run.refused(option, 2, &[&format!("option {option}: {value}"), needle]);
    }
    // The punch on the base (tests/pairs/punch3d.geo) at -ksp_atol 1e-3:
    // the solves end at the start and UBR's stresses grow; the Hertz scene
    // at 1e6: the first solve too, u stays 0 and UBR "converged" to no
    // contact at all (exit 0 before), an answer that violates equilibrium.
    let dir = scratch("solves-nothing");
    let msh = punch3d_mesh(&dir);
    let punch = punch3d_args(
        &msh,
        &["-ksp_type", "cg", "-pc_type", "gamg", "-ksp_atol", "1e-3"],
    );
    let hertz_1e6 = gamg(&["-ksp_atol", "1e6"]);
    // Between the two, 0 and 1 inner iterations in turn: a stall, whose
    // words blamed the contact set's cycling.
    let hertz_100 = gamg(&["-ksp_atol", "100"]);
    for (ranks, args, needle) in [
        (1, &hertz_100[..], "solves before their first iteration"),
        (1, &punch[..], "before its first iteration"),
        (2, &punch[..], "before its first iteration"),
        (
            1,
            &hertz_1e6[..],
            "violates equilibrium (relative residual 1.0e0)",
        ),
        (
            2,
            &hertz_1e6[..],
            "violates equilibrium (relative residual 1.0e0)",
        ),
    ] {
        let run = mpirun(ranks, args);
        assert_eq!(run.status, Some(3), "{}", run.context());
        let lines = run.stderr_with(needle);
        assert_eq!(lines.len(), 1, "{}", run.context());
        assert!(lines[0].contains("-ksp_atol"), "{}", lines[0]);
    }
    let _ = std::fs::remove_dir_all(&dir);
    let run = mpirun(1, &gamg(&["-ksp_atol", "1e-9"]));
    assert_eq!(run.status, Some(0), "{}", run.context());
}

/// `-ksp_type preonly` with a preconditioner that approximates K^-1 solves
/// nothing: it ended with exit 3 after a few iterations and the words "the
/// body is not held" (the solves, not the scene, were wrong); refused now,
/// exit 2, one line naming both options; so is a Krylov method without a
/// norm (`-ksp_norm_type none`).
#[test]
fn preonly_with_an_approximate_preconditioner_is_refused() {
    for (ranks, pc) in [(1, "jacobi"), (2, "gamg"), (2, "bjacobi")] {
        let run = mpirun(ranks, &hertz(&["-ksp_type", "preonly", "-pc_type", pc]));
        run.refused(
            pc,
            2,
            &[
                "option -ksp_type preonly",
                &format!("-pc_type {pc} applied once"),
            ],
        );
    }
    // A Krylov method without a norm meets no tolerance (CG ran 274
    // iterations to DIVERGED_INDEFINITE_MAT, exit 3); with the default
    // factorization (preonly) the norm is none anyway.
    let run = mpirun(2, &hertz(&["-pc_type", "gamg", "-ksp_norm_type", "none"]));
    run.refused("norm none", 2, &["option -ksp_norm_type none"]);
    let run = mpirun(1, &hertz(&["-ksp_norm_type", "none"]));
    assert_eq!(run.status, Some(0), "{}", run.context());
}
