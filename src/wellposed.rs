//! Is the scene well posed? The rigid motions of each body (connected part
//! of the mesh) against what restrains them: Dirichlet conditions, contact
//! along n at the candidates, and, with friction, the tangential contact
//! terms. Decided from the operator before anything is assembled: a rigid
//! motion v is free when every constraint row vanishes on it, i.e. when it
//! is in the null space of the Gram matrix `G = sum_rows c c^T` (one k x k
//! matrix per body, k = 3 in 2D and 6 in 3D, reduced over the ranks), so a
//! free motion is named before any solve rather than met as a zero pivot
//! (one rank) or as an arbitrary drift (several ranks).
//!
//! The motions that no Dirichlet condition restrains are the null space of
//! the Dirichlet-eliminated stiffness K: only the augmentation terms
//! `r B^T W B` hold them in `K + r B^T W B` (the paper's floating Hertz body,
//! section 4.1's remark). They are returned for the choice of r, whose
//! spectrum they would otherwise dominate ([`crate::solver::penalty`]).

use crate::comm::{allreduce_count, allreduce_max_vec, allreduce_sum_vec, Layout};
use crate::contact::ContactSet;
use crate::error::Error;
use crate::mesh::distribute::LocalMesh;
use crate::options::{Friction, Settings, TrescaBound};
use crate::petsc::{self, sys, Gather, Vector};
use mpi::traits::*;
use nalgebra::{DMatrix, SymmetricEigen};
use pairs::{joined, pair_bodies, self_contact_faces};

mod loads;
mod pairs;
pub use loads::{check_steps, check_tresca, Judged, LoadStep, MAX_CHECKED_STEPS};

/// A mode is free when its eigenvalue of the constraint Gram matrix is below
/// this fraction of the matrix's trace (exactly free modes sit at round-off,
/// 1e-16 of it; the weakest genuine restraint of a scene, a rotation held by
/// two nodes a mesh size apart on a body 1e4 mesh sizes long, at 1e-8).
const FREE_TOL: f64 = 1e-11;

/// One rigid motion of one body, as coefficients of [`Bodies::basis`].
#[derive(Clone, Debug)]
pub struct Motion {
    pub body: usize,
    pub coef: Vec<f64>,
}

/// The bodies (connected parts) of the mesh and their rigid motions.
pub struct Bodies {
    dim: usize,
    /// Body of every local node (owned and ghost).
    pub node_body: Vec<usize>,
    /// Centre (of the bounding box) and diameter of each body.
    center: Vec<[f64; 3]>,
    size: Vec<f64>,
    /// Nodes of each body (global counts).
    nodes: Vec<usize>,
}

/// Rigid-motion basis size.
fn modes(dim: usize) -> usize {
    if dim == 2 {
        3
    } else {
        6
    }
}

