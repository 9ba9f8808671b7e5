//! The 3D mortar of `-contact_pair` ([`super::mortar`] is the 2D one):
//! segment-based integration on triangle and quadrilateral facets.
//!
//! For each slave facet, its plane (centroid, outward unit normal, two
//! in-plane axes); each master facet facing it is projected orthogonally
//! onto that plane and clipped against the slave facet (Sutherland-Hodgman:
//! both convex); the clipped polygon is cut into triangles from its
//! centroid, and `M_kj = int psi_k N_j^m` is integrated there with a
//! degree-4 rule (exact for the products of two bilinear functions on
//! parallelogram facets, and of two linear ones on triangles). The slave's
//! dual basis is `psi = A N` with `A = D_e M_e^{-1}` per facet (`M_e` the
//! facet's mass matrix, `D_e` its lumped diagonal): `int psi_k N_l =
//! delta_kl int N_l` (on a triangle, `psi_k = 4 lambda_k - 1`). Rows,
//! weights, gaps and the coverage rule are those of the 2D mortar.

use super::mortar::{rows, MortarNode, Sums};
use crate::comm::Layout;
use crate::error::{bad, Error};
use crate::mesh::distribute::LocalMesh;
use mpi::traits::*;
use nalgebra::DMatrix;
use std::collections::HashMap;

type V3 = [f64; 3];

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: V3) -> V3 {
    let n = dot(a, a).sqrt();
    [a[0] / n, a[1] / n, a[2] / n]
}

/// One facet of a pair's surface: its 3 or 4 nodes (global numbers, in
/// order around it), their coordinates and its unit normal, outward.
#[derive(Clone, Debug, PartialEq)]
pub struct Facet {
    pub nodes: Vec<usize>,
    pub x: Vec<V3>,
    pub normal: V3,
}

/// f64 values per packed facet: count, 4 nodes, 4 points, normal.
const PACKED: usize = 1 + 4 + 12 + 3;

/// The unit normal of a facet from its points (a quadrilateral's from its
/// diagonals).
fn facet_normal(x: &[V3]) -> V3 {
    let c = if x.len() == 4 {
        cross(sub(x[2], x[0]), sub(x[3], x[1]))
    } else {
        cross(sub(x[1], x[0]), sub(x[2], x[0]))
    };
    unit(c)
}

/// This rank's facets of the surface group `name` (triangles and
/// quadrilaterals), each once over the ranks (on the rank owning its
/// lowest-numbered node), oriented outward by the cell that holds it.
pub fn local_facets(mesh: &LocalMesh, option: &str, name: &str) -> Result<Vec<Facet>, Error> {
    let group = mesh.group_for(option, name, 2..=2, "a contact surface of a pair")?;
    let mut cells_of: HashMap<usize, Vec<usize>> = HashMap::new();
    for e in &group.conn {
        if e.len() != 3 && e.len() != 4 {
            return bad(format!(
                "option {option}: group '{name}' has a facet of {} nodes; contact pairs take 3-node triangles and 4-node quadrilaterals",
                e.len()
            ));
        }
        for &v in e {
            cells_of.entry(v).or_default();
        }
    }
    for (c, cell) in mesh.cells.iter().enumerate() {
        for v in cell {
            if let Some(list) = cells_of.get_mut(v) {
                list.push(c);
            }
        }
    }
    let mut out = Vec::new();
    for e in &group.conn {
        let low = *e
            .iter()
            .min_by_key(|&&v| mesh.node_global[v])
            .expect("a facet");
        if !mesh.is_owned(low) {
            continue;
        }
        let holder = cells_of[&e[0]]
            .iter()
            .find(|&&c| e.iter().all(|v| mesh.cells.get(c).contains(v)));
        let Some(&c) = holder else {
            return bad(format!(
                "option {option}: a facet of group '{name}' (nodes {}) is no face of a cell of the mesh",
                e.iter().map(|&v| mesh.node_tag[v].to_string()).collect::<Vec<_>>().join(", ")
            ));
        };
        let x: Vec<V3> = e
            .iter()
            .map(|&v| [mesh.x(v)[0], mesh.x(v)[1], mesh.x(v)[2]])
            .collect();
        let mut n = facet_normal(&x);
        if !n.iter().all(|v| v.is_finite()) {
            return bad(format!(
                "option {option}: a facet of group '{name}' is degenerate (node {})",
                mesh.node_tag[e[0]]
            ));
        }
        let corners: Vec<V3> = mesh
            .cells
            .get(c)
            .iter()
            .map(|&v| [mesh.x(v)[0], mesh.x(v)[1], mesh.x(v)[2]])
            .collect();
        let centroid = mean(&corners);
        let mid = mean(&x);
        if dot(n, sub(centroid, mid)) > 0.0 {
            n = [-n[0], -n[1], -n[2]];
        }
        out.push(Facet {
            nodes: e.iter().map(|&v| mesh.node_global[v]).collect(),
            x,
            normal: n,
        });
    }
    Ok(out)
}

