//! Distribution of a serial mesh over the ranks.
//!
//! Rank 0 holds the whole mesh. METIS (or RCB) partitions it into one part
//! per rank; nodes are renumbered so that each rank owns a contiguous block of
//! global node numbers (part 0 first). Each rank then receives only the cells
//! that touch one of its nodes, with every node those cells use (its owned
//! nodes first, then the "ghost" nodes of its neighbours), and the group
//! elements that touch one of its nodes. With that, a rank assembles the full
//! rows of the nodes it owns without any communication. Rank 0 sends the
//! parts raw, and each rank numbers its own (`mesh/scatter.rs`); `split` (tests)
//! makes every part on one process (the same local meshes).
//!
//! A generated mesh skips the sending: split by RCB, every rank cuts the
//! mesh the same way and keeps its own part (own_part_rcb here; the
//! block's boxes in block3d_parts.rs, without the rest of the mesh); split
//! by METIS, rank 0's parts are broadcast and each rank builds its own
//! (own_part_metis).

use super::{Bodies, CellMaterials, Cells, Group, Mesh};
use crate::error::Error;
use mpi::traits::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// The part of the mesh a rank works on (sent from rank 0 to its rank
/// serialized with `postcard`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LocalMesh {
    pub dim: usize,
    pub global_nodes: usize,
    pub global_cells: usize,
    /// The kinds of the whole mesh's cells in words, for summaries:
    /// "triangles", "quadrilaterals", "triangles and quadrilaterals", ...
    pub cell_kinds: String,
    /// First global (renumbered) node this rank owns, and how many.
    pub owned_start: usize,
    pub owned_count: usize,
    /// Global node number of each local node: owned first (contiguous), then ghosts.
    pub node_global: Vec<usize>,
    /// The node's tag in the input mesh.
    pub node_tag: Vec<u64>,
    pub coords: Vec<f64>,
    /// Cells touching an owned node, in local numbering (any mix of kinds).
    pub cells: Cells,
    /// Every group of the mesh, in the same order on every rank; each with the
    /// elements that touch an owned node.
    pub groups: Vec<Group>,
    /// The body groups of each local cell (the table of sets whole, the
    /// same on every rank).
    pub bodies: Bodies,
    /// The material of each local cell (resolved on each rank after the
    /// distribution, not sent).
    #[serde(skip)]
    pub materials: CellMaterials,
}

impl LocalMesh {
    pub fn num_local_nodes(&self) -> usize {
        self.node_global.len()
    }
    pub fn num_cells(&self) -> usize {
        self.cells.len()
    }
    pub fn is_owned(&self, local: usize) -> bool {
        local < self.owned_count
    }
    pub fn group(&self, name: &str) -> Option<&Group> {
        self.groups.get(super::find_group(&self.groups, name)?)
    }
    /// "a (1D), b (2D)": the mesh's groups and their dimensions, for messages.
    pub fn group_names(&self) -> String {
        let names: Vec<String> = self
            .groups
            .iter()
            .map(|g| format!("{} ({}D)", g.name, g.dim))
            .collect();
        names.join(", ")
    }

