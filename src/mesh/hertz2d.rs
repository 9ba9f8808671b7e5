//! Built-in mesh of the paper's 2D Hertz scene (section 7.1), selected with
//! `-mesh_generate hertz2d -mesh_h H`.
//!
//! The body is a quarter of the cross-section of a cylinder of radius
//! `R = 8` centred at `(0, 8)`: the region `x >= 0`, `y <= 8` inside the
//! circle. Its boundary is the quarter arc from `(0, 0)` to `(8, 8)` (group
//! `contact`, where the body touches the plane `y = 0` near `(0, 0)`), the
//! edge `x = 0` from `(0, 8)` to `(0, 0)` (group `symmetry`) and the edge
//! `y = 8` from `(8, 8)` to `(0, 8)` (group `top`). These are the names of
//! `meshes/hertz.geo`.
//!
//! Construction: concentric rings around the centre at radii `k R / N`,
//! `k = 0..=N`, with ring spacing `R / N ~ (sqrt(3) / 2) h`, the height of an
//! equilateral triangle of side `h`; ring `k` carries `s_k + 1` nodes equally
//! spaced in angle over the quarter, `s_k = round(r_k (pi / 2) / h)` (at least
//! 1), from the `(0, 0)` direction (straight down) to the `(8, 8)` direction.
//! Consecutive rings are stitched by a zipper that adds, at each step, the
//! triangle whose new diagonal is the shorter one. The mesh has about
//! `2 / (sqrt(3) h^2)` nodes per unit area, that of equilateral triangles of
//! side `h`, as Gmsh 4.8 with `meshes/hertz.geo` at the same `h` (272, 6001
//! and 36674 nodes for `h` = 0.5, 0.1, 0.04, against Gmsh's 280, 6002 and
//! 36839); the minimum angle is about 36 degrees at every size. The arc nodes are on the circle,
//! the nodes of the straight edges exactly on them, and every triangle is
//! counter-clockwise. The node numbering is ring by ring, from the centre
//! outwards.

use super::{Cells, Group, Mesh, MeshError};
use std::f64::consts::FRAC_PI_2;

/// Radius of the cylinder; its centre is `(0, R)`.
const R: f64 = 8.0;

/// The largest mesh the generator builds (nodes).
const MAX_NODES: f64 = 50.0e6;

/// Ring spacing over element size: the height of an equilateral triangle.
const RING_FACTOR: f64 = 0.866_025_403_784_438_6; // sqrt(3) / 2

/// About how many nodes [`generate`] makes at element size `h` (interior
/// density plus the boundary).
pub fn expected_nodes(h: f64) -> f64 {
    std::f64::consts::PI * R * R / (2.0 * 3f64.sqrt() * h * h) + 16.0 / h
}

