//! A read mesh renumbered for memory locality.
//!
//! A Gmsh file numbers its nodes by entity and its volume nodes in the
//! mesher's insertion order, and lists its cells in yet another order: on a
//! 446k-node tetrahedral block (`gmsh -3 -setnumber h 0.015
//! meshes/block3d.geo`) the nodes of one tetrahedron span half the numbering
//! (median 235,640 apart) and consecutive cells jump 50,619 nodes. Every
//! pass that follows a cell to its nodes (the orientation check, the nodal
//! graph, the parts, the assembly) then waits on memory for each node. The
//! nodes are renumbered along a space-filling curve (Morton order of the
//! coordinates on the bounding box) and the cells sorted by their first
//! node in that order: neighbours in space become neighbours in memory.
//!
//! Nothing a user sees depends on the internal numbering: nodes and cells
//! keep their file tags (the CSV is ordered by tag, the VTU carries them),
//! and the parts and orderings are made after this.

use super::{Cells, Mesh};

/// Files of fewer nodes keep their numbering: their arrays stay in cache
/// (block3d_17887, 17,887 nodes: partition phase 0.02-0.05 s either way),
/// and MUMPS' orderings of the renumbered shipped meshes took -0.8% to +3.1%
/// more flops (block3d_17887 on 2 ranks: 5.213e10 -> 5.376e10), so their
/// results stay the same to the bit. A 60k-node file gains already (2
/// ranks: partition phase 0.13-0.15 -> 0.08-0.11 s, assembly 0.39-0.41 ->
/// 0.32-0.35 s).
pub const MIN_NODES: usize = 50_000;