    /// The group an option names, of a dimension in `dims`; an error naming
    /// the option otherwise: the groups the mesh has, how Gmsh adds them when
    /// it has none, the group's dimension when it is of another.
    pub fn group_for(
        &self,
        option: &str,
        name: &str,
        dims: std::ops::RangeInclusive<usize>,
        what: &str,
    ) -> Result<&Group, Error> {
        let Some(group) = self.group(name) else {
            if self.groups.is_empty() {
                let (kind, example) = if self.dim == 2 {
                    ("Physical Curve", "Physical Curve(\"contact\") = {1, 2};")
                } else {
                    ("Physical Surface", "Physical Surface(\"contact\") = {1};")
                };
                return Err(Error::BadInput(format!(
                    "option {option}: the mesh has no physical groups, and options name them: in Gmsh, add a {kind} (or Physical Point, Curve) for each boundary part before meshing, e.g. {example} in the .geo file"
                )));
            }
            let spaces = if self.groups.iter().any(|g| g.name.contains(' ')) {
                "; a space in a group's name is written _ in an option"
            } else {
                ""
            };
            return Err(Error::BadInput(format!(
                "option {option}: the mesh has no physical group '{name}' (it has: {}{spaces})",
                self.group_names()
            )));
        };
        if !dims.contains(&group.dim) {
            let held = if group.dim == self.dim {
                let volume = if self.dim == 2 {
                    "; a 3D body needs its volume in a Physical Volume, or Gmsh writes no 3D cell"
                } else {
                    ""
                };
                format!(
                    " (it holds the body's cells, the mesh is {}D{volume})",
                    self.dim
                )
            } else {
                String::new()
            };
            let want = if dims.start() == dims.end() {
                format!("dimension {}", dims.start())
            } else {
                format!("dimension {} to {}", dims.start(), dims.end())
            };
            return Err(Error::BadInput(format!(
                "option {option}: group '{name}' has dimension {}{held}; {what} needs a group of {want}",
                group.dim
            )));
        }
        if group.off_body > 0 {
            // Gmsh writes a physical group's elements whether or not the
            // body's cells use their nodes (a helper curve, a surface meshed
            // apart from the volume): a load or support there would act on
            // nothing, silently.
            let (off, all, d) = (group.off_body, group.file_len, self.dim);
            let which = if all == 1 {
                format!("its one element uses a node that no {d}D cell of the mesh uses")
            } else if off == all {
                format!("none of its {all} elements is on it (each uses a node that no {d}D cell of the mesh uses)")
            } else {
                format!("{off} of its {all} elements are not on it (each uses a node that no {d}D cell of the mesh uses)")
            };
            let lead = if off == all {
                "is not on the body"
            } else {
                "is partly off the body"
            };
            return Err(Error::BadInput(format!(
                "option {option}: group '{name}' {lead}: {which}; {what} there would act on nothing: mesh the group on the body's own boundary (in Gmsh, a curve or surface of the body itself, or join separate pieces with BooleanFragments)"
            )));
        }
        Ok(group)
    }
    pub fn x(&self, local: usize) -> &[f64] {
        &self.coords[local * self.dim..(local + 1) * self.dim]
    }
}

/// The nodal graph of a mesh (nodes sharing a cell, whatever its kind: the
/// eight nodes of a hexahedron are all neighbours, as the stiffness
/// couples them), in CSR form as METIS wants it.
pub struct NodeGraph {
    pub xadj: Vec<i32>,
    pub adjncy: Vec<i32>,
}

impl NodeGraph {
    pub fn new(mesh: &Mesh) -> NodeGraph {
        NodeGraph::of_cells(mesh.num_nodes(), &mesh.cells)
    }

    /// The graph of `n` nodes joined by `cells`: each node's neighbours
    /// gathered from the cells around it (a node-to-cell incidence in
    /// compressed rows), sorted, without repeats. Flat arrays only: the
    /// list per node this replaced took 0.25 s of a 0.33 s partition on
    /// rank 0 (60k-node tetrahedral mesh).
    pub fn of_cells(n: usize, cells: &Cells) -> NodeGraph {
        NodeGraph::rows_of_cells(n, 0..n, cells)
    }

