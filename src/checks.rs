//! The checks of a returned solution: the discrete optimality conditions,
//! each printed value relative to a named scale, and the friction law
//! checked where it applies, at the nodes in contact (stick or slip).
//!
//! An open node may carry a leftover tangential traction of the last
//! fixed-point step (its Coulomb bound nu_f lambda_n is then 0): it says
//! nothing about the friction law, and is left out of its checks.

use crate::comm::{
    allreduce_count, allreduce_max, allreduce_max_n, allreduce_sum, allreduce_sum_vec,
};
use crate::contact::ContactSet;
use crate::error::Error;
use crate::fem;
use crate::mesh::distribute::LocalMesh;
use crate::options::{Friction, Settings};
use crate::petsc::{sys, Gather, Vector};
use crate::solver::outcome::Method;
use crate::solver::surface::UbrState;
use crate::solver::{ContactTerms, Problem};
use mpi::traits::*;

/// The discrete optimality conditions at the returned iterate.
#[derive(Clone, Debug, Default)]
pub struct Diagnostics {
    /// `||K u - f + B^T W lambda||` on the free dofs, and relative to
    /// `max(||f||, ||B^T W lambda||, ||A x_D||)` (the load, the contact
    /// forces, or the load of the prescribed displacements).
    pub equilibrium_abs: f64,
    pub equilibrium_rel: f64,
    pub load_norm: f64,
    /// Smallest and largest lambda_n over the candidates.
    pub min_lambda: f64,
    pub max_lambda: f64,
    /// `max (u_n - g)` over the candidates, `max |g|`, and the largest
    /// displacement component over the body.
    pub max_penetration: f64,
    pub max_abs_gap: f64,
    pub max_abs_u: f64,
    /// The largest initial penetration `max (-g)^+`.
    pub max_initial_penetration: f64,
    /// `sum w lambda_n (g - u_n)`, `sum w |lambda_n|`, and `sum w` (the
    /// measure of the contact surface).
    pub complementarity: f64,
    /// The largest opening `max |g - u_n|` over the candidates: the length
    /// of the complementarity's terms, which the gaps of open candidates
    /// can make far larger than the displacement (a stiff body).
    pub max_opening: f64,
    pub force_abs: f64,
    pub area: f64,
    /// The largest of the applied load and the reactions (their Euclidean
    /// norms; [`Diagnostics::with_forces`]): the force scale of the body
    /// when nothing, or little, touches.
    pub external: f64,
    /// Where no node touches: the pressure scale of the accuracy stop
    /// (the largest contact stress of UBR's first evaluation, made by the
    /// loads and the prescribed displacements); 0 where a node touches.
    /// Without it the open nodes' stresses, the iteration's leftover
    /// `r (u_n - phi)`, would be measured against themselves.
    pub idle_scale: f64,
    /// Friction, at the nodes in contact: `max (|lambda_t| - s)`, and the
    /// largest s there.
    pub max_friction_excess: f64,
    pub max_bound: f64,
    /// Largest tangential slip |u_t| over the nodes in contact, and over
    /// those that stick (with a bound above 1e-6 of the largest).
    pub max_slip: f64,
    pub max_stick_slip: f64,
    /// Whether some node in contact slides with a nonzero slip (else every
    /// slip is a sticking node's, and [`Diagnostics::stick_slip_rel`] is
    /// relative to [`Diagnostics::length`]).
    pub sliding: bool,
    /// Smallest cosine between u_t and lambda_t over the sliding nodes whose
    /// slip exceeds 1e-6 of the largest (1: same direction, (2.9)).
    pub min_slip_alignment: f64,
}

/// `a / b`, 0 when `b` is 0 (nothing to be relative to: nothing there).
fn ratio(a: f64, b: f64) -> f64 {
    if b > 0.0 {
        a / b
    } else {
        0.0
    }
}

