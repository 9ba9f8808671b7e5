//! Checks of a surface (degenerate elements, orientation, manifoldness,
//! open boundary) and its pseudo-normals at edges and vertices.

use super::geom::{self, V3};
use super::Surface;
use crate::error::Error;
use std::collections::HashMap;

/// Relative size below which an element is degenerate.
const DEGENERATE: f64 = 1e-12;

/// The unit outward normal of each element; an error on the first
/// degenerate one (zero length, or zero area against its longest edge).
pub(super) fn face_normals(s: &Surface) -> Result<Vec<V3>, Error> {
    if s.elems.is_empty() {
        return s.error(if s.dim == 3 {
            "no triangles or quadrilaterals (the surface of a 3D obstacle)"
        } else {
            "no line elements (the boundary of a 2D obstacle)"
        });
    }
    let mut size: f64 = 0.0;
    for p in &s.coords {
        size = size.max(geom::norm(p));
    }
    let mut out = Vec::with_capacity(s.elems.len());
    for (e, c) in s.elems.iter().enumerate() {
        let [a, b, d] = c.map(|i| s.coords[i]);
        let ab = geom::sub(&b, &a);
        let (n, degenerate) = if s.dim == 2 {
            let len = geom::norm(&ab);
            ([ab[1], -ab[0], 0.0], len <= DEGENERATE * size)
        } else {
            let ad = geom::sub(&d, &a);
            let bd = geom::sub(&d, &b);
            let n = geom::cross(&ab, &ad);
            let longest = geom::norm(&ab).max(geom::norm(&ad)).max(geom::norm(&bd));
            let tiny = longest <= DEGENERATE * size;
            (n, tiny || geom::norm(&n) <= DEGENERATE * longest * longest)
        };
        if degenerate || !geom::norm(&n).is_finite() {
            let nodes: Vec<String> = c[..s.dim].iter().map(|&i| s.node_name(i)).collect();
            return s.error(format_args!(
                "{} ({}) is degenerate (zero {})",
                s.elem_name(e),
                nodes.join(", "),
                if s.dim == 2 { "length" } else { "area" }
            ));
        }
        out.push(geom::unit(&n));
    }
    Ok(out)
}

/// Pseudo-normals and the open boundary of a checked surface.
pub(super) struct Topology {
    pub edge_n: Vec<[V3; 3]>,
    pub vert_n: Vec<V3>,
    pub open: usize,
    pub first_open: Option<String>,
}

/// Checks orientation and manifoldness; pseudo-normals (Baerentzen and
/// Aanaes 2005) and the open boundary.
pub(super) fn build(s: &Surface, face_n: &[V3]) -> Result<Topology, Error> {
    if s.dim == 2 {
        build_2d(s, face_n)
    } else {
        build_3d(s, face_n)
    }
}

/// A node's segments: (element, the node is its start).
fn build_2d(s: &Surface, face_n: &[V3]) -> Result<Topology, Error> {
    let n = s.coords.len();
    let mut uses: Vec<Vec<(usize, bool)>> = vec![Vec::new(); n];
    for (e, c) in s.elems.iter().enumerate() {
        uses[c[0]].push((e, true));
        uses[c[1]].push((e, false));
    }
    let mut vert_n = vec![[0.0; 3]; n];
    let mut open = 0;
    let mut first_open = None;
    // In element order, so that the message names the first problem.
    for c in &s.elems {
        for &i in &c[..2] {
            let u = &uses[i];
            if u.len() > 2 {
                let els: Vec<String> = u.iter().map(|&(e, _)| s.elem_name(e)).collect();
                return s.error(format_args!(
                    "{} is in {} segments ({}): not a manifold curve",
                    s.node_name(i),
                    u.len(),
                    els.join(", ")
                ));
            }
            if let [(e1, start1), (e2, start2)] = u[..] {
                if start1 == start2 {
                    return s.error(format_args!(
                        "{} and {} both {} at {}: inconsistent orientation (each segment must \
                         end where the next one starts; Gmsh writes a line's elements its own \
                         way, whatever sign a Curve Loop gives it: draw the lines head to tail, \
                         or turn one with Reverse Curve {{n}};)",
                        s.elem_name(e1),
                        s.elem_name(e2),
                        if start1 { "start" } else { "end" },
                        s.node_name(i)
                    ));
                }
            }
        }
    }
    for (i, u) in uses.iter().enumerate() {
        for &(e, _) in u {
            vert_n[i] = geom::add(&vert_n[i], &face_n[e]);
        }
        if u.len() == 1 {
            open += 1;
            if first_open.is_none() {
                first_open = Some(format!(
                    "{} is an end of {} only",
                    s.node_name(i),
                    s.elem_name(u[0].0)
                ));
            }
        }
    }
    Ok(Topology {
        edge_n: Vec::new(),
        vert_n,
        open,
        first_open,
    })
}

