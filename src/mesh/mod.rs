//! Meshes: the serial mesh that rank 0 reads or generates, and its
//! distribution over the ranks (`partition`).
//!
//! A [`Mesh`] holds linear (first-order) cells: P1 triangles and Q1
//! (bilinear) quadrilaterals in 2D; P1 tetrahedra, Q1 (trilinear)
//! hexahedra, and the 6-node prisms and 5-node pyramids that join them in
//! 3D, in any mix. Lower-dimensional physical groups (points,
//! lines, and triangles or quadrilaterals in 3D) are kept as named
//! [`Group`]s, since boundary conditions refer to physical-group names.
//!
//! # Mixed cells
//! Connectivity is stored flat with offsets, as in CSR ([`Cells`]); the
//! offsets are left out while every cell has the same number of nodes, so a
//! pure P1 (or pure Q1) mesh costs what it did before mixed meshes, and its
//! loops run over fixed-size chunks. A cell's kind follows from the mesh's
//! dimension and its node count ([`CellKind::of`]): 3 or 4 nodes in 2D,
//! 4, 5, 6 or 8 in 3D.

pub mod block3d;
pub mod block3d_parts;
mod cells;
pub mod distribute;
pub mod gmsh;
pub mod hertz2d;
mod locality;
pub mod ptscotch;
mod scatter;

use crate::error::{bad, Error};
use crate::options::materials::Material;
use crate::options::MeshSource;
use crate::progress;
pub use cells::{CellIter, Cells};
use serde::{Deserialize, Serialize};
use std::fmt;

/// The element shapes a mesh can hold: cells of the top dimension and
/// boundary facets (points, lines, triangles, quadrilaterals). Node order
/// is Gmsh's: counter-clockwise corners for a quadrilateral, the bottom
/// face's four corners then the top face's for a hexahedron, the bottom
/// triangle then the top one for a prism, the base quadrilateral then the
/// apex for a pyramid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CellKind {
    Point,
    Line,
    Triangle,
    Quadrilateral,
    Tetrahedron,
    Hexahedron,
    Prism,
    Pyramid,
}

impl CellKind {
    /// The kind of an element of dimension `dim` with `nodes` nodes.
    pub fn of(dim: usize, nodes: usize) -> Option<CellKind> {
        match (dim, nodes) {
            (0, 1) => Some(CellKind::Point),
            (1, 2) => Some(CellKind::Line),
            (2, 3) => Some(CellKind::Triangle),
            (2, 4) => Some(CellKind::Quadrilateral),
            (3, 4) => Some(CellKind::Tetrahedron),
            (3, 8) => Some(CellKind::Hexahedron),
            (3, 6) => Some(CellKind::Prism),
            (3, 5) => Some(CellKind::Pyramid),
            _ => None,
        }
    }

    pub fn nodes(self) -> usize {
        match self {
            CellKind::Point => 1,
            CellKind::Line => 2,
            CellKind::Triangle => 3,
            CellKind::Quadrilateral | CellKind::Tetrahedron => 4,
            CellKind::Hexahedron => 8,
            CellKind::Prism => 6,
            CellKind::Pyramid => 5,
        }
    }

    /// Name, for messages.
    pub fn name(self) -> &'static str {
        match self {
            CellKind::Point => "point",
            CellKind::Line => "line",
            CellKind::Triangle => "triangle",
            CellKind::Quadrilateral => "quadrilateral",
            CellKind::Tetrahedron => "tetrahedron",
            CellKind::Hexahedron => "hexahedron",
            CellKind::Prism => "prism",
            CellKind::Pyramid => "pyramid",
        }
    }

    /// Plural name, for summaries and messages.
    pub fn plural(self) -> &'static str {
        match self {
            CellKind::Point => "points",
            CellKind::Line => "lines",
            CellKind::Triangle => "triangles",
            CellKind::Quadrilateral => "quadrilaterals",
            CellKind::Tetrahedron => "tetrahedra",
            CellKind::Hexahedron => "hexahedra",
            CellKind::Prism => "prisms",
            CellKind::Pyramid => "pyramids",
        }
    }
}