impl Diagnostics {
    /// Sets the force scale from the loads and reactions.
    pub fn with_forces(mut self, f: &Forces) -> Diagnostics {
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        self.external = f
            .reactions
            .iter()
            .map(|(_, r)| norm(r))
            .fold(norm(&f.load), f64::max);
        self
    }
    /// The contact force scale: `max(sum w |lambda_n|, external force)`
    /// (and, where nothing touches, the idle pressure scale times the area).
    pub fn force_scale(&self) -> f64 {
        self.force_abs
            .max(self.external)
            .max(self.idle_scale * self.area)
    }
    /// The pressure scale: `max(max |lambda_n|, external force / area)`
    /// (and, where nothing touches, [`Self::idle_scale`]).
    pub fn pressure_scale(&self) -> f64 {
        let spread = ratio(self.external, self.area);
        self.max_lambda
            .max(-self.min_lambda)
            .max(spread)
            .max(self.idle_scale)
    }
    /// `min lambda_n` relative to [`Self::pressure_scale`] (0 when nonnegative).
    pub fn min_lambda_rel(&self) -> f64 {
        ratio(self.min_lambda.min(0.0), self.pressure_scale())
    }
    /// The length the normal checks are relative to: the largest
    /// displacement or initial penetration.
    pub fn length(&self) -> f64 {
        self.max_abs_u.max(self.max_initial_penetration)
    }
    /// `max (u_n - g)^+` relative to [`Self::length`].
    pub fn penetration_rel(&self) -> f64 {
        ratio(self.max_penetration.max(0.0), self.length())
    }
    /// `|sum w lambda_n (g - u_n)|` relative to [`Self::force_scale`] times
    /// the larger of [`Self::length`] and the largest opening (a force
    /// times a length: the terms' own scale, where the stresses left on
    /// open candidates, within the tolerance, meet gaps far larger than
    /// the displacement).
    pub fn complementarity_rel(&self) -> f64 {
        ratio(
            self.complementarity.abs(),
            self.force_scale() * self.length().max(self.max_opening),
        )
    }
    /// `max (|lambda_t| - s)^+` at the nodes in contact, relative to max s.
    pub fn friction_excess_rel(&self) -> f64 {
        ratio(self.max_friction_excess.max(0.0), self.max_bound)
    }
    /// The scale of the sticking nodes' slip: the largest slip where some
    /// node slides; where none does, the largest slip is a sticking node's
    /// own (their ratio would be 1 however small), and the scale is
    /// [`Self::length`].
    pub fn slip_scale(&self) -> f64 {
        if self.sliding {
            self.max_slip
        } else {
            self.length()
        }
    }
    /// The slip of the sticking nodes relative to [`Self::slip_scale`].
    pub fn stick_slip_rel(&self) -> f64 {
        ratio(self.max_stick_slip, self.slip_scale())
    }
}

/// The equilibrium residual on the free dofs and its scale (both squared,
/// this rank's sums).
fn equilibrium(p: &Problem, st: &UbrState) -> Result<(f64, f64), Error> {
    let d = p.dim;
    let cs = &p.contact;
    let au = p.lin.rhs0.duplicate()?;
    p.lin.matrix.mult(&st.u, &au)?;
    let r = if p.terms == ContactTerms::None {
        0.0
    } else {
        p.lin.r_assembled()
    };
    let sums = au.write(|a| {
        p.lin.rhs0.read(|b| {
            p.load.read(|f| {
                for (ai, bi) in a.iter_mut().zip(b) {
                    *ai -= bi;
                }
                let mut c2 = 0.0;
                for i in 0..cs.len() {
                    let base = cs.node[i] * d;
                    let w = cs.w[i];
                    let n = cs.n(i);
                    for c in 0..d {
                        // remove r B^T W B u, add B^T W lambda
                        let (bu, lam) = if p.tangential {
                            (
                                st.surface.un[i] * n[c] + st.surface.ut[i * d + c],
                                st.surface.stress_n[i] * n[c] + st.surface.stress_t[i * d + c],
                            )
                        } else {
                            (st.surface.un[i] * n[c], st.surface.stress_n[i] * n[c])
                        };
                        a[base + c] += w * (lam - r * bu);
                    }
                    // The scale: the contact forces, when the body is loaded
                    // through a prescribed displacement only.
                    c2 += (w * st.surface.stress_n[i]).powi(2);
                    if p.tangential {
                        for c in 0..d {
                            c2 += (w * st.surface.stress_t[i * d + c]).powi(2);
                        }
                    }
                }
                let (mut eq2, mut f2, mut l2) = (0.0, 0.0, 0.0);
                for (i, ai) in a.iter().enumerate() {
                    if !p.dirichlet.fixed[i] {
                        eq2 += ai * ai;
                        f2 += f[i] * f[i];
                        // Loaded by prescribed displacements: their lifting load.
                        l2 += b[i] * b[i];
                    }
                }
                (eq2, f2.max(c2).max(l2))
            })
        })
    })???;
    Ok(sums)
}

/// The friction bound the friction law is checked against: s for Tresca,
/// nu_f |lambda_n| of the returned solution for Coulomb.
pub fn friction_bound(settings: &Settings, st: &UbrState, bound: &[f64]) -> Vec<f64> {
    if settings.friction == Friction::Coulomb {
        st.surface
            .stress_n
            .iter()
            .map(|l| settings.friction_coefficient * l.abs())
            .collect()
    } else {
        bound.to_vec()
    }
}

