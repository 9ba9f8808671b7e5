//! Q1 quadrilaterals and hexahedra, prisms and pyramids, and meshes that mix
//! them with P1 cells: the contact patch test, the paper's scenes on them,
//! mixed against pure meshes, rank-count independence, bad input.
mod common;
use common::*;
use std::fmt::Write as _;
use std::path::Path;

/// Tight UBR settings for comparisons, explicit so that they do not depend
/// on the defaults (`-ubr_stop paper` makes `-ubr_rtol` the stopping test
/// where the default stop is another one).
const TIGHT: [&str; 6] = [
    "-ubr_anderson",
    "10",
    "-ubr_stop",
    "paper",
    "-ubr_rtol",
    "1e-10",
];

/// PETSc's SNES VI (vinewtonrsls) on the frictionless Hertz scene, from the
/// body shifted onto the obstacle: an independent solution of the same
/// discrete problem.
const SNES_VI: [&str; 4] = [
    "-contact_algorithm",
    "snesvi",
    "-ssn_initial_shift",
    "0,-0.01",
];

/// The Hertz scene of options/hertz (at the defaults) on another mesh.
fn hertz_scene<'a>(mesh: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["-options_file", "options/hertz", "-mesh", mesh];
    v.extend_from_slice(extra);
    v
}

/// Writes a Gmsh 2.2 ASCII mesh: `x` three coordinates per node (tags
/// 1..), `cells` 0-based, `groups` named facet (or edge) groups.
fn write_msh(
    path: &Path,
    dim: usize,
    x: &[f64],
    cells: &[Vec<usize>],
    groups: &[(&str, Vec<Vec<usize>>)],
) {
    let ty = |d: usize, k: usize| match (d, k) {
        (1, 2) => 1,
        (2, 3) => 2,
        (2, 4) => 3,
        (3, 4) => 4,
        (3, 8) => 5,
        (3, 6) => 6,
        (3, 5) => 7,
        _ => panic!("no type for {k} nodes in {d}D"),
    };
    let mut s = String::from("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n");
    writeln!(s, "{}", groups.len() + 1).unwrap();
    for (g, (name, _)) in groups.iter().enumerate() {
        writeln!(s, "{} {} \"{name}\"", dim - 1, g + 1).unwrap();
    }
    writeln!(
        s,
        "{dim} 100 \"body\"\n$EndPhysicalNames\n$Nodes\n{}",
        x.len() / 3
    )
    .unwrap();
    for (i, p) in x.chunks(3).enumerate() {
        writeln!(s, "{} {:?} {:?} {:?}", i + 1, p[0], p[1], p[2]).unwrap();
    }
    let n: usize = cells.len() + groups.iter().map(|g| g.1.len()).sum::<usize>();
    writeln!(s, "$EndNodes\n$Elements\n{n}").unwrap();
    let mut tag = 0;
    let mut line = |s: &mut String, t: usize, phys: usize, e: &[usize]| {
        tag += 1;
        let nodes: Vec<String> = e.iter().map(|v| (v + 1).to_string()).collect();
        writeln!(s, "{tag} {t} 2 {phys} 1 {}", nodes.join(" ")).unwrap();
    };
    for (g, (_, elems)) in groups.iter().enumerate() {
        for e in elems {
            line(&mut s, ty(dim - 1, e.len()), g + 1, e);
        }
    }
    for c in cells {
        line(&mut s, ty(dim, c.len()), 100, c);
    }
    s.push_str("$EndElements\n");
    std::fs::write(path, s).unwrap();
}

/// Deterministic pseudo-random numbers in [-1, 1].
fn jitter(i: usize, k: usize) -> f64 {
    let v = ((i * 7919 + k * 104_729 + 17) % 1000) as f64 / 999.0;
    2.0 * v - 1.0
}

