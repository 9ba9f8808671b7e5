//! Ill-posed scenes are diagnosed from the operator, never answered: a rigid
//! motion that nothing restrains ends every rank count with exit 2 and one
//! line naming the motion, before any solve; the same bodies held by
//! friction, or by a Dirichlet condition, converge.
mod common;
use common::*;

/// The paper's Hertz quarter without its symmetry condition, pressed
/// straight down: nothing holds it along x (frictionless contact along
/// n = -y cannot).
fn hertz_free_x<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    common::hertz_free_x("meshes/hertz_442.msh", "0,-100", extra)
}

/// A generated block pressed by a traction on its top onto a ball: no
/// Dirichlet condition at all.
fn block_on_ball<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "-mesh_generate",
        "block3d",
        "-mesh_h",
        "0.25",
        "-E",
        "1e6",
        "-nu",
        "0.3",
        "-traction_top",
        "0,0,-1e4",
        "-contact_surface",
        "bottom",
        "-contact_direction",
        "0,0,-1",
        "-obstacle",
        "ball",
        "-obstacle_center",
        "-0.1,0.2,-1",
        "-obstacle_radius",
        "0.5",
        "-contact_normal",
        "fixed",
    ];
    v.extend_from_slice(extra);
    v
}

fn expect_free(name: &str, ranks: usize, args: &[&str], words: &[&str]) {
    let run = mpirun(ranks, args);
    run.refused(&format!("{name} on {ranks} ranks"), 2, words);
    assert!(
        !run.stdout.contains("iterations"),
        "{name}: decided before any iteration:\n{}",
        run.stdout
    );
}

#[test]
fn frictionless_body_free_along_x_is_named() {
    for ranks in [1, 2] {
        for extra in [&[][..], &["-ubr_anderson", "0", "-ubr_stop", "paper"][..]] {
            expect_free(
                "hertz without ux=0",
                ranks,
                &hertz_free_x(extra),
                &[
                    "the body is free to translate along x",
                    "frictionless contact cannot hold it",
                    "add a Dirichlet condition or friction",
                ],
            );
        }
    }
    // The comparators meet the same singular operator.
    expect_free(
        "hertz without ux=0, SSN-C",
        1,
        &hertz_free_x(&["-contact_algorithm", "ssn"]),
        &["free to translate along x"],
    );
}

#[test]
fn traction_only_block_on_a_ball_is_named() {
    for ranks in [1, 2] {
        expect_free(
            "block on a ball",
            ranks,
            &block_on_ball(&[]),
            &[
                "free to translate along x, to translate along y and to rotate about z",
                "frictionless contact cannot hold it",
            ],
        );
    }
}

/// With Coulomb friction the same scenes are well posed: friction holds the
/// tangential motions, and the vertical loads need no friction force.
#[test]
fn friction_holds_the_same_bodies() {
    for (name, args, ranks) in [
        (
            "hertz free x, Coulomb",
            hertz_free_x(&["-friction", "coulomb", "-friction_coefficient", "0.3"]),
            2,
        ),
        (
            "block on a ball, Coulomb",
            block_on_ball(&["-friction", "coulomb", "-friction_coefficient", "0.3"]),
            1,
        ),
    ] {
        let (run, rep, rows) = solve_rows(name, ranks, &args);
        assert!(rep.converged, "{name}: {}", run.stdout);
        let load = if name.starts_with("hertz") {
            800.0
        } else {
            2e4
        };
        // Signorini's conditions and Coulomb's bound from the CSV, at the
        // accuracy stop's 1e-3 (the total contact force equals the load at
        // any iterate: no evidence).
        let sc = Scales::of(&rows, 0.0, 0.0);
        check_signorini(&rows, sc, 1e-3).unwrap_or_else(|e| panic!("{name}: {e}"));
        check_friction(&rows, sc, 1e-3, 1.0, |x| 0.3 * x.lambda_n.max(0.0))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        // No tangential load: no net friction force.
        for &t in &rep.tangential_force {
            assert!(t.abs() <= 1e-6 * load, "{name}: tangential force {t}");
        }
        assert!(!rows.is_empty());
    }
}

/// Friction alone holds the Hertz body against a tangential load (a third
/// of nu_f times the normal one): a frictionless first Tresca solve has no
/// solution (the body slid away: 10,000 iterations and exit 3 before CF-FP
/// started from sticking); it converges, and the friction force balances
/// the tangential load. (At half of nu_f times the normal load a later
/// Tresca bound of the plain fixed-point step still cannot hold the body.)
#[test]
fn friction_holds_a_body_under_a_tangential_load() {
    let args = hertz_free_x(&["-friction", "coulomb", "-friction_coefficient", "0.3"]);
    let args: Vec<&str> = args
        .iter()
        .map(|&a| if a == "0,-100" { "10,-100" } else { a })
        .collect();
    let (run, rep, _) = solve_rows("hertz tangential load, Coulomb", 2, &args);
    assert!(rep.converged, "{}", run.stdout);
    let tx = rep.tangential_force[0];
    // The friction force on the obstacle: the tangential load.
    assert!(
        (tx - 80.0).abs() <= 1e-6 * 800.0,
        "tangential force {tx}: {}",
        run.stdout
    );
    assert!((rep.contact_force - 800.0).abs() <= 1e-6 * 800.0);
}