/// The friction checks over the nodes in contact: (excess, max s, max slip,
/// max slip at stick, min cosine at slip, 1 where some node slides with a
/// nonzero slip), global (collective: every rank calls it, with or without
/// candidates).
#[allow(clippy::needless_range_loop)] // per-candidate arrays indexed together
fn friction<C: Communicator>(world: &C, p: &Problem, st: &UbrState, bound: &[f64]) -> [f64; 6] {
    let d = p.dim;
    let sf = &st.surface;
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let touching = |i: usize| sf.in_contact[i];
    // (Empty when a frictionless solve for the bound failed: no bound.)
    let b = |i: usize| bound.get(i).copied().unwrap_or(0.0);
    let mut local_bound = 0.0f64;
    for i in (0..p.contact.len()).filter(|&i| touching(i)) {
        local_bound = local_bound.max(b(i));
    }
    let max_bound = allreduce_max(world, local_bound);
    // Where the bound is meaningful: s above 1e-6 of the largest.
    let meaningful = |i: usize| touching(i) && b(i) > 1e-6 * max_bound;
    // The slip: u_t, or in a load history its change over the step
    // (quasi-static friction: u_t less the step's origin).
    let slip_of = |i: usize| -> [f64; 3] {
        let mut v = [0.0; 3];
        for c in 0..d {
            v[c] = sf.ut[i * d + c] - sf.slip_origin.get(i * d + c).copied().unwrap_or(0.0);
        }
        v
    };
    let (mut excess, mut max_slip, mut stick_slip) = (f64::NEG_INFINITY, 0.0f64, 0.0f64);
    let mut sliding = 0.0f64;
    for i in (0..p.contact.len()).filter(|&i| touching(i)) {
        let slip = norm(&slip_of(i)[..d]);
        max_slip = max_slip.max(slip);
        if !sf.slip[i] && meaningful(i) {
            stick_slip = stick_slip.max(slip);
        }
        if sf.slip[i] && slip > 0.0 {
            sliding = 1.0;
        }
        excess = excess.max(norm(&sf.stress_t[i * d..(i + 1) * d]) - b(i));
    }
    let [excess, max_slip, stick_slip, sliding] =
        allreduce_max_n(world, [excess, max_slip, stick_slip, sliding]);
    let mut min_cos = 1.0f64;
    for i in (0..p.contact.len()).filter(|&i| meaningful(i) && sf.slip[i]) {
        let sl = slip_of(i);
        let ut = &sl[..d];
        let lt = &sf.stress_t[i * d..(i + 1) * d];
        let (nu, nl) = (norm(ut), norm(lt));
        if nu > 1e-6 * max_slip && nl > 0.0 {
            let dot: f64 = ut.iter().zip(lt).map(|(a, b)| a * b).sum();
            min_cos = min_cos.min(dot / (nu * nl));
        }
    }
    let min_cos = -allreduce_max(world, -min_cos);
    let excess = if excess.is_finite() { excess } else { 0.0 };
    [excess, max_bound, max_slip, stick_slip, min_cos, sliding]
}

/// The discrete optimality conditions at the returned iterate; `bound` is
/// the friction bound per owned candidate ([`friction_bound`]; empty
/// without friction).
pub fn diagnostics<C: Communicator>(
    world: &C,
    p: &Problem,
    st: &UbrState,
    bound: &[f64],
) -> Result<Diagnostics, Error> {
    let (eq2, f2) = equilibrium(p, st)?;
    let cs = &p.contact;
    let sf = &st.surface;
    // -min lambda, max lambda, max penetration, max |g|, max |u|, max (-g),
    // max |g - u_n|
    let mut lo = [f64::NEG_INFINITY; 7];
    lo[4] =
        st.u.read(|u| u.iter().fold(0.0f64, |a, b| a.max(b.abs())))?;
    let mut compl = 0.0;
    let (mut force, mut area, mut touching) = (0.0, 0.0, 0.0);
    for i in 0..cs.len() {
        if sf.in_contact[i] {
            touching += 1.0;
        }
        let (l, un, g) = (sf.stress_n[i], sf.un[i], cs.g[i]);
        lo[0] = lo[0].max(-l);
        lo[1] = lo[1].max(l);
        lo[2] = lo[2].max(un - g);
        lo[3] = lo[3].max(g.abs());
        lo[5] = lo[5].max(-g);
        lo[6] = lo[6].max((g - un).abs());
        compl += cs.w[i] * l * (g - un);
        force += cs.w[i] * l.abs();
        area += cs.w[i];
    }
    let [eq2, f2, compl, force, area, touching] =
        allreduce_sum(world, [eq2, f2, compl, force, area, touching]);
    let m = allreduce_max_n(world, lo);
    let [excess, max_bound, max_slip, stick_slip, min_cos, sliding] = if p.tangential {
        friction(world, p, st, bound)
    } else {
        [0.0, 0.0, 0.0, 0.0, 1.0, 0.0]
    };
    Ok(Diagnostics {
        equilibrium_abs: eq2.sqrt(),
        equilibrium_rel: if f2 > 0.0 {
            (eq2 / f2).sqrt()
        } else {
            eq2.sqrt()
        },
        load_norm: f2.sqrt(),
        min_lambda: -m[0],
        max_lambda: m[1],
        max_penetration: m[2],
        max_abs_gap: m[3].max(0.0),
        max_abs_u: m[4].max(0.0),
        max_initial_penetration: m[5].max(0.0),
        complementarity: compl,
        max_opening: m[6].max(0.0),
        force_abs: force,
        area,
        external: 0.0,
        idle_scale: if touching == 0.0 {
            st.stress_scale
        } else {
            0.0
        },
        max_friction_excess: excess,
        max_bound,
        max_slip,
        max_stick_slip: stick_slip,
        sliding: sliding > 0.0,
        min_slip_alignment: min_cos,
    })
}

