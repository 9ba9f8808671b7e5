//! Patch tests: a linear displacement field (a uniform stress state) is
//! reproduced to round-off on distorted meshes of Q1 cells, alone and mixed
//! with P1 cells, in 2D and 3D; with the field prescribed on the boundary
//! (the interior solved for), and with the uniform traction it produces
//! loaded on the boundary through the nodal facet weights (the weights of a
//! non-parallelogram quadrilateral facet included).

use super::*;
use nalgebra::{DMatrix, DVector};

struct Patch {
    dim: usize,
    x: Vec<f64>,
    cells: Vec<Vec<usize>>,
    /// Boundary facets, oriented outward.
    facets: Vec<Vec<usize>>,
    boundary: Vec<bool>,
}

/// Deterministic pseudo-random shifts in [-s, s].
fn shift(i: usize, k: usize, s: f64) -> f64 {
    let v = ((i * 7919 + k * 104_729 + 17) % 1000) as f64 / 999.0;
    s * (2.0 * v - 1.0)
}

/// An `n x n` grid of the square [0,2]x[0,1.5], interior nodes moved by up
/// to 0.3 cell, boundary nodes moved along their edge (corners fixed);
/// the cells where `split(i, j)` are split into two triangles.
fn patch_2d(n: usize, split: impl Fn(usize, usize) -> bool) -> Patch {
    let (lx, ly) = (2.0, 1.5);
    let id = |i: usize, j: usize| j * (n + 1) + i;
    let mut x = Vec::new();
    let mut boundary = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (bx, by) = (i == 0 || i == n, j == 0 || j == n);
            let s = 0.3 / n as f64;
            let dx = if bx { 0.0 } else { shift(id(i, j), 0, s) };
            let dy = if by { 0.0 } else { shift(id(i, j), 1, s) };
            x.push(lx * (i as f64 / n as f64 + dx));
            x.push(ly * (j as f64 / n as f64 + dy));
            boundary.push(bx || by);
        }
    }
    let mut cells = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if split(i, j) {
                cells.push(vec![q[0], q[1], q[2]]);
                cells.push(vec![q[0], q[2], q[3]]);
            } else {
                cells.push(q.to_vec());
            }
        }
    }
    let mut facets = Vec::new();
    for i in 0..n {
        facets.push(vec![id(i, 0), id(i + 1, 0)]);
        facets.push(vec![id(i + 1, n), id(i, n)]);
        facets.push(vec![id(n, i), id(n, i + 1)]);
        facets.push(vec![id(0, i + 1), id(0, i)]);
    }
    Patch {
        dim: 2,
        x,
        cells,
        facets,
        boundary,
    }
}

/// An `n^3` grid of the box [0,1]x[0,1.2]x[0,0.8] of hexahedra, nodes
/// moved (boundary nodes within their face plane, so the faces are
/// planar but the quadrilateral facets are not parallelograms).
fn patch_3d(n: usize) -> Patch {
    let l = [1.0, 1.2, 0.8];
    let id = |i: usize, j: usize, k: usize| (k * (n + 1) + j) * (n + 1) + i;
    let mut x = Vec::new();
    let mut boundary = Vec::new();
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                let on = [i == 0 || i == n, j == 0 || j == n, k == 0 || k == n];
                for (a, ijk) in [i, j, k].into_iter().enumerate() {
                    let d = if on[a] {
                        0.0
                    } else {
                        shift(id(i, j, k), a, 0.25 / n as f64)
                    };
                    x.push(l[a] * (ijk as f64 / n as f64 + d));
                }
                boundary.push(on.iter().any(|&b| b));
            }
        }
    }
    let mut cells = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = |a: usize, b: usize, e: usize| id(i + a, j + b, k + e);
                cells.push(vec![
                    c(0, 0, 0),
                    c(1, 0, 0),
                    c(1, 1, 0),
                    c(0, 1, 0),
                    c(0, 0, 1),
                    c(1, 0, 1),
                    c(1, 1, 1),
                    c(0, 1, 1),
                ]);
            }
        }
    }
    let facets = boundary_facets(&cells);
    Patch {
        dim: 3,
        x,
        cells,
        facets,
        boundary,
    }
}

