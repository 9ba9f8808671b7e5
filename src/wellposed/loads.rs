//! Can the contact hold the loads? The check before the factorization
//! ([`check_steps`]): the loads' work on the rigid motions that only the
//! contact holds must lie in the cone of the contact forces (frictionless:
//! pushes; Coulomb: within the friction cone), a non-negative
//! least-squares problem on rank 0; with a load history, at each step's
//! load. A Tresca bound given before the solve: its total against the
//! tangential load ([`check_tresca`]).

use super::Restraint;
use crate::comm::{allreduce_sum_vec, Layout};
use crate::contact::ContactSet;
use crate::error::Error;
use crate::mesh::distribute::LocalMesh;
use mpi::traits::*;
use nalgebra::DMatrix;

/// Rays of the polygonal friction cone in 3D (the circular cone lies
/// between the polygon through the rays and the one around them).
const CONE_RAYS: usize = 16;

/// The most distinct load directions of a history [`check_steps`] judges
/// (each a small non-negative least-squares problem on rank 0): a history
/// of a million steps in as many directions is judged on its first ones.
pub const MAX_CHECKED_STEPS: usize = 10_000;

/// One load to judge: `sum_p coefs[p] parts[p]`, named by `label` (a load
/// step) in the message.
pub struct LoadStep {
    pub label: Option<String>,
    pub coefs: Vec<f64>,
}

/// The loads to judge and what may hold them: the mesh, the rigid motions
/// that no Dirichlet condition holds, the contact candidates, and the load
/// `parts` (per owned dof) that each of `steps` combines.
pub struct Judged<'a, C> {
    pub world: &'a C,
    pub mesh: &'a LocalMesh,
    pub restraint: &'a Restraint,
    pub cs: &'a ContactSet,
    pub parts: &'a [&'a [f64]],
    pub steps: &'a [LoadStep],
}

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
/// absent (frictionless contact; a Tresca bound: [`check_tresca`]).
/// `refusal`: the message of a failure in place of the check's own (the
/// frictionless solve behind a Tresca bound,
/// [`crate::wellposed::frictionless_bound_refusal`]).
///
/// At each of `steps` (combinations of the load `parts`, per owned dof),
/// the first that the contact cannot hold named: a load history applies
/// its steps' loads, not the whole load at once (which may never be
/// applied: a table of negative factors of a pulling load). The loads'
/// work on the motions and the contact's columns are made once.
pub fn check_steps<C: Communicator>(
    judged: &Judged<C>,
    coulomb: Option<f64>,
    refusal: Option<&str>,
) -> Result<(), Error> {
    let &Judged {
        world,
        mesh,
        restraint,
        cs,
        parts,
        steps,
    } = judged;
    let modes = &restraint.contact_held;
    let k = modes.len();
    if k == 0 || steps.is_empty() {
        return Ok(());
    }
    let d = mesh.dim;
    // Per part: b = f . v_j over the owned nodes, and the resultant of the
    // load on the bodies that have such motions (for the message).
    let work: Vec<f64> = parts
        .iter()
        .flat_map(|load| load_work(mesh, restraint, load))
        .collect();
    let work = allreduce_sum_vec(world, &work);
    let columns = contact_columns(mesh, restraint, cs, coulomb);
    let all = Layout::new(world, columns.len()).gather(world, &columns);
    // [the failing step + 1 (0: none), its relative residual]
    let mut verdict = [0.0f64; 2];
    if world.rank() == 0 {
        let a = DMatrix::from_column_slice(k, all.len() / k, &all);
        for (s, step) in steps.iter().enumerate() {
            let b = combine(&work, k + 3, &step.coefs);
            let bv = nalgebra::DVector::from_column_slice(&b[..k]);
            let bn = bv.norm();
            if bn > 0.0 {
                let x = nnls(&a, &bv);
                let res = (&a * &x - &bv).norm() / bn;
                if res > 1e-6 {
                    verdict = [(s + 1) as f64, res];
                    break;
                }
            }
        }
    }
    world.process_at_rank(0).broadcast_into(&mut verdict[..]);
    if verdict[0] == 0.0 {
        return Ok(());
    }
    let step = &steps[verdict[0] as usize - 1];
    let b = combine(&work, k + 3, &step.coefs);
    let why = refusal.map_or_else(
        || {
            ill_posed(
                restraint,
                &b[k..],
                cs.common_normal(),
                d,
                coulomb,
                verdict[1],
            )
        },
        str::to_string,
    );
    Err(Error::IllPosed(match &step.label {
        Some(label) => format!("{label}: {why}"),
        None => why,
    }))
}

