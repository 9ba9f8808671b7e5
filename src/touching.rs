//! Do the mesh's parts touch? Contact between two elastic bodies is not
//! modelled (only contact with the rigid obstacle): where two connected
//! parts of the mesh touch or overlap, before the solve or in the deformed
//! shape `x + u`, they pass through each other freely, and the user is told.
//!
//! A node of one part touches another when it lies in or on one of the
//! other's cells (barycentric coordinates above `-TOUCH_TOL` in one of the
//! cell's simplices). Only the nodes inside the overlap of two parts'
//! bounding boxes are tested, against the cells of the other part there:
//! one gather of those nodes, each rank testing its own cells.

use crate::comm::Layout;
use crate::mesh::distribute::LocalMesh;
use crate::wellposed::Bodies;
use mpi::collective::SystemOperation;
use mpi::traits::*;

/// A node within this (barycentric) distance of a cell touches it.
const TOUCH_TOL: f64 = 1e-9;
/// Bounding boxes closer than this fraction of the larger body's size touch.
const BOX_TOL: f64 = 1e-9;

/// Two parts that touch: their indices and the number of nodes of either
/// found in or on the other.
#[derive(Clone, Debug)]
pub struct Touch {
    pub a: usize,
    pub b: usize,
    pub nodes: usize,
}

/// The simplices of a cell of `k` nodes (local node positions): a triangle
/// or tetrahedron itself, a quadrilateral in two triangles, a pyramid in
/// two, a prism in three and a hexahedron in six tetrahedra (Gmsh's
/// orderings); None for other kinds.
fn simplices(dim: usize, k: usize) -> Option<&'static [&'static [usize]]> {
    match (dim, k) {
        (2, 3) => Some(&[&[0, 1, 2]]),
        (2, 4) => Some(&[&[0, 1, 2], &[0, 2, 3]]),
        (3, 4) => Some(&[&[0, 1, 2, 3]]),
        (3, 5) => Some(&[&[0, 1, 2, 4], &[0, 2, 3, 4]]),
        (3, 6) => Some(&[&[0, 1, 2, 3], &[1, 2, 3, 4], &[2, 3, 4, 5]]),
        (3, 8) => Some(&[
            &[0, 1, 2, 6],
            &[0, 2, 3, 6],
            &[0, 3, 7, 6],
            &[0, 7, 4, 6],
            &[0, 4, 5, 6],
            &[0, 5, 1, 6],
        ]),
        _ => None,
    }
}

/// Whether `p` lies in or on the simplex `v` (d + 1 vertices of d coordinates).
fn in_simplex(d: usize, v: &[[f64; 3]], p: &[f64; 3]) -> bool {
    // Solve [v1 - v0, ..., vd - v0] l = p - v0 by Cramer's rule.
    let e = |i: usize, c: usize| v[i + 1][c] - v[0][c];
    let q: Vec<f64> = (0..d).map(|c| p[c] - v[0][c]).collect();
    if d == 2 {
        let det = e(0, 0) * e(1, 1) - e(1, 0) * e(0, 1);
        if det == 0.0 {
            return false;
        }
        let l1 = (q[0] * e(1, 1) - e(1, 0) * q[1]) / det;
        let l2 = (e(0, 0) * q[1] - q[0] * e(0, 1)) / det;
        return l1 >= -TOUCH_TOL && l2 >= -TOUCH_TOL && 1.0 - l1 - l2 >= -TOUCH_TOL;
    }
    let m = [
        [e(0, 0), e(1, 0), e(2, 0)],
        [e(0, 1), e(1, 1), e(2, 1)],
        [e(0, 2), e(1, 2), e(2, 2)],
    ];
    let det3 = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let det = det3(&m);
    if det == 0.0 {
        return false;
    }
    let mut sum = 0.0;
    for col in 0..3 {
        let mut mc = m;
        for row in 0..3 {
            mc[row][col] = q[row];
        }
        let l = det3(&mc) / det;
        if l < -TOUCH_TOL {
            return false;
        }
        sum += l;
    }
    1.0 - sum >= -TOUCH_TOL
}

