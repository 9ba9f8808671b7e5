//! The MPI collectives of the crate, one implementation each: the per-rank
//! [`Layout`] of a distributed array (gather, scatter) and the reductions
//! `allreduce_*` of a few numbers over every rank.

use mpi::collective::SystemOperation;
use mpi::datatype::{Equivalence, Partition, PartitionMut};
use mpi::traits::*;

/// The per-rank layout of a distributed array gathered on the host.
pub struct Layout {
    counts: Vec<i32>,
    displs: Vec<i32>,
}

impl Layout {
    pub fn new<C: Communicator>(world: &C, local: usize) -> Layout {
        let mut counts = vec![0i32; world.size() as usize];
        world.all_gather_into(&(local as i32), &mut counts[..]);
        let displs = displacements(&counts);
        Layout { counts, displs }
    }

    pub fn total(&self) -> usize {
        self.counts.iter().map(|&c| c as usize).sum()
    }

    /// Rank `p`'s count.
    pub fn count(&self, p: usize) -> usize {
        self.counts[p] as usize
    }

    /// `local` of every rank, in rank order, on the host (empty elsewhere).
    pub fn gather<C: Communicator>(&self, world: &C, local: &[f64]) -> Vec<f64> {
        let mut all = if world.rank() == 0 {
            vec![0.0; self.total()]
        } else {
            Vec::new()
        };
        self.gather_into(world, local, &mut all);
        all
    }

    /// [`Layout::gather`] into `all` (the host's, of length [`Layout::total`];
    /// unused elsewhere): no allocation, for the solves of every iteration.
    pub fn gather_into<C: Communicator>(&self, world: &C, local: &[f64], all: &mut [f64]) {
        let root = world.process_at_rank(0);
        if world.rank() == 0 {
            let mut part = PartitionMut::new(all, &self.counts[..], &self.displs[..]);
            root.gather_varcount_into_root(local, &mut part);
        } else {
            root.gather_varcount_into(local);
        }
    }

    /// `local` of every rank, in rank order, on every rank.
    pub fn all_gather<C: Communicator, T: Equivalence + Default + Clone>(
        &self,
        world: &C,
        local: &[T],
    ) -> Vec<T> {
        let mut all = vec![T::default(); self.total()];
        let mut part = PartitionMut::new(&mut all[..], &self.counts[..], &self.displs[..]);
        world.all_gather_varcount_into(local, &mut part);
        all
    }

    /// The host's `all` back to the ranks, each its part into `local`.
    pub fn scatter<C: Communicator>(&self, world: &C, all: &[f64], local: &mut [f64]) {
        let root = world.process_at_rank(0);
        if world.rank() == 0 {
            let part = Partition::new(all, &self.counts[..], &self.displs[..]);
            root.scatter_varcount_into_root(&part, local);
        } else {
            root.scatter_varcount_into(local);
        }
    }
}

/// The displacements of `counts` (each the sum of those before it), for
/// MPI's varcount collectives.
pub fn displacements(counts: &[i32]) -> Vec<i32> {
    counts
        .iter()
        .scan(0i32, |acc, &c| {
            let s = *acc;
            *acc += c;
            Some(s)
        })
        .collect()
}

/// Sum of `vals` over all ranks, in one reduction.
pub fn allreduce_sum<C: Communicator, const N: usize>(world: &C, vals: [f64; N]) -> [f64; N] {
    let mut out = [0.0; N];
    world.all_reduce_into(&vals[..], &mut out[..], SystemOperation::sum());
    out
}

/// Elementwise sum of `vals` over all ranks.
pub fn allreduce_sum_vec<C: Communicator>(world: &C, vals: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; vals.len()];
    world.all_reduce_into(vals, &mut out[..], SystemOperation::sum());
    out
}

pub fn allreduce_max_n<C: Communicator, const N: usize>(world: &C, vals: [f64; N]) -> [f64; N] {
    let mut out = [0.0; N];
    world.all_reduce_into(&vals[..], &mut out[..], SystemOperation::max());
    out
}

pub fn allreduce_max<C: Communicator>(world: &C, v: f64) -> f64 {
    let mut out = 0.0;
    world.all_reduce_into(&v, &mut out, SystemOperation::max());
    out
}

pub fn allreduce_count<C: Communicator>(world: &C, v: usize) -> usize {
    let mut out = 0u64;
    world.all_reduce_into(&(v as u64), &mut out, SystemOperation::sum());
    out as usize
}

/// Elementwise maximum of `vals` over all ranks.
pub fn allreduce_max_vec<C: Communicator>(world: &C, vals: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; vals.len()];
    world.all_reduce_into(vals, &mut out[..], SystemOperation::max());
    out
}
