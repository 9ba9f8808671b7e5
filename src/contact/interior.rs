//! Contact surfaces lie on a body's boundary: a surface group holding
//! facets inside a body (each a face of two cells, e.g. a line embedded in
//! a Gmsh surface, or the interface of two parts meshed with shared nodes)
//! is refused. A rigid obstacle's candidates there would sit inside the
//! material, and the normal of a pair's facet there has no outside to
//! point to.

use crate::comm::allreduce_sum_vec;
use crate::error::Error;
use crate::mesh::distribute::LocalMesh;
use mpi::traits::*;

/// This rank's count of the facets of `name` that are faces of two or more
/// cells (each counted on the rank owning its lowest-numbered node, which
/// holds every cell through that node), and the smallest file tag among
/// their nodes (`u64::MAX` for none).
fn inside(mesh: &LocalMesh, name: &str) -> (usize, u64) {
    let Some(group) = mesh.group(name) else {
        return (0, u64::MAX);
    };
    if group.dim + 1 != mesh.dim {
        return (0, u64::MAX); // (not of facets: refused where it is read)
    }
    // The cells through each facet's first node (a slot per such node:
    // one pass over the cells, an array look-up per cell node).
    let mut slot = vec![u32::MAX; mesh.node_global.len()];
    let mut cells_of: Vec<Vec<usize>> = Vec::new();
    for e in &group.conn {
        if let Some(&v) = e.first() {
            if slot[v] == u32::MAX {
                slot[v] = cells_of.len() as u32;
                cells_of.push(Vec::new());
            }
        }
    }
    for (c, cell) in mesh.cells.iter().enumerate() {
        for &v in cell {
            if let Some(list) = cells_of.get_mut(slot[v] as usize) {
                list.push(c);
            }
        }
    }
    let (mut count, mut tag) = (0, u64::MAX);
    for e in &group.conn {
        let Some(&low) = e.iter().min_by_key(|&&v| mesh.node_global[v]) else {
            continue;
        };
        if !mesh.is_owned(low) {
            continue;
        }
        let holders = cells_of[slot[e[0]] as usize]
            .iter()
            .filter(|&&c| e.iter().all(|v| mesh.cells.get(c).contains(v)))
            .count();
        if holders >= 2 {
            count += 1;
            tag = tag.min(
                e.iter()
                    .map(|&v| mesh.node_tag[v])
                    .min()
                    .unwrap_or(u64::MAX),
            );
        }
    }
    (count, tag)
}

/// Refuses (exit 2, on every rank) a surface of `names` (of `option`) with
/// facets inside a body. Collective.
pub fn refuse_inside<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    option: &str,
    names: &[&str],
) -> Result<(), Error> {
    let found: Vec<(usize, u64)> = names.iter().map(|n| inside(mesh, n)).collect();
    let counts: Vec<f64> = found.iter().map(|&(c, _)| c as f64).collect();
    let counts = allreduce_sum_vec(world, &counts);
    let mut tags = vec![0u64; names.len()];
    let mine: Vec<u64> = found.iter().map(|&(_, t)| t).collect();
    world.all_reduce_into(
        &mine[..],
        &mut tags[..],
        mpi::collective::SystemOperation::min(),
    );
    for (k, name) in names.iter().enumerate() {
        let count = counts[k] as usize;
        if count > 0 {
            return Err(Error::BadInput(format!(
                "option {option}: surface '{name}' has {count} facet{} inside the body (each a face of two cells, or of a cell the mesh gives twice; the first at node {}): a contact surface lies on the boundary of its body",
                if count == 1 { "" } else { "s" },
                tags[k]
            )));
        }
    }
    Ok(())
}