/// `sum_p coefs[p] work[p]`, each part's `len` numbers in turn.
fn combine(work: &[f64], len: usize, coefs: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; len];
    for (w, &c) in work.chunks(len).zip(coefs) {
        out.iter_mut().zip(w).for_each(|(o, w)| *o += c * w);
    }
    out
}

/// The load's work `f . v_j` on each motion over the owned nodes, then the
/// resultant (3 numbers) on the bodies that have such motions.
fn load_work(mesh: &LocalMesh, restraint: &Restraint, load: &[f64]) -> Vec<f64> {
    let (modes, bodies) = (&restraint.contact_held, &restraint.bodies);
    let (k, d) = (modes.len(), mesh.dim);
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
    b
}

/// The columns of the owned candidates: the work of each ray of each one's
/// cone (around its own normal) on the motions, `k` numbers per ray.
fn contact_columns(
    mesh: &LocalMesh,
    restraint: &Restraint,
    cs: &ContactSet,
    coulomb: Option<f64>,
) -> Vec<f64> {
    let (modes, bodies) = (&restraint.contact_held, &restraint.bodies);
    let d = mesh.dim;
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
    cols
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
    let nu = coulomb.unwrap_or(0.0);
    let fmt = |v: f64| format!("{v:.4e}");
    // The resultant speaks plainly where the contact alone holds every
    // translation of a single body: N = F.n must push, |F_t| <= nu_f N.
    // (With normals of their own, the candidates have no one direction.)
    let translations_free = translations_free(restraint, n, d);
    let n = n.unwrap_or(&[0.0; 3][..d]);
    let (f_n, f_t) = normal_and_tangential(resultant, n);
    if translations_free && f_n <= 0.0 {
        pulled_off(f_n)
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
            "the contact cannot hold the loads: along the rigid motions that no Dirichlet condition restrains, no contact forces within the friction cone (|lambda_t| <= nu_f lambda_n = {nu} lambda_n) balance them (relative residual {:.2}), so the body slides, tips or lifts off; lower the loads, raise -friction_coefficient, or add a Dirichlet condition; {HINT}",
            residual
        )
    } else {
        format!(
            "the loads pull the body off the obstacle: along the motions that only the contact holds, no contact pressure (which can only push) balances them (relative residual {:.2}), so nothing holds the body; {HINT}",
            residual
        )
    }
}

const HINT: &str = "check the signs of the loads, the contact direction (-contact_direction points from the body toward the obstacle) and the obstacle's position";

/// Whether the contact alone holds every translation of the single body
/// and the candidates share one normal `n`: then the loads' resultant
/// must be balanced by the contact forces' (along n pushes only).
fn translations_free(restraint: &Restraint, n: Option<&[f64]>, d: usize) -> bool {
    let (modes, bodies) = (&restraint.contact_held, &restraint.bodies);
    n.is_some()
        && bodies.len() == 1
        && (0..d).all(|c| {
            let p2: f64 = modes.iter().map(|m| m.coef[c] * m.coef[c]).sum();
            p2 > 1.0 - 1e-8
        })
}

/// The parts of `f` along the unit `n` and across it (its length).
fn normal_and_tangential(f: &[f64], n: &[f64]) -> (f64, f64) {
    let f_n: f64 = n.iter().zip(f).map(|(n, f)| n * f).sum();
    let f_t = (n.iter().zip(f))
        .map(|(n, f)| (f - f_n * n).powi(2))
        .sum::<f64>()
        .sqrt();
    (f_n, f_t)
}

/// The message of loads whose resultant `f_n` along the contact direction
/// pulls the body off.
fn pulled_off(f_n: f64) -> String {
    format!(
        "the loads pull the body off the obstacle: their resultant along the contact direction is {f_n:.4e} (it must push the body onto the obstacle, > 0), and nothing else holds the body; {HINT}"
    )
}