/// The same body under Tresca friction with its default bound, nu_f times
/// the pressure of a frictionless solve, and a tangential load: that solve
/// has no solution, and the scene is refused before the factorization,
/// naming the bound and the motion (it ran 130 iterations and ended "moves
/// without bound ... raise the friction" with exit 3); the same for
/// Coulomb started from that bound, and for a history, naming the step.
/// Pressed straight down, the frictionless solve has an answer (its x
/// position arbitrary), and the run converges; so does a given bound.
#[test]
fn a_frictionless_bound_is_refused_where_friction_alone_holds() {
    let sideways =
        |extra: &[&'static str]| common::hertz_free_x("meshes/hertz_442.msh", "10,-100", extra);
    let tresca = ["-friction", "tresca", "-friction_coefficient", "0.3"];
    for (bound, words) in [
        (&[][..], "the default bound of -friction tresca"),
        (
            &["-tresca_bound", "frictionless"][..],
            "-tresca_bound frictionless is",
        ),
    ] {
        for ranks in [1, 2] {
            let mut extra = tresca.to_vec();
            extra.extend_from_slice(bound);
            expect_free(
                "hertz free x, Tresca, pushed sideways",
                ranks,
                &sideways(&extra),
                &[
                    words,
                    "without friction the body is free to translate along x, and the loads move it so",
                    "-tresca_bound VALUE",
                ],
            );
        }
    }
    let mut extra = tresca.to_vec();
    extra.extend_from_slice(&["-load_steps", "2"]);
    expect_free(
        "hertz free x, Tresca history",
        2,
        &sideways(&extra),
        &["load step 1/2", "the default bound of -friction tresca"],
    );
    let coulomb = ["-friction", "coulomb", "-friction_coefficient", "0.3"];
    let mut extra = coulomb.to_vec();
    extra.extend_from_slice(&["-tresca_bound", "frictionless"]);
    expect_free(
        "hertz free x, Coulomb from a frictionless bound",
        2,
        &sideways(&extra),
        &[
            "starting bound of -friction coulomb",
            "leave -tresca_bound out",
        ],
    );
    for (name, args) in [
        ("pressed down, default bound", hertz_free_x(&tresca)),
        (
            "pushed sideways, bound 10",
            sideways(&["-friction", "tresca", "-tresca_bound", "10"]),
        ),
    ] {
        let (run, rep, _) = solve_rows(name, 2, &args);
        assert!(rep.converged, "{name}: {}", run.stdout);
        assert!((rep.contact_force - 800.0).abs() <= 1e-6 * 800.0);
    }
}

/// Two disconnected parts, one clamped, the other resting on the obstacle
/// under a traction: the free part is named by where it is.
#[test]
fn disconnected_free_part_is_named() {
    let dir = scratch("two-parts");
    let mesh = dir.join("two.msh");
    std::fs::write(
        &mesh,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n1 1 \"fixed\"\n1 2 \"contact\"\n1 3 \"top\"\n2 4 \"body\"\n$EndPhysicalNames\n\
$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 0 0\n6 3 0 0\n7 3 1 0\n8 2 1 0\n$EndNodes\n\
$Elements\n7\n1 1 2 1 1 1 2\n2 1 2 2 2 5 6\n3 1 2 3 3 7 8\n4 2 2 4 4 1 2 3\n5 2 2 4 4 1 3 4\n6 2 2 4 4 5 6 7\n7 2 2 4 4 5 7 8\n$EndElements\n",
    )
    .unwrap();
    let m = mesh.to_str().unwrap();
    let args = [
        "-mesh",
        m,
        "-E",
        "100",
        "-nu",
        "0.3",
        "-dirichlet_fixed",
        "ux=0,uy=0",
        "-traction_top",
        "0,-1",
        "-contact_surface",
        "contact",
        "-contact_direction",
        "0,-1",
        "-obstacle",
        "plane",
        "-obstacle_point",
        "0,0",
    ];
    for ranks in [1, 2] {
        expect_free(
            "two parts",
            ranks,
            &args,
            &[
                "around (2.5000, 0.5000) (4 nodes, one of 2 disconnected parts) is free to translate along x",
            ],
        );
    }
    // Held along x too: well posed.
    let mut held = args.to_vec();
    held.extend_from_slice(&["-dirichlet_top", "ux=0"]);
    let (run, rep, _) = solve_rows("two parts held", 2, &held);
    assert!(rep.converged, "{}", run.stdout);
}

/// A body held along n by contact alone and pulled away from the obstacle
/// has no equilibrium: a clear error (exit 2) instead of 10000 iterations.
#[test]
fn body_pulled_off_the_obstacle_is_named() {
    let run = mpirun(
        1,
        &[
            "-options_file",
            "options/hertz",
            "-mesh",
            "meshes/hertz_442.msh",
            "-traction_top",
            "0,100",
        ],
    );
    assert_eq!(run.status, Some(2), "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stderr
            .contains("the loads pull the body off the obstacle"),
        "{}",
        run.stderr
    );
}

/// Nothing touches (the half-ball lowered 0.5 below the block, which a
/// prescribed displacement moves down by 0.2): the answer is no contact,
/// and the optimality checks measure the open nodes' stresses, the
/// iteration's leftover `r (u_n - phi)`, against the pressure scale of the
/// accuracy stop (made by the prescribed displacement). They were measured
/// against themselves: `min_lambda_n_rel` -0.96 and `complementarity_rel`
/// 2.6 on a converged run whose stresses were 1e-7 of that scale.
#[test]
fn nothing_touching_is_measured_against_the_loads() {
    for (ranks, extra) in [
        (1, &[][..]),
        (2, &[][..]),
        (1, &["-mesh_h", "2"][..]),
        (
            2,
            &["-friction", "coulomb", "-friction_coefficient", "0.3"][..],
        ),
        (
            1,
            &["-ubr_condense_max", "0", "-ubr_lambda_rtol", "1e-6"][..],
        ),
    ] {
        let mut args = vec![
            "-options_file",
            "options/block3d",
            "-mesh_generate",
            "block3d",
            "-mesh_h",
            "0.25",
            "-obstacle_center",
            "-0.3,0,-1.5",
        ];
        args.extend_from_slice(extra);
        let name = format!("nothing_touching_{ranks}_{}", extra.join("_"));
        let (run, rep, rows) = solve_rows(&name, ranks, &args);
        let what = format!("{ranks} ranks {extra:?}: {}", run.stdout);
        assert!(rep.converged, "{what}");
        assert_eq!(rep.contact_active, 0.0, "{what}");
        assert!(rows.iter().all(|r| r.status == "open"), "{what}");
        let tol: f64 = extra
            .iter()
            .position(|&a| a == "-ubr_lambda_rtol")
            .map_or(1e-3, |k| extra[k + 1].parse().unwrap());
        assert!(
            rep.min_lambda_n_rel > -tol && rep.min_lambda_n_rel <= 0.0,
            "min_lambda_n_rel {}: {what}",
            rep.min_lambda_n_rel
        );
        assert!(
            rep.complementarity_rel < tol,
            "complementarity_rel {}: {what}",
            rep.complementarity_rel
        );
    }
}

/// A Tresca bound given before the solve, against the loads, where the
/// contact alone holds the quarter along x and y (a plane obstacle): a
/// sideways load above the bound's total `sum s w` (s = 5 over the 69
/// candidates: 62.83 against 80) is refused before the factorization on
/// every rank count, naming the total and the option that raises it (it
/// ran 801 iterations to exit 3); so is a bound from Hertz' pressure
/// (nu_f 0.3: 243.3 against 320), naming the coefficient; a load that
/// pulls the body off (97 iterations to exit 3 before); and the step of a
/// history that exceeds it (-load_steps 2: 40, then 80). Within the total
/// the run goes on and converges.
#[test]
fn a_tresca_bound_is_measured_against_the_loads() {
    let scene = |load: &'static str, extra: &[&'static str]| {
        let mut v = vec!["-friction", "tresca"];
        v.extend_from_slice(extra);
        common::hertz_free_x("meshes/hertz_1692.msh", load, &v)
    };
    let total =
        "exceeds what the Tresca bound can hold, the sum of s w over the 69 contact candidates";
    for ranks in [1, 2, 3] {
        let run = mpirun(ranks, &scene("10,-100", &["-tresca_bound", "5"]));
        run.refused(
            &format!("bound 5, {ranks} ranks"),
            2,
            &[
                "tangential load 8.0000e1",
                total,
                "= 6.283",
                "raise -tresca_bound",
            ],
        );
    }
    let hertz = [
        "-tresca_bound",
        "hertz",
        "-friction_coefficient",
        "0.3",
        "-reference",
        "hertz",
        "-reference_force",
        "1600",
        "-reference_radius",
        "8",
    ];
    let run = mpirun(2, &scene("40,-100", &hertz));
    run.refused(
        "Hertz bound",
        2,
        &[
            "tangential load 3.2000e2",
            total,
            "raise -friction_coefficient",
        ],
    );
    let run = mpirun(2, &scene("0,100", &["-tresca_bound", "5"]));
    run.refused(
        "pulled off",
        2,
        &["the loads pull the body off the obstacle"],
    );
    let run = mpirun(
        2,
        &scene("10,-100", &["-tresca_bound", "5", "-load_steps", "2"]),
    );
    run.refused(
        "history",
        2,
        &["load step 2/2", "tangential load 8.0000e1", total],
    );
    let (run, rep, _) = solve_rows("within", 2, &scene("5,-100", &["-tresca_bound", "10"]));
    assert!(rep.converged, "{}", run.context());
    assert!(
        (rep.tangential_force[0] - 40.0).abs() <= 1e-6 * 800.0,
        "{}",
        run.stdout
    );
}
