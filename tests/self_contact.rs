//! A body in contact with itself: `-contact_pair` of two surfaces of one
//! body (a crack's faces, the two sides of a slot), which facing each
//! other across a gap or touching are a pair like any other; the tip
//! where they meet is no candidate, and two faces with the master behind
//! the slave through the body are refused (tests/pairs.rs,
//! `bad_pairs_are_refused`).

mod common;
use common::*;

/// Opens the line `crack` of the MSH 2.2 mesh `text` into an edge crack:
/// its nodes on x = 0.5 stays one (the tip), every other gets a copy at
/// the same place, taken by the triangles above y = 0.5 and by the part of
/// group `left` above it; the upper face is group `crack_top` (its lines
/// reversed: the triangles above lie on their left), the lower stays
/// `crack`.
fn open_crack(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let at = |s: &str| lines.iter().position(|l| *l == s).unwrap();
    let (n0, e0) = (at("$Nodes"), at("$Elements"));
    let nodes: Vec<(usize, [f64; 2])> = lines[n0 + 2..at("$EndNodes")]
        .iter()
        .map(|l| {
            let w: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            (w[0] as usize, [w[1], w[2]])
        })
        .collect();
    let x: std::collections::HashMap<usize, [f64; 2]> = nodes.iter().copied().collect();
    let mut elems: Vec<Vec<usize>> = lines[e0 + 2..at("$EndElements")]
        .iter()
        .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
        .collect();
    let names = &lines[at("$PhysicalNames") + 2..at("$EndPhysicalNames")];
    let tag = |name: &str| -> usize {
        let l = names
            .iter()
            .find(|l| l.ends_with(&format!("\"{name}\"")))
            .unwrap();
        l.split_whitespace().nth(1).unwrap().parse().unwrap()
    };
    let (crack, left) = (tag("crack"), tag("left"));
    let on_crack: Vec<Vec<usize>> = elems
        .iter()
        .filter(|e| e[1] == 1 && e[3] == crack)
        .cloned()
        .collect();
    let mut copy = std::collections::BTreeMap::new();
    let mut next = nodes.iter().map(|n| n.0).max().unwrap();
    for e in &on_crack {
        for &v in &e[e.len() - 2..] {
            if (x[&v][0] - 0.5).abs() > 1e-12 && !copy.contains_key(&v) {
                next += 1;
                copy.insert(v, next);
            }
        }
    }
    let above = |vs: &[usize], k: usize| vs.iter().map(|v| x[v][1]).sum::<f64>() / k as f64 > 0.5;
    for e in elems.iter_mut() {
        let n = e.len();
        let moved = match e[1] {
            2 => above(&e[n - 3..], 3),
            1 => e[3] == left && above(&e[n - 2..], 2),
            _ => false,
        };
        if moved {
            let first = 3 + e[2];
            for v in e[first..].iter_mut() {
                *v = *copy.get(v).unwrap_or(v);
            }
        }
    }
    let mut id = elems.len();
    for e in &on_crack {
        id += 1;
        let (a, b) = (e[e.len() - 2], e[e.len() - 1]);
        let c = |v: usize| *copy.get(&v).unwrap_or(&v);
        elems.push(vec![id, 1, 2, 100, 100, c(b), c(a)]);
    }
    let mut out = vec!["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames"]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>();
    out.push((names.len() + 1).to_string());
    out.extend(names.iter().map(|s| s.to_string()));
    out.push("1 100 \"crack_top\"".into());
    out.extend(["$EndPhysicalNames".into(), "$Nodes".into()]);
    out.push((nodes.len() + copy.len()).to_string());
    for (v, p) in &nodes {
        out.push(format!("{v} {} {} 0", p[0], p[1]));
    }
    for (v, c) in &copy {
        out.push(format!("{c} {} {} 0", x[v][0], x[v][1]));
    }
    out.extend([
        "$EndNodes".into(),
        "$Elements".into(),
        elems.len().to_string(),
    ]);
    for e in &elems {
        let w: Vec<String> = e.iter().map(|v| v.to_string()).collect();
        out.push(w.join(" "));
    }
    out.push("$EndElements".into());
    out.join("\n") + "\n"
}

