//! One rank's part of the built-in block (`-mesh_generate block3d`), made
//! without the rest of the mesh (issue "Scaling studies", item 4): the grid
//! of nodes is cut into boxes of whole node layers by recursive bisection
//! along the rank tree of [`crate::mesh::distribute::partition_rcb`] (each
//! range of ranks `[lo, hi)` split at `lo + (hi - lo) / 2`, across the
//! box's longest extent, in the ratio of the two halves' rank counts), so
//! every rank knows every box from the grid's size alone: no graph, no
//! coordinates of other parts, nothing sent. A rank then makes the cells
//! touching its box (one layer of boxes around it), its ghost nodes and its
//! boundary elements, numbered as `distribute::split` numbers
//! them: each part's nodes contiguous (part 0 first), x fastest within a
//! box; ghosts after the owned nodes, by global number. Cells, elements,
//! coordinates and node tags are those of [`super::block3d::generate`] and
//! [`super::block3d::generate_hex`], in their order.

use super::block3d::{coordinate, dims, HEX, KUHN, LENGTH};
use super::distribute::LocalMesh;
use super::{kinds_label, Cells, Group, MeshError};
use std::collections::HashMap;

/// A box of grid nodes: `lo[a] <= index[a] < hi[a]` along each axis.
#[derive(Clone, Copy, Debug, PartialEq)]
struct NodeBox {
    lo: [usize; 3],
    hi: [usize; 3],
}

impl NodeBox {
    fn count(&self) -> usize {
        (0..3).map(|a| self.hi[a] - self.lo[a]).product()
    }

    fn contains(&self, ijk: [usize; 3]) -> bool {
        (0..3).all(|a| self.lo[a] <= ijk[a] && ijk[a] < self.hi[a])
    }

    /// Position of `ijk` in the box, x fastest.
    fn offset(&self, ijk: [usize; 3]) -> usize {
        let w = [self.hi[0] - self.lo[0], self.hi[1] - self.lo[1]];
        (ijk[0] - self.lo[0]) + w[0] * ((ijk[1] - self.lo[1]) + w[1] * (ijk[2] - self.lo[2]))
    }
}

/// The boxes of ranks `lo..hi`, appended in rank order; false when a box
/// of one node would have to be cut (then the caller cuts the whole mesh
/// instead).
fn bisect(b: NodeBox, n: [usize; 3], lo: usize, hi: usize, out: &mut Vec<NodeBox>) -> bool {
    if hi - lo <= 1 {
        out.push(b);
        return true;
    }
    let mid = lo + (hi - lo) / 2;
    // The longest extent (the first axis on ties, as partition_rcb).
    let extent = |a: usize| (b.hi[a] - b.lo[a] - 1) as f64 * LENGTH[a] / n[a] as f64;
    let mut axis = 0;
    for a in 1..3 {
        if extent(a) > extent(axis) {
            axis = a;
        }
    }
    let layers = b.hi[axis] - b.lo[axis];
    if layers < 2 {
        return false;
    }
    // Layers in the ratio of the ranks, at least one each side.
    let left = ((layers * (mid - lo) + (hi - lo) / 2) / (hi - lo)).clamp(1, layers - 1);
    let (mut a, mut c) = (b, b);
    a.hi[axis] = b.lo[axis] + left;
    c.lo[axis] = b.lo[axis] + left;
    bisect(a, n, lo, mid, out) && bisect(c, n, mid, hi, out)
}

/// Corner `c = a + 2 b + 4 c'` of the grid box whose lowest corner is `ijk`.
fn corner(ijk: [usize; 3], c: usize) -> [usize; 3] {
    [ijk[0] + (c & 1), ijk[1] + ((c >> 1) & 1), ijk[2] + (c >> 2)]
}

