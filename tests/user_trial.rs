//! The findings of a new user's trial (issue 14), each as the scene that
//! showed it, on 2 ranks: unknown options named with a suggestion (item 2),
//! friction checks over the nodes in contact and scaled residuals (3),
//! warnings for set-ups that are probably wrong (4), progress lines (5),
//! messages (6), and the features users expected (7): body force and
//! gravity, pressure, reactions, several contact surfaces, one .vtu
//! readable by meshio, the contact plot's coordinate.
//!
//! Meshes are made at test time by Gmsh from the `.geo` texts below.
mod common;
use common::*;
use std::path::Path;
use std::process::Command;

/// A 2x1 block; its base split at x = 1 into `base_a` and `base_b`, and
/// whole as `base`; the cells' group is `body`.
const BLOCK: &str = r#"
h = 0.1;
Point(1) = {0, 0, 0, h}; Point(2) = {1, 0, 0, h}; Point(3) = {2, 0, 0, h};
Point(4) = {2, 1, 0, h}; Point(5) = {0, 1, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4, 5}; Plane Surface(1) = {1};
Physical Curve("base") = {1, 2}; Physical Curve("base_a") = {1}; Physical Curve("base_b") = {2};
Physical Curve("right") = {3}; Physical Curve("top") = {4}; Physical Curve("left") = {5};
Physical Surface("body") = {1};
"#;

/// A 1 x 4 column standing on its base.
const COLUMN: &str = r#"
h = 0.1;
Point(1) = {0, 0, 0, h}; Point(2) = {1, 0, 0, h}; Point(3) = {1, 4, 0, h}; Point(4) = {0, 4, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Curve("base") = {1}; Physical Curve("right") = {2}; Physical Curve("top") = {3}; Physical Curve("left") = {4};
Physical Surface("body") = {1};
"#;

/// A quarter of the ring 1 < r < 2 (symmetry edges `left`, `bottom`).
const RING: &str = r#"
h = 0.05;
Point(1) = {0, 0, 0, h}; Point(2) = {1, 0, 0, h}; Point(3) = {2, 0, 0, h}; Point(4) = {0, 2, 0, h}; Point(5) = {0, 1, 0, h};
Line(1) = {2, 3}; Circle(2) = {3, 1, 4}; Line(3) = {4, 5}; Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Curve("bottom") = {1}; Physical Curve("outer") = {2}; Physical Curve("left") = {3}; Physical Curve("inner") = {4};
Physical Surface("ring") = {1};
"#;

/// The block without physical groups.
const NO_GROUPS: &str = r#"
h = 0.2;
Point(1) = {0, 0, 0, h}; Point(2) = {2, 0, 0, h}; Point(3) = {2, 1, 0, h}; Point(4) = {0, 1, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
"#;

/// Meshes `geo` with Gmsh into `dir/name.msh`.
fn gmsh(dir: &Path, name: &str, geo: &str) -> String {
    let g = dir.join(format!("{name}.geo"));
    let m = dir.join(format!("{name}.msh"));
    std::fs::write(&g, geo).unwrap();
    let out = Command::new("gmsh")
        .args(["-2", "-format", "msh41", "-o"])
        .arg(&m)
        .arg(&g)
        .output()
        .expect("gmsh runs (apt-get install gmsh)");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    m.to_str().unwrap().to_string()
}

/// The column of `COLUMN` clamped at its base under gravity, its right side
/// a contact surface facing a plane it does not reach.
fn column<'a>(mesh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "-mesh",
        mesh,
        "-E",
        "1e4",
        "-nu",
        "0.3",
        "-dirichlet_base",
        "ux=0,uy=0",
        "-gravity",
        "0,-9.81",
        "-density",
        "2",
        "-contact_surface",
        "right",
        "-contact_direction",
        "1,0",
        "-obstacle",
        "plane",
        "-obstacle_point",
        "10,0",
    ];
    v.extend_from_slice(extra);
    v
}

/// The options of the block pressed on the plane y = 0 by its top edge.
fn block<'a>(mesh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "-mesh",
        mesh,
        "-E",
        "1000",
        "-nu",
        "0.3",
        "-contact_surface",
        "base",
        "-contact_direction",
        "0,-1",
        "-obstacle",
        "plane",
        "-obstacle_point",
        "0,0",
    ];
    v.extend_from_slice(extra);
    v
}