/// A body in contact with itself (`-contact_pair` of two surfaces of one
/// body, issue "Two elastic bodies" left it refused): the unit square
/// with an edge crack (tests/pairs/crack2d.geo, opened by `open_crack`)
/// pressed by 10 on its top, its bottom held. The closed crack carries the
/// uniform stress: the pressure is 10 at every node of its upper face to
/// 1e-8 (measured 1e-11), on 1 and 2 ranks; the tip, a node of both faces,
/// is no candidate. Two faces of one body with the master behind the
/// slave, through the body, are refused as before (`bad_pairs_are_refused`).
#[test]
fn a_crack_closed_by_pressure_carries_it() {
    let (dir, plain) = gmsh_2d("pairs-crack", "tests/pairs/crack2d.geo");
    let msh = dir.join("crack.msh");
    std::fs::write(&msh, open_crack(&std::fs::read_to_string(&plain).unwrap())).unwrap();
    let msh = msh.to_str().unwrap();
    let args = [
        "-mesh",
        msh,
        "-E",
        "1000",
        "-nu",
        "0.3",
        "-dirichlet_bottom",
        "uy=0",
        "-dirichlet_corner",
        "ux=0",
        "-pressure_top",
        "10",
        "-contact_pair",
        "crack_top,crack",
        "-ubr_lambda_rtol",
        "1e-10",
    ];
    for ranks in [1, 2] {
        let (run, report, rows) = solve_rows(&format!("crack-{ranks}"), ranks, &args);
        assert!(report.converged, "{}", run.stdout);
        // The crack's nodes but its tip: 28 at h / 2 to h / 4.
        assert!(rows.len() >= 20, "{} candidates", rows.len());
        every_pressure_is(10.0, &rows, ranks);
        assert!(!run.stderr.contains("warning"), "{}", run.stderr);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every candidate of `rows` in contact at pressure `p`, to 1e-7.
fn every_pressure_is(p: f64, rows: &[Row], ranks: usize) {
    for r in rows {
        assert!(
            (r.lambda_n - p).abs() < 1e-7 && r.status != "open",
            "{ranks} ranks: node {} at {:?}: {} ({})",
            r.node,
            r.x,
            r.lambda_n,
            r.status
        );
    }
}

/// A C-shaped block closing on itself in 3D (tests/pairs/slot3d.geo): its
/// arms pressed together by 1 on the top and the bottom, the left side
/// held, the back held in z; the slot (0.1 wide) closes at its mouth. The
/// pair's force balances: the loads cancel, the contact's force is the
/// scale of the balance; 1 and 2 ranks agree to 1e-8. Measured: 8 nodes in
/// contact, force 0.2055.
#[test]
fn a_slot_closing_in_3d() {
    let dir = scratch("self-slot3d");
    let msh = dir.join("slot3d.msh");
    gmsh("-3", "tests/pairs/slot3d.geo", &msh, &[]);
    let msh = msh.to_str().unwrap();
    let args = [
        "-mesh",
        msh,
        "-E",
        "1000",
        "-nu",
        "0.3",
        "-dirichlet_left",
        "ux=0,uy=0",
        "-dirichlet_back",
        "uz=0",
        "-traction_top",
        "0,-1,0",
        "-traction_bottom",
        "0,1,0",
        "-contact_pair",
        "slot_top,slot_bottom",
        "-ubr_lambda_rtol",
        "1e-10",
    ];
    let (run, report, one) = solve_rows("slot3d-1", 1, &args);
    assert!(report.converged, "{}", run.stdout);
    let touching = one.iter().filter(|r| r.status != "open").count();
    assert!(touching >= 4, "{touching} nodes in contact\n{}", run.stdout);
    let balance = run
        .stdout
        .lines()
        .find(|l| l.contains("balance"))
        .and_then(|l| l.split("balance ").nth(1))
        .and_then(|w| w.split_whitespace().next())
        .map(|w| w.parse::<f64>().unwrap())
        .expect("the forces line");
    assert!(balance < 1e-8, "{}", run.stdout);
    let (_, _, two) = solve_rows("slot3d-2", 2, &args);
    let gap = max_pressure_gap(&one, &two);
    assert!(gap < 1e-8, "1 and 2 ranks differ by {gap:.3e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The unit cube, n x n x n cubes (n even) of 6 tetrahedra each (Kuhn's
/// split, every square face cut along its (i, j) -> (i + 1, j + 1)
/// diagonal), with a crack in the plane z = 0.5 from x = 0 to its front x
/// = 0.5 (through in y): the crack's nodes but the front's doubled, the
/// copies taken by the cubes above. MSH 2.2; groups top, bottom (z = 1, 0),
/// crack_top, crack_bottom (the faces, outward), p0 = (0, 0, 0), p1 = (1,
/// 0, 0), body.
fn cracked_cube(n: usize) -> String {
    let m = n + 1;
    let id = |i: usize, j: usize, k: usize| 1 + i + m * (j + m * k);
    let half = n / 2;
    // The copy of crack node (i, j) (i < half), numbered after the grid.
    let copy = |i: usize, j: usize| m * m * m + 1 + i + half * j;
    let mut nodes: Vec<String> = Vec::new();
    for k in 0..m {
        for j in 0..m {
            for i in 0..m {
                let h = 1.0 / n as f64;
                nodes.push(format!(
                    "{} {} {} {}",
                    id(i, j, k),
                    i as f64 * h,
                    j as f64 * h,
                    k as f64 * h
                ));
            }
        }
    }
    for j in 0..m {
        for i in 0..half {
            let h = 1.0 / n as f64;
            nodes.push(format!(
                "{} {} {} 0.5",
                copy(i, j),
                i as f64 * h,
                j as f64 * h
            ));
        }
    }
    // A node of the cube (i, j, k) at its corner (a, b, c): the copy where
    // the cube lies above the crack and the corner on it.
    let at = |i: usize, j: usize, k: usize, a: usize, b: usize, c: usize| {
        let (x, y, z) = (i + a, j + b, k + c);
        if k >= half && z == half && x < half {
            copy(x, y)
        } else {
            id(x, y, z)
        }
    };
    let mut elems: Vec<String> = vec![
        format!("15 2 5 5 {}", id(0, 0, 0)),
        format!("15 2 6 6 {}", id(n, 0, 0)),
    ];
    let tri = |tag: usize, v: [usize; 3], up: bool| {
        let [a, b, c] = v;
        if up {
            format!("2 2 {tag} {tag} {a} {b} {c}")
        } else {
            format!("2 2 {tag} {tag} {a} {c} {b}")
        }
    };
    for j in 0..n {
        for i in 0..n {
            // Each square of a z-plane, from its cube's corners (0/1).
            let sq = |k: usize, c: usize| {
                let v = |a, b| at(i, j, k, a, b, c);
                [[v(0, 0), v(1, 0), v(1, 1)], [v(0, 0), v(1, 1), v(0, 1)]]
            };
            for t in sq(n - 1, 1) {
                elems.push(tri(1, t, true));
            }
            for t in sq(0, 0) {
                elems.push(tri(2, t, false));
            }
            if i < half {
                for t in sq(half, 0) {
                    elems.push(tri(3, t, false));
                }
                for t in sq(half - 1, 1) {
                    elems.push(tri(4, t, true));
                }
            }
        }
    }
    let steps = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                for s in steps {
                    let mut c = [0usize; 3];
                    let mut tet = vec![at(i, j, k, 0, 0, 0)];
                    for d in s {
                        c[d] = 1;
                        tet.push(at(i, j, k, c[0], c[1], c[2]));
                    }
                    // (An odd permutation's tetrahedron turned positive.)
                    if matches!(s, [0, 2, 1] | [1, 0, 2] | [2, 1, 0]) {
                        tet.swap(2, 3);
                    }
                    let w: Vec<String> = tet.iter().map(|v| v.to_string()).collect();
                    elems.push(format!("4 2 7 7 {}", w.join(" ")));
                }
            }
        }
    }
    let mut out = vec![
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat".to_string(),
        "$PhysicalNames\n7\n2 1 \"top\"\n2 2 \"bottom\"\n2 3 \"crack_top\"\n2 4 \"crack_bottom\"\n0 5 \"p0\"\n0 6 \"p1\"\n3 7 \"body\"\n$EndPhysicalNames".to_string(),
        format!("$Nodes\n{}", nodes.len()),
    ];
    out.extend(nodes);
    out.push(format!("$EndNodes\n$Elements\n{}", elems.len()));
    out.extend(
        elems
            .iter()
            .enumerate()
            .map(|(e, s)| format!("{} {s}", e + 1)),
    );
    out.push("$EndElements\n".into());
    out.join("\n")
}

/// The crack of `a_crack_closed_by_pressure_carries_it` in 3D: a cube
/// cracked to its middle (`cracked_cube`, 6 x 6 x 6 cubes), its front a
/// line of nodes on both faces (no candidates), the crack through in y.
/// Under a pressure of 10 on its top (the bottom held along z, two
/// corners across) the pressure is 10 at every candidate, the 21 copied
/// nodes, to 1e-8 (measured 1.7e-11 on a Gmsh mesh, 1-3 ranks).
#[test]
fn a_crack_front_in_3d() {
    let dir = scratch("self-crack3d");
    let msh = dir.join("cube.msh");
    std::fs::write(&msh, cracked_cube(6)).unwrap();
    let msh = msh.to_str().unwrap();
    let args = [
        "-mesh",
        msh,
        "-E",
        "1000",
        "-nu",
        "0.3",
        "-dirichlet_bottom",
        "uz=0",
        "-dirichlet_p0",
        "ux=0,uy=0",
        "-dirichlet_p1",
        "uy=0",
        "-pressure_top",
        "10",
        "-contact_pair",
        "crack_top,crack_bottom",
        "-ubr_lambda_rtol",
        "1e-10",
    ];
    for ranks in [1, 2] {
        let (run, report, rows) = solve_rows(&format!("crack3d-{ranks}"), ranks, &args);
        assert!(report.converged, "{}", run.stdout);
        assert_eq!(rows.len(), 21, "{}", run.stdout);
        every_pressure_is(10.0, &rows, ranks);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