/// The faces of a positively oriented 3D cell, outward.
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

/// The faces used by one cell only (the others by exactly two: conforming).
fn boundary_facets(cells: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let mut count = std::collections::HashMap::new();
    for c in cells {
        for f in faces(c.len()) {
            let q: Vec<usize> = f.iter().map(|&a| c[a]).collect();
            let mut key = q.clone();
            key.sort_unstable();
            count.entry(key).or_insert((0, q)).0 += 1;
        }
    }
    assert!(count.values().all(|(k, _)| *k <= 2), "non-conforming");
    let mut facets: Vec<Vec<usize>> = count
        .into_values()
        .filter(|(k, _)| *k == 1)
        .map(|(_, q)| q)
        .collect();
    facets.sort();
    facets
}

/// The 3x3x3 patch with its centre hexahedron split into 6 pyramids
/// (apex inside), its corner hexahedron at the origin into 6 pyramids of
/// which the three on the boundary are split into 2 tetrahedra each, and
/// the column of hexahedra along the edge x = 1, y = 0 into 2 prisms each.
fn patch_3d_mixed() -> Patch {
    let mut p = patch_3d(3);
    let hexes = std::mem::take(&mut p.cells);
    for (c, h) in hexes.into_iter().enumerate() {
        let (i, j) = (c % 3, (c / 3) % 3);
        if c == 13 || c == 0 {
            let centre: Vec<f64> = (0..3)
                .map(|r| {
                    h.iter().map(|&v| p.x[v * 3 + r]).sum::<f64>() / 8.0 + 0.02 * (r as f64 - 1.0)
                })
                .collect();
            let apex = p.x.len() / 3;
            p.x.extend_from_slice(&centre);
            p.boundary.push(false);
            for (fi, f) in faces(8).iter().enumerate() {
                let base: Vec<usize> = f.iter().rev().map(|&a| h[a]).collect();
                // Faces 0 (z = 0), 2 (y = 0), 5 (x = 0) of the corner cell.
                if c == 0 && [0, 2, 5].contains(&fi) {
                    p.cells.push(vec![base[0], base[1], base[2], apex]);
                    p.cells.push(vec![base[0], base[2], base[3], apex]);
                } else {
                    p.cells.push([base.as_slice(), &[apex]].concat());
                }
            }
        } else if i == 2 && j == 0 {
            p.cells.push(vec![h[0], h[1], h[2], h[4], h[5], h[6]]);
            p.cells.push(vec![h[0], h[2], h[3], h[4], h[6], h[7]]);
        } else {
            p.cells.push(h);
        }
    }
    p.facets = boundary_facets(&p.cells);
    p
}

/// The `n^3` grid of [`patch_3d`] with every hexahedron cut into the six
/// tetrahedra around its diagonal from (0,0,0) to (1,1,1) (Kuhn's
/// subdivision: the same in every cell, so the face diagonals match),
/// each oriented positively.
fn patch_3d_tetrahedra(n: usize) -> Patch {
    let mut p = patch_3d(n);
    let hexes = std::mem::take(&mut p.cells);
    // Hexahedron corners by their offsets (a, b, c) in {0, 1}^3.
    let corner = |h: &[usize], o: [usize; 3]| match o {
        [0, 0, 0] => h[0],
        [1, 0, 0] => h[1],
        [1, 1, 0] => h[2],
        [0, 1, 0] => h[3],
        [0, 0, 1] => h[4],
        [1, 0, 1] => h[5],
        [1, 1, 1] => h[6],
        _ => h[7],
    };
    let x = p.x.clone();
    let signed = |t: &[usize]| {
        let e = |a: usize, r: usize| x[t[a] * 3 + r] - x[t[0] * 3 + r];
        let (u, v, w) = (
            [0, 1, 2].map(|r| e(1, r)),
            [0, 1, 2].map(|r| e(2, r)),
            [0, 1, 2].map(|r| e(3, r)),
        );
        u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0])
    };
    for h in &hexes {
        for perm in [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ] {
            let mut o = [0usize; 3];
            let mut t = vec![corner(h, o)];
            for &axis in &perm {
                o[axis] = 1;
                t.push(corner(h, o));
            }
            if signed(&t) < 0.0 {
                t.swap(2, 3);
            }
            p.cells.push(t);
        }
    }
    p.facets = boundary_facets(&p.cells);
    p
}

