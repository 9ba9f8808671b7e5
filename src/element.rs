//! Q1 (isoparametric) elements: the bilinear quadrilateral in 2D and the
//! trilinear hexahedron in 3D, integrated by 2x2 and 2x2x2 Gauss points;
//! the 6-node prism and the 5-node pyramid as degenerate hexahedra; and the
//! nodal weights of boundary facets (points, segments, triangles,
//! quadrilaterals).
//!
//! # Prisms and pyramids
//! A prism is the hexahedron with corners `[0, 1, 2, 2, 3, 4, 5, 5]` of its
//! nodes, a pyramid the one with corners `[0, 1, 2, 3, 4, 4, 4, 4]`
//! ([`PRISM_AS_HEX`], [`PYRAMID_AS_HEX`]): the trilinear map collapses an
//! edge of each square face pair, or the whole top face, which is Duffy's
//! collapsed-coordinate map. Summing the shape functions of the merged
//! corners gives, for the prism, the usual `P1(triangle) x P1(segment)`
//! basis, and for the pyramid the rational basis of Bedrosian (1992),
//! `N_i = (1 - z + xi_i x)(1 - z + eta_i y) / (4 (1 - z))`, `N_apex = z`, in
//! Gmsh's reference pyramid: bilinear on the base (conforming with the
//! hexahedra), linear on the triangular faces (conforming with the
//! tetrahedra). Both contain the linear functions, the Jacobian vanishes
//! only on the collapsed edges (never at a Gauss point), and the 2x2x2 rule
//! in the collapsed coordinates integrates `int grad N_a dx` exactly (the
//! integrand is a polynomial there), so the patch test holds as for the
//! hexahedron. The stiffness is the hexahedron's on the repeated
//! coordinates, with the rows and columns of merged corners summed.
//!
//! Reference cells are `[-1, 1]^d`, nodes in Gmsh's order (also VTK's):
//! the quadrilateral's corners counter-clockwise from `(-1, -1)`; the
//! hexahedron's bottom face `zeta = -1` the same way, then its top face.
//! At a Gauss point the Jacobian `J = dx/dxi` maps reference gradients to
//! physical ones, `grad N = J^-T grad_xi N`, and the point's weight is
//! `w |det J|`: a cell listed clockwise (2D) or left-handed (3D) integrates
//! the same as its mirror listing, as for the P1 kernels; a cell whose
//! `det J` changes sign or vanishes at a Gauss point is refused (folded).
//!
//! The stiffness uses the isotropic form, equal to `B^T D B` (a test checks
//! it): `K[(a,i),(b,j)] = int lambda dN_a/dx_i dN_b/dx_j + mu dN_a/dx_j
//! dN_b/dx_i + mu delta_ij grad N_a . grad N_b`, with plane stress's
//! `lambda* = E nu / (1 - nu^2)` in place of `lambda` ([`lame`]). 2x2(x2)
//! Gauss integrates it exactly on parallelograms (parallelepipeds); on
//! distorted cells it still reproduces every linear displacement field
//! exactly (the patch test, `tests` below), because it integrates
//! `int grad N_a dx` exactly.

use nalgebra::SMatrix;
use std::sync::OnceLock;

/// The Gauss points of the 2-point rule on `[-1, 1]` (weights 1).
const G: f64 = 0.577_350_269_189_625_8; // 1 / sqrt(3)

/// Corners of the reference quadrilateral, Gmsh order.
pub const QUAD_CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

/// Corners of the reference hexahedron, Gmsh order.
pub const HEX_CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Hexahedron corner -> prism node (Gmsh's prism: bottom triangle 0 1 2,
/// top triangle 3 4 5 above it).
pub const PRISM_AS_HEX: [usize; 8] = [0, 1, 2, 2, 3, 4, 5, 5];
/// Hexahedron corner -> pyramid node (Gmsh's pyramid: base 0 1 2 3, apex 4).
pub const PYRAMID_AS_HEX: [usize; 8] = [0, 1, 2, 3, 4, 4, 4, 4];
const HEX_AS_HEX: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];

