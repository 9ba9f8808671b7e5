//! Full solves with MUMPS' distributed right-hand sides and solutions
//! (ICNTL(20) = 10, ICNTL(21) = 1; issue "Scaling studies", item 3): each
//! rank hands MUMPS its own rows of the right-hand sides, and MUMPS returns
//! the rows of the solution whose pivots it eliminated on each rank. Those
//! are sent to the ranks that own them by one all-to-all; nothing of size
//! n passes through the host (the centralized path gathered every
//! right-hand side there and scattered every solution from there).
//!
//! Which rows MUMPS returns where is fixed by the factorization's mapping:
//! the plan of the all-to-all (counts and positions) is made at the first
//! solve and kept while the returned rows stay the same.

use crate::comm::displacements;
use crate::error::Error;
use crate::mumps::Mumps;
use mpi::datatype::{Partition, PartitionMut};
use mpi::traits::*;

/// The all-to-all from MUMPS' solution rows to their owners.
struct Plan {
    /// The rows MUMPS returned (1-based), as when the plan was made.
    isol: Vec<i32>,
    /// MUMPS' rows grouped by owner: positions in `isol`.
    send_order: Vec<usize>,
    send_counts: Vec<i32>,
    /// The owned rows received, in the order they arrive (positions in
    /// this rank's rows), and how many from each rank.
    recv_pos: Vec<usize>,
    recv_counts: Vec<i32>,
    /// The counts and displacements of the values sent and received for
    /// the last number of columns `k` (made again when it changes).
    values: (usize, [Vec<i32>; 4]),
}

/// The counts of an all-to-all of `k` values per entry and their
/// displacements: those of `counts` entries, each times `k`.
fn scaled(counts: &[i32], k: usize) -> (Vec<i32>, Vec<i32>) {
    let scaled: Vec<i32> = counts.iter().map(|&c| c * k as i32).collect();
    let starts = displacements(&scaled);
    (scaled, starts)
}

/// This rank's rows (`first` .. `first + local`, 0-based global) and the
/// buffers and plan of the distributed solves.
pub(super) struct DistSolve {
    /// This rank's rows, 1-based (MUMPS' IRHS_loc).
    irhs: Vec<i32>,
    /// The first row of every rank, and the total at the end.
    starts: Vec<usize>,
    sol: Vec<f64>,
    isol: Vec<i32>,
    send: Vec<f64>,
    recv: Vec<f64>,
    plan: Option<Plan>,
}

impl DistSolve {
    /// The rows of this rank: `local` of them, every rank's rows
    /// contiguous in rank order (collective).
    pub(super) fn new<C: Communicator>(world: &C, local: usize) -> DistSolve {
        let mut counts = vec![0u64; world.size() as usize];
        world.all_gather_into(&(local as u64), &mut counts[..]);
        let mut starts = vec![0usize; counts.len() + 1];
        for (p, &c) in counts.iter().enumerate() {
            starts[p + 1] = starts[p] + c as usize;
        }
        let first = starts[world.rank() as usize];
        DistSolve {
            irhs: (first..first + local).map(|g| (g + 1) as i32).collect(),
            starts,
            sol: Vec::new(),
            isol: Vec::new(),
            send: Vec::new(),
            recv: Vec::new(),
            plan: None,
        }
    }

    /// The condensation or a full solve without Schur complement
    /// (`schur_phase` 1 or 0) of the `k` columns of `cols` (this rank's
    /// rows of each, column-major); with phase 0 the solutions overwrite
    /// `cols`. Collective.
    pub(super) fn solve<C: Communicator>(
        &mut self,
        world: &C,
        mumps: &mut Mumps,
        cols: &mut [f64],
        k: usize,
        schur_phase: i32,
    ) -> Result<(), Error> {
        let mut rhs = std::mem::take(&mut self.send);
        rhs.clear();
        rhs.extend_from_slice(cols);
        let r = mumps.solve_distributed(
            &mut rhs,
            &mut self.irhs,
            k,
            schur_phase,
            &mut self.sol,
            &mut self.isol,
        );
        self.send = rhs;
        r?;
        if schur_phase != 1 {
            self.deliver(world, cols, k)?;
        }
        Ok(())
    }