fn assemble(p: &Patch, young: f64, nu: f64) -> DMatrix<f64> {
    let d = p.dim;
    let n = p.x.len() / d;
    let mut k = DMatrix::zeros(n * d, n * d);
    let lame = element::lame(young, nu, d, false);
    for c in &p.cells {
        let nl = c.len() * d;
        let mut ke = vec![0.0; nl * nl];
        let pt = |a: usize, r: usize| p.x[c[a] * d + r];
        match (d, c.len()) {
            (2, 3) => {
                let (m, _) = stiffness_2d(
                    &[0, 1, 2].map(|a| [pt(a, 0), pt(a, 1)]),
                    &hooke_2d(young, nu, false),
                );
                ke.copy_from_slice(m.transpose().as_slice());
            }
            (2, 4) => {
                let xs: [[f64; 2]; 4] = std::array::from_fn(|a| [pt(a, 0), pt(a, 1)]);
                let mut l = [0.0; 4];
                element::q1_stiffness(&xs, element::quad_rule(), lame, &mut ke, &mut l).unwrap();
            }
            (3, 4) => {
                // The closed form that the assembly uses (cell_stiffness).
                let xs = [0, 1, 2, 3].map(|a| [pt(a, 0), pt(a, 1), pt(a, 2)]);
                let vol = stiffness_p1_3d_into(&xs, lame, &mut ke);
                assert!(vol > 0.0, "a tetrahedron of volume {vol}");
            }
            (3, k) => {
                let xs: Vec<[f64; 3]> = (0..k).map(|a| [pt(a, 0), pt(a, 1), pt(a, 2)]).collect();
                let mut l = [0.0; 8];
                element::hex_family_stiffness(&xs, lame, &mut ke, &mut l).unwrap();
            }
            _ => unreachable!(),
        }
        for (ia, &a) in c.iter().enumerate() {
            for (ib, &b) in c.iter().enumerate() {
                for r in 0..d {
                    for s in 0..d {
                        k[(a * d + r, b * d + s)] += ke[(ia * d + r) * nl + ib * d + s];
                    }
                }
            }
        }
    }
    k
}

/// The linear field u = G x + c and its stress (plane strain in 2D).
fn field(d: usize) -> (DMatrix<f64>, Vec<f64>) {
    let g = DMatrix::from_fn(d, d, |r, s| {
        1e-3 * (1.0 + r as f64 + 2.0 * s as f64) * if r == s { 1.0 } else { 0.4 }
    });
    (g, vec![2e-4, -1e-4, 3e-4][..d].to_vec())
}

fn exact(p: &Patch) -> DVector<f64> {
    let d = p.dim;
    let (g, c) = field(d);
    DVector::from_fn(p.x.len(), |i, _| {
        let (a, r) = (i / d, i % d);
        c[r] + (0..d).map(|s| g[(r, s)] * p.x[a * d + s]).sum::<f64>()
    })
}

/// Solves K u = f with the dofs in `fixed` set to the exact field.
fn solve(
    k: &DMatrix<f64>,
    f: &DVector<f64>,
    fixed: &[bool],
    u_exact: &DVector<f64>,
) -> DVector<f64> {
    let n = f.len();
    let free: Vec<usize> = (0..n).filter(|&i| !fixed[i]).collect();
    let mut rhs = DVector::from_fn(free.len(), |i, _| f[free[i]]);
    for (fi, &i) in free.iter().enumerate() {
        for j in (0..n).filter(|&j| fixed[j]) {
            rhs[fi] -= k[(i, j)] * u_exact[j];
        }
    }
    let kff = DMatrix::from_fn(free.len(), free.len(), |a, b| k[(free[a], free[b])]);
    let uf = kff.lu().solve(&rhs).expect("nonsingular");
    let mut u = u_exact.clone();
    for (fi, &i) in free.iter().enumerate() {
        u[i] = uf[fi];
    }
    u
}