/// The faces of a positively oriented 3D cell (Gmsh order), outward.
fn faces(k: usize) -> &'static [&'static [usize]] {
    match k {
        4 => &[&[1, 2, 3], &[0, 3, 2], &[0, 1, 3], &[0, 2, 1]],
        5 => &[
            &[0, 3, 2, 1],
            &[0, 1, 4],
            &[1, 2, 4],
            &[2, 3, 4],
            &[3, 0, 4],
        ],
        6 => &[
            &[0, 2, 1],
            &[3, 4, 5],
            &[0, 1, 4, 3],
            &[1, 2, 5, 4],
            &[2, 0, 3, 5],
        ],
        _ => &[
            &[0, 3, 2, 1],
            &[4, 5, 6, 7],
            &[0, 1, 5, 4],
            &[1, 2, 6, 5],
            &[2, 3, 7, 6],
            &[3, 0, 4, 7],
        ],
    }
}

/// The unit cube as an `n^3` grid of distorted hexahedra (interior nodes
/// moved by up to 0.25 cell, boundary nodes within their face, so the faces
/// stay planar but their quadrilaterals are not parallelograms); with
/// `mixed`, the centre hexahedron split into 6 pyramids (apex inside), the
/// corner one at the origin into 6 pyramids whose 3 boundary ones are split
/// into 2 tetrahedra each, and the column along the edge x = 1, y = 0 into
/// prisms. Returns the coordinates, the cells and the groups `bottom`,
/// `top`, `xmin`, `ymin` (the faces z = 0, z = 1, x = 0, y = 0).
type MeshData = (
    Vec<f64>,
    Vec<Vec<usize>>,
    Vec<(&'static str, Vec<Vec<usize>>)>,
);

fn cube(n: usize, mixed: bool) -> MeshData {
    let id = |i: usize, j: usize, k: usize| (k * (n + 1) + j) * (n + 1) + i;
    let mut x = Vec::new();
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                for (a, ijk) in [i, j, k].into_iter().enumerate() {
                    let on = ijk == 0 || ijk == n;
                    let d = if on {
                        0.0
                    } else {
                        0.25 * jitter(id(i, j, k), a)
                    };
                    x.push((ijk as f64 + d) / n as f64);
                }
            }
        }
    }
    let mut cells = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = |a: usize, b: usize, e: usize| id(i + a, j + b, k + e);
                let h = vec![
                    c(0, 0, 0),
                    c(1, 0, 0),
                    c(1, 1, 0),
                    c(0, 1, 0),
                    c(0, 0, 1),
                    c(1, 0, 1),
                    c(1, 1, 1),
                    c(0, 1, 1),
                ];
                let centre_cell = (i, j, k) == (n / 2, n / 2, n / 2);
                if mixed && (centre_cell || (i, j, k) == (0, 0, 0)) {
                    let apex = x.len() / 3;
                    for r in 0..3 {
                        let m = h.iter().map(|&v| x[3 * v + r]).sum::<f64>() / 8.0;
                        x.push(m + 0.01 * jitter(apex, r));
                    }
                    for (fi, f) in faces(8).iter().enumerate() {
                        let b: Vec<usize> = f.iter().rev().map(|&a| h[a]).collect();
                        if !centre_cell && [0, 2, 5].contains(&fi) {
                            cells.push(vec![b[0], b[1], b[2], apex]);
                            cells.push(vec![b[0], b[2], b[3], apex]);
                        } else {
                            cells.push(vec![b[0], b[1], b[2], b[3], apex]);
                        }
                    }
                } else if mixed && i == n - 1 && j == 0 {
                    cells.push(vec![h[0], h[1], h[2], h[4], h[5], h[6]]);
                    cells.push(vec![h[0], h[2], h[3], h[4], h[6], h[7]]);
                } else {
                    cells.push(h);
                }
            }
        }
    }
    // Boundary facets: the faces used once, grouped by the plane they lie in.
    let mut count = std::collections::HashMap::new();
    for c in &cells {
        for f in faces(c.len()) {
            let q: Vec<usize> = f.iter().map(|&a| c[a]).collect();
            let mut key = q.clone();
            key.sort_unstable();
            count.entry(key).or_insert((0, q)).0 += 1;
        }
    }
    let mut facets: Vec<Vec<usize>> = count
        .into_values()
        .filter(|(k, _)| *k == 1)
        .map(|(_, q)| q)
        .collect();
    facets.sort();
    let on = |f: &Vec<usize>, axis: usize, value: f64| {
        f.iter().all(|&v| (x[3 * v + axis] - value).abs() < 1e-12)
    };
    let group = |axis: usize, value: f64| -> Vec<Vec<usize>> {
        facets
            .iter()
            .filter(|f| on(f, axis, value))
            .cloned()
            .collect()
    };
    let groups = vec![
        ("bottom", group(2, 0.0)),
        ("top", group(2, 1.0)),
        ("xmin", group(0, 0.0)),
        ("ymin", group(1, 0.0)),
    ];
    (x, cells, groups)
}

