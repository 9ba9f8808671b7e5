//! The numerical stability contract on a fast subset of bench/stability's matrix.
//!
//! Every run either converges with finite numbers and the discrete optimality
//! conditions satisfied, or ends with exit status 3 (2 for bad input) and a
//! message on stderr saying what did not converge and how far it got. Never NaN
//! or Inf in the report, the contact CSV or the printed text, never a hang
//! (killed after 120 s), never a crash (any other exit status).
//!
//! Optimality of a converged run, with S the stress scale (the larger of the
//! peak pressure and the scene's nominal stress) and U the displacement scale
//! (the larger of max |u_n| and the scene's nominal displacement: 0.4 =
//! traction x R / E for hertz, 0.2 = the top displacement for block3d), at
//! KKT_TOL = 100 x the default -ubr_rtol: equilibrium residual <= 1e-8;
//! min lambda_n >= -KKT_TOL S;
//! max(u_n - g) <= KKT_TOL U; at every candidate
//! min(lambda_n^+ / S, (g - u_n)^+ / U) <= KKT_TOL; the friction bound exceeded
//! by at most KKT_TOL S; lambda_t along u_t at slip nodes (Coulomb: the
//! law checked from the CSV, |lambda_t| <= nu_f lambda_n, |lambda_t| = nu_f
//! lambda_n where the node slips). The total contact force is not evidence:
//! it equals the load at every iterate (the stresses are -sigma(u^k)).
mod common;
use common::*;

use std::sync::OnceLock;

const KKT_TOL: f64 = 1e-3;
const EQ_TOL: f64 = 1e-8;
const TIMEOUT_S: u64 = 120;
const H442: &str = "meshes/hertz_442.msh";
const B198: &str = "meshes/block3d_198.msh";
/// Hertz scenes: the traction on the top edge.
const HERTZ_S: f64 = 100.0;
const HERTZ_U: f64 = 0.4;
/// block3d: E x (top displacement / height), and the top displacement.
const BLOCK_S: f64 = 0.2e6;
const BLOCK_U: f64 = 0.2;
/// One run (`status` None: killed by the timeout) and the scene's nominal
/// displacement.
struct Case {
    out: Outputs,
    u0: f64,
}

impl std::ops::Deref for Case {
    type Target = Outputs;
    fn deref(&self) -> &Outputs {
        &self.out
    }
}

/// Runs `mpirun -n ranks ubr-petsc args -report -contact_output` under a
/// timeout, from the repository root.
fn run(name: &str, ranks: usize, args: &[&str]) -> Case {
    let out = run_outputs(&format!("stability-{name}"), ranks, args, Some(TIMEOUT_S));
    let u0 = if args.iter().any(|a| a.contains("block3d")) {
        BLOCK_U
    } else {
        HERTZ_U
    };
    Case { out, u0 }
}

fn hertz<'a>(options: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["-options_file", options, "-mesh", H442];
    v.extend_from_slice(extra);
    v
}

fn block<'a>(options: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["-options_file", options, "-mesh", B198];
    v.extend_from_slice(extra);
    v
}

/// options/hertz-paper without -dirichlet_symmetry, with this traction on the top
/// edge: nothing holds the body in x.
fn hertz_free_x(traction: &str) -> Vec<&str> {
    let paper = [
        "-ubr_r",
        "220",
        "-ubr_anderson",
        "0",
        "-ubr_stop",
        "paper",
        "-ubr_rho",
        "330",
    ];
    common::hertz_free_x(H442, traction, &paper)
}

/// A word "nan", "inf" or "infinity" (any case) in the text.
fn nonfinite_word(text: &str) -> Option<String> {
    text.split(|c: char| !c.is_ascii_alphabetic())
        .find(|w| matches!(w.to_ascii_lowercase().as_str(), "nan" | "inf" | "infinity"))
        .map(str::to_string)
}

