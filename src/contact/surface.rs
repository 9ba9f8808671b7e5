//! The contact surface: the operators B and B^T W of the contact set, and
//! the UBR matrix block of a candidate.
//!
//! Unknowns at the contact nodes are stored candidate by candidate: `u_C`
//! has component c of candidate i at `i * dim + c`. `B u = (u_n, u_t)` with
//! `u_n = u.n_i` and `u_t = u - u_n n_i` (2.1), n_i the candidate's normal;
//! `B^T W (v_n, v_t)` is the nodal force `w_i (v_n n_i + v_t)` (nodal
//! quadrature of `(v, B u)_{Gamma_c}`),
//! zero on the components that carry a Dirichlet condition (their rows are
//! eliminated from the linear system).

use super::ContactSet;

/// B and B^T W of the candidates owned by this rank.
pub struct Surface<'a> {
    pub cs: &'a ContactSet,
    pub dim: usize,
    /// Whether the tangential part is in play (friction).
    pub tangential: bool,
    /// Per contact unknown (`i * dim + c`): a Dirichlet component.
    pub dirichlet: &'a [bool],
}

impl Surface<'_> {
    pub fn len(&self) -> usize {
        self.cs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cs.is_empty()
    }

    /// `u_n` of candidate i from `u_C`.
    #[inline]
    pub fn normal(&self, uc: &[f64], i: usize) -> f64 {
        let d = self.dim;
        let n = self.cs.n(i);
        (0..d).map(|c| uc[i * d + c] * n[c]).sum()
    }

    /// `u_t` of candidate i from `u_C`, given its `u_n`.
    #[inline]
    pub fn tangential_part(&self, uc: &[f64], i: usize, un: f64, out: &mut [f64]) {
        let d = self.dim;
        let n = self.cs.n(i);
        for c in 0..d {
            out[c] = uc[i * d + c] - un * n[c];
        }
    }

    /// The contact load `B^T W (v_n, v_t)` at the contact nodes, where
    /// candidate i has `v_n = vn(i)` and (with friction) `v_t = vt(i, c)`.
    pub fn load(
        &self,
        vn: impl Fn(usize) -> f64,
        vt: impl Fn(usize, usize) -> f64,
        out: &mut [f64],
    ) {
        let d = self.dim;
        for i in 0..self.len() {
            let n = self.cs.n(i);
            let w = self.cs.w[i];
            let sn = w * vn(i);
            for c in 0..d {
                out[i * d + c] = if self.dirichlet[i * d + c] {
                    0.0
                } else if self.tangential {
                    sn * n[c] + w * vt(i, c)
                } else {
                    sn * n[c]
                };
            }
        }
    }

    /// The contact block `M_i` of `B^T W B` at candidate i (`w n n^T`, or
    /// `w I` with friction), applied to `u_C` and kept on the components
    /// without a Dirichlet condition: `out = M u_C` there.
    pub fn apply_contact_block(&self, uc: &[f64], out: &mut [f64]) {
        let d = self.dim;
        for i in 0..self.len() {
            let w = self.cs.w[i];
            let un = self.normal(uc, i);
            for c in 0..d {
                out[i * d + c] = if self.dirichlet[i * d + c] {
                    0.0
                } else if self.tangential {
                    w * uc[i * d + c]
                } else {
                    w * un * self.cs.n(i)[c]
                };
            }
        }
    }
}

/// The UBR matrix block `r w (n n^T)` (frictionless) or `r w I` (with friction) of one node.
pub fn contact_block(dim: usize, n: &[f64], rw: f64, tangential: bool) -> Vec<f64> {
    let mut b = vec![0.0; dim * dim];
    for i in 0..dim {
        for j in 0..dim {
            b[i * dim + j] = if tangential {
                if i == j {
                    rw
                } else {
                    0.0
                }
            } else {
                rw * n[i] * n[j]
            };
        }
    }
    b
}