/// The index of the group named `name`: the group of that exact name, else
/// the one group whose name reads `name` with each space written `_` (an
/// option's name holds no space: `-dirichlet_Bottom_Face` names Gmsh's
/// "Bottom Face"); none when two such groups make it ambiguous.
pub fn find_group(groups: &[Group], name: &str) -> Option<usize> {
    if let Some(i) = groups.iter().position(|g| g.name == name) {
        return Some(i);
    }
    let spaced = |g: &Group| g.name.contains(' ') && g.name.replace(' ', "_") == name;
    let mut it = groups.iter().enumerate().filter(|(_, g)| spaced(g));
    match (it.next(), it.next()) {
        (Some((i, _)), None) => Some(i),
        _ => None,
    }
}

/// A boundary (or point) physical group: its name and its elements.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Group {
    /// Physical name from `$PhysicalNames`, or the physical tag as a string when unnamed.
    pub name: String,
    /// Dimension of the group's elements: 0 (points), 1 (lines), 2 (triangles
    /// and quadrilaterals, in 3D).
    pub dim: usize,
    /// Its elements, node indices 0-based into `Mesh::coords`.
    pub conn: Cells,
    /// Of the mesh file's group, the elements that use a node no cell uses
    /// (dropped by [`Mesh::drop_unused_nodes`]: they are not on the body),
    /// and, where there are such, all its elements (else 0); the same on
    /// every rank. An option naming a group with such elements is refused
    /// ([`super::distribute::LocalMesh::group_for`]).
    #[serde(default)]
    pub off_body: usize,
    #[serde(default)]
    pub file_len: usize,
}

impl Group {
    /// A group whose elements are all on the body.
    pub fn new(name: impl Into<String>, dim: usize, conn: Cells) -> Group {
        Group {
            name: name.into(),
            dim,
            conn,
            off_body: 0,
            file_len: 0,
        }
    }
    /// A part of this group: `conn`, with the file's counts.
    pub fn part(&self, conn: Cells) -> Group {
        Group {
            name: self.name.clone(),
            dim: self.dim,
            conn,
            off_body: self.off_body,
            file_len: self.file_len,
        }
    }
    pub fn len(&self) -> usize {
        self.conn.len()
    }
    pub fn is_empty(&self) -> bool {
        self.conn.is_empty()
    }
}

/// The body groups (physical groups of the mesh's dimension: Gmsh's
/// Physical Surface in 2D, Physical Volume in 3D) each cell belongs to, as
/// an index per cell into a table of distinct sets of groups (most meshes
/// have one set per body). A cell may be in several groups (Gmsh writes it
/// once per group), or in none.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Bodies {
    /// Per cell, its index in `sets`; empty when no cell is in a body group.
    pub cell_set: Vec<u32>,
    /// The distinct sets of body groups, each the ascending indices of its
    /// groups in the mesh's `groups`; `sets[0]` is the empty set.
    pub sets: Vec<Vec<u32>>,
}

impl Bodies {
    /// From `(cell, group)` memberships of a mesh of `ncells` cells (in any
    /// order, repeats allowed): the sets in order of their first cell.
    pub fn from_members(ncells: usize, mut members: Vec<(usize, u32)>) -> Bodies {
        if members.is_empty() {
            return Bodies::default();
        }
        members.sort_unstable();
        members.dedup();
        let mut sets: Vec<Vec<u32>> = vec![Vec::new()];
        let mut index: std::collections::HashMap<Vec<u32>, u32> =
            std::collections::HashMap::from([(Vec::new(), 0)]);
        let mut cell_set = vec![0u32; ncells];
        let mut i = 0;
        while i < members.len() {
            let c = members[i].0;
            let mut set = Vec::new();
            while i < members.len() && members[i].0 == c {
                set.push(members[i].1);
                i += 1;
            }
            let next = sets.len() as u32;
            let k = *index.entry(set.clone()).or_insert(next);
            if k == next {
                sets.push(set);
            }
            if let Some(slot) = cell_set.get_mut(c) {
                *slot = k;
            }
        }
        Bodies { cell_set, sets }
    }