/// Quarter-cylinder mesh of the paper's Hertz scene with target element size `h`.
pub fn generate(h: f64) -> Result<Mesh, MeshError> {
    if !h.is_finite() || h <= 0.0 {
        return Err(MeshError(format!(
            "option -mesh_h: {h} is not a positive finite element size (-mesh_generate hertz2d)"
        )));
    }
    // Node count estimate (interior density plus the boundary), checked
    // before any allocation; an underflowing `h * h` gives infinity.
    let estimate = expected_nodes(h);
    if estimate > MAX_NODES {
        return Err(MeshError(format!(
            "option -mesh_h: {h} is too small for -mesh_generate hertz2d \
             (about {estimate:.2e} nodes, the limit is {MAX_NODES:.0e})"
        )));
    }

    let n_rings = ((R / (RING_FACTOR * h)).ceil() as usize).max(1);
    let radius = |k: usize| (k as f64 * R) / n_rings as f64;
    // Segments of ring k > 0 (ring 0 is the centre, one node).
    let segments: Vec<usize> = (0..=n_rings)
        .map(|k| {
            if k == 0 {
                0
            } else {
                ((radius(k) * FRAC_PI_2 / h).round() as usize).max(1)
            }
        })
        .collect();
    // First node index of each ring.
    let mut first = Vec::with_capacity(n_rings + 2);
    first.push(0usize);
    for &s in &segments {
        first.push(first.last().unwrap() + s + 1);
    }
    let n_nodes = first[n_rings + 1];

    let mut coords = Vec::with_capacity(2 * n_nodes);
    for (k, &s) in segments.iter().enumerate() {
        let r = radius(k);
        if s == 0 {
            coords.extend_from_slice(&[0.0, R]);
            continue;
        }
        // End nodes set exactly: (0, R - r) on x = 0 and (r, R) on y = R.
        coords.extend_from_slice(&[0.0, R - r]);
        let dt = FRAC_PI_2 / s as f64;
        for j in 1..s {
            let (sin, cos) = (j as f64 * dt).sin_cos();
            coords.extend_from_slice(&[r * sin, R - r * cos]);
        }
        coords.extend_from_slice(&[r, R]);
    }
    debug_assert_eq!(coords.len(), 2 * n_nodes);

    let n_cells: usize = segments.windows(2).map(|w| w[0] + w[1]).sum();
    let mut cells = Vec::with_capacity(3 * n_cells);
    let dist2 = |a: usize, b: usize| {
        let dx = coords[2 * a] - coords[2 * b];
        let dy = coords[2 * a + 1] - coords[2 * b + 1];
        dx * dx + dy * dy
    };
    for k in 0..n_rings {
        // Zipper between the inner ring a[0..=p] and the outer ring b[0..=q].
        let (a0, p) = (first[k], segments[k]);
        let (b0, q) = (first[k + 1], segments[k + 1]);
        let (mut i, mut j) = (0, 0);
        while i < p || j < q {
            let advance_outer =
                i == p || (j < q && dist2(a0 + i, b0 + j + 1) <= dist2(a0 + i + 1, b0 + j));
            if advance_outer {
                cells.extend_from_slice(&[a0 + i, b0 + j, b0 + j + 1]);
                j += 1;
            } else {
                cells.extend_from_slice(&[a0 + i, b0 + j, a0 + i + 1]);
                i += 1;
            }
        }
    }
    debug_assert_eq!(cells.len(), 3 * n_cells);

    // Boundary groups, oriented along the counter-clockwise boundary
    // (as in meshes/hertz.geo): arc (0,0) -> (8,8), top (8,8) -> (0,8),
    // symmetry (0,8) -> (0,0).
    let outer = first[n_rings];
    let contact: Vec<usize> = (0..segments[n_rings])
        .flat_map(|j| [outer + j, outer + j + 1])
        .collect();
    // Last node of ring k: on y = R (the centre for k = 0).
    let top: Vec<usize> = (0..n_rings)
        .rev()
        .flat_map(|k| [first[k + 2] - 1, first[k + 1] - 1])
        .collect();
    let symmetry: Vec<usize> = (0..n_rings)
        .flat_map(|k| [first[k], first[k + 1]])
        .collect();
    let line =
        |name: &str, conn: Vec<usize>| Group::new(name.to_string(), 1, Cells::uniform(conn, 2));

    Ok(Mesh {
        dim: 2,
        coords,
        node_tags: (1..=n_nodes as u64).collect(),
        cell_tags: (1..=(cells.len() / 3) as u64).collect(),
        cells: Cells::uniform(cells, 3),
        groups: vec![
            line("contact", contact),
            line("symmetry", symmetry),
            line("top", top),
        ],
        bodies: Default::default(),
    })
}

/// Side of the O-grid's inner square over the radius (see [`generate_quad`]).
const SQUARE: f64 = 0.45;