/// What holds whatever the outcome: no hang, no crash, no NaN/Inf, an exit 3
/// that says what did not converge and how far it got, an exit 2 with an error line.
fn assert_never_broken(c: &Case) {
    assert!(
        c.status.is_some(),
        "hang: killed after {TIMEOUT_S} s: {}",
        c.context()
    );
    let s = c.status.unwrap();
    assert!(matches!(s, 0 | 2 | 3), "crash: {}", c.context());
    assert!(!c.run.stderr.contains("panicked"), "panic: {}", c.context());
    for (what, text) in [
        ("report", c.report_text.as_deref().unwrap_or("")),
        ("contact CSV", c.csv_text.as_deref().unwrap_or("")),
        ("stdout", &c.run.stdout),
        ("stderr", &c.run.stderr),
    ] {
        if let Some(w) = nonfinite_word(text) {
            panic!("'{w}' in the {what}: {}", c.context());
        }
    }
    if s == 3 {
        let msg = c.run.stderr.to_ascii_lowercase();
        let line = msg
            .lines()
            .find(|l| l.contains("not converged:"))
            .unwrap_or_else(|| {
                panic!("exit 3 without 'not converged:' on stderr: {}", c.context())
            });
        let after_n = line
            .split("after ")
            .skip(1)
            .any(|t| t.starts_with(|ch: char| ch.is_ascii_digit()));
        assert!(
            after_n && (line.contains("change") || line.contains("residual")),
            "exit 3 without how far it got: {}",
            c.context()
        );
        assert!(!c.report().converged, "{}", c.context());
    }
    if s == 2 {
        assert!(
            c.run.stderr.contains("error:"),
            "exit 2 without an error line: {}",
            c.context()
        );
    }
    if s == 0 {
        assert!(c.report().converged, "{}", c.context());
    }
}

/// The discrete optimality conditions of a converged run: equilibrium
/// from the report, Signorini's conditions and Coulomb's law from the CSV.
fn assert_optimal(c: &Case, s0: f64, eq_tol: f64) {
    let r = c.report();
    let rows = c.rows();
    let sc = Scales::of(&rows, s0.max(r.peak_pressure), c.u0);
    let ctx = c.context();
    let eq = r.equilibrium_residual_rel;
    assert!(eq <= eq_tol, "equilibrium residual {eq:e}: {ctx}");
    check_signorini(&rows, sc, KKT_TOL)
        .unwrap_or_else(|e| panic!("{e} (S {}, U {}): {ctx}", sc.s, sc.u));
    match r.friction.as_str() {
        "coulomb" => {
            let nu_f = r.friction_coefficient;
            // Sticking nodes may still creep at this tolerance: the law's
            // bound and the slip nodes at it only (slip_tol 1).
            check_friction(&rows, sc, KKT_TOL, 1.0, |x| nu_f * x.lambda_n.max(0.0))
                .unwrap_or_else(|e| panic!("Coulomb: {e}: {ctx}"));
        }
        "tresca" => {
            let exc = r.max_friction_excess;
            assert!(
                exc <= KKT_TOL * sc.s,
                "Tresca bound exceeded by {exc:e}: {ctx}"
            );
        }
        _ => {}
    }
    for x in rows.iter().filter(|x| x.status == "slip") {
        let (lt, ut) = (norm(&x.lambda_t), norm(&x.ut));
        if lt > KKT_TOL * sc.s && ut > 1e-9 * sc.u {
            let dot: f64 = x.lambda_t.iter().zip(&x.ut).map(|(a, b)| a * b).sum();
            assert!(
                dot >= 0.99 * lt * ut,
                "slip node {}: lambda_t {:?} not along u_t {:?}: {ctx}",
                x.node,
                x.lambda_t,
                x.ut
            );
        }
    }
}

fn assert_converged(c: &Case, s0: f64) {
    assert_never_broken(c);
    assert_eq!(c.status, Some(0), "no converged answer: {}", c.context());
    assert_optimal(c, s0, EQ_TOL);
}

/// Exit 2 (an ill-posed scene is bad input) with one error line that
/// carries `what`.
fn assert_ill_posed(c: &Case, what: &str) {
    assert_never_broken(c);
    let line = c.run.refused(&c.name, 2, &[what]);
    assert!(line.starts_with("error: ill-posed scene: "), "{line}");
}