fn warnings(run: &Run) -> Vec<&str> {
    run.stderr
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .collect()
}

fn ok(run: &Run) {
    assert_eq!(
        run.status,
        Some(0),
        "stdout:\n{}\nstderr:\n{}",
        run.stdout,
        run.stderr
    );
}

/// The one error line of a bad-input run (exit status 2).
fn error_line(run: &Run) -> String {
    assert_eq!(run.status, Some(2), "{}\n{}", run.stdout, run.stderr);
    let lines = run.error_lines();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    lines[0].to_string()
}

fn hertz442(extra: &[&str]) -> Vec<String> {
    let mut v: Vec<String> = [
        "-options_file",
        "options/hertz",
        "-mesh",
        "meshes/hertz_442.msh",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    v.extend(extra.iter().map(|s| s.to_string()));
    v
}

fn run_hertz(extra: &[&str]) -> Run {
    let args = hertz442(extra);
    let a: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
    mpirun(2, &a)
}

// ----- item 2: unknown options -----

/// The trial's mistyped options are named once each with the closest known
/// name; the run goes on (exit 0). PETSc's own options are checked too.
#[test]
fn unknown_options_are_named_with_a_suggestion() {
    let run = run_hertz(&[
        "-ubr_rtoll",
        "1e-6",
        "-frictoin",
        "coulomb",
        "-ksp_tpye",
        "cg",
    ]);
    ok(&run);
    let w = warnings(&run);
    for (typed, meant) in [
        ("-ubr_rtoll", "-ubr_rtol"),
        ("-frictoin", "-friction"),
        ("-ksp_tpye", "-ksp_type"),
    ] {
        let line = format!("warning: option {typed} was not used; did you mean {meant}?");
        assert_eq!(
            w.iter().filter(|l| **l == line).count(),
            1,
            "{line}\n{}",
            run.stderr
        );
    }
    // A mistyped option that makes the run fail is named beside the error.
    let run = mpirun(
        2,
        &[
            "-mesh",
            "meshes/hertz_442.msh",
            "-E",
            "2000",
            "-nu",
            "0.3",
            "-dirichlet_symmetry",
            "ux=0",
            "-traction_top",
            "0,-100",
            "-contact_surfce",
            "contact",
            "-contact_direction",
            "0,-1",
            "-obstacle",
            "plane",
            "-obstacle_point",
            "0,0",
        ],
    );
    assert!(error_line(&run).contains("option -contact_surface is required"));
    assert_eq!(
        warnings(&run),
        ["warning: option -contact_surfce was not used; did you mean -contact_surface?"],
        "{}",
        run.stderr
    );
    // An option of the program that does not apply here says so.
    let run = run_hertz(&["-obstacle_radius", "5"]);
    ok(&run);
    assert!(
        warnings(&run).contains(
            &"warning: option -obstacle_radius was not used: the option it goes with is not given, or another overrides it (-help)"
        ),
        "{}",
        run.stderr
    );
    // A correct run, with PETSc's options read at the end, warns of nothing.
    let run = run_hertz(&["-log_view", "ascii:/dev/null", "-options_left", "0"]);
    ok(&run);
    assert!(!run.stderr.contains("was not used"), "{}", run.stderr);
}

// ----- item 3: diagnostics a user can trust -----

/// Friction checked at the nodes in contact only: on a block slid over a
/// cylinder (a few nodes touch, the others are open), the slip is aligned
/// with the traction (cos 1) and the traction within the bound (excess 0),
/// for Coulomb and for Tresca with the bound of a frictionless solve (whose
/// open nodes carry tractions: before, the summary said cos -1).
#[test]
fn friction_checks_are_one_and_zero_on_a_coulomb_block() {
    let dir = scratch("trial-friction");
    let mesh = gmsh(&dir, "block", BLOCK);
    let ball = [
        "-dirichlet_top",
        "ux=0.005,uy=-0.02",
        "-contact_surface",
        "base",
        "-contact_direction",
        "0,-1",
        "-obstacle",
        "ball",
        "-obstacle_center",
        "1,-5",
        "-obstacle_radius",
        "5",
        "-contact_normal",
        "fixed",
    ];
    for friction in [
        &["-friction", "coulomb", "-friction_coefficient", "0.6"][..],
        &["-friction", "tresca", "-friction_coefficient", "0.3"][..],
    ] {
        let mut args = vec!["-mesh", &mesh, "-E", "1000", "-nu", "0.3"];
        args.extend_from_slice(&ball);
        args.extend_from_slice(friction);
        let (run, r, _) = solve_rows("trial-friction-run", 2, &args);
        let what = friction[1];
        assert!(r.stick_nodes > 0.0 && r.slip_nodes > 0.0, "{what}");
        assert!(r.contact_active < r.contact_nodes, "{what}");
        assert!(
            r.min_slip_alignment >= 1.0 - 1e-12,
            "{what}: cos {}",
            r.min_slip_alignment
        );
        assert!(r.max_friction_excess_rel <= 1e-5, "{what}");
        // At the default tolerance on lambda (1e-3) the sticking nodes slip a little.
        assert!(r.max_stick_slip_rel <= 1e-3, "{what}");
        assert!(
            run.stdout
                .contains("min cos(u_t, lambda_t) at slip nodes 1.000000000000"),
            "{what}: {}",
            run.stdout
        );
        assert!(run.stdout.contains("at the"), "{}", run.stdout);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// When nothing touches, the checks are small numbers relative to the
/// scales the summary names, not raw residuals.
#[test]
fn residuals_are_scaled_when_nothing_touches() {
    let dir = scratch("trial-scaled");
    let mesh = gmsh(&dir, "column", COLUMN);
    let args = column(&mesh, &[]);
    let (run, r, _) = solve_rows("trial-scaled-run", 2, &args);
    assert_eq!(r.contact_active, 0.0);
    for (key, v) in [
        ("min_lambda_n_rel", r.min_lambda_n_rel),
        ("max_penetration_rel", r.max_penetration_rel),
        ("complementarity_rel", r.complementarity_rel),
    ] {
        assert!(v.abs() <= 1e-5, "{key} {v}");
    }
    assert!(
        run.stdout.contains("relative to the pressure scale"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout.contains("relative to the force scale"),
        "{}",
        run.stdout
    );
    let _ = std::fs::remove_dir_all(&dir);
}

// ----- item 4: warnings -----

/// Each set-up of the trial that ran to exit 0 without a word now warns,
/// one line each, and the run goes on.
#[test]
fn probably_wrong_set_ups_warn() {
    let dir = scratch("trial-warn");
    let mesh = gmsh(&dir, "block", BLOCK);
    let floating = |point| {
        [
            "-dirichlet_left",
            "ux=0",
            "-traction_top",
            "0,-5",
            "-obstacle_point",
            point,
        ]
    };
    let top = [
        "-dirichlet_left",
        "ux=0",
        "-traction_top",
        "0,-5",
        "-contact_surface",
        "top",
    ];
    let cases: [(&[&str], &[&str]); 7] = [
        // The contact direction pointing away from the plane obstacle: the
        // base faces away from it, and nothing touches.
        (
            &["-dirichlet_top", "ux=0,uy=-0.01", "-contact_direction", "0,1"],
            &[
                "contact surface 'base' faces away from the obstacle: on 100% of its area its outward normal points against the contact direction n = (0,1)",
                "no node is in contact, and the obstacle lies behind the body along the contact direction n",
            ],
        ),
        // The top named as the contact surface of a block on the floor: it
        // was moved down through the floor rigidly until its top touched,
        // without a word.
        (
            &top,
            &["contact surface 'top' faces away from the obstacle: on 100% of its area"],
        ),
        // A Dirichlet condition on half of the contact surface (on all of
        // it: bad input, `prescribed_contact_candidates_are_dropped`).
        (
            &["-dirichlet_top", "ux=0,uy=-0.01", "-dirichlet_base_a", "uy=0"],
            &["-dirichlet_base_a prescribes the displacement along n at 11 contact candidates of 'base': they are no candidates"],
        ),
        // A traction on a Dirichlet group.
        (
            &["-dirichlet_top", "ux=0,uy=-0.01", "-traction_top", "0,-5"],
            &["-traction_top acts on uy, which a Dirichlet condition prescribes at 21 of its 21 nodes"],
        ),
        // A push of 150% strain: the deformed shape inverts.
        (
            &["-dirichlet_top", "ux=0,uy=-1.5"],
            &["elements invert in the deformed shape x + u"],
        ),
        // 10% strain: beyond small deformations.
        (
            &["-dirichlet_top", "ux=0,uy=-0.1"],
            &["(above 5%): the model is linear elasticity, for small deformations"],
        ),
        // The plane 0.15 above the base (7.5% of the block's length): the
        // block starts deep inside the obstacle (it is lifted out rigidly,
        // without strain, and ran without a word).
        (
            &floating("0,0.15"),
            &["21 of 21 contact candidates start inside the obstacle (or behind their master surface), by up to 1.5000e-1, 8% of the mesh's largest extent 2.0000e0"],
        ),
    ];
    for (extra, expected) in cases {
        let run = mpirun(2, &block(&mesh, extra));
        ok(&run);
        let w = warnings(&run);
        assert_eq!(w.len(), expected.len(), "{extra:?}: {}", run.stderr);
        for (w, e) in w.iter().zip(expected) {
            assert!(w.contains(e), "{extra:?}: {w}");
        }
    }
    // The correct set-up warns of nothing, nor does a penetration of 4.5%
    // of the length (an interference fit is far below it).
    let run = mpirun(2, &block(&mesh, &["-dirichlet_top", "ux=0,uy=-0.01"]));
    ok(&run);
    assert!(warnings(&run).is_empty(), "{}", run.stderr);
    let run = mpirun(2, &block(&mesh, &floating("0,0.09")));
    ok(&run);
    assert!(warnings(&run).is_empty(), "{}", run.stderr);
    let _ = std::fs::remove_dir_all(&dir);
}

// ----- item 5: progress -----

/// A short run prints nothing extra; a long one names its phases and
/// reports while it iterates; a mesh expected large is announced, with its
/// size, before it is made.
#[test]
fn long_runs_report_progress() {
    let short = run_hertz(&[]);
    ok(&short);
    let progress = |run: &Run| -> Vec<String> {
        run.stdout
            .lines()
            .filter(|l| l.starts_with('['))
            .map(String::from)
            .collect()
    };
    assert!(progress(&short).is_empty(), "{}", short.stdout);
    // About 5 s: the paper's plain iteration with full solves on 37473
    // nodes, with an r five times below the paper's (about 190 iterations).
    let run = mpirun(
        2,
        &[
            "-options_file",
            "options/hertz-paper",
            "-mesh",
            "meshes/hertz_37473.msh",
            "-ubr_condense_max",
            "0",
            "-ubr_r",
            "40",
            "-ubr_rho",
            "60",
        ],
    );
    ok(&run);
    let lines = progress(&run);
    for phase in ["] iterating", "] UBR-C iteration", "] writing the outputs"] {
        assert!(
            lines.iter().any(|l| l.contains(phase)),
            "no '{phase}' line:\n{}",
            run.stdout
        );
    }
    // 2.6e5 nodes to generate: said at once (the scene then stops on a
    // contact surface the mesh does not have).
    let run = mpirun(
        2,
        &[
            "-options_file",
            "options/hertz",
            "-mesh_generate",
            "hertz2d",
            "-mesh_h",
            "0.015",
            "-contact_surface",
            "nosuch",
        ],
    );
    error_line(&run);
    assert!(
        progress(&run)[0].ends_with("] generating hertz2d (h = 0.015): about 2.590e5 nodes"),
        "{}",
        run.stdout
    );
}

// ----- item 6: messages -----

/// The trial's confusing messages, now one line each that says what is wrong.
#[test]
fn messages_say_what_is_wrong() {
    let dir = scratch("trial-messages");
    let mesh = gmsh(&dir, "block", BLOCK);
    // A group of the wrong dimension says its dimension.
    let run = mpirun(
        2,
        &block(
            &mesh,
            &["-dirichlet_top", "uy=-0.01", "-contact_surface", "body"],
        ),
    );
    let e = error_line(&run);
    assert!(
        e.contains("group 'body' has dimension 2")
            && e.contains("a contact surface needs a group of dimension 1"),
        "{e}"
    );
    // A missing options file: one line, exit 2, no PETSc traceback.
    let run = mpirun(2, &["-options_file", "options/does_not_exist"]);
    let e = error_line(&run);
    assert!(
        e.contains("-options_file") && e.contains("options/does_not_exist"),
        "{e}"
    );
    assert!(!run.stderr.contains("PETSC ERROR"), "{}", run.stderr);
    // A contact direction within 1e-3 of unit length is normalised, and said so.
    let run = mpirun(
        2,
        &block(
            &mesh,
            &[
                "-dirichlet_top",
                "ux=0,uy=-0.001",
                "-contact_direction",
                "0.7071,-0.7071",
            ],
        ),
    );
    ok(&run);
    assert!(
        run.stderr
            .contains("note: -contact_direction 0.7071,-0.7071 (norm 0.99999040995")
            && run
                .stderr
                .contains("normalised to (0.707106781187, -0.707106781187)"),
        "{}",
        run.stderr
    );
    // A mesh without physical groups says so, and how Gmsh adds them.
    let bare = gmsh(&dir, "bare", NO_GROUPS);
    let run = mpirun(2, &block(&bare, &["-dirichlet_top", "uy=-0.01"]));
    let e = error_line(&run);
    assert!(
        e.contains("the mesh has no physical groups") && e.contains("Physical Curve(\"contact\")"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

// ----- item 7: features -----

/// A column clamped at its base under gravity: the base's reaction is the
/// weight rho g A (to 1e-10), and `-gravity` wants `-density`.
#[test]
fn gravity_reaction_is_the_weight() {
    let dir = scratch("trial-gravity");
    let mesh = gmsh(&dir, "column", COLUMN);
    let args = column(&mesh, &["-ubr_lambda_rtol", "1e-8"]);
    let (run, r, _) = solve_rows("trial-gravity-run", 2, &args);
    let weight = 2.0 * 9.81 * 4.0;
    let reaction = &r.reactions["base"];
    assert!(reaction[0].abs() <= 1e-10 * weight, "{reaction:?}");
    assert!(
        (reaction[1] - weight).abs() <= 1e-10 * weight,
        "{reaction:?}"
    );
    assert!(
        run.stdout.contains("reaction        base: ("),
        "{}",
        run.stdout
    );
    // The trial's `-gravity 0,-9.81` alone.
    let run = mpirun(2, &block(&mesh, &["-gravity", "0,-9.81"]));
    assert!(error_line(&run).contains("-gravity needs -density"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A pressurized quarter ring (plane strain) against Lamé's radial
/// displacement `u_r(r) = (1+nu) p a^2 / (E (b^2 - a^2)) ((1-2nu) r + b^2/r)`
/// at the outer arc (its candidates' u_n = u_x with n = (1,0)).
#[test]
fn pressure_on_a_ring_matches_lame() {
    let dir = scratch("trial-lame");
    let mesh = gmsh(&dir, "ring", RING);
    let args = [
        "-mesh",
        &mesh,
        "-E",
        "1000",
        "-nu",
        "0.3",
        "-dirichlet_left",
        "ux=0",
        "-dirichlet_bottom",
        "uy=0",
        "-pressure_inner",
        "10",
        "-contact_surface",
        "outer",
        "-contact_direction",
        "1,0",
        "-obstacle",
        "plane",
        "-obstacle_point",
        "10,0",
    ];
    let (_, r, rows) = solve_rows("trial-lame-run", 2, &args);
    let (e, nu, p, a, b) = (1000.0, 0.3, 10.0, 1.0, 2.0);
    let ur = |x: f64| {
        (1.0 + nu) * p * a * a / (e * (b * b - a * a)) * ((1.0 - 2.0 * nu) * x + b * b / x)
    };
    let mut worst = 0.0f64;
    for row in &rows {
        let rr = row.x[0].hypot(row.x[1]);
        let cos = row.x[0] / rr;
        if cos > 0.3 {
            worst = worst.max((row.un / cos - ur(rr)).abs() / ur(rr));
        }
    }
    assert!(
        worst < 5e-3,
        "radial displacement off Lamé's by {worst:.2e}"
    );
    // The pressure's resultant on the quarter: p a along x and along y,
    // taken by the symmetry edges.
    let load = &r.load;
    assert!(
        (load[0] - p * a).abs() < 1e-3 * p * a && (load[1] - p * a).abs() < 1e-3 * p * a,
        "{load:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Hertz scene: the contact force equals minus the sum of the
/// reactions and the loads, to round-off.
#[test]
fn hertz_contact_force_balances_reactions_and_loads() {
    let (_, r, _) = solve_rows(
        "trial-balance",
        2,
        &hertz_args("meshes/hertz_1692.msh", &[]),
    );
    let (contact, load) = (&r.contact_force_vector, &r.load);
    let reactions = &r.reactions;
    assert_eq!(reactions.len(), 1);
    for c in 0..2 {
        let sum: f64 = reactions.values().map(|v| v[c]).sum::<f64>() + load[c];
        assert!(
            (contact[c] + sum).abs() <= 1e-10 * 800.0,
            "component {c}: contact {} vs reactions + loads {sum}",
            contact[c]
        );
    }
    assert!((contact[1] - 800.0).abs() < 1e-6 * 800.0);
}

/// Two contact surfaces on one scene give the run of the one surface that
/// merges them.
#[test]
fn two_contact_surfaces_agree_with_their_union() {
    let dir = scratch("trial-two");
    let mesh = gmsh(&dir, "block", BLOCK);
    let extra = [
        "-dirichlet_top",
        "ux=0.002,uy=-0.01",
        "-friction",
        "coulomb",
        "-friction_coefficient",
        "0.3",
    ];
    let one = block(&mesh, &extra);
    let mut two = one.clone();
    let i = two.iter().position(|a| *a == "base").unwrap();
    two[i] = "base_a,base_b";
    let (_, r1, c1) = solve_rows("trial-one", 2, &one);
    let (_, r2, c2) = solve_rows("trial-two-run", 2, &two);
    assert_eq!(r1.contact_nodes, r2.contact_nodes);
    assert_eq!(c1.len(), c2.len());
    for (a, b) in c1.iter().zip(&c2) {
        assert_eq!(a.node, b.node);
        assert!((a.lambda_n - b.lambda_n).abs() <= 1e-9 * r1.peak_pressure);
        assert_eq!(a.status, b.status);
    }
    let f = r1.contact_force;
    assert!((f - r2.contact_force).abs() <= 1e-10 * f);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Gmsh's physical names may hold spaces, an option's name cannot: an
/// option names "Top Edge" as `Top_Edge` (or the value of `-contact_surface`
/// as "Base Edge" too). The block with spaced names gives the answer of its
/// plain names (contact CSV byte for byte, 1 rank; 2 ranks to 1e-9), its
/// Dirichlet, contact and material options alike; a wrong name's error says
/// how spaces are written. Before, such a group could not be named.
#[test]
fn group_names_with_spaces() {
    let dir = scratch("trial-spaces");
    let spaced = BLOCK
        .replace("\"base\"", "\"Base Edge\"")
        .replace("\"top\"", "\"Top Edge\"")
        .replace("\"body\"", "\"The Body\"");
    let plain = gmsh(&dir, "plain", BLOCK);
    let spaced = gmsh(&dir, "spaced", &spaced);
    let scene = |mesh: &str, names: [&str; 3], ranks: usize, tag: &str| -> Vec<u8> {
        let [base, top, body] = names;
        let (dirichlet, e) = (format!("-dirichlet_{top}"), format!("-E_{body}"));
        let extra = ["-friction", "coulomb", "-friction_coefficient", "0.3"];
        let mut a = block(mesh, &extra);
        let i = a.iter().position(|x| *x == "base").unwrap();
        a[i] = base;
        a.extend([dirichlet.as_str(), "ux=0.002,uy=-0.01", e.as_str(), "800"]);
        let csv = dir.join(format!("{tag}.csv"));
        a.extend(["-contact_output", csv.to_str().unwrap()]);
        let run = mpirun(ranks, &a);
        ok(&run);
        assert!(run.stdout.contains("E = 800"), "{}", run.stdout);
        std::fs::read(&csv).unwrap()
    };
    let reference = scene(&plain, ["base", "top", "body"], 1, "plain");
    for base in ["Base_Edge", "Base Edge"] {
        let rows = scene(&spaced, [base, "Top_Edge", "The_Body"], 1, "spaced");
        assert_eq!(rows, reference, "-contact_surface {base}");
    }
    let two = scene(&spaced, ["Base_Edge", "Top_Edge", "The_Body"], 2, "two");
    let gap = max_stress_gap(
        &parse_rows(&String::from_utf8(two).unwrap()),
        &parse_rows(&String::from_utf8(reference).unwrap()),
    );
    assert!(gap <= 1e-9, "2 ranks: {gap:e}");
    let mut a = block(&spaced, &[]);
    let i = a.iter().position(|x| *x == "base").unwrap();
    a[i] = "Base_Edge";
    a.extend(["-dirichlet_top_edge", "uy=-0.01"]);
    let line = error_line(&mpirun(2, &a));
    assert!(
        line.contains("no physical group 'top_edge'")
            && line.contains("Top Edge (1D)")
            && line.contains("a space in a group's name is written _"),
        "{line}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `-vtk FILE.vtu` from 2 ranks: one file, read by meshio, with the mesh's
/// node and cell counts, its node tags, and the report's pressure maximum;
/// the `.pvtu` pieces carry the node tags too.
#[test]
fn single_vtu_reads_with_meshio() {
    let dir = scratch("trial-vtu");
    let vtu = dir.join("hertz.vtu");
    let pvtu = dir.join("pieces.pvtu");
    let rep = dir.join("r.json");
    for out in [&vtu, &pvtu] {
        let run = run_hertz(&[
            "-vtk",
            out.to_str().unwrap(),
            "-report",
            rep.to_str().unwrap(),
        ]);
        ok(&run);
    }
    let script = r#"
import sys, meshio, numpy
m = meshio.read(sys.argv[1])
tags = m.point_data["node_tag"].ravel()
print(len(m.points), sum(len(c.data) for c in m.cells), repr(float(m.point_data["contact_pressure"].max())), len(set(tags.tolist())), int(tags.min()), int(tags.max()))
p = meshio.read(sys.argv[2])
print("node_tag" in p.point_data)
"#;
    let out = Command::new(python())
        .args([
            "-c",
            script,
            vtu.to_str().unwrap(),
            dir.join("pieces_1.vtu").to_str().unwrap(),
        ])
        .output()
        .expect("python3 runs (apt-get install python3-meshio)");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r = report(&rep);
    let first: Vec<&str> = text.lines().next().unwrap().split_whitespace().collect();
    let n: f64 = first[0].parse().unwrap();
    assert_eq!(n, r.nodes, "each node once");
    assert_eq!(first[1].parse::<f64>().unwrap(), r.elements);
    let pmax: f64 = first[2].parse().unwrap();
    assert!((pmax - r.peak_pressure).abs() <= 1e-12 * pmax);
    assert_eq!(first[3].parse::<f64>().unwrap(), n, "node tags are unique");
    assert_eq!(
        text.lines().nth(1),
        Some("True"),
        "the .pvtu pieces carry node_tag"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `-plot_contact` on an asymmetric 2D contact and on a 3D one centred by
/// `-reference_center` without `-reference`: both write their plots.
#[test]
fn contact_plots_for_asymmetric_and_3d_contact() {
    let dir = scratch("trial-plot");
    let mesh = gmsh(&dir, "block", BLOCK);
    let p2 = dir.join("block.png");
    let run = mpirun(
        2,
        &block(
            &mesh,
            &[
                "-dirichlet_top",
                "ux=0.02,uy=-0.01",
                "-obstacle",
                "ball",
                "-obstacle_center",
                "0.6,-5",
                "-obstacle_radius",
                "5",
                "-contact_normal",
                "fixed",
                "-friction",
                "coulomb",
                "-friction_coefficient",
                "0.3",
                "-plot_contact",
                p2.to_str().unwrap(),
            ],
        ),
    );
    ok(&run);
    let p3 = dir.join("block3d.png");
    let run = mpirun(
        2,
        &[
            "-options_file",
            "options/block3d",
            "-mesh_generate",
            "block3d",
            "-mesh_h",
            "0.25",
            "-reference_center",
            "-0.3,0,-0.5",
            "-plot_contact",
            p3.to_str().unwrap(),
        ],
    );
    ok(&run);
    assert!(
        !run.stderr.contains("-reference_center was not used"),
        "{}",
        run.stderr
    );
    for p in [&p2, &p3] {
        assert!(
            std::fs::metadata(p)
                .map(|m| m.len() > 10_000)
                .unwrap_or(false),
            "{}",
            p.display()
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