/// Can a Tresca bound hold the loads? Where the candidates share the
/// normal n (a plane obstacle) and the contact alone holds a translation
/// `e` of the single body (no Dirichlet condition holds it), the loads'
/// work along `e` is their resultant's part `F . e`, balanced by the
/// contact forces alone: pressures along n, friction forces across it,
/// each at most `w_i s_i` whether the node touches or not (the Tresca law
/// bounds lambda_t by s alone). So where n is such a translation, F must
/// push (F . n > 0); and F's part in the free tangential translations
/// (those of the free ones across n) must be at most `sum_i w_i s_i`.
/// Else no equilibrium exists, and the iteration drifted or stalled for
/// hundreds of iterations before saying so (the Hertz quarter free along
/// x at `-tresca_bound 5`, 63 in all, under a sideways load of 480: 637
/// iterations to exit 3). A necessary condition only: the moments and
/// curved obstacles are left to the iteration. `bound`: s at the owned
/// candidates; `raise`: what raises it (the option). At each of `steps`,
/// the first that fails named, as [`check_steps`].
pub fn check_tresca<C: Communicator>(
    judged: &Judged<C>,
    bound: &[f64],
    raise: &str,
) -> Result<(), Error> {
    let (world, mesh, restraint, cs) = (judged.world, judged.mesh, judged.restraint, judged.cs);
    let d = mesh.dim;
    let (Some(n), true) = (cs.common_normal(), restraint.bodies.len() == 1) else {
        return Ok(());
    };
    let n = nalgebra::DVector::from_column_slice(&n[..d]);
    let Some((normal_free, across)) = free_translations(restraint, &n) else {
        return Ok(());
    };
    let k = restraint.contact_held.len();
    // The resultant of each part (3 numbers each), then the capacity.
    let mut sums: Vec<f64> = (judged.parts.iter())
        .flat_map(|load| load_work(mesh, restraint, load).split_off(k))
        .collect();
    sums.push((0..cs.len()).map(|i| cs.w[i] * bound[i]).sum());
    let sums = allreduce_sum_vec(world, &sums);
    let (resultants, capacity) = sums.split_at(3 * judged.parts.len());
    let capacity = capacity[0];
    let candidates = crate::comm::allreduce_count(world, cs.len());
    for step in judged.steps {
        let f = nalgebra::DVector::from_column_slice(&combine(resultants, 3, &step.coefs)[..d]);
        let (f_n, f_t) = (f.dot(&n), (&across * &f).norm());
        let why = if normal_free && f_n < -1e-9 * f.norm() {
            pulled_off(f_n)
        } else if f_t > capacity * (1.0 + 1e-9) {
            format!(
                "the tangential load {f_t:.4e} exceeds what the Tresca bound can hold, the sum of s w over the {candidates} contact candidates = {capacity:.4e}: friction cannot hold the body (no Dirichlet condition holds it along the obstacle); lower the tangential load, {raise}, or add a Dirichlet condition"
            )
        } else {
            continue;
        };
        return Err(Error::IllPosed(match &step.label {
            Some(label) => format!("{label}: {why}"),
            None => why,
        }));
    }
    Ok(())
}