    /// The body groups of cell `c` (indices into the mesh's `groups`).
    pub fn of(&self, c: usize) -> &[u32] {
        match self.cell_set.get(c) {
            Some(&k) => &self.sets[k as usize],
            None => &[],
        }
    }
}

/// The material of each cell of a local mesh, once resolved from the
/// options and the body groups (`crate::fem::material::resolve`).
#[derive(Clone, Debug, Default)]
pub struct CellMaterials {
    /// The distinct materials, `list[0]` the global one; empty until
    /// resolved (the element kernels then take the global `-E`, `-nu`).
    pub list: Vec<Material>,
    /// Per local cell, its index in `list`; empty when every cell has the
    /// global material.
    pub of_cell: Vec<u32>,
}

impl CellMaterials {
    /// The index in `list` of cell `c`'s material.
    #[inline]
    pub fn index(&self, c: usize) -> usize {
        self.of_cell.get(c).map_or(0, |&k| k as usize)
    }
}

/// A serial mesh. Equality compares the geometry, the node tags, the
/// groups and the cells' body groups, not the element tags (formats number
/// elements differently).
#[derive(Clone, Debug)]
pub struct Mesh {
    /// 2 (triangles, quadrilaterals) or 3 (tetrahedra, hexahedra).
    pub dim: usize,
    /// Node coordinates, `dim` values per node.
    pub coords: Vec<f64>,
    /// The node's tag in the input file (1-based numbering for generated meshes).
    pub node_tags: Vec<u64>,
    /// Cells: `dim + 1` (simplex) or `2^dim` (Q1) node indices per cell.
    pub cells: Cells,
    /// The cell's element tag in the input file (1-based numbering for generated meshes).
    pub cell_tags: Vec<u64>,
    /// Physical groups of dimension < `dim`, and those of dimension `dim`
    /// by name only (no elements: the cells are the body), so that an
    /// option naming one is told its dimension.
    pub groups: Vec<Group>,
    /// The groups of dimension `dim` of each cell.
    pub bodies: Bodies,
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
            && self.bodies == o.bodies
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
        self.cells.len()
    }
    pub fn group(&self, name: &str) -> Option<&Group> {
        self.groups.get(find_group(&self.groups, name)?)
    }

    /// The kind of cell `c`.
    pub fn cell_kind(&self, c: usize) -> CellKind {
        CellKind::of(self.dim, self.cells.get(c).len()).expect("a cell of a known kind")
    }

    /// "triangles", "quadrilaterals", or "triangles and quadrilaterals";
    /// "tetrahedra, pyramids and hexahedra" (kinds by node count).
    pub fn cell_kinds_label(&self) -> String {
        kinds_label(self.dim, &self.cells)
    }

    /// Drops the nodes that no cell uses (Gmsh keeps geometry points) and
    /// renumbers cells and groups. Group elements that touch a dropped node are
    /// dropped too (a point group on an unused geometry point, say).
    pub fn drop_unused_nodes(&mut self) {
        let n = self.num_nodes();
        let mut used = vec![false; n];
        for &v in self.cells.nodes() {
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
        for v in self.cells.nodes_mut() {
            *v = new_index[*v];
        }
        for g in &mut self.groups {
            let mut conn = Cells::new();
            let mut e2 = Vec::new();
            for e in &g.conn {
                if e.iter().all(|&v| used[v]) {
                    e2.clear();
                    e2.extend(e.iter().map(|&v| new_index[v]));
                    conn.push(&e2);
                }
            }
            if conn.len() < g.conn.len() {
                g.off_body = g.conn.len() - conn.len();
                g.file_len = g.conn.len();
            }
            g.conn = conn;
        }
    }

    /// Cell volume (area in 2D) of cell `c`, signed: positive when the cell is
    /// positively oriented. Q1 cells: the integral of the Jacobian determinant
    /// by the element's Gauss rule (exact).
    pub fn signed_measure(&self, c: usize) -> f64 {
        let d = self.dim;
        let v = self.cells.get(c);
        let x = |i: usize, k: usize| self.coords[v[i] * d + k];
        match v.len() {
            3 if d == 2 => {
                0.5 * ((x(1, 0) - x(0, 0)) * (x(2, 1) - x(0, 1))
                    - (x(2, 0) - x(0, 0)) * (x(1, 1) - x(0, 1)))
            }
            4 if d == 3 => {
                let a = [x(1, 0) - x(0, 0), x(1, 1) - x(0, 1), x(1, 2) - x(0, 2)];
                let b = [x(2, 0) - x(0, 0), x(2, 1) - x(0, 1), x(2, 2) - x(0, 2)];
                let c3 = [x(3, 0) - x(0, 0), x(3, 1) - x(0, 1), x(3, 2) - x(0, 2)];
                (a[0] * (b[1] * c3[2] - b[2] * c3[1]) - a[1] * (b[0] * c3[2] - b[2] * c3[0])
                    + a[2] * (b[0] * c3[1] - b[1] * c3[0]))
                    / 6.0
            }
            _ => {
                let pts: Vec<f64> = v
                    .iter()
                    .flat_map(|&n| self.coords[n * d..(n + 1) * d].iter().copied())
                    .collect();
                crate::element::jacobians(d, &pts)
                    .iter()
                    .map(|(w, j)| w * j)
                    .sum()
            }
        }
    }

    /// The smallest and the largest Jacobian determinant of cell `c` over
    /// its Gauss points (a simplex: its constant Jacobian, `d!` times its
    /// signed measure). A cell is valid when both have the same sign; a
    /// sign change inside a Q1 cell means it is folded (non-convex, or its
    /// nodes listed in the wrong order).
    pub fn jacobian_range(&self, c: usize) -> (f64, f64) {
        let d = self.dim;
        let v = self.cells.get(c);
        if v.len() == d + 1 {
            let j = self.signed_measure(c) * if d == 2 { 2.0 } else { 6.0 };
            return (j, j);
        }
        let pts: Vec<f64> = v
            .iter()
            .flat_map(|&n| self.coords[n * d..(n + 1) * d].iter().copied())
            .collect();
        crate::element::jacobians(d, &pts)
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &(_, j)| {
                (lo.min(j), hi.max(j))
            })
    }
}

