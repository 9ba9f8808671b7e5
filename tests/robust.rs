//! Trust at the edges: a run that runs out of memory ends every rank
//! promptly with one line naming memory and exit status 4 (it hung in
//! OpenBLAS' allocator before); a run that fails after the assembly (a
//! failed factorization or linear solve, memory in MUMPS) still writes its
//! report and contact CSV, with `converged: false` and the message under
//! `failure`, what it did not compute null.
mod common;
use common::*;
use std::time::Instant;

/// `mpirun -n ranks ubr-petsc args... -report R -contact_output C`, each
/// rank under an address-space limit of `limit_kb` when given (`ulimit -v`
/// in a shell that then runs the program, so that mpirun itself is not
/// limited), ended by `timeout` (exit 124) if it takes longer than
/// `seconds`. Returns the run and the scratch directory of R and C.
fn run(
    name: &str,
    ranks: usize,
    limit_kb: Option<u64>,
    seconds: u64,
    args: &[&str],
) -> (Run, Scratch) {
    let dir = scratch(name);
    let (rep, csv) = (dir.join("report.json"), dir.join("contact.csv"));
    let (mut cmd, _session) = mpi_command("timeout");
    cmd.args(["-k", "10", &seconds.to_string(), "mpirun", "-n"])
        .arg(ranks.to_string());
    if let Some(kb) = limit_kb {
        cmd.args([
            "bash",
            "-c",
            &format!("ulimit -v {kb} && exec \"$0\" \"$@\""),
        ]);
    }
    cmd.arg(BIN).args(args);
    cmd.arg("-report")
        .arg(&rep)
        .arg("-contact_output")
        .arg(&csv);
    let t = Instant::now();
    let out = cmd.output().expect("timeout and mpirun run");
    let run = Run {
        status: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        seconds: t.elapsed().as_secs_f64(),
    };
    (run, dir)
}

/// The report of a failed run: `converged` false, `failure` the message
/// the run printed (its first line on stderr that carries it), the
/// contact CSV one row per candidate.
fn failed_report(run: &Run, dir: &std::path::Path, candidates: usize) -> Report {
    let rep = report(&dir.join("report.json"));
    assert!(!rep.converged, "{rep:?}");
    let failure = rep
        .failure
        .as_deref()
        .unwrap_or_else(|| panic!("no failure in the report: {rep:?}"));
    assert!(
        run.stderr.lines().any(|l| l == failure),
        "the report's failure is not the printed message:\n{failure}\nstderr:\n{}",
        run.stderr
    );
    assert_eq!(rep.contact_nodes as usize, candidates);
    assert_eq!(contact_rows(&dir.join("contact.csv")).len(), candidates);
    rep
}

#[test]
fn a_memory_limit_ends_every_rank_with_exit_4() {
    // 560 MB of address space per rank: above what MPI, PETSc and
    // OpenBLAS' 128 MiB work space take to start (about 430 MB here),
    // below what the 10761-node block needs (about 620 MB). Before, at this
    // limit, rank 0 spun for ever in OpenBLAS' allocator (its work space,
    // first mapped in MUMPS' factorization) and rank 1 waited in MUMPS.
    // Where the limit is met may vary (MUMPS' factorization here; OpenBLAS'
    // work space at start-up, PETSc, a Rust allocation at tighter limits):
    // every one ends the same way.
    let (run, dir) = run(
        "oom-ulimit",
        2,
        Some(560_000),
        120,
        &[
            "-options_file",
            "options/block3d",
            "-mesh",
            "meshes/block3d_10761.msh",
        ],
    );
    let _ = std::fs::remove_dir_all(&dir);
    assert_ne!(run.status, Some(124), "hung:\n{}", run.stderr);
    assert_eq!(
        run.status,
        Some(4),
        "stdout:\n{}\nstderr:\n{}",
        run.stdout,
        run.stderr
    );
    let named: Vec<&str> = run
        .stderr
        .lines()
        .filter(|l| l.contains("error: out of memory: "))
        .collect();
    assert!(!named.is_empty(), "no line names memory:\n{}", run.stderr);
    assert!(!run.stderr.contains("internal error"), "{}", run.stderr);
    assert!(run.seconds < 60.0, "took {:.1} s", run.seconds);
}