impl Bodies {
    /// The connected parts of the mesh, by label propagation: each rank joins
    /// the nodes of its cells (union-find), then the smallest global node
    /// number of every part travels across the ranks through the ghost nodes
    /// until no label changes (as many rounds as the part crosses ranks).
    pub fn find<C: Communicator>(world: &C, mesh: &LocalMesh) -> Result<Bodies, Error> {
        let d = mesh.dim;
        let nloc = mesh.num_local_nodes();
        let mut parent: Vec<usize> = (0..nloc).collect();
        fn root(p: &mut [usize], mut a: usize) -> usize {
            while p[a] != a {
                p[a] = p[p[a]];
                a = p[a];
            }
            a
        }
        for cell in &mesh.cells {
            let mut r0 = root(&mut parent, cell[0]);
            for &v in &cell[1..] {
                let rv = root(&mut parent, v);
                if rv != r0 {
                    let (lo, hi) = if rv < r0 { (rv, r0) } else { (r0, rv) };
                    parent[hi] = lo;
                    r0 = lo;
                }
            }
        }
        let set: Vec<usize> = (0..nloc).map(|v| root(&mut parent, v)).collect();
        // Label of each local set: the smallest global number seen.
        let mut label = vec![u64::MAX; nloc];
        for v in 0..nloc {
            let g = mesh.node_global[v] as u64;
            label[set[v]] = label[set[v]].min(g);
        }
        let owned = mesh.owned_count;
        let labels = Vector::new(petsc::comm_world(), owned, 1)?;
        let idx: Vec<sys::PetscInt> = mesh
            .node_global
            .iter()
            .map(|&g| g as sys::PetscInt)
            .collect();
        let gather = Gather::new(&labels, &idx)?;
        loop {
            labels.write(|l| {
                for v in 0..owned {
                    l[v] = label[set[v]] as f64;
                }
            })?;
            gather.gather(&labels)?;
            let changed = gather.local.read(|all| {
                let mut changed = 0usize;
                for v in 0..nloc {
                    let seen = all[v] as u64;
                    if seen < label[set[v]] {
                        label[set[v]] = seen;
                        changed += 1;
                    }
                }
                changed
            })?;
            if allreduce_count(world, changed) == 0 {
                break;
            }
        }
        // Number the bodies by their labels, in increasing order on every rank.
        let mut mine: Vec<u64> = (0..owned).map(|v| label[set[v]]).collect();
        mine.sort_unstable();
        mine.dedup();
        let mut every = Layout::new(world, mine.len()).all_gather(world, &mine);
        every.sort_unstable();
        every.dedup();
        let nb = every.len();
        let node_body: Vec<usize> = (0..nloc)
            .map(|v| {
                every
                    .binary_search(&label[set[v]])
                    .expect("every label is some rank's")
            })
            .collect();
        // Bounding box and node count of each body.
        let mut hi = vec![f64::NEG_INFINITY; nb * 3];
        let mut lo_neg = vec![f64::NEG_INFINITY; nb * 3];
        let mut count = vec![0.0; nb];
        for (v, &b) in node_body.iter().enumerate().take(owned) {
            count[b] += 1.0;
            for (c, &x) in mesh.x(v).iter().enumerate() {
                hi[b * 3 + c] = hi[b * 3 + c].max(x);
                lo_neg[b * 3 + c] = lo_neg[b * 3 + c].max(-x);
            }
        }
        let hi = allreduce_max_vec(world, &hi);
        let lo_neg = allreduce_max_vec(world, &lo_neg);
        let count = allreduce_sum_vec(world, &count);
        let mut center = vec![[0.0; 3]; nb];
        let mut size = vec![0.0; nb];
        for b in 0..nb {
            let mut diag2 = 0.0;
            for c in 0..d {
                let (h, l) = (hi[b * 3 + c], -lo_neg[b * 3 + c]);
                center[b][c] = 0.5 * (h + l);
                diag2 += (h - l) * (h - l);
            }
            size[b] = if diag2 > 0.0 { diag2.sqrt() } else { 1.0 };
        }
        Ok(Bodies {
            dim: d,
            node_body,
            center,
            size,
            nodes: count.iter().map(|&c| c as usize).collect(),
        })
    }

    pub fn len(&self) -> usize {
        self.center.len()
    }

    /// The diameter of body `b`'s bounding box.
    pub fn size(&self, b: usize) -> f64 {
        self.size[b]
    }

    /// The centre of body `b`'s bounding box.
    pub fn center(&self, b: usize) -> [f64; 3] {
        self.center[b]
    }

