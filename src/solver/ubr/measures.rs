//! The measures of one UBR iteration, summed and maximized over the ranks
//! in one reduction each.

use crate::solver::surface::Surface;

/// The inner-product weights of z: w_i on every entry of candidate i.
pub(super) fn z_weights(surface: &Surface) -> Vec<f64> {
    let (cs, d) = (surface.cs, surface.dim);
    let mut w = cs.w.clone();
    if surface.tangential {
        for &wi in &cs.w {
            w.extend(std::iter::repeat_n(wi, d));
        }
    }
    w
}

/// Sums reduced over the ranks after each projection.
#[derive(Clone, Copy, Default)]
pub(super) struct Sums {
    pub(super) du2: f64,
    pub(super) u2: f64,
    pub(super) dphi2: f64,
    pub(super) phi2: f64,
    pub(super) res2: f64,
    pub(super) contact: f64,
    pub(super) stick: f64,
    pub(super) slip: f64,
    pub(super) lam2: f64,
    /// `||T(z) - z||_W^2`
    pub(super) f2: f64,
    /// Statuses changed since the previous evaluation.
    pub(super) changes: f64,
    /// The contact nodes' part of `||u^k - u^{k-1}||^2` (condensed solves).
    pub(super) dc2: f64,
}

impl Sums {
    pub(super) fn to_array(self) -> [f64; 12] {
        [
            self.du2,
            self.u2,
            self.dphi2,
            self.phi2,
            self.res2,
            self.contact,
            self.stick,
            self.slip,
            self.lam2,
            self.f2,
            self.changes,
            self.dc2,
        ]
    }
    pub(super) fn from_array(a: [f64; 12]) -> Sums {
        Sums {
            du2: a[0],
            u2: a[1],
            dphi2: a[2],
            phi2: a[3],
            res2: a[4],
            contact: a[5],
            stick: a[6],
            slip: a[7],
            lam2: a[8],
            f2: a[9],
            changes: a[10],
            dc2: a[11],
        }
    }
}

/// Maxima reduced over the ranks after each projection.
#[derive(Clone, Copy, Default)]
pub(super) struct Maxima {
    /// Largest tensile stress, largest |stress_n|, largest |u_n|.
    pub(super) tension: f64,
    pub(super) stress: f64,
    pub(super) un: f64,
    /// Accuracy test: largest residual `|stress - lambda|` (normal,
    /// tangential) and largest multiplier (normal, tangential).
    pub(super) f_n: f64,
    pub(super) f_t: f64,
    pub(super) lam_n: f64,
    pub(super) lam_t: f64,
    /// Largest change of u_n (negative: every candidate moved away).
    pub(super) dun: f64,
    /// Largest displacement component of a candidate.
    pub(super) umax: f64,
}

impl Maxima {
    pub(super) fn to_array(self) -> [f64; 9] {
        [
            self.tension,
            self.stress,
            self.un,
            self.f_n,
            self.f_t,
            self.lam_n,
            self.lam_t,
            self.dun,
            self.umax,
        ]
    }
    pub(super) fn from_array(a: [f64; 9]) -> Maxima {
        Maxima {
            tension: a[0],
            stress: a[1],
            un: a[2],
            f_n: a[3],
            f_t: a[4],
            lam_n: a[5],
            lam_t: a[6],
            dun: a[7],
            umax: a[8],
        }
    }
}