/// Q1 quadrilateral mesh of the same quarter cylinder: an O-grid of three
/// structured blocks, selected with `-mesh_generate hertz2d -mesh_element
/// quad -mesh_h H`.
///
/// The square `[0, a] x [R - a, R]` (`a = 0.45 R`, one corner at the centre
/// `(0, R)`) carries `n x n` cells, `n = ceil((pi R / 4) / h)`. Two curved
/// blocks of `n x m` cells join its lower and right edges to the two halves
/// of the arc, by linear blending between the square's edge and the arc
/// (`m = round(r / h)`, `r` the mean distance from the square to the arc,
/// `((R - a) + (R - sqrt(2) a)) / 2`). The arc gets `2 n + 1` nodes equally
/// spaced in angle, about `h` apart, like [`generate`]'s; the quadrilaterals
/// in the square are smaller (`a / n`, about `0.57 h`), so the mesh has
/// about 1.5 times the nodes of [`generate`] at the same `h`. Every cell is
/// counter-clockwise and convex; the groups have the names and
/// orientations of [`generate`]'s. Nodes are numbered square first (row by
/// row from the centre down), then the lower block, then the right one.
pub fn generate_quad(h: f64) -> Result<Mesh, MeshError> {
    if !h.is_finite() || h <= 0.0 {
        return Err(MeshError(format!(
            "option -mesh_h: {h} is not a positive finite element size (-mesh_generate hertz2d)"
        )));
    }
    let a = SQUARE * R;
    let reach = 0.5 * ((R - a) + (R - std::f64::consts::SQRT_2 * a));
    let nf = (R * std::f64::consts::FRAC_PI_4 / h).ceil().max(1.0);
    let mf = (reach / h).round().max(1.0);
    let estimate = (nf + 1.0) * (nf + 1.0) + 2.0 * mf * (nf + 1.0);
    if estimate > MAX_NODES {
        return Err(MeshError(format!(
            "option -mesh_h: {h} is too small for -mesh_generate hertz2d \
             (about {estimate:.2e} nodes, the limit is {MAX_NODES:.0e})"
        )));
    }
    let q = QuadBlocks {
        n: nf as usize,
        m: mf as usize,
    };
    let (n, m) = (q.n, q.m);
    let (sq, lower, right) = (
        |i, j| q.sq(i, j),
        |k, j| q.lower(k, j),
        |k, i| q.right(k, i),
    );
    let n_nodes = q.num_nodes();
    let coords = q.coords(a);
    let cells = q.cells();
    // Boundary groups along the counter-clockwise boundary, as generate's.
    let path = |nodes: Vec<usize>| -> Cells {
        Cells::uniform(nodes.windows(2).flatten().copied().collect(), 2)
    };
    let contact: Vec<usize> = (0..=n)
        .map(|j| lower(m, j))
        .chain((0..n).rev().map(|i| right(m, i)))
        .collect();
    let top: Vec<usize> = (1..=m)
        .rev()
        .map(|k| right(k, 0))
        .chain((0..=n).rev().map(|j| sq(0, j)))
        .collect();
    let symmetry: Vec<usize> = (0..=n)
        .map(|i| sq(i, 0))
        .chain((1..=m).map(|k| lower(k, 0)))
        .collect();
    let line = |name: &str, conn: Cells| Group::new(name.to_string(), 1, conn);
    Ok(Mesh {
        dim: 2,
        coords,
        node_tags: (1..=n_nodes as u64).collect(),
        cell_tags: (1..=(cells.len() / 4) as u64).collect(),
        cells: Cells::uniform(cells, 4),
        groups: vec![
            line("contact", path(contact)),
            line("symmetry", path(symmetry)),
            line("top", path(top)),
        ],
        bodies: Default::default(),
    })
}

/// The node numbering of [`generate_quad`]'s mesh: the `n x n` square,
/// then the lower block of `n x m` cells, then the right one.
struct QuadBlocks {
    n: usize,
    m: usize,
}

impl QuadBlocks {
    /// Square node (i, j): i rows down from the centre, j columns right.
    fn sq(&self, i: usize, j: usize) -> usize {
        i * (self.n + 1) + j
    }

