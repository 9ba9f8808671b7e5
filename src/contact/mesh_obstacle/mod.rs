//! A rigid obstacle given as a surface mesh, and the signed distance to it.
//!
//! # Input
//! [`MeshObstacle::read`] reads a Gmsh file (MSH 2.2 or 4.1, ASCII) and
//! keeps every element of the surface dimension: 2-node lines for a 2D
//! obstacle, 3-node triangles and 4-node quadrilaterals (each split into
//! two triangles along its first diagonal) for a 3D one; other elements
//! (points, volumes, lines of a 3D file) are skipped.
//! [`MeshObstacle::read_group`] keeps only those of one physical group. In
//! 3D the file may also be an STL file, ASCII or binary (vertices with
//! equal coordinates are one node). A 2D obstacle's nodes must lie in a
//! plane z = constant (z is dropped).
//!
//! # Orientation
//! The element orientation gives the obstacle's outward side (where the
//! body is): in 3D the right-hand rule (Gmsh's, and STL's vertex order),
//! the outward normal of triangle `(a, b, c)` is `(b - a) x (c - a)`; in 2D
//! the outward normal of segment `(a, b)` is `b - a` turned by -90 degrees,
//! `(dy, -dx) / len`, so a counter-clockwise circle is a solid disc and a
//! clockwise one a circular hole. The obstacle occupies the side the
//! normals point away from; a closed surface with inward normals is the
//! outside of a cavity (a seat), which is allowed. The contact set reads a
//! connected part of the surface whose orientation puts most of the
//! body's nodes nearest to it inside the obstacle reversed
//! ([`MeshObstacle::reversed`], by `orient_to_body` in `crate::contact`).
//!
//! # Signed distance
//! [`MeshObstacle::closest`] finds the closest point with an R*-tree
//! (`rstar`) over the elements' bounding boxes and the exact point-segment
//! or point-triangle distance. Its sign comes from the pseudo-normal of the
//! feature the closest point lies on (Baerentzen and Aanaes, IEEE TVCG
//! 2005): the face normal inside a face (a segment's normal inside a
//! segment), the sum of the two face normals on an edge, the
//! angle-weighted sum of the face normals at a vertex (in 2D the sum of the
//! two segment normals). This sign is exact for a closed, consistently
//! oriented surface; on an open one it is right where the closest point
//! is an interior point of the surface.
//!
//! # Validation
//! Reading fails, with one line naming the file and the element or node,
//! on: no element of the surface dimension, a degenerate element (zero
//! length or area), inconsistent orientation (two triangles that traverse
//! their shared edge in the same direction; two segments that share a node
//! as both start or both end), a non-manifold edge (in more than two
//! triangles) or node (in more than two segments). An open boundary (an
//! edge in one triangle, a node in one segment) is allowed by the reader;
//! [`MeshObstacle::require_closed`] rejects it.

mod geom;
mod read;
mod topology;

#[cfg(test)]
mod tests;

use crate::error::{bad, Error};
use geom::{Feature, V3};
use rstar::{RTree, RTreeObject, AABB};
use std::path::Path;

/// The option that names an obstacle's surface file, for messages.
const OPTION: &str = "-obstacle_mesh";

/// The closest point of the obstacle to a query point `x`.
#[derive(Clone, Debug, PartialEq)]
pub struct Closest {
    /// Signed distance from `x` to the surface: positive outside the
    /// obstacle, negative inside it (penetration), 0 on the surface.
    pub gap: f64,
    /// Unit vector (`dim` components): the obstacle's outward direction at
    /// the closest point, reversed. Outside, it points from `x` to the
    /// closest point (the direction in which `x` moves to touch); inside,
    /// from the closest point to `x`; on the surface, the reversed unit
    /// pseudo-normal. The constraint on a displacement `u` of `x` is
    /// `u . normal <= gap`.
    pub normal: Vec<f64>,
    /// The closest point of the surface (`dim` components).
    pub point: Vec<f64>,
    /// The connected part of the surface it lies on (elements that share
    /// a node are in one part), numbered from 0.
    pub component: usize,
}

