//! A material per body (`-E_NAME`, `-nu_NAME`, `-density_NAME` on the
//! physical groups of the mesh's dimension; issue "Two elastic bodies",
//! item 1).
//!
//! The scene: a column of two bonded unit squares (one mesh, the interface
//! nodes shared), "soft" below (E 1) and "hard" above (E 10), held at the
//! bottom (uy = 0) and on the left (ux = 0), pulled by a traction T on the
//! top. With nu = 0 the exact field is piecewise linear (u_x = 0, u_y with
//! slope T/E in each body), which P1 and Q1 cells hold: the top moves by
//! the series springs' T (1/E_soft + 1/E_hard). The contact surface the
//! program requires is the top, against a plane far above it (nothing
//! touches); its CSV gives each top node's u_y (`un`, the direction 0,1).
//!
//! - (a) triangles and quadrilaterals: the closed form to 1e-8 relative;
//!   confined on both sides (ux = 0 left and right) with a Poisson's ratio
//!   per body, the oedometric springs T (1/M_soft + 1/M_hard), M the P-wave
//!   modulus; `-E_soft` equal to `-E` gives the global-material answer
//!   bit for bit; each cell's density weighs (the bottom reaction is the
//!   weight of both bodies); the VTU's stresses take each cell's E.
//! - (b) tetrahedra (two bonded unit cubes): the closed form to 1e-8.
//! - (c) 1, 2, 3 ranks agree to 1e-8.
//! - (d) bad input: exit 2, one line naming the option.
//! - (e) a Poisson's ratio above 0.49 on any body is warned of (the linear
//!   elements lock): the option that set it named, none for an option no
//!   cell takes, none in plane stress.

mod common;
use common::*;