    /// The rows of the nodes `rows` (a range of node numbers) of the graph
    /// of [`NodeGraph::of_cells`] (`cells` numbering `n` nodes): row `i`
    /// of the result is node `rows.start + i`, its neighbours numbered as
    /// in `cells`. Each row's neighbours are collected once (a mark per
    /// node) and only those sorted, not the ~90 nodes of the ~23
    /// tetrahedra around a node: the 1M-node generated block's graph in
    /// 0.36-0.50 s against 0.73-0.79 s (three runs each; on a 446k-node
    /// Gmsh file's numbering 1.3-1.7 s either way: cache misses rule).
    pub fn rows_of_cells(n: usize, rows: std::ops::Range<usize>, cells: &Cells) -> NodeGraph {
        let (lo, m) = (rows.start, rows.len());
        let mine = |a: usize| a.wrapping_sub(lo) < m;
        let mut start = vec![0usize; m + 1];
        for cell in cells {
            for &a in cell.iter().filter(|&&a| mine(a)) {
                start[a - lo + 1] += 1;
            }
        }
        for v in 0..m {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut around = vec![0u32; start[m]];
        for (c, cell) in cells.iter().enumerate() {
            for &a in cell.iter().filter(|&&a| mine(a)) {
                around[fill[a - lo]] = c as u32;
                fill[a - lo] += 1;
            }
        }
        drop(fill);
        let mut xadj = Vec::with_capacity(m + 1);
        let mut adjncy = Vec::with_capacity(start[m] * 4);
        let mut list: Vec<i32> = Vec::with_capacity(64);
        // mark[b] == v: b is in row v's list already (or is its node).
        let mut mark = vec![u32::MAX; n];
        xadj.push(0i32);
        for v in 0..m {
            list.clear();
            mark[lo + v] = v as u32;
            for &c in &around[start[v]..start[v + 1]] {
                for &b in cells.get(c as usize) {
                    if mark[b] != v as u32 {
                        mark[b] = v as u32;
                        list.push(b as i32);
                    }
                }
            }
            list.sort_unstable();
            adjncy.extend_from_slice(&list);
            xadj.push(adjncy.len() as i32);
        }
        NodeGraph { xadj, adjncy }
    }

    pub fn neighbours(&self, v: usize) -> &[i32] {
        &self.adjncy[self.xadj[v] as usize..self.xadj[v + 1] as usize]
    }
    fn degree(&self, v: usize) -> usize {
        (self.xadj[v + 1] - self.xadj[v]) as usize
    }
}

/// Partitions the nodal graph into `nparts` parts with METIS.
/// Falls back to contiguous blocks if METIS leaves a part empty.
pub fn partition_nodes(graph: &NodeGraph, nparts: usize) -> Result<Vec<usize>, Error> {
    let n = graph.xadj.len() - 1;
    if nparts <= 1 {
        return Ok(vec![0; n]);
    }
    let mut part = vec![0i32; n];
    let ok = if n >= nparts {
        metis::Graph::new(1, nparts as i32, &graph.xadj, &graph.adjncy)
            .map_err(|e| Error::Internal(format!("METIS: {e}")))?
            .part_kway(&mut part)
            .is_ok()
    } else {
        false
    };
    let mut counts = vec![0usize; nparts];
    for &p in &part {
        counts[p as usize] += 1;
    }
    if !ok || counts.contains(&0) {
        // Contiguous blocks: every rank owns at least one node when n >= nparts.
        return Ok((0..n).map(|i| i * nparts / n.max(1)).collect());
    }
    Ok(part.into_iter().map(|p| p as usize).collect())
}

/// Recursive coordinate bisection into `nparts` parts, numbered along the
/// binary tree over the rank range that [`crate::linalg::ordering`] builds
/// (each range `[lo, hi)` split at `lo + (hi - lo) / 2`): each tree node's
/// nodes are cut by a plane across their longest extent, in the ratio of
/// the two halves' rank counts, so every part holds n/P nodes (within one)
/// and the separators of the parallel ordering are the thin layers along
/// the cutting planes. It needs only the coordinates: O(n log P), against
/// a graph partition of the whole mesh on rank 0 (METIS: 3.7 s of a 39 s
/// run on 16 ranks for the 1M-node block).
pub fn partition_rcb(coords: &[f64], dim: usize, nparts: usize) -> Vec<usize> {
    let n = coords.len() / dim.max(1);
    let mut part = vec![0usize; n];
    if nparts > 1 && n >= nparts {
        let mut idx: Vec<usize> = (0..n).collect();
        rcb(coords, dim, &mut idx, 0, nparts, &mut part);
    } else if nparts > 1 {
        // Fewer nodes than parts: one node each for the first ranks.
        for (v, p) in part.iter_mut().enumerate() {
            *p = v;
        }
    }
    part
}

fn rcb(coords: &[f64], dim: usize, idx: &mut [usize], lo: usize, hi: usize, part: &mut [usize]) {
    if hi - lo <= 1 {
        for &v in idx.iter() {
            part[v] = lo;
        }
        return;
    }
    let mid = lo + (hi - lo) / 2;
    let axis = (0..dim)
        .map(|d| {
            let (mn, mx) = idx
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    let c = coords[v * dim + d];
                    (a.min(c), b.max(c))
                });
            (d, mx - mn)
        })
        .fold((0, f64::NEG_INFINITY), |best, (d, w)| {
            if w > best.1 {
                (d, w)
            } else {
                best
            }
        })
        .0;
    // Nodes in the ratio of the ranks, each half keeping one node per rank.
    let len = idx.len();
    let k = ((len * (mid - lo) + (hi - lo) / 2) / (hi - lo)).clamp(mid - lo, len - (hi - mid));
    let key = |v: &usize| coords[v * dim + axis];
    idx.select_nth_unstable_by(k, |a, b| key(a).total_cmp(&key(b)).then(a.cmp(b)));
    let (left, right) = idx.split_at_mut(k);
    rcb(coords, dim, left, lo, mid, part);
    rcb(coords, dim, right, mid, hi, part);
}

