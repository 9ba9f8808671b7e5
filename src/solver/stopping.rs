//! When to stop a UBR run: one module for every algorithm.
//!
//! - **paper** (`-ubr_stop paper`): the relative change (4.16)/(5.6) of
//!   `(u, phi)` below eps and, as in section 7, the constraint residual
//!   `||B u - phi||_{0,Gamma_c}` below its tolerance; and the dual residual
//!   `r ||phi^k - phi^{k-1}|| / ||lambda^{k+1}||` below `-ubr_dual_rtol`
//!   (our addition: for a large r the change (4.16) stalls while the
//!   multipliers are still far off).
//! - **accuracy** (`-ubr_stop accuracy`, the default): a bound on the error
//!   of the multipliers. A change is not an error: near a fixed point with
//!   Jacobian J the error is about `(I - J)^{-1}` times the residual, and the
//!   contraction of UBR's last phase (0.74-0.997 measured) makes that 4 to
//!   400 times the change. So the test is `P_k K_k <= tol / 4` with no
//!   status (open/contact/stick/slip) changed in the last 3 evaluations,
//!   where `P_k` is the residual of the plain map in lambda (normal and
//!   tangential parts, each relative to its own max norm) and `K_k`
//!   estimates `||(I - J)^{-1}||`: from Anderson's secant pairs
//!   (`sigma_max(dX dF^+)`, the largest of the last 10), or `1/(1 - q)` for
//!   the plain iteration, q the largest of the last 10 ratios
//!   `P_j / P_{j-1}` of residuals above round-off (1e-12; below it the
//!   ratios are noise about 1, and the last K measured above holds; with
//!   inexact inner solves the ratios' geometric mean where the largest is 1
//!   or more). The product `P_k K_k` is reported as the error
//!   estimate. Measured on the ten scenes of `tests/scenes/` against
//!   references converged to 1e-12 (`bench/accuracy`, bench/README.md,
//!   "The defaults", 2026-11-23): the estimate was 0.8 to 5.4 times the
//!   measured error, and every error at most 0.32 tol; `tests/accuracy.rs`
//!   checks those scenes.

use std::collections::VecDeque;

/// The relative change (4.16)/(5.6): `sqrt((du2 + dphi2) / (u2 + phi2))`
/// from the squared norms of the changes of u (lumped mass on Omega) and of
/// phi (weights w_i on Gamma_c), and of the new values.
pub fn paper_change(du2: f64, dphi2: f64, u2: f64, phi2: f64) -> f64 {
    if u2 + phi2 > 0.0 {
        ((du2 + dphi2) / (u2 + phi2)).sqrt()
    } else {
        0.0
    }
}

pub use crate::options::StopRule;

/// Evaluations without progress after which a run has stalled: its
/// smallest residual P has not fallen by 3% ([`STALL_FACTOR`]) in that
/// many. Measured (the residual's best over its slowest 500 evaluations):
/// runs that converge slowly at r far from the automatic one still gain
/// 10% (hertz_442 at r/E = 1e-3, converged after 2266 evaluations) and 22%
/// (block3d_198 at r/E = 1e3, after 2833); runs that cannot converge stay
/// within 0.3% (a Tresca problem whose bound cannot hold the body, r = 1e30
/// on the Hertz scene, a pinned ring's point contact), and ran to the cap
/// of 10,000 before.
pub const STALL_ITS: usize = 500;
const STALL_FACTOR: f64 = 0.97;
/// Residuals below this are round-off: no progress is expected of them.
const STALL_FLOOR: f64 = 1e-12;
/// Evaluations without progress at round-off (best residual at most
/// `STALL_FLOOR`) after which a run of the accuracy test stops: its
/// estimate cannot fall further. A request below what double precision
/// resolves ran to -ubr_max_it before (hertz_1692 at -ubr_lambda_rtol
/// 1e-14: 10,000 iterations, the residual flat at 1e-15 after 88).
pub const ROUNDOFF_ITS: usize = 100;

/// Whether a run still makes progress (see [`STALL_ITS`]).
#[derive(Clone, Debug)]
pub struct Progress {
    /// The best residual at the last progress, the best since, and the
    /// evaluations and status changes since the last progress.
    mark: f64,
    pub best: f64,
    pub since: usize,
    pub changes: usize,
    /// A warm start's first evaluation, not counted (see [`Progress::new`]).
    skip: bool,
}

impl Default for Progress {
    fn default() -> Self {
        Progress {
            mark: f64::INFINITY,
            best: f64::INFINITY,
            since: 0,
            changes: 0,
            skip: false,
        }
    }
}