/// The unit square as an `n^2` grid of distorted quadrilaterals (every
/// other one split into two triangles with `mixed`), z = 0; groups
/// `bottom`, `top`, `xmin` (y = 0, y = 1, x = 0).
fn square(n: usize, mixed: bool) -> MeshData {
    let id = |i: usize, j: usize| j * (n + 1) + i;
    let mut x = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            for (a, ij) in [i, j].into_iter().enumerate() {
                let on = ij == 0 || ij == n;
                let d = if on { 0.0 } else { 0.3 * jitter(id(i, j), a) };
                x.push((ij as f64 + d) / n as f64);
            }
            x.push(0.0);
        }
    }
    let mut cells = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let q = vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if mixed && (i + j) % 2 == 1 {
                cells.push(vec![q[0], q[1], q[2]]);
                cells.push(vec![q[0], q[2], q[3]]);
            } else {
                cells.push(q);
            }
        }
    }
    let groups = vec![
        (
            "bottom",
            (0..n).map(|i| vec![id(i + 1, 0), id(i, 0)]).collect(),
        ),
        (
            "top",
            (0..n).map(|i| vec![id(i, n), id(i + 1, n)]).collect(),
        ),
        (
            "xmin",
            (0..n).map(|j| vec![id(0, j + 1), id(0, j)]).collect(),
        ),
    ];
    (x, cells, groups)
}