/// A surface as read: nodes, elements (`dim` corners each: segments in 2D,
/// triangles in 3D) and their names in the file.
#[derive(Clone, Debug)]
pub(crate) struct Surface {
    pub dim: usize,
    /// The file, for messages.
    pub file: String,
    /// Node coordinates (z = 0 in 2D).
    pub coords: Vec<V3>,
    /// Corner nodes; the third is unused in 2D.
    pub elems: Vec<[usize; 3]>,
    /// Each element's number in the file: Gmsh's element tag, or the STL
    /// facet's position from 1.
    pub elem_id: Vec<u64>,
    /// Gmsh's node tags; None for STL (a vertex is named by its coordinates).
    pub node_id: Option<Vec<u64>>,
}

impl Surface {
    /// An element, for messages: "element 12" or "facet 12".
    fn elem_name(&self, e: usize) -> String {
        let id = self.elem_id.get(e).copied().unwrap_or(e as u64 + 1);
        match self.node_id {
            Some(_) => format!("element {id}"),
            None => format!("facet {id}"),
        }
    }

    /// A node, for messages: "node 7" or "vertex (x, y, z)".
    fn node_name(&self, i: usize) -> String {
        match &self.node_id {
            Some(tags) => format!("node {}", tags.get(i).copied().unwrap_or(i as u64 + 1)),
            None => {
                let p = self.coords.get(i).copied().unwrap_or_default();
                format!("vertex ({}, {}, {})", p[0], p[1], p[2])
            }
        }
    }

    /// A one-line bad-input error about this surface.
    fn error<T>(&self, what: impl std::fmt::Display) -> Result<T, Error> {
        bad(format!("option {OPTION}: {}: {what}", self.file))
    }
}

/// One element in the R*-tree: its corners (a segment repeats its second).
#[derive(Clone, Debug)]
struct Prim {
    elem: usize,
    segment: bool,
    p: [V3; 3],
    /// The corners' bounding box (rstar asks for it at every visit).
    envelope: AABB<V3>,
}

impl Prim {
    fn closest(&self, x: &V3) -> (V3, Feature) {
        if self.segment {
            geom::closest_on_segment(x, &self.p[0], &self.p[1])
        } else {
            geom::closest_on_triangle(x, &self.p[0], &self.p[1], &self.p[2])
        }
    }
}

impl RTreeObject for Prim {
    type Envelope = AABB<V3>;
    fn envelope(&self) -> AABB<V3> {
        self.envelope
    }
}

impl rstar::PointDistance for Prim {
    fn distance_2(&self, x: &V3) -> f64 {
        let (q, _) = self.closest(x);
        let d = geom::sub(x, &q);
        geom::dot(&d, &d)
    }
}

/// A rigid obstacle bounded by a surface mesh (see the module doc).
#[derive(Clone, Debug)]
pub struct MeshObstacle {
    surface: Surface,
    /// Unit outward normal of each element.
    face_n: Vec<V3>,
    /// Pseudo-normal of each triangle's edge `k` (corners `k`, `k + 1`).
    edge_n: Vec<[V3; 3]>,
    /// Pseudo-normal of each node.
    vert_n: Vec<V3>,
    /// Open boundary: how many edges (3D) or nodes (2D) lie in a single
    /// element, and a message naming the first.
    open: usize,
    first_open: Option<String>,
    /// Diagonal of the bounding box.
    size: f64,
    /// Farther closest points are not returned.
    search: f64,
    tree: RTree<Prim>,
    /// Each element's connected part, and how many parts.
    component: Vec<u32>,
    components: usize,
}

impl MeshObstacle {
    /// Reads the surface in `path` (Gmsh, or STL in 3D) for a `dim`-D body:
    /// every element of dimension `dim - 1`. Validated as the module doc
    /// says; open surfaces are accepted (see [`MeshObstacle::require_closed`]).
    pub fn read(path: &Path, dim: usize) -> Result<MeshObstacle, Error> {
        MeshObstacle::read_group(path, dim, None)
    }

    /// As [`MeshObstacle::read`], keeping only the elements of the physical
    /// group `group` (its name, or its number) when given; STL has no groups.
    pub fn read_group(path: &Path, dim: usize, group: Option<&str>) -> Result<MeshObstacle, Error> {
        if dim != 2 && dim != 3 {
            return bad(format!(
                "option {OPTION}: {}: a {dim}D body (2 or 3 expected)",
                path.display()
            ));
        }
        let surface = read::read(path, dim, group)?;
        MeshObstacle::from_surface(surface)
    }

