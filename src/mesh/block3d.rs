//! Built-in mesh of the paper's 3D block scene (section 7.2), selected with
//! `-mesh_generate block3d -mesh_h H`.
//!
//! The body is the box `(-0.5, 0.5) x (-1, 1) x (-0.5, 0.5)`. Its top face
//! `z = 0.5` is group `top` (where the displacement `(0, 0, -0.2)` is
//! imposed), its bottom face `z = -0.5` is group `bottom` (the contact
//! surface, pressed onto a rigid half-ball) and the four other faces form
//! group `sides`. These are the names of `meshes/block3d.geo`.
//!
//! Construction: a structured grid of `nx x ny x nz` boxes, `nx = ceil(1 / h)`,
//! `ny = ceil(2 / h)`, `nz = ceil(1 / h)` (with a relative tolerance of `1e-10`,
//! so that `h = 1 / n` gives exactly `n`), so
//! `(nx + 1) (ny + 1) (nz + 1)` nodes. Each box is split into 6 tetrahedra by
//! the Kuhn (Freudenthal) subdivision: one tetrahedron per monotone path of
//! box edges from its lowest corner to its highest one, so all six share the
//! main diagonal. The split is the same in every box, hence conforming: on
//! every box face the diagonal runs from the face's lowest corner to its
//! highest. Every tetrahedron is positively oriented
//! ([`Mesh::signed_measure`] `> 0`) and the boundary triangles (two per box
//! face, along the same diagonal) are faces of the tetrahedra, ordered
//! counter-clockwise seen from outside (outward normal).
//!
//! Node `(i, j, k)` (`x = -0.5 + i / nx`, `y = -1 + 2 j / ny`,
//! `z = -0.5 + k / nz`) has index `i + (nx + 1) (j + (ny + 1) k)`: x varies
//! fastest, z slowest, so the bottom-face nodes come first; node tags are
//! `1..=N` in that order. Boxes are ordered the same way, six consecutive
//! tetrahedra per box. The groups come in the order `top`, `bottom`, `sides`.

use super::{Cells, Group, Mesh, MeshError};

/// The largest mesh the generator builds (nodes).
const MAX_NODES: f64 = 60.0e6;

/// The box: lower corner and edge lengths along x, y, z.
const LOWER: [f64; 3] = [-0.5, -1.0, -0.5];
pub(super) const LENGTH: [f64; 3] = [1.0, 2.0, 1.0];

/// The Kuhn subdivision of the unit cube, corners numbered `a + 2 b + 4 c`
/// for the corner `(a, b, c)`: for each permutation of the axes, the path
/// from corner 0 to corner 7 along those axes. The four vertices of the odd
/// permutations are listed with the last two swapped, so that all six are
/// positively oriented.
pub(super) const KUHN: [[usize; 4]; 6] = [
    [0, 1, 3, 7], // x, y, z (even)
    [0, 1, 7, 5], // x, z, y (odd)
    [0, 2, 7, 3], // y, x, z (odd)
    [0, 2, 6, 7], // y, z, x (even)
    [0, 4, 5, 7], // z, x, y (even)
    [0, 4, 7, 6], // z, y, x (odd)
];

/// Box corner `a + 2 b + 4 c` in Gmsh's hexahedron order.
pub(super) const HEX: [usize; 8] = [0, 1, 3, 2, 4, 5, 7, 6];

/// Number of intervals along an edge of length `length` for element size `h`.
fn intervals(length: f64, h: f64) -> f64 {
    ((length / h) * (1.0 - 1e-10)).ceil().max(1.0)
}

/// How many nodes [`generate`] and [`generate_hex`] make at element size `h`.
pub fn expected_nodes(h: f64) -> f64 {
    LENGTH.iter().map(|&l| intervals(l, h) + 1.0).product()
}

/// The structured grid of `generate` and `generate_hex`: intervals per
/// axis and node coordinates (x fastest, z slowest).
struct Grid {
    dims: [usize; 3],
    coords: Vec<f64>,
}