/// The order in which the nodes get their new global numbers: part by part,
/// and within a part by reverse Cuthill-McKee on the part's subgraph, so that
/// neighbours get close numbers (Gmsh's own numbering scatters them, which
/// made every factorization and triangular solve 30-50% slower).
pub fn locality_order(graph: &NodeGraph, part: &[usize], nparts: usize) -> Vec<usize> {
    let n = part.len();
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); nparts];
    for (v, &p) in part.iter().enumerate() {
        members[p].push(v);
    }
    let mut visited = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let mut queue = std::collections::VecDeque::new();
    let mut nbrs: Vec<usize> = Vec::new();
    // Breadth-first search from `start` within its part; appends to `out`.
    let mut bfs = |start: usize, visited: &mut Vec<bool>, out: &mut Vec<usize>| {
        let p = part[start];
        visited[start] = true;
        queue.push_back(start);
        while let Some(v) = queue.pop_front() {
            out.push(v);
            nbrs.clear();
            nbrs.extend(
                graph
                    .neighbours(v)
                    .iter()
                    .map(|&w| w as usize)
                    .filter(|&w| part[w] == p && !visited[w]),
            );
            nbrs.sort_by_key(|&w| (graph.degree(w), w));
            for &w in &nbrs {
                visited[w] = true;
                queue.push_back(w);
            }
        }
    };
    for list in &mut members {
        list.sort_by_key(|&v| (graph.degree(v), v));
        let begin = order.len();
        for &v in list.iter() {
            if visited[v] {
                continue;
            }
            // A pseudo-peripheral start: the last node reached from `v`.
            let mut probe = Vec::new();
            bfs(v, &mut visited, &mut probe);
            let far = *probe.last().unwrap_or(&v);
            for &w in &probe {
                visited[w] = false;
            }
            bfs(far, &mut visited, &mut order);
        }
        order[begin..].reverse();
    }
    order
}

/// Builds the local meshes of all parts from the serial mesh and its node
/// partition, on one process: the reference of the tests (a run builds
/// each part on its own rank, `mesh/scatter.rs`).
/// `order` lists the nodes in their new global numbering, part by part
/// (e.g. from [`locality_order`]).
#[cfg(test)]
pub fn split(mesh: &Mesh, part: &[usize], order: &[usize], nparts: usize) -> Vec<LocalMesh> {
    let numbering = Numbering::new(part, order, nparts);
    // Cells per part: each cell goes to every part owning one of its nodes.
    let mut cells_of: Vec<Vec<usize>> = vec![Vec::new(); nparts];
    let mut parts_here = Vec::with_capacity(8);
    for (c, cell) in mesh.cells.iter().enumerate() {
        parts_here.clear();
        for &v in cell {
            if !parts_here.contains(&part[v]) {
                parts_here.push(part[v]);
            }
        }
        for &p in &parts_here {
            cells_of[p].push(c);
        }
    }
    let kinds = mesh.cell_kinds_label();
    (0..nparts)
        .map(|p| numbering.local_mesh(mesh, part, &cells_of[p], p, &kinds))
        .collect()
}

