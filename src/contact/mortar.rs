//! Two elastic bodies in contact (`-contact_pair SLAVE,MASTER`, issue "Two
//! elastic bodies"): segment-based mortar coupling with dual Lagrange
//! multipliers (Wohlmuth's biorthogonal basis), 2D.
//!
//! On a slave segment with shape functions `N_a = (1 - xi)/2`,
//! `N_b = (1 + xi)/2`, the dual basis is `psi_a = (1 - 3 xi)/2`,
//! `psi_b = (1 + 3 xi)/2`: `int psi_k N_l = delta_kl int N_l`, so the
//! slave mortar matrix `D_kl = int psi_k N_l` is diagonal. The master
//! matrix `M_kj = int psi_k N_j^m` is integrated segment by segment over
//! the parts of the slave segment that a master segment covers (the master
//! segment projected orthogonally onto the slave segment's line, its
//! parameter then affine in the slave's: two Gauss points are exact).
//!
//! The constraint of slave node k is pointwise, `n_k . (u_k - sum_j P_kj
//! u_j) <= g_k`, with `P_kj = M_kj / sum_j M_kj` (`= M_kj / D_kk` where
//! the node's segments are covered: a linear field is reproduced exactly,
//! the contact patch test) and the weighted gap `g_k = n_k . (sum_j P_kj
//! x_j - x_k)`; `n_k` is the slave's averaged nodal normal (outward). The
//! node's weight `w_k` is `int N_k` over the covered part of its support.
//! A slave node less than half covered (by length) is no candidate.
//!
//! The solver keeps its node-local contact rows through a change of
//! unknowns ([`crate::solver::mortar`]): at a slave node, the relative
//! displacement `v_k = u_k - Q_k sum_j P_kj u_j` replaces `u_k`.

use crate::comm::Layout;
use crate::error::{bad, Error};
use crate::mesh::distribute::LocalMesh;
use mpi::traits::*;
use std::collections::HashMap;

/// One segment of a pair's surface: its nodes (global numbers), their
/// coordinates and its unit normal, outward of its body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub nodes: [usize; 2],
    pub x: [[f64; 2]; 2],
    pub normal: [f64; 2],
}

/// f64 values per packed segment.
const PACKED: usize = 8;