/// The translations that the contact alone holds (the single body's
/// motions are orthonormal coefficients, translations first): whether n
/// is one, and the projector onto those across n (the free translations
/// orthogonal to n). None where no translation is free.
fn free_translations(
    restraint: &Restraint,
    n: &nalgebra::DVector<f64>,
) -> Option<(bool, DMatrix<f64>)> {
    let d = n.len();
    // G = sum_m t_m t_m^T (t_m: a motion's translation part) is the
    // translations' block of the projector onto the motions: a
    // translation e is free where e^T G e = 1.
    let mut g = DMatrix::<f64>::zeros(d, d);
    for m in &restraint.contact_held {
        let t = nalgebra::DVector::from_column_slice(&m.coef[..d]);
        g += &t * t.transpose();
    }
    let eig = nalgebra::SymmetricEigen::new(g);
    let free: Vec<_> = (0..d)
        .filter(|&j| eig.eigenvalues[j] > 1.0 - 1e-8)
        .map(|j| eig.eigenvectors.column(j).into_owned())
        .collect();
    if free.is_empty() {
        return None;
    }
    let mut p = DMatrix::<f64>::zeros(d, d);
    for e in &free {
        p += e * e.transpose();
    }
    // Those free translations orthogonal to n: orthogonal to P n.
    let pn = &p * n;
    let normal_free = pn.norm_squared() > 1.0 - 1e-8;
    if pn.norm() > 1e-8 {
        let q = &pn / pn.norm();
        p -= &q * q.transpose();
    }
    Some((normal_free, p))
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
/// Hanson's active-set method), for A with few rows. Solved on the problem
/// scaled to unit columns and a unit right-hand side, so that its
/// tolerances hold in any units (a micrometre model's columns are facet
/// areas of 1e-12 and below, a stress's entries 1e9).
fn nnls(a: &DMatrix<f64>, b: &nalgebra::DVector<f64>) -> nalgebra::DVector<f64> {
    let n = a.ncols();
    let mut x = nalgebra::DVector::<f64>::zeros(n);
    let bn = b.norm();
    let norms: Vec<f64> = a.column_iter().map(|c| c.norm()).collect();
    let cols: Vec<usize> = (0..n)
        .filter(|&j| norms[j] > 0.0 && norms[j].is_finite())
        .collect();
    if bn == 0.0 || !bn.is_finite() || cols.is_empty() {
        return x;
    }
    let mut unit = a.select_columns(&cols);
    for (p, &j) in cols.iter().enumerate() {
        unit.column_mut(p).scale_mut(1.0 / norms[j]);
    }
    let y = nnls_unit(&unit, &(b / bn));
    for (p, &j) in cols.iter().enumerate() {
        x[j] = y[p] * bn / norms[j];
    }
    x
}

/// [`nnls`] on unit columns and a unit right-hand side.
fn nnls_unit(a: &DMatrix<f64>, b: &nalgebra::DVector<f64>) -> nalgebra::DVector<f64> {
    let n = a.ncols();
    let mut x = nalgebra::DVector::<f64>::zeros(n);
    let mut passive = vec![false; n];
    let tol = 1e-12;
    let solve_passive = |passive: &[bool]| -> nalgebra::DVector<f64> {
        let idx: Vec<usize> = (0..n).filter(|&j| passive[j]).collect();
        let sub = a.select_columns(&idx);
        let svd = sub.svd(true, true);
        let top = svd.singular_values.max();
        let z = svd
            .solve(b, 1e-12 * top)
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
        // Each pass leaves the passive set or drops one index from it.
        for _inner in 0..=n {
            let s = solve_passive(&passive);
            if (0..n).filter(|&j| passive[j]).all(|j| s[j] > 0.0) {
                x = s;
                break;
            }
            // The step to the first passive x that reaches zero, and that
            // index (which leaves the passive set whatever its round-off).
            let (mut alpha, mut first) = (f64::INFINITY, j);
            for j in (0..n).filter(|&j| passive[j] && s[j] <= 0.0) {
                let t = x[j] / (x[j] - s[j]);
                if t < alpha {
                    (alpha, first) = (t, j);
                }
            }
            // (A new index whose solution is not positive either: no step.)
            if !alpha.is_finite() {
                alpha = 0.0;
            }
            x += (s - &x) * alpha;
            let big = x.amax();
            for j in 0..n {
                if passive[j] && (j == first || x[j] <= 1e-14 * big) {
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

    /// The same cones in any units: columns of facet areas in square
    /// micrometres (1e-14) against forces of 1e-6 or 1e9, and the reverse.
    /// (Its tolerances were absolute: on a micrometre model, the one row of
    /// a body that only the contact holds along n, its columns all below
    /// the SVD's 1e-12, made a NaN step, and the check never ended.)
    #[test]
    fn nnls_holds_in_any_units() {
        for (ca, cb) in [(1e-14, 2e-6), (1e-14, 1e9), (1e9, 1e-14), (1.0, 1.0)] {
            let a = DMatrix::from_row_slice(1, 4, &[ca, 2.0 * ca, 0.5 * ca, ca]);
            for (b, inside) in [(1.0, true), (-1.0, false)] {
                let bv = nalgebra::DVector::from_element(1, b * cb);
                let x = nnls(&a, &bv);
                let res = (&a * &x - &bv).norm() / bv.norm();
                assert_eq!(res < 1e-9, inside, "{ca} {cb} b = {b}: residual {res}");
            }
            let a = DMatrix::from_row_slice(2, 3, &[ca, 1e3 * ca, ca, 0.0, 1e3 * ca, -ca]);
            for (b, inside) in [
                ([2.0, 1.0], true),
                ([-1.0, 0.0], false),
                ([1.0, 2.0], false),
            ] {
                let bv = nalgebra::DVector::from_column_slice(&b) * cb;
                let x = nnls(&a, &bv);
                assert!(x.iter().all(|&v| v >= 0.0 && v.is_finite()));
                let res = (&a * &x - &bv).norm() / bv.norm();
                assert_eq!(res < 1e-9, inside, "{ca} {cb} b = {b:?}: residual {res}");
            }
        }
    }
}