    /// The mesh's dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    pub fn is_empty(&self) -> bool {
        self.center.is_empty()
    }

    /// The rigid motions of body `b` at `x`: `out[j][c]` is component c of
    /// basis motion j (translations along the axes, then the rotations about
    /// the axes through the body's centre, scaled by its diameter so that
    /// every basis motion moves the body by about 1).
    pub fn basis(&self, b: usize, x: &[f64]) -> [[f64; 3]; 6] {
        let mut out = [[0.0; 3]; 6];
        let c = &self.center[b];
        let l = self.size[b];
        let dx: Vec<f64> = (0..self.dim).map(|i| (x[i] - c[i]) / l).collect();
        for (j, row) in out.iter_mut().enumerate().take(self.dim) {
            row[j] = 1.0;
        }
        if self.dim == 2 {
            out[2] = [-dx[1], dx[0], 0.0];
        } else {
            out[3] = [0.0, -dx[2], dx[1]];
            out[4] = [dx[2], 0.0, -dx[0]];
            out[5] = [-dx[1], dx[0], 0.0];
        }
        out
    }

    /// The displacement of `m` at `x`.
    pub fn displacement(&self, m: &Motion, x: &[f64]) -> [f64; 3] {
        let basis = self.basis(m.body, x);
        let mut u = [0.0; 3];
        for (j, a) in m.coef.iter().enumerate() {
            for c in 0..self.dim {
                u[c] += a * basis[j][c];
            }
        }
        u
    }

    /// Words for a rigid motion of body `b` given by `coef`.
    fn describe(&self, b: usize, coef: &[f64]) -> String {
        let d = self.dim;
        let axis = ["x", "y", "z"];
        let (t, w) = coef.split_at(d);
        let tn = t.iter().map(|v| v * v).sum::<f64>().sqrt();
        let wn = w.iter().map(|v| v * v).sum::<f64>().sqrt();
        let dir = |v: &[f64], n: f64| -> String {
            if let Some(i) = (0..v.len()).find(|&i| (v[i].abs() / n - 1.0).abs() < 1e-6) {
                axis[i].to_string()
            } else {
                format!(
                    "({})",
                    v.iter()
                        .map(|x| format!("{:.3}", x / n))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            }
        };
        if wn <= 1e-6 * tn {
            return format!("translate along {}", dir(t, tn));
        }
        let c = &self.center[b];
        let l = self.size[b];
        if d == 2 {
            // u = t + (w/l) e_z x (x - c): a rotation about p = c + l (-t_y, t_x) / w.
            let p = [c[0] - l * t[1] / w[0], c[1] + l * t[0] / w[0]];
            return format!("rotate about the point ({:.4}, {:.4})", p[0], p[1]);
        }
        // 3D: omega = w / l; a rotation about an axis when t is orthogonal to omega.
        let along = t.iter().zip(w).map(|(a, b)| a * b).sum::<f64>() / wn;
        if along.abs() <= 1e-6 * tn.max(wn) {
            // The point of the axis closest to c: c + l (w x t) / |w|^2.
            let cr = [
                w[1] * t[2] - w[2] * t[1],
                w[2] * t[0] - w[0] * t[2],
                w[0] * t[1] - w[1] * t[0],
            ];
            let p: Vec<String> = (0..3)
                .map(|i| format!("{:.4}", c[i] + l * cr[i] / (wn * wn)))
                .collect();
            return format!(
                "rotate about the axis along {} through ({})",
                dir(w, wn),
                p.join(", ")
            );
        }
        format!(
            "move rigidly (a screw motion: translation {} with rotation about {})",
            dir(t, tn),
            dir(w, wn)
        )
    }
}

/// What holds the bodies: the motions only contact holds (for the choice of
/// r), after the check that every motion is held.
pub struct Restraint {
    pub bodies: Bodies,
    /// Rigid motions that no Dirichlet condition restrains (orthonormal
    /// coefficients per body): null vectors of the Dirichlet-eliminated K.
    pub contact_held: Vec<Motion>,
    /// Some rigid motion is held by friction alone (neither Dirichlet
    /// conditions nor contact along n restrain it): a frictionless solve of
    /// the scene has no solution. The words of the first such motion ("the
    /// body is free to translate along x").
    pub friction_held: Option<String>,
    /// Each contact pair's master body (usize::MAX when unknown).
    pub pair_master: Vec<usize>,
}