/// A direct solve of a singular matrix (a rigid motion nothing holds, e.g. a
/// sideways load on a frictionless body) does not always fail: the
/// equilibrium of the answer tells. The message of such a run, if it is one.
/// An iterative solver's answer is held to [`ITERATIVE_EQUILIBRIUM`]: with
/// `-ksp_atol 1e6` on the Hertz scene every solve ended before its first
/// iteration, u stayed 0, and UBR "converged" in 3 iterations to no contact
/// at all (relative residual 1.0, exit 0).
pub fn singular(
    p: &Problem,
    diag: &Diagnostics,
    name: Method,
    iterations: usize,
) -> Option<String> {
    let eq = diag.equilibrium_rel;
    if p.lin.iterative {
        return (eq > ITERATIVE_EQUILIBRIUM).then(|| format!(
            "{name} stopped after {iterations} iterations: the answer violates equilibrium (relative residual {eq:.1e}): the iterative solver's solves did not solve the elasticity problem: its tolerances (-ksp_atol, -ksp_rtol, -ksp_max_it) end them before they do, or a rigid-body motion is free; leave the tolerances to the program, or use the direct solver (the default)"
        ));
    }
    (eq > 1e-4).then(|| format!(
        "{name} stopped after {iterations} iterations: the answer violates equilibrium (relative residual {eq:.1e}): the body is not held: a rigid-body motion is free or the loads pull it off the obstacle; check the Dirichlet conditions, the loads and the obstacle"
    ))
}

/// The largest relative equilibrium residual of an iterative solver's
/// answer. Measured on converged runs (CG + GAMG, GMRES + block Jacobi; the
/// Hertz scene, the 3D block, Coulomb, a pair of blocks, a friction-held
/// roller; `-ksp_rtol` up to 0.9): at most 6e-6.
const ITERATIVE_EQUILIBRIUM: f64 = 1e-3;

/// `u` at every local node (owned and ghost), node-major (collective).
pub fn local_displacement(local: &LocalMesh, u: &Vector) -> Result<Vec<f64>, Error> {
    let d = local.dim;
    let idx: Vec<sys::PetscInt> = local
        .node_global
        .iter()
        .flat_map(|&g| (0..d).map(move |c| (g * d + c) as sys::PetscInt))
        .collect();
    let gather = Gather::new(u, &idx)?;
    gather.gather(u)?;
    gather.local.read(|v| v.to_vec())
}

/// The contact pairs' forces on their slave nodes (`w (lambda_n n +
/// lambda_t)`, this rank's owned dofs; empty without a pair).
pub fn slave_forces(local: &LocalMesh, p: &Problem, st: &UbrState) -> Vec<f64> {
    let (d, cs) = (p.dim, &p.contact);
    if p.transform.is_none() {
        return Vec::new();
    }
    let mut f = vec![0.0; local.owned_count * d];
    for i in (0..cs.len()).filter(|&i| cs.pair[i] != usize::MAX) {
        for c in 0..d {
            let mut lam = st.surface.stress_n[i] * cs.n(i)[c];
            if p.tangential {
                lam += st.surface.stress_t[i * d + c];
            }
            f[cs.node[i] * d + c] += cs.w[i] * lam;
        }
    }
    f
}

