//! The paper's stopping test (4.16)/(5.6) on the condensed back-end.
//!
//! A condensed iteration knows u only at the contact nodes, but the change
//! (4.16)/(5.6) needs the whole displacement. An evaluation where every
//! other test of the paper's mode passes is kept as a candidate (a snapshot
//! of the surface state); candidates are decided together by one solve with
//! many right-hand sides, and the run goes back to the first that passes, so
//! that it stops where the uncondensed iteration does. The accuracy mode
//! (the default) needs none of this: it looks at the surface alone.
//!
//! When to decide. A solve with many right-hand sides costs about 35 ms plus
//! 7 ms per column on hertz_37473 (MUMPS walks its tree once per call), so:
//! - a candidate whose change, counting only the contact nodes' part of
//!   `||u^k - u^{k-1}||^2` and with `||u||^2` taken 10% larger than last
//!   seen, is still at least eps fails for sure: it is not solved;
//! - the newest candidate triggers the decision when its change predicted
//!   with the largest ratio seen of the whole change to its contact part
//!   (60-130 on the Hertz meshes) is below eps; the first one (nothing
//!   learnt yet), 16 pending ones, or the last evaluation of the run trigger
//!   it too.
//!
//! Every candidate not surely failing is decided, so the iteration stops
//! where the uncondensed one does, unless `||u||^2` grows by more than 10%
//! over iterations whose other tests already pass (checked on 60 runs of a
//! sweep: every count equal).

use super::mass_norms;
use super::stopping::paper_change;
use super::surface::{Surface, SurfaceState};
use crate::comm::{allreduce_max_n, allreduce_sum};
use crate::error::Error;
use crate::linalg::linear::LinearSolver;
use mpi::traits::*;

const U2_MARGIN: f64 = 1.1;
const MAX_PENDING: usize = 16;

/// A condensed evaluation whose tests but the change (4.16)/(5.6) are
/// decided (`others_ok`), or the last one of the run.
pub struct Candidate {
    /// Its outer iteration (1-based) and evaluation number.
    pub iteration: usize,
    pub evaluation: usize,
    /// Length of the inner-iteration record after it.
    pub inner_len: usize,
    pub others_ok: bool,
    /// `||phi^k - phi^{k-1}||^2` and `||phi^k||^2` (global sums), and the
    /// part of `||u^k - u^{k-1}||^2` at the contact nodes.
    pub dphi2: f64,
    pub phi2: f64,
    pub dc2: f64,
    /// The contact loads of this evaluation and of the previous one, and
    /// `u_C` of this one.
    pub c: Vec<f64>,
    pub c_prev: Vec<f64>,
    pub uc: Vec<f64>,
    pub uc_prev: Vec<f64>,
    pub snap: SurfaceState,
    pub peak_stress: f64,
    /// The change (4.16)/(5.6), once decided.
    pub change: f64,
}

/// What deciding a batch found.
pub enum Resolution {
    /// The candidate at this position passes every test.
    Converged(usize),
    /// None does.
    Open,
    /// The condensed and the full solves disagree (a matrix singular or
    /// nearly so): the run goes on without condensation.
    Inconsistent(String),
}

/// The pending candidates and what was learnt from decided ones.
#[derive(Default)]
pub struct Deferred {
    pub pending: Vec<Candidate>,
    /// `||u||^2` of the last decided candidate, and the largest ratio of
    /// the whole change of u to its contact part.
    u2: Option<f64>,
    ratio: f64,
    /// The whole displacement of the last decided candidate, and its
    /// evaluation number (0: the initial u = 0).
    pub u_prev: Vec<f64>,
    pub u_prev_of: usize,
}

impl Deferred {
    pub fn new(n: usize) -> Deferred {
        Deferred {
            u_prev: vec![0.0; n],
            ..Default::default()
        }
    }

    /// The squared change of `cand` with the contact part of
    /// `||u^k - u^{k-1}||^2` scaled by `ratio` and the last `||u||^2` by
    /// `u2_scale`; None while nothing is learnt.
    fn change2(&self, cand: &Candidate, ratio: f64, u2_scale: f64) -> Option<f64> {
        let u2 = self.u2? * u2_scale + cand.phi2;
        Some(if u2 > 0.0 {
            (ratio * cand.dc2 + cand.dphi2) / u2
        } else {
            0.0
        })
    }

    fn surely_fails(&self, cand: &Candidate, rtol: f64) -> bool {
        self.change2(cand, 1.0, U2_MARGIN)
            .is_some_and(|c2| c2 >= rtol * rtol)
    }

    fn predicted_to_pass(&self, cand: &Candidate, rtol: f64) -> bool {
        self.change2(cand, self.ratio.max(1.0), 1.0)
            .is_none_or(|c2| c2 < rtol * rtol)
    }