fn mean(x: &[V3]) -> V3 {
    let k = x.len() as f64;
    let mut m = [0.0; 3];
    for p in x {
        for c in 0..3 {
            m[c] += p[c] / k;
        }
    }
    m
}

/// Every rank's facets, on every rank.
pub fn gather_facets<C: Communicator>(world: &C, mine: &[Facet]) -> Vec<Facet> {
    let mut data = Vec::with_capacity(mine.len() * PACKED);
    for f in mine {
        let k = f.nodes.len();
        data.push(k as f64);
        for i in 0..4 {
            data.push(if i < k { f.nodes[i] as f64 } else { 0.0 });
        }
        for i in 0..4 {
            data.extend(if i < k { f.x[i] } else { [0.0; 3] });
        }
        data.extend(f.normal);
    }
    let all = Layout::new(world, data.len()).all_gather(world, &data);
    all.chunks(PACKED)
        .map(|p| {
            let k = p[0] as usize;
            Facet {
                nodes: (0..k).map(|i| p[1 + i] as usize).collect(),
                x: (0..k)
                    .map(|i| [p[5 + 3 * i], p[6 + 3 * i], p[7 + 3 * i]])
                    .collect(),
                normal: [p[17], p[18], p[19]],
            }
        })
        .collect()
}

/// Shape functions at local coordinates: a triangle's barycentric
/// `(1 - r - s, r, s)`, a quadrilateral's bilinear ones on [-1, 1]^2.
fn shapes(k: usize, r: f64, s: f64) -> [f64; 4] {
    if k == 3 {
        [1.0 - r - s, r, s, 0.0]
    } else {
        [
            0.25 * (1.0 - r) * (1.0 - s),
            0.25 * (1.0 + r) * (1.0 - s),
            0.25 * (1.0 + r) * (1.0 + s),
            0.25 * (1.0 - r) * (1.0 + s),
        ]
    }
}

/// The local coordinates of the plane point `p` in the polygon `q` (3 or
/// 4 plane vertices): exact for a triangle, Newton for a quadrilateral.
fn local(q: &[[f64; 2]], p: [f64; 2]) -> (f64, f64) {
    if q.len() == 3 {
        let (a, b) = (
            [q[1][0] - q[0][0], q[1][1] - q[0][1]],
            [q[2][0] - q[0][0], q[2][1] - q[0][1]],
        );
        let det = a[0] * b[1] - a[1] * b[0];
        let d = [p[0] - q[0][0], p[1] - q[0][1]];
        return (
            (d[0] * b[1] - d[1] * b[0]) / det,
            (a[0] * d[1] - a[1] * d[0]) / det,
        );
    }
    let (mut r, mut s) = (0.0, 0.0);
    for _ in 0..20 {
        let n = shapes(4, r, s);
        let dr = [
            -0.25 * (1.0 - s),
            0.25 * (1.0 - s),
            0.25 * (1.0 + s),
            -0.25 * (1.0 + s),
        ];
        let ds = [
            -0.25 * (1.0 - r),
            -0.25 * (1.0 + r),
            0.25 * (1.0 + r),
            0.25 * (1.0 - r),
        ];
        let (mut f, mut jr, mut js) = ([-p[0], -p[1]], [0.0; 2], [0.0; 2]);
        for i in 0..4 {
            for c in 0..2 {
                f[c] += n[i] * q[i][c];
                jr[c] += dr[i] * q[i][c];
                js[c] += ds[i] * q[i][c];
            }
        }
        let det = jr[0] * js[1] - jr[1] * js[0];
        let (dr_, ds_) = (
            (f[0] * js[1] - f[1] * js[0]) / det,
            (jr[0] * f[1] - jr[1] * f[0]) / det,
        );
        r -= dr_;
        s -= ds_;
        if dr_.abs() + ds_.abs() < 1e-15 {
            break;
        }
    }
    (r, s)
}