    /// Lower block row k >= 1 (k = 0 is the square's last row), column j.
    fn lower(&self, k: usize, j: usize) -> usize {
        let n = self.n;
        if k == 0 {
            self.sq(n, j)
        } else {
            (n + 1) * (n + 1) + (k - 1) * (n + 1) + j
        }
    }

    /// Right block column k >= 1 (k = 0 is the square's last column), row
    /// i; its row n is the lower block's column n (the diagonal).
    fn right(&self, k: usize, i: usize) -> usize {
        let (n, m) = (self.n, self.m);
        if k == 0 {
            self.sq(i, n)
        } else if i == n {
            self.lower(k, n)
        } else {
            (n + 1) * (n + 1) + m * (n + 1) + (k - 1) * n + i
        }
    }

    fn num_nodes(&self) -> usize {
        let (n, m) = (self.n, self.m);
        (n + 1) * (n + 1) + m * (n + 1) + m * n
    }

    /// The coordinates of every node, for the square's side `a`.
    fn coords(&self, a: f64) -> Vec<f64> {
        let (n, m) = (self.n, self.m);
        let arc = |theta: f64| {
            let (sin, cos) = theta.sin_cos();
            [R * sin, R - R * cos]
        };
        let blend =
            |p: [f64; 2], q: [f64; 2], u: f64| [p[0] + u * (q[0] - p[0]), p[1] + u * (q[1] - p[1])];
        let frac = |i: usize, n: usize| i as f64 / n as f64;
        let sq_x = |i: usize, j: usize| [a * frac(j, n), R - a * frac(i, n)];
        let quarter = std::f64::consts::FRAC_PI_4;
        // Exact on the straight edges and at the arc's ends.
        let lower_x = |k: usize, j: usize| {
            let q = if j == 0 {
                [0.0, 0.0]
            } else {
                arc(quarter * frac(j, n))
            };
            let mut p = if k == m {
                q
            } else {
                blend(sq_x(n, j), q, frac(k, m))
            };
            if j == 0 {
                p[0] = 0.0;
            }
            p
        };
        let right_x = |k: usize, i: usize| {
            let q = if i == 0 {
                [R, R]
            } else {
                arc(FRAC_PI_2 - quarter * frac(i, n))
            };
            let mut p = if k == m {
                q
            } else {
                blend(sq_x(i, n), q, frac(k, m))
            };
            if i == 0 {
                p[1] = R;
            }
            p
        };
        let mut coords = vec![0.0; 2 * self.num_nodes()];
        let mut set = |v: usize, p: [f64; 2]| {
            coords[2 * v] = p[0];
            coords[2 * v + 1] = p[1];
        };
        for i in 0..=n {
            for j in 0..=n {
                set(self.sq(i, j), sq_x(i, j));
            }
        }
        for k in 1..=m {
            for j in 0..=n {
                set(self.lower(k, j), lower_x(k, j));
            }
            for i in 0..n {
                set(self.right(k, i), right_x(k, i));
            }
        }
        coords
    }

    /// The quadrilaterals, 4 nodes each, counter-clockwise.
    fn cells(&self) -> Vec<usize> {
        let (n, m) = (self.n, self.m);
        let (sq, lower, right) = (
            |i, j| self.sq(i, j),
            |k, j| self.lower(k, j),
            |k, i| self.right(k, i),
        );
        let mut cells = Vec::with_capacity(4 * (n * n + 2 * n * m));
        for i in 0..n {
            for j in 0..n {
                cells.extend_from_slice(&[sq(i, j), sq(i + 1, j), sq(i + 1, j + 1), sq(i, j + 1)]);
            }
        }
        for k in 0..m {
            for j in 0..n {
                cells.extend_from_slice(&[
                    lower(k, j),
                    lower(k + 1, j),
                    lower(k + 1, j + 1),
                    lower(k, j + 1),
                ]);
            }
        }
        for k in 0..m {
            for i in 0..n {
                cells.extend_from_slice(&[
                    right(k, i),
                    right(k, i + 1),
                    right(k + 1, i + 1),
                    right(k + 1, i),
                ]);
            }
        }
        cells
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;
    use std::f64::consts::PI;

    fn point(m: &Mesh, v: usize) -> [f64; 2] {
        [m.coords[2 * v], m.coords[2 * v + 1]]
    }

    fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
        (a[0] - b[0]).hypot(a[1] - b[1])
    }