/// Checks that every rigid motion of every body is restrained, by Dirichlet
/// conditions (`dirichlet`: owned dofs `node * dim + component`), by contact
/// along n at the candidates, or by the tangential contact terms when
/// `friction`. A free motion is an ill-posed scene: an error naming it
/// (exit 2), the same on every rank.
pub fn check<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    dirichlet: &[(usize, f64)],
    cs: &ContactSet,
    friction: bool,
    pairs: &[(String, String)],
) -> Result<Restraint, Error> {
    let bodies = Bodies::find(world, mesh)?;
    let (sides, one_body) = pair_bodies(world, mesh, &bodies, pairs);
    self_contact_faces(world, cs, pairs, &one_body)?;
    let d = mesh.dim;
    let k = modes(d);
    let nb = bodies.len();
    // Per body: G_D (Dirichlet), G_C (contact along n), G_T (friction),
    // k x k each, and the number of candidates.
    let per = 3 * k * k + 1;
    let mut g = vec![0.0; nb * per];
    let mut row = [0.0; 6];
    for &(dof, _) in dirichlet {
        let (v, c) = (dof / d, dof % d);
        let b = bodies.node_body[v];
        let basis = bodies.basis(b, mesh.x(v));
        for j in 0..k {
            row[j] = basis[j][c];
        }
        add_outer(&mut g[b * per..b * per + k * k], &row[..k]);
    }
    for (i, &v) in cs.node.iter().enumerate() {
        if cs.pair.get(i).is_some_and(|&p| p != usize::MAX) {
            continue; // (a contact pair's rows: `joined` below)
        }
        let n = cs.n(i);
        let b = bodies.node_body[v];
        let basis = bodies.basis(b, mesh.x(v));
        let gc = &mut g[b * per + k * k..b * per + 2 * k * k];
        for j in 0..k {
            row[j] = (0..d).map(|c| basis[j][c] * n[c]).sum();
        }
        add_outer(gc, &row[..k]);
        if friction {
            let normal = row;
            let gt = &mut g[b * per + 2 * k * k..b * per + 3 * k * k];
            for c in 0..d {
                for j in 0..k {
                    row[j] = basis[j][c] - normal[j] * n[c];
                }
                add_outer(gt, &row[..k]);
            }
        }
        g[b * per + 3 * k * k] += 1.0;
    }
    let g = allreduce_sum_vec(world, &g);
    let (joined, pair_master) = joined(world, mesh, &bodies, cs, friction, &sides);
    let block = |b: usize, i: usize| {
        DMatrix::from_row_slice(k, k, &g[b * per + i * k * k..b * per + (i + 1) * k * k])
    };
    // What the pairs add to each body: the rows of the pairs whose other
    // body is held, until no body changes (a body that only a pair holds is
    // held once its partner is).
    let with_pairs = |b: usize, held: &[bool]| {
        let (mut gn, mut gt, mut count) = (block(b, 1), block(b, 2), 0);
        for j in joined.iter().filter(|j| j.body == b && held[j.other]) {
            gn += &j.normal;
            gt += &j.tangential;
            count += j.candidates;
        }
        (gn, gt, count)
    };
    let mut held = vec![false; nb];
    let mut changed = true;
    while changed {
        changed = false;
        for b in 0..nb {
            if held[b] {
                continue;
            }
            let (gn, gt, _) = with_pairs(b, &held);
            let all = block(b, 0) + gn + gt;
            let scale = all.trace().max(f64::MIN_POSITIVE);
            if null_space(&all, FREE_TOL * scale).is_empty() {
                held[b] = true;
                changed = true;
            }
        }
    }
    let mut contact_held = Vec::new();
    let mut friction_held = None;
    for b in 0..nb {
        let (gd, (gc, gt, paired)) = (block(b, 0), with_pairs(b, &held));
        let candidates = g[b * per + 3 * k * k] as usize + paired;
        let held_by_n = &gd + &gc;
        let all = &held_by_n + &gt;
        let scale = all.trace().max(f64::MIN_POSITIVE);
        let free = null_space(&all, FREE_TOL * scale);
        if !free.is_empty() {
            let message = free_message(&bodies, b, &free, candidates, friction, &gd);
            // A contact pair holds a body only against one that is held.
            let loose = joined.iter().any(|j| j.body == b && !held[j.other]);
            return Err(Error::IllPosed(if loose {
                format!("{message}; its contact pair (-contact_pair) joins it only to a body that is free as well: hold one of the two")
            } else {
                message
            }));
        }
        let slides = null_space(&held_by_n, FREE_TOL * scale);
        if friction && !slides.is_empty() && friction_held.is_none() {
            friction_held = Some(free_motion(&bodies, b, &slides));
        }
        for coef in null_space(&gd, FREE_TOL * scale) {
            contact_held.push(Motion { body: b, coef });
        }
    }
    Ok(Restraint {
        bodies,
        contact_held,
        friction_held,
        pair_master,
    })
}

/// `g += row row^T` (k x k, row-major).
fn add_outer(g: &mut [f64], row: &[f64]) {
    let k = row.len();
    for a in 0..k {
        for b in 0..k {
            g[a * k + b] += row[a] * row[b];
        }
    }
}

/// Orthonormal eigenvectors of the symmetric `m` whose eigenvalues are below `tol`.
fn null_space(m: &DMatrix<f64>, tol: f64) -> Vec<Vec<f64>> {
    let eig = SymmetricEigen::new(m.clone());
    (0..m.nrows())
        .filter(|&i| eig.eigenvalues[i] <= tol)
        .map(|i| eig.eigenvectors.column(i).iter().copied().collect())
        .collect()
}