/// The local mesh of part `p` alone, for a mesh that every rank holds whole
/// (a generated one: every rank generates it, which costs less than one
/// rank generating, splitting and sending every part): the nodes
/// partitioned by [`partition_rcb`] (the same on every rank: the same
/// coordinates, the same cuts) and numbered part by part in the mesh's own
/// order (the generators number neighbours close together already). Only
/// part `p`'s cells are visited; nothing is sent.
pub fn own_part_rcb(mesh: &Mesh, nparts: usize, p: usize) -> LocalMesh {
    let part = partition_rcb(&mesh.coords, mesh.dim, nparts);
    // The nodes part by part, each part in the mesh's order (a stable sort).
    let mut order: Vec<usize> = (0..part.len()).collect();
    order.sort_by_key(|&v| part[v]);
    let numbering = Numbering::new(&part, &order, nparts);
    let cells: Vec<usize> = mesh
        .cells
        .iter()
        .enumerate()
        .filter(|(_, cell)| cell.iter().any(|&v| part[v] == p))
        .map(|(c, _)| c)
        .collect();
    numbering.local_mesh(mesh, &part, &cells, p, &mesh.cell_kinds_label())
}

/// The new global numbering of a partitioned mesh: each part owns a
/// contiguous block, part 0 first.
struct Numbering<'a> {
    /// First new number of each part (and the total at the end).
    start: Vec<usize>,
    /// New number of each old node.
    new_id: Vec<usize>,
    /// Old node of each new number.
    old_of_new: &'a [usize],
}