    /// Smallest angle (degrees) of the mesh.
    fn min_angle(m: &Mesh) -> f64 {
        let mut min = 180.0f64;
        for t in m.cells.iter() {
            for c in 0..3 {
                let o = point(m, t[c]);
                let u = point(m, t[(c + 1) % 3]);
                let w = point(m, t[(c + 2) % 3]);
                let (ux, uy, wx, wy) = (u[0] - o[0], u[1] - o[1], w[0] - o[0], w[1] - o[1]);
                let angle = (ux * wy - uy * wx).atan2(ux * wx + uy * wy).abs();
                min = min.min(angle.to_degrees());
            }
        }
        min
    }

    fn group_length(m: &Mesh, name: &str) -> f64 {
        let g = m.group(name).unwrap();
        g.conn
            .iter()
            .map(|e| dist(point(m, e[0]), point(m, e[1])))
            .sum()
    }

    /// Exact area of the meshed polygon: the quarter disk minus the circular
    /// segments cut off by the arc's chords.
    fn polygon_area(m: &Mesh) -> f64 {
        let segments: f64 = m
            .group("contact")
            .unwrap()
            .conn
            .iter()
            .map(|e| {
                let c = dist(point(m, e[0]), point(m, e[1]));
                let theta = 2.0 * (c / (2.0 * R)).asin();
                0.5 * R * R * (theta - theta.sin())
            })
            .sum();
        0.25 * PI * R * R - segments
    }

    const SIZES: [f64; 7] = [20.0, 8.0, 2.0, 0.5, 0.37, 0.1, 0.04];

    #[test]
    fn areas_positive_and_sum_to_the_polygon() {
        for h in SIZES {
            let m = generate(h).unwrap();
            let mut area = 0.0;
            for c in 0..m.num_cells() {
                let a = m.signed_measure(c);
                assert!(a > 0.0, "h = {h}: cell {c} has area {a}");
                area += a;
            }
            let polygon = polygon_area(&m);
            assert!(
                (area - polygon).abs() < 1e-10 * polygon,
                "h = {h}: {area} vs {polygon}"
            );
            let disk = 16.0 * PI;
            assert!(area < disk && (disk - area) / disk < h * h, "h = {h}");
        }
    }

    #[test]
    fn min_angle_bound() {
        for h in SIZES {
            let m = generate(h).unwrap();
            let a = min_angle(&m);
            assert!(a > 30.0, "h = {h}: min angle {a}");
        }
    }