/// The intervals along x, y, z at element size `h`, or the error that
/// names `-mesh_h` (not positive and finite, or too many nodes: checked in
/// floating point before any allocation, a tiny `h` gives infinity).
pub(super) fn dims(h: f64) -> Result<[usize; 3], MeshError> {
    if !h.is_finite() || h <= 0.0 {
        return Err(MeshError(format!(
            "option -mesh_h: {h} is not a positive finite element size (-mesh_generate block3d)"
        )));
    }
    let nf = LENGTH.map(|l| intervals(l, h));
    let estimate = (nf[0] + 1.0) * (nf[1] + 1.0) * (nf[2] + 1.0);
    if estimate > MAX_NODES {
        return Err(MeshError(format!(
            "option -mesh_h: {h} is too small for -mesh_generate block3d \
             ({:.0} x {:.0} x {:.0} boxes, about {estimate:.2e} nodes, the limit is {MAX_NODES:.0e})",
            nf[0], nf[1], nf[2]
        )));
    }
    Ok(nf.map(|n| n as usize))
}

/// Coordinate `axis` of grid line `i` of `n` intervals (exact on the upper faces).
pub(super) fn coordinate(axis: usize, i: usize, n: usize) -> f64 {
    if i == n {
        LOWER[axis] + LENGTH[axis]
    } else {
        LOWER[axis] + LENGTH[axis] * (i as f64 / n as f64)
    }
}

impl Grid {
    fn new(h: f64) -> Result<Grid, MeshError> {
        let [nx, ny, nz] = dims(h)?;
        let n_nodes = (nx + 1) * (ny + 1) * (nz + 1);
        let mut coords = Vec::with_capacity(3 * n_nodes);
        for k in 0..=nz {
            let z = coordinate(2, k, nz);
            for j in 0..=ny {
                let y = coordinate(1, j, ny);
                for i in 0..=nx {
                    coords.extend_from_slice(&[coordinate(0, i, nx), y, z]);
                }
            }
        }
        debug_assert_eq!(coords.len(), 3 * n_nodes);
        Ok(Grid {
            dims: [nx, ny, nz],
            coords,
        })
    }

    fn node(&self, i: usize, j: usize, k: usize) -> usize {
        let [nx, ny, _] = self.dims;
        i + (nx + 1) * (j + (ny + 1) * k)
    }

    /// The squares of the face `axis = 0` (`upper == false`) or `axis = n`,
    /// as `(c00, c10, c01, c11)`: with (p, q) the two other axes in cyclic
    /// order (`e_p x e_q = e_axis`), corner `cab` is `a` steps along p and
    /// `b` along q from `c00`.
    fn face_squares(&self, axis: usize, upper: bool) -> Vec<[usize; 4]> {
        let dims = self.dims;
        let (p, q) = ((axis + 1) % 3, (axis + 2) % 3);
        let at = |a: usize, b: usize| {
            let mut ijk = [0; 3];
            ijk[axis] = if upper { dims[axis] } else { 0 };
            ijk[p] = a;
            ijk[q] = b;
            self.node(ijk[0], ijk[1], ijk[2])
        };
        let mut out = Vec::with_capacity(dims[p] * dims[q]);
        for b in 0..dims[q] {
            for a in 0..dims[p] {
                out.push([at(a, b), at(a + 1, b), at(a, b + 1), at(a + 1, b + 1)]);
            }
        }
        out
    }

    fn n_nodes(&self) -> usize {
        self.coords.len() / 3
    }
}

