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
use crate::petsc::{self, sys, Gather, Vector};
use mpi::traits::*;
use nalgebra::{DMatrix, SymmetricEigen};
use pairs::{joined, pair_bodies};

mod pairs;

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
    /// the scene has no solution.
    pub friction_held: bool,
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
    let sides = pair_bodies(world, mesh, &bodies, pairs)?;
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
    let mut friction_held = false;
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
        friction_held |= friction && !null_space(&held_by_n, FREE_TOL * scale).is_empty();
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

/// The message for the free motions `free` (orthonormal) of body `b`. The
/// canonical motions (translations along the axes, rotations about the axes
/// through the body's centre) that lie in the free space are named; what
/// remains is described as it is.
fn free_message(
    bodies: &Bodies,
    b: usize,
    free: &[Vec<f64>],
    candidates: usize,
    friction: bool,
    gd: &DMatrix<f64>,
) -> String {
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
    // Would friction hold what is free? Only where contact candidates exist
    // and the motion is tangential; a motion that no Dirichlet condition and
    // no candidate restrains needs a Dirichlet condition.
    let held_by_dirichlet_somewhere = gd.trace() > 0.0;
    let hint = if candidates == 0 {
        if held_by_dirichlet_somewhere {
            "nothing holds it (its Dirichlet conditions do not, and it has no contact candidate); add a Dirichlet condition"
        } else {
            "it has neither a Dirichlet condition nor a contact candidate; add a Dirichlet condition"
        }
    } else if friction {
        "neither its Dirichlet conditions nor the contact can hold it; add a Dirichlet condition"
    } else {
        "frictionless contact cannot hold it; add a Dirichlet condition or friction"
    };
    format!("{body} is free to {what}: {hint}")
}

/// Rays of the polygonal friction cone in 3D (the circular cone lies
/// between the polygon through the rays and the one around them).
const CONE_RAYS: usize = 16;

/// Can the contact hold the loads? Along the rigid motions that no
/// Dirichlet condition restrains (`K v_j = 0`), every solution balances the
/// load's work `b_j = f . v_j` by contact forces alone:
/// `b = sum_i w_i (lambda_n,i a_i + lambda_t,i . t_i)` with
/// `a_i = (n . v_j(x_i))_j`, `t_i` the tangential displacements of the
/// motions. Frictionless contact can only push (`lambda_n >= 0`, no
/// `lambda_t`); with Coulomb friction the force lies in the cone
/// `|lambda_t| <= nu_f lambda_n`, spanned by the rays `n + nu_f t` (two in
/// 2D; in 3D a polygon of [`CONE_RAYS`] rays, taken around the circle so
/// that a load outside it is surely outside the circular cone). So the
/// scene has a solution only if b lies in the cone of those columns, a
/// non-negative least-squares problem in at most 6 rows per body (solved
/// on rank 0). Outside it no equilibrium exists, whatever the gaps (they
/// only decide where the body touches) and the prescribed displacements
/// (which do no work on these motions): the loads pull the body off the
/// obstacle, or push it along harder than friction can hold, an
/// ill-posed scene named now (exit 2) rather than met as a drift of
/// thousands of iterations. With `coulomb` None the friction is taken as
/// absent (frictionless contact; a Tresca bound is not checked here).
pub fn check_loads<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    restraint: &Restraint,
    cs: &ContactSet,
    load: &[f64],
    coulomb: Option<f64>,
) -> Result<(), Error> {
    let modes = &restraint.contact_held;
    let k = modes.len();
    if k == 0 {
        return Ok(());
    }
    let d = mesh.dim;
    let bodies = &restraint.bodies;
    // b = f . v_j over the owned nodes, and the resultant of the load on
    // the bodies that have such motions (for the message).
    let mut b = vec![0.0; k + 3];
    let mut has_modes = vec![false; bodies.len()];
    for m in modes {
        has_modes[m.body] = true;
    }
    for v in 0..mesh.owned_count {
        let x = mesh.x(v);
        let body = bodies.node_body[v];
        for (j, m) in modes.iter().enumerate() {
            if body != m.body {
                continue;
            }
            let u = bodies.displacement(m, x);
            for c in 0..d {
                b[j] += load[v * d + c] * u[c];
            }
        }
        if has_modes[body] {
            for c in 0..d {
                b[k + c] += load[v * d + c];
            }
        }
    }
    let b = allreduce_sum_vec(world, &b);
    let (b, resultant) = b.split_at(k);
    // The columns of the owned candidates (the rays of each one's cone
    // around its own normal), gathered on rank 0.
    let mut cols: Vec<f64> = Vec::new();
    for (i, &v) in cs.node.iter().enumerate() {
        let x = mesh.x(v);
        let rays = cone_rays(cs.n(i), d, coulomb);
        // A contact pair's force acts on both bodies: on the master,
        // opposite, at the node's image.
        let master = cs
            .pair
            .get(i)
            .and_then(|&p| restraint.pair_master.get(p))
            .map(|&b| (b, &cs.image[i * d..(i + 1) * d]));
        for ray in &rays {
            for m in modes {
                let work = |at: &[f64]| {
                    let u = bodies.displacement(m, at);
                    cs.w[i] * (0..d).map(|c| u[c] * ray[c]).sum::<f64>()
                };
                let mut a = if bodies.node_body[v] == m.body {
                    work(x)
                } else {
                    0.0
                };
                if let Some((_, image)) = master.filter(|&(b, _)| b == m.body) {
                    a -= work(image);
                }
                cols.push(a);
            }
        }
    }
    let root = world.process_at_rank(0);
    let all = Layout::new(world, cols.len()).gather(world, &cols);
    let mut verdict = [0.0f64; 2]; // [no equilibrium?, relative residual]
    if world.rank() == 0 {
        let total = all.len();
        let ncols = total / k;
        let a = DMatrix::from_column_slice(k, ncols, &all);
        let bv = nalgebra::DVector::from_column_slice(b);
        let bn = bv.norm();
        if bn > 0.0 {
            let x = nnls(&a, &bv);
            let res = (&a * &x - &bv).norm() / bn;
            verdict = [if res > 1e-6 { 1.0 } else { 0.0 }, res];
        }
    }
    root.broadcast_into(&mut verdict[..]);
    if verdict[0] == 0.0 {
        return Ok(());
    }
    Err(Error::IllPosed(ill_posed(
        restraint,
        resultant,
        cs.common_normal(),
        d,
        coulomb,
        verdict[1],
    )))
}