    #[test]
    fn boundary_groups() {
        for h in SIZES {
            let m = generate(h).unwrap();
            assert_eq!(m.groups.len(), 3);
            for g in &m.groups {
                assert_eq!(g.dim, 1);
                assert!(!g.is_empty());
            }
            let arc = group_length(&m, "contact");
            assert!(
                arc <= 4.0 * PI && arc > 4.0 * PI * (1.0 - h * h / 8.0),
                "h = {h}: {arc}"
            );
            assert!((group_length(&m, "symmetry") - 8.0).abs() < 1e-12);
            assert!((group_length(&m, "top") - 8.0).abs() < 1e-12);

            // Nodes of each group on their curve.
            for e in m.group("contact").unwrap().conn.nodes() {
                let p = point(&m, *e);
                assert!((dist(p, [0.0, R]) - R).abs() < 1e-13, "h = {h}: {p:?}");
                assert!(p[0] >= 0.0 && p[1] <= R);
            }
            for e in m.group("symmetry").unwrap().conn.nodes() {
                assert_eq!(point(&m, *e)[0], 0.0);
            }
            for e in m.group("top").unwrap().conn.nodes() {
                assert_eq!(point(&m, *e)[1], R);
            }

            // Boundary edges (used by one triangle), as sorted node pairs,
            // with their counter-clockwise orientation.
            let mut count: HashMap<(usize, usize), (usize, (usize, usize))> = HashMap::new();
            for t in m.cells.iter() {
                for c in 0..3 {
                    let (a, b) = (t[c], t[(c + 1) % 3]);
                    let e = count.entry((a.min(b), a.max(b))).or_insert((0, (a, b)));
                    e.0 += 1;
                }
            }
            assert!(count.values().all(|&(n, _)| n <= 2), "h = {h}");
            let boundary: HashMap<(usize, usize), (usize, usize)> = count
                .iter()
                .filter(|(_, &(n, _))| n == 1)
                .map(|(&k, &(_, o))| (k, o))
                .collect();
            let mut seen = HashMap::new();
            for g in &m.groups {
                for e in g.conn.iter() {
                    let key = (e[0].min(e[1]), e[0].max(e[1]));
                    let orient = boundary.get(&key);
                    assert!(
                        orient.is_some(),
                        "h = {h}: {} edge {e:?} is not on the boundary",
                        g.name
                    );
                    assert_eq!(
                        orient,
                        Some(&(e[0], e[1])),
                        "h = {h}: {} edge orientation",
                        g.name
                    );
                    assert!(
                        seen.insert(key, &g.name).is_none(),
                        "h = {h}: edge {key:?} twice"
                    );
                }
            }
            assert_eq!(
                seen.len(),
                boundary.len(),
                "h = {h}: boundary edge without a group"
            );

            // Corners in both adjacent groups.
            let has = |name: &str, p: [f64; 2]| {
                m.group(name)
                    .unwrap()
                    .conn
                    .nodes()
                    .iter()
                    .any(|&v| point(&m, v) == p)
            };
            assert!(has("contact", [0.0, 0.0]) && has("symmetry", [0.0, 0.0]));
            assert!(has("symmetry", [0.0, R]) && has("top", [0.0, R]));
            assert!(has("top", [R, R]) && has("contact", [R, R]));
        }
    }

    #[test]
    fn node_count_and_numbering() {
        for h in SIZES {
            let m = generate(h).unwrap();
            let n = m.num_nodes();
            assert_eq!(m.node_tags, (1..=n as u64).collect::<Vec<_>>());
            assert!(m.cells.nodes().iter().all(|&v| v < n));
            // Every node in a cell.
            let mut used = vec![false; n];
            m.cells.nodes().iter().for_each(|&v| used[v] = true);
            assert!(used.iter().all(|&u| u));
            // Euler: V - E + F = 1 for a disk, E = (3F + boundary edges) / 2.
            let nb: usize = m.groups.iter().map(|g| g.len()).sum();
            assert_eq!(2 * n, 2 + nb + m.num_cells());
            if h <= 0.5 {
                let interior = 2.0 * 16.0 * PI / (3f64.sqrt() * h * h);
                let ratio = n as f64 / interior;
                assert!(ratio > 1.0 && ratio < 1.0 + 0.5 * h, "h = {h}: {n} nodes");
            }
        }
        let coarse = generate(100.0).unwrap();
        assert_eq!((coarse.num_nodes(), coarse.num_cells()), (3, 1));
    }