impl Segment {
    fn length(&self) -> f64 {
        let t = sub(self.x[1], self.x[0]);
        dot(t, t).sqrt()
    }
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// One slave node's mortar data.
#[derive(Clone, Debug, PartialEq)]
pub struct MortarNode {
    /// The slave node (global number).
    pub node: usize,
    /// `int N_k` over the covered part of its support.
    pub w: f64,
    /// Averaged nodal normal, outward of the slave body (`dim` values).
    pub normal: Vec<f64>,
    /// Weighted gap along the normal (negative: initial penetration).
    pub gap: f64,
    /// `P_kj` by master node (global number), increasing.
    pub row: Vec<(usize, f64)>,
    /// The node's image on the master, `sum_j P_kj x_j` (`dim` values).
    pub point: Vec<f64>,
}

/// This rank's segments of the surface group `name` (2D lines), each once
/// over the ranks (on the rank that owns its lower-numbered node),
/// oriented outward of the body by the cell that holds it.
pub fn local_segments(mesh: &LocalMesh, option: &str, name: &str) -> Result<Vec<Segment>, Error> {
    let group = mesh.group_for(option, name, 1..=1, "a contact surface of a pair")?;
    // The cell of each wanted edge (by its sorted local nodes).
    let mut wanted: HashMap<(usize, usize), Option<usize>> = HashMap::new();
    for e in &group.conn {
        if e.len() != 2 {
            return bad(format!(
                "option {option}: group '{name}' has a line element of {} nodes; contact pairs take 2-node lines",
                e.len()
            ));
        }
        wanted.insert((e[0].min(e[1]), e[0].max(e[1])), None);
    }
    for (c, cell) in mesh.cells.iter().enumerate() {
        let k = cell.len();
        for i in 0..k {
            let (a, b) = (cell[i], cell[(i + 1) % k]);
            if let Some(slot) = wanted.get_mut(&(a.min(b), a.max(b))) {
                slot.get_or_insert(c);
            }
        }
    }
    let mut out = Vec::new();
    for e in &group.conn {
        let (a, b) = (e[0], e[1]);
        let low = if mesh.node_global[a] < mesh.node_global[b] {
            a
        } else {
            b
        };
        if !mesh.is_owned(low) {
            continue;
        }
        let Some(Some(c)) = wanted.get(&(a.min(b), a.max(b))) else {
            return bad(format!(
                "option {option}: a line of group '{name}' (nodes {} and {}) is no edge of a cell of the mesh",
                mesh.node_tag[a], mesh.node_tag[b]
            ));
        };
        let xa = [mesh.x(a)[0], mesh.x(a)[1]];
        let xb = [mesh.x(b)[0], mesh.x(b)[1]];
        let t = sub(xb, xa);
        let len = dot(t, t).sqrt();
        if len == 0.0 {
            return bad(format!(
                "option {option}: a line of group '{name}' has zero length (nodes {} and {})",
                mesh.node_tag[a], mesh.node_tag[b]
            ));
        }
        let mut n = [t[1] / len, -t[0] / len];
        // Outward: away from the cell's centroid.
        let cell = mesh.cells.get(*c);
        let mut centroid = [0.0; 2];
        for &v in cell {
            centroid[0] += mesh.x(v)[0] / cell.len() as f64;
            centroid[1] += mesh.x(v)[1] / cell.len() as f64;
        }
        let mid = [(xa[0] + xb[0]) / 2.0, (xa[1] + xb[1]) / 2.0];
        if dot(n, sub(centroid, mid)) > 0.0 {
            n = [-n[0], -n[1]];
        }
        out.push(Segment {
            nodes: [mesh.node_global[a], mesh.node_global[b]],
            x: [xa, xb],
            normal: n,
        });
    }
    Ok(out)
}

/// Every rank's segments, on every rank, in rank order.
pub fn gather_segments<C: Communicator>(world: &C, mine: &[Segment]) -> Vec<Segment> {
    let mut data = Vec::with_capacity(mine.len() * PACKED);
    for s in mine {
        data.extend([
            s.nodes[0] as f64,
            s.nodes[1] as f64,
            s.x[0][0],
            s.x[0][1],
            s.x[1][0],
            s.x[1][1],
            s.normal[0],
            s.normal[1],
        ]);
    }
    let all = Layout::new(world, data.len()).all_gather(world, &data);
    all.chunks(PACKED)
        .map(|p| Segment {
            nodes: [p[0] as usize, p[1] as usize],
            x: [[p[2], p[3]], [p[4], p[5]]],
            normal: [p[6], p[7]],
        })
        .collect()
}

/// The part of a slave segment that a master segment covers, seen from
/// the slave: its interval `[lo, hi]` of the slave parameter, the affine
/// map `eta = e0 + e1 xi` to the master parameter, and the distance along
/// the slave's normal at its middle.
#[derive(Clone, Copy)]
struct Overlap {
    lo: f64,
    hi: f64,
    e0: f64,
    e1: f64,
    dist: f64,
}

/// The part of slave segment `s` that master segment `m` covers; None
/// when `m` does not face `s` or covers nothing of it.
fn overlap(s: &Segment, m: &Segment) -> Option<Overlap> {
    if dot(s.normal, m.normal) >= 0.0 {
        return None;
    }
    let t = sub(s.x[1], s.x[0]);
    let tt = dot(t, t);
    let xi = |x: [f64; 2]| 2.0 * dot(sub(x, s.x[0]), t) / tt - 1.0;
    let (x0, x1) = (xi(m.x[0]), xi(m.x[1]));
    if (x1 - x0).abs() < 1e-12 {
        return None;
    }
    let lo = x0.min(x1).max(-1.0);
    let hi = x0.max(x1).min(1.0);
    if hi - lo <= 1e-12 {
        return None;
    }
    // eta(xi): -1 at x0, +1 at x1.
    let e1 = 2.0 / (x1 - x0);
    let e0 = -1.0 - e1 * x0;
    let mid = 0.5 * (lo + hi);
    let eta = e0 + e1 * mid;
    let xs = lerp(s, mid);
    let xm = lerp(m, eta);
    Some(Overlap {
        lo,
        hi,
        e0,
        e1,
        dist: dot(sub(xm, xs), s.normal),
    })
}

/// The point of segment `s` at parameter `xi` in [-1, 1].
fn lerp(s: &Segment, xi: f64) -> [f64; 2] {
    let (a, b) = ((1.0 - xi) / 2.0, (1.0 + xi) / 2.0);
    [a * s.x[0][0] + b * s.x[1][0], a * s.x[0][1] + b * s.x[1][1]]
}

/// Accumulated integrals of one slave node (3 coordinates: the 3D mortar
/// shares them, [`super::mortar3d`]; 0 beyond the mesh's dimension).
#[derive(Default)]
pub(super) struct Sums {
    pub(super) x: [f64; 3],
    /// The facet normals weighted by `int N_k` (summed).
    pub(super) normal: [f64; 3],
    /// `int N_k` over the whole support and over the covered part.
    pub(super) full: f64,
    pub(super) covered: f64,
    /// `M_kj` by master node.
    pub(super) m: HashMap<usize, f64>,
    /// Master nodes' coordinates.
    pub(super) xm: HashMap<usize, [f64; 3]>,
}

fn lift(p: [f64; 2]) -> [f64; 3] {
    [p[0], p[1], 0.0]
}

/// The rows from the sums: a node less than half covered is no candidate;
/// `P_kj = M_kj / sum_j M_kj` (round-off entries, where a master element
/// only touches the support at its edge, dropped), the averaged normal,
/// the weighted gap and the image `sum_j P_kj x_j`; `dim` values each.
pub(super) fn rows(sums: HashMap<usize, Sums>, dim: usize) -> Vec<MortarNode> {
    let dot3 = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let mut out: Vec<MortarNode> = sums
        .into_iter()
        .filter_map(|(node, e)| {
            // By master node first: a sum in the map's order (random per
            // run) made one rank's runs differ by 1e-10, and a 3D ball on
            // a block with Coulomb friction converge or not from run to run.
            let mut row: Vec<(usize, f64)> = e.m.iter().map(|(&j, &v)| (j, v)).collect();
            row.sort_unstable_by_key(|&(j, _)| j);
            let total: f64 = row.iter().map(|r| r.1).sum();
            if e.covered < 0.5 * e.full || total < 0.25 * e.full {
                return None;
            }
            let nn = dot3(e.normal, e.normal).sqrt();
            let normal = e.normal.map(|v| v / nn);
            row.iter_mut().for_each(|r| r.1 /= total);
            row.retain(|&(_, p)| p.abs() > 1e-12);
            let kept: f64 = row.iter().map(|r| r.1).sum();
            row.iter_mut().for_each(|r| r.1 /= kept);
            let mut proj = [0.0; 3];
            for &(j, p) in &row {
                let x = e.xm[&j];
                (0..3).for_each(|c| proj[c] += p * x[c]);
            }
            let d = [proj[0] - e.x[0], proj[1] - e.x[1], proj[2] - e.x[2]];
            Some(MortarNode {
                node,
                w: e.covered,
                normal: normal[..dim].to_vec(),
                gap: dot3(normal, d),
                row,
                point: proj[..dim].to_vec(),
            })
        })
        .collect();
    out.sort_unstable_by_key(|m| m.node);
    out
}

/// The mortar rows of the slave nodes for which `wanted(node)` holds.
/// `slave`, `master`: every segment of the pair's two surfaces.
pub fn mortar_rows(
    slave: &[Segment],
    master: &[Segment],
    wanted: impl Fn(usize) -> bool,
) -> Vec<MortarNode> {
    let mut sums: HashMap<usize, Sums> = HashMap::new();
    let gauss = [-1.0 / 3f64.sqrt(), 1.0 / 3f64.sqrt()];
    let search = super::search::Search::new(
        master
            .iter()
            .map(|m| super::search::bounds(m.x.iter().map(|p| &p[..])))
            .collect(),
    );
    for s in slave {
        if !s.nodes.iter().any(|&v| wanted(v)) {
            continue;
        }
        let len = s.length();
        for (k, &v) in s.nodes.iter().enumerate() {
            if wanted(v) {
                let e = sums.entry(v).or_default();
                e.x = lift(s.x[k]);
                e.normal[0] += len * s.normal[0];
                e.normal[1] += len * s.normal[1];
                e.full += len / 2.0;
            }
        }
        // The master segments facing s, and the nearest layer of them.
        let near = search.near(
            &s.x.map(|p| [p[0], p[1], 0.0]),
            [s.normal[0], s.normal[1], 0.0],
            len,
            |j| overlap(s, &master[j]).map(|o| o.dist),
        );
        let found: Vec<(usize, Overlap)> = near
            .into_iter()
            .filter_map(|j| overlap(s, &master[j]).map(|o| (j, o)))
            .collect();
        let Some(nearest) = found.iter().map(|f| f.1.dist).reduce(f64::min) else {
            continue;
        };
        for &(
            j,
            Overlap {
                lo,
                hi,
                e0,
                e1,
                dist,
            },
        ) in &found
        {
            if dist > nearest + len {
                continue; // a farther layer behind the nearest one
            }
            let m = &master[j];
            let half = 0.5 * (hi - lo);
            let mid = 0.5 * (lo + hi);
            for g in gauss {
                let xi = mid + half * g;
                // ds = (len / 2) dxi; the Gauss weight is 1 on [-1, 1].
                let jw = half * len / 2.0;
                let eta = e0 + e1 * xi;
                let n = [(1.0 - xi) / 2.0, (1.0 + xi) / 2.0];
                let psi = [(1.0 - 3.0 * xi) / 2.0, (1.0 + 3.0 * xi) / 2.0];
                let nm = [(1.0 - eta) / 2.0, (1.0 + eta) / 2.0];
                for (k, &v) in s.nodes.iter().enumerate() {
                    if !wanted(v) {
                        continue;
                    }
                    let e = sums.get_mut(&v).expect("entered above");
                    e.covered += n[k] * jw;
                    for (l, &mv) in m.nodes.iter().enumerate() {
                        *e.m.entry(mv).or_insert(0.0) += psi[k] * nm[l] * jw;
                        e.xm.insert(mv, lift(m.x[l]));
                    }
                }
            }
        }
    }
    rows(sums, 2)
}

/// The node-to-segment rows (`-contact_pair_scheme node_to_segment`, for
/// comparison): each wanted slave node's ray along its nodal normal meets
/// the nearest facing master segment at `(1 - s) a + s b`, which is its
/// row `(a: 1 - s, b: s)`; its weight is `int N_k` over its whole support.
/// Not a mortar method: it fails the contact patch test on non-matching
/// meshes (tests/pairs.rs gives the figure).
pub fn node_to_segment_rows(
    slave: &[Segment],
    master: &[Segment],
    wanted: impl Fn(usize) -> bool,
) -> Vec<MortarNode> {
    let mut sums: HashMap<usize, Sums> = HashMap::new();
    for s in slave.iter().filter(|s| s.nodes.iter().any(|&v| wanted(v))) {
        let len = s.length();
        for (k, &v) in s.nodes.iter().enumerate().filter(|(_, &v)| wanted(v)) {
            let e = sums.entry(v).or_default();
            e.x = lift(s.x[k]);
            e.normal[0] += len * s.normal[0];
            e.normal[1] += len * s.normal[1];
            e.full += len / 2.0;
        }
    }
    let mut out: Vec<MortarNode> = sums
        .into_iter()
        .filter_map(|(node, e)| {
            let x = [e.x[0], e.x[1]];
            let nn = e.normal[0].hypot(e.normal[1]);
            let n = [e.normal[0] / nn, e.normal[1] / nn];
            // x + t n = a + s (b - a): the nearest hit, |t| smallest.
            let mut best: Option<(f64, &Segment, f64)> = None;
            for m in master.iter().filter(|m| dot(n, m.normal) < 0.0) {
                let ab = sub(m.x[1], m.x[0]);
                let det = n[0] * (-ab[1]) - n[1] * (-ab[0]);
                if det.abs() < 1e-14 * dot(ab, ab).sqrt() {
                    continue;
                }
                let r = sub(m.x[0], x);
                let t = (r[0] * (-ab[1]) - r[1] * (-ab[0])) / det;
                let sp = (n[0] * r[1] - n[1] * r[0]) / det;
                if (-1e-12..=1.0 + 1e-12).contains(&sp) && best.is_none_or(|b| t.abs() < b.0.abs())
                {
                    best = Some((t, m, sp.clamp(0.0, 1.0)));
                }
            }
            let (t, m, sp) = best?;
            let mut row = vec![(m.nodes[0], 1.0 - sp), (m.nodes[1], sp)];
            row.retain(|r| r.1 != 0.0);
            row.sort_unstable_by_key(|r| r.0);
            Some(MortarNode {
                node,
                w: e.full,
                normal: n.to_vec(),
                gap: t,
                row,
                point: vec![x[0] + t * n[0], x[1] + t * n[1]],
            })
        })
        .collect();
    out.sort_unstable_by_key(|m| m.node);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight surface along x at height y from x0 to x1 in k segments,
    /// nodes numbered from `first`, outward normal (0, ny).
    fn line(first: usize, x0: f64, x1: f64, y: f64, k: usize, ny: f64) -> Vec<Segment> {
        (0..k)
            .map(|i| {
                let a = x0 + (x1 - x0) * i as f64 / k as f64;
                let b = x0 + (x1 - x0) * (i + 1) as f64 / k as f64;
                Segment {
                    nodes: [first + i, first + i + 1],
                    x: [[a, y], [b, y]],
                    normal: [0.0, ny],
                }
            })
            .collect()
    }

    #[test]
    fn matching_surfaces_pair_node_to_node() {
        let slave = line(0, 0.0, 1.0, 0.0, 4, -1.0);
        let master = line(100, 0.0, 1.0, -0.01, 4, 1.0);
        let rows = mortar_rows(&slave, &master, |_| true);
        assert_eq!(rows.len(), 5);
        for (k, r) in rows.iter().enumerate() {
            assert_eq!(r.row.len(), 1, "{r:?}");
            assert_eq!(r.row[0].0, 100 + k);
            assert!((r.row[0].1 - 1.0).abs() < 1e-14);
            assert!((r.gap - 0.01).abs() < 1e-14);
            let w = if k == 0 || k == 4 { 0.125 } else { 0.25 };
            assert!((r.w - w).abs() < 1e-14);
        }
    }

    #[test]
    fn non_matching_surfaces_reproduce_linear_fields() {
        // Slave over [0.2, 0.8] (3 segments), master over [0, 1] (7).
        let slave = line(0, 0.2, 0.8, 0.0, 3, -1.0);
        let master = line(100, 0.0, 1.0, 0.0, 7, 1.0);
        let rows = mortar_rows(&slave, &master, |_| true);
        assert_eq!(rows.len(), 4);
        let f = |x: f64| 3.0 - 2.0 * x;
        for r in &rows {
            let xs = 0.2 + 0.2 * r.node as f64;
            let sum: f64 = r.row.iter().map(|&(_, p)| p).sum();
            assert!((sum - 1.0).abs() < 1e-14);
            let proj: f64 = r
                .row
                .iter()
                .map(|&(j, p)| p * f((j - 100) as f64 / 7.0))
                .sum();
            assert!(
                (proj - f(xs)).abs() < 1e-13,
                "node {}: {proj} vs {}",
                r.node,
                f(xs)
            );
            assert!(r.gap.abs() < 1e-14);
        }
    }

    #[test]
    fn uncovered_and_back_facing_segments_are_no_candidates() {
        // The slave sticks out of the master on the right: its last node
        // is uncovered; a master facing the same way pairs with nothing.
        let slave = line(0, 0.5, 1.5, 0.0, 2, -1.0);
        let master = line(100, 0.0, 1.0, -0.1, 4, 1.0);
        let rows = mortar_rows(&slave, &master, |_| true);
        let nodes: Vec<usize> = rows.iter().map(|r| r.node).collect();
        assert_eq!(nodes, vec![0, 1]);
        let same_way = line(100, 0.0, 2.0, -0.1, 4, -1.0);
        assert!(mortar_rows(&slave, &same_way, |_| true).is_empty());
    }

    #[test]
    fn only_the_nearest_layer_counts() {
        let slave = line(0, 0.0, 1.0, 0.0, 2, -1.0);
        let mut master = line(100, 0.0, 1.0, -0.1, 3, 1.0);
        master.extend(line(200, 0.0, 1.0, -5.0, 3, 1.0));
        let rows = mortar_rows(&slave, &master, |_| true);
        for r in &rows {
            assert!(r.row.iter().all(|&(j, _)| j < 200), "{r:?}");
            assert!((r.gap - 0.1).abs() < 1e-14);
        }
    }
}
