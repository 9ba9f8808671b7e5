//! A mesh read on rank 0 sent to the ranks as raw parts, which each rank
//! numbers and assembles itself (issue "Scaling studies", item 4).
//!
//! Rank 0 reads the file and partitions it (RCB: coordinates alone; METIS:
//! the nodal graph). Then, one part at a time, it sends each rank the nodes
//! it owns, the cells touching them with every node they use, and the group
//! elements touching them, in their input numbering, as messages of at
//! most [`CHUNK`] bytes; it holds one part's message at a time. Each rank
//! then orders its own nodes (reverse Cuthill-McKee on its part, the same
//! order [`super::distribute::locality_order`] gives on the whole graph),
//! learns its ghosts' new numbers from their owners (one all-to-all), and
//! builds its [`LocalMesh`] — the work rank 0 did for every rank before
//! (the whole nodal graph, the order, every local mesh: 0.25 + 0.03 + 0.04
//! s of 0.33 s on a 60k-node tetrahedral mesh, the others waiting; with
//! RCB the partition phase on 2 ranks is now 0.10-0.15 s against 0.20-0.32
//! s). With METIS rank 0 still builds the whole graph for it.
//!
//! The local meshes equal those rank 0 made before (`distribute::split`
//! with that order, kept as the tests' reference): the same numbering,
//! cells, groups and bodies; the contact CSVs and VTU files of a 60k-node
//! mesh on 1 and 2 ranks are byte-identical to the earlier binary's.

use super::distribute::{locality_order, LocalMesh, NodeGraph};
use super::{Bodies, CellMaterials, Cells, Group, Mesh};
use crate::comm::displacements;
use crate::error::Error;
use mpi::datatype::{Partition, PartitionMut};
use mpi::traits::*;
use serde::{Deserialize, Serialize};

/// The largest message of a raw part (bytes).
const CHUNK: usize = 1 << 26;

/// One rank's raw part, indices into its own `nodes`.
#[derive(Serialize, Deserialize)]
struct RawPart {
    dim: usize,
    global_nodes: usize,
    global_cells: usize,
    cell_kinds: String,
    /// The number of nodes every part owns.
    counts: Vec<usize>,
    /// Input numbers of the nodes: those the part owns and those its cells
    /// use, ascending; the part owning each.
    nodes: Vec<usize>,
    owner: Vec<u32>,
    coords: Vec<f64>,
    tags: Vec<u64>,
    /// Cells touching an owned node, in input order.
    cells: Cells,
    cell_set: Vec<u32>,
    sets: Vec<Vec<u32>>,
    /// Every group; the elements touching an owned node whose nodes are all
    /// in `nodes`.
    groups: Vec<Group>,
}

/// Rank 0's raw parts, one at a time.
struct Parts<'a> {
    mesh: &'a Mesh,
    part: &'a [usize],
    counts: Vec<usize>,
    owned: Vec<Vec<usize>>,
    cells_of: Vec<Vec<usize>>,
    /// Scratch: each input node's index in the part being made (u32::MAX:
    /// none).
    index: Vec<u32>,
    kinds: String,
}