impl<'a> Numbering<'a> {
    fn new(part: &[usize], order: &'a [usize], nparts: usize) -> Numbering<'a> {
        let mut start = vec![0usize; nparts + 1];
        for &p in part {
            start[p + 1] += 1;
        }
        for p in 0..nparts {
            start[p + 1] += start[p];
        }
        let mut new_id = vec![0usize; part.len()];
        for (g, &old) in order.iter().enumerate() {
            new_id[old] = g;
        }
        Numbering {
            start,
            new_id,
            old_of_new: order,
        }
    }

    /// Part `p`'s local mesh from the cells `cells_p` (those touching one
    /// of its nodes, in increasing order).
    fn local_mesh(
        &self,
        mesh: &Mesh,
        part: &[usize],
        cells_p: &[usize],
        p: usize,
        kinds: &str,
    ) -> LocalMesh {
        let d = mesh.dim;
        let new_id = &self.new_id;
        let owned_start = self.start[p];
        let owned_count = self.start[p + 1] - owned_start;
        let mut node_global: Vec<usize> = (owned_start..owned_start + owned_count).collect();
        let mut ghost_ids: Vec<usize> = Vec::new();
        for &c in cells_p {
            for &v in mesh.cells.get(c) {
                if part[v] != p {
                    ghost_ids.push(new_id[v]);
                }
            }
        }
        ghost_ids.sort_unstable();
        ghost_ids.dedup();
        let mut local_of_ghost: HashMap<usize, usize> = HashMap::with_capacity(ghost_ids.len());
        for (j, &g) in ghost_ids.iter().enumerate() {
            local_of_ghost.insert(g, owned_count + j);
        }
        node_global.extend_from_slice(&ghost_ids);
        let to_local = |old: usize| -> Option<usize> {
            let g = new_id[old];
            if part[old] == p {
                Some(g - owned_start)
            } else {
                local_of_ghost.get(&g).copied()
            }
        };
        let mut coords = Vec::with_capacity(node_global.len() * d);
        let mut node_tag = Vec::with_capacity(node_global.len());
        for &g in &node_global {
            let old = self.old_of_new[g];
            coords.extend_from_slice(&mesh.coords[old * d..(old + 1) * d]);
            node_tag.push(mesh.node_tags[old]);
        }
        let mut cells = Cells::new();
        let mut cell = Vec::with_capacity(8);
        for &c in cells_p {
            cell.clear();
            cell.extend(
                mesh.cells
                    .get(c)
                    .iter()
                    .map(|&v| to_local(v).expect("cell node is local")),
            );
            cells.push(&cell);
        }
        let mut groups = Vec::with_capacity(mesh.groups.len());
        for g in &mesh.groups {
            let mut conn = Cells::new();
            for e in &g.conn {
                if e.iter().any(|&v| part[v] == p) && e.iter().all(|&v| to_local(v).is_some()) {
                    cell.clear();
                    cell.extend(e.iter().map(|&v| to_local(v).unwrap()));
                    conn.push(&cell);
                }
            }
            groups.push(g.part(conn));
        }
        LocalMesh {
            dim: d,
            global_nodes: mesh.num_nodes(),
            global_cells: mesh.num_cells(),
            cell_kinds: kinds.to_string(),
            owned_start,
            owned_count,
            node_global,
            node_tag,
            coords,
            cells,
            groups,
            bodies: Bodies {
                cell_set: if mesh.bodies.cell_set.is_empty() {
                    Vec::new()
                } else {
                    cells_p.iter().map(|&c| mesh.bodies.cell_set[c]).collect()
                },
                sets: mesh.bodies.sets.clone(),
            },
            materials: CellMaterials::default(),
        }
    }
}

/// Rank 0's verdict to every rank (collective): `Some(error)` on rank 0
/// (ignored elsewhere) becomes the same error on every rank, with rank 0's
/// message; `None`, Ok everywhere.
pub(super) fn root_verdict<C: Communicator>(
    world: &C,
    failed: Option<&Error>,
) -> Result<(), Error> {
    let root = world.process_at_rank(0);
    if world.rank() == 0 {
        let Some(e) = failed else {
            root.broadcast_into(&mut [0u64][..]);
            return Ok(());
        };
        let mut status = [if e.exit_code() == 2 { 2u64 } else { 1 }];
        let mut msg = e.to_string().into_bytes();
        let mut len = [msg.len() as u64];
        root.broadcast_into(&mut status[..]);
        root.broadcast_into(&mut len[..]);
        root.broadcast_into(&mut msg[..]);
        // The caller returns its own error.
        return Ok(());
    }
    let mut status = [0u64];
    root.broadcast_into(&mut status[..]);
    if status[0] == 0 {
        return Ok(());
    }
    let mut len = [0u64];
    root.broadcast_into(&mut len[..]);
    let mut msg = vec![0u8; len[0] as usize];
    root.broadcast_into(&mut msg[..]);
    let text = String::from_utf8_lossy(&msg).into_owned();
    let text = text.strip_prefix("error: ").unwrap_or(&text).to_string();
    Err(if status[0] == 2 {
        Error::BadInput(text)
    } else {
        Error::Internal(text)
    })
}

/// Rank 0 runs `load` (read or generate) and `partition` (the part of
/// every node, e.g. [`partition_nodes`] or [`partition_rcb`]) and sends
/// every rank its raw part, which the rank builds into its local mesh
/// (`mesh/scatter.rs`). One rank is one part: `partition` is not called
/// (METIS' nodal graph took 1.3-1.7 s of a 446k-node file for nothing). An
/// error on rank 0 reaches every rank, so the caller's error handling
/// stays collective.
pub fn distribute<C: Communicator>(
    world: &C,
    load: impl FnOnce() -> Result<Mesh, Error>,
    partition: impl FnOnce(&Mesh) -> Result<Vec<usize>, Error>,
) -> Result<LocalMesh, Error> {
    if world.rank() != 0 {
        root_verdict(world, None)?;
        return super::scatter::receive_part(world);
    }
    let parts = |mesh: &Mesh| match world.size() {
        1 => Ok(vec![0; mesh.num_nodes()]),
        _ => partition(mesh),
    };
    match load().and_then(|mesh| parts(&mesh).map(|part| (mesh, part))) {
        Err(e) => {
            root_verdict(world, Some(&e))?;
            Err(e)
        }
        Ok((mesh, part)) => {
            root_verdict(world, None)?;
            super::scatter::send_parts(world, &mesh, &part)
        }
    }
}

/// This rank's local mesh of a generated mesh that every rank has made
/// (the same on every rank), split by METIS on rank 0: rank 0 partitions
/// the nodal graph and broadcasts the parts; each rank makes and builds its
/// own part from its own copy, nothing else sent (rank 0 made and sent
/// every rank's part before). Collective.
pub fn own_part_metis<C: Communicator>(world: &C, mesh: &Mesh) -> Result<LocalMesh, Error> {
    let n = mesh.num_nodes();
    let mut part32 = vec![0u32; n];
    if world.rank() == 0 {
        match partition_nodes(&NodeGraph::new(mesh), world.size() as usize) {
            Ok(part) => {
                root_verdict(world, None)?;
                for (a, &b) in part32.iter_mut().zip(&part) {
                    *a = b as u32;
                }
            }
            Err(e) => {
                root_verdict(world, Some(&e))?;
                return Err(e);
            }
        }
    } else {
        root_verdict(world, None)?;
    }
    world.process_at_rank(0).broadcast_into(&mut part32[..]);
    let part: Vec<usize> = part32.into_iter().map(|p| p as usize).collect();
    super::scatter::own_part(world, mesh, &part)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The graph from the node-to-cell incidence equals the pairs of nodes
    /// sharing a cell, on mixed cells with a node in no cell.
    #[test]
    fn node_graph_of_mixed_cells() {
        let mut cells = Cells::new();
        cells.push(&[0, 1, 4, 3]);
        cells.push(&[1, 2, 4]);
        cells.push(&[2, 5, 4]);
        cells.push(&[3, 4, 7, 6]);
        let n = 9; // node 8 in no cell
        let g = NodeGraph::of_cells(n, &cells);
        for v in 0..n {
            let mut want: Vec<i32> = cells
                .iter()
                .filter(|c| c.contains(&v))
                .flat_map(|c| c.iter().copied())
                .filter(|&w| w != v)
                .map(|w| w as i32)
                .collect();
            want.sort_unstable();
            want.dedup();
            assert_eq!(g.neighbours(v), &want[..], "node {v}");
        }
        assert!(g.neighbours(8).is_empty());
        assert_eq!(g.xadj.len(), n + 1);
    }

    fn square() -> Mesh {
        // 3x3 nodes, 8 triangles.
        let mut coords = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                coords.push(i as f64);
                coords.push(j as f64);
            }
        }
        let mut cells = Vec::new();
        for j in 0..2 {
            for i in 0..2 {
                let a = j * 3 + i;
                cells.extend_from_slice(&[a, a + 1, a + 4, a, a + 4, a + 3]);
            }
        }
        let cells = Cells::uniform(cells, 3);
        Mesh {
            dim: 2,
            coords,
            node_tags: (1..=9).collect(),
            cell_tags: (1..=8).collect(),
            cells,
            groups: vec![Group::new("bottom", 1, Cells::uniform(vec![0, 1, 1, 2], 2))],
            bodies: Default::default(),
        }
    }

    #[test]
    fn split_covers_every_node_once_and_roundtrips() {
        let m = square();
        let part: Vec<usize> = (0..9).map(|i| if i % 3 < 2 { 0 } else { 1 }).collect();
        let order = locality_order(&NodeGraph::new(&m), &part, 2);
        let mut seen = order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..9).collect::<Vec<_>>());
        assert!(order[..6].iter().all(|&v| part[v] == 0));
        let locals = split(&m, &part, &order, 2);
        let owned: usize = locals.iter().map(|l| l.owned_count).sum();
        assert_eq!(owned, 9);
        assert_eq!(locals[0].owned_start, 0);
        assert_eq!(locals[1].owned_start, 6);
        for l in &locals {
            let wire = postcard::to_allocvec(l).unwrap();
            let back: LocalMesh = postcard::from_bytes(&wire).unwrap();
            assert_eq!(back.node_global, l.node_global);
            assert_eq!(back.cells, l.cells);
            assert_eq!(back.cell_kinds, "triangles");
            assert_eq!(back.coords, l.coords);
            assert_eq!(back.node_tag, l.node_tag);
            assert_eq!(back.groups, l.groups);
            // every cell touches an owned node
            for c in &l.cells {
                assert!(c.iter().any(|&v| l.is_owned(v)));
            }
        }
        // Part 1 owns column x=2: its cells are the 4 touching it.
        assert_eq!(locals[1].num_cells(), 4);
        // The bottom group's element (2,3) touches part 1's node 2 (old index 2).
        assert_eq!(locals[1].groups[0].len(), 1);
        assert_eq!(locals[0].groups[0].len(), 2);
    }

    /// The body groups travel with the cells: each local cell keeps its
    /// set (here: left of x = 1 in group 1, right of it in group 2).
    #[test]
    fn body_groups_follow_their_cells() {
        let mut m = square();
        let centre_x = |m: &Mesh, cell: &[usize]| -> f64 {
            cell.iter().map(|&v| m.coords[2 * v]).sum::<f64>() / 3.0
        };
        let members: Vec<(usize, u32)> = (0..m.num_cells())
            .map(|c| {
                (
                    c,
                    if centre_x(&m, m.cells.get(c)) < 1.0 {
                        1
                    } else {
                        2
                    },
                )
            })
            .collect();
        m.bodies = Bodies::from_members(m.num_cells(), members);
        assert_eq!(m.bodies.sets, vec![vec![], vec![1], vec![2]]);
        let part: Vec<usize> = (0..9).map(|i| i % 3).collect();
        let order = locality_order(&NodeGraph::new(&m), &part, 3);
        for l in split(&m, &part, &order, 3) {
            let wire = postcard::to_allocvec(&l).unwrap();
            let l: LocalMesh = postcard::from_bytes(&wire).unwrap();
            assert_eq!(l.bodies.sets, m.bodies.sets);
            assert_eq!(l.bodies.cell_set.len(), l.num_cells());
            for (c, cell) in l.cells.iter().enumerate() {
                let x = cell.iter().map(|&v| l.x(v)[0]).sum::<f64>() / 3.0;
                assert_eq!(l.bodies.of(c), &[if x < 1.0 { 1 } else { 2 }]);
            }
        }
    }

    #[test]
    fn rcb_parts_are_balanced_and_follow_the_tree() {
        // A 10 x 3 grid of points cut into 3 parts: the first cut gives
        // rank 0 one third, the second splits the rest in two.
        let coords: Vec<f64> = (0..30)
            .flat_map(|i| [(i % 10) as f64, (i / 10) as f64])
            .collect();
        let part = partition_rcb(&coords, 2, 3);
        for p in 0..3 {
            assert_eq!(part.iter().filter(|&&q| q == p).count(), 10);
        }
        // Cuts across x, the longest extent: part 0 holds the smallest x.
        let max_x = |p: usize| {
            (0..30)
                .filter(|&i| part[i] == p)
                .map(|i| coords[2 * i])
                .fold(f64::MIN, f64::max)
        };
        let min_x = |p: usize| {
            (0..30)
                .filter(|&i| part[i] == p)
                .map(|i| coords[2 * i])
                .fold(f64::MAX, f64::min)
        };
        assert!(max_x(0) <= min_x(1) && max_x(1) <= min_x(2));
        assert_eq!(partition_rcb(&coords[..4], 2, 3), vec![0, 1]);
    }

    #[test]
    fn metis_partition_is_balanced() {
        let m = square();
        let part = partition_nodes(&NodeGraph::new(&m), 2).unwrap();
        let c0 = part.iter().filter(|&&p| p == 0).count();
        assert!((3..=6).contains(&c0));
    }
}