impl Progress {
    /// A run started warm (`cold` false): its first evaluation is the last
    /// iterate of the run before, under the new map's bound only after its
    /// projection, and is not the best this run has to beat (CF-FP's second
    /// Tresca solve on stamp2d_gravity_coulomb at -ubr_anderson 0: 6.9e-3
    /// at the warm start, 0.45 next, then falling 14% in 250 iterations,
    /// was taken for stalled: "the residual stays flat").
    pub fn new(cold: bool) -> Progress {
        Progress {
            skip: !cold,
            ..Progress::default()
        }
    }

    /// Records an evaluation's residual and status changes; true when the
    /// run has stalled.
    pub fn record(&mut self, p: f64, changes: usize) -> bool {
        if std::mem::replace(&mut self.skip, false) {
            return false;
        }
        self.best = self.best.min(p);
        if self.best <= STALL_FACTOR * self.mark || self.mark.is_infinite() && p.is_finite() {
            self.mark = self.best;
            self.since = 0;
            self.changes = 0;
        } else {
            self.since += 1;
            self.changes += changes;
        }
        self.since >= STALL_ITS && self.best > STALL_FLOOR
    }

    /// At round-off: the best residual at most `STALL_FLOOR`, without
    /// progress in the last [`ROUNDOFF_ITS`] evaluations.
    pub fn at_roundoff(&self) -> bool {
        self.best <= STALL_FLOOR && self.since >= ROUNDOFF_ITS
    }
}

/// Evaluations whose ratios or estimates the accuracy test remembers.
const WINDOW: usize = 10;
/// Evaluations without a status change the accuracy test needs.
const STABLE: usize = 3;

/// The accuracy test's memory over one run.
#[derive(Clone, Debug)]
pub struct Accuracy {
    pub tol: f64,
    /// The last `WINDOW + 1` residuals P.
    p: VecDeque<f64>,
    /// Anderson's amplification estimates of the last `WINDOW` evaluations.
    k_aa: VecDeque<Option<f64>>,
    /// Consecutive evaluations without a status change.
    stable: usize,
    /// The last P, K and their product.
    pub residual: f64,
    pub amplification: f64,
    pub estimate: f64,
    /// The smallest estimate of the run.
    pub smallest: f64,
    /// The plain iteration's last K from residuals above round-off.
    measured: Option<f64>,
    /// Inexact (iterative) inner solves: see [`Accuracy::inexact`].
    inexact: bool,
}

impl Accuracy {
    pub fn new(tol: f64) -> Accuracy {
        Accuracy {
            tol,
            p: VecDeque::new(),
            k_aa: VecDeque::new(),
            stable: 0,
            residual: f64::INFINITY,
            amplification: f64::INFINITY,
            estimate: f64::INFINITY,
            smallest: f64::INFINITY,
            measured: None,
            inexact: false,
        }
    }

    /// Records an evaluation: its residual `p`, how many statuses changed,
    /// and (Anderson) the amplification its memory estimates (`None` for
    /// the plain iteration). Returns the error estimate.
    pub fn record(&mut self, p: f64, changes: usize, anderson: Option<Option<f64>>) -> f64 {
        self.p.push_back(p);
        if self.p.len() > WINDOW + 1 {
            self.p.pop_front();
        }
        self.stable = if changes == 0 { self.stable + 1 } else { 0 };
        let k = match anderson {
            Some(est) => {
                self.k_aa.push_back(est);
                if self.k_aa.len() > WINDOW {
                    self.k_aa.pop_front();
                }
                self.k_aa
                    .iter()
                    .flatten()
                    .fold(None, |a: Option<f64>, &b| Some(a.map_or(b, |a| a.max(b))))
                    .map_or(f64::INFINITY, |k| k.max(1.0))
            }
            None => {
                // The largest recent contraction ratio of the plain
                // iteration, from residuals above round-off: below it the
                // ratios are noise about 1 (hertz_1692: 1 - 1e-15, K
                // 1e15, the residual flat at 1e-14), and the contraction
                // measured on the way down holds.
                let k_of = |q: f64| {
                    if self.p.len() < 3 || q.is_nan() || q >= 1.0 {
                        f64::INFINITY
                    } else {
                        1.0 / (1.0 - q.max(0.0))
                    }
                };
                // A ratio of 1 or more where residuals reach round-off
                // measures nothing new.
                let above = self.p.iter().all(|&p| p > STALL_FLOOR);
                let fresh = match (self.largest_ratio(STALL_FLOOR), self.mean_ratio()) {
                    (Some(q), Some(g)) if q >= 1.0 && self.inexact => Some(k_of(g)),
                    (Some(q), _) if q < 1.0 || above => Some(k_of(q)),
                    _ => None,
                };
                match (fresh, self.measured) {
                    (Some(k), _) => {
                        self.measured = Some(k);
                        k
                    }
                    (None, Some(k)) => k,
                    // Never above round-off: the ratios are all there is.
                    (None, None) => self.largest_ratio(0.0).map_or(f64::INFINITY, k_of),
                }
            }
        };
        self.residual = p;
        self.amplification = k;
        self.estimate = if p == 0.0 { 0.0 } else { p * k };
        self.smallest = self.smallest.min(self.estimate);
        self.estimate
    }