/// The hexahedron corners of a 3D cell of `k` nodes (8, 6 or 5), as nodes
/// of the cell.
pub fn as_hex(k: usize) -> Option<&'static [usize; 8]> {
    match k {
        8 => Some(&HEX_AS_HEX),
        6 => Some(&PRISM_AS_HEX),
        5 => Some(&PYRAMID_AS_HEX),
        _ => None,
    }
}

/// Stiffness of a hexahedron, prism or pyramid whose `k = x.len()` node
/// coordinates are `x`, written into `ke` (`(3k)^2` values, zeroed first),
/// and `int N_a dx` into `lumped[..k]`; returns the measure. A prism or a
/// pyramid is computed as its degenerate hexahedron (module doc).
pub fn hex_family_stiffness(
    x: &[[f64; 3]],
    lame: (f64, f64),
    ke: &mut [f64],
    lumped: &mut [f64],
) -> Result<f64, Folded> {
    let k = x.len();
    let map = as_hex(k).expect("a hexahedron, prism or pyramid");
    let nloc = 3 * k;
    ke[..nloc * nloc].fill(0.0);
    lumped[..k].fill(0.0);
    let x8: [[f64; 3]; 8] = std::array::from_fn(|a| x[map[a]]);
    if k == 8 {
        let mut l8 = [0.0; 8];
        let r = q1_stiffness(&x8, hex_rule(), lame, ke, &mut l8);
        lumped[..8].copy_from_slice(&l8);
        return r;
    }
    let mut k8 = [0.0; 576];
    let mut l8 = [0.0; 8];
    let measure = q1_stiffness(&x8, hex_rule(), lame, &mut k8, &mut l8)?;
    for a in 0..8 {
        lumped[map[a]] += l8[a];
        for b in 0..8 {
            for i in 0..3 {
                let dst = (map[a] * 3 + i) * nloc + map[b] * 3;
                let src = (a * 3 + i) * 24 + b * 3;
                for j in 0..3 {
                    ke[dst + j] += k8[src + j];
                }
            }
        }
    }
    Ok(measure)
}

/// Bilinear shape functions and their reference gradients at `p`.
pub fn q1_2d(p: [f64; 2]) -> ([f64; 4], [[f64; 2]; 4]) {
    let mut n = [0.0; 4];
    let mut dn = [[0.0; 2]; 4];
    for (a, c) in QUAD_CORNERS.iter().enumerate() {
        let (fx, fy) = (0.5 * (1.0 + c[0] * p[0]), 0.5 * (1.0 + c[1] * p[1]));
        n[a] = fx * fy;
        dn[a] = [0.5 * c[0] * fy, 0.5 * c[1] * fx];
    }
    (n, dn)
}

/// Trilinear shape functions and their reference gradients at `p`.
pub fn q1_3d(p: [f64; 3]) -> ([f64; 8], [[f64; 3]; 8]) {
    let mut n = [0.0; 8];
    let mut dn = [[0.0; 3]; 8];
    for (a, c) in HEX_CORNERS.iter().enumerate() {
        let f = [0, 1, 2].map(|k| 0.5 * (1.0 + c[k] * p[k]));
        n[a] = f[0] * f[1] * f[2];
        dn[a] = [
            0.5 * c[0] * f[1] * f[2],
            0.5 * c[1] * f[0] * f[2],
            0.5 * c[2] * f[0] * f[1],
        ];
    }
    (n, dn)
}

/// A quadrature rule tabulated with the shape functions of an `N`-node
/// element of dimension `D`.
pub struct Rule<const N: usize, const D: usize> {
    pub weight: Vec<f64>,
    pub n: Vec<[f64; N]>,
    pub dn: Vec<[[f64; D]; N]>,
}