/// A tightly converged run of a Hertz scene at its own r: the discrete solution.
fn tight(options: &'static str) -> &'static Case {
    static C: OnceLock<Case> = OnceLock::new();
    static TF: OnceLock<Case> = OnceLock::new();
    static CF: OnceLock<Case> = OnceLock::new();
    let cell = match options {
        "options/hertz-paper" => &C,
        "options/hertz-tresca-paper" => &TF,
        _ => &CF,
    };
    cell.get_or_init(|| {
        let c = run(
            &format!("tight-{}", options.trim_start_matches("options/")),
            1,
            &hertz(options, &["-ubr_rtol", "1e-10", "-ubr_fp_rtol", "1e-10"]),
        );
        assert_converged(&c, HERTZ_S);
        c
    })
}

/// r = rho = r_over_e x E on hertz_442, at most `max_it` iterations: exit
/// 0, optimal, and the contact stresses within `tol` of the peak pressure
/// from the discrete solution (the paper's stopping test bounds the change
/// of an iterate, not its error: measured 1.0% (UBR-C) and 1.5% (UBR-TF)
/// at r = 0.01 E, 4.2e-4 or less at r = E and above).
///
/// A wrong answer fails it: `UBR_TEST_PERTURB=stability-hertz-paper-r1=1.01
/// cargo test --release --test stability r_ubr_c_equal_e` ends "r = 1 E:
/// stresses 9.93e-3 of the peak from the converged solution" (tolerance 2e-3).
fn r_case(options: &'static str, r_over_e: f64, max_it: &str, tol: f64) {
    let r = format!("{}", 2000.0 * r_over_e);
    let c = run(
        &format!("{}-r{r_over_e}", options.trim_start_matches("options/")),
        1,
        &hertz(
            options,
            &["-ubr_r", &r, "-ubr_rho", &r, "-ubr_max_it", max_it],
        ),
    );
    assert_converged(&c, HERTZ_S);
    let dev = max_stress_gap(&c.rows(), &tight(options).rows());
    assert!(
        dev <= tol,
        "r = {r_over_e} E: stresses {dev:.2e} of the peak from the converged solution: {}",
        c.context()
    );
}

#[test]
fn r_ubr_c_small() {
    r_case("options/hertz-paper", 1e-2, "20000", 0.02);
}

#[test]
fn r_ubr_c_equal_e() {
    r_case("options/hertz-paper", 1.0, "20000", 2e-3);
}

/// Large r: the iteration crawls (31087 iterations at r = 100 E, 1 s), so
/// a relative-change test could stop early (the build of 14:29 stopped at
/// 11935 iterations with open nodes carrying 1.1% of the peak pressure, the
/// pressures 7% of the peak from the discrete solution). Converged must
/// mean optimal and near the discrete solution.
#[test]
fn r_ubr_c_large() {
    r_case("options/hertz-paper", 100.0, "40000", 2e-3);
}

/// Too large an r: r = 1000 E does not converge in any number of iterations
/// a test can afford (still 5.7e-5 from the paper's 1e-5 when it stalls,
/// after 7858 iterations, with -ubr_max_it 400000 too): the documented
/// failure, exit 3 with the stall named and r placed against r0, for this
/// r only.
#[test]
fn r_ubr_c_huge() {
    let c = run(
        "hertz-paper-r1000",
        1,
        &hertz(
            "options/hertz-paper",
            &["-ubr_r", "2e6", "-ubr_rho", "2e6", "-ubr_max_it", "20000"],
        ),
    );
    assert_never_broken(&c);
    assert_eq!(c.status, Some(3), "{}", c.context());
    let line = c
        .run
        .stderr
        .lines()
        .find(|l| l.contains("not converged:"))
        .unwrap();
    assert!(
        line.contains("stalled") && line.contains("far outside the range"),
        "{}",
        c.context()
    );
}

#[test]
fn r_ubr_tf_small() {
    r_case("options/hertz-tresca-paper", 1e-2, "20000", 0.02);
}

/// r = 10 E (the build of 14:29 stopped at 2091 iterations with open nodes at
/// 1.1e-3 of the peak pressure, just over the tolerance; bench/stability runs 100 E).
#[test]
fn r_ubr_tf_large() {
    r_case("options/hertz-tresca-paper", 10.0, "20000", 2e-3);
}

#[test]
fn r_cf_fp_equal_e() {
    r_case("options/hertz-coulomb-paper", 1.0, "20000", 2e-3);
}

/// CF-FP at r = 10 E (bench/stability runs 100 E and 1000 E: 3e4 and 3e5
/// Tresca iterations, too long here).
#[test]
fn r_cf_fp_large() {
    r_case("options/hertz-coulomb-paper", 10.0, "20000", 2e-3);
}

/// Near incompressibility P1 locks (Hertz error 2% at nu = 0.3, 21% at 0.499 on
/// 442 nodes) but the answer is still a converged, optimal discrete solution.
#[test]
fn poisson_ratio_near_one_half() {
    for nu in ["0", "0.49", "0.499"] {
        let c = run(
            &format!("nu{nu}"),
            1,
            &hertz("options/hertz-paper", &["-nu", nu]),
        );
        assert_converged(&c, HERTZ_S);
        let err = c.report().pressure_error_rel;
        assert!(err.is_finite() && err < 1.0, "nu {nu}: Hertz error {err}");
        println!("nu = {nu}: Hertz pressure error {:.2}%", 100.0 * err);
    }
}

/// E, the traction, r, rho and the Hertz force scaled together by 1e-6 and 1e6:
/// the same iterations and the same lambda/E and displacements.
#[test]
fn unit_invariance() {
    for (options, r, rho) in [
        ("options/hertz-paper", 220.0, 330.0),
        ("options/hertz-coulomb-paper", 580.0, 870.0),
    ] {
        let scaled = |f: f64| {
            let v: Vec<String> = [2000.0 * f, r * f, rho * f, -100.0 * f, 1600.0 * f]
                .iter()
                .map(|x| format!("{x:e}"))
                .collect();
            let a = [
                "-E",
                &v[0],
                "-ubr_r",
                &v[1],
                "-ubr_rho",
                &v[2],
                "-traction_top",
                &format!("0,{}", v[3]),
                "-reference_force",
                &v[4],
            ]
            .iter()
            .map(|s| s.to_string())
            .collect::<Vec<String>>();
            let args: Vec<&str> = a.iter().map(String::as_str).collect();
            let c = run(&format!("units{f:e}"), 1, &hertz(options, &args));
            assert_converged(&c, HERTZ_S * f);
            c
        };
        let base = scaled(1.0);
        let (rb, b) = (base.report(), base.rows());
        let lmax = b.iter().map(|x| x.lambda_n.abs()).fold(0.0, f64::max);
        let umax = b
            .iter()
            .map(|x| x.un.abs().max(norm(&x.ut)))
            .fold(0.0, f64::max);
        for f in [1e-6, 1e6] {
            let c = scaled(f);
            let r = c.report();
            assert_eq!(
                r.iterations,
                rb.iterations,
                "{options} x{f:e}: {}",
                c.context()
            );
            assert_eq!(
                r.fixed_point_iterations, rb.fixed_point_iterations,
                "{options} x{f:e}"
            );
            for (x, y) in c.rows().iter().zip(&b) {
                assert!(
                    (x.lambda_n / f - y.lambda_n).abs() <= 1e-8 * lmax,
                    "{options} x{f:e} node {}: lambda_n",
                    x.node
                );
                for k in 0..3 {
                    assert!(
                        (x.lambda_t[k] / f - y.lambda_t[k]).abs() <= 1e-8 * lmax,
                        "{options} x{f:e} node {}: lambda_t",
                        x.node
                    );
                    assert!(
                        (x.ut[k] - y.ut[k]).abs() <= 1e-8 * umax,
                        "{options} x{f:e} node {}: u_t",
                        x.node
                    );
                }
                assert!(
                    (x.un - y.un).abs() <= 1e-8 * umax,
                    "{options} x{f:e} node {}: u_n",
                    x.node
                );
            }
        }
    }
}

/// Obstacle far away: the Hertz body (free vertically) translates 100 and
/// touches; without load it stays put and touches nothing; the block, held by
/// its top, touches nothing (lambda = 0 up to the tolerance).
#[test]
fn no_contact() {
    let c = run(
        "far",
        1,
        &hertz("options/hertz-paper", &["-obstacle_point", "0,-100"]),
    );
    assert_converged(&c, HERTZ_S);
    let c = run(
        "far-noload",
        1,
        &hertz(
            "options/hertz-paper",
            &["-obstacle_point", "0,-100", "-traction_top", "0,0"],
        ),
    );
    assert_converged(&c, HERTZ_S);
    assert_eq!(c.report().contact_active, 0.0);
    let c = run(
        "block-far",
        2,
        &block("options/block3d-paper", &["-obstacle_center", "-0.3,0,-10"]),
    );
    assert_converged(&c, BLOCK_S);
    assert_eq!(c.report().contact_active, 0.0, "{}", c.context());
    let c = run(
        "block-far-cf",
        1,
        &block(
            "options/block3d-coulomb-paper",
            &["-obstacle_center", "-0.3,0,-10"],
        ),
    );
    assert_converged(&c, BLOCK_S);
}

/// The block with Tresca friction (bound from a frictionless solve) and the
/// ball far away: nothing touches and nothing loads the body but its
/// prescribed top displacement, a rigid translation. The answer is exact; the
/// equilibrium residual (round-off, 8e-10) must be measured against a scale
/// that is not itself round-off (the applied load norm is 2e-10 here: today's
/// relative residual 3.66).
#[test]
fn no_contact_block_tresca() {
    let c = run(
        "block-far-tf",
        1,
        &block(
            "options/block3d-tresca-paper",
            &["-obstacle_center", "-0.3,0,-10"],
        ),
    );
    assert_converged(&c, BLOCK_S);
    assert_eq!(c.report().contact_active, 0.0, "{}", c.context());
}

/// A flat punch: the block's bottom face on the plane z = -0.5 (gaps 0) or
/// z = -0.45 (every candidate penetrates by 0.05): every candidate in contact.
#[test]
fn contact_everywhere() {
    for (name, options, z) in [
        ("punch", "options/block3d-paper", "0,0,-0.5"),
        ("punch-cf", "options/block3d-coulomb-paper", "0,0,-0.5"),
        ("punch-pen", "options/block3d-paper", "0,0,-0.45"),
    ] {
        let c = run(
            name,
            2,
            &block(options, &["-obstacle", "plane", "-obstacle_point", z]),
        );
        assert_converged(&c, BLOCK_S);
        let r = c.report();
        assert_eq!(r.contact_active, r.contact_nodes, "{}", c.context());
    }
}

/// Negative gaps (the plane 0.05 above the lowest node).
#[test]
fn initial_penetration() {
    for options in ["options/hertz-paper", "options/hertz-coulomb-paper"] {
        let c = run("pen", 1, &hertz(options, &["-obstacle_point", "0,0.05"]));
        assert_converged(&c, HERTZ_S);
    }
}

/// One contact candidate (a small ball under node (0,0), under the block's
/// corner), on two ranks: one of them owns no candidate.
#[test]
fn single_contact_node() {
    let c = run(
        "single2d",
        2,
        &hertz(
            "options/hertz-paper",
            &[
                "-contact_normal",
                "fixed",
                "-obstacle",
                "ball",
                "-obstacle_center",
                "0,-0.1",
                "-obstacle_radius",
                "0.1",
            ],
        ),
    );
    assert_converged(&c, HERTZ_S);
    assert_eq!(c.report().contact_nodes, 1.0);
    let c = run(
        "single3d",
        2,
        &block(
            "options/block3d-coulomb-paper",
            &[
                "-contact_normal",
                "fixed",
                "-obstacle",
                "ball",
                "-obstacle_center",
                "0.5,1,-0.6",
                "-obstacle_radius",
                "0.1",
            ],
        ),
    );
    assert_converged(&c, BLOCK_S);
    assert_eq!(c.report().contact_nodes, 1.0);
}

#[test]
fn friction_coefficients() {
    for options in ["options/hertz-tresca-paper", "options/hertz-coulomb-paper"] {
        for nu_f in ["0", "10"] {
            let c = run(
                &format!("nuf{nu_f}"),
                1,
                &hertz(options, &["-friction_coefficient", nu_f]),
            );
            assert_converged(&c, HERTZ_S);
        }
    }
}

/// Flat (sliver) elements of quality 5e-4 (2D, 3D) and 5e-10 (2D: condition
/// number ~1e9, equilibrium to 1e-5 only).
#[test]
fn sliver_meshes() {
    let c = run(
        "sliver",
        1,
        &[
            "-options_file",
            "options/hertz-paper",
            "-mesh",
            "meshes/stability_sliver.msh",
        ],
    );
    assert_converged(&c, HERTZ_S);
    let c = run(
        "sliver3d",
        1,
        &[
            "-options_file",
            "options/block3d-paper",
            "-mesh",
            "meshes/stability_sliver3d.msh",
        ],
    );
    assert_converged(&c, BLOCK_S);
    let c = run(
        "sliver-roundoff",
        1,
        &[
            "-options_file",
            "options/hertz-paper",
            "-mesh",
            "meshes/stability_sliver_roundoff.msh",
        ],
    );
    assert_never_broken(&c);
    assert_eq!(c.status, Some(0), "{}", c.context());
    assert_optimal(&c, HERTZ_S, 1e-5);
}

/// meshes/stability_inverted.msh: triangle 390 (nodes 330 331 189) is listed
/// clockwise; meshes/stability_inverted3d.msh: tetrahedron 383 (nodes 183 191
/// 195 185) negatively oriented. A bad-input error naming the element's nodes.
#[test]
fn inverted_element_is_bad_input() {
    for (mesh, options, nodes) in [
        (
            "meshes/stability_inverted.msh",
            "options/hertz-paper",
            "330 331 189",
        ),
        (
            "meshes/stability_inverted3d.msh",
            "options/block3d-paper",
            "183 191 195 185",
        ),
    ] {
        let c = run("inverted", 2, &["-options_file", options, "-mesh", mesh]);
        assert_never_broken(&c);
        assert_eq!(c.status, Some(2), "{}", c.context());
        assert!(c.run.stderr.contains("inverted"), "{}", c.context());
        assert!(
            c.run.stderr.contains(&format!("(nodes {nodes})")),
            "{}",
            c.context()
        );
    }
}

/// The error names the inverted element by its tag in the mesh file (390),
/// not by its position among the mesh's cells.
#[test]
fn inverted_element_named_by_its_file_tag() {
    let c = run(
        "inverted-tag",
        1,
        &[
            "-options_file",
            "options/hertz-paper",
            "-mesh",
            "meshes/stability_inverted.msh",
        ],
    );
    assert_never_broken(&c);
    assert!(
        c.run.stderr.contains(" 390 ")
            || c.run.stderr.contains(" 390,")
            || c.run.stderr.contains(" 390:"),
        "the message does not name element 390: {}",
        c.context()
    );
}

/// The Hertz body pulled away from the obstacle: nothing holds it, no
/// equilibrium exists. Refused before the solve as ill-posed (exit 2, the
/// contract's bad input) with the reason, not a long run that ends in a
/// generic "stopped after N iterations".
#[test]
fn free_body_pulled_away_is_a_clear_error() {
    let c = run(
        "pull",
        1,
        &hertz(
            "options/hertz-paper",
            &["-traction_top", "0,100", "-ubr_max_it", "2000"],
        ),
    );
    assert_ill_posed(&c, "the loads pull the body off the obstacle");
}

/// The same with -ubr_rtol 1e-3: the multiplier of the drifting body grows like
/// k, its relative change decays like 1/k and meets the test at k = 1000: today
/// an exit 0 with a tensile "contact" force of -800.
#[test]
fn free_body_pulled_away_never_converges() {
    let c = run(
        "pull-rtol",
        1,
        &hertz(
            "options/hertz-paper",
            &["-traction_top", "0,100", "-ubr_rtol", "1e-3"],
        ),
    );
    assert_never_broken(&c);
    assert_ne!(
        c.status,
        Some(0),
        "a drifting body reported converged: {}",
        c.context()
    );
}

/// CF-FP on the drifting body, -ubr_rtol 1e-3: its Tresca solves meet their
/// tolerance the same way, s stays 0, and the fixed point reports converged
/// (with the default tolerances too, after 1e5 Tresca iterations and 22 s).
#[test]
fn free_body_pulled_away_never_converges_cf_fp() {
    let c = run(
        "pull-cf",
        1,
        &hertz(
            "options/hertz-coulomb-paper",
            &["-traction_top", "0,100", "-ubr_rtol", "1e-3"],
        ),
    );
    assert_never_broken(&c);
    assert_ne!(
        c.status,
        Some(0),
        "a drifting body reported converged: {}",
        c.context()
    );
}

/// A sideways load on a body that nothing holds sideways (frictionless, no
/// Dirichlet data in x): no equilibrium exists (it was once an exit 0 with an
/// equilibrium residual of 25%). Refused as ill-posed, the free direction named.
#[test]
fn free_body_loaded_sideways_is_a_clear_error() {
    let c = run("side", 1, &hertz_free_x("10,-100"));
    assert_ill_posed(&c, "free to translate along x");
}

/// Nothing holds the body in x, even though the load is vertical: the
/// operator is singular (today's issue 12: an arbitrary sideways shift on
/// two ranks, a zero pivot on one). An ill-posed scene, named, exit 2, on
/// both rank counts.
#[test]
fn free_tangential_translation() {
    for ranks in [1, 2] {
        let c = run("freex", ranks, &hertz_free_x("0,-100"));
        assert_never_broken(&c);
        assert_eq!(c.status, Some(2), "{}", c.context());
        assert!(
            c.run.stderr.contains("free to translate along x"),
            "{}",
            c.context()
        );
    }
}