/// One rank's box among all of them, with its ghost nodes.
struct Part {
    /// Intervals along each axis.
    n: [usize; 3],
    /// The box of nodes this rank owns.
    mine: NodeBox,
    /// First global number of the box.
    start: usize,
    /// The grid boxes (cells) touching an owned node: `cell_lo <= c < cell_hi`.
    cell_lo: [usize; 3],
    cell_hi: [usize; 3],
    /// The ghost nodes: global number and grid index, by global number.
    ghosts: Vec<(usize, [usize; 3])>,
    local_of_ghost: HashMap<[usize; 3], usize>,
}

impl Part {
    fn new(n: [usize; 3], boxes: &[NodeBox], start: &[usize], p: usize) -> Part {
        let mine = boxes[p];
        let global = |ijk: [usize; 3]| -> usize {
            let q = boxes
                .iter()
                .position(|b| b.contains(ijk))
                .expect("boxes cover the grid");
            start[q] + boxes[q].offset(ijk)
        };
        let cell_lo: [usize; 3] = std::array::from_fn(|a| mine.lo[a].saturating_sub(1));
        let cell_hi: [usize; 3] = std::array::from_fn(|a| mine.hi[a].min(n[a]));
        let mut ghosts: Vec<(usize, [usize; 3])> = Vec::new();
        for k in cell_lo[2]..=cell_hi[2] {
            for j in cell_lo[1]..=cell_hi[1] {
                for i in cell_lo[0]..=cell_hi[0] {
                    if !mine.contains([i, j, k]) {
                        ghosts.push((global([i, j, k]), [i, j, k]));
                    }
                }
            }
        }
        ghosts.sort_unstable();
        let owned = mine.count();
        let local_of_ghost = ghosts
            .iter()
            .enumerate()
            .map(|(g, &(_, ijk))| (ijk, owned + g))
            .collect();
        Part {
            n,
            mine,
            start: start[p],
            cell_lo,
            cell_hi,
            ghosts,
            local_of_ghost,
        }
    }

    fn local(&self, ijk: [usize; 3]) -> usize {
        if self.mine.contains(ijk) {
            self.mine.offset(ijk)
        } else {
            self.local_of_ghost[&ijk]
        }
    }

    /// Global numbers, tags and coordinates of the local nodes: the box
    /// (x fastest), then the ghosts.
    fn nodes(&self) -> (Vec<usize>, Vec<u64>, Vec<f64>) {
        let (n, mine) = (self.n, self.mine);
        let mut ijks: Vec<[usize; 3]> = Vec::with_capacity(mine.count() + self.ghosts.len());
        for k in mine.lo[2]..mine.hi[2] {
            for j in mine.lo[1]..mine.hi[1] {
                for i in mine.lo[0]..mine.hi[0] {
                    ijks.push([i, j, k]);
                }
            }
        }
        let owned = ijks.len();
        ijks.extend(self.ghosts.iter().map(|&(_, ijk)| ijk));
        let node_global = (self.start..self.start + owned)
            .chain(self.ghosts.iter().map(|&(g, _)| g))
            .collect();
        let original = |ijk: [usize; 3]| ijk[0] + (n[0] + 1) * (ijk[1] + (n[1] + 1) * ijk[2]);
        let node_tag = ijks.iter().map(|&ijk| original(ijk) as u64 + 1).collect();
        let coords = ijks
            .iter()
            .flat_map(|&ijk| (0..3).map(move |a| coordinate(a, ijk[a], n[a])))
            .collect();
        (node_global, node_tag, coords)
    }

    /// Cells touching an owned node, in the generators' order (boxes x
    /// fastest; six tetrahedra or one hexahedron each).
    fn cells(&self, q1: bool) -> Cells {
        let (lo, hi) = (self.cell_lo, self.cell_hi);
        let mut conn = Vec::new();
        for k in lo[2]..hi[2] {
            for j in lo[1]..hi[1] {
                for i in lo[0]..hi[0] {
                    if q1 {
                        conn.extend(HEX.iter().map(|&c| self.local(corner([i, j, k], c))));
                        continue;
                    }
                    // A box at the edge of the part has tetrahedra without
                    // an owned node: those belong to others alone.
                    for t in &KUHN {
                        let tet = t.map(|c| corner([i, j, k], c));
                        if tet.iter().any(|&v| self.mine.contains(v)) {
                            conn.extend(tet.iter().map(|&v| self.local(v)));
                        }
                    }
                }
            }
        }
        Cells::uniform(conn, if q1 { 8 } else { 4 })
    }