fn check(p: &Patch, what: &str) {
    let d = p.dim;
    let (young, nu) = (1000.0, 0.3);
    let k = assemble(p, young, nu);
    let ue = exact(p);
    let scale = ue.amax();
    // Dirichlet patch test: the field on the boundary, the interior solved.
    let fixed: Vec<bool> = (0..p.x.len()).map(|i| p.boundary[i / d]).collect();
    let u = solve(&k, &DVector::zeros(p.x.len()), &fixed, &ue);
    let err = (&u - &ue).amax() / scale;
    assert!(err < 1e-12, "{what}, Dirichlet: error {err:e}");
    // Neumann patch test: the traction sigma n on the boundary facets
    // through their nodal weights; rigid motions held by the exact
    // values at the dofs of two (2D) or three (3D) corners.
    let (g, _) = field(d);
    let eps = (&g + g.transpose()) * 0.5;
    let (lambda, mu) = element::lame(young, nu, d, false);
    let sigma = DMatrix::identity(d, d) * (lambda * eps.trace()) + &eps * (2.0 * mu);
    let mut f = DVector::zeros(p.x.len());
    let mut w = Vec::new();
    for e in &p.facets {
        let pts: Vec<&[f64]> = e.iter().map(|&v| &p.x[v * d..(v + 1) * d]).collect();
        // Outward unit normal of the (planar) facet.
        let nrm: Vec<f64> = if d == 2 {
            let t = [pts[1][0] - pts[0][0], pts[1][1] - pts[0][1]];
            let l = t[0].hypot(t[1]);
            vec![t[1] / l, -t[0] / l]
        } else {
            let m = pts.len();
            let u = [0, 1, 2].map(|r| pts[2][r] - pts[0][r]);
            let v = [0, 1, 2].map(|r| pts[m - 1][r] - pts[1][r]);
            let c = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let l = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
            c.iter().map(|x| x / l).collect()
        };
        element::facet_weights(&pts, &mut w);
        for (&v, &wa) in e.iter().zip(&w) {
            for r in 0..d {
                let t: f64 = (0..d).map(|s| sigma[(r, s)] * nrm[s]).sum();
                f[v * d + r] += wa * t;
            }
        }
    }
    let n = p.x.len() / d;
    let mut fixed = vec![false; p.x.len()];
    // Three corners of the 3x3x3 grid in 3D: (0,0,0), (1,0,0), (0,1.2,0).
    let corners: Vec<usize> = if d == 2 {
        vec![0, n - 1]
    } else {
        vec![0, 3, 12]
    };
    for &c in &corners {
        for r in 0..d {
            fixed[c * d + r] = true;
        }
    }
    let u = solve(&k, &f, &fixed, &ue);
    let err = (&u - &ue).amax() / scale;
    assert!(err < 1e-10, "{what}, Neumann: error {err:e}");
}

#[test]
fn q1_quadrilaterals_2d() {
    check(&patch_2d(4, |_, _| false), "quadrilaterals");
}

#[test]
fn triangles_and_quadrilaterals_2d() {
    check(
        &patch_2d(4, |i, j| (i + j) % 2 == 1),
        "triangles + quadrilaterals",
    );
}

#[test]
fn p1_triangles_2d() {
    check(&patch_2d(4, |_, _| true), "triangles");
}

#[test]
fn p1_tetrahedra_3d() {
    let p = patch_3d_tetrahedra(3);
    assert!(p.cells.iter().all(|c| c.len() == 4) && p.cells.len() == 6 * 27);
    assert!(p.facets.iter().all(|f| f.len() == 3));
    check(&p, "tetrahedra");
}

#[test]
fn q1_hexahedra_3d() {
    check(&patch_3d(3), "hexahedra");
}

#[test]
fn hexahedra_prisms_pyramids_tetrahedra_3d() {
    let p = patch_3d_mixed();
    for k in [4, 5, 6, 8] {
        assert!(p.cells.iter().any(|c| c.len() == k));
    }
    assert!(p.facets.iter().any(|f| f.len() == 3) && p.facets.iter().any(|f| f.len() == 4));
    check(&p, "hexahedra + prisms + pyramids + tetrahedra");
}
