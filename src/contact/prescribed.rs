//! Candidates that a Dirichlet condition holds along their normal. The
//! paper's Gamma_D and Gamma_c do not meet; a mesh's do, at a clamped
//! corner or where a user prescribes the displacement of the contact
//! surface itself. There the contact condition cannot act: `u_n` is given,
//! and where it puts the node inside the obstacle, the multiplier grew by
//! `r (u_n - g)` at every iteration without bound (a block's corner pushed
//! 0.02 into the floor by `-dirichlet_left uy=-0.02`: 3948 iterations,
//! "converged", a contact force 1300 times the load; two stacked blocks
//! overlapping by 5e-4, clamped on their left sides: 301 iterations, a
//! force 500 times the load). Such candidates are no candidates: the
//! Dirichlet condition holds them, and its reaction carries their force.

use super::ContactSet;
use crate::comm::{allreduce_max, allreduce_sum_vec};
use crate::error::{bad, Error};
use crate::mesh::distribute::LocalMesh;
use crate::options::DirichletBc;
use mpi::traits::Communicator;
use std::collections::{HashMap, HashSet};

/// The part of a unit normal off the prescribed components below which the
/// displacement along it counts as prescribed (squared: a part of 1e-6).
const FREE_PART: f64 = 1e-12;

impl ContactSet {
    /// Removes the candidates whose displacement along n is prescribed:
    /// every component of n off 1e-6 prescribed by `dirichlet` (owned dofs
    /// and values) at the node. A pair's slave node too: the mortar
    /// coupling acts through the slave's displacement relative to the
    /// master ([`crate::solver::mortar`]), which a Dirichlet condition on
    /// the slave leaves out (the stacked blocks, the upper one's corner
    /// clamped, the lower one's free: 4002 iterations, "converged", a force
    /// 530 times the load). Returns a warning where a prescribed
    /// displacement puts a removed node inside its obstacle (or master
    /// surface), or where a tenth of the candidates went; bad input where
    /// none is left. Collective.
    pub fn drop_prescribed<C: Communicator>(
        &mut self,
        world: &C,
        mesh: &LocalMesh,
        dirichlet: &[(usize, f64)],
        bcs: &[DirichletBc],
        surface: &str,
    ) -> Result<Option<String>, Error> {
        let d = self.dim;
        let value: HashMap<usize, f64> = dirichlet.iter().copied().collect();
        // A node's prescribed part: the free part of n, and n . u_D.
        let own = |v: usize, n: &[f64]| -> (f64, f64) {
            (0..d).fold((0.0, 0.0), |(free, un), c| match value.get(&(v * d + c)) {
                Some(x) => (free, un + n[c] * x),
                None => (free + n[c] * n[c], un),
            })
        };
        let mut keep = vec![true; self.len()];
        let mut depth = 0.0f64;
        let mut inside = 0usize;
        for (i, k) in keep.iter_mut().enumerate() {
            let (free, un) = own(self.node[i], self.n(i));
            if free > FREE_PART {
                continue;
            }
            *k = false;
            let over = un - self.g[i];
            if over > 1e-9 * (un.abs() + self.g[i].abs()) {
                inside += 1;
                depth = depth.max(over);
            }
        }
        let dropped: Vec<usize> = (0..self.len()).filter(|&i| !keep[i]).collect();
        // Which Dirichlet groups hold them, for the message (read only
        // where this rank dropped a candidate).
        let mut counts = vec![0.0; bcs.len() + 5];
        if !dropped.is_empty() {
            for (g, bc) in bcs.iter().enumerate() {
                let Some(group) = mesh.group(&bc.group) else {
                    continue;
                };
                let nodes: HashSet<usize> = group.conn.nodes().iter().copied().collect();
                // (Those of its components along n.)
                let along = |i: usize| bc.comps.iter().any(|&(c, _)| self.n(i)[c].abs() > 1e-6);
                counts[g] = dropped
                    .iter()
                    .filter(|&&i| nodes.contains(&self.node[i]) && along(i))
                    .count() as f64;
            }
        }
        let tail = bcs.len();
        counts[tail..].copy_from_slice(&[
            dropped.len() as f64,
            inside as f64,
            self.len() as f64,
            self.pair.iter().filter(|&&p| p != usize::MAX).count() as f64,
            dropped
                .iter()
                .filter(|&&i| self.pair[i] != usize::MAX)
                .count() as f64,
        ]);
        let counts = allreduce_sum_vec(world, &counts);
        let depth = allreduce_max(world, depth);
        let [removed, inside, before, paired, slaves] =
            [0, 1, 2, 3, 4].map(|k| counts[tail + k] as usize);
        if removed == 0 {
            return Ok(None);
        }
        self.retain(&keep);
        let names: Vec<String> = bcs
            .iter()
            .zip(&counts)
            .filter(|(_, &c)| c > 0.0)
            .map(|(bc, _)| format!("-dirichlet_{}", bc.group))
            .collect();
        let verb = if names.len() == 1 {
            "prescribes"
        } else {
            "prescribe"
        };
        let names = names.join(", ");
        if removed == before {
            let option = if paired == before {
                "-contact_pair"
            } else {
                "-contact_surface"
            };
            return bad(format!(
                "option {option}: {names} {verb} the displacement along n at every candidate of '{surface}' ({removed}): no contact condition is left to act; prescribe only the components across n there, or name another contact surface"
            ));
        }
        let one = removed == 1;
        let (s, they, them, their) = if one {
            ("", "it is no candidate", "it", "its")
        } else {
            ("s", "they are no candidates", "them", "their")
        };
        let mut message = format!(
            "{names} {verb} the displacement along n at {removed} contact candidate{s} of '{surface}': {they} (the Dirichlet condition holds {them}, and its reaction carries {their} force)"
        );
        if inside > 0 {
            let at = if one {
                String::new()
            } else {
                format!("at {inside} of them ")
            };
            message.push_str(&format!(
                "; {at}it puts the node inside {}, by {}{depth:.4e}, and no contact force pushes it out",
                if slaves == 0 { "the obstacle" } else { "its master surface" },
                if inside == 1 { "" } else { "up to " }
            ));
        } else if removed * 10 <= before {
            // A clamped corner or edge: common, and harmless.
            return Ok(None);
        }
        Ok(Some(message))
    }

    /// Keeps the candidates i with `keep[i]`.
    fn retain(&mut self, keep: &[bool]) {
        let d = self.dim;
        let mut k = 0;
        for (i, _) in keep.iter().enumerate().filter(|(_, &k)| k) {
            for c in 0..d {
                self.normal[k * d + c] = self.normal[i * d + c];
                self.image[k * d + c] = self.image[i * d + c];
            }
            self.node[k] = self.node[i];
            self.w[k] = self.w[i];
            self.g[k] = self.g[i];
            self.group[k] = self.group[i];
            self.obstacle[k] = self.obstacle[i];
            self.pair[k] = self.pair[i];
            self.mortar.swap(k, i);
            k += 1;
        }
        self.normal.truncate(k * d);
        self.image.truncate(k * d);
        self.node.truncate(k);
        self.w.truncate(k);
        self.g.truncate(k);
        self.group.truncate(k);
        self.obstacle.truncate(k);
        self.pair.truncate(k);
        self.mortar.truncate(k);
    }
}