    /// The boundary elements touching an owned node on the faces `list`
    /// (axis, upper), in the generators' order: per face, its squares with
    /// the second in-plane axis outer, split as the generators split them.
    fn faces(&self, q1: bool, list: &[(usize, bool)]) -> Cells {
        let (lo, hi) = (self.cell_lo, self.cell_hi);
        let mut conn: Vec<usize> = Vec::new();
        for &(axis, upper) in list {
            let (pa, qa) = ((axis + 1) % 3, (axis + 2) % 3);
            let plane = if upper { self.n[axis] } else { 0 };
            if plane < lo[axis] || plane > hi[axis] {
                continue;
            }
            for b in lo[qa]..hi[qa] {
                for a in lo[pa]..hi[pa] {
                    let at = |da: usize, db: usize| {
                        let mut ijk = [0; 3];
                        ijk[axis] = plane;
                        ijk[pa] = a + da;
                        ijk[qa] = b + db;
                        ijk
                    };
                    let [c00, c10, c01, c11] = [at(0, 0), at(1, 0), at(0, 1), at(1, 1)];
                    let elements: Vec<Vec<[usize; 3]>> = match (q1, upper) {
                        (false, true) => vec![vec![c00, c10, c11], vec![c00, c11, c01]],
                        (false, false) => vec![vec![c00, c11, c10], vec![c00, c01, c11]],
                        (true, true) => vec![vec![c00, c10, c11, c01]],
                        (true, false) => vec![vec![c00, c01, c11, c10]],
                    };
                    for e in elements {
                        if e.iter().any(|&v| self.mine.contains(v)) {
                            conn.extend(e.iter().map(|&v| self.local(v)));
                        }
                    }
                }
            }
        }
        Cells::uniform(conn, if q1 { 4 } else { 3 })
    }
}

/// Part `p` of `nparts` of the block at element size `h` (hexahedra with
/// `q1`, else the Kuhn tetrahedra). `Ok(None)` when a cut would leave a
/// rank without nodes (a tiny mesh on many ranks).
pub fn own_part(h: f64, q1: bool, nparts: usize, p: usize) -> Result<Option<LocalMesh>, MeshError> {
    let n = dims(h)?;
    let whole = NodeBox {
        lo: [0; 3],
        hi: [n[0] + 1, n[1] + 1, n[2] + 1],
    };
    let mut boxes = Vec::with_capacity(nparts);
    if !bisect(whole, n, 0, nparts, &mut boxes) {
        return Ok(None);
    }
    let mut start = vec![0usize; nparts + 1];
    for (q, b) in boxes.iter().enumerate() {
        start[q + 1] = start[q] + b.count();
    }
    let part = Part::new(n, &boxes, &start, p);
    let (node_global, node_tag, coords) = part.nodes();
    let cells = part.cells(q1);
    let group =
        |name: &str, list: &[(usize, bool)]| Group::new(name.to_string(), 2, part.faces(q1, list));
    let groups = vec![
        group("top", &[(2, true)]),
        group("bottom", &[(2, false)]),
        group("sides", &[(0, false), (0, true), (1, false), (1, true)]),
    ];
    let boxes_total = n[0] * n[1] * n[2];
    Ok(Some(LocalMesh {
        dim: 3,
        global_nodes: start[nparts],
        global_cells: if q1 { boxes_total } else { 6 * boxes_total },
        cell_kinds: kinds_label(3, &cells),
        owned_start: start[p],
        owned_count: boxes[p].count(),
        node_global,
        node_tag,
        coords,
        cells,
        groups,
        bodies: Default::default(),
        materials: Default::default(),
    }))
}

#[cfg(test)]
mod tests {
    use super::super::block3d::{generate, generate_hex};
    use super::*;