/// The message for the free motions `free` (orthonormal) of body `b`: the
/// motions ([`free_motion`]) and what would hold them.
fn free_message(
    bodies: &Bodies,
    b: usize,
    free: &[Vec<f64>],
    candidates: usize,
    friction: bool,
    gd: &DMatrix<f64>,
) -> String {
    let motion = free_motion(bodies, b, free);
    // Would friction hold what is free? Only where contact candidates exist
    // and the motion is tangential; a motion that no Dirichlet condition and
    // no candidate restrains needs a Dirichlet condition.
    let held_by_dirichlet_somewhere = gd.trace() > 0.0;
    let hint = if candidates == 0 {
        if held_by_dirichlet_somewhere {
            "nothing holds it (its Dirichlet conditions do not, and it has no contact candidate against an obstacle or another body); add a Dirichlet condition"
        } else {
            "it has neither a Dirichlet condition nor a contact candidate against an obstacle or another body; add a Dirichlet condition"
        }
    } else if friction {
        "neither its Dirichlet conditions nor the contact can hold it; add a Dirichlet condition"
    } else {
        "frictionless contact cannot hold it; add a Dirichlet condition or friction"
    };
    format!("{motion}: {hint}")
}

/// Words for the rigid motions `free` (orthonormal) of body `b`: "the body
/// is free to translate along x". The canonical motions (translations along
/// the axes, rotations about the axes through the body's centre) that lie
/// in the free space are named; what remains is described as it is.
fn free_motion(bodies: &Bodies, b: usize, free: &[Vec<f64>]) -> String {
    let d = bodies.dim;
    let k = modes(d);
    let in_free = |e: &[f64]| -> bool {
        // |projection of e onto span(free)| = |e| = 1
        let p2: f64 = free
            .iter()
            .map(|f| f.iter().zip(e).map(|(a, b)| a * b).sum::<f64>().powi(2))
            .sum();
        p2 > 1.0 - 1e-8
    };
    let mut words = Vec::new();
    let mut named = 0;
    let axis = ["x", "y", "z"];
    for j in 0..k {
        let mut e = vec![0.0; k];
        e[j] = 1.0;
        if in_free(&e) {
            named += 1;
            words.push(if j < d {
                format!("translate along {}", axis[j])
            } else if d == 2 {
                "rotate in its plane".to_string()
            } else {
                format!("rotate about {}", axis[j - d])
            });
        }
    }
    if named < free.len() {
        // The free space is not spanned by canonical motions: name its basis.
        words.clear();
        for f in free {
            words.push(bodies.describe(b, f));
        }
    }
    let what = match words.len() {
        1 => words[0].clone(),
        n => format!("{} and to {}", words[..n - 1].join(", to "), words[n - 1]),
    };
    let body = if bodies.len() > 1 {
        let c = &bodies.center[b];
        format!(
            "the part of the mesh around ({}) ({} nodes, one of {} disconnected parts)",
            (0..d)
                .map(|i| format!("{:.4}", c[i]))
                .collect::<Vec<_>>()
                .join(", "),
            bodies.nodes[b],
            bodies.len()
        )
    } else {
        "the body".to_string()
    };
    format!("{body} is free to {what}")
}

/// A bound from a frictionless solve (`-tresca_bound frictionless`, the
/// default of `-friction tresca`; CF-FP's start where given) where friction
/// alone holds a body: that solve has a solution only where frictionless
/// contact holds the loads, i.e. where they do no work along the motions
/// only friction holds (a body free along x, pressed straight down, has
/// one: the x motion is then arbitrary). The message refusing such a scene
/// where the loads do work along them ([`crate::wellposed::check_steps`]
/// without friction decides); None where no frictionless solve is made or
/// every motion is held without friction. CF-FP's default start needs no
/// such solve: it sticks first ([`Restraint::friction_held`]).
pub fn frictionless_bound_refusal(restraint: &Restraint, settings: &Settings) -> Option<String> {
    let motion = restraint.friction_held.as_ref()?;
    let (which, instead) = match (settings.friction, settings.tresca_bound) {
        (Friction::Tresca, None) => (
            "the default bound of -friction tresca (-tresca_bound frictionless)",
            "give the bound (-tresca_bound VALUE) or use -friction coulomb",
        ),
        (Friction::Tresca, Some(TrescaBound::Frictionless)) => (
            "-tresca_bound frictionless",
            "give the bound (-tresca_bound VALUE) or use -friction coulomb",
        ),
        (Friction::Coulomb, Some(TrescaBound::Frictionless)) => (
            "-tresca_bound frictionless (the starting bound of -friction coulomb)",
            "leave -tresca_bound out (the first solve then sticks)",
        ),
        _ => return None,
    };
    Some(format!(
        "{which} is nu_f times the pressure of a frictionless solve, and that has no solution: without friction {motion}, and the loads move it so; {instead}, or add a Dirichlet condition that holds it"
    ))
}