/// The rays of the (outer polygon of the) friction cone around n of
/// `coulomb`'s coefficient, or n alone (frictionless).
fn cone_rays(n: &[f64], d: usize, coulomb: Option<f64>) -> Vec<[f64; 3]> {
    let nu = coulomb.unwrap_or(0.0);
    // The tangent directions of the rays: +-t in 2D, CONE_RAYS around n in 3D.
    let tangents = tangent_rays(n);
    // The outer polygon: its rays reach nu / cos(pi / CONE_RAYS) in 3D.
    let nu_out = if d == 3 {
        nu / (std::f64::consts::PI / CONE_RAYS as f64).cos()
    } else {
        nu
    };
    if coulomb.is_some() && nu > 0.0 {
        tangents
            .iter()
            .map(|t| {
                [
                    n[0] + nu_out * t[0],
                    n[1] + nu_out * t[1],
                    n.get(2).copied().unwrap_or(0.0) + nu_out * t[2],
                ]
            })
            .collect()
    } else {
        vec![[n[0], n[1], n.get(2).copied().unwrap_or(0.0)]]
    }
}

/// Why the loads cannot be held: in words of the resultant where the
/// contact alone holds every translation of a single body, else of the
/// motions (`residual`: the relative residual of the best contact forces).
fn ill_posed(
    restraint: &Restraint,
    resultant: &[f64],
    n: Option<&[f64]>,
    d: usize,
    coulomb: Option<f64>,
    residual: f64,
) -> String {
    let (modes, bodies) = (&restraint.contact_held, &restraint.bodies);
    let nu = coulomb.unwrap_or(0.0);
    let fmt = |v: f64| format!("{v:.4e}");
    let hint = "check the signs of the loads, the contact direction (-contact_direction points from the body toward the obstacle) and the obstacle's position";
    // The resultant speaks plainly where the contact alone holds every
    // translation of a single body: N = F.n must push, |F_t| <= nu_f N.
    // (With normals of their own, the candidates have no one direction.)
    let translations_free = n.is_some()
        && bodies.len() == 1
        && (0..d).all(|c| {
            let p2: f64 = modes.iter().map(|m| m.coef[c] * m.coef[c]).sum();
            p2 > 1.0 - 1e-8
        });
    let n = n.unwrap_or(&[0.0; 3][..d]);
    let f_n: f64 = (0..d).map(|c| resultant[c] * n[c]).sum();
    let f_t = (0..d)
        .map(|c| (resultant[c] - f_n * n[c]).powi(2))
        .sum::<f64>()
        .sqrt();
    if translations_free && f_n <= 0.0 {
        format!(
            "the loads pull the body off the obstacle: their resultant along the contact direction is {} (it must push the body onto the obstacle, > 0), and nothing else holds the body; {hint}",
            fmt(f_n)
        )
    } else if translations_free && coulomb.is_some() && f_t > nu * f_n {
        format!(
            "the tangential load {} exceeds nu_f N = {} x {} = {}: friction cannot hold the body (no Dirichlet condition holds it along the obstacle); lower the tangential load, raise -friction_coefficient, or add a Dirichlet condition",
            fmt(f_t),
            nu,
            fmt(f_n),
            fmt(nu * f_n)
        )
    } else if coulomb.is_some() {
        format!(
            "the contact cannot hold the loads: along the rigid motions that no Dirichlet condition restrains, no contact forces within the friction cone (|lambda_t| <= nu_f lambda_n = {nu} lambda_n) balance them (relative residual {:.2}), so the body slides, tips or lifts off; lower the loads, raise -friction_coefficient, or add a Dirichlet condition; {hint}",
            residual
        )
    } else {
        format!(
            "the loads pull the body off the obstacle: along the motions that only the contact holds, no contact pressure (which can only push) balances them (relative residual {:.2}), so nothing holds the body; {hint}",
            residual
        )
    }
}