    /// Every part against the whole generated mesh: the parts own every
    /// node once, in contiguous blocks; each part holds exactly the cells
    /// and boundary elements of the whole mesh that touch one of its nodes,
    /// in the whole mesh's order, with the same node tags and coordinates.
    #[test]
    fn parts_are_the_whole_mesh_cut() {
        for (h, q1) in [(0.25, false), (0.2, true), (0.34, false)] {
            let whole = if q1 { generate_hex(h) } else { generate(h) }.unwrap();
            for nparts in [1, 2, 3, 5, 8] {
                let parts: Vec<LocalMesh> = (0..nparts)
                    .map(|p| own_part(h, q1, nparts, p).unwrap().unwrap())
                    .collect();
                // Owner of each whole-mesh node (by tag).
                let mut owner = vec![usize::MAX; whole.num_nodes()];
                let mut next = 0;
                for (p, m) in parts.iter().enumerate() {
                    assert_eq!(m.owned_start, next, "h {h}, {nparts} parts");
                    next += m.owned_count;
                    assert_eq!(m.global_nodes, whole.num_nodes());
                    assert_eq!(m.global_cells, whole.num_cells());
                    for v in 0..m.owned_count {
                        let old = (m.node_tag[v] - 1) as usize;
                        assert_eq!(owner[old], usize::MAX, "node owned twice");
                        owner[old] = p;
                    }
                    for v in 0..m.num_local_nodes() {
                        let old = (m.node_tag[v] - 1) as usize;
                        assert_eq!(m.x(v), &whole.coords[3 * old..3 * old + 3]);
                    }
                    let mut ghosts = m.node_global[m.owned_count..].to_vec();
                    ghosts.dedup();
                    assert!(ghosts.windows(2).all(|w| w[0] < w[1]));
                    assert_eq!(ghosts.len(), m.num_local_nodes() - m.owned_count);
                }
                assert_eq!(next, whole.num_nodes());
                for (p, m) in parts.iter().enumerate() {
                    let tags = |c: &[usize]| c.iter().map(|&v| m.node_tag[v]).collect::<Vec<_>>();
                    let want: Vec<Vec<u64>> = whole
                        .cells
                        .iter()
                        .filter(|c| c.iter().any(|&v| owner[v] == p))
                        .map(|c| c.iter().map(|&v| v as u64 + 1).collect())
                        .collect();
                    let got: Vec<Vec<u64>> = m.cells.iter().map(tags).collect();
                    assert_eq!(got, want, "cells of part {p} of {nparts}");
                    for (g, wg) in m.groups.iter().zip(&whole.groups) {
                        assert_eq!(g.name, wg.name);
                        let want: Vec<Vec<u64>> = wg
                            .conn
                            .iter()
                            .filter(|e| e.iter().any(|&v| owner[v] == p))
                            .map(|e| e.iter().map(|&v| v as u64 + 1).collect())
                            .collect();
                        let got: Vec<Vec<u64>> = g.conn.iter().map(tags).collect();
                        assert_eq!(got, want, "group {} of part {p} of {nparts}", g.name);
                    }
                    // Global numbers: the owner's block, consistently on every part.
                    for v in 0..m.num_local_nodes() {
                        let old = (m.node_tag[v] - 1) as usize;
                        let q = owner[old];
                        let g = m.node_global[v];
                        assert!(
                            parts[q].owned_start <= g
                                && g < parts[q].owned_start + parts[q].owned_count
                        );
                        assert_eq!(parts[q].node_tag[g - parts[q].owned_start], m.node_tag[v]);
                    }
                }
            }
        }
    }

    #[test]
    fn too_few_layers_falls_back() {
        // h = 1: 2 x 3 x 2 nodes; 13 ranks need more cuts than nodes.
        assert!(own_part(1.0, false, 13, 0).unwrap().is_none());
        assert!(own_part(1.0, false, 2, 1).unwrap().is_some());
        assert!(own_part(-1.0, false, 2, 0).is_err());
    }
}