/// The forces on the body, summed over all ranks.
#[derive(Clone, Debug, Default)]
pub struct Forces {
    /// What the obstacle exerts, `-sum w (lambda_n n + lambda_t)`.
    pub contact: Vec<f64>,
    /// The applied loads: tractions, pressures, body force.
    pub load: Vec<f64>,
    /// The reaction force of each Dirichlet group (by its name), which its
    /// prescribed components exert: `K u - f + B^T W lambda` summed over
    /// them (a component prescribed by two groups counts for the first).
    pub reactions: Vec<(String, Vec<f64>)>,
    /// Per obstacle (`-obstacles`; one, named "obstacle", without): its
    /// name, the force it exerts on the body, and its nodes in contact.
    pub obstacles: Vec<(String, Vec<f64>, usize)>,
}

impl Forces {
    /// `contact + load + sum of reactions`: zero at equilibrium.
    pub fn imbalance(&self) -> Vec<f64> {
        let mut s: Vec<f64> = self
            .contact
            .iter()
            .zip(&self.load)
            .map(|(a, b)| a + b)
            .collect();
        for (_, r) in &self.reactions {
            s.iter_mut().zip(r).for_each(|(a, b)| *a += b);
        }
        s
    }
}

/// The contact force, the total load and the reaction of each Dirichlet
/// group; `u_local` from [`local_displacement`].
pub fn forces<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    settings: &Settings,
    p: &Problem,
    st: &UbrState,
    u_local: &[f64],
) -> Result<Forces, Error> {
    let d = p.dim;
    let cs = &p.contact;
    let nown = local.owned_count * d;
    let load = p.load.read(|f| f.to_vec())?;
    // Each prescribed owned dof, to the first group (by name) that prescribes it.
    let mut owner = vec![usize::MAX; nown];
    for (g, bc) in settings.dirichlet.iter().enumerate() {
        let group = local.group(&bc.group).expect("checked at assembly");
        for &v in group.conn.nodes().iter().filter(|&&v| local.is_owned(v)) {
            for &(c, _) in &bc.comps {
                if owner[v * d + c] == usize::MAX {
                    owner[v * d + c] = g;
                }
            }
        }
    }
    let wanted: Vec<bool> = owner.iter().map(|&g| g != usize::MAX).collect();
    let mut r = fem::loads::stiffness_rows(local, settings, u_local, &wanted)?;
    let mut contact = vec![0.0; d];
    let names: Vec<String> = settings
        .contact
        .as_ref()
        .map(|c| {
            let pairs = c.pairs.iter().map(|(s, m)| format!("{s}/{m}"));
            c.obstacles
                .iter()
                .map(|o| o.name.clone())
                .chain(pairs)
                .collect()
        })
        .unwrap_or_default();
    // Per obstacle (and contact pair): its force (d values) and its nodes
    // in contact. A pair's force is internal: on the slave here, its
    // mortar share on the master below.
    let mut each = vec![0.0; names.len() * (d + 1)];
    let mut slave_force = vec![0.0; if p.transform.is_some() { nown } else { 0 }];
    for i in 0..cs.len() {
        let w = cs.w[i];
        let k = cs.obstacle.get(i).copied().unwrap_or(0);
        let paired = cs.pair.get(i).is_some_and(|&q| q != usize::MAX);
        for c in 0..d {
            let mut lam = st.surface.stress_n[i] * cs.n(i)[c];
            if p.tangential {
                lam += st.surface.stress_t[i * d + c];
            }
            if paired {
                slave_force[cs.node[i] * d + c] += w * lam;
            } else {
                r[cs.node[i] * d + c] += w * lam;
                contact[c] -= w * lam;
            }
            if let Some(f) = each.get_mut(k * (d + 1) + c) {
                *f -= w * lam;
            }
        }
        if st.surface.in_contact[i] {
            if let Some(n) = each.get_mut(k * (d + 1) + d) {
                *n += 1.0;
            }
        }
    }
    if let Some(t) = &p.transform {
        // On both sides: 2 F - T^T F (F on the slave, minus its share,
        // T^T F - F, on the master).
        let share = t.transpose_apply(&slave_force, d)?;
        for (ri, (f, g)) in r.iter_mut().zip(slave_force.iter().zip(&share)) {
            *ri += 2.0 * f - g;
        }
    }
    let each = allreduce_sum_vec(world, &each);
    let obstacles = names
        .into_iter()
        .enumerate()
        .map(|(k, name)| {
            let e = &each[k * (d + 1)..(k + 1) * (d + 1)];
            (name, e[..d].to_vec(), e[d] as usize)
        })
        .collect();
    let mut sums = vec![0.0; d * (settings.dirichlet.len() + 1)];
    for (i, &g) in owner.iter().enumerate() {
        sums[i % d] += load[i];
        if g != usize::MAX {
            sums[(g + 1) * d + i % d] += r[i] - load[i];
        }
    }
    let sums = allreduce_sum_vec(world, &sums);
    let contact = allreduce_sum_vec(world, &contact);
    Ok(Forces {
        contact,
        load: sums[..d].to_vec(),
        reactions: settings
            .dirichlet
            .iter()
            .enumerate()
            .map(|(g, bc)| (bc.group.clone(), sums[(g + 1) * d..(g + 2) * d].to_vec()))
            .collect(),
        obstacles,
    })
}

