//! The mesh split by PT-Scotch in parallel (`-partition ptscotch`): the
//! nodal graph is distributed over the ranks in contiguous blocks of n/P
//! nodes, PT-Scotch (through PETSc's `MatPartitioning`,
//! [`crate::petsc::partition::ptscotch`]) partitions it with every rank
//! working on its block, and the parts are gathered (4 bytes a node) where
//! the parts are made: on every rank for a generated mesh (each rank makes
//! its own part from its own copy), on rank 0 for a file (which sends the
//! parts as with METIS or RCB; each rank builds its block's rows from the
//! cells touching it, which rank 0 sends: the whole graph is built on no
//! rank). Where a part would be empty, contiguous blocks (as with METIS).

use super::distribute::{root_verdict, LocalMesh, NodeGraph};
use super::{Cells, Mesh};
use crate::error::Error;
use mpi::datatype::PartitionMut;
use mpi::traits::*;

/// The first node of rank `r`'s block of `n` nodes over `size` ranks.
fn block(n: usize, size: usize, r: usize) -> usize {
    r * n / size
}

/// The block sizes of every rank and their offsets, as MPI counts: the
/// layout of the gathered parts.
fn block_layout(n: usize, size: usize) -> (Vec<i32>, Vec<i32>) {
    let counts: Vec<i32> = (0..size)
        .map(|r| (block(n, size, r + 1) - block(n, size, r)) as i32)
        .collect();
    let displs = crate::comm::displacements(&counts);
    (counts, displs)
}

/// Contiguous blocks: the part of each of `n` nodes.
fn blocks(n: usize, size: usize) -> Vec<usize> {
    (0..n).map(|i| i * size / n.max(1)).collect()
}

/// PT-Scotch's parts of this rank's block of the graph (its rows, `graph`,
/// numbered in the whole graph of `n` nodes). Collective.
fn parts_of_rows(n: usize, graph: &NodeGraph) -> Result<Vec<u32>, Error> {
    let comm = crate::petsc::comm_world();
    Ok(
        crate::petsc::partition::ptscotch(comm, n, &graph.xadj, &graph.adjncy)?
            .into_iter()
            .map(|p| p as u32)
            .collect(),
    )
}

/// `part32` as parts, or contiguous blocks where a part is empty or out
/// of range.
fn checked(part32: Vec<u32>, size: usize) -> Vec<usize> {
    let mut filled = vec![false; size];
    for &p in &part32 {
        match filled.get_mut(p as usize) {
            Some(f) => *f = true,
            None => return blocks(part32.len(), size),
        }
    }
    if filled.contains(&false) {
        return blocks(part32.len(), size);
    }
    part32.into_iter().map(|p| p as usize).collect()
}

/// This rank's local mesh of a generated mesh that every rank has made:
/// each rank builds the graph's rows of its block from its own copy, the
/// parts are gathered on every rank, and each rank makes and builds its
/// own part. Collective.
pub fn own_part<C: Communicator>(world: &C, mesh: &Mesh) -> Result<LocalMesh, Error> {
    let (n, size) = (mesh.num_nodes(), world.size() as usize);
    if n < size {
        return super::scatter::own_part(world, mesh, &blocks(n, size));
    }
    let rank = world.rank() as usize;
    let rows = block(n, size, rank)..block(n, size, rank + 1);
    let mine = parts_of_rows(n, &NodeGraph::rows_of_cells(n, rows, &mesh.cells))?;
    let mut part32 = vec![0u32; n];
    let (counts, displs) = block_layout(n, size);
    world.all_gather_varcount_into(
        &mine[..],
        &mut PartitionMut::new(&mut part32[..], &counts[..], &displs[..]),
    );
    super::scatter::own_part(world, mesh, &checked(part32, size))
}