/// Morton (Z-order) key of each point, its coordinates quantized on the
/// bounding box: 32 bits per axis in 2D, 21 in 3D.
fn morton_keys(coords: &[f64], dim: usize) -> Vec<u64> {
    let bits = if dim == 2 { 32 } else { 21 };
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in coords.chunks_exact(dim) {
        for k in 0..dim {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let cells = ((1u64 << bits) - 1) as f64;
    let scale: Vec<f64> = (0..dim)
        .map(|k| {
            let w = hi[k] - lo[k];
            if w > 0.0 {
                cells / w
            } else {
                0.0
            }
        })
        .collect();
    coords
        .chunks_exact(dim)
        .map(|p| {
            let mut q = [0u64; 3];
            for k in 0..dim {
                q[k] = (((p[k] - lo[k]) * scale[k]) as u64).min(cells as u64);
            }
            let mut key = 0u64;
            for b in (0..bits).rev() {
                for qk in &q[..dim] {
                    key = (key << 1) | ((qk >> b) & 1);
                }
            }
            key
        })
        .collect()
}

/// Renumbers the nodes of `mesh` in Morton order and sorts its cells by
/// their smallest new node number (ties in file order); groups, tags and
/// bodies follow. Returns each cell's former position.
pub fn renumber(mesh: &mut Mesh) -> Vec<usize> {
    let (n, d) = (mesh.num_nodes(), mesh.dim);
    let nc = mesh.num_cells();
    if n < 2 || nc == 0 {
        return (0..nc).collect();
    }
    let keys = morton_keys(&mesh.coords, d);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_unstable_by_key(|&i| (keys[i], i));
    drop(keys);
    let mut new_of = vec![0usize; n];
    for (k, &i) in order.iter().enumerate() {
        new_of[i] = k;
    }
    let mut coords = vec![0.0; n * d];
    for (k, &i) in order.iter().enumerate() {
        coords[k * d..(k + 1) * d].copy_from_slice(&mesh.coords[i * d..(i + 1) * d]);
    }
    mesh.coords = coords;
    if mesh.node_tags.len() == n {
        mesh.node_tags = order.iter().map(|&i| mesh.node_tags[i]).collect();
    }
    drop(order);
    // The cells, by their first node in the new numbering (a counting
    // sort: stable, so ties stay in file order).
    let first: Vec<usize> = (0..nc)
        .map(|c| {
            mesh.cells
                .get(c)
                .iter()
                .map(|&v| new_of[v])
                .min()
                .unwrap_or(0)
        })
        .collect();
    let mut start = vec![0usize; n + 1];
    for &f in &first {
        start[f + 1] += 1;
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut origin = vec![0usize; nc];
    for (c, &f) in first.iter().enumerate() {
        origin[start[f]] = c;
        start[f] += 1;
    }
    drop((first, start));
    let cells = match mesh.cells.stride() {
        Some(k) => {
            let mut nodes = Vec::with_capacity(nc * k);
            for &c in &origin {
                nodes.extend(mesh.cells.get(c).iter().map(|&v| new_of[v]));
            }
            Cells::uniform(nodes, k)
        }
        None => {
            let mut cells = Cells::new();
            let mut buf = Vec::new();
            for &c in &origin {
                buf.clear();
                buf.extend(mesh.cells.get(c).iter().map(|&v| new_of[v]));
                cells.push(&buf);
            }
            cells
        }
    };
    mesh.cells = cells;
    // The tags were the cells' positions when the file gave none.
    mesh.cell_tags = origin.iter().map(|&c| mesh.cell_tag(c)).collect();
    if mesh.bodies.cell_set.len() == nc {
        let set = &mesh.bodies.cell_set;
        mesh.bodies.cell_set = origin.iter().map(|&c| set[c]).collect();
    }
    for g in &mut mesh.groups {
        for v in g.conn.nodes_mut() {
            *v = new_of[*v];
        }
    }
    origin
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Bodies, Group};

    #[test]
    fn morton_keys_follow_the_z_curve() {
        // The unit square's corners, x the leading bit: (0,0) (0,1) (1,0)
        // (1,1); then a point of each quadrant's corner at 1/4 (the
        // curve visits a quadrant whole before the next).
        let c = [1.0, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.25, 0.25];
        let k = morton_keys(&c, 2);
        let mut order: Vec<usize> = (0..5).collect();
        order.sort_by_key(|&i| k[i]);
        assert_eq!(order, vec![3, 4, 1, 2, 0]);
        // A flat 3D point set (zero width along z) still orders.
        let flat = [0.0, 0.0, 5.0, 1.0, 1.0, 5.0];
        let k3 = morton_keys(&flat, 3);
        assert!(k3[0] < k3[1]);
    }

    #[test]
    fn renumbering_keeps_the_mesh() {
        // Two triangles over four nodes listed out of spatial order, a
        // boundary line, and a body group on the second cell.
        let mut mesh = Mesh {
            dim: 2,
            coords: vec![1.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0],
            node_tags: vec![10, 20, 30, 40],
            cells: Cells::uniform(vec![1, 2, 0, 1, 0, 3], 3),
            cell_tags: Vec::new(),
            groups: vec![Group::new("bottom", 1, Cells::uniform(vec![1, 2], 2))],
            bodies: Bodies {
                cell_set: vec![0, 1],
                sets: vec![vec![], vec![0]],
            },
        };
        let before: Vec<(u64, Vec<u64>, Vec<f64>)> = (0..2)
            .map(|c| {
                let v = mesh.cells.get(c);
                (
                    mesh.cell_tag(c),
                    v.iter().map(|&i| mesh.node_tags[i]).collect(),
                    v.iter()
                        .flat_map(|&i| mesh.coords[2 * i..2 * i + 2].to_vec())
                        .collect(),
                )
            })
            .collect();
        let set_of_tag = |m: &Mesh, tag: u64| {
            let c = (0..m.num_cells()).find(|&c| m.cell_tag(c) == tag).unwrap();
            m.bodies.cell_set[c]
        };
        assert_eq!(set_of_tag(&mesh, 2), 1);
        let origin = renumber(&mut mesh);
        assert_eq!(origin.len(), 2);
        // Node 20 at (0, 0) comes first.
        assert_eq!(mesh.node_tags[0], 20);
        assert_eq!(&mesh.coords[..2], &[0.0, 0.0]);
        for (tag, tags, xy) in &before {
            let c = (0..2).find(|&c| mesh.cell_tag(c) == *tag).unwrap();
            let v = mesh.cells.get(c);
            let t: Vec<u64> = v.iter().map(|&i| mesh.node_tags[i]).collect();
            let x: Vec<f64> = v
                .iter()
                .flat_map(|&i| mesh.coords[2 * i..2 * i + 2].to_vec())
                .collect();
            assert_eq!((&t, &x), (tags, xy));
        }
        assert_eq!(set_of_tag(&mesh, 2), 1);
        assert_eq!(set_of_tag(&mesh, 1), 0);
        let line: Vec<u64> = mesh.groups[0]
            .conn
            .get(0)
            .iter()
            .map(|&i| mesh.node_tags[i])
            .collect();
        assert_eq!(line, vec![20, 30]);
    }
}