/// Tetrahedral mesh of the paper's 3D block (section 7.2) with target element size `h`.
pub fn generate(h: f64) -> Result<Mesh, MeshError> {
    let grid = Grid::new(h)?;
    let [nx, ny, nz] = grid.dims;
    let n_nodes = grid.n_nodes();
    let node = |i: usize, j: usize, k: usize| grid.node(i, j, k);

    // Offsets of the 8 box corners from corner 0, numbered a + 2 b + 4 c.
    let corner: [usize; 8] = std::array::from_fn(|c| node(c & 1, (c >> 1) & 1, c >> 2));
    let mut cells = Vec::with_capacity(24 * nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let v0 = node(i, j, k);
                for t in &KUHN {
                    cells.extend_from_slice(&t.map(|c| v0 + corner[c]));
                }
            }
        }
    }
    debug_assert_eq!(cells.len(), 24 * nx * ny * nz);

    // Boundary triangles: each square of a face of the grid split along
    // c00 - c11 (the Kuhn diagonal) into two triangles oriented by the
    // outward normal.
    let triangles = |faces: &[(usize, bool)]| {
        let mut conn = Vec::new();
        for &(axis, upper) in faces {
            for [c00, c10, c01, c11] in grid.face_squares(axis, upper) {
                if upper {
                    conn.extend_from_slice(&[c00, c10, c11, c00, c11, c01]);
                } else {
                    conn.extend_from_slice(&[c00, c11, c10, c00, c01, c11]);
                }
            }
        }
        conn
    };
    let group =
        |name: &str, conn: Vec<usize>| Group::new(name.to_string(), 2, Cells::uniform(conn, 3));
    let groups = vec![
        group("top", triangles(&[(2, true)])),
        group("bottom", triangles(&[(2, false)])),
        group(
            "sides",
            triangles(&[(0, false), (0, true), (1, false), (1, true)]),
        ),
    ];

    Ok(Mesh {
        dim: 3,
        node_tags: (1..=n_nodes as u64).collect(),
        cell_tags: (1..=(cells.len() / 4) as u64).collect(),
        cells: Cells::uniform(cells, 4),
        coords: grid.coords,
        groups,
        bodies: Default::default(),
    })
}

