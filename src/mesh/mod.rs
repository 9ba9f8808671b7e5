//! Meshes: the serial mesh that rank 0 reads or generates, and its
//! distribution over the ranks (`partition`).
//!
//! A [`Mesh`] is P1 only: triangles in 2D, tetrahedra in 3D. Lower-dimensional
//! physical groups (points, lines, and triangles in 3D) are kept as named
//! [`Group`]s, since boundary conditions refer to physical-group names.

pub mod block3d;
pub mod distribute;
pub mod gmsh;
pub mod hertz2d;

use std::fmt;

/// A boundary (or point) physical group: its name and its elements.
#[derive(Clone, Debug, PartialEq)]
pub struct Group {
    /// Physical name from `$PhysicalNames`, or the physical tag as a string when unnamed.
    pub name: String,
    /// Dimension of the group's elements: 0 (points), 1 (lines), 2 (triangles in 3D).
    pub dim: usize,
    /// Connectivity, `dim + 1` node indices (0-based into `Mesh::coords`) per element.
    pub conn: Vec<usize>,
}

impl Group {
    pub fn nodes_per_element(&self) -> usize {
        self.dim + 1
    }
    pub fn len(&self) -> usize {
        self.conn.len() / self.nodes_per_element()
    }
    pub fn is_empty(&self) -> bool {
        self.conn.is_empty()
    }
}

/// A serial P1 mesh. Equality compares the geometry, the node tags and the
/// groups, not the element tags (formats number elements differently).
#[derive(Clone, Debug)]
pub struct Mesh {
    /// 2 (triangles) or 3 (tetrahedra).
    pub dim: usize,
    /// Node coordinates, `dim` values per node.
    pub coords: Vec<f64>,
    /// The node's tag in the input file (1-based numbering for generated meshes).
    pub node_tags: Vec<u64>,
    /// Cells, `dim + 1` node indices per cell.
    pub cells: Vec<usize>,
    /// The cell's element tag in the input file (1-based numbering for generated meshes).
    pub cell_tags: Vec<u64>,
    /// Physical groups of dimension < `dim`, and those of dimension `dim`
    /// by name only (no elements: the cells are the body), so that an
    /// option naming one is told its dimension.
    pub groups: Vec<Group>,
}

/// An error reading or generating a mesh. Its `Display` is one line naming the
/// file and the line (ASCII) or byte offset (binary) where it went wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshError(pub String);

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for MeshError {}

impl From<MeshError> for crate::error::Error {
    fn from(e: MeshError) -> Self {
        crate::error::Error::Mesh(e.0)
    }
}

impl PartialEq for Mesh {
    fn eq(&self, o: &Mesh) -> bool {
        self.dim == o.dim
            && self.coords == o.coords
            && self.node_tags == o.node_tags
            && self.cells == o.cells
            && self.groups == o.groups
    }
}

impl Mesh {
    /// The element tag of cell `c` in the input file (its 1-based position if unknown).
    pub fn cell_tag(&self, c: usize) -> u64 {
        self.cell_tags.get(c).copied().unwrap_or(c as u64 + 1)
    }

    pub fn num_nodes(&self) -> usize {
        self.coords.len() / self.dim
    }
    pub fn num_cells(&self) -> usize {
        self.cells.len() / (self.dim + 1)
    }
    pub fn group(&self, name: &str) -> Option<&Group> {
        self.groups.iter().find(|g| g.name == name)
    }

    /// Drops the nodes that no cell uses (Gmsh keeps geometry points) and
    /// renumbers cells and groups. Group elements that touch a dropped node are
    /// dropped too (a point group on an unused geometry point, say).
    pub fn drop_unused_nodes(&mut self) {
        let n = self.num_nodes();
        let mut used = vec![false; n];
        for &v in &self.cells {
            used[v] = true;
        }
        if used.iter().all(|&u| u) {
            return;
        }
        let mut new_index = vec![usize::MAX; n];
        let mut next = 0;
        for (ni, &u) in new_index.iter_mut().zip(&used) {
            if u {
                *ni = next;
                next += 1;
            }
        }
        let d = self.dim;
        let mut coords = Vec::with_capacity(next * d);
        let mut tags = Vec::with_capacity(next);
        for (i, _) in used.iter().enumerate().filter(|(_, &u)| u) {
            coords.extend_from_slice(&self.coords[i * d..(i + 1) * d]);
            tags.push(self.node_tags[i]);
        }
        self.coords = coords;
        self.node_tags = tags;
        for v in &mut self.cells {
            *v = new_index[*v];
        }
        for g in &mut self.groups {
            let k = g.nodes_per_element();
            let mut conn = Vec::with_capacity(g.conn.len());
            for e in g.conn.chunks(k) {
                if e.iter().all(|&v| used[v]) {
                    conn.extend(e.iter().map(|&v| new_index[v]));
                }
            }
            g.conn = conn;
        }
    }

    /// Cell volume (area in 2D) of cell `c`, signed: positive when the cell is
    /// positively oriented.
    pub fn signed_measure(&self, c: usize) -> f64 {
        let d = self.dim;
        let v = &self.cells[c * (d + 1)..(c + 1) * (d + 1)];
        let x = |i: usize, k: usize| self.coords[v[i] * d + k];
        if d == 2 {
            0.5 * ((x(1, 0) - x(0, 0)) * (x(2, 1) - x(0, 1))
                - (x(2, 0) - x(0, 0)) * (x(1, 1) - x(0, 1)))
        } else {
            let a = [x(1, 0) - x(0, 0), x(1, 1) - x(0, 1), x(1, 2) - x(0, 2)];
            let b = [x(2, 0) - x(0, 0), x(2, 1) - x(0, 1), x(2, 2) - x(0, 2)];
            let c3 = [x(3, 0) - x(0, 0), x(3, 1) - x(0, 1), x(3, 2) - x(0, 2)];
            (a[0] * (b[1] * c3[2] - b[2] * c3[1]) - a[1] * (b[0] * c3[2] - b[2] * c3[0])
                + a[2] * (b[0] * c3[1] - b[1] * c3[0]))
                / 6.0
        }
    }
}