/// The model is small-deformation: strains above this are warned about.
pub const STRAIN_LIMIT: f64 = 0.05;

/// Set-ups that are probably wrong, found before the solve (one line each):
/// a Dirichlet condition along n on contact candidates, a traction on the
/// components a Dirichlet condition prescribes at the same nodes.
pub fn setup_warnings<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    settings: &Settings,
    dirichlet: &[(usize, f64)],
    cs: &ContactSet,
) -> Result<Vec<String>, Error> {
    let d = local.dim;
    let mut fixed = vec![false; local.owned_count * d];
    for &(i, _) in dirichlet {
        fixed[i] = true;
    }
    let mut out = Vec::new();
    // Candidates whose prescribed components have a part along n_i.
    let along_n = |i: usize| {
        (0..d)
            .filter(|&c| fixed[cs.node[i] * d + c])
            .map(|c| cs.n(i)[c].powi(2))
            .sum::<f64>()
            > 1e-6
    };
    let mut counts = vec![0.0; settings.dirichlet.len()];
    for (g, bc) in settings.dirichlet.iter().enumerate() {
        let Some(group) = local.group(&bc.group) else {
            continue;
        };
        let nodes: std::collections::HashSet<usize> = group.conn.nodes().iter().copied().collect();
        counts[g] = (0..cs.len())
            .filter(|&i| nodes.contains(&cs.node[i]) && along_n(i))
            .count() as f64;
    }
    counts.push(cs.len() as f64);
    let counts = allreduce_sum_vec(world, &counts);
    let (counts, candidates) = counts.split_at(settings.dirichlet.len());
    // A corner or an edge shared with a Dirichlet boundary is common; a
    // tenth of the surface is not.
    let many = 0.1 * candidates[0];
    let surface = settings
        .contact
        .as_ref()
        .map(|c| c.surface_names())
        .unwrap_or_default();
    for (bc, &n) in settings
        .dirichlet
        .iter()
        .zip(counts)
        .filter(|(_, &n)| n > many)
    {
        out.push(format!(
            "-dirichlet_{} prescribes part of the displacement along the contact direction n at {n} contact candidates of '{surface}': there the contact acts through the free components alone (a Dirichlet condition on the contact surface)",
            bc.group
        ));
    }
    // Tractions on components prescribed at (most of) the group's nodes.
    for t in &settings.traction {
        let Some(group) = local.group(&t.group) else {
            continue;
        };
        let mut nodes: Vec<usize> = group
            .conn
            .nodes()
            .iter()
            .copied()
            .filter(|&v| local.is_owned(v))
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        for c in (0..d).filter(|&c| t.traction.get(c).is_some_and(|&x| x != 0.0)) {
            let held = nodes.iter().filter(|&&v| fixed[v * d + c]).count();
            let [held, total] = allreduce_sum(world, [held as f64, nodes.len() as f64]);
            if total > 0.0 && held > 0.5 * total {
                out.push(format!(
                    "-traction_{} acts on u{}, which a Dirichlet condition prescribes at {held} of its {total} nodes: that load goes into the support and moves nothing",
                    t.group,
                    ["x", "y", "z"][c]
                ));
            }
        }
    }
    out.extend(penetration_warning(world, local, cs));
    if let Some(contact) = &settings.contact {
        if cs.uniform && cs.direction.len() == d {
            let cells_of = fem::loads::cells_around(local);
            for name in &contact.surfaces {
                out.extend(facing_warning(world, local, &cells_of, name, &cs.direction));
            }
        }
    }
    Ok(out)
}