    /// The obstacle bounded by elements given in memory: `coords` holds
    /// `dim` coordinates per node, `elems` `dim` node indices (from 0) per
    /// element, oriented as the module doc says; `name` stands for the
    /// file in messages, elements and nodes are numbered from 1 there.
    pub fn from_elements(
        dim: usize,
        coords: &[f64],
        elems: &[usize],
        name: &str,
    ) -> Result<MeshObstacle, Error> {
        if (dim != 2 && dim != 3)
            || !coords.len().is_multiple_of(dim)
            || !elems.len().is_multiple_of(dim)
        {
            return bad(format!(
                "option {OPTION}: {name}: {} coordinates and {} element nodes for a {dim}D obstacle",
                coords.len(),
                elems.len()
            ));
        }
        let n = coords.len() / dim;
        let pts = coords
            .chunks_exact(dim)
            .map(|c| [c[0], c[1], if dim == 3 { c[2] } else { 0.0 }])
            .collect();
        let mut tri = Vec::with_capacity(elems.len() / dim);
        for (e, c) in elems.chunks_exact(dim).enumerate() {
            if let Some(&bad_node) = c.iter().find(|&&i| i >= n) {
                return bad(format!(
                    "option {OPTION}: {name}: element {} refers to node {} of {n}",
                    e + 1,
                    bad_node + 1
                ));
            }
            tri.push([c[0], c[1], if dim == 3 { c[2] } else { c[1] }]);
        }
        MeshObstacle::from_surface(Surface {
            dim,
            file: name.to_string(),
            coords: pts,
            elem_id: (1..=tri.len() as u64).collect(),
            elems: tri,
            node_id: Some((1..=n as u64).collect()),
        })
    }