/// 2x2 Gauss on the reference quadrilateral.
pub fn quad_rule() -> &'static Rule<4, 2> {
    static RULE: OnceLock<Rule<4, 2>> = OnceLock::new();
    RULE.get_or_init(|| {
        let mut r = Rule {
            weight: Vec::new(),
            n: Vec::new(),
            dn: Vec::new(),
        };
        for &y in &[-G, G] {
            for &x in &[-G, G] {
                let (n, dn) = q1_2d([x, y]);
                r.weight.push(1.0);
                r.n.push(n);
                r.dn.push(dn);
            }
        }
        r
    })
}

/// 2x2x2 Gauss on the reference hexahedron.
pub fn hex_rule() -> &'static Rule<8, 3> {
    static RULE: OnceLock<Rule<8, 3>> = OnceLock::new();
    RULE.get_or_init(|| {
        let mut r = Rule {
            weight: Vec::new(),
            n: Vec::new(),
            dn: Vec::new(),
        };
        for &z in &[-G, G] {
            for &y in &[-G, G] {
                for &x in &[-G, G] {
                    let (n, dn) = q1_3d([x, y, z]);
                    r.weight.push(1.0);
                    r.n.push(n);
                    r.dn.push(dn);
                }
            }
        }
        r
    })
}

/// `J[r][c] = dx_r / dxi_c` from the nodes and the reference gradients.
#[inline]
fn jacobian<const N: usize, const D: usize>(
    x: &[[f64; D]; N],
    dn: &[[f64; D]; N],
) -> [[f64; D]; D] {
    let mut j = [[0.0; D]; D];
    for a in 0..N {
        for r in 0..D {
            for c in 0..D {
                j[r][c] += x[a][r] * dn[a][c];
            }
        }
    }
    j
}

/// Determinant and inverse of a 2x2 or 3x3 matrix (the inverse is
/// meaningless when the determinant is 0).
#[inline]
fn det_inv<const D: usize>(m: &[[f64; D]; D]) -> (f64, [[f64; D]; D]) {
    let mut inv = [[0.0; D]; D];
    if D == 2 {
        let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        let s = 1.0 / det;
        inv[0][0] = m[1][1] * s;
        inv[0][1] = -m[0][1] * s;
        inv[1][0] = -m[1][0] * s;
        inv[1][1] = m[0][0] * s;
        (det, inv)
    } else {
        let c = |r: usize, k: usize| m[r % 3][k % 3];
        let mut cof = [[0.0; 3]; 3];
        for (r, row) in cof.iter_mut().enumerate() {
            for (k, v) in row.iter_mut().enumerate() {
                *v = c(r + 1, k + 1) * c(r + 2, k + 2) - c(r + 1, k + 2) * c(r + 2, k + 1);
            }
        }
        let det = m[0][0] * cof[0][0] + m[0][1] * cof[0][1] + m[0][2] * cof[0][2];
        let s = 1.0 / det;
        for r in 0..D {
            for k in 0..D {
                inv[r][k] = cof[k][r] * s;
            }
        }
        (det, inv)
    }
}

/// Physical gradients `grad N_a = J^-T grad_xi N_a` and `det J`.
#[inline]
pub fn gradients<const N: usize, const D: usize>(
    x: &[[f64; D]; N],
    dn: &[[f64; D]; N],
) -> ([[f64; D]; N], f64) {
    let (det, inv) = det_inv(&jacobian(x, dn));
    let mut g = [[0.0; D]; N];
    for a in 0..N {
        for r in 0..D {
            let mut s = 0.0;
            for c in 0..D {
                s += dn[a][c] * inv[c][r];
            }
            g[a][r] = s;
        }
    }
    (g, det)
}

/// Lamé's `(lambda, mu)` of the stiffness: plane stress replaces lambda by
/// `E nu / (1 - nu^2)` (2D only).
pub fn lame(young: f64, nu: f64, dim: usize, plane_stress: bool) -> (f64, f64) {
    let mu = young / (2.0 * (1.0 + nu));
    let lambda = if dim == 2 && plane_stress {
        young * nu / (1.0 - nu * nu)
    } else {
        young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    };
    (lambda, mu)
}

