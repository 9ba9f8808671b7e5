//! Safeguarded type-II Anderson acceleration of a fixed-point map `z -> T(z)`
//! on the contact surface (H. F. Walker, P. Ni, "Anderson acceleration for
//! fixed-point iterations", SIAM J. Numer. Anal. 49 (2011) 1715-1735).
//!
//! With `f_j = T(z_j) - z_j`, `g_j = T(z_j)` and the last M differences
//! `dF`, `dG` of consecutive accepted evaluations,
//! `gamma = argmin ||f_k - dF gamma||_W` and `z_{k+1} = g_k - dG gamma`. The
//! norm is W-weighted (nodal weights of Gamma_c), so the Gram matrices are
//! sums of local dot products, reduced once per iteration; every rank solves
//! the same small system (nalgebra's Cholesky) and takes the same step.
//!
//! Safeguard: an extrapolated point is accepted only if its residual
//! `||f||_W` is at most [`SAFEGUARD`] times the smallest residual seen so
//! far; otherwise the memory is cleared and the iteration takes the plain
//! step `T(z)` of the last accepted point (known: no extra evaluation).
//! Measured with this rule (`bench/run --steps 7`, bench/README.md,
//! "Iterations against r/E", 2026-11-23): to `-ubr_lambda_rtol 1e-3` the
//! accelerated iteration converged at every r/E from 1e-3 to 1e3 on
//! hertz_1692 (the floating Hertz body) and from 3.16e-3 to 1e3 on
//! block3d_739 (not within 20000 iterations at 1e-3), and at the automatic
//! r in 4-7x fewer iterations than the plain one at its own best r;
//! `tests/r_range.rs` checks r/E = 1e-3, 0.1, 10, 100 (Hertz) and 1e-3, 1,
//! 1e3 (block).
//!
//! The secant pairs also estimate the error amplification of the fixed
//! point, `||(I - J)^{-1}||`: `dF ~ (J - I) dX`, so `sigma_max(dX dF^+)`
//! (W-norm) estimates it on the span of the memory ([`Step::amplification`]).

use nalgebra::{DMatrix, DVector, SymmetricEigen};

/// Accept an extrapolated point while its residual is at most this times
/// the smallest residual seen.
pub const SAFEGUARD: f64 = 2.0;
/// Tikhonov regularization of the Gram matrix, relative to its largest diagonal entry.
const REGULARIZATION: f64 = 1e-10;
/// Extrapolation coefficients larger than this are not trusted (a reset instead).
const MAX_WEIGHT: f64 = 1e8;

/// What one Anderson step did.
#[derive(Clone, Copy, Debug, Default)]
pub struct Step {
    /// The evaluation was at an extrapolated point, rejected by the safeguard.
    pub rejected: bool,
    /// The next point is extrapolated (not a plain step).
    pub extrapolated: bool,
    /// `sigma_max(dX dF^+)`, when the memory holds a pair.
    pub amplification: Option<f64>,
}

/// The memory of the acceleration, allocated once per run.
pub struct Anderson {
    mem: usize,
    /// Inner-product weights of the entries of z.
    w: Vec<f64>,
    /// f and g of the last accepted evaluation.
    f_prev: Vec<f64>,
    g_prev: Vec<f64>,
    have_prev: bool,
    /// Columns of dF and dG: a ring of `mem` columns, `count` filled, `next` to overwrite.
    df: Vec<f64>,
    dg: Vec<f64>,
    count: usize,
    next: usize,
    /// Whether the point being evaluated is extrapolated.
    extrapolated: bool,
    /// The smallest residual `||f||_W` seen.
    best: f64,
    send: Vec<f64>,
    recv: Vec<f64>,
    f: Vec<f64>,
    /// Evaluations at extrapolated points, and rejections.
    pub steps: usize,
    pub rejected: usize,
}

