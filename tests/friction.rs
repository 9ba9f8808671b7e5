//! Friction on the paper's Hertz problem (section 7.1.2): UBR-TF with the
//! Tresca bound nu_f x Hertz pressure, and CF-FP for Coulomb friction.
mod common;
use common::*;

const MESHES: [&str; 5] = [
    "meshes/hertz_442.msh",
    "meshes/hertz_1692.msh",
    "meshes/hertz_6619.msh",
    "meshes/hertz_26181.msh",
    "meshes/hertz_37473.msh",
];

fn scene<'a>(file: &'a str, mesh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["-options_file", file, "-mesh", mesh];
    v.extend_from_slice(extra);
    v
}

/// Table 3: UBR-TF takes 35-70 iterations on the five meshes (paper: 47-57).
#[test]
fn table3_tresca_iterations() {
    for mesh in MESHES {
        let (run, r, rows) =
            solve_rows("table3", 2, &scene("options/hertz-tresca-paper", mesh, &[]));
        let its = num(&r, "iterations");
        assert!(
            (35.0..=70.0).contains(&its),
            "{mesh}: {its}\n{}",
            run.stdout
        );
        assert!((num(&r, "contact_force") - 800.0).abs() <= 1e-6 * 800.0);
        assert!(
            rows.iter().any(|x| x.status == "stick") && rows.iter().any(|x| x.status == "slip")
        );
        println!("{mesh}: UBR-TF {its} iterations");
    }
}

/// Table 4: CF-FP takes 5-15 fixed-point and 80-140 Tresca iterations in all
/// (paper: 8-13 and 106-122).
#[test]
fn table4_coulomb_iterations() {
    for mesh in MESHES {
        let (run, r, _) = solve_rows(
            "table4",
            2,
            &scene("options/hertz-coulomb-paper", mesh, &[]),
        );
        let fp = num(&r, "fixed_point_iterations");
        let inner = num(&r, "iterations");
        assert!(
            (5.0..=15.0).contains(&fp),
            "{mesh}: {fp} fixed-point iterations\n{}",
            run.stdout
        );
        assert!(
            (80.0..=140.0).contains(&inner),
            "{mesh}: {inner} inner iterations\n{}",
            run.stdout
        );
        assert!((num(&r, "contact_force") - 800.0).abs() <= 1e-6 * 800.0);
        println!("{mesh}: CF-FP {fp} / {inner}");
    }
}

fn check_friction_conditions(r: &serde_json::Value, what: &str) {
    let excess = num(r, "max_friction_excess");
    let smax = num(r, "max_bound");
    assert!(
        excess <= 1e-8 * smax,
        "{what}: |lambda_t| exceeds s by {excess} (max s {smax})"
    );
    let stick = num(r, "max_stick_slip");
    let slip = num(r, "max_slip");
    assert!(
        stick <= 1e-8 * slip,
        "{what}: slip {stick} at sticking nodes (max slip {slip})"
    );
    let cos = num(r, "min_slip_alignment");
    assert!(
        cos >= 1.0 - 1e-6,
        "{what}: u_t and lambda_t not aligned at a sliding node (cos {cos})"
    );
    let eq = num(r, "equilibrium_residual_rel");
    assert!(eq <= 1e-10, "{what}: equilibrium {eq}");
    let pmax = num(r, "peak_pressure");
    assert!(num(r, "min_lambda_n") >= -1e-10 * pmax);
    assert!(num(r, "max_penetration") <= 1e-8 * num(r, "max_abs_gap"));
}

/// At a tight tolerance the Tresca and Coulomb laws hold at every candidate.
#[test]
fn friction_laws_at_tight_tolerance() {
    let (_, r, rows) = solve_rows(
        "tresca_tight",
        2,
        &scene(
            "options/hertz-tresca-paper",
            "meshes/hertz_1692.msh",
            &["-ubr_rtol", "1e-12"],
        ),
    );
    check_friction_conditions(&r, "Tresca");
    assert!(rows.iter().filter(|x| x.status == "slip").count() >= 2);
    let (_, r, _) = solve_rows(
        "coulomb_tight",
        2,
        &scene(
            "options/hertz-coulomb-paper",
            "meshes/hertz_1692.msh",
            &["-ubr_rtol", "1e-12", "-ubr_fp_rtol", "1e-10"],
        ),
    );
    check_friction_conditions(&r, "Coulomb");
}