/// An undirected edge's triangles: (element, local edge, forward).
type EdgeUses = HashMap<(usize, usize), Vec<(usize, usize, bool)>>;

fn edge_key(a: usize, b: usize) -> ((usize, usize), bool) {
    if a < b {
        ((a, b), true)
    } else {
        ((b, a), false)
    }
}

fn build_3d(s: &Surface, face_n: &[V3]) -> Result<Topology, Error> {
    let mut edges: EdgeUses = HashMap::with_capacity(s.elems.len() * 2);
    let mut vert_n = vec![[0.0; 3]; s.coords.len()];
    for (e, c) in s.elems.iter().enumerate() {
        for k in 0..3 {
            let (key, fwd) = edge_key(c[k], c[(k + 1) % 3]);
            edges.entry(key).or_default().push((e, k, fwd));
            // The angle at corner k weighs the face normal there.
            let p = s.coords[c[k]];
            let to_next = geom::sub(&s.coords[c[(k + 1) % 3]], &p);
            let to_prev = geom::sub(&s.coords[c[(k + 2) % 3]], &p);
            let w = geom::angle(&to_next, &to_prev);
            vert_n[c[k]] = geom::axpy(&vert_n[c[k]], w, &face_n[e]);
        }
    }
    let mut edge_n = vec![[[0.0; 3]; 3]; s.elems.len()];
    let mut open = 0;
    let mut first_open = None;
    for (e, c) in s.elems.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (c[k], c[(k + 1) % 3]);
            let uses = &edges[&edge_key(a, b).0];
            let edge = || format!("edge ({}, {})", s.node_name(a), s.node_name(b));
            match uses[..] {
                [_] => {
                    open += 1;
                    if first_open.is_none() {
                        first_open = Some(format!("{} is in {} only", edge(), s.elem_name(e)));
                    }
                    edge_n[e][k] = face_n[e];
                }
                [(e1, _, f1), (e2, _, f2)] => {
                    if f1 == f2 {
                        return s.error(format_args!(
                            "{} and {} traverse their shared {} in the same direction: \
                             inconsistent orientation (the right-hand rule must give the \
                             outward side of both; in Gmsh, Reverse Surface {{n}}; turns a \
                             surface's triangles)",
                            s.elem_name(e1),
                            s.elem_name(e2),
                            edge()
                        ));
                    }
                    edge_n[e][k] = geom::add(&face_n[e1], &face_n[e2]);
                }
                _ => {
                    let els: Vec<String> = uses.iter().map(|&(t, _, _)| s.elem_name(t)).collect();
                    return s.error(format_args!(
                        "{} is in {} triangles ({}): not a manifold surface",
                        edge(),
                        uses.len(),
                        els.join(", ")
                    ));
                }
            }
        }
    }
    Ok(Topology {
        edge_n,
        vert_n,
        open,
        first_open,
    })
}

/// The connected part of each element (elements that share a node are in
/// one part), numbered from 0 in the order of their first element, and
/// how many parts.
pub(super) fn components(s: &Surface) -> (Vec<u32>, usize) {
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut parent: Vec<usize> = (0..s.coords.len()).collect();
    for c in &s.elems {
        let a = root(&mut parent, c[0]);
        for &v in &c[1..s.dim] {
            let b = root(&mut parent, v);
            parent[b] = a;
        }
    }
    let mut number = HashMap::new();
    let part = s
        .elems
        .iter()
        .map(|c| {
            let r = root(&mut parent, c[0]);
            let next = number.len() as u32;
            *number.entry(r).or_insert(next)
        })
        .collect();
    (part, number.len())
}