/// The kinds of cells in `cells` (dimension `dim`), as words for a summary.
pub fn kinds_label(dim: usize, cells: &Cells) -> String {
    let mut kinds: Vec<CellKind> = Vec::new();
    if let Some(k) = cells.stride() {
        kinds.extend(CellKind::of(dim, k));
    } else {
        for c in cells {
            if let Some(k) = CellKind::of(dim, c.len()) {
                if !kinds.contains(&k) {
                    kinds.push(k);
                }
            }
        }
        kinds.sort_by_key(|k| k.nodes());
    }
    let names: Vec<&str> = kinds.iter().map(|k| k.plural()).collect();
    match names.len() {
        0 => if dim == 2 { "triangles" } else { "tetrahedra" }.to_string(),
        1 => names[0].to_string(),
        n => format!("{} and {}", names[..n - 1].join(", "), names[n - 1]),
    }
}

/// A mesh this large (nodes to generate, or MB to read) takes seconds:
/// its phase says so at once.
const LARGE_MESH_NODES: f64 = 2e5;
const LARGE_FILE_MB: f64 = 20.0;

/// The built-in mesh `name` at element size `h` (Q1 cells with `q1`).
fn generate(name: &str, h: f64, q1: bool) -> Result<Mesh, Error> {
    Ok(match (name, q1) {
        ("hertz2d", false) => hertz2d::generate(h)?,
        ("hertz2d", true) => hertz2d::generate_quad(h)?,
        ("block3d", false) => block3d::generate(h)?,
        ("block3d", true) => block3d::generate_hex(h)?,
        (other, _) => return bad(format!("option -mesh_generate: unknown mesh '{other}'")),
    })
}