    #[test]
    fn quad_mesh_is_valid() {
        for h in SIZES {
            let m = generate_quad(h).unwrap();
            let n = m.num_nodes();
            assert_eq!(m.cells.stride(), Some(4));
            assert_eq!(m.node_tags, (1..=n as u64).collect::<Vec<_>>());
            // Convex and counter-clockwise: det J > 0 at the Gauss points
            // and at the corners (the cross products of the edges).
            let mut area = 0.0;
            for (c, q) in m.cells.iter().enumerate() {
                let (lo, _) = m.jacobian_range(c);
                assert!(lo > 0.0, "h = {h}: cell {c}");
                for i in 0..4 {
                    let (o, u, w) = (
                        point(&m, q[i]),
                        point(&m, q[(i + 1) % 4]),
                        point(&m, q[(i + 3) % 4]),
                    );
                    let cross = (u[0] - o[0]) * (w[1] - o[1]) - (u[1] - o[1]) * (w[0] - o[0]);
                    assert!(cross > 0.0, "h = {h}: cell {c} corner {i}");
                }
                area += m.signed_measure(c);
            }
            let outer = m.group("contact").unwrap();
            let polygon = polygon_area(&m);
            assert!(
                (area - polygon).abs() < 1e-10 * polygon,
                "h = {h}: {area} vs {polygon}"
            );
            // Arc nodes on the circle, equally spaced in angle, about h apart.
            let arc: Vec<[f64; 2]> = outer.conn.iter().map(|e| point(&m, e[0])).collect();
            for p in &arc {
                assert!((dist(*p, [0.0, R]) - R).abs() < 1e-13);
            }
            let l0 = dist(arc[0], arc[1]);
            assert!(arc
                .windows(2)
                .all(|w| (dist(w[0], w[1]) - l0).abs() < 1e-12));
            assert!(
                l0 <= h * 1.0001 || outer.len() <= 2,
                "h = {h}: arc spacing {l0}"
            );
            // Boundary edges (used by one quadrilateral) are the groups'
            // edges, oriented counter-clockwise; the groups' lengths.
            let mut count: HashMap<(usize, usize), (usize, (usize, usize))> = HashMap::new();
            for q in &m.cells {
                for c in 0..4 {
                    let (a, b) = (q[c], q[(c + 1) % 4]);
                    let e = count.entry((a.min(b), a.max(b))).or_insert((0, (a, b)));
                    e.0 += 1;
                }
            }
            assert!(count.values().all(|&(k, _)| k <= 2), "h = {h}");
            let boundary: HashMap<(usize, usize), (usize, usize)> = count
                .iter()
                .filter(|(_, &(k, _))| k == 1)
                .map(|(&k, &(_, o))| (k, o))
                .collect();
            let mut seen = 0;
            for g in &m.groups {
                for e in &g.conn {
                    let key = (e[0].min(e[1]), e[0].max(e[1]));
                    assert_eq!(
                        boundary.get(&key),
                        Some(&(e[0], e[1])),
                        "h = {h}: {} edge {e:?}",
                        g.name
                    );
                    seen += 1;
                }
            }
            assert_eq!(seen, boundary.len(), "h = {h}");
            assert!((group_length(&m, "symmetry") - 8.0).abs() < 1e-12);
            assert!((group_length(&m, "top") - 8.0).abs() < 1e-12);
            for &v in m.group("symmetry").unwrap().conn.nodes() {
                assert_eq!(point(&m, v)[0], 0.0);
            }
            for &v in m.group("top").unwrap().conn.nodes() {
                assert_eq!(point(&m, v)[1], R);
            }
            // Euler for a disk: V - E + F = 1.
            let edges = count.len();
            assert_eq!(n + m.num_cells(), 1 + edges, "h = {h}");
            let used: std::collections::HashSet<usize> = m.cells.nodes().iter().copied().collect();
            assert_eq!(used.len(), n);
        }
        assert_eq!(generate_quad(0.3).unwrap(), generate_quad(0.3).unwrap());
        assert!(generate_quad(1e-5).unwrap_err().0.contains("-mesh_h"));
    }

    #[test]
    fn deterministic() {
        assert_eq!(generate(0.3).unwrap(), generate(0.3).unwrap());
    }

    #[test]
    fn bad_sizes() {
        for h in [
            0.0,
            -1.0,
            f64::NAN,
            f64::INFINITY,
            1e-5,
            1e-300,
            f64::MIN_POSITIVE,
        ] {
            let e = generate(h).unwrap_err();
            assert!(e.0.contains("-mesh_h") && !e.0.contains('\n'), "{e}");
        }
    }
}