/// The pairs of parts of the mesh that touch or overlap, at the positions
/// `x + u` (`u` for every local node, owned and ghost; None: the mesh as
/// given). Collective; the same answer on every rank.
pub fn touching<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    bodies: &Bodies,
    u: Option<&[f64]>,
) -> Vec<Touch> {
    let nb = bodies.len();
    if nb < 2 {
        return Vec::new();
    }
    let d = mesh.dim;
    let pos = |v: usize| -> [f64; 3] {
        let mut p = [0.0; 3];
        for (c, x) in mesh.x(v).iter().enumerate() {
            p[c] = x + u.map_or(0.0, |u| u[v * d + c]);
        }
        p
    };
    let pairs = overlapping_pairs(world, mesh, bodies, &pos);
    if pairs.is_empty() {
        return Vec::new();
    }
    let inside =
        |p: &[f64; 3], l: &[f64; 3], h: &[f64; 3]| (0..d).all(|c| p[c] >= l[c] && p[c] <= h[c]);
    // The owned nodes in some overlap box of their part: (x, y, z, part).
    let mut mine: Vec<f64> = Vec::new();
    for v in 0..mesh.owned_count {
        let b = bodies.node_body[v];
        let p = pos(v);
        if pairs
            .iter()
            .any(|(pa, pb, l, h)| (*pa == b || *pb == b) && inside(&p, l, h))
        {
            mine.extend_from_slice(&[p[0], p[1], p[2], b as f64]);
        }
    }
    let points = Layout::new(world, mine.len()).all_gather(world, &mine);
    let np = points.len() / 4;
    if np == 0 {
        return Vec::new();
    }
    // Each rank tests its cells (those of the parts in a pair) against the
    // other part's points; a point hit anywhere counts once.
    let mut hit = vec![0.0f64; np];
    let mut verts = [[0.0; 3]; 8];
    for cell in mesh.cells.iter() {
        let body = bodies.node_body[cell[0]];
        let Some(parts) = simplices(d, cell.len()) else {
            continue;
        };
        let (mut cl, mut ch) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for (j, &v) in cell.iter().enumerate() {
            verts[j] = pos(v);
            for c in 0..d {
                cl[c] = cl[c].min(verts[j][c]);
                ch[c] = ch[c].max(verts[j][c]);
            }
        }
        let span = (0..d).map(|c| ch[c] - cl[c]).fold(0.0, f64::max);
        let pad = TOUCH_TOL * span * 10.0;
        for q in 0..np {
            if hit[q] > 0.0 {
                continue;
            }
            let pb = points[q * 4 + 3] as usize;
            if pb == body {
                continue;
            }
            let p = [points[q * 4], points[q * 4 + 1], points[q * 4 + 2]];
            if !(0..d).all(|c| p[c] >= cl[c] - pad && p[c] <= ch[c] + pad) {
                continue;
            }
            let found = parts.iter().any(|s| {
                let v: Vec<[f64; 3]> = s.iter().map(|&j| verts[j]).collect();
                in_simplex(d, &v, &p)
            });
            if found {
                hit[q] = 1.0 + body as f64;
            }
        }
    }
    let mut all = vec![0.0; np];
    world.all_reduce_into(&hit[..], &mut all[..], SystemOperation::max());
    let mut counts = vec![0.0; nb * nb];
    for q in 0..np {
        if all[q] > 0.0 {
            let a = points[q * 4 + 3] as usize;
            let b = all[q] as usize - 1;
            let (a, b) = if a < b { (a, b) } else { (b, a) };
            counts[a * nb + b] += 1.0;
        }
    }
    // Every rank has every point and every verdict: the same pairs.
    let mut out = Vec::new();
    for a in 0..nb {
        for b in a + 1..nb {
            if counts[a * nb + b] > 0.0 {
                out.push(Touch {
                    a,
                    b,
                    nodes: counts[a * nb + b] as usize,
                });
            }
        }
    }
    out
}

/// Two parts whose bounding boxes overlap, and the overlap box (low, high).
type Pair = (usize, usize, [f64; 3], [f64; 3]);