    /// The ratios `P_j / P_{j-1}` of the remembered residuals with both
    /// above `floor`.
    fn ratios(&self, floor: f64) -> impl Iterator<Item = f64> + '_ {
        self.p
            .iter()
            .zip(self.p.iter().skip(1))
            .filter(move |&(&a, &b)| a > floor && b > floor)
            .map(|(&a, &b)| b / a)
    }

    /// The largest of [`Accuracy::ratios`]; None where there is none.
    fn largest_ratio(&self, floor: f64) -> Option<f64> {
        self.ratios(floor).reduce(f64::max)
    }

    /// Starts from a contraction measured by an earlier run of nearly the
    /// same map ([`crate::solver::surface::UbrState::contraction`]): it
    /// holds until this run measures its own above round-off.
    pub fn seeded(mut self, contraction: Option<f64>) -> Accuracy {
        self.measured = contraction.filter(|k| k.is_finite());
        self
    }

    /// Inexact inner solves (a Krylov method): the plain iteration's
    /// residual falls with ratios about its rate, some of them above 1 (the
    /// solves' errors), and the largest ratio says nothing; where the last
    /// ratios fall on the whole, their geometric mean is the rate
    /// (block3d_extruded_1674 on one rank with CG + GAMG: the residual fell
    /// by e every 50 iterations, and the estimate stayed infinite for 1400).
    pub fn inexact(mut self, inexact: bool) -> Accuracy {
        self.inexact = inexact;
        self
    }

    /// The plain iteration's K last measured above round-off.
    pub fn contraction(&self) -> Option<f64> {
        self.measured
    }

    /// The geometric mean of the remembered ratios `P_j / P_{j-1}` of
    /// residuals above round-off; None with fewer than 3 of them.
    fn mean_ratio(&self) -> Option<f64> {
        let (n, sum) = self
            .ratios(STALL_FLOOR)
            .fold((0, 0.0), |(n, s), q| (n + 1, s + q.ln()));
        (n >= 3).then(|| (sum / n as f64).exp())
    }

    /// `P K <= tol / 4` with statuses stable.
    pub fn satisfied(&self) -> bool {
        self.estimate <= 0.25 * self.tol && self.stable >= STABLE
    }

    /// Whether only the status changes keep the test open.
    pub fn statuses_unsettled(&self) -> bool {
        self.estimate <= 0.25 * self.tol && self.stable < STABLE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_change_is_relative() {
        assert_eq!(paper_change(0.0, 0.0, 0.0, 0.0), 0.0);
        assert!((paper_change(1.0, 3.0, 100.0, 300.0) - 0.1).abs() < 1e-15);
    }

    /// A geometric residual P_k = q^k: the plain estimate P/(1-q) is the
    /// remaining sum of the series, the true error of a fixed-point iteration
    /// contracting by q.
    #[test]
    fn plain_estimate_is_the_geometric_tail() {
        let q: f64 = 0.9;
        let mut a = Accuracy::new(1e-3);
        let mut k = 0;
        loop {
            let p = q.powi(k);
            let est = a.record(p, 0, None);
            if k >= 3 {
                let tail = p / (1.0 - q);
                assert!((est - tail).abs() < 1e-9 * tail, "{est} vs {tail}");
            }
            if a.satisfied() {
                break;
            }
            k += 1;
        }
        // Stops when q^k / (1 - q) <= tol / 4.
        assert!(q.powi(k) / (1.0 - q) <= 0.25e-3);
        assert!(q.powi(k - 1) / (1.0 - q) > 0.25e-3);
    }

    /// At round-off the plain iteration's ratios are noise about 1: the
    /// estimate keeps the contraction measured on the way down (it was
    /// about 1e15 or infinite, and the frictionless bound of a Tresca run
    /// at -ubr_anderson 0 -ubr_lambda_rtol 1e-9 failed for it).
    #[test]
    fn plain_estimate_at_roundoff_keeps_the_measured_contraction() {
        let q: f64 = 0.95;
        let mut a = Accuracy::new(1e-12);
        let mut k = 0;
        while q.powi(k) > 2e-12 {
            a.record(q.powi(k), 0, None);
            k += 1;
        }
        let measured = a.amplification;
        assert!((measured - 1.0 / (1.0 - q)).abs() < 1e-6 * measured);
        for j in 0..50 {
            let p = 1e-15 * (1.0 + 0.3 * ((j % 3) as f64));
            let est = a.record(p, 0, None);
            assert_eq!(a.amplification, measured, "{j}");
            assert_eq!(est, p * measured);
        }
        // Above round-off a ratio of 1 or more means no contraction known.
        let mut b = Accuracy::new(1e-3);
        for p in [1.0, 0.5, 0.25, 0.3] {
            b.record(p, 0, None);
        }
        assert!(b.amplification.is_infinite());
        // Never above round-off: the ratios themselves.
        let mut c = Accuracy::new(1e-3);
        for p in [1e-15, 0.5e-15, 0.25e-15] {
            c.record(p, 0, None);
        }
        assert_eq!(c.amplification, 2.0);
    }

    /// Inexact solves: ratios alternating 1.001 and 0.9 (the residual falls
    /// by 0.9009 every two evaluations). The largest ratio says nothing;
    /// the geometric mean is the rate. Exact solves keep the largest.
    #[test]
    fn inexact_plain_estimate_takes_the_mean_rate() {
        for inexact in [false, true] {
            let mut a = Accuracy::new(1e-3).inexact(inexact);
            let mut p = 1.0;
            for k in 0..40 {
                p *= if k % 2 == 0 { 1.001 } else { 0.9 };
                a.record(p, 0, None);
            }
            if inexact {
                let g = (1.001f64 * 0.9).sqrt();
                let k = 1.0 / (1.0 - g);
                assert!(
                    (a.amplification - k).abs() < 1e-9 * k,
                    "{}",
                    a.amplification
                );
            } else {
                assert!(a.amplification.is_infinite());
            }
        }
    }

    #[test]
    fn progress_stalls_on_a_flat_residual_only() {
        let mut p = Progress::default();
        // Slow geometric decay, 10% in 500 evaluations: never stalled.
        for k in 0..5000 {
            assert!(!p.record(0.9998f64.powi(k), 0));
        }
        // Flat: stalled after STALL_ITS evaluations.
        let mut q = Progress::default();
        let mut when = None;
        for k in 0..2000 {
            if q.record(4.3e-2 * (1.0 + 0.01 * ((k % 7) as f64)), 1) && when.is_none() {
                when = Some(k);
            }
        }
        assert_eq!(when, Some(STALL_ITS));
        assert_eq!(q.changes, q.since);
        // At round-off: never stalled, but at round-off after ROUNDOFF_ITS.
        let mut z = Progress::default();
        for k in 0..2000 {
            assert!(!z.record(1e-15, 0));
            assert_eq!(z.at_roundoff(), k >= ROUNDOFF_ITS, "{k}");
        }
        // Still falling below the floor: not at round-off.
        let mut f = Progress::default();
        for k in 0..1000 {
            f.record(1e-13 * 0.9f64.powi(k), 0);
            assert!(!f.at_roundoff());
        }
    }

    #[test]
    fn status_changes_hold_the_test() {
        let mut a = Accuracy::new(1e-3);
        for _ in 0..5 {
            a.record(1e-9, 0, Some(Some(10.0)));
        }
        assert!(a.satisfied());
        a.record(1e-9, 2, Some(Some(10.0)));
        assert!(!a.satisfied() && a.statuses_unsettled());
        a.record(1e-9, 0, Some(Some(10.0)));
        a.record(1e-9, 0, Some(Some(10.0)));
        assert!(!a.satisfied());
        a.record(1e-9, 0, Some(Some(10.0)));
        assert!(a.satisfied());
    }

    #[test]
    fn anderson_estimate_is_the_recent_maximum() {
        let mut a = Accuracy::new(1e-3);
        a.record(1e-5, 0, Some(Some(50.0)));
        for _ in 0..9 {
            a.record(1e-5, 0, Some(Some(2.0)));
        }
        assert_eq!(a.amplification, 50.0);
        a.record(1e-5, 0, Some(None));
        assert_eq!(a.amplification, 2.0);
        // Nothing known yet: no stop.
        let mut b = Accuracy::new(1e-3);
        b.record(1e-12, 0, Some(None));
        assert!(b.estimate.is_infinite());
    }
}