/// A contact surface whose outward normal points against the contact
/// direction on most of its area (`-contact_surface top` for a body resting
/// on a floor along `0,-1`: the obstacle lies behind the body as seen from
/// that surface). Its nodes can only reach the obstacle through the body:
/// a floating body was moved through it rigidly, exit 0. The facets are
/// oriented outward by the cell that holds them, each counted by the rank
/// that owns its lowest global node.
fn facing_warning<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    cells_of: &std::collections::HashMap<usize, Vec<usize>>,
    name: &str,
    n: &[f64],
) -> Option<String> {
    let group = local.group(name).filter(|g| g.dim + 1 == local.dim)?;
    let (mut away, mut total) = (0.0, 0.0);
    let mut weights = Vec::with_capacity(4);
    for f in &group.conn {
        let low = f.iter().min_by_key(|&&v| local.node_global[v]);
        if !low.is_some_and(|&v| local.is_owned(v)) {
            continue;
        }
        let Some(cell) = fem::loads::facet_cell(local, cells_of, f) else {
            continue;
        };
        let pts: Vec<&[f64]> = f.iter().map(|&v| local.x(v)).collect();
        let outward = fem::loads::outward_normal(local, &pts, cell);
        crate::element::facet_weights(&pts, &mut weights);
        let size: f64 = weights.iter().sum();
        total += size;
        if outward.iter().zip(n).map(|(a, b)| a * b).sum::<f64>() < -0.1 {
            away += size;
        }
    }
    let [away, total] = allreduce_sum(world, [away, total]);
    if !(total > 0.0 && away > 0.5 * total) {
        return None;
    }
    let n: Vec<String> = n.iter().map(|v| format!("{v}")).collect();
    Some(format!(
        "contact surface '{name}' faces away from the obstacle: on {:.0}% of its area its outward normal points against the contact direction n = ({}), so its nodes reach the obstacle only through the body; check that '{name}' is the surface that meets the obstacle and that -contact_direction points from the body toward it",
        100.0 * away / total,
        n.join(",")
    ))
}

/// The initial penetration, as a fraction of the mesh's largest extent,
/// from which a set-up is named as probably wrong: an interference fit is
/// far below it, a contact direction of the wrong sign or an obstacle point
/// in another unit far above.
pub const DEEP_PENETRATION: f64 = 0.05;

/// Candidates that start inside the obstacle (or behind their master
/// surface) by more than [`DEEP_PENETRATION`] of the mesh's largest extent.
fn penetration_warning<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    cs: &ContactSet,
) -> Option<String> {
    let d = local.dim;
    // The bounding box of the owned nodes: max of x and of -x per axis.
    let mut bb = [f64::NEG_INFINITY; 6];
    for v in 0..local.owned_count {
        for (c, &x) in local.x(v).iter().enumerate() {
            bb[c] = bb[c].max(x);
            bb[3 + c] = bb[3 + c].max(-x);
        }
    }
    let deepest = cs.g.iter().fold(0.0f64, |m, &g| m.max(-g));
    let mut m = [0.0; 7];
    m[..6].copy_from_slice(&bb);
    m[6] = deepest;
    let m = allreduce_max_n(world, m);
    let extent = (0..d).map(|c| m[c] + m[3 + c]).fold(0.0, f64::max);
    let deepest = m[6];
    if !(extent > 0.0 && deepest > DEEP_PENETRATION * extent) {
        return None;
    }
    let inside = cs.g.iter().filter(|&&g| g < 0.0).count();
    let [inside, all] = allreduce_sum(world, [inside as f64, cs.len() as f64]);
    Some(format!(
        "{inside} of {all} contact candidates start inside the obstacle (or behind their master surface), by up to {deepest:.4e}, {:.0}% of the mesh's largest extent {extent:.4e}: the contact pushes them out by that much; check the sign of -contact_direction (from the body toward the obstacle), -obstacle_point, and that the mesh and the obstacle use one unit of length",
        100.0 * deepest / extent
    ))
}

/// How far the answer is from small deformations.
#[derive(Clone, Debug, Default)]
pub struct Deformation {
    /// The largest principal strain (absolute value) over the cells.
    pub max_strain: f64,
    /// Cells whose deformed shape `x + u` is inverted.
    pub inverted: usize,
}

/// The strain and inversion of every cell, each counted by the rank that
/// owns its smallest global node.
pub fn deformation<C: Communicator>(world: &C, local: &LocalMesh, u_local: &[f64]) -> Deformation {
    let d = local.dim;
    let (mut xs, mut us) = (Vec::with_capacity(8 * d), Vec::with_capacity(8 * d));
    let (mut max_strain, mut inverted) = (0.0f64, 0usize);
    for cell in &local.cells {
        let first = cell.iter().min_by_key(|&&v| local.node_global[v]);
        if !first.is_some_and(|&v| local.is_owned(v)) {
            continue;
        }
        xs.clear();
        us.clear();
        for &v in cell {
            xs.extend_from_slice(local.x(v));
            us.extend_from_slice(&u_local[v * d..(v + 1) * d]);
        }
        let (e, inv) = fem::deformation::cell_deformation(d, &xs, &us, max_strain);
        max_strain = max_strain.max(e);
        inverted += usize::from(inv);
    }
    Deformation {
        max_strain: allreduce_max(world, max_strain),
        inverted: allreduce_count(world, inverted),
    }
}