/// A slave facet's plane: centroid, normal and in-plane axes.
struct Plane {
    c: V3,
    n: V3,
    e1: V3,
    e2: V3,
}

impl Plane {
    fn of(f: &Facet) -> Plane {
        let (c, n) = (mean(&f.x), f.normal);
        let t = sub(f.x[1], f.x[0]);
        let e1 = unit(sub(
            t,
            [n[0] * dot(t, n), n[1] * dot(t, n), n[2] * dot(t, n)],
        ));
        Plane {
            c,
            n,
            e1,
            e2: cross(n, e1),
        }
    }
    fn at(&self, x: V3) -> [f64; 2] {
        let d = sub(x, self.c);
        [dot(d, self.e1), dot(d, self.e2)]
    }
}

fn area2(p: &[[f64; 2]]) -> f64 {
    let k = p.len();
    (0..k)
        .map(|i| p[i][0] * p[(i + 1) % k][1] - p[(i + 1) % k][0] * p[i][1])
        .sum::<f64>()
        / 2.0
}

/// `poly` clipped by the convex counter-clockwise polygon `clip`.
fn clip(poly: &[[f64; 2]], clip: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut out = poly.to_vec();
    let k = clip.len();
    for i in 0..k {
        let (a, b) = (clip[i], clip[(i + 1) % k]);
        let side = |p: [f64; 2]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        let input = std::mem::take(&mut out);
        for j in 0..input.len() {
            let (p, q) = (input[j], input[(j + 1) % input.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// The 6-point degree-4 rule on a triangle: barycentric points, weights
/// summing to 1.
const RULE: [(f64, f64, f64); 6] = [
    (0.445948490915965, 0.445948490915965, 0.223381589678011),
    (0.108103018168070, 0.445948490915965, 0.223381589678011),
    (0.445948490915965, 0.108103018168070, 0.223381589678011),
    (0.091576213509771, 0.091576213509771, 0.109951743655322),
    (0.816847572980459, 0.091576213509771, 0.109951743655322),
    (0.091576213509771, 0.816847572980459, 0.109951743655322),
];

/// The dual-basis matrix `A = D_e M_e^{-1}` of a slave facet (plane
/// vertices `p`): `psi_k = sum_l A_kl N_l`; and `int N_k` over it.
fn dual(p: &[[f64; 2]]) -> (DMatrix<f64>, Vec<f64>) {
    let k = p.len();
    let mut m = DMatrix::zeros(k, k);
    // The facet cut into triangles from vertex 0; each point's local
    // coordinates by `local` (exact on planar facets).
    for t in 1..k - 1 {
        let tri = [p[0], p[t], p[t + 1]];
        let a = area2(&tri).abs();
        for &(l1, l2, w) in &RULE {
            let x = [
                tri[0][0] * (1.0 - l1 - l2) + tri[1][0] * l1 + tri[2][0] * l2,
                tri[0][1] * (1.0 - l1 - l2) + tri[1][1] * l1 + tri[2][1] * l2,
            ];
            let (r, s) = local(p, x);
            let n = shapes(k, r, s);
            for i in 0..k {
                for j in 0..k {
                    m[(i, j)] += n[i] * n[j] * w * a;
                }
            }
        }
    }
    let d: Vec<f64> = (0..k).map(|i| m.row(i).sum()).collect();
    let inv = m
        .clone()
        .try_inverse()
        .unwrap_or_else(|| DMatrix::zeros(k, k));
    (
        DMatrix::from_diagonal(&nalgebra::DVector::from_vec(d.clone())) * inv,
        d,
    )
}

/// The mortar rows of the slave nodes for which `wanted(node)` holds.
pub fn mortar_rows(
    slave: &[Facet],
    master: &[Facet],
    wanted: impl Fn(usize) -> bool,
) -> Vec<MortarNode> {
    let mut sums: HashMap<usize, Sums> = HashMap::new();
    let search = super::search::Search::new(
        master
            .iter()
            .map(|m| super::search::bounds(m.x.iter().map(|p| &p[..])))
            .collect(),
    );
    for s in slave.iter().filter(|s| s.nodes.iter().any(|&v| wanted(v))) {
        let plane = Plane::of(s);
        // The slave's plane points in its own order (for its local
        // coordinates) and counter-clockwise (for the clipping).
        let ps: Vec<[f64; 2]> = s.x.iter().map(|&x| plane.at(x)).collect();
        let mut p = ps.clone();
        let (a, full) = dual(&ps);
        let size = area2(&ps).abs().sqrt();
        for (k, &v) in s.nodes.iter().enumerate().filter(|(_, &v)| wanted(v)) {
            let e = sums.entry(v).or_default();
            e.x = s.x[k];
            for c in 0..3 {
                e.normal[c] += full[k] * s.normal[c];
            }
            e.full += full[k];
        }
        if area2(&p) < 0.0 {
            p.reverse();
        }
        // The facing master facets, clipped; the nearest layer of them.
        let clipped = |m: &Facet| {
            let q: Vec<[f64; 2]> = m.x.iter().map(|&x| plane.at(x)).collect();
            let mut qc = q.clone();
            if area2(&qc) < 0.0 {
                qc.reverse();
            }
            let poly = clip(&qc, &p);
            (poly.len() >= 3 && area2(&poly) > 1e-12 * size * size).then_some((q, poly))
        };
        let near = search.near(&s.x, s.normal, size, |j| {
            let m = &master[j];
            if dot(m.normal, s.normal) >= 0.0 {
                return None;
            }
            // (Its distance along the normal, bounded by its corners'.)
            clipped(m).map(|_| {
                m.x.iter()
                    .map(|&x| dot(sub(x, plane.c), plane.n).abs())
                    .fold(0.0, f64::max)
            })
        });
        let mut found = Vec::new();
        for m in near.into_iter().map(|j| &master[j]) {
            let Some((q, poly)) = clipped(m) else {
                continue;
            };
            let c = [
                poly.iter().map(|v| v[0]).sum::<f64>() / poly.len() as f64,
                poly.iter().map(|v| v[1]).sum::<f64>() / poly.len() as f64,
            ];
            let (r, t) = local(&q, c);
            let nm = shapes(m.x.len(), r, t);
            let depth: f64 = (0..m.x.len())
                .map(|j| nm[j] * dot(sub(m.x[j], plane.c), plane.n))
                .sum();
            found.push((m, q, poly, depth));
        }
        let Some(nearest) = found.iter().map(|f| f.3).reduce(f64::min) else {
            continue;
        };
        for (m, q, poly, depth) in &found {
            if *depth > nearest + size {
                continue;
            }
            integrate(s, &ps, &a, m, q, poly, &wanted, &mut sums);
        }
    }
    rows(sums, 3)
}

/// Adds the part of slave facet `s` (plane points `p`, in its own order;
/// dual basis `a`) that master facet `m` (plane points `q`) covers
/// (`poly`, counter-clockwise) to the sums of its wanted nodes.
#[allow(clippy::too_many_arguments)]
fn integrate(
    s: &Facet,
    p: &[[f64; 2]],
    a: &DMatrix<f64>,
    m: &Facet,
    q: &[[f64; 2]],
    poly: &[[f64; 2]],
    wanted: &impl Fn(usize) -> bool,
    sums: &mut HashMap<usize, Sums>,
) {
    let ps = p;
    let (ks, km) = (s.x.len(), m.x.len());
    let c = [
        poly.iter().map(|v| v[0]).sum::<f64>() / poly.len() as f64,
        poly.iter().map(|v| v[1]).sum::<f64>() / poly.len() as f64,
    ];
    for i in 0..poly.len() {
        let tri = [c, poly[i], poly[(i + 1) % poly.len()]];
        let area = area2(&tri).abs();
        for &(l1, l2, w) in &RULE {
            let x = [
                tri[0][0] * (1.0 - l1 - l2) + tri[1][0] * l1 + tri[2][0] * l2,
                tri[0][1] * (1.0 - l1 - l2) + tri[1][1] * l1 + tri[2][1] * l2,
            ];
            let (r, t) = local(ps, x);
            let ns = shapes(ks, r, t);
            let (r, t) = local(q, x);
            let nm = shapes(km, r, t);
            let jw = w * area;
            for (k, &v) in s.nodes.iter().enumerate() {
                if !wanted(v) {
                    continue;
                }
                let psi: f64 = (0..ks).map(|l| a[(k, l)] * ns[l]).sum();
                let e = sums.get_mut(&v).expect("entered by the caller");
                e.covered += ns[k] * jw;
                for (j, &mv) in m.nodes.iter().enumerate() {
                    *e.m.entry(mv).or_insert(0.0) += psi * nm[j] * jw;
                    e.xm.insert(mv, m.x[j]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat square grid [x0, x1] x [y0, y1] at height z of n x n
    /// quadrilaterals (or 2 n^2 triangles), nodes from `first`, outward
    /// normal (0, 0, nz).
    fn grid(
        first: usize,
        (x0, x1, y0, y1): (f64, f64, f64, f64),
        z: f64,
        n: usize,
        tri: bool,
        nz: f64,
    ) -> Vec<Facet> {
        let id = |i: usize, j: usize| first + j * (n + 1) + i;
        let pt = |i: usize, j: usize| {
            [
                x0 + (x1 - x0) * i as f64 / n as f64,
                y0 + (y1 - y0) * j as f64 / n as f64,
                z,
            ]
        };
        let mut out = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let q = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                let mut polys: Vec<Vec<(usize, usize)>> = if tri {
                    vec![vec![q[0], q[1], q[2]], vec![q[0], q[2], q[3]]]
                } else {
                    vec![q.to_vec()]
                };
                for poly in &mut polys {
                    if nz < 0.0 {
                        poly.reverse();
                    }
                    out.push(Facet {
                        nodes: poly.iter().map(|&(a, b)| id(a, b)).collect(),
                        x: poly.iter().map(|&(a, b)| pt(a, b)).collect(),
                        normal: [0.0, 0.0, nz],
                    });
                }
            }
        }
        out
    }

    #[test]
    fn non_matching_grids_reproduce_linear_fields() {
        for (tri_s, tri_m) in [(false, false), (true, true), (false, true), (true, false)] {
            let slave = grid(0, (0.1, 0.9, 0.2, 0.8), 0.0, 3, tri_s, -1.0);
            let master = grid(1000, (0.0, 1.0, 0.0, 1.0), -0.05, 5, tri_m, 1.0);
            let rows = mortar_rows(&slave, &master, |_| true);
            assert_eq!(rows.len(), 16, "{tri_s} {tri_m}");
            let f = |x: V3| 2.0 - 3.0 * x[0] + 0.5 * x[1];
            let node_x = |j: usize| {
                let k = j - 1000;
                [(k % 6) as f64 / 5.0, (k / 6) as f64 / 5.0, -0.05]
            };
            for r in &rows {
                let xs = [
                    0.1 + 0.8 * (r.node % 4) as f64 / 3.0,
                    0.2 + 0.6 * (r.node / 4) as f64 / 3.0,
                    0.0,
                ];
                let proj: f64 = r.row.iter().map(|&(j, p)| p * f(node_x(j))).sum();
                assert!(
                    (proj - f(xs)).abs() < 1e-12,
                    "{tri_s} {tri_m}: node {}: {proj} vs {}",
                    r.node,
                    f(xs)
                );
                assert!((r.gap - 0.05).abs() < 1e-12);
                assert!((r.normal[2] + 1.0).abs() < 1e-12);
            }
            let total: f64 = rows.iter().map(|r| r.w).sum();
            assert!((total - 0.48).abs() < 1e-12, "area {total}");
        }
    }

    #[test]
    fn clipping_two_squares() {
        let a = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let b = [[0.5, 0.5], [1.5, 0.5], [1.5, 1.5], [0.5, 1.5]];
        assert!((area2(&clip(&b, &a)) - 0.25).abs() < 1e-15);
        let far = [[2.0, 2.0], [3.0, 2.0], [3.0, 3.0]];
        assert!(clip(&far, &a).len() < 3);
    }

    #[test]
    fn triangle_dual_basis_is_4_lambda_minus_1() {
        let (a, d) = dual(&[[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]]);
        for k in 0..3 {
            assert!((d[k] - 1.0 / 3.0).abs() < 1e-14);
            for l in 0..3 {
                let want = if k == l { 3.0 } else { -1.0 };
                assert!((a[(k, l)] - want).abs() < 1e-12, "{a}");
            }
        }
    }
}