/// Unit tangents of the friction cone's rays around n: `t, -t` in 2D
/// (`t = (-n_y, n_x)`), [`CONE_RAYS`] directions around n in 3D.
fn tangent_rays(n: &[f64]) -> Vec<[f64; 3]> {
    if n.len() == 2 {
        return vec![[-n[1], n[0], 0.0], [n[1], -n[0], 0.0]];
    }
    // t1: the axis least aligned with n, made orthogonal; t2 = n x t1.
    let axis = (0..3)
        .min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
        .unwrap_or(0);
    let mut t1 = [0.0; 3];
    t1[axis] = 1.0;
    let dot: f64 = (0..3).map(|c| t1[c] * n[c]).sum();
    for c in 0..3 {
        t1[c] -= dot * n[c];
    }
    let norm = (t1.iter().map(|v| v * v).sum::<f64>()).sqrt();
    t1.iter_mut().for_each(|v| *v /= norm);
    let t2 = [
        n[1] * t1[2] - n[2] * t1[1],
        n[2] * t1[0] - n[0] * t1[2],
        n[0] * t1[1] - n[1] * t1[0],
    ];
    (0..CONE_RAYS)
        .map(|q| {
            let th = 2.0 * std::f64::consts::PI * q as f64 / CONE_RAYS as f64;
            let (s, c) = th.sin_cos();
            [
                c * t1[0] + s * t2[0],
                c * t1[1] + s * t2[1],
                c * t1[2] + s * t2[2],
            ]
        })
        .collect()
}

/// Non-negative least squares `min ||A x - b||, x >= 0` (Lawson and
/// Hanson's active-set method), for A with few rows.
fn nnls(a: &DMatrix<f64>, b: &nalgebra::DVector<f64>) -> nalgebra::DVector<f64> {
    let n = a.ncols();
    let mut x = nalgebra::DVector::<f64>::zeros(n);
    let mut passive = vec![false; n];
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs())) * b.norm();
    let tol = 1e-12 * scale.max(f64::MIN_POSITIVE);
    let solve_passive = |passive: &[bool]| -> nalgebra::DVector<f64> {
        let idx: Vec<usize> = (0..n).filter(|&j| passive[j]).collect();
        let sub = a.select_columns(&idx);
        let z = sub
            .svd(true, true)
            .solve(b, 1e-12)
            .unwrap_or_else(|_| nalgebra::DVector::zeros(idx.len()));
        let mut s = nalgebra::DVector::zeros(n);
        for (p, &j) in idx.iter().enumerate() {
            s[j] = z[p];
        }
        s
    };
    for _outer in 0..3 * n.max(1) {
        let w = a.transpose() * (b - a * &x);
        let Some(j) = (0..n)
            .filter(|&j| !passive[j] && w[j] > tol)
            .max_by(|&p, &q| w[p].total_cmp(&w[q]))
        else {
            break;
        };
        passive[j] = true;
        loop {
            let s = solve_passive(&passive);
            if (0..n).filter(|&j| passive[j]).all(|j| s[j] > 0.0) {
                x = s;
                break;
            }
            let mut alpha = f64::INFINITY;
            for j in (0..n).filter(|&j| passive[j] && s[j] <= 0.0) {
                alpha = alpha.min(x[j] / (x[j] - s[j]));
            }
            x += (s - &x) * alpha;
            for j in 0..n {
                if passive[j] && x[j] <= 1e-14 * scale.max(1.0) {
                    passive[j] = false;
                    x[j] = 0.0;
                }
            }
            if !passive.iter().any(|&p| p) {
                break;
            }
        }
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nnls_finds_cone_membership() {
        // Columns (1, 0), (1, 1), (1, -1): the cone is x >= |y|.
        let a = DMatrix::from_row_slice(2, 3, &[1.0, 1.0, 1.0, 0.0, 1.0, -1.0]);
        for (b, inside) in [
            ([2.0, 1.0], true),
            ([1.0, -1.0], true),
            ([-1.0, 0.0], false),
            ([1.0, 2.0], false),
        ] {
            let bv = nalgebra::DVector::from_column_slice(&b);
            let x = nnls(&a, &bv);
            assert!(x.iter().all(|&v| v >= 0.0));
            let res = (&a * &x - &bv).norm() / bv.norm();
            assert_eq!(res < 1e-9, inside, "b = {b:?}: residual {res}, x = {x}");
        }
    }
}