    fn from_surface(surface: Surface) -> Result<MeshObstacle, Error> {
        let face_n = topology::face_normals(&surface)?;
        let topo = topology::build(&surface, &face_n)?;
        let prims: Vec<Prim> = surface
            .elems
            .iter()
            .enumerate()
            .map(|(e, c)| {
                let p = c.map(|i| surface.coords[i]);
                let [a, b, c] = &p;
                let lo = [0, 1, 2].map(|k| a[k].min(b[k]).min(c[k]));
                let hi = [0, 1, 2].map(|k| a[k].max(b[k]).max(c[k]));
                Prim {
                    elem: e,
                    segment: surface.dim == 2,
                    p,
                    envelope: AABB::from_corners(lo, hi),
                }
            })
            .collect();
        let tree = RTree::bulk_load(prims);
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &surface.coords {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let (component, components) = topology::components(&surface);
        Ok(MeshObstacle {
            component,
            components,
            size: geom::norm(&geom::sub(&hi, &lo)),
            surface,
            face_n,
            edge_n: topo.edge_n,
            vert_n: topo.vert_n,
            open: topo.open,
            first_open: topo.first_open,
            search: f64::INFINITY,
            tree,
        })
    }

    /// The number of connected parts of the surface (see
    /// [`Closest::component`]).
    pub fn components(&self) -> usize {
        self.components
    }

    /// The same surface with the orientation of every element of the parts
    /// `flip[k]` reversed (a segment's ends swapped, a triangle's last two
    /// corners): the obstacle becomes the other side of those parts, a
    /// solid its cavity and a cavity its solid. The search distance is
    /// kept.
    pub fn reversed(self, flip: &[bool]) -> Result<MeshObstacle, Error> {
        let mut surface = self.surface;
        for (e, &k) in surface.elems.iter_mut().zip(&self.component) {
            if flip.get(k as usize).copied().unwrap_or(false) {
                *e = if surface.dim == 2 {
                    [e[1], e[0], e[0]]
                } else {
                    [e[0], e[2], e[1]]
                };
            }
        }
        Ok(MeshObstacle::from_surface(surface)?.with_search_distance(self.search))
    }

    /// The same obstacle, with [`MeshObstacle::closest`] returning None for
    /// points farther than `d >= 0` from the surface, on either side
    /// (treated as open); infinity (the default) returns every point.
    pub fn with_search_distance(mut self, d: f64) -> MeshObstacle {
        self.search = d;
        self
    }

    /// The search distance ([`MeshObstacle::with_search_distance`]).
    pub fn search_distance(&self) -> f64 {
        self.search
    }

    /// The file it was read from (the name given to
    /// [`MeshObstacle::from_elements`]).
    pub fn file(&self) -> &str {
        &self.surface.file
    }

    /// The body's dimension, 2 or 3.
    pub fn dim(&self) -> usize {
        self.surface.dim
    }

    /// The number of elements (segments, or triangles after splitting
    /// quadrilaterals).
    pub fn len(&self) -> usize {
        self.surface.elems.len()
    }

    /// Never true: an empty surface is an error when it is read.
    pub fn is_empty(&self) -> bool {
        self.surface.elems.is_empty()
    }

    /// Whether the surface is closed: every edge in two triangles (3D),
    /// every node in two segments (2D).
    pub fn is_closed(&self) -> bool {
        self.open == 0
    }

    /// An error naming the first open edge (3D) or node (2D), and how many
    /// there are, unless the surface is closed.
    pub fn require_closed(&self) -> Result<(), Error> {
        match &self.first_open {
            None => Ok(()),
            Some(first) => self.surface.error(format_args!(
                "the surface is open: {first} ({} open {} in all); the signed distance needs a closed surface",
                self.open,
                if self.surface.dim == 3 { "edges" } else { "ends" },
            )),
        }
    }

    /// The signed volume (3D) or area (2D) the surface encloses: positive
    /// for a solid with outward normals, negative for a cavity (inward
    /// normals). Meaningful for a closed surface only.
    pub fn enclosed_volume(&self) -> f64 {
        let s = &self.surface;
        let mut v = 0.0;
        for c in &s.elems {
            let [a, b, d] = c.map(|i| s.coords[i]);
            v += if s.dim == 3 {
                geom::dot(&a, &geom::cross(&b, &d)) / 6.0
            } else {
                // Outward (dy, -dx): counter-clockwise is positive.
                (a[0] * b[1] - b[0] * a[1]) / 2.0
            };
        }
        v
    }

    /// The closest point of the surface to `x` (`dim` coordinates), its
    /// signed distance and the normal (see [`Closest`]); None when it is
    /// farther than the search distance ([`MeshObstacle::with_search_distance`]).
    pub fn closest(&self, x: &[f64]) -> Option<Closest> {
        let dim = self.surface.dim;
        let q = [
            x.first().copied().unwrap_or(0.0),
            x.get(1).copied().unwrap_or(0.0),
            if dim == 3 {
                x.get(2).copied().unwrap_or(0.0)
            } else {
                0.0
            },
        ];
        // Nothing within the search distance: no nearest-neighbour search
        // (deep inside or far outside, every box is about as near).
        if self.search.is_finite()
            && self
                .tree
                .locate_within_distance(q, self.search * self.search)
                .next()
                .is_none()
        {
            return None;
        }
        let prim = self.tree.nearest_neighbor(&q)?;
        let (p, feature) = prim.closest(&q);
        let diff = geom::sub(&q, &p);
        let dist = geom::norm(&diff);
        if dist > self.search {
            return None;
        }
        let pn = self.pseudo_normal(prim.elem, feature);
        let (gap, normal) = if dist <= 1e-12 * self.size {
            (0.0, geom::scale(&geom::unit(&pn), -1.0))
        } else if geom::dot(&diff, &pn) >= 0.0 {
            (dist, geom::scale(&diff, -1.0 / dist))
        } else {
            (-dist, geom::scale(&diff, 1.0 / dist))
        };
        Some(Closest {
            gap,
            normal: normal[..dim].to_vec(),
            point: p[..dim].to_vec(),
            component: self.component[prim.elem] as usize,
        })
    }

    /// The pseudo-normal of a feature of element `e` (not of unit length).
    fn pseudo_normal(&self, e: usize, feature: Feature) -> V3 {
        match feature {
            Feature::Face => self.face_n[e],
            Feature::Edge(k) => self.edge_n[e][k],
            Feature::Vertex(k) => self.vert_n[self.surface.elems[e][k]],
        }
    }
}
