//! The rows of the contact pairs (`-contact_pair`) in the check of rigid
//! motions ([`super::check`]): a pair restrains each of its two bodies once
//! the other is held.

use super::{add_outer, modes, Bodies};
use crate::comm::{allreduce_max_vec, allreduce_sum_vec};
use crate::contact::ContactSet;
use crate::error::Error;
use crate::mesh::distribute::LocalMesh;
use mpi::traits::*;
use nalgebra::DMatrix;

/// What a contact pair's rows restrain on one of its two bodies, once the
/// other body is held: the slave's rows at its nodes, the master's at the
/// nodes' images (`sum_j P_kj x_j`: rigid motions are affine, so the row
/// `sum_j P_kj n . m(x_j)` is `n . m(image)`).
pub(super) struct Joined {
    pub(super) body: usize,
    pub(super) other: usize,
    pub(super) normal: DMatrix<f64>,
    pub(super) tangential: DMatrix<f64>,
    pub(super) candidates: usize,
}

/// The rows of every contact pair, by body ([`Joined`]); a pair's master
/// body is the one its master surface's nodes lie in (the last where it
/// spans several): `sides`, from [`pair_bodies`]. Collective.
pub(super) fn joined<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    bodies: &Bodies,
    cs: &ContactSet,
    friction: bool,
    sides: &[f64],
) -> (Vec<Joined>, Vec<usize>) {
    let (d, k, nb) = (mesh.dim, modes(mesh.dim), bodies.len());
    let np = sides.len() / 2;
    if np == 0 {
        return (Vec::new(), Vec::new());
    }
    // Per pair: slave normal, slave tangential, master normal, master
    // tangential (k x k each), and the candidates.
    let per = 4 * k * k + 1;
    let mut g = vec![0.0; np * per];
    let mut row = [0.0; 6];
    for (i, &v) in cs.node.iter().enumerate() {
        let p = cs.pair[i];
        if p == usize::MAX || sides[2 * p + 1] < 0.0 {
            continue;
        }
        let n = cs.n(i);
        let master = sides[2 * p + 1] as usize;
        let image = &cs.image[i * d..(i + 1) * d];
        for (side, body, x) in [(0, bodies.node_body[v], mesh.x(v)), (2, master, image)] {
            let basis = bodies.basis(body, x);
            let at = p * per + side * k * k;
            for j in 0..k {
                row[j] = (0..d).map(|c| basis[j][c] * n[c]).sum();
            }
            add_outer(&mut g[at..at + k * k], &row[..k]);
            if friction {
                let normal = row;
                for c in 0..d {
                    for j in 0..k {
                        row[j] = basis[j][c] - normal[j] * n[c];
                    }
                    add_outer(&mut g[at + k * k..at + 2 * k * k], &row[..k]);
                }
            }
        }
        g[p * per + 4 * k * k] += 1.0;
    }
    let g = allreduce_sum_vec(world, &g);
    let m = |p: usize, i: usize| {
        DMatrix::from_row_slice(k, k, &g[p * per + i * k * k..p * per + (i + 1) * k * k])
    };
    let mut out = Vec::new();
    for p in 0..np {
        let (s, ms) = (sides[2 * p], sides[2 * p + 1]);
        if s < 0.0 || ms < 0.0 || s as usize >= nb || ms as usize >= nb {
            continue;
        }
        let candidates = g[p * per + 4 * k * k] as usize;
        let (s, ms) = (s as usize, ms as usize);
        if s == ms {
            continue; // (a body's contact with itself holds none of its motions)
        }
        out.push(Joined {
            body: s,
            other: ms,
            normal: m(p, 0),
            tangential: m(p, 1),
            candidates,
        });
        out.push(Joined {
            body: ms,
            other: s,
            normal: m(p, 2),
            tangential: m(p, 3),
            candidates: 0,
        });
    }
    let masters = (0..np)
        .map(|p| match sides[2 * p + 1] {
            m if m >= 0.0 && (m as usize) < nb => m as usize,
            _ => usize::MAX,
        })
        .collect();
    (out, masters)
}

/// The bodies of each pair's two surfaces: the largest body of the slave's
/// nodes, then of the master's (-1 for a group with no node), two values
/// per pair, and whether the two surfaces lie on one body (a contact of
/// the body with itself: [`self_contact_faces`]). Collective.
pub(super) fn pair_bodies<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    bodies: &Bodies,
    pairs: &[(String, String)],
) -> (Vec<f64>, Vec<bool>) {
    // Per surface: the largest body of its nodes and minus the smallest
    // (-1 and -inf where this rank has none: neutral in the maximum).
    let none = [-1.0, f64::NEG_INFINITY];
    let span = |name: &str| -> [f64; 2] {
        mesh.group(name).map_or(none, |g| {
            g.conn.nodes().iter().fold(none, |[hi, lo], &v| {
                let b = bodies.node_body[v] as f64;
                [hi.max(b), lo.max(-b)]
            })
        })
    };
    let local: Vec<f64> = pairs
        .iter()
        .flat_map(|(s, m)| span(s).into_iter().chain(span(m)))
        .collect();
    let all = allreduce_max_vec(world, &local);
    let one_body = (0..pairs.len())
        .map(|p| {
            let [shi, slo, mhi, mlo] = [0, 1, 2, 3].map(|i| all[4 * p + i]);
            shi >= 0.0 && mhi >= 0.0 && shi == -slo && mhi == -mlo && shi == mhi
        })
        .collect();
    (all.chunks(2).map(|c| c[0]).collect(), one_body)
}

/// A pair of two surfaces of one body models the body's contact with
/// itself (a slot or a crack closing, a clip, a C-clamp): they must face
/// each other across a gap. Two faces of one body also pass the mortar's
/// facing test with the master behind the slave, through the body (a
/// block's top and bottom): the gap is minus the body's thickness, and the
/// run pressed them through each other, every element inverted. Refused
/// (exit 2) where a slave node's gap is below minus half its facets' size
/// (its nodal weight, in 3D its square root): more interference than a
/// touching curved surface's mesh makes. Collective.
pub(super) fn self_contact_faces<C: Communicator>(
    world: &C,
    cs: &ContactSet,
    pairs: &[(String, String)],
    one_body: &[bool],
) -> Result<(), Error> {
    if !one_body.contains(&true) {
        return Ok(());
    }
    // Per pair: the largest -(g + h/2) and -g over its slave nodes.
    let mut worst = vec![f64::NEG_INFINITY; 2 * pairs.len()];
    for i in 0..cs.len() {
        let p = cs.pair[i];
        if p == usize::MAX || !one_body[p] || cs.mortar[i].is_empty() {
            continue;
        }
        let h = cs.w[i].powf(1.0 / (cs.dim - 1) as f64);
        worst[2 * p] = worst[2 * p].max(-(cs.g[i] + 0.5 * h));
        worst[2 * p + 1] = worst[2 * p + 1].max(-cs.g[i]);
    }
    let worst = allreduce_max_vec(world, &worst);
    for (p, (s, m)) in pairs.iter().enumerate() {
        if one_body[p] && worst[2 * p] > 0.0 {
            return Err(Error::BadInput(format!(
                "option -contact_pair: '{s}' and '{m}' are surfaces of one body, and the master lies behind the slave, through the body (a gap of {:.4e} at a slave node); a pair of one body's surfaces models its contact with itself, two faces across a slot, a crack or a gap",
                -worst[2 * p + 1]
            )));
        }
    }
    Ok(())
}