    /// Offers a candidate (`last`: the run's last evaluation); returns
    /// whether the pending ones are to be decided now.
    pub fn offer(&mut self, cand: Candidate, rtol: f64, last: bool) -> bool {
        if last || !self.surely_fails(&cand, rtol) {
            let decide = last
                || self.pending.len() + 1 >= MAX_PENDING
                || self.predicted_to_pass(&cand, rtol);
            self.pending.push(cand);
            decide
        } else {
            last && !self.pending.is_empty()
        }
    }

    /// Decides the pending candidates: the whole displacement of each (and
    /// of its predecessor, unless known) from one solve with many right-hand
    /// sides, checked against the condensed values at the contact nodes,
    /// then the change (4.16)/(5.6) of each in turn. Unless the two disagree,
    /// `u_prev` and `u` are then the displacement of the first candidate that
    /// passes every test, else of the last candidate.
    pub fn decide<C: Communicator>(
        &mut self,
        world: &C,
        lin: &mut LinearSolver,
        surface: &Surface,
        lumped_mass: &[f64],
        u: &crate::petsc::Vector,
        rtol: f64,
    ) -> Result<Resolution, Error> {
        let d = surface.dim;
        let cs = surface.cs;
        let n = self.u_prev.len();
        // Columns: for each candidate, its predecessor's displacement (None:
        // u_prev) and its own.
        let mut cols: Vec<(&[f64], &[f64])> = Vec::new();
        let mut prev_col = Vec::with_capacity(self.pending.len());
        let mut own_col: Vec<usize> = Vec::with_capacity(self.pending.len());
        for (i, cand) in self.pending.iter().enumerate() {
            let e = cand.evaluation;
            let prev = if e == self.u_prev_of + 1 {
                None
            } else if i > 0 && self.pending[i - 1].evaluation + 1 == e {
                Some(own_col[i - 1])
            } else {
                cols.push((&cand.c_prev, &cand.uc_prev));
                Some(cols.len() - 1)
            };
            prev_col.push(prev);
            cols.push((&cand.c, &cand.uc));
            own_col.push(cols.len() - 1);
        }
        // A condensed solve knows u at the Schur components only.
        let comps: Vec<usize> = lin
            .schur_comps()
            .map_or_else(|| (0..d).collect(), |c| c.to_vec());
        let x = lin.displacements(surface, &cols, false)?;
        let mut found = None;
        let mut chosen = self.pending.len() - 1;
        let pending = &mut self.pending;
        let u_prev = &mut self.u_prev;
        let (u2_seen, ratio) = (&mut self.u2, &mut self.ratio);
        let inconsistent = x.read(|xx| -> Result<Option<String>, Error> {
            for (i, cand) in pending.iter_mut().enumerate() {
                let uu = &xx[own_col[i] * n..(own_col[i] + 1) * n];
                let up = match prev_col[i] {
                    None => &u_prev[..],
                    Some(j) => &xx[j * n..(j + 1) * n],
                };
                let (mut diff, mut scale) = (0.0f64, 0.0f64);
                for (l, &v) in cs.node.iter().enumerate() {
                    for &k in &comps {
                        diff = diff.max((uu[v * d + k] - cand.uc[l * d + k]).abs());
                        scale = scale.max(uu[v * d + k].abs());
                    }
                }
                // Global maxima: the decision is the same on every rank.
                let [diff, scale] = allreduce_max_n(
                    world,
                    [if diff.is_nan() { f64::INFINITY } else { diff }, scale],
                );
                if diff > 1e-6 * scale {
                    return Ok(Some(format!(
                        "the condensed solve differs from the full one by {diff:.3e} at the \
                         contact nodes (displacements up to {scale:.3e}): is the body held?"
                    )));
                }
                let (du2, u2) = mass_norms(lumped_mass, d, uu, up);
                let [du2, u2] = allreduce_sum(world, [du2, u2]);
                *u2_seen = Some(u2);
                if cand.dc2 > 0.0 {
                    *ratio = ratio.max(du2 / cand.dc2);
                }
                cand.change = paper_change(du2, cand.dphi2, u2, cand.phi2);
                if !cand.change.is_finite() {
                    return Err(Error::NotConverged(format!(
                        "UBR produced a non-finite iterate at iteration {}",
                        cand.iteration
                    )));
                }
                if cand.others_ok && cand.change < rtol {
                    found = Some(i);
                    chosen = i;
                    break;
                }
            }
            let uu = &xx[own_col[chosen] * n..(own_col[chosen] + 1) * n];
            u_prev.copy_from_slice(uu);
            Ok(None)
        })??;
        if let Some(why) = inconsistent {
            return Ok(Resolution::Inconsistent(why));
        }
        self.u_prev_of = self.pending[chosen].evaluation;
        let up = &self.u_prev;
        u.write(|uu| uu.copy_from_slice(up))?;
        Ok(match found {
            Some(i) => Resolution::Converged(i),
            None => Resolution::Open,
        })
    }
}