    /// The expansion (ICNTL(26) = 2) of the last condensation, from the
    /// Schur solutions MUMPS holds in REDRHS: the `k` whole solutions into
    /// `cols` (this rank's rows of each, column-major). Collective.
    pub(super) fn expand<C: Communicator>(
        &mut self,
        world: &C,
        mumps: &mut Mumps,
        cols: &mut [f64],
        k: usize,
    ) -> Result<(), Error> {
        // The expansion reads no right-hand side; MUMPS is given zeros.
        let mut rhs = std::mem::take(&mut self.send);
        rhs.clear();
        rhs.resize(cols.len(), 0.0);
        let r = mumps.solve_distributed(
            &mut rhs,
            &mut self.irhs,
            k,
            2,
            &mut self.sol,
            &mut self.isol,
        );
        self.send = rhs;
        r?;
        self.deliver(world, cols, k)
    }

    /// MUMPS' solution rows (`self.sol`, `self.isol`) to their owners'
    /// `cols`.
    fn deliver<C: Communicator>(
        &mut self,
        world: &C,
        cols: &mut [f64],
        k: usize,
    ) -> Result<(), Error> {
        if self.plan.as_ref().is_none_or(|p| p.isol != self.isol) {
            self.plan = Some(self.make_plan(world, cols.len() / k.max(1))?);
        }
        let plan = self.plan.as_mut().expect("made above");
        if plan.values.0 != k {
            let (sc, sd) = scaled(&plan.send_counts, k);
            let (rc, rd) = scaled(&plan.recv_counts, k);
            plan.values = (k, [sc, sd, rc, rd]);
        }
        let mine = self.isol.len();
        self.send.clear();
        for &i in &plan.send_order {
            for j in 0..k {
                self.send.push(self.sol[j * mine + i]);
            }
        }
        self.recv.resize(plan.recv_pos.len() * k, 0.0);
        let [sc, sd, rc, rd] = &plan.values.1;
        world.all_to_all_varcount_into(
            &Partition::new(&self.send[..], &sc[..], &sd[..]),
            &mut PartitionMut::new(&mut self.recv[..], &rc[..], &rd[..]),
        );
        let local = cols.len() / k.max(1);
        for (e, &pos) in plan.recv_pos.iter().enumerate() {
            for j in 0..k {
                cols[j * local + pos] = self.recv[e * k + j];
            }
        }
        Ok(())
    }

    /// The plan of [`DistSolve::deliver`] for the rows in `self.isol`:
    /// every owned row must come from exactly one rank.
    fn make_plan<C: Communicator>(&self, world: &C, local: usize) -> Result<Plan, Error> {
        let p = world.size() as usize;
        let owner = |row: i32| -> usize { self.starts.partition_point(|&s| s < row as usize) - 1 };
        let mut send_order: Vec<usize> = (0..self.isol.len()).collect();
        send_order.sort_by_key(|&i| owner(self.isol[i]));
        let mut send_counts = vec![0i32; p];
        for &row in &self.isol {
            send_counts[owner(row)] += 1;
        }
        let mut recv_counts = vec![0i32; p];
        world.all_to_all_into(&send_counts[..], &mut recv_counts[..]);
        let rows: Vec<i32> = send_order.iter().map(|&i| self.isol[i]).collect();
        let total: usize = recv_counts.iter().map(|&c| c as usize).sum();
        let mut got = vec![0i32; total];
        let (sd, rd) = (displacements(&send_counts), displacements(&recv_counts));
        world.all_to_all_varcount_into(
            &Partition::new(&rows[..], &send_counts[..], &sd[..]),
            &mut PartitionMut::new(&mut got[..], &recv_counts[..], &rd[..]),
        );
        let first = self.starts[world.rank() as usize];
        let mut seen = vec![false; local];
        let mut recv_pos = Vec::with_capacity(total);
        for &row in &got {
            let pos = row as usize - 1 - first;
            seen[pos] = true;
            recv_pos.push(pos);
        }
        let complete = total == local && seen.iter().all(|&s| s);
        let all = crate::comm::allreduce_count(world, usize::from(!complete));
        if all > 0 {
            return Err(Error::Internal(format!(
                "MUMPS' distributed solution does not hold every row once ({total} rows received for {local} owned on some rank)"
            )));
        }
        Ok(Plan {
            isol: self.isol.clone(),
            send_order,
            send_counts,
            recv_pos,
            recv_counts,
            values: (0, Default::default()),
        })
    }
}