/// A cell whose Jacobian determinant changes sign or vanishes (or is not
/// finite) at a Gauss point: the smallest and largest values seen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Folded {
    pub min_det: f64,
    pub max_det: f64,
}

/// Stiffness of an `N`-node Q1 cell, added into `ke` (`(N D)^2` values,
/// row-major, dofs node-major), the integrals `int N_a dx` added into
/// `lumped` (the row-sum lumped mass); returns the cell's measure.
pub fn q1_stiffness<const N: usize, const D: usize>(
    x: &[[f64; D]; N],
    rule: &Rule<N, D>,
    (lambda, mu): (f64, f64),
    ke: &mut [f64],
    lumped: &mut [f64; N],
) -> Result<f64, Folded> {
    let nd = N * D;
    debug_assert!(ke.len() >= nd * nd);
    let (mut min_det, mut max_det) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut measure = 0.0;
    for q in 0..rule.weight.len() {
        let (g, det) = gradients(x, &rule.dn[q]);
        min_det = min_det.min(det);
        max_det = max_det.max(det);
        let w = rule.weight[q] * det.abs();
        measure += w;
        for (l, n) in lumped.iter_mut().zip(&rule.n[q]) {
            *l += w * n;
        }
        for (a, &ga) in g.iter().enumerate() {
            for (b, &gb) in g.iter().enumerate().skip(a) {
                let mut dot = 0.0;
                for r in 0..D {
                    dot += ga[r] * gb[r];
                }
                for i in 0..D {
                    let row = (a * D + i) * nd + b * D;
                    for j in 0..D {
                        let mut v = lambda * ga[i] * gb[j] + mu * ga[j] * gb[i];
                        if i == j {
                            v += mu * dot;
                        }
                        ke[row + j] += w * v;
                    }
                }
            }
        }
    }
    if !(min_det > 0.0 || max_det < 0.0) || !min_det.is_finite() || !max_det.is_finite() {
        return Err(Folded { min_det, max_det });
    }
    // The lower blocks from the upper ones (K is symmetric).
    for a in 0..N {
        for b in 0..a {
            for i in 0..D {
                for j in 0..D {
                    ke[(a * D + i) * nd + b * D + j] = ke[(b * D + j) * nd + a * D + i];
                }
            }
        }
    }
    Ok(measure)
}

/// The Gauss points' weights and Jacobian determinants `(w, det J)` of a
/// Q1 cell (`dim` = 2: 4 nodes; 3: 8 nodes, or a prism or pyramid as a
/// degenerate hexahedron) whose node coordinates are `x` (`dim` values per
/// node). Empty for any other node count.
pub fn jacobians(dim: usize, x: &[f64]) -> Vec<(f64, f64)> {
    match (dim, x.len()) {
        (3, 15) | (3, 18) => {
            let map = as_hex(x.len() / 3).expect("a prism or pyramid");
            let x8: Vec<f64> = map
                .iter()
                .flat_map(|&a| x[3 * a..3 * a + 3].iter().copied())
                .collect();
            jacobians(3, &x8)
        }
        (2, 8) => {
            let p: [[f64; 2]; 4] = std::array::from_fn(|a| [x[2 * a], x[2 * a + 1]]);
            let r = quad_rule();
            (0..r.weight.len())
                .map(|q| (r.weight[q], det_inv(&jacobian(&p, &r.dn[q])).0))
                .collect()
        }
        (3, 24) => {
            let p: [[f64; 3]; 8] = std::array::from_fn(|a| [x[3 * a], x[3 * a + 1], x[3 * a + 2]]);
            let r = hex_rule();
            (0..r.weight.len())
                .map(|q| (r.weight[q], det_inv(&jacobian(&p, &r.dn[q])).0))
                .collect()
        }
        _ => Vec::new(),
    }
}