impl Anderson {
    /// Memory `mem` for vectors with the inner-product weights `w`.
    pub fn new(mem: usize, w: Vec<f64>) -> Anderson {
        let n = w.len();
        let nred = mem * (mem + 1) + mem;
        Anderson {
            mem,
            f_prev: vec![0.0; n],
            g_prev: vec![0.0; n],
            have_prev: false,
            df: vec![0.0; n * mem],
            dg: vec![0.0; n * mem],
            count: 0,
            next: 0,
            extrapolated: false,
            best: f64::INFINITY,
            send: vec![0.0; nred],
            recv: vec![0.0; nred],
            f: vec![0.0; n],
            w,
            steps: 0,
            rejected: 0,
        }
    }

    fn clear(&mut self) {
        self.count = 0;
        self.next = 0;
    }

    /// Forgets every evaluation: the next point is a new start.
    pub fn restart(&mut self) {
        self.clear();
        self.have_prev = false;
        self.extrapolated = false;
        self.best = f64::INFINITY;
    }

    /// Local part of `||v||_W^2`.
    pub fn local_norm2(&self, v: &[f64]) -> f64 {
        v.iter().zip(&self.w).map(|(x, w)| w * x * x).sum()
    }

    /// After the evaluation `g = T(z)` whose residual is `fnorm = ||g - z||_W`
    /// (global): the next point into `next`. `sum` adds local sums over the
    /// ranks (an allreduce).
    pub fn step(
        &mut self,
        sum: impl FnOnce(&[f64], &mut [f64]),
        z: &[f64],
        g: &[f64],
        fnorm: f64,
        next: &mut [f64],
    ) -> Step {
        let n = z.len();
        let was_extrapolated = self.extrapolated;
        if was_extrapolated {
            self.steps += 1;
        }
        let worse = fnorm.is_nan() || fnorm > SAFEGUARD * self.best;
        if was_extrapolated && worse {
            // Back to the plain step of the last accepted point.
            self.rejected += 1;
            self.clear();
            self.extrapolated = false;
            next.copy_from_slice(&self.g_prev);
            return Step {
                rejected: true,
                ..Default::default()
            };
        }
        for j in 0..n {
            self.f[j] = g[j] - z[j];
        }
        if self.have_prev {
            let col = self.next * n..(self.next + 1) * n;
            for (j, (df, dg)) in self.df[col.clone()]
                .iter_mut()
                .zip(&mut self.dg[col])
                .enumerate()
            {
                *df = self.f[j] - self.f_prev[j];
                *dg = g[j] - self.g_prev[j];
            }
            self.next = (self.next + 1) % self.mem;
            self.count = (self.count + 1).min(self.mem);
        }
        self.f_prev.copy_from_slice(&self.f);
        self.g_prev.copy_from_slice(g);
        self.have_prev = true;
        self.best = self.best.min(fnorm);
        self.extrapolated = false;
        next.copy_from_slice(g);
        let m = self.count;
        if m == 0 || fnorm == 0.0 {
            return Step::default();
        }
        // One reduction: dF^T W dF, dX^T W dX (upper triangles), dF^T W f,
        // with dX = dG - dF (the differences of the points z).
        let w = &self.w;
        let col = |a: usize| a * n..(a + 1) * n;
        let mut p = 0;
        for a in 0..m {
            let (fa, ga) = (&self.df[col(a)], &self.dg[col(a)]);
            for b in a..m {
                let (fb, gb) = (&self.df[col(b)], &self.dg[col(b)]);
                let (mut sf, mut sx) = (0.0, 0.0);
                for j in 0..n {
                    sf += w[j] * fa[j] * fb[j];
                    sx += w[j] * (ga[j] - fa[j]) * (gb[j] - fb[j]);
                }
                self.send[p] = sf;
                self.send[p + 1] = sx;
                p += 2;
            }
            self.send[p] = (0..n).map(|j| w[j] * fa[j] * self.f[j]).sum();
            p += 1;
        }
        sum(&self.send[..p], &mut self.recv[..p]);
        let (mut gf, gx, rhs) = unpack(&self.recv, m);
        let diag_max = (0..m).map(|a| gf[(a, a)]).fold(0.0, f64::max);
        let reg = REGULARIZATION * diag_max + f64::MIN_POSITIVE;
        for a in 0..m {
            gf[(a, a)] += reg;
        }
        let Some(chol) = gf.cholesky() else {
            self.clear();
            return Step::default();
        };
        let gamma = chol.solve(&rhs);
        if !gamma.iter().all(|x| x.is_finite() && x.abs() <= MAX_WEIGHT) {
            self.clear();
            return Step::default();
        }
        // sigma_max(dX dF^+)^2 = lambda_max(L^{-1} Gx L^{-T}), Gf = L L^T.
        let amplification = amplification(&chol.l(), &gx);
        // z_{k+1} = g_k - dG gamma
        for a in 0..m {
            let ga = gamma[a];
            let c = &self.dg[a * n..(a + 1) * n];
            for (x, cj) in next.iter_mut().zip(c) {
                *x -= ga * cj;
            }
        }
        self.extrapolated = true;
        Step {
            rejected: false,
            extrapolated: true,
            amplification,
        }
    }
}

