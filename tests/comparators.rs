//! The comparators of the paper's section 7 and of PETSc: SSN-C (semi-smooth
//! Newton, refactorized every iteration) and SNES VI (vinewtonrsls).
mod common;
use common::report as report_of;
use common::*;

const MESHES: [&str; 5] = [
    "meshes/hertz_442.msh",
    "meshes/hertz_1692.msh",
    "meshes/hertz_6619.msh",
    "meshes/hertz_26181.msh",
    "meshes/hertz_37473.msh",
];

fn hertz<'a>(mesh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["-options_file", "options/hertz-paper", "-mesh", mesh];
    v.extend_from_slice(extra);
    v
}

/// Table 1: SSN-C (r = 1e3 E, u^0 = (0,-0.01)) takes 5-12 iterations (paper:
/// 7-10), and its answer satisfies Signorini's conditions from the CSV (to
/// 1e-3: the penalized problem's penetration ~ lambda_n / r).
#[test]
#[ignore = "slow"]
fn ssn_iterations_on_five_meshes() {
    for mesh in MESHES {
        let (run, r, rows) = solve_rows(
            "ssn",
            2,
            &hertz(
                mesh,
                &["-contact_algorithm", "ssn", "-ssn_initial_shift", "0,-0.01"],
            ),
        );
        let its = r.iterations;
        assert!((5.0..=12.0).contains(&its), "{mesh}: {its}\n{}", run.stdout);
        check_signorini(&rows, Scales::of(&rows, 0.0, 0.0), 1e-3)
            .unwrap_or_else(|e| panic!("{mesh}: {e}"));
    }
}

/// SSN-C factorizes every iteration but analyses the pattern once.
#[test]
fn ssn_refactorizes_with_one_symbolic_analysis() {
    let run = mpirun(
        2,
        &hertz(
            "meshes/hertz_1692.msh",
            &[
                "-contact_algorithm",
                "ssn",
                "-ssn_initial_shift",
                "0,-0.01",
                "-log_view",
            ],
        ),
    );
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    let count = |event: &str| -> usize {
        let line = run
            .stdout
            .lines()
            .find(|l| l.starts_with(event))
            .unwrap_or_else(|| panic!("no {event}"));
        line.split_whitespace().nth(1).unwrap().parse().unwrap()
    };
    assert_eq!(count("MatCholFctrSym"), 1);
    assert!(count("MatCholFctrNum") >= 5);
}

/// At convergence SSN-C (with a large r: it solves the penalized problem) and
/// UBR-C at a tight tolerance give the same pressures, and SNES VI matches both.
#[test]
fn ssn_snesvi_and_ubr_agree() {
    let mesh = "meshes/hertz_1692.msh";
    let (_, _, ubr) = solve_rows("ubr_tight", 2, &hertz(mesh, &["-ubr_rtol", "1e-12"]));
    let (_, _, ssn) = solve_rows(
        "ssn_big_r",
        2,
        &hertz(
            mesh,
            &[
                "-contact_algorithm",
                "ssn",
                "-ssn_initial_shift",
                "0,-0.01",
                "-ssn_r",
                "2e12",
            ],
        ),
    );
    let (_, r, vi) = solve_rows(
        "snesvi",
        2,
        &hertz(
            mesh,
            &[
                "-contact_algorithm",
                "snesvi",
                "-ssn_initial_shift",
                "0,-0.01",
            ],
        ),
    );
    assert!(r.max_penetration <= 1e-12);
    let d1 = max_pressure_gap(&ubr, &ssn);
    let d2 = max_pressure_gap(&ssn, &vi);
    let d3 = max_pressure_gap(&ubr, &vi);
    assert!(d1 <= 1e-6, "UBR-C vs SSN-C {d1}");
    assert!(d2 <= 1e-6, "SSN-C vs SNES VI {d2}");
    assert!(d3 <= 1e-6, "UBR-C vs SNES VI {d3}");
}

/// A floating body that no active node holds: SSN-C says so instead of returning garbage.
#[test]
fn ssn_without_initial_contact_says_why() {
    let run = mpirun(
        2,
        &hertz("meshes/hertz_442.msh", &["-contact_algorithm", "ssn"]),
    );
    assert_eq!(run.status, Some(3), "{}", run.stderr);
    assert!(run.stderr.contains("-ssn_initial_shift"), "{}", run.stderr);
}

/// SNES VI stopped by its cap: the summary and the report give the Newton
/// iterations it ran and its last iterate (they said 0 iterations and the
/// zero state), exit 3 with PETSc's reason; SNES VI refuses two elastic
/// bodies by name (it blamed the contact normal).
#[test]
fn snesvi_stopped_says_how_far_it_went() {
    let dir = scratch("snesvi_stopped");
    let report = dir.join("r.json");
    let report = report.to_str().unwrap();
    let run = mpirun(
        2,
        &hertz(
            "meshes/hertz_442.msh",
            &[
                "-contact_algorithm",
                "snesvi",
                "-snes_max_it",
                "2",
                "-report",
                report,
            ],
        ),
    );
    assert_eq!(run.status, Some(3), "{}", run.stderr);
    assert!(
        run.stderr.contains(
            "not converged: SNES VI did not converge after 2 Newton iterations: DIVERGED_MAX_IT"
        ),
        "{}",
        run.stderr
    );
    assert!(
        run.stdout
            .contains("2 Newton iterations of PETSc's vinewtonrsls"),
        "{}",
        run.stdout
    );
    let rep = report_of(std::path::Path::new(report));
    assert_eq!(rep.iterations, 2.0);
    assert!(!rep.converged);
    let pair = mpirun(
        1,
        &[
            "-options_file",
            "options/hertz",
            "-contact_algorithm",
            "snesvi",
            "-contact_pair",
            "contact,top",
        ],
    );
    pair.refused(
        "snesvi with a contact pair",
        2,
        &["-contact_algorithm snesvi", "-contact_pair"],
    );
}

/// The same agreement in 3D, on the paper's block (held by its top face, so
/// SSN-C needs no initial shift): UBR-C at a tight tolerance, SSN-C with
/// r = 1e9 E (the penalized problem's distance to the exact one ~ 1/r), and
/// SNES VI with the bound u_z >= g along the contact direction -z.
#[test]
fn ssn_snesvi_and_ubr_agree_in_3d() {
    let block = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut v = vec![
            "-options_file",
            "options/block3d-paper",
            "-mesh",
            "meshes/block3d_739.msh",
        ];
        v.extend_from_slice(extra);
        v
    };
    let (_, r_ubr, ubr) = solve_rows("ubr3d_tight", 2, &block(&["-ubr_rtol", "1e-12"]));
    let (_, r_ssn, ssn) = solve_rows(
        "ssn3d_big_r",
        2,
        &block(&["-contact_algorithm", "ssn", "-ssn_r", "1e15"]),
    );
    let (_, r_vi, vi) = solve_rows("snesvi3d", 2, &block(&["-contact_algorithm", "snesvi"]));
    for r in [&r_ubr, &r_ssn, &r_vi] {
        assert_eq!(r.dimension, 3.0);
        assert!(r.equilibrium_residual_rel <= 1e-8);
    }
    let d1 = max_pressure_gap(&ubr, &ssn);
    let d2 = max_pressure_gap(&ssn, &vi);
    let d3 = max_pressure_gap(&ubr, &vi);
    assert!(d1 <= 1e-6, "3D UBR-C vs SSN-C {d1}");
    assert!(d2 <= 1e-6, "3D SSN-C vs SNES VI {d2}");
    assert!(d3 <= 1e-6, "3D UBR-C vs SNES VI {d3}");
}