/// Physical gradients of the shape functions at the centre of a Q1 cell
/// (`dim` values per node in `x`), node-major: `dim` values per node. For
/// a prism or a pyramid, at the image of its degenerate hexahedron's
/// centre (a pyramid: on its axis, half-way up).
pub fn centre_gradients(dim: usize, x: &[f64]) -> Vec<f64> {
    if dim == 2 {
        let p: [[f64; 2]; 4] = std::array::from_fn(|a| [x[2 * a], x[2 * a + 1]]);
        let (g, _) = gradients(&p, &q1_2d([0.0, 0.0]).1);
        g.iter().flatten().copied().collect()
    } else {
        // A prism or a pyramid: its degenerate hexahedron, merged corners summed.
        let k = x.len() / 3;
        let map = as_hex(k).expect("a hexahedron, prism or pyramid");
        let p: [[f64; 3]; 8] = std::array::from_fn(|a| {
            let v = map[a];
            [x[3 * v], x[3 * v + 1], x[3 * v + 2]]
        });
        let (g, _) = gradients(&p, &q1_3d([0.0, 0.0, 0.0]).1);
        let mut out = vec![0.0; 3 * k];
        for (a, ga) in g.iter().enumerate() {
            for r in 0..3 {
                out[3 * map[a] + r] += ga[r];
            }
        }
        out
    }
}

/// Nodal weights of a boundary facet, `w_a = int_F N_a dA`, given its
/// vertices (in a space of any dimension up to 3). A point weighs 1, a
/// segment gives half its length to each end, a triangle a third of its
/// area to each vertex (the P1 nodal rule of docs/DESIGN.md). A
/// quadrilateral is the bilinear surface through its four vertices, and
/// `w_a` integrates its bilinear shape function over it with 2x2 Gauss
/// points, `dA = |x_xi x x_eta| dxi deta`: exact for a planar facet, a
/// quarter of the area for a parallelogram (and the weights of a uniform
/// traction or pressure are then the consistent nodal forces, which the
/// patch test needs); for a warped facet the same Gauss rule on the
/// bilinear surface. The weights sum to the facet's measure. Any other
/// vertex count gets zero weights.
pub fn facet_weights(pts: &[&[f64]], out: &mut Vec<f64>) {
    out.clear();
    let m = pts.len();
    let sub = |a: &[f64], b: &[f64]| -> [f64; 3] {
        let mut v = [0.0; 3];
        for (k, (x, y)) in a.iter().zip(b).enumerate().take(3) {
            v[k] = x - y;
        }
        v
    };
    let cross_norm = |u: [f64; 3], v: [f64; 3]| {
        let c = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
    };
    match m {
        1 => out.push(1.0),
        2 => {
            let d = sub(pts[1], pts[0]);
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            out.extend_from_slice(&[0.5 * l, 0.5 * l]);
        }
        3 => {
            let a = 0.5 * cross_norm(sub(pts[1], pts[0]), sub(pts[2], pts[0]));
            out.extend_from_slice(&[a / 3.0; 3]);
        }
        4 => {
            out.extend_from_slice(&[0.0; 4]);
            let r = quad_rule();
            for q in 0..r.weight.len() {
                let mut t = [[0.0; 3]; 2];
                for (a, p) in pts.iter().enumerate() {
                    for (k, &xk) in p.iter().enumerate().take(3) {
                        t[0][k] += xk * r.dn[q][a][0];
                        t[1][k] += xk * r.dn[q][a][1];
                    }
                }
                let da = r.weight[q] * cross_norm(t[0], t[1]);
                for (o, n) in out.iter_mut().zip(&r.n[q]) {
                    *o += n * da;
                }
            }
        }
        _ => out.resize(m, 0.0),
    }
}

/// Isotropic Hooke law in Voigt notation (engineering shear strains).
pub fn hooke_2d(young: f64, nu: f64, plane_stress: bool) -> SMatrix<f64, 3, 3> {
    let (c11, c12, c33) = if plane_stress {
        let c = young / (1.0 - nu * nu);
        (c, c * nu, c * (1.0 - nu) / 2.0)
    } else {
        let c = young / ((1.0 + nu) * (1.0 - 2.0 * nu));
        (c * (1.0 - nu), c * nu, c * (1.0 - 2.0 * nu) / 2.0)
    };
    SMatrix::<f64, 3, 3>::new(c11, c12, 0.0, c12, c11, 0.0, 0.0, 0.0, c33)
}