/// Q1 hexahedral mesh of the same block: the boxes of the grid of
/// [`generate`] (same nodes, same numbering), each one trilinear hexahedron
/// with its corners in Gmsh's order (bottom face counter-clockwise seen
/// from above, then the top face), positively oriented; the boundary
/// groups hold one quadrilateral per box face, ordered counter-clockwise
/// seen from outside. Boxes are ordered x fastest, z slowest.
pub fn generate_hex(h: f64) -> Result<Mesh, MeshError> {
    let grid = Grid::new(h)?;
    let [nx, ny, nz] = grid.dims;
    let n_nodes = grid.n_nodes();
    let corner: [usize; 8] = std::array::from_fn(|c| grid.node(c & 1, (c >> 1) & 1, c >> 2));
    let mut cells = Vec::with_capacity(8 * nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let v0 = grid.node(i, j, k);
                cells.extend(HEX.iter().map(|&c| v0 + corner[c]));
            }
        }
    }
    let quads = |faces: &[(usize, bool)]| {
        let mut conn = Vec::new();
        for &(axis, upper) in faces {
            for [c00, c10, c01, c11] in grid.face_squares(axis, upper) {
                if upper {
                    conn.extend_from_slice(&[c00, c10, c11, c01]);
                } else {
                    conn.extend_from_slice(&[c00, c01, c11, c10]);
                }
            }
        }
        Cells::uniform(conn, 4)
    };
    let group = |name: &str, conn: Cells| Group::new(name.to_string(), 2, conn);
    let groups = vec![
        group("top", quads(&[(2, true)])),
        group("bottom", quads(&[(2, false)])),
        group(
            "sides",
            quads(&[(0, false), (0, true), (1, false), (1, true)]),
        ),
    ];
    Ok(Mesh {
        dim: 3,
        node_tags: (1..=n_nodes as u64).collect(),
        cell_tags: (1..=(nx * ny * nz) as u64).collect(),
        cells: Cells::uniform(cells, 8),
        coords: grid.coords,
        groups,
        bodies: Default::default(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn point(m: &Mesh, v: usize) -> [f64; 3] {
        [m.coords[3 * v], m.coords[3 * v + 1], m.coords[3 * v + 2]]
    }

    fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    /// Area vector (normal times area) of a triangle.
    fn area_vector(m: &Mesh, t: &[usize]) -> [f64; 3] {
        let (a, b, c) = (point(m, t[0]), point(m, t[1]), point(m, t[2]));
        cross(sub(b, a), sub(c, a)).map(|x| 0.5 * x)
    }

    fn norm(a: [f64; 3]) -> f64 {
        (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
    }

    fn sorted(t: &[usize]) -> [usize; 3] {
        let mut s = [t[0], t[1], t[2]];
        s.sort_unstable();
        s
    }

    /// Faces of the tetrahedra (sorted vertices) with the number of
    /// tetrahedra using them and, for the last one, the face oriented
    /// outward from that tetrahedron.
    fn tet_faces(m: &Mesh) -> HashMap<[usize; 3], (usize, [usize; 3])> {
        let mut faces = HashMap::new();
        for t in m.cells.iter() {
            // Faces opposite each vertex, outward for a positive tetrahedron.
            for f in [
                [t[1], t[2], t[3]],
                [t[0], t[3], t[2]],
                [t[0], t[1], t[3]],
                [t[0], t[2], t[1]],
            ] {
                let e = faces.entry(sorted(&f)).or_insert((0, f));
                e.0 += 1;
                e.1 = f;
            }
        }
        faces
    }

    /// Same cyclic order (same orientation) of two triangles.
    fn same_orientation(a: &[usize], b: &[usize]) -> bool {
        (0..3).any(|r| (0..3).all(|i| a[i] == b[(i + r) % 3]))
    }

    const SIZES: [f64; 6] = [100.0, 1.0, 0.5, 0.3, 0.25, 0.1];

    #[test]
    fn volumes_positive_and_sum_to_two() {
        for h in SIZES {
            let m = generate(h).unwrap();
            let mut volume = 0.0;
            for c in 0..m.num_cells() {
                let v = m.signed_measure(c);
                assert!(v > 0.0, "h = {h}: cell {c} has volume {v}");
                volume += v;
            }
            assert!((volume - 2.0).abs() < 1e-12, "h = {h}: volume {volume}");
        }
    }

    #[test]
    fn group_areas_and_normals() {
        for h in SIZES {
            let m = generate(h).unwrap();
            let names: Vec<&str> = m.groups.iter().map(|g| g.name.as_str()).collect();
            assert_eq!(names, ["top", "bottom", "sides"]);
            for (name, area) in [("top", 2.0), ("bottom", 2.0), ("sides", 6.0)] {
                let g = m.group(name).unwrap();
                assert_eq!(g.dim, 2);
                let mut sum = 0.0;
                for t in g.conn.iter() {
                    let a = area_vector(&m, t);
                    let c = [0, 1, 2].map(|i| {
                        (point(&m, t[0])[i] + point(&m, t[1])[i] + point(&m, t[2])[i]) / 3.0
                    });
                    // Outward: the normal points away from the box centre.
                    assert!(
                        a[0] * c[0] + a[1] * c[1] + a[2] * c[2] > 0.0,
                        "h = {h}: {name} triangle {t:?} points inward"
                    );
                    sum += norm(a);
                }
                assert!((sum - area).abs() < 1e-12, "h = {h}: {name} area {sum}");
            }
            for &v in m.group("top").unwrap().conn.nodes() {
                assert_eq!(point(&m, v)[2], 0.5);
            }
            for &v in m.group("bottom").unwrap().conn.nodes() {
                assert_eq!(point(&m, v)[2], -0.5);
            }
            for t in m.group("sides").unwrap().conn.iter() {
                let p = [0, 1, 2].map(|i| point(&m, t[i]));
                let on = |axis: usize, x: f64| p.iter().all(|q| q[axis] == x);
                assert!(
                    on(0, -0.5) || on(0, 0.5) || on(1, -1.0) || on(1, 1.0),
                    "h = {h}: side triangle {p:?}"
                );
            }
        }
    }

    #[test]
    fn boundary_faces_are_the_groups() {
        for h in [100.0, 1.0, 0.5, 0.3, 0.25] {
            let m = generate(h).unwrap();
            let faces = tet_faces(&m);
            // Conformity: a face is shared by one tetrahedron (boundary) or
            // two (interior).
            assert!(faces.values().all(|&(n, _)| n == 1 || n == 2), "h = {h}");
            let boundary: HashMap<[usize; 3], [usize; 3]> = faces
                .iter()
                .filter(|(_, &(n, _))| n == 1)
                .map(|(&k, &(_, f))| (k, f))
                .collect();
            let interior = faces.len() - boundary.len();
            assert_eq!(4 * m.num_cells(), 2 * interior + boundary.len());
            let mut seen: HashMap<[usize; 3], &str> = HashMap::new();
            for g in &m.groups {
                for t in g.conn.iter() {
                    let key = sorted(t);
                    let f = boundary.get(&key);
                    assert!(
                        f.is_some(),
                        "h = {h}: {} triangle {t:?} is not a boundary face",
                        g.name
                    );
                    assert!(
                        same_orientation(t, f.unwrap()),
                        "h = {h}: {} triangle {t:?} is not oriented outward",
                        g.name
                    );
                    assert!(
                        seen.insert(key, &g.name).is_none(),
                        "h = {h}: triangle {t:?} in two groups"
                    );
                }
            }
            assert_eq!(
                seen.len(),
                boundary.len(),
                "h = {h}: boundary face without a group"
            );
        }
    }

    #[test]
    fn conforming_small_grid() {
        // 2 x 3 x 2 boxes: every interior face shared by exactly two
        // tetrahedra, every face on the box surface by exactly one.
        let m = generate(0.6).unwrap();
        assert_eq!(m.num_nodes(), 3 * 5 * 3);
        let faces = tet_faces(&m);
        for (f, &(n, _)) in &faces {
            let p = f.map(|v| point(&m, v));
            let on_surface = (0..3).any(|axis| {
                let (lo, hi) = (LOWER[axis], LOWER[axis] + LENGTH[axis]);
                p.iter().all(|q| q[axis] == lo) || p.iter().all(|q| q[axis] == hi)
            });
            assert_eq!(n, if on_surface { 1 } else { 2 }, "face {p:?}");
        }
        // Euler characteristic of a ball: V - E + F - T = 1.
        let mut edges = std::collections::HashSet::new();
        for t in m.cells.iter() {
            for a in 0..4 {
                for b in a + 1..4 {
                    edges.insert((t[a].min(t[b]), t[a].max(t[b])));
                }
            }
        }
        let chi =
            m.num_nodes() as i64 - edges.len() as i64 + faces.len() as i64 - m.num_cells() as i64;
        assert_eq!(chi, 1);
    }

    #[test]
    fn node_count_and_numbering() {
        for (h, n) in [
            (100.0, [1, 1, 1]),
            (1.0, [1, 2, 1]),
            (0.6, [2, 4, 2]),
            (0.5, [2, 4, 2]),
            (0.3, [4, 7, 4]),
            (0.25, [4, 8, 4]),
            (0.1, [10, 20, 10]),
            (1.0 / 3.0, [3, 6, 3]),
        ] {
            let m = generate(h).unwrap();
            let [nx, ny, nz] = n;
            let nodes = (nx + 1) * (ny + 1) * (nz + 1);
            assert_eq!(m.dim, 3);
            assert_eq!(m.num_nodes(), nodes, "h = {h}");
            assert_eq!(m.num_cells(), 6 * nx * ny * nz, "h = {h}");
            assert_eq!(m.group("top").unwrap().len(), 2 * nx * ny);
            assert_eq!(m.group("bottom").unwrap().len(), 2 * nx * ny);
            assert_eq!(m.group("sides").unwrap().len(), 4 * (ny * nz + nx * nz));
            assert_eq!(m.node_tags, (1..=nodes as u64).collect::<Vec<_>>());
            assert!(m.cells.nodes().iter().all(|&v| v < nodes));
            let mut used = vec![false; nodes];
            m.cells.nodes().iter().for_each(|&v| used[v] = true);
            assert!(used.iter().all(|&u| u), "h = {h}: unused node");
            // Lexicographic: x fastest, then y, then z.
            for k in 0..=nz {
                for j in 0..=ny {
                    for i in 0..=nx {
                        let v = i + (nx + 1) * (j + (ny + 1) * k);
                        let expect = [
                            -0.5 + i as f64 / nx as f64,
                            -1.0 + 2.0 * j as f64 / ny as f64,
                            -0.5 + k as f64 / nz as f64,
                        ];
                        let p = point(&m, v);
                        assert!(
                            (0..3).all(|a| (p[a] - expect[a]).abs() < 1e-15),
                            "h = {h}: node {v} at {p:?}"
                        );
                    }
                }
            }
        }
        // The ~1M-node size (81 x 161 x 81 nodes), without building it.
        assert_eq!(LENGTH.map(|l| intervals(l, 0.0125)), [80.0, 160.0, 80.0]);
        // A size just above 1 / n gives n intervals.
        assert_eq!(intervals(1.0, 0.1 * (1.0 + 1e-12)), 10.0);
        assert_eq!(intervals(1.0, 0.1 * (1.0 - 1e-6)), 11.0);
    }

    #[test]
    fn hex_mesh_is_valid() {
        for h in [100.0, 1.0, 0.5, 0.3, 0.25] {
            let m = generate_hex(h).unwrap();
            let t = generate(h).unwrap();
            assert_eq!(
                (m.coords.clone(), m.node_tags.clone()),
                (t.coords.clone(), t.node_tags.clone())
            );
            assert_eq!(6 * m.num_cells(), t.num_cells());
            let mut volume = 0.0;
            for c in 0..m.num_cells() {
                let (lo, hi) = m.jacobian_range(c);
                assert!(
                    lo > 0.0 && (hi - lo).abs() < 1e-12 * hi,
                    "h = {h}: cell {c}"
                );
                volume += m.signed_measure(c);
            }
            assert!((volume - 2.0).abs() < 1e-12);
            // Faces of the hexahedra (outward for a positive hexahedron);
            // the groups are exactly the faces used once, oriented outward.
            let hex_faces = [
                [0, 3, 2, 1],
                [4, 5, 6, 7],
                [0, 1, 5, 4],
                [1, 2, 6, 5],
                [2, 3, 7, 6],
                [3, 0, 4, 7],
            ];
            let mut faces: HashMap<[usize; 4], (usize, Vec<usize>)> = HashMap::new();
            for c in &m.cells {
                for f in hex_faces {
                    let q: Vec<usize> = f.iter().map(|&i| c[i]).collect();
                    let mut key = [q[0], q[1], q[2], q[3]];
                    key.sort_unstable();
                    let e = faces.entry(key).or_insert((0, q.clone()));
                    e.0 += 1;
                    e.1 = q;
                }
            }
            let boundary: HashMap<[usize; 4], Vec<usize>> = faces
                .iter()
                .filter(|(_, (k, _))| *k == 1)
                .map(|(k, (_, q))| (*k, q.clone()))
                .collect();
            let mut seen = 0;
            for g in &m.groups {
                let mut area = 0.0;
                for q in &g.conn {
                    let mut key = [q[0], q[1], q[2], q[3]];
                    key.sort_unstable();
                    let f = boundary.get(&key).expect("a boundary face");
                    let r = (0..4).find(|&r| f[r] == q[0]).unwrap();
                    assert!(
                        (0..4).all(|i| f[(r + i) % 4] == q[i]),
                        "{} face {q:?} not outward",
                        g.name
                    );
                    area += norm(area_vector(&m, &[q[0], q[1], q[2]]))
                        + norm(area_vector(&m, &[q[0], q[2], q[3]]));
                    seen += 1;
                }
                let want = if g.name == "sides" { 6.0 } else { 2.0 };
                assert!(
                    (area - want).abs() < 1e-12,
                    "h = {h}: {} area {area}",
                    g.name
                );
            }
            assert_eq!(seen, boundary.len());
            for &v in m.group("bottom").unwrap().conn.nodes() {
                assert_eq!(point(&m, v)[2], -0.5);
            }
        }
        assert_eq!(generate_hex(0.3).unwrap(), generate_hex(0.3).unwrap());
        assert!(generate_hex(1e-3).unwrap_err().0.contains("-mesh_h"));
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
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e-3,
            1e-300,
            f64::MIN_POSITIVE,
            5e-324,
        ] {
            let e = generate(h).unwrap_err();
            assert!(e.0.contains("-mesh_h") && !e.0.contains('\n'), "{e}");
        }
    }
}