/// Reads or generates the mesh `-mesh` or `-mesh_generate` names (rank 0),
/// and refuses a mesh with inverted, folded or degenerate cells, naming the
/// first.
pub fn load(source: &MeshSource) -> Result<Mesh, Error> {
    let mut mesh = match source {
        MeshSource::File(path) => {
            let mb = std::fs::metadata(path).map_or(0.0, |m| m.len() as f64 / 1e6);
            progress::phase(mb > LARGE_FILE_MB, || {
                format!("reading {path} ({mb:.0} MB)")
            });
            let bytes = std::fs::read(path).map_err(|e| {
                let hint = crate::options::files::path_hint("-mesh", path);
                MeshError(format!("option -mesh: cannot read '{path}': {e}{hint}"))
            })?;
            gmsh::parse_gmsh(&bytes, path)?
        }
        MeshSource::Generate { name, h, q1 } => {
            let nodes = match (name.as_str(), q1) {
                ("hertz2d", false) => hertz2d::expected_nodes(*h),
                // Quadrilaterals: about 1.5 times the triangles' nodes.
                ("hertz2d", true) => 1.5 * hertz2d::expected_nodes(*h),
                _ => block3d::expected_nodes(*h),
            };
            progress::phase(nodes > LARGE_MESH_NODES, || {
                format!("generating {name} (h = {h}): about {nodes:.3e} nodes")
            });
            generate(name, *h, *q1)?
        }
    };
    // A large file's mesh renumbered for locality first (every later pass
    // is faster for it, the check below included); `origin[c]`: cell c's
    // position in the file, so that an error names the first bad cell.
    let origin = match source {
        MeshSource::File(_) if mesh.num_nodes() >= locality::MIN_NODES => {
            Some(locality::renumber(&mut mesh))
        }
        _ => None,
    };
    check_cells(&mesh, origin.as_deref())?;
    if let MeshSource::File(_) = source {
        check_repeated(&mesh)?;
    }
    Ok(mesh)
}