pub fn hooke_3d(young: f64, nu: f64) -> SMatrix<f64, 6, 6> {
    let c = young / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let (a, b, g) = (c * (1.0 - nu), c * nu, young / (2.0 * (1.0 + nu)));
    let mut d = SMatrix::<f64, 6, 6>::zeros();
    for i in 0..3 {
        for j in 0..3 {
            d[(i, j)] = if i == j { a } else { b };
        }
        d[(i + 3, i + 3)] = g;
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// `B^T D B` integrated with the same rule: the reference for the isotropic form.
    fn btdb<const N: usize, const D: usize>(
        x: &[[f64; D]; N],
        rule: &Rule<N, D>,
        young: f64,
        nu: f64,
        ps: bool,
    ) -> DMatrix<f64> {
        let nd = N * D;
        let s = if D == 2 { 3 } else { 6 };
        let dm = if D == 2 {
            DMatrix::from_fn(3, 3, |r, c| hooke_2d(young, nu, ps)[(r, c)])
        } else {
            DMatrix::from_fn(6, 6, |r, c| hooke_3d(young, nu)[(r, c)])
        };
        let mut k = DMatrix::zeros(nd, nd);
        for q in 0..rule.weight.len() {
            let (g, det) = gradients(x, &rule.dn[q]);
            let mut b = DMatrix::zeros(s, nd);
            for a in 0..N {
                if D == 2 {
                    b[(0, 2 * a)] = g[a][0];
                    b[(1, 2 * a + 1)] = g[a][1];
                    b[(2, 2 * a)] = g[a][1];
                    b[(2, 2 * a + 1)] = g[a][0];
                } else {
                    let (gx, gy, gz) = (g[a][0], g[a][1], g[a][2]);
                    b[(0, 3 * a)] = gx;
                    b[(1, 3 * a + 1)] = gy;
                    b[(2, 3 * a + 2)] = gz;
                    b[(3, 3 * a + 1)] = gz;
                    b[(3, 3 * a + 2)] = gy;
                    b[(4, 3 * a)] = gz;
                    b[(4, 3 * a + 2)] = gx;
                    b[(5, 3 * a)] = gy;
                    b[(5, 3 * a + 1)] = gx;
                }
            }
            k += b.transpose() * &dm * b * (rule.weight[q] * det.abs());
        }
        k
    }

    fn distorted_quad() -> [[f64; 2]; 4] {
        [[0.1, -0.2], [2.3, 0.1], [1.9, 1.7], [-0.3, 1.2]]
    }

    fn distorted_hex() -> [[f64; 3]; 8] {
        let mut x = HEX_CORNERS;
        let shift = [
            [0.1, -0.05, 0.02],
            [0.2, 0.1, -0.1],
            [-0.1, 0.15, 0.05],
            [0.05, -0.1, 0.1],
            [-0.15, 0.05, -0.05],
            [0.1, -0.1, 0.2],
            [0.3, 0.2, 0.1],
            [-0.05, 0.1, -0.15],
        ];
        for (p, s) in x.iter_mut().zip(shift) {
            for k in 0..3 {
                p[k] = 0.5 * (p[k] + 1.0) * [1.0, 2.0, 0.7][k] + s[k];
            }
        }
        x
    }

    #[test]
    fn isotropic_form_is_btdb() {
        for ps in [false, true] {
            let x = distorted_quad();
            let mut ke = vec![0.0; 64];
            let mut m = [0.0; 4];
            q1_stiffness(&x, quad_rule(), lame(210.0, 0.3, 2, ps), &mut ke, &mut m).unwrap();
            let r = btdb(&x, quad_rule(), 210.0, 0.3, ps);
            let k = DMatrix::from_row_slice(8, 8, &ke);
            assert!((&k - &r).norm() < 1e-12 * r.norm(), "plane stress {ps}");
        }
        let x = distorted_hex();
        let mut ke = vec![0.0; 576];
        let mut m = [0.0; 8];
        let vol = q1_stiffness(&x, hex_rule(), lame(1e3, 0.45, 3, false), &mut ke, &mut m).unwrap();
        let r = btdb(&x, hex_rule(), 1e3, 0.45, false);
        let k = DMatrix::from_row_slice(24, 24, &ke);
        assert!((&k - &r).norm() < 1e-12 * r.norm());
        assert!((m.iter().sum::<f64>() - vol).abs() < 1e-13 * vol);
    }

    #[test]
    fn rigid_motions_in_the_kernel() {
        let x = distorted_hex();
        let mut ke = vec![0.0; 576];
        let mut m = [0.0; 8];
        q1_stiffness(&x, hex_rule(), lame(1.0, 0.3, 3, false), &mut ke, &mut m).unwrap();
        let k = DMatrix::from_row_slice(24, 24, &ke);
        for mode in 0..6 {
            let u = DVector::from_fn(24, |i, _| {
                let (a, c) = (i / 3, i % 3);
                let p = x[a];
                match mode {
                    0..=2 => f64::from(u8::from(c == mode)),
                    3 => [-p[1], p[0], 0.0][c],
                    4 => [0.0, -p[2], p[1]][c],
                    _ => [p[2], 0.0, -p[0]][c],
                }
            });
            assert!((&k * u).norm() < 1e-12 * k.norm(), "mode {mode}");
        }
    }

    #[test]
    fn clockwise_listing_integrates_the_same() {
        let x = distorted_quad();
        let y = [x[0], x[3], x[2], x[1]];
        let (mut kx, mut ky) = (vec![0.0; 64], vec![0.0; 64]);
        let (mut mx, mut my) = ([0.0; 4], [0.0; 4]);
        let ax = q1_stiffness(&x, quad_rule(), (1.0, 1.0), &mut kx, &mut mx).unwrap();
        let ay = q1_stiffness(&y, quad_rule(), (1.0, 1.0), &mut ky, &mut my).unwrap();
        assert!((ax - ay).abs() < 1e-14);
        // Node 1 of y is node 3 of x.
        assert!((kx[(3 * 2) * 8 + 3 * 2] - ky[(2) * 8 + 2]).abs() < 1e-12);
        // A bow-tie (crossed listing) is refused.
        let z = [x[0], x[1], x[3], x[2]];
        let e = q1_stiffness(&z, quad_rule(), (1.0, 1.0), &mut kx, &mut mx).unwrap_err();
        assert!(e.min_det < 0.0 && e.max_det > 0.0);
    }

    #[test]
    fn degenerate_hexahedra_are_the_prism_and_pyramid_bases() {
        // Merged shape functions of the degenerate hexahedron at collapsed
        // coordinates (u, v, w), against the classical bases.
        let merged = |map: &[usize; 8], k: usize, p: [f64; 3]| {
            let (n, _) = q1_3d(p);
            let mut m = vec![0.0; k];
            for a in 0..8 {
                m[map[a]] += n[a];
            }
            m
        };
        for &(u, v, w) in &[(0.3, -0.7, 0.1), (-0.9, 0.2, -0.5), (0.0, 0.0, 0.8)] {
            // Pyramid: x = (1 - z) u, y = (1 - z) v, z = (1 + w) / 2 (Gmsh's reference).
            let z = 0.5 * (1.0 + w);
            let (x, y) = ((1.0 - z) * u, (1.0 - z) * v);
            let m = merged(&PYRAMID_AS_HEX, 5, [u, v, w]);
            for (a, c) in QUAD_CORNERS.iter().enumerate() {
                let b = (1.0 - z + c[0] * x) * (1.0 - z + c[1] * y) / (4.0 * (1.0 - z));
                assert!((m[a] - b).abs() < 1e-14, "pyramid node {a}");
            }
            assert!((m[4] - z).abs() < 1e-14);
            // Prism: x = (1 + u)(1 - v) / 4, y = (1 + v) / 2 on the triangle
            // (0,0) (1,0) (0,1), z = w.
            let (x, y) = (0.25 * (1.0 + u) * (1.0 - v), 0.5 * (1.0 + v));
            let m = merged(&PRISM_AS_HEX, 6, [u, v, w]);
            let tri = [1.0 - x - y, x, y];
            for a in 0..3 {
                assert!(
                    (m[a] - tri[a] * 0.5 * (1.0 - w)).abs() < 1e-14,
                    "prism node {a}"
                );
                assert!((m[a + 3] - tri[a] * 0.5 * (1.0 + w)).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn facet_weights_rules() {
        let mut w = Vec::new();
        facet_weights(&[&[0.0, 0.0], &[3.0, 4.0]], &mut w);
        assert_eq!(w, [2.5, 2.5]);
        facet_weights(
            &[&[0.0, 0.0, 0.0], &[1.0, 0.0, 0.0], &[0.0, 2.0, 0.0]],
            &mut w,
        );
        assert!(w.iter().all(|&v| (v - 1.0 / 3.0).abs() < 1e-15));
        // A parallelogram: a quarter each.
        let p = [
            [0.0, 0.0, 1.0],
            [2.0, 0.0, 1.0],
            [2.5, 1.0, 1.0],
            [0.5, 1.0, 1.0],
        ];
        let pts: Vec<&[f64]> = p.iter().map(|v| &v[..]).collect();
        facet_weights(&pts, &mut w);
        assert!(w.iter().all(|&v| (v - 0.5).abs() < 1e-14), "{w:?}");
        // A trapezoid (area 1.5) and a warped facet: the integrals of the
        // shape functions, against a fine midpoint rule.
        let fine = |p: &[[f64; 3]; 4]| {
            let n = 400;
            let mut w = [0.0; 4];
            for i in 0..n {
                for j in 0..n {
                    let xi = [
                        -1.0 + (2 * i + 1) as f64 / n as f64,
                        -1.0 + (2 * j + 1) as f64 / n as f64,
                    ];
                    let (sh, dn) = q1_2d(xi);
                    let mut t = [[0.0; 3]; 2];
                    for a in 0..4 {
                        for k in 0..3 {
                            t[0][k] += p[a][k] * dn[a][0];
                            t[1][k] += p[a][k] * dn[a][1];
                        }
                    }
                    let c = [
                        t[0][1] * t[1][2] - t[0][2] * t[1][1],
                        t[0][2] * t[1][0] - t[0][0] * t[1][2],
                        t[0][0] * t[1][1] - t[0][1] * t[1][0],
                    ];
                    let da =
                        (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt() * 4.0 / (n * n) as f64;
                    for a in 0..4 {
                        w[a] += sh[a] * da;
                    }
                }
            }
            w
        };
        let trapezoid = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let pts: Vec<&[f64]> = trapezoid.iter().map(|v| &v[..]).collect();
        facet_weights(&pts, &mut w);
        assert!((w.iter().sum::<f64>() - 1.5).abs() < 1e-14);
        let f = fine(&trapezoid);
        assert!((0..4).all(|a| (w[a] - f[a]).abs() < 1e-5), "{w:?} {f:?}");
        assert!(w[0] > w[3] && w[1] > w[2]);
        let warped = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.3],
            [0.0, 1.0, 0.0],
        ];
        let pts: Vec<&[f64]> = warped.iter().map(|v| &v[..]).collect();
        facet_weights(&pts, &mut w);
        let f = fine(&warped);
        let a: f64 = w.iter().sum();
        assert!(a > 1.0 && a < 1.03, "{a}");
        // 2x2 Gauss on a warped facet: close to, not equal to, the integral.
        assert!(
            (0..4).all(|k| (w[k] - f[k]).abs() < 1e-3 * a),
            "{w:?} {f:?}"
        );
    }
}