/// Like [`super::distribute::distribute`] with PT-Scotch's parts: rank 0
/// runs `load` (a file read) and sends each rank the cells touching its
/// block of nodes (one pass over the cells, messages of at most 64 MiB);
/// each rank builds its block's rows of the graph, PT-Scotch partitions
/// them, rank 0 gathers the parts and sends every rank its raw part. No
/// rank builds the whole graph. An error of `load` reaches every rank.
/// Collective.
pub fn distribute<C: Communicator>(
    world: &C,
    load: impl FnOnce() -> Result<Mesh, Error>,
) -> Result<LocalMesh, Error> {
    let (size, rank, root) = (
        world.size() as usize,
        world.rank() as usize,
        world.process_at_rank(0),
    );
    let mesh = if rank == 0 {
        match load() {
            Err(e) => {
                root_verdict(world, Some(&e))?;
                return Err(e);
            }
            Ok(mesh) => Some(mesh),
        }
    } else {
        None
    };
    root_verdict(world, None)?;
    let mut n = mesh.as_ref().map_or(0, |m| m.num_nodes()) as u64;
    root.broadcast_into(&mut n);
    let n = n as usize;
    let part = if n < size || size == 1 {
        blocks(n, size) // one rank: one part, no graph
    } else {
        let cells = match &mesh {
            Some(mesh) => send_cells(world, mesh)?,
            None => super::scatter::receive_value(world, "the cells of a block")?,
        };
        let rows = block(n, size, rank)..block(n, size, rank + 1);
        let mine = parts_of_rows(n, &NodeGraph::rows_of_cells(n, rows, &cells))?;
        drop(cells);
        if rank != 0 {
            root.gather_varcount_into(&mine[..]);
            return super::scatter::receive_part(world);
        }
        let mut part32 = vec![0u32; n];
        let (counts, displs) = block_layout(n, size);
        root.gather_varcount_into_root(
            &mine[..],
            &mut PartitionMut::new(&mut part32[..], &counts[..], &displs[..]),
        );
        checked(part32, size)
    };
    match &mesh {
        Some(mesh) => super::scatter::send_parts(world, mesh, &part),
        None => super::scatter::receive_part(world),
    }
}

/// The rank whose block of `n` nodes over `size` ranks holds node `v`: the
/// `r` with `block(r) <= v < block(r + 1)`. In u64: (v + 1) size stays far
/// below 2^64 for any mesh a rank can hold (u128's division was slower).
fn block_of(v: usize, n: usize, size: usize) -> usize {
    (((v as u64 + 1) * size as u64 - 1) / n as u64) as usize
}

/// Rank 0: the cells touching each rank's block of nodes, in one pass;
/// sends every other rank its cells and returns its own.
fn send_cells<C: Communicator>(world: &C, mesh: &Mesh) -> Result<Cells, Error> {
    let (n, size) = (mesh.num_nodes(), world.size() as usize);
    let mut by_rank: Vec<Cells> = (0..size).map(|_| Cells::new()).collect();
    let mut ranks: Vec<usize> = Vec::with_capacity(32);
    for cell in &mesh.cells {
        ranks.clear();
        ranks.extend(cell.iter().map(|&v| block_of(v, n, size)));
        ranks.sort_unstable();
        ranks.dedup();
        for &r in &ranks {
            by_rank[r].push(cell);
        }
    }
    for (r, cells) in by_rank.iter_mut().enumerate().skip(1) {
        super::scatter::send_value(world, r, &*cells, "the cells of a block")?;
        *cells = Cells::new();
    }
    Ok(by_rank.swap_remove(0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A part left empty or out of range falls back to contiguous blocks.
    #[test]
    fn empty_or_bad_parts_fall_back_to_blocks() {
        assert_eq!(checked(vec![1, 0, 1, 0], 2), vec![1, 0, 1, 0]);
        assert_eq!(checked(vec![0, 0, 0, 0], 2), vec![0, 0, 1, 1]);
        assert_eq!(checked(vec![0, 3, 1, 1], 2), vec![0, 0, 1, 1]);
        assert_eq!(block_layout(7, 3), (vec![2, 2, 3], vec![0, 2, 4]));
        assert_eq!(blocks(7, 3), vec![0, 0, 0, 1, 1, 2, 2]);
    }

    /// Every node's block is the one whose range holds it.
    #[test]
    fn block_of_a_node() {
        for (n, size) in [(7, 3), (8, 8), (100, 7), (1_000_003, 16)] {
            for r in 0..size {
                for v in block(n, size, r)..block(n, size, r + 1) {
                    assert_eq!(block_of(v, n, size), r, "n {n}, {size} ranks, node {v}");
                }
            }
        }
    }
}