/// A file's cell given twice (the same nodes under two element tags: two
/// meshes of one part concatenated, a converter's copy) would count its
/// stiffness twice, silently: refused, naming both. (Gmsh's own copies of
/// an element in two physical groups, MSH 2.2, share a tag and are read
/// once.) Cells are grouped by their lowest node (a counting sort), and
/// compared within a group: linear in the cells.
fn check_repeated(mesh: &Mesh) -> Result<(), Error> {
    let n = mesh.num_cells();
    let low = |c: usize| mesh.cells.get(c).iter().copied().min().unwrap_or(0);
    let mut start = vec![0usize; mesh.num_nodes() + 1];
    for c in 0..n {
        start[low(c) + 1] += 1;
    }
    for v in 0..mesh.num_nodes() {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut by_low = vec![0usize; n];
    for c in 0..n {
        by_low[fill[low(c)]] = c;
        fill[low(c)] += 1;
    }
    // A cell's nodes sorted, padded (cells have at most 8 nodes).
    let key = |c: usize| {
        let mut k = [usize::MAX; 8];
        for (slot, &v) in k.iter_mut().zip(mesh.cells.get(c)) {
            *slot = v;
        }
        k.sort_unstable();
        k
    };
    let mut keys: Vec<([usize; 8], usize)> = Vec::new();
    for v in 0..mesh.num_nodes() {
        keys.clear();
        keys.extend(by_low[start[v]..start[v + 1]].iter().map(|&c| (key(c), c)));
        keys.sort_unstable();
        if let Some(w) = keys.windows(2).find(|w| w[0].0 == w[1].0) {
            let (a, b) = (w[0].1, w[1].1);
            return bad(format!(
                "mesh: elements {} and {} have the same nodes ({}): a cell given twice would count its stiffness twice; remove one",
                mesh.cell_tag(a).min(mesh.cell_tag(b)),
                mesh.cell_tag(a).max(mesh.cell_tag(b)),
                cell_nodes(mesh, a)
            ));
        }
    }
    Ok(())
}

/// The file's node tags of cell `c`, for messages: "12 7 40".
fn cell_nodes(mesh: &Mesh, c: usize) -> String {
    let tags: Vec<String> = mesh
        .cells
        .get(c)
        .iter()
        .map(|&v| mesh.node_tags[v].to_string())
        .collect();
    tags.join(" ")
}

/// Cells of both orientations: the minority ones are inverted (a broken
/// mesh, e.g. a node moved across an edge); names the first of them in the
/// file's order (`origin`, as [`load`] made it). The orientation is the
/// sign of the Jacobian determinant, constant on a simplex, taken at every
/// Gauss point of a Q1 cell: a sign change inside one means it is folded.
fn check_cells(mesh: &Mesh, origin: Option<&[usize]>) -> Result<(), Error> {
    let ranges: Vec<(f64, f64)> = (0..mesh.num_cells())
        .map(|c| mesh.jacobian_range(c))
        .collect();
    let positive = ranges.iter().filter(|r| r.0 > 0.0).count();
    let negative_is_minority = 2 * positive >= mesh.num_cells();
    let mixed = positive != 0 && positive != mesh.num_cells();
    let is_inverted =
        |lo: f64, hi: f64| (lo > 0.0 || hi < 0.0) && ((hi < 0.0) == negative_is_minority);
    let fails = |&(lo, hi): &(f64, f64)| {
        let finite = lo.is_finite() && hi.is_finite();
        !finite
            || lo == 0.0
            || hi == 0.0
            || (lo < 0.0 && hi > 0.0)
            || (is_inverted(lo, hi) && mixed)
    };
    let first = (0..ranges.len())
        .filter(|&c| fails(&ranges[c]))
        .min_by_key(|&c| origin.map_or(c, |o| o[c]));
    let Some(c) = first else {
        return Ok(());
    };
    let (lo, hi) = ranges[c];
    let nodes = cell_nodes(mesh, c);
    let finite = lo.is_finite() && hi.is_finite();
    if finite && lo < 0.0 && hi > 0.0 {
        return bad(format!(
            "mesh: element {} (nodes {nodes}) is folded: its Jacobian determinant changes sign inside it (from {lo:.3e} to {hi:.3e} at its Gauss points; a {} with its nodes out of order, or not convex)",
            mesh.cell_tag(c),
            mesh.cell_kind(c).name()
        ));
    }
    if finite && is_inverted(lo, hi) && mixed {
        return bad(format!(
            "mesh: element {} (nodes {nodes}) is inverted: its orientation is opposite to that of the other {} cells",
            mesh.cell_tag(c),
            if negative_is_minority { positive } else { mesh.num_cells() - positive }
        ));
    }
    bad(format!(
        "mesh: element {} (nodes {nodes}) is degenerate: zero {}",
        mesh.cell_tag(c),
        match (mesh.dim, lo == hi) {
            (2, true) => "area",
            (3, true) => "volume",
            _ => "Jacobian determinant at a Gauss point",
        }
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_by_name_spaces_as_underscores() {
        let g = |name: &str| Group::new(name.to_string(), 1, Cells::new());
        let groups = [
            g("Bottom Face"),
            g("a b"),
            g("a_b"),
            g("x y"),
            g("x  y"),
            g("x_ y"),
        ];
        assert_eq!(find_group(&groups, "Bottom Face"), Some(0));
        assert_eq!(find_group(&groups, "Bottom_Face"), Some(0));
        assert_eq!(find_group(&groups, "bottom_face"), None);
        assert_eq!(find_group(&groups, "a_b"), Some(2), "the exact name first");
        assert_eq!(find_group(&groups, "x_y"), Some(3));
        assert_eq!(
            find_group(&groups, "x__y"),
            None,
            "'x  y' and 'x_ y': ambiguous"
        );
        assert_eq!(find_group(&groups, "Face"), None);
    }

    #[test]
    fn cells_uniform_then_mixed() {
        let mut c = Cells::new();
        assert!(c.is_empty() && c.stride().is_none());
        c.push(&[0, 1, 2]);
        c.push(&[2, 1, 3]);
        assert_eq!(c.stride(), Some(3));
        assert_eq!(c.len(), 2);
        c.push(&[3, 4, 5, 6]);
        assert_eq!(c.stride(), None);
        assert_eq!(c.len(), 3);
        assert_eq!(c.get(1), &[2, 1, 3]);
        assert_eq!(c.get(2), &[3, 4, 5, 6]);
        c.push(&[7, 8, 9]);
        assert_eq!(c.max_nodes(), 4);
        let all: Vec<&[usize]> = c.iter().collect();
        assert_eq!(all.len(), 4);
        assert_eq!(all[3], &[7, 8, 9]);
        let wire = postcard::to_allocvec(&c).unwrap();
        assert_eq!(postcard::from_bytes::<Cells>(&wire).unwrap(), c);
        // Equality is on the elements, not the storage.
        let a = Cells::uniform(vec![0, 1, 2, 3, 4, 5], 3);
        let b: Cells = vec![vec![0, 1, 2], vec![3, 4, 5]].into_iter().collect();
        assert_eq!(a, b);
        assert_ne!(a, Cells::uniform(vec![0, 1, 2, 3, 4, 5], 2));
    }

    #[test]
    fn kinds_and_labels() {
        assert_eq!(CellKind::of(2, 4), Some(CellKind::Quadrilateral));
        assert_eq!(CellKind::of(3, 4), Some(CellKind::Tetrahedron));
        assert_eq!(CellKind::of(3, 6), Some(CellKind::Prism));
        assert_eq!(CellKind::of(2, 6), None);
        let all: Cells = [4, 5, 6, 8].iter().map(|&k| (0..k).collect()).collect();
        assert_eq!(
            kinds_label(3, &all),
            "tetrahedra, pyramids, prisms and hexahedra"
        );
        let mixed: Cells = vec![vec![0, 1, 2, 3], vec![0, 1, 2]].into_iter().collect();
        assert_eq!(kinds_label(2, &mixed), "triangles and quadrilaterals");
        assert_eq!(kinds_label(3, &Cells::uniform(vec![0; 8], 8)), "hexahedra");
    }

    #[test]
    fn q1_measures_and_jacobians() {
        // A trapezoid (area 1.5) and a unit cube, then the trapezoid's nodes
        // listed clockwise (negative) and in a crossed order (folded).
        let mut m = Mesh {
            dim: 2,
            coords: vec![0.0, 0.0, 2.0, 0.0, 1.0, 1.0, 0.0, 1.0],
            node_tags: vec![1, 2, 3, 4],
            cells: Cells::uniform(vec![0, 1, 2, 3], 4),
            cell_tags: vec![1],
            groups: vec![],
            bodies: Bodies::default(),
        };
        assert!((m.signed_measure(0) - 1.5).abs() < 1e-14);
        let (lo, hi) = m.jacobian_range(0);
        assert!(lo > 0.0 && hi > lo);
        m.cells = Cells::uniform(vec![0, 3, 2, 1], 4);
        assert!((m.signed_measure(0) + 1.5).abs() < 1e-14);
        m.cells = Cells::uniform(vec![0, 1, 3, 2], 4);
        let (lo, hi) = m.jacobian_range(0);
        assert!(lo < 0.0 && hi > 0.0, "{lo} {hi}");
        let cube = Mesh {
            dim: 3,
            coords: vec![
                0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0., 0., 0., 1., 1., 0., 1., 1., 1., 1.,
                0., 1., 1.,
            ],
            node_tags: (1..=8).collect(),
            cells: Cells::uniform((0..8).collect(), 8),
            cell_tags: vec![1],
            groups: vec![],
            bodies: Bodies::default(),
        };
        assert!((cube.signed_measure(0) - 1.0).abs() < 1e-14);
        let (lo, hi) = cube.jacobian_range(0);
        assert!((lo - 0.125).abs() < 1e-15 && (hi - 0.125).abs() < 1e-15);
    }
}