/// The Gram matrices `dF^T W dF`, `dX^T W dX` and the right-hand side
/// `dF^T W f` of memory `m` from the reduced sums (upper triangles, row by
/// row, each row followed by its right-hand side entry).
fn unpack(recv: &[f64], m: usize) -> (DMatrix<f64>, DMatrix<f64>, DVector<f64>) {
    let mut gf = DMatrix::<f64>::zeros(m, m);
    let mut gx = DMatrix::<f64>::zeros(m, m);
    let mut rhs = DVector::<f64>::zeros(m);
    let mut p = 0;
    for a in 0..m {
        for b in a..m {
            gf[(a, b)] = recv[p];
            gf[(b, a)] = recv[p];
            gx[(a, b)] = recv[p + 1];
            gx[(b, a)] = recv[p + 1];
            p += 2;
        }
        rhs[a] = recv[p];
        p += 1;
    }
    (gf, gx, rhs)
}

/// `sigma_max(dX dF^+) = sqrt(lambda_max(L^{-1} Gx L^{-T}))`, `Gf = L L^T`
/// (None when not finite).
fn amplification(l: &DMatrix<f64>, gx: &DMatrix<f64>) -> Option<f64> {
    l.solve_lower_triangular(gx)
        .and_then(|a| l.solve_lower_triangular(&a.transpose()))
        .map(|s| {
            let s = (&s + s.transpose()) * 0.5;
            SymmetricEigen::new(s)
                .eigenvalues
                .iter()
                .fold(0.0f64, |a, &b| a.max(b))
                .sqrt()
        })
        .filter(|a| a.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear contraction z -> A z + b with slow modes: Anderson reaches
    /// the fixed point in about dimension-many steps, and its amplification
    /// estimate matches ||(I - A)^{-1}||.
    #[test]
    fn linear_map_converges_and_estimates_the_amplification() {
        let n = 6;
        let diag = [0.99, 0.95, 0.9, 0.5, 0.2, -0.3];
        let b: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let fixed: Vec<f64> = (0..n).map(|i| b[i] / (1.0 - diag[i])).collect();
        let mut aa = Anderson::new(10, vec![1.0; n]);
        let mut z = vec![0.0; n];
        let mut next = vec![0.0; n];
        let mut amp = 0.0;
        let mut its = 0;
        for k in 0..50 {
            let g: Vec<f64> = (0..n).map(|i| diag[i] * z[i] + b[i]).collect();
            let fnorm = g
                .iter()
                .zip(&z)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
                .sqrt();
            if fnorm < 1e-10 {
                its = k;
                break;
            }
            let s = aa.step(|a, b| b.copy_from_slice(a), &z, &g, fnorm, &mut next);
            if let Some(a) = s.amplification {
                amp = a;
            }
            z.copy_from_slice(&next);
        }
        assert!(its > 0 && its <= 12, "{its} evaluations");
        for i in 0..n {
            assert!((z[i] - fixed[i]).abs() < 1e-7 * fixed[i].abs().max(1.0));
        }
        // ||(I - A)^{-1}|| = 1 / (1 - 0.99) = 100
        assert!(amp > 50.0 && amp < 200.0, "amplification {amp}");
    }
}