impl<'a> Parts<'a> {
    /// The parts of `part` (every part, or part `only` alone).
    fn new(mesh: &'a Mesh, part: &'a [usize], nparts: usize, only: Option<usize>) -> Parts<'a> {
        let wanted = |p: usize| only.is_none_or(|o| o == p);
        let mut counts = vec![0usize; nparts];
        let mut owned: Vec<Vec<usize>> = vec![Vec::new(); nparts];
        for (v, &p) in part.iter().enumerate() {
            counts[p] += 1;
            if wanted(p) {
                owned[p].push(v);
            }
        }
        let mut cells_of: Vec<Vec<usize>> = vec![Vec::new(); nparts];
        let mut here = Vec::with_capacity(8);
        for (c, cell) in mesh.cells.iter().enumerate() {
            here.clear();
            for &v in cell {
                if wanted(part[v]) && !here.contains(&part[v]) {
                    here.push(part[v]);
                }
            }
            for &p in &here {
                cells_of[p].push(c);
            }
        }
        Parts {
            mesh,
            part,
            counts,
            owned,
            cells_of,
            index: vec![u32::MAX; part.len()],
            kinds: mesh.cell_kinds_label(),
        }
    }

    /// Part `p`'s raw part (its lists of owned nodes and cells are freed).
    fn make(&mut self, p: usize) -> RawPart {
        let (mesh, d) = (self.mesh, self.mesh.dim);
        let cells_p = std::mem::take(&mut self.cells_of[p]);
        // The owned nodes and, once each, the others the cells use.
        let mut nodes = std::mem::take(&mut self.owned[p]);
        for &v in &nodes {
            self.index[v] = 0;
        }
        for &c in &cells_p {
            for &v in mesh.cells.get(c) {
                if self.index[v] == u32::MAX {
                    self.index[v] = 0;
                    nodes.push(v);
                }
            }
        }
        nodes.sort_unstable();
        for (i, &v) in nodes.iter().enumerate() {
            self.index[v] = i as u32;
        }
        let index = &self.index;
        let local = |v: usize| index[v] as usize;
        let mut cells = Cells::new();
        let mut buf = Vec::with_capacity(8);
        for &c in &cells_p {
            buf.clear();
            buf.extend(mesh.cells.get(c).iter().map(|&v| local(v)));
            cells.push(&buf);
        }
        let groups = mesh
            .groups
            .iter()
            .map(|g| {
                let mut conn = Cells::new();
                for e in &g.conn {
                    if e.iter().any(|&v| self.part[v] == p)
                        && e.iter().all(|&v| index[v] != u32::MAX)
                    {
                        buf.clear();
                        buf.extend(e.iter().map(|&v| local(v)));
                        conn.push(&buf);
                    }
                }
                g.part(conn)
            })
            .collect();
        let raw = RawPart {
            dim: d,
            global_nodes: mesh.num_nodes(),
            global_cells: mesh.num_cells(),
            cell_kinds: self.kinds.clone(),
            counts: self.counts.clone(),
            owner: nodes.iter().map(|&v| self.part[v] as u32).collect(),
            coords: nodes
                .iter()
                .flat_map(|&v| mesh.coords[v * d..(v + 1) * d].iter().copied())
                .collect(),
            tags: nodes.iter().map(|&v| mesh.node_tags[v]).collect(),
            cells,
            cell_set: if mesh.bodies.cell_set.is_empty() {
                Vec::new()
            } else {
                cells_p.iter().map(|&c| mesh.bodies.cell_set[c]).collect()
            },
            sets: mesh.bodies.sets.clone(),
            groups,
            nodes,
        };
        for &v in &raw.nodes {
            self.index[v] = u32::MAX;
        }
        raw
    }
}

/// Rank 0: sends each other rank its raw part (in messages of at most
/// [`CHUNK`] bytes) and returns its own local mesh.
pub(super) fn send_parts<C: Communicator>(
    world: &C,
    mesh: &Mesh,
    part: &[usize],
) -> Result<LocalMesh, Error> {
    let nparts = world.size() as usize;
    let mut parts = Parts::new(mesh, part, nparts, None);
    for p in 1..nparts {
        send_value(world, p, &parts.make(p), "the mesh part")?;
    }
    let own = parts.make(0);
    drop(parts);
    build(world, own)
}

/// This rank's local mesh of a mesh every rank holds whole, split by
/// `part` (the same on every rank): its own part alone made and built,
/// nothing sent. Collective (the ghosts' numbers).
pub(super) fn own_part<C: Communicator>(
    world: &C,
    mesh: &Mesh,
    part: &[usize],
) -> Result<LocalMesh, Error> {
    let me = world.rank() as usize;
    let raw = Parts::new(mesh, part, world.size() as usize, Some(me)).make(me);
    build(world, raw)
}

/// A rank other than 0: receives its raw part and builds its local mesh.
pub(super) fn receive_part<C: Communicator>(world: &C) -> Result<LocalMesh, Error> {
    build(world, receive_value(world, "the mesh part")?)
}

/// Rank 0: sends `value` (serialized, its length first, then messages of
/// at most [`CHUNK`] bytes) to rank `dest`, which takes it with
/// [`receive_value`]; `what` names it in an error.
pub(super) fn send_value<C: Communicator, T: Serialize>(
    world: &C,
    dest: usize,
    value: &T,
    what: &str,
) -> Result<(), Error> {
    let buf = postcard::to_allocvec(value)
        .map_err(|e| Error::Internal(format!("serializing {what}: {e}")))?;
    let dest = world.process_at_rank(dest as i32);
    dest.send(&(buf.len() as u64));
    for chunk in buf.chunks(CHUNK) {
        dest.send(chunk);
    }
    Ok(())
}

/// A rank other than 0: the value rank 0 sent it with [`send_value`].
pub(super) fn receive_value<C: Communicator, T: for<'de> Deserialize<'de>>(
    world: &C,
    what: &str,
) -> Result<T, Error> {
    let root = world.process_at_rank(0);
    let (len, _) = root.receive::<u64>();
    let mut buf = vec![0u8; len as usize];
    for chunk in buf.chunks_mut(CHUNK) {
        root.receive_into(chunk);
    }
    postcard::from_bytes(&buf)
        .map_err(|e| Error::Internal(format!("reading {what} from rank 0: {e}")))
}