/// A factorization larger than the machine: refused after the analysis,
/// before it starts (the kernel killed such a run, signal 9, nothing
/// written: the generated block at -mesh_h 0.006 on this 24 GB machine).
/// Here the machine's memory is `-ubr_memory_mb 12`, above the matrix (5 MB)
/// and below what MUMPS' analysis predicts (24 MB on one rank, 45 on two):
/// exit 4 on 1 and 2 ranks, the prediction and the budget named, the
/// report written, nothing factorized. At 1 MB the matrix alone is refused
/// before the assembly (the generated block at -mesh_h 0.006 on this
/// machine, 24 GB of matrix, was killed during it), with no report, on
/// CG + GAMG too.
#[test]
fn runs_larger_than_the_machine_are_refused() {
    for ranks in [1, 2] {
        let (run, dir) = run(
            "oom-machine",
            ranks,
            None,
            120,
            &[
                "-options_file",
                "options/block3d",
                "-mesh",
                "meshes/block3d_2357.msh",
                "-ubr_memory_mb",
                "12",
            ],
        );
        assert_eq!(run.status, Some(4), "stderr:\n{}", run.stderr);
        let rep = failed_report(&run, &dir, 262);
        let failure = rep.failure.as_deref().unwrap();
        let plural = if ranks == 1 { "rank" } else { "ranks" };
        for needle in [
            "error: out of memory: MUMPS' analysis predicts that the factorization needs",
            &format!("on the {ranks} {plural} of one machine"),
            "more than the 12 MB that -ubr_memory_mb allows",
            "-ksp_type cg -pc_type gamg",
        ] {
            assert!(failure.contains(needle), "'{needle}' not in: {failure}");
        }
        assert_eq!(rep.iterations, 0.0);
        assert_eq!(rep.linear_solves, 0.0);
        let _ = std::fs::remove_dir_all(&dir);
    }
    for (ranks, extra) in [(1, None), (2, None), (2, Some("gamg"))] {
        let mut a = vec![
            "-options_file",
            "options/block3d",
            "-mesh",
            "meshes/block3d_2357.msh",
            "-ubr_memory_mb",
            "1",
        ];
        if let Some(pc) = extra {
            a.extend_from_slice(&["-ksp_type", "cg", "-pc_type", pc]);
        }
        let run = mpirun(ranks, &a);
        let line = run.refused(
            "matrix over -ubr_memory_mb",
            4,
            &[
                "the stiffness matrix alone",
                "more than the 1 MB that -ubr_memory_mb allows",
            ],
        );
        assert_eq!(line.contains("MUMPS' copy"), extra.is_none(), "{line}");
        assert!(run.seconds < 20.0, "took {:.1} s", run.seconds);
    }
    // The budget is checked as an option: positive.
    let run = mpirun(
        2,
        &["-options_file", "options/block3d", "-ubr_memory_mb", "0"],
    );
    run.refused("-ubr_memory_mb 0", 2, &["-ubr_memory_mb", "not positive"]);
}

/// MemAvailable of this machine in MB.
fn available_mb() -> u64 {
    let text = std::fs::read_to_string("/proc/meminfo").expect("/proc/meminfo");
    let kb: u64 = text
        .lines()
        .find_map(|l| l.strip_prefix("MemAvailable:"))
        .and_then(|v| v.split_whitespace().next()?.parse().ok())
        .expect("MemAvailable");
    kb / 1024
}

#[test]
fn runs_that_fill_the_machine_end_with_their_phase() {
    // Between the checks before the assembly and the factorization the need
    // is not predicted: a run that leaves less free memory than the reserve
    // ends with exit 4 naming the phase, not by the system's signal 9.
    // Here a reserve 600 MB under what is free now, and a run that needs
    // GBs (the 262,701-node block, MUMPS' factorization).
    let reserve = (available_mb() - 600).to_string();
    let (over, dir) = run(
        "reserve-run",
        2,
        None,
        300,
        &[
            "-options_file",
            "options/block3d",
            "-mesh_generate",
            "block3d",
            "-mesh_h",
            "0.02",
            "-ubr_memory_reserve",
            &reserve,
        ],
    );
    over.refused(
        "a run over the reserve",
        4,
        &[
            "error: out of memory: the free memory of this machine fell to",
            &format!("below the {reserve} MB a run keeps free (-ubr_memory_reserve)"),
            "while assembling and factorizing (788103 unknowns), rank 0 holding",
            "use more machines or a coarser mesh",
        ],
    );
    assert!(!dir.join("contact.csv").exists(), "nothing written");
    let _ = std::fs::remove_dir_all(&dir);
    // A machine with less free than the reserve at the start: refused at
    // once, on every rank count.
    for ranks in [1, 2] {
        let (start, dir) = run(
            "reserve-start",
            ranks,
            None,
            60,
            &[
                "-options_file",
                "options/hertz",
                "-ubr_memory_reserve",
                "1e9",
            ],
        );
        start.refused(
            "a reserve over the machine",
            4,
            &[
                "MB free (free memory and swap), less than the 1000000000 MB a run keeps free (-ubr_memory_reserve)",
            ],
        );
        assert!(start.seconds < 20.0, "took {:.1} s", start.seconds);
        assert!(!dir.join("contact.csv").exists(), "nothing written");
        let _ = std::fs::remove_dir_all(&dir);
    }
    // 0 turns the watch off; a negative size is bad input.
    let run = mpirun(
        1,
        &["-options_file", "options/hertz", "-ubr_memory_reserve", "0"],
    );
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    let run = mpirun(
        2,
        &[
            "-options_file",
            "options/hertz",
            "-ubr_memory_reserve",
            "-5",
        ],
    );
    run.refused(
        "-ubr_memory_reserve -5",
        2,
        &["-ubr_memory_reserve", "0 or more"],
    );
}