/// Results that say the set-up is probably wrong (one line each): nothing
/// in contact with the obstacle behind the body along n; strains beyond
/// small deformations, or inverted cells.
pub fn result_warnings<C: Communicator>(
    world: &C,
    local: &LocalMesh,
    settings: &Settings,
    cs: &ContactSet,
    st: &UbrState,
    shape: &Deformation,
) -> Vec<String> {
    let mut out = Vec::new();
    let d = local.dim;
    if settings.friction == Friction::Tresca {
        out.extend(tresca_on_open(world, cs, st));
    }
    let in_contact = allreduce_count(world, st.surface.in_contact.iter().filter(|&&c| c).count());
    // (Along the one normal that the candidates share.)
    if let (0, Some(contact)) = (in_contact, settings.contact.as_ref().filter(|_| cs.uniform)) {
        // The body's centre (mean of its nodes) against the obstacle.
        let mut sums = vec![0.0; d + 1];
        for v in 0..local.owned_count {
            sums.iter_mut().zip(local.x(v)).for_each(|(s, x)| *s += x);
            sums[d] += 1.0;
        }
        let sums = allreduce_sum_vec(world, &sums);
        let ahead: f64 = (0..d)
            .map(|c| (contact.obstacle.anchor()[c] - sums[c] / sums[d]) * contact.direction[c])
            .sum();
        if ahead < 0.0 {
            let flipped: Vec<String> = contact
                .direction
                .iter()
                .map(|v| (-v + 0.0).to_string())
                .collect();
            out.push(format!(
                "no node is in contact, and the obstacle lies behind the body along the contact direction n: n must point from the body toward the obstacle (did you mean -contact_direction {}?)",
                flipped.join(",")
            ));
        }
    }
    if shape.inverted > 0 {
        out.push(format!(
            "{} of {} elements invert in the deformed shape x + u (largest strain {}): the model is linear elasticity, for small deformations, and this answer is not physical; reduce the load or the prescribed displacement",
            shape.inverted,
            local.global_cells,
            percent(shape.max_strain)
        ));
    } else if shape.max_strain > STRAIN_LIMIT {
        out.push(format!(
            "the largest strain is {:.1}% (above {:.0}%): the model is linear elasticity, for small deformations; at such strains its answer departs from a large-deformation one",
            100.0 * shape.max_strain,
            100.0 * STRAIN_LIMIT
        ));
    }
    out
}

/// A strain as a percentage, "458%"; past 1e6 % (a load absurd against E)
/// with an exponent, "9.19e33%".
fn percent(strain: f64) -> String {
    let p = 100.0 * strain;
    if p.abs() >= 1e6 {
        format!("{p:.2e}%")
    } else {
        format!("{p:.0}%")
    }
}

/// Friction carried by open candidates above this fraction of the whole
/// friction force is named (Tresca).
const OPEN_FRICTION: f64 = 0.05;

/// The paper's Tresca law bounds the friction by s on all of Gamma_C,
/// whether the node touches or not ([`crate::solver::ubr`], (5.2)): with a
/// constant bound, candidates that never reach the obstacle carry friction
/// too. Named when they carry more than [`OPEN_FRICTION`] of it.
fn tresca_on_open<C: Communicator>(world: &C, cs: &ContactSet, st: &UbrState) -> Option<String> {
    let d = cs.dim;
    let sf = &st.surface;
    // [sum w |lambda_t| on open candidates, on all, open count carrying
    // friction, sum w lambda_n]
    let mut acc = [0.0; 4];
    for i in 0..cs.len() {
        let lt = (0..d)
            .map(|c| sf.stress_t[i * d + c].powi(2))
            .sum::<f64>()
            .sqrt();
        let f = cs.w[i] * lt;
        acc[1] += f;
        acc[3] += cs.w[i] * sf.stress_n[i].max(0.0);
        if !sf.in_contact[i] && lt > 0.0 {
            acc[0] += f;
            acc[2] += 1.0;
        }
    }
    let [open, all, count, normal] = allreduce_sum(world, acc);
    if all <= 0.0 || open <= OPEN_FRICTION * all {
        return None;
    }
    Some(format!(
        "Tresca friction acts on {count:.0} open candidates (nodes that do not touch the obstacle): they carry {:.0}% of the friction force ({:.4e} of {:.4e}, against a total contact force of {:.4e}), because the Tresca law bounds the friction by -tresca_bound on the whole contact surface, touching or not (the paper's model); for friction only where the body touches, use -friction coulomb or -tresca_bound frictionless (nu_f times the frictionless contact pressure)",
        100.0 * open / all,
        open,
        all,
        normal
    ))
}