/// nu_f = 0 (and a zero Tresca bound) reproduce the frictionless pressures.
#[test]
fn zero_friction_is_frictionless() {
    let tight = ["-ubr_rtol", "1e-13"];
    let (_, _, free) = solve_rows(
        "free",
        1,
        &scene("options/hertz-paper", "meshes/hertz_1692.msh", &tight),
    );
    let pmax = free.iter().map(|x| x.lambda_n).fold(0.0, f64::max);
    let variants: [(&str, Vec<&str>); 2] = [
        (
            "options/hertz-coulomb-paper",
            vec!["-friction_coefficient", "0"],
        ),
        ("options/hertz-tresca-paper", vec!["-tresca_bound", "0"]),
    ];
    for (file, extra) in variants {
        let mut e = extra.clone();
        e.extend_from_slice(&tight);
        let (_, _, rows) = solve_rows("zero", 1, &scene(file, "meshes/hertz_1692.msh", &e));
        assert_eq!(rows.len(), free.len());
        for (a, b) in free.iter().zip(&rows) {
            assert_eq!(a.node, b.node);
            assert!(
                (a.lambda_n - b.lambda_n).abs() <= 1e-8 * pmax,
                "{file}: node {}: {} vs {}",
                a.node,
                a.lambda_n,
                b.lambda_n
            );
            assert!(b.lambda_t.iter().all(|t| t.abs() <= 1e-8 * pmax));
        }
    }
}

/// A very large friction coefficient sticks every contact node.
#[test]
fn large_friction_sticks_everything() {
    let (_, r, rows) = solve_rows(
        "stick",
        2,
        &scene(
            "options/hertz-coulomb-paper",
            "meshes/hertz_1692.msh",
            &["-friction_coefficient", "100"],
        ),
    );
    let contact = rows.iter().filter(|x| x.status != "open").count();
    assert!(contact > 5);
    assert!(
        rows.iter().all(|x| x.status != "slip"),
        "a contact node slips"
    );
    assert_eq!(num(&r, "slip_nodes"), 0.0);
}

/// Coulomb friction raises the peak pressure and narrows the contact zone
/// (paper section 7.1.2; an independent implementation: 384 vs 365, 69 vs 72 nodes).
#[test]
fn coulomb_peak_higher_and_zone_narrower() {
    let mesh = "meshes/hertz_37473.msh";
    let (_, free, _) = solve_rows("free37", 2, &scene("options/hertz-paper", mesh, &[]));
    let (_, coul, _) = solve_rows(
        "coul37",
        2,
        &scene("options/hertz-coulomb-paper", mesh, &[]),
    );
    let (pf, pc) = (num(&free, "peak_pressure"), num(&coul, "peak_pressure"));
    let (nf, nc) = (num(&free, "contact_active"), num(&coul, "contact_active"));
    println!("peak {pc} vs {pf}, contact nodes {nc} vs {nf}");
    assert!(pc > pf + 10.0, "peak {pc} vs frictionless {pf}");
    assert!(nc < nf, "contact nodes {nc} vs frictionless {nf}");
}

/// CF-FP factorizes once for the whole fixed point.
#[test]
fn coulomb_one_numeric_factorization() {
    let run = mpirun(
        2,
        &scene(
            "options/hertz-coulomb-paper",
            "meshes/hertz_1692.msh",
            &["-log_view"],
        ),
    );
    assert_eq!(run.status, Some(0), "{}", run.stderr);
    let line = run
        .stdout
        .lines()
        .find(|l| l.starts_with("MUMPSFactorNum"))
        .expect("MUMPSFactorNum");
    let count: usize = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    assert_eq!(count, 1, "{line}");
}

/// -n 1, 2, 3 agree at a tight tolerance, on lambda_n and lambda_t.
#[test]
fn friction_rank_count_independence() {
    let args = scene(
        "options/hertz-coulomb-paper",
        "meshes/hertz_1692.msh",
        &["-ubr_rtol", "1e-12", "-ubr_fp_rtol", "1e-10"],
    );
    let runs: Vec<Vec<Row>> = [1, 2, 3]
        .iter()
        .map(|&n| solve_rows("franks", n, &args).2)
        .collect();
    let pmax = runs[0].iter().map(|x| x.lambda_n).fold(0.0, f64::max);
    for other in &runs[1..] {
        assert_eq!(other.len(), runs[0].len());
        for (a, b) in runs[0].iter().zip(other) {
            assert_eq!(a.node, b.node);
            assert!(
                (a.lambda_n - b.lambda_n).abs() <= 1e-8 * pmax,
                "node {}",
                a.node
            );
            for c in 0..3 {
                assert!(
                    (a.lambda_t[c] - b.lambda_t[c]).abs() <= 1e-8 * pmax,
                    "node {}",
                    a.node
                );
            }
        }
    }
}
