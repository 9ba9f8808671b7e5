//! Anderson acceleration of UBR (`-ubr_anderson M`): at a tight tolerance it
//! reaches the pressures of the plain iteration in far fewer iterations, on
//! any rank count, with and without friction; bad memories are bad input.
mod common;
use common::*;

/// The recommended memory.
const M: &str = "10";

#[test]
fn hertz_pressures_match_plain_in_half_the_iterations() {
    let mesh = "meshes/hertz_1692.msh";
    let (_, plain, _) = solve_rows("aa_plain", 1, &hertz_args(mesh, &["-ubr_rtol", "1e-10"]));
    assert!(plain.converged);
    assert_eq!(plain.anderson_memory, 0.0);
    let plain_its = plain.iterations;
    // The pressures are compared with plain UBR-C converged further (1e-12):
    // at 1e-10 the plain iteration, contracting by 0.99 per step, is itself
    // still 5e-7 (max abs diff / max pressure) from its limit, Anderson 2e-8.
    let (_, tight, plain_rows) = solve_rows(
        "aa_plain_tight",
        1,
        &hertz_args(mesh, &["-ubr_rtol", "1e-12"]),
    );
    assert!(tight.converged);
    for ranks in [1, 2] {
        let (run, r, rows) = solve_rows(
            &format!("aa_{ranks}"),
            ranks,
            &hertz_aa_args(
                mesh,
                &[
                    "-ubr_stop",
                    "accuracy",
                    "-ubr_lambda_rtol",
                    "1e-8",
                    "-ubr_anderson",
                    M,
                ],
            ),
        );
        assert!(r.converged);
        assert_eq!(r.anderson_memory, M.parse::<f64>().unwrap());
        assert!(run.stdout.contains("Anderson"), "{}", run.stdout);
        let its = r.iterations;
        assert!(
            its <= 0.5 * plain_its,
            "-n {ranks}: {its} Anderson iterations vs {plain_its} plain"
        );
        // The accuracy test's guarantee: within 1e-8 of the converged pressures.
        let gap = max_pressure_gap(&rows, &plain_rows);
        assert!(gap <= 1e-8, "-n {ranks}: pressures differ by {gap:.3e}");
        println!("-n {ranks}: {its} iterations (plain {plain_its}), pressure gap {gap:.2e}");
    }
}

#[test]
fn coulomb_pressures_match_plain() {
    let tight = ["-ubr_rtol", "1e-10", "-ubr_fp_rtol", "1e-9"];
    let args = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut v = vec!["-options_file", "options/hertz-coulomb-paper"];
        if extra.first() == Some(&"-ubr_anderson") {
            // Anderson takes rho = r: the paper's r and test, without its rho.
            v = vec![
                "-options_file",
                "options/hertz-coulomb",
                "-ubr_r",
                "580",
                "-ubr_stop",
                "paper",
            ];
        }
        v.extend_from_slice(&tight);
        v.extend_from_slice(extra);
        v
    };
    let (_, plain, plain_rows) = solve_rows("aa_cf_plain", 1, &args(&[]));
    let (_, r, rows) = solve_rows("aa_cf", 2, &args(&["-ubr_anderson", M]));
    assert!(plain.converged);
    assert!(r.converged);
    let gap = max_pressure_gap(&rows, &plain_rows);
    assert!(gap <= 1e-7, "pressures differ by {gap:.3e}");
    let (its, plain_its) = (r.iterations, plain.iterations);
    assert!(
        its < plain_its,
        "{its} Anderson iterations vs {plain_its} plain"
    );
    println!("CF-FP: {its} Tresca iterations (plain {plain_its}), pressure gap {gap:.2e}");
}

/// The plain iteration at a tight target, where its residual ends at
/// round-off: the accuracy test keeps the contraction it measured on the way
/// down. Each case ended with exit 3 before, and now meets its target
/// against an Anderson run 100x tighter:
/// - the Tresca bound's frictionless solve (100x tighter) at 1e-9: its
///   estimate was infinite, the ratios of its round-off residual 1 or more;
/// - plain UBR-C at 1e-11, the same;
/// - a Coulomb load history at 1e-10: a Tresca solve started warm at
///   CF-FP's fixed point, its residual at round-off from its first
///   iteration, had no contraction of its own (it takes the last measured);
/// - CG + GAMG at 1e-9 on one rank: the inexact solves make ratios above 1
///   while the residual falls by e every 50 iterations (their geometric
///   mean is the rate), and the second load step starts at round-off.
#[test]
fn the_plain_iteration_meets_tight_targets_at_round_off() {
    let hertz = ["-mesh", "meshes/hertz_1692.msh"];
    let tresca = [&hertz[..], &["-tresca_bound", "frictionless"]].concat();
    let coulomb = [
        &hertz[..],
        &[
            "-friction",
            "coulomb",
            "-friction_coefficient",
            "0.1",
            "-load_steps",
            "3",
        ],
    ]
    .concat();
    let block = [
        "-mesh",
        "meshes/block3d_extruded_1674.msh",
        "-friction",
        "tresca",
        "-friction_coefficient",
        "0.8",
        "-tresca_bound",
        "frictionless",
        "-load_steps",
        "2",
    ];
    let gamg = ["-ksp_type", "cg", "-pc_type", "gamg"];
    for (file, scene, plain, tol) in [
        ("options/hertz-tresca", &tresca[..], &[][..], 1e-9),
        ("options/hertz", &hertz[..], &[][..], 1e-11),
        ("options/hertz", &coulomb[..], &[][..], 1e-10),
        ("options/block3d", &block[..], &gamg[..], 1e-9),
    ] {
        let tight = format!("{:e}", tol * 1e-2);
        let mut a = vec!["-options_file", file];
        a.extend_from_slice(scene);
        a.extend_from_slice(&["-ubr_lambda_rtol", &tight]);
        let (_, reference, ref_rows) = solve_rows("aa_roundoff_ref", 1, &a);
        assert!(reference.converged);
        let target = format!("{tol:e}");
        for ranks in [1, 2] {
            let mut a = vec!["-options_file", file];
            a.extend_from_slice(scene);
            a.extend_from_slice(plain);
            a.extend_from_slice(&["-ubr_anderson", "0", "-ubr_lambda_rtol", &target]);
            let (run, r, rows) = solve_rows(&format!("aa_roundoff_{ranks}"), ranks, &a);
            assert!(r.converged, "{a:?} -n {ranks}: {}", run.context());
            assert_eq!(r.anderson_memory, 0.0);
            let gap = max_stress_gap(&rows, &ref_rows);
            assert!(
                gap <= tol,
                "{a:?} -n {ranks}: stresses {gap:.2e} from the reference"
            );
            println!(
                "{file} {plain:?} -n {ranks}: {} iterations, error {gap:.2e}, target {tol:e}",
                r.iterations
            );
        }
    }
}

#[test]
fn bad_memory_is_bad_input() {
    for bad in ["-1", "2.5", "ten", "1000"] {
        let run = mpirun(
            2,
            &hertz_args("meshes/hertz_442.msh", &["-ubr_anderson", bad]),
        );
        run.refused(&format!("-ubr_anderson {bad}"), 2, &["-ubr_anderson"]);
    }
}