/// The column in 2D: `soft` (0,1)^2 below `hard` (0,1)x(1,2), groups
/// bottom, left, right, top; `quads`: a structured mesh of quadrilaterals;
/// `extra`: more .geo lines.
fn geo_2d(quads: bool, extra: &str) -> String {
    let cells = if quads {
        "Transfinite Curve{1:7} = 5; Transfinite Surface{1,2}; Recombine Surface{1,2};"
    } else {
        ""
    };
    format!(
        "h = 0.3;
Point(1) = {{0,0,0,h}}; Point(2) = {{1,0,0,h}}; Point(3) = {{1,1,0,h}}; Point(4) = {{0,1,0,h}};
Point(5) = {{1,2,0,h}}; Point(6) = {{0,2,0,h}};
Line(1) = {{1,2}}; Line(2) = {{2,3}}; Line(3) = {{3,4}}; Line(4) = {{4,1}};
Line(5) = {{3,5}}; Line(6) = {{5,6}}; Line(7) = {{6,4}};
Curve Loop(1) = {{1,2,3,4}}; Plane Surface(1) = {{1}};
Curve Loop(2) = {{-3,5,6,7}}; Plane Surface(2) = {{2}};
{cells}
Physical Surface(\"soft\") = {{1}}; Physical Surface(\"hard\") = {{2}};
Physical Curve(\"bottom\") = {{1}}; Physical Curve(\"left\") = {{4,7}};
Physical Curve(\"right\") = {{2,5}}; Physical Curve(\"top\") = {{6}};
{extra}
"
    )
}

/// The column in 3D: two bonded unit cubes, `soft` below `hard`,
/// tetrahedra; groups bottom, top, xmin, ymin.
const GEO_3D: &str = "SetFactory(\"OpenCASCADE\");
Box(1) = {0,0,0,1,1,1};
Box(2) = {0,0,1,1,1,1};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Mesh.CharacteristicLengthMax = 0.4;
e = 1e-6;
Physical Volume(\"soft\") = {1};
Physical Volume(\"hard\") = {2};
Physical Surface(\"bottom\") = Surface In BoundingBox{-e,-e,-e,1+e,1+e,e};
Physical Surface(\"top\") = Surface In BoundingBox{-e,-e,2-e,1+e,1+e,2+e};
Physical Surface(\"xmin\") = Surface In BoundingBox{-e,-e,-e,e,1+e,2+e};
Physical Surface(\"ymin\") = Surface In BoundingBox{-e,-e,-e,1+e,e,2+e};
";

/// Meshes `geo` (the text) with gmsh in a scratch directory: its `.msh`.
fn mesh(name: &str, dim: &str, geo: &str) -> (Scratch, String) {
    let dir = scratch(&format!("materials-{name}"));
    let g = dir.join(format!("{name}.geo"));
    std::fs::write(&g, geo).unwrap();
    let out = dir.join(format!("{name}.msh"));
    gmsh(dim, g.to_str().unwrap(), &out, &[]);
    let msh = out.to_str().unwrap().to_string();
    (dir, msh)
}

/// The traction on the top.
const T: f64 = 0.01;

/// The 2D scene's options on `msh`, then `extra`.
fn args_2d<'a>(msh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "-mesh",
        msh,
        "-nu",
        "0",
        "-dirichlet_bottom",
        "uy=0",
        "-dirichlet_left",
        "ux=0",
        "-traction_top",
        "0,0.01",
        "-contact_surface",
        "top",
        "-obstacle",
        "plane",
        "-obstacle_point",
        "0,10",
        "-contact_direction",
        "0,1",
    ];
    v.extend_from_slice(extra);
    v
}

/// The top's displacement along the contact direction at every top node
/// (the CSV's `un`), by node tag; checks that nothing touched and that no
/// option was reported unused.
fn top_displacements(name: &str, ranks: usize, args: &[&str]) -> Vec<(u64, f64)> {
    let (run, report, rows) = solve_rows(name, ranks, args);
    assert_eq!(report.contact_active, 0.0, "{name}: nothing touches");
    assert!(
        !run.stderr.contains("was not used") && !run.stderr.contains("has no effect"),
        "{name}: {}",
        run.stderr
    );
    assert!(!rows.is_empty(), "{name}: top nodes");
    rows.iter().map(|r| (r.node, r.un)).collect()
}

/// The largest relative gap of every value of `u` to `exact`.
fn worst(u: &[(u64, f64)], exact: f64) -> f64 {
    u.iter()
        .map(|&(_, v)| ((v - exact) / exact).abs())
        .fold(0.0, f64::max)
}

/// (a) Series springs: the top moves by T (1/E_soft + 1/E_hard), on
/// triangles and on quadrilaterals, to 1e-8.
#[test]
fn two_bonded_bodies_2d_series_springs() {
    for quads in [false, true] {
        let (dir, msh) = mesh(
            if quads { "quads" } else { "tris" },
            "-2",
            &geo_2d(quads, ""),
        );
        let u = top_displacements("series", 1, &args_2d(&msh, &["-E", "1", "-E_hard", "10"]));
        let exact = T * (1.0 / 1.0 + 1.0 / 10.0);
        let gap = worst(&u, exact);
        println!(
            "quads {quads}: top u_y {:.15e}, exact {exact:e}, gap {gap:.2e}",
            u[0].1
        );
        assert!(gap < 1e-8, "quads {quads}: relative gap {gap:e}");
        // Given for both bodies, the global E is the default of none.
        let u2 = top_displacements(
            "series-both",
            1,
            &args_2d(&msh, &["-E", "3", "-E_soft", "1", "-E_hard", "10"]),
        );
        assert!(worst(&u2, exact) < 1e-8, "both given: {u2:?}");
        let _ = std::fs::remove_dir_all(dir);
    }
}

/// (a) The stresses of `-vtk` take each cell's material: in series both
/// bodies carry sigma_yy = T (with the global E in the hard body's cells
/// it would be 10 T there).
#[test]
fn stresses_use_each_cells_material() {
    let (dir, msh) = mesh("stress", "-2", &geo_2d(false, ""));
    let vtu = dir.join("out.vtu");
    let vtu = vtu.to_str().unwrap();
    top_displacements(
        "stress",
        2,
        &args_2d(&msh, &["-E", "1", "-E_hard", "10", "-vtk", vtu]),
    );
    let script = "import sys, meshio, numpy as np
m = meshio.read(sys.argv[1])
s = np.concatenate(m.cell_data['stress']).reshape(-1, 9)
print(s[:, 4].min(), s[:, 4].max())";
    let py = std::process::Command::new(python())
        .args(["-c", script, vtu])
        .output()
        .expect("python3 with meshio");
    let text = String::from_utf8_lossy(&py.stdout).to_string();
    let f: Vec<f64> = text
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect();
    assert!(
        py.status.success() && f.len() == 2,
        "{text}\n{}",
        String::from_utf8_lossy(&py.stderr)
    );
    println!("sigma_yy from {:e} to {:e}, T = {T:e}", f[0], f[1]);
    assert!((f[0] - T).abs() < 1e-8 * T && (f[1] - T).abs() < 1e-8 * T);
    let _ = std::fs::remove_dir_all(dir);
}

/// (a) `-E_soft` equal to `-E`: the global-material answer, bit for bit.
#[test]
fn same_material_as_global_changes_nothing() {
    let (dir, msh) = mesh("same", "-2", &geo_2d(false, ""));
    let global = top_displacements("global", 1, &args_2d(&msh, &["-E", "2"]));
    let same = top_displacements("same", 1, &args_2d(&msh, &["-E", "2", "-E_soft", "2"]));
    assert_eq!(global, same);
    let exact = T * 2.0 / 2.0;
    assert!(worst(&global, exact) < 1e-8, "{global:?}");
    let _ = std::fs::remove_dir_all(dir);
}

/// (a) Confined on both sides (ux = 0 left and right), Poisson's ratio per
/// body: the top moves by T (1/M_soft + 1/M_hard), M = E (1 - nu) / ((1 +
/// nu)(1 - 2 nu)), on quadrilaterals, to 1e-8.
#[test]
fn confined_column_poisson_ratio_per_body() {
    let (dir, msh) = mesh("confined", "-2", &geo_2d(true, ""));
    let u = top_displacements(
        "confined",
        1,
        &args_2d(
            &msh,
            &[
                "-E",
                "1",
                "-E_hard",
                "10",
                "-nu_soft",
                "0.2",
                "-nu_hard",
                "0.35",
                "-dirichlet_right",
                "ux=0",
            ],
        ),
    );
    let m = |e: f64, nu: f64| e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let exact = T * (1.0 / m(1.0, 0.2) + 1.0 / m(10.0, 0.35));
    let gap = worst(&u, exact);
    println!(
        "confined: top u_y {:.15e}, exact {exact:e}, gap {gap:.2e}",
        u[0].1
    );
    assert!(gap < 1e-8, "relative gap {gap:e}");
    let _ = std::fs::remove_dir_all(dir);
}

/// (a) Each cell's density weighs: under gravity the bottom carries the
/// weight of both unit squares, g (rho_soft + rho_hard).
#[test]
fn density_per_body_weighs() {
    let (dir, msh) = mesh("weight", "-2", &geo_2d(false, ""));
    let (_, report, _) = solve_rows(
        "weight",
        2,
        &args_2d(
            &msh,
            &[
                "-E",
                "1",
                "-E_hard",
                "10",
                "-gravity",
                "0,-0.001",
                "-density",
                "1",
                "-density_hard",
                "3",
            ],
        ),
    );
    // The load (traction and weight) and the bottom's reaction.
    let weight = 0.001 * (1.0 + 3.0);
    let load = report.load[1];
    assert!((load - (T - weight)).abs() < 1e-12, "load {load}");
    let reaction = report.reactions["bottom"][1];
    assert!(
        (reaction + (T - weight)).abs() < 1e-10,
        "bottom reaction {reaction}, expected {}",
        weight - T
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// (b) Two bonded cubes of tetrahedra (the assembly's tetrahedron path):
/// the series springs to 1e-8.
#[test]
fn two_bonded_bodies_3d_tetrahedra() {
    let (dir, msh) = mesh("cubes", "-3", GEO_3D);
    let args = [
        "-mesh",
        &msh,
        "-E",
        "1",
        "-E_hard",
        "10",
        "-nu",
        "0",
        "-dirichlet_bottom",
        "uz=0",
        "-dirichlet_xmin",
        "ux=0",
        "-dirichlet_ymin",
        "uy=0",
        "-traction_top",
        "0,0,0.01",
        "-contact_surface",
        "top",
        "-obstacle",
        "plane",
        "-obstacle_point",
        "0,0,10",
        "-contact_direction",
        "0,0,1",
    ];
    let u = top_displacements("cubes", 2, &args);
    let exact = T * (1.0 + 0.1);
    let gap = worst(&u, exact);
    println!(
        "3D: top u_z {:.15e}, exact {exact:e}, gap {gap:.2e}",
        u[0].1
    );
    assert!(gap < 1e-8, "relative gap {gap:e}");
    let _ = std::fs::remove_dir_all(dir);
}

/// (c) 1, 2 and 3 ranks agree to 1e-8 (the body groups travel with the
/// cells to every rank).
#[test]
fn ranks_agree() {
    let (dir, msh) = mesh("ranks", "-2", &geo_2d(false, ""));
    let args = args_2d(&msh, &["-E", "1", "-E_hard", "10", "-nu_hard", "0.3"]);
    let one = top_displacements("ranks-1", 1, &args);
    for n in [2, 3] {
        let other = top_displacements(&format!("ranks-{n}"), n, &args);
        assert_eq!(one.len(), other.len());
        let gap = one
            .iter()
            .zip(&other)
            .map(|(a, b)| ((a.1 - b.1) / a.1).abs())
            .fold(0.0, f64::max);
        println!("-n {n} against -n 1: largest relative gap {gap:.2e}");
        for (a, b) in one.iter().zip(&other) {
            assert_eq!(a.0, b.0);
            assert!(
                (a.1 - b.1).abs() < 1e-8 * a.1.abs(),
                "-n {n}: node {}: {} against {}",
                a.0,
                a.1,
                b.1
            );
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// Runs the 2D scene with `extra` on `msh`: exit 2, one line naming each
/// of `needles`.
fn refused(msh: &str, what: &str, extra: &[&str], needles: &[&str]) {
    for ranks in [1, 2] {
        let run = mpirun(ranks, &args_2d(msh, extra));
        let line = run.refused(what, 2, needles);
        println!("{what} (-n {ranks}): {line}");
    }
}

/// (d) Bad input: exit 2, one line naming the option.
#[test]
fn bad_input() {
    let both = "Physical Surface(\"lower\") = {1};";
    let (dir, msh) = mesh("bad", "-2", &geo_2d(false, both));
    let e = ["-E", "1"];
    let with = |more: &[&'static str]| -> Vec<&'static str> {
        let mut v = e.to_vec();
        v.extend_from_slice(more);
        v
    };
    refused(
        &msh,
        "unknown group",
        &with(&["-E_stone", "5"]),
        &["-E_stone", "'stone'", "hard", "soft"],
    );
    refused(
        &msh,
        "group of another dimension",
        &with(&["-nu_top", "0.2"]),
        &["-nu_top", "dimension 1"],
    );
    refused(
        &msh,
        "negative E",
        &with(&["-E_soft", "-1"]),
        &["-E_soft", "not positive"],
    );
    refused(
        &msh,
        "bad nu",
        &with(&["-nu_hard", "0.5"]),
        &["-nu_hard", "(-1, 0.5)"],
    );
    refused(
        &msh,
        "density without gravity",
        &with(&["-density_hard", "2"]),
        &["-density_hard", "-gravity"],
    );
    // "lower" holds the cells of "soft" too: two materials for them.
    refused(
        &msh,
        "two materials",
        &with(&["-E_soft", "2"]),
        &["-E_soft", "'soft'", "'lower'"],
    );
    let _ = std::fs::remove_dir_all(&dir);
    // A generated mesh has no body groups.
    let run = mpirun(
        1,
        &[
            "-options_file",
            "options/hertz",
            "-mesh_generate",
            "hertz2d",
            "-E_body",
            "5",
        ],
    );
    run.refused("generated mesh", 2, &["-E_body", "it has none"]);
}

/// (e) Nearly incompressible bodies are warned of, once, in stderr and the
/// report, naming the option that set the Poisson's ratio; not for nu 0.49,
/// not for a global -nu that no cell takes (each body has its own), not in
/// plane stress.
#[test]
fn nearly_incompressible_is_warned() {
    let (dir, msh) = mesh("locking", "-2", &geo_2d(false, ""));
    let warned = |name: &str, ranks: usize, global: &'static str, extra: &[&str]| {
        let mut a = args_2d(&msh, &["-E", "1"]);
        a[3] = global; // the value of "-nu"
        a.extend_from_slice(extra);
        let (run, report, _) = solve_rows(name, ranks, &a);
        let w: Vec<&String> = report
            .warnings
            .iter()
            .filter(|w| w.contains("nearly incompressible"))
            .collect();
        assert!(w.len() <= 1, "{name}: {w:?}");
        let w = w.first().map(|w| w.to_string());
        if let Some(w) = &w {
            assert_eq!(run.stderr.matches("nearly incompressible").count(), 1);
            assert!(
                run.stderr.contains(&format!("warning: {w}")),
                "{}",
                run.stderr
            );
            assert!(w.contains("lock") && w.contains("too stiff"), "{w}");
        }
        w
    };
    let w = warned("global", 1, "0.4999", &[]).expect("-nu 0.4999 is warned of");
    assert!(
        w.starts_with("-nu 0.4999: nearly incompressible (lambda/mu = 4999)"),
        "{w}"
    );
    for ranks in [1, 3] {
        let w = warned("body", ranks, "0.3", &["-nu_hard", "0.495"]).expect("-nu_hard 0.495");
        assert!(w.starts_with("-nu_hard 0.495: "), "{w}");
    }
    assert_eq!(warned("at_0.49", 1, "0.49", &[]), None);
    let unused = ["-nu_soft", "0.3", "-nu_hard", "0.3"];
    assert_eq!(warned("unused_global", 2, "0.4999", &unused), None);
    assert_eq!(
        warned("plane_stress", 1, "0.4999", &["-plane_stress"]),
        None
    );
    let _ = std::fs::remove_dir_all(dir);
}