/// The new global numbers of this rank's ghosts (`ghosts`: indices into
/// `raw.nodes`), asked of their owners; `owned_sorted`: this rank's owned
/// input numbers ascending, with their new numbers. Collective.
fn ghost_numbers<C: Communicator>(
    world: &C,
    raw: &RawPart,
    ghosts: &[usize],
    owned_sorted: &[(usize, usize)],
) -> Vec<usize> {
    let p = world.size() as usize;
    // The ghosts grouped by owner (stable: ascending input number in each).
    let mut by_owner: Vec<usize> = ghosts.to_vec();
    by_owner.sort_by_key(|&i| raw.owner[i]);
    let mut send_counts = vec![0i32; p];
    for &i in ghosts {
        send_counts[raw.owner[i] as usize] += 1;
    }
    let mut recv_counts = vec![0i32; p];
    world.all_to_all_into(&send_counts[..], &mut recv_counts[..]);
    let asked: Vec<u64> = by_owner.iter().map(|&i| raw.nodes[i] as u64).collect();
    let (sd, rd) = (displacements(&send_counts), displacements(&recv_counts));
    let mut got = vec![0u64; recv_counts.iter().sum::<i32>() as usize];
    world.all_to_all_varcount_into(
        &Partition::new(&asked[..], &send_counts[..], &sd[..]),
        &mut PartitionMut::new(&mut got[..], &recv_counts[..], &rd[..]),
    );
    let answers: Vec<u64> = got
        .iter()
        .map(|&v| {
            let k = owned_sorted
                .binary_search_by_key(&(v as usize), |&(old, _)| old)
                .expect("a ghost's owner owns it");
            owned_sorted[k].1 as u64
        })
        .collect();
    let mut back = vec![0u64; asked.len()];
    world.all_to_all_varcount_into(
        &Partition::new(&answers[..], &recv_counts[..], &rd[..]),
        &mut PartitionMut::new(&mut back[..], &send_counts[..], &sd[..]),
    );
    let mut new_of = vec![0usize; raw.nodes.len()];
    for (k, &i) in by_owner.iter().enumerate() {
        new_of[i] = back[k] as usize;
    }
    ghosts.iter().map(|&i| new_of[i]).collect()
}

/// This rank's local mesh from its raw part: its owned nodes in reverse
/// Cuthill-McKee order, then its ghosts by new number. Collective.
fn build<C: Communicator>(world: &C, raw: RawPart) -> Result<LocalMesh, Error> {
    let me = world.rank() as usize;
    let n = raw.nodes.len();
    let owned_start: usize = raw.counts[..me].iter().sum();
    let owned_count = raw.counts[me];
    let graph = NodeGraph::of_cells(n, &raw.cells);
    let side: Vec<usize> = raw
        .owner
        .iter()
        .map(|&o| usize::from(o as usize != me))
        .collect();
    let order = locality_order(&graph, &side, 2);
    drop(graph);
    if order[..owned_count].iter().any(|&i| side[i] != 0) {
        return Err(Error::Internal(
            "the mesh part's order mixes owned and ghost nodes".into(),
        ));
    }
    // Final local index of each raw node.
    let mut fin = vec![0usize; n];
    let mut owned_sorted = Vec::with_capacity(owned_count);
    for (k, &i) in order[..owned_count].iter().enumerate() {
        fin[i] = k;
        owned_sorted.push((raw.nodes[i], owned_start + k));
    }
    owned_sorted.sort_unstable();
    let ghosts: Vec<usize> = (0..n).filter(|&i| side[i] != 0).collect();
    let ghost_new = ghost_numbers(world, &raw, &ghosts, &owned_sorted);
    let mut by_new: Vec<(usize, usize)> = ghost_new
        .iter()
        .copied()
        .zip(ghosts.iter().copied())
        .collect();
    by_new.sort_unstable();
    let mut node_global: Vec<usize> = (owned_start..owned_start + owned_count).collect();
    for (j, &(g, i)) in by_new.iter().enumerate() {
        fin[i] = owned_count + j;
        node_global.push(g);
    }
    let d = raw.dim;
    let mut coords = vec![0.0; n * d];
    let mut node_tag = vec![0u64; n];
    for i in 0..n {
        coords[fin[i] * d..(fin[i] + 1) * d].copy_from_slice(&raw.coords[i * d..(i + 1) * d]);
        node_tag[fin[i]] = raw.tags[i];
    }
    let mut cells = raw.cells;
    for v in cells.nodes_mut() {
        *v = fin[*v];
    }
    let mut groups = raw.groups;
    for g in &mut groups {
        for v in g.conn.nodes_mut() {
            *v = fin[*v];
        }
    }
    Ok(LocalMesh {
        dim: d,
        global_nodes: raw.global_nodes,
        global_cells: raw.global_cells,
        cell_kinds: raw.cell_kinds,
        owned_start,
        owned_count,
        node_global,
        node_tag,
        coords,
        cells,
        groups,
        bodies: Bodies {
            cell_set: raw.cell_set,
            sets: raw.sets,
        },
        materials: CellMaterials::default(),
    })
}