#[test]
fn mumps_out_of_memory_writes_the_report() {
    // MUMPS' own memory cap (ICNTL(23), MB per rank) far below what the
    // factorization needs: INFOG(1) = -19 on every rank, after the
    // assembly. Exit 4, and the report and CSV as for a run that did not
    // converge.
    let (run, dir) = run(
        "oom-mumps",
        2,
        None,
        120,
        &[
            "-options_file",
            "options/block3d",
            "-mesh",
            "meshes/block3d_2357.msh",
            "-mat_mumps_icntl_23",
            "5",
        ],
    );
    assert_eq!(run.status, Some(4), "stderr:\n{}", run.stderr);
    let rep = failed_report(&run, &dir, 262);
    let failure = rep.failure.as_deref().unwrap();
    assert!(
        failure.starts_with("error: out of memory: MUMPS factorization needs"),
        "{failure}"
    );
    assert!(failure.contains("ICNTL(23)"), "{failure}");
    // Nothing ran: no iteration, no estimate, no r choice.
    assert_eq!(rep.iterations, 0.0);
    assert_eq!(rep.linear_solves, 0.0);
    assert!(rep.lambda_error_estimate.is_nan(), "{rep:?}");
    assert!(rep.criterion.is_nan(), "{rep:?}");
    assert!(rep.r_estimate.is_nan(), "{rep:?}");
    assert_eq!(rep.r_source, "auto");
    assert_eq!(rep.contact_force, 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_r_far_outside_the_range_is_named_and_the_report_written() {
    // r = 1e-30 on the floating Hertz body (contact alone holds it along
    // n): K + r B^T W B is singular to round-off, and the dense Cholesky
    // factorization of its Schur complement (one rank) fails. Before: no
    // report, and a message that did not name r.
    let (run, dir) = run(
        "tiny-r",
        1,
        None,
        120,
        &["-options_file", "options/hertz", "-ubr_r", "1e-30"],
    );
    assert_eq!(run.status, Some(3), "stderr:\n{}", run.stderr);
    let rep = failed_report(&run, &dir, 69);
    let failure = rep.failure.as_deref().unwrap();
    for part in [
        "Schur complement",
        "r = 1e-30 (-ubr_r)",
        "far outside the range",
        "-ubr_r auto",
    ] {
        assert!(failure.contains(part), "'{part}' not in: {failure}");
    }
    assert_eq!(rep.iterations, 0.0);
    // (serde_json's default parsing may be one ulp off.)
    assert!((rep.r / 1e-30 - 1.0).abs() < 1e-12, "{rep:?}");
    assert_eq!(rep.r_source, "option");
    assert!(rep.lambda_error_estimate.is_nan(), "{rep:?}");
    // The summary is printed, saying so.
    assert!(run.stdout.contains("NOT converged"), "{}", run.stdout);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_diverged_linear_solve_writes_the_report() {
    // Unpreconditioned CG capped at 5 iterations: the first solve (of the
    // r choice) reports DIVERGED_ITS on every rank.
    let (run, dir) = run(
        "ksp-diverged",
        2,
        None,
        120,
        &[
            "-options_file",
            "options/hertz",
            "-ksp_type",
            "cg",
            "-pc_type",
            "none",
            "-ksp_max_it",
            "5",
        ],
    );
    assert_eq!(run.status, Some(3), "stderr:\n{}", run.stderr);
    let rep = failed_report(&run, &dir, 69);
    let failure = rep.failure.as_deref().unwrap();
    assert!(failure.contains("DIVERGED_ITS"), "{failure}");
    assert_eq!(rep.iterations, 0.0);
    assert!(rep.lambda_error_estimate.is_nan(), "{rep:?}");
    assert!(rep.r_estimate.is_nan(), "{rep:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Loads that overflow double precision (a traction of 1e160 against E =
/// 2000: the first solve's energy norms are infinite) end with exit 3 and a
/// message that names the cause (the units), not the bare "non-finite
/// iterate" it printed before; the report is written, on 1 and 2 ranks.
#[test]
fn overflowing_loads_name_the_units() {
    for ranks in [1, 2] {
        let (run, dir) = run(
            "overflow",
            ranks,
            None,
            120,
            &[
                "-options_file",
                "options/hertz",
                "-mesh",
                "meshes/hertz_442.msh",
                "-traction_top",
                "0,-1e160",
            ],
        );
        assert_eq!(run.status, Some(3), "stderr:\n{}", run.stderr);
        let rep = report(&dir.join("report.json"));
        let failure = rep.failure.as_deref().unwrap_or_default();
        assert!(
            failure.contains("non-finite iterate at iteration 1")
                && failure.contains("express the problem in other units"),
            "{ranks} ranks: {failure}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// Tiny matrix entries (E = 1e-20, the loads alike): MUMPS replaced tiny
/// pivots while computing the Schur complement of the condensed solves
/// (INFOG(25) = 505 on block3d_739), whatever its controls, and the Schur
/// complement came out wrong: the run ended "not converged, the body is
/// not held" (exit 3). The run now says so and uses full solves: the
/// contact stresses are the E = 1e6 run's times 1e-26, on 1 and 2 ranks.
#[test]
fn tiny_young_modulus_falls_back_to_full_solves() {
    let args = |e: &'static str| {
        vec![
            "-options_file",
            "options/block3d",
            "-E",
            e,
            "-ubr_lambda_rtol",
            "1e-8",
        ]
    };
    let (_, _, reference) = solve_rows("e1e6", 1, &args("1e6"));
    for ranks in [1, 2] {
        let (run, report, rows) = solve_rows("e1e-20", ranks, &args("1e-20"));
        assert!(report.converged, "{}", run.context());
        let warned = run.stderr_with("tiny pivots (INFOG(25))");
        assert_eq!(warned.len(), 1, "{}", run.context());
        let scaled: Vec<Row> = rows
            .into_iter()
            .map(|mut r| {
                r.lambda_n *= 1e26;
                r
            })
            .collect();
        let gap = max_pressure_gap(&scaled, &reference);
        assert!(gap < 1e-6, "{ranks} ranks: {gap:.2e} from the E = 1e6 run");
    }
}

/// A very soft body held by the contact alone (E = 0.2 under Hertz's
/// load: its first iterate already moves ten times its size) is solved,
/// with the warning that its elements invert; it was called "moves without
/// bound" (exit 3). Its contact stresses match a run at a tight tolerance
/// within the estimate, on 1 and 2 ranks. A Tresca bound too small for the
/// tangential load (nothing else holds the body along the plane) is
/// refused before the solve, the sliding named (exit 2; it ended with exit
/// 3 after Anderson's drift and the plain iteration's stall).
#[test]
fn a_very_soft_body_is_solved_and_a_sliding_one_named() {
    let args = |tol: &'static str| {
        vec![
            "-options_file",
            "options/hertz",
            "-E",
            "0.2",
            "-ubr_lambda_rtol",
            tol,
        ]
    };
    let (_, _, tight) = solve_rows("soft-tight", 1, &args("1e-10"));
    for ranks in [1, 2] {
        let (run, report, rows) = solve_rows("soft", ranks, &args("1e-3"));
        assert!(report.converged, "{}", run.context());
        assert_eq!(
            run.stderr_with("elements invert").len(),
            1,
            "{}",
            run.context()
        );
        let gap = max_pressure_gap(&rows, &tight);
        assert!(gap < 1e-3, "{ranks} ranks: {gap:.2e} from the tight run");
    }
    let tresca = ["-friction", "tresca", "-tresca_bound", "0.1"];
    let run = mpirun(2, &hertz_sideways_held_y(&tresca));
    run.refused(
        "a Tresca bound too small",
        2,
        &[
            "the tangential load 2.4000e2 exceeds what the Tresca bound can hold",
            "friction cannot hold the body",
        ],
    );
}