/// The contact patch test: a distorted (and mixed) body on a rigid plane,
/// pressed by a uniform displacement delta of its top, the symmetry planes
/// x = 0 (and y = 0) sliding: uniaxial compression, a linear field in every
/// element space. Every bottom node is in contact and carries the uniform
/// pressure (E delta in 3D and in plane stress, E delta / (1 - nu^2) in
/// plane strain), to the
/// solver's tolerance: the stiffness, the quadrilateral facet weights
/// (int N_a dA on non-parallelogram facets) and the contact terms are exact.
#[test]
fn contact_patch_test() {
    let dir = scratch("q1-patch-meshes");
    let (e, nu, delta) = (1000.0, 0.3, 0.01);
    for (name, dim, (x, cells, groups)) in [
        ("quadrilaterals", 2, square(4, false)),
        ("quadrilaterals, plane stress", 2, square(4, false)),
        ("triangles + quadrilaterals", 2, square(4, true)),
        ("hexahedra", 3, cube(3, false)),
        (
            "hexahedra + prisms + pyramids + tetrahedra",
            3,
            cube(3, true),
        ),
    ] {
        let plane_stress = name.contains("plane stress");
        let path = dir.join(format!("patch{}.msh", cells.len()));
        write_msh(&path, dim, &x, &cells, &groups);
        let mesh = path.to_str().unwrap().to_string();
        let (direction, point, top, pressure) = if dim == 2 {
            (
                "0,-1",
                "0,0",
                format!("uy={}", -delta),
                if plane_stress {
                    e * delta
                } else {
                    e * delta / (1.0 - nu * nu)
                },
            )
        } else {
            ("0,0,-1", "0,0,0", format!("uz={}", -delta), e * delta)
        };
        let mut args = vec![
            "-mesh",
            &mesh,
            "-E",
            "1000",
            "-nu",
            "0.3",
            "-dirichlet_top",
            &top,
            "-dirichlet_xmin",
            "ux=0",
            "-contact_surface",
            "bottom",
            "-contact_direction",
            direction,
            "-obstacle",
            "plane",
            "-obstacle_point",
            point,
            "-ubr_r",
            "1000",
        ];
        if dim == 3 {
            args.extend_from_slice(&["-dirichlet_ymin", "uy=0"]);
        }
        if plane_stress {
            args.push("-plane_stress");
        }
        args.extend_from_slice(&TIGHT);
        let (run, r, rows) = solve_rows("q1-patch", 2, &args);
        assert!(!rows.is_empty());
        for row in &rows {
            assert_eq!(row.status, "contact", "{name}: node {}", row.node);
            assert!(
                (row.lambda_n - pressure).abs() < 1e-7 * pressure,
                "{name}: node {} pressure {} vs {pressure}\n{}",
                row.node,
                row.lambda_n,
                run.stdout
            );
            assert!(row.un.abs() < 1e-9, "{name}: u_n {}", row.un);
        }
        // The force on the unit face (side).
        let force = r.contact_force;
        assert!(
            (force - pressure).abs() < 1e-7 * pressure,
            "{name}: force {force}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Hertz scene on Gmsh's Blossom-recombined quadrilaterals (same
/// geometry file, same element size and contact-arc nodes as the P1 mesh,
/// within 1.3% of its nodes): at a tight tolerance the pressures are PETSc's
/// SNES VI's on the same mesh to 1e-6 of the peak (measured 2e-9 to 1e-8),
/// and the pressure error against Hertz is the P1
/// mesh's within 0.1 point (both about 2-3%: Hertz's half-space model,
/// not the discretization, dominates it; bench/q1 has all five sizes).
#[test]
fn hertz_on_quadrilaterals() {
    for (quad, p1) in [
        ("meshes/hertz_quad_442.msh", "meshes/hertz_442.msh"),
        ("meshes/hertz_quad_1692.msh", "meshes/hertz_1692.msh"),
        ("meshes/hertz_mixed_1692.msh", "meshes/hertz_1692.msh"),
    ] {
        let (_, rq, rows) = solve_rows("q1-hertz", 1, &hertz_scene(quad, &TIGHT));
        let (_, rp, _) = solve_rows("q1-hertz-p1", 1, &hertz_scene(p1, &TIGHT));
        let (nq, np) = (rq.nodes, rp.nodes);
        assert!((nq - np).abs() < 0.013 * np, "{quad}: {nq} nodes vs {np}");
        let (_, _, vi) = solve_rows("q1-hertz-vi", 1, &hertz_scene(quad, &SNES_VI));
        let gap = max_pressure_gap(&rows, &vi);
        assert!(gap <= 1e-6, "{quad}: {gap:.2e} from SNES VI's pressures");
        let (eq, ep) = (rq.pressure_error_rel, rp.pressure_error_rel);
        assert!(eq < ep + 1e-3, "{quad}: Hertz error {eq} vs P1 {ep}");
        assert_eq!(rq.contact_nodes, rp.contact_nodes);
    }
}

/// The built-in generators with -mesh_element: the Hertz quarter cylinder
/// as an O-grid of quadrilaterals, the block as hexahedra (the boxes of the
/// tetrahedral grid). Hertz: SNES VI's pressures to 1e-6, error under 4%. Block: hexahedra
/// are softer than the locking-prone P1 tetrahedra (nu = 0.45) on the same
/// grid, and both forces decrease under refinement, the gap closing
/// (bench/q1: 2.0% at 34,476 nodes).
#[test]
fn generated_quadrilaterals_and_hexahedra() {
    let scene = [
        "-options_file",
        "options/hertz",
        "-mesh_generate",
        "hertz2d",
        "-mesh_element",
        "quad",
        "-mesh_h",
        "0.3",
    ];
    let (run, r, rows) = solve_rows("q1-gen-hertz", 2, &[&scene[..], &TIGHT].concat());
    let (_, _, vi) = solve_rows("q1-gen-hertz-vi", 2, &[&scene[..], &SNES_VI].concat());
    assert!(
        run.stdout
            .contains("generated hertz2d, h = 0.3, quadrilaterals"),
        "{}",
        run.stdout
    );
    let gap = max_pressure_gap(&rows, &vi);
    assert!(gap <= 1e-6, "{gap:.2e} from SNES VI's pressures");
    assert!(r.pressure_error_rel < 0.04);
    let force = |h: &str, element: &str| {
        let args = [
            &[
                "-options_file",
                "options/block3d",
                "-mesh_generate",
                "block3d",
                "-mesh_h",
                h,
                "-mesh_element",
                element,
            ][..],
            &TIGHT,
        ]
        .concat();
        let (_, r, _) = solve_rows("q1-gen-block", 2, &args);
        r.contact_force
    };
    let (h1, h2) = (force("0.25", "hex"), force("0.125", "hex"));
    let (t1, t2) = (force("0.25", "tet"), force("0.125", "tet"));
    assert!(h1 < t1 && h2 < t2, "hex {h1} {h2}, tet {t1} {t2}");
    assert!((t2 - h2) < (t1 - h1), "gap {} -> {}", t1 - h1, t2 - h2);
    assert!((h2 - h1).abs() < 0.05 * h2, "hex {h1} -> {h2}");
}

/// Mixed meshes against pure ones of about the same resolution. 2D: the
/// Hertz quarter as triangles + quadrilaterals (Gmsh's simple
/// recombination), as quadrilaterals and as triangles: the pressures at the
/// (same) arc nodes agree within 2.5% of the peak (measured: 1.9% at most),
/// less than each one's error against Hertz (3%). 3D: the block as
/// hexahedra + pyramids + tetrahedra (lower half structured, upper half
/// tetrahedral) and as hexahedra + prisms (an extruded triangle +
/// quadrilateral face): their contact forces lie within the spread of the
/// pure hexahedral and tetrahedral meshes of the same grid size, 3% of it.
#[test]
fn mixed_meshes_match_pure_ones() {
    let p = |mesh: &str| {
        let (_, r, rows) = solve_rows("q1-mixed2d", 1, &hertz_scene(mesh, &TIGHT));
        (r, rows)
    };
    let (rm, mixed) = p("meshes/hertz_mixed_1692.msh");
    let (_, quads) = p("meshes/hertz_quad_1692.msh");
    let (_, tris) = p("meshes/hertz_1692.msh");
    let peak = rm.peak_pressure;
    let at = |rows: &[Row], x: [f64; 3]| {
        rows.iter()
            .find(|r| (r.x[0] - x[0]).abs() < 1e-9 && (r.x[1] - x[1]).abs() < 1e-9)
            .map(|r| r.lambda_n)
    };
    for row in &mixed {
        for other in [&quads, &tris] {
            let v = at(other, row.x).expect("the same arc node");
            assert!(
                (v - row.lambda_n).abs() < 0.025 * peak,
                "node at {:?}: {} vs {v}",
                row.x,
                row.lambda_n
            );
        }
    }
    let force = |extra: &[&str]| {
        let args = [&["-options_file", "options/block3d"][..], extra, &TIGHT].concat();
        let (_, r, _) = solve_rows("q1-mixed3d", 2, &args);
        r.contact_force
    };
    let hex = force(&[
        "-mesh_generate",
        "block3d",
        "-mesh_h",
        "0.125",
        "-mesh_element",
        "hex",
    ]);
    let tet = force(&["-mesh_generate", "block3d", "-mesh_h", "0.125"]);
    let (lo, hi) = (hex.min(tet), hex.max(tet));
    for mesh in [
        "meshes/block3d_mixed_1596.msh",
        "meshes/block3d_extruded_1674.msh",
    ] {
        let f = force(&["-mesh", mesh]);
        assert!(
            f > 0.97 * lo && f < 1.03 * hi,
            "{mesh}: {f} (hex {hex}, tet {tet})"
        );
    }
}

/// -n 1, 2, 3 agree on mixed meshes to 1e-8 (of the peak pressure) at a
/// tight tolerance: the 3D blocks of hexahedra, pyramids and tetrahedra
/// and of hexahedra and prisms, and the 2D Hertz quarter of triangles and
/// quadrilaterals.
/// MUMPS gets 60% more workspace than it estimates (`-mat_mumps_icntl_14
/// 60`): on 3 ranks the extruded block's factorization ran out of it in 3
/// runs of 30 with the default (a PC_FACTOR_OUTMEMORY failure), in none of
/// 30 with this.
#[test]
fn mixed_meshes_rank_counts_agree() {
    for args in [
        vec![
            "-options_file",
            "options/block3d",
            "-mesh",
            "meshes/block3d_mixed_1596.msh",
        ],
        vec![
            "-options_file",
            "options/block3d",
            "-mesh",
            "meshes/block3d_extruded_1674.msh",
        ],
        hertz_scene("meshes/hertz_mixed_1692.msh", &[]),
    ] {
        let args = [
            &args[..],
            &[
                "-ubr_anderson",
                "10",
                "-ubr_stop",
                "paper",
                "-ubr_rtol",
                "1e-12",
                "-mat_mumps_icntl_14",
                "60",
            ],
        ]
        .concat();
        let runs: Vec<Vec<Row>> = (1..=3)
            .map(|n| solve_rows("q1-ranks", n, &args).2)
            .collect();
        let peak = runs[0].iter().map(|r| r.lambda_n).fold(0.0, f64::max);
        assert!(peak > 0.0);
        for (n, rows) in runs.iter().enumerate().skip(1) {
            assert_eq!(rows.len(), runs[0].len());
            for (a, b) in runs[0].iter().zip(rows) {
                assert_eq!(a.node, b.node);
                assert!(
                    (a.lambda_n - b.lambda_n).abs() < 1e-8 * peak,
                    "{args:?}: -n {} node {}: {} vs {}",
                    n + 1,
                    a.node,
                    b.lambda_n,
                    a.lambda_n
                );
            }
        }
    }
}

/// Bad input on the new kinds: an inverted quadrilateral (listed clockwise
/// among counter-clockwise ones) and a folded one (nodes crossed) named by
/// their tags in the file; an inverted and a folded hexahedron; a
/// second-order triangle named in words; -mesh_element misused.
#[test]
fn bad_quadrilaterals_hexahedra_and_types() {
    let dir = scratch("q1-bad");
    let expect = |args: &[&str], words: &[&str]| {
        let run = mpirun(1, args);
        assert_eq!(
            run.status,
            Some(2),
            "{args:?}\n{}\n{}",
            run.stdout,
            run.stderr
        );
        for w in words {
            assert!(
                run.stderr.contains(w),
                "{args:?}: no '{w}' in: {}",
                run.stderr
            );
        }
        // One error line (mpirun adds its own lines about the exit status).
        assert_eq!(run.stderr.matches("error").count(), 1, "{}", run.stderr);
    };
    // The quadrilateral with tag 200 of hertz_quad_442.msh (4.1: "tag n1 n2 n3 n4").
    let text = std::fs::read_to_string(root().join("meshes/hertz_quad_442.msh")).unwrap();
    let (line, nodes) = text
        .lines()
        .find_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f.len() == 5 && f[0] == "200").then(|| {
                (
                    l.to_string(),
                    f[1..].iter().map(|s| s.to_string()).collect::<Vec<_>>(),
                )
            })
        })
        .expect("element 200 is a quadrilateral");
    for (what, order, words) in [
        ("inverted", [0, 3, 2, 1], vec!["element 200", "is inverted"]),
        (
            "folded",
            [0, 1, 3, 2],
            vec!["element 200", "is folded", "quadrilateral"],
        ),
    ] {
        let new = format!("200 {}", order.map(|i| nodes[i].as_str()).join(" "));
        let path = dir.join(format!("{what}.msh"));
        std::fs::write(&path, text.replacen(&line, &new, 1)).unwrap();
        let p = path.to_str().unwrap();
        let mut w = words.clone();
        w.push(&nodes[0]);
        expect(&hertz_scene(p, &[]), &w);
    }
    // Hexahedra: the 27-cell cube with cell 5 upside down (inverted) or two
    // nodes swapped (folded); the tags count the 2.2 file's facets first.
    let (x, cells, groups) = cube(3, false);
    let nfacets: usize = groups.iter().map(|g| g.1.len()).sum();
    let tag = (nfacets + 6).to_string();
    for (what, words) in [
        ("inverted", ["is inverted", tag.as_str()]),
        ("folded", ["is folded", tag.as_str()]),
    ] {
        let mut c = cells.clone();
        let h = c[5].clone();
        c[5] = if what == "inverted" {
            vec![h[4], h[5], h[6], h[7], h[0], h[1], h[2], h[3]]
        } else {
            vec![h[0], h[1], h[2], h[3], h[4], h[5], h[7], h[6]]
        };
        let path = dir.join(format!("hex-{what}.msh"));
        write_msh(&path, 3, &x, &c, &groups);
        let p = path.to_str().unwrap();
        expect(
            &[
                "-mesh",
                p,
                "-E",
                "1000",
                "-nu",
                "0.3",
                "-dirichlet_top",
                "uz=-0.01",
                "-contact_surface",
                "bottom",
                "-contact_direction",
                "0,0,-1",
                "-obstacle",
                "plane",
                "-obstacle_point",
                "0,0,0",
            ],
            &[&format!("element {}", words[1]), words[0]],
        );
    }
    // A second-order triangle.
    let path = dir.join("p2.msh");
    std::fs::write(
        &path,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0.5 0 0\n5 0.5 0.5 0\n6 0 0.5 0\n$EndNodes\n$Elements\n1\n1 9 2 1 1 1 2 3 4 5 6\n$EndElements\n",
    )
    .unwrap();
    expect(
        &hertz_scene(path.to_str().unwrap(), &[]),
        &["p2.msh:15: second-order triangle (Gmsh type 9) is not supported"],
    );
    expect(
        &hertz_scene("meshes/hertz_442.msh", &["-mesh_element", "quad"]),
        &["-mesh_element applies to -mesh_generate only"],
    );
    expect(
        &[
            "-options_file",
            "options/hertz",
            "-mesh_generate",
            "hertz2d",
            "-mesh_element",
            "hex",
        ],
        &["option -mesh_element: 'hex' is not a cell of -mesh_generate hertz2d (tri or quad)"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// VTU output of mixed meshes: every rank writes its cells with their VTK
/// types (10 tetrahedron, 12 hexahedron, 13 wedge, 14 pyramid) and the
/// centre stresses; read back by VTK, the cells are the mesh's, every one
/// with a positive volume (the wedges' points reordered), in all the block's
/// volume, 2.
#[test]
fn vtu_of_mixed_meshes() {
    let dir = scratch("q1-vtk");
    let out = dir.join("mixed.pvtu");
    let o = out.to_str().unwrap();
    let script = "import sys, vtk\nr = vtk.vtkXMLPUnstructuredGridReader()\nr.SetFileName(sys.argv[1])\nr.Update()\ng = r.GetOutput()\nn = g.GetNumberOfCells()\nts = sorted(set(g.GetCellType(c) for c in range(n)))\nf = vtk.vtkCellSizeFilter()\nf.SetInputData(g)\nf.Update()\nv = f.GetOutput().GetCellData().GetArray('Volume')\nprint(n, ','.join(map(str, ts)), min(v.GetValue(c) for c in range(n)), sum(v.GetValue(c) for c in range(n)))\n";
    for (mesh, cells, types) in [
        ("meshes/block3d_mixed_1596.msh", "4517", "10,12,14"),
        ("meshes/block3d_extruded_1674.msh", "1432", "12,13"),
    ] {
        let run = mpirun(
            2,
            &["-options_file", "options/block3d", "-mesh", mesh, "-vtk", o],
        );
        assert_eq!(run.status, Some(0), "{}\n{}", run.stdout, run.stderr);
        let py = std::process::Command::new(python())
            .arg("-c")
            .arg(script)
            .arg(o)
            .output()
            .expect("python3 with vtk (python3-vtk9)");
        let text = String::from_utf8_lossy(&py.stdout).to_string();
        let f: Vec<&str> = text.split_whitespace().collect();
        assert!(
            py.status.success() && f.len() == 4,
            "{text}\n{}",
            String::from_utf8_lossy(&py.stderr)
        );
        assert_eq!((f[0], f[1]), (cells, types), "{mesh}");
        let (min, total): (f64, f64) = (f[2].parse().unwrap(), f[3].parse().unwrap());
        assert!(min > 0.0 && (total - 2.0).abs() < 1e-9, "{mesh}: {text}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A section extruded along z and held in plane strain (u_z = 0 on both end
/// faces) gives the 2D section's contact stresses at every layer of its
/// nodes, and L times its contact force: the quarter cylinder of
/// meshes/hertz.geo on triangles against its prisms (frictionless, 1 rank),
/// on quadrilaterals against its hexahedra (Coulomb with a shear, 3 ranks).
/// An identity of the discretizations: the z-independent field lies in both
/// spaces, and both quadratures are exact on it.
#[test]
fn extruded_section_in_plane_strain_equals_2d() {
    for (rec, coulomb, ranks) in [("0", false, 1), ("1", true, 3)] {
        let dir = scratch(&format!("extruded_{rec}"));
        let (m2, m3) = (dir.join("section.msh"), dir.join("slab.msh"));
        gmsh("-2", "meshes/hertz.geo", &m2, &[("recombine", rec)]);
        gmsh(
            "-3",
            "tests/edges/extruded_hertz.geo",
            &m3,
            &[("recombine", rec), ("L", "2"), ("nl", "3")],
        );
        let (m2, m3) = (m2.to_str().unwrap(), m3.to_str().unwrap());
        let mut both = vec![
            "-E",
            "2000",
            "-nu",
            "0.3",
            "-dirichlet_symmetry",
            "ux=0",
            "-contact_surface",
            "contact",
            "-obstacle",
            "plane",
            "-ubr_lambda_rtol",
            "1e-10",
        ];
        if coulomb {
            both.extend(["-friction", "coulomb", "-friction_coefficient", "0.3"]);
        }
        let mut a2 = both.clone();
        a2.extend([
            "-mesh",
            m2,
            "-contact_direction",
            "0,-1",
            "-obstacle_point",
            "0,0",
        ]);
        a2.extend(["-traction_top", if coulomb { "20,-100" } else { "0,-100" }]);
        let mut a3 = both;
        a3.extend([
            "-mesh",
            m3,
            "-contact_direction",
            "0,-1,0",
            "-obstacle_point",
            "0,0,0",
        ]);
        a3.extend(["-dirichlet_front", "uz=0", "-dirichlet_back", "uz=0"]);
        a3.extend([
            "-traction_top",
            if coulomb { "20,-100,0" } else { "0,-100,0" },
        ]);
        let (_, r2, rows2) = solve_rows(&format!("extruded_{rec}_2d"), 1, &a2);
        let (run, r3, rows3) = solve_rows(&format!("extruded_{rec}_3d"), ranks, &a3);
        let force = r3.contact_force / 2.0;
        assert!(
            (force - r2.contact_force).abs() <= 1e-9 * r2.contact_force,
            "{rec}: {force} per unit length against {}",
            r2.contact_force
        );
        let key = |x: &[f64; 3]| ((x[0] * 1e9).round() as i64, (x[1] * 1e9).round() as i64);
        let section: std::collections::HashMap<_, _> =
            rows2.iter().map(|r| (key(&r.x), r)).collect();
        let peak = rows2.iter().map(|r| r.lambda_n.abs()).fold(0.0, f64::max);
        assert_eq!(
            rows3.len(),
            4 * rows2.len(),
            "{rec}: four layers of candidates"
        );
        for r in &rows3 {
            let s = section[&key(&r.x)];
            let gap = (r.lambda_n - s.lambda_n)
                .abs()
                .max((r.lambda_t[0] - s.lambda_t[0]).abs())
                .max((r.lambda_t[1] - s.lambda_t[1]).abs())
                .max(r.lambda_t[2].abs());
            assert!(
                gap <= 1e-8 * peak,
                "{rec}: node {} at {:?}: {gap:.3e} of {peak}\n{}",
                r.node,
                r.x,
                run.stdout
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