/// The pairs of parts whose bounding boxes (at `pos`, padded by
/// [`BOX_TOL`]) overlap, the same on every rank.
fn overlapping_pairs<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    bodies: &Bodies,
    pos: &dyn Fn(usize) -> [f64; 3],
) -> Vec<Pair> {
    let (nb, d) = (bodies.len(), mesh.dim);
    // Each part's bounding box (at x + u), from the owned nodes.
    let mut hi = vec![f64::NEG_INFINITY; nb * 3];
    let mut lo = vec![f64::NEG_INFINITY; nb * 3]; // of -x
    for v in 0..mesh.owned_count {
        let b = bodies.node_body[v];
        let p = pos(v);
        for c in 0..d {
            hi[b * 3 + c] = hi[b * 3 + c].max(p[c]);
            lo[b * 3 + c] = lo[b * 3 + c].max(-p[c]);
        }
    }
    let mut ghi = vec![0.0f64; nb * 3];
    let mut glo = vec![0.0f64; nb * 3];
    world.all_reduce_into(&hi[..], &mut ghi[..], SystemOperation::max());
    world.all_reduce_into(&lo[..], &mut glo[..], SystemOperation::max());
    // The overlapping pairs and their overlap boxes.
    let mut pairs: Vec<Pair> = Vec::new();
    for a in 0..nb {
        for b in a + 1..nb {
            let tol = BOX_TOL * bodies.size(a).max(bodies.size(b));
            let (mut l, mut h) = ([0.0; 3], [0.0; 3]);
            let mut overlap = true;
            for c in 0..d {
                l[c] = (-glo[a * 3 + c]).max(-glo[b * 3 + c]) - tol;
                h[c] = ghi[a * 3 + c].min(ghi[b * 3 + c]) + tol;
                overlap &= l[c] <= h[c];
            }
            if overlap {
                pairs.push((a, b, l, h));
            }
        }
    }
    pairs
}

/// The warning for parts that touch (`deformed`: in the deformed shape).
pub fn warning(bodies: &Bodies, touches: &[Touch], deformed: bool) -> Option<String> {
    let t = touches.first()?;
    let d = bodies.dim();
    let at = |b: usize| {
        let c = bodies.center(b);
        (0..d)
            .map(|i| format!("{:.4}", c[i]))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let more = if touches.len() > 1 {
        format!(" (and {} other pairs of parts)", touches.len() - 1)
    } else {
        String::new()
    };
    let how = if deformed {
        "interpenetrate in the deformed shape x + u"
    } else {
        "touch or overlap in the mesh as given"
    };
    Some(format!(
        "the parts of the mesh around ({}) and ({}) {how}, at {} nodes{more}: contact between bodies is not modelled (only contact with the rigid obstacle), so they pass through each other freely; mesh them as one body if they are bonded",
        at(t.a),
        at(t.b),
        t.nodes
    ))
}

/// The touches left once the parts that a contact pair (`-contact_pair`,
/// slave and master surface groups) joins are set aside: those touch on
/// purpose. Collective.
pub fn unpaired<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    bodies: &Bodies,
    pairs: &[(String, String)],
    touches: Vec<Touch>,
) -> Vec<Touch> {
    if pairs.is_empty() || touches.is_empty() {
        return touches;
    }
    let nb = bodies.len();
    // The parts that hold each pair's slave and master facets, over every
    // rank: a rank may hold facets of one side alone (a partition between
    // the bodies), so the sides are gathered before they are joined.
    let mut sides = vec![0.0; 2 * pairs.len() * nb];
    for (k, name) in pairs.iter().flat_map(|(s, m)| [s, m]).enumerate() {
        if let Some(g) = mesh.group(name) {
            for &v in g.conn.nodes() {
                sides[k * nb + bodies.node_body[v]] = 1.0;
            }
        }
    }
    let sides = crate::comm::allreduce_max_vec(world, &sides);
    // joined[a * nb + b]: some pair's slave nodes lie in part a and its
    // master nodes in part b.
    let mut joined = vec![false; nb * nb];
    for pair in sides.chunks_exact(2 * nb) {
        let (slave, master) = pair.split_at(nb);
        for a in (0..nb).filter(|&a| slave[a] > 0.0) {
            for b in (0..nb).filter(|&b| master[b] > 0.0) {
                joined[a * nb + b] = true;
                joined[b * nb + a] = true;
            }
        }
    }
    touches
        .into_iter()
        .filter(|t| !joined[t.a * nb + t.b])
        .collect()
}
