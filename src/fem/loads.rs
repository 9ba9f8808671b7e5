//! The external loads beyond surface tractions: a body force per unit
//! volume, a pressure along the facet normals of a boundary group; and the
//! unmodified stiffness applied to a displacement at chosen rows, for the
//! reaction forces of the Dirichlet groups.

use super::{cell_stiffness, element, traction_load, Kernels};
use crate::error::{bad, Error};
use crate::mesh::distribute::LocalMesh;
use crate::options::Settings;
use std::collections::HashMap;

/// The load vector's owned entries: tractions, pressures and the body force.
/// `lumped_mass` is `int phi_a` of each owned node, so that a constant body
/// force b gives `b int phi_a` to node a, exactly.
pub fn external_load(
    mesh: &LocalMesh,
    settings: &Settings,
    lumped_mass: &[f64],
) -> Result<Vec<f64>, Error> {
    let d = mesh.dim;
    let mut f = traction_load(mesh, &settings.traction)?;
    pressure_load(mesh, settings, &mut f)?;
    if let Some(b) = &settings.body_force {
        if b.len() != d {
            return bad(format!(
                "option -body_force (or -gravity): {} components given, the mesh is {d}D",
                b.len()
            ));
        }
        for (a, m) in lumped_mass.iter().enumerate() {
            for c in 0..d {
                f[a * d + c] += m * b[c];
            }
        }
        if let Some(g) = &settings.materials.gravity {
            density_load(mesh, settings, g, &mut f)?;
        }
    }
    Ok(f)
}

/// Adds to `f` the weight of the cells whose density is not the global one
/// (`-density_NAME`): `(rho_cell - rho) g int phi_a` to each owned vertex
/// a, on top of the global density's share in the body force.
fn density_load(
    mesh: &LocalMesh,
    settings: &Settings,
    g: &[f64],
    f: &mut [f64],
) -> Result<(), Error> {
    let d = mesh.dim;
    let rho = settings.materials.global.density;
    let list = &mesh.materials.list;
    if list.iter().all(|m| m.density == rho) || g.len() != d {
        return Ok(());
    }
    let kernels = Kernels::new(settings, mesh);
    let nmax = d * mesh.cells.max_nodes();
    let (mut ke, mut lumped) = (vec![0.0; nmax * nmax], [0.0; 8]);
    for c in 0..mesh.cells.len() {
        let extra = list[mesh.materials.index(c)].density - rho;
        let cell = mesh.cells.get(c);
        if extra == 0.0 || !cell.iter().any(|&v| mesh.is_owned(v)) {
            continue;
        }
        // The integral of each vertex's shape function over the cell.
        let measure = cell_stiffness(mesh, c, &kernels, &mut ke, &mut lumped)?;
        if cell.len() == d + 1 {
            lumped[..cell.len()].fill(measure / cell.len() as f64);
        }
        for (&a, share) in cell.iter().zip(lumped) {
            if mesh.is_owned(a) {
                for k in 0..d {
                    f[a * d + k] += share * extra * g[k];
                }
            }
        }
    }
    Ok(())
}

/// The unit normal of a facet (2 points in 2D, 3 or 4 in 3D), not oriented.
fn facet_normal(pts: &[&[f64]]) -> Vec<f64> {
    let sub = |a: &[f64], b: &[f64]| -> Vec<f64> { a.iter().zip(b).map(|(x, y)| x - y).collect() };
    let n = if pts[0].len() == 2 {
        let t = sub(pts[1], pts[0]);
        vec![t[1], -t[0]]
    } else {
        // A triangle: (p1 - p0) x (p2 - p0); a quadrilateral: its diagonals.
        let (u, v) = if pts.len() == 4 {
            (sub(pts[2], pts[0]), sub(pts[3], pts[1]))
        } else {
            (sub(pts[1], pts[0]), sub(pts[2], pts[0]))
        };
        vec![
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let len = n.iter().map(|v| v * v).sum::<f64>().sqrt();
    n.iter().map(|v| v / len).collect()
}

fn centroid<'a>(dim: usize, pts: impl ExactSizeIterator<Item = &'a [f64]>) -> Vec<f64> {
    let k = pts.len() as f64;
    let mut c = vec![0.0; dim];
    for p in pts {
        for (ci, pi) in c.iter_mut().zip(p) {
            *ci += pi / k;
        }
    }
    c
}

/// The local cells around each local node (every cell of an owned node).
pub fn cells_around(mesh: &LocalMesh) -> HashMap<usize, Vec<usize>> {
    let mut cells_of: HashMap<usize, Vec<usize>> = HashMap::new();
    for (c, cell) in mesh.cells.iter().enumerate() {
        for &v in cell {
            cells_of.entry(v).or_default().push(c);
        }
    }
    cells_of
}

/// The cell that facet `e` (local nodes) bounds, from [`cells_around`].
pub fn facet_cell(
    mesh: &LocalMesh,
    cells_of: &HashMap<usize, Vec<usize>>,
    e: &[usize],
) -> Option<usize> {
    cells_of.get(e.first()?).and_then(|cs| {
        cs.iter()
            .copied()
            .find(|&c| e.iter().all(|v| mesh.cells.get(c).contains(v)))
    })
}

/// The unit normal of the facet with vertices `pts`, outward of `cell`
/// (away from its centroid).
pub fn outward_normal(mesh: &LocalMesh, pts: &[&[f64]], cell: usize) -> Vec<f64> {
    let d = mesh.dim;
    let mut nu = facet_normal(pts);
    let fc = centroid(d, pts.iter().copied());
    let cc = centroid(d, mesh.cells.get(cell).iter().map(|&v| mesh.x(v)));
    if nu
        .iter()
        .zip(fc.iter().zip(&cc))
        .map(|(n, (a, b))| n * (a - b))
        .sum::<f64>()
        < 0.0
    {
        nu.iter_mut().for_each(|v| *v = -*v);
    }
    nu
}

/// Adds the pressures `-pressure_NAME P` to `f`: on each facet of the group
/// the force `-P nu |F|` (nu the body's outward normal there, taken away
/// from the cell the facet bounds), shared among its vertices like a traction.
fn pressure_load(mesh: &LocalMesh, settings: &Settings, f: &mut [f64]) -> Result<(), Error> {
    if settings.pressure.is_empty() {
        return Ok(());
    }
    let d = mesh.dim;
    let cells_of = cells_around(mesh);
    for p in &settings.pressure {
        let option = format!("-pressure_{}", p.group);
        let group = mesh.group_for(&option, &p.group, d - 1..=d - 1, "a pressure")?;
        let mut weights = Vec::with_capacity(4);
        for e in &group.conn {
            if !e.iter().any(|&v| mesh.is_owned(v)) {
                continue;
            }
            let Some(cell) = facet_cell(mesh, &cells_of, e) else {
                return bad(format!(
                    "option {option}: a facet of group '{}' (nodes {}) bounds no cell of the mesh",
                    p.group,
                    e.iter()
                        .map(|&v| mesh.node_tag[v].to_string())
                        .collect::<Vec<_>>()
                        .join(" ")
                ));
            };
            let pts: Vec<&[f64]> = e.iter().map(|&v| mesh.x(v)).collect();
            let nu = outward_normal(mesh, &pts, cell);
            element::facet_weights(&pts, &mut weights);
            for (&v, &share) in e.iter().zip(&weights) {
                if mesh.is_owned(v) {
                    for c in 0..d {
                        f[v * d + c] -= share * p.pressure * nu[c];
                    }
                }
            }
        }
    }
    Ok(())
}

/// `(K u)_i` at the owned dofs i where `wanted[i]`, with K the stiffness
/// before any Dirichlet elimination, element by element; `u_local` holds
/// the displacement at every local node (owned and ghost).
pub fn stiffness_rows(
    mesh: &LocalMesh,
    settings: &Settings,
    u_local: &[f64],
    wanted: &[bool],
) -> Result<Vec<f64>, Error> {
    let d = mesh.dim;
    let mut out = vec![0.0; wanted.len()];
    let kernels = Kernels::new(settings, mesh);
    let nmax = d * mesh.cells.max_nodes();
    let (mut ke, mut lumped) = (vec![0.0; nmax * nmax], [0.0; 8]);
    let wants = |v: usize| mesh.is_owned(v) && (0..d).any(|c| wanted[v * d + c]);
    for c in 0..mesh.cells.len() {
        let cell = mesh.cells.get(c);
        if !cell.iter().any(|&v| wants(v)) {
            continue;
        }
        cell_stiffness(mesh, c, &kernels, &mut ke, &mut lumped)?;
        let nloc = d * cell.len();
        for (ia, &a) in cell.iter().enumerate() {
            for ca in (0..d).filter(|&ca| mesh.is_owned(a) && wanted[a * d + ca]) {
                let row = &ke[(ia * d + ca) * nloc..(ia * d + ca + 1) * nloc];
                out[a * d + ca] += cell
                    .iter()
                    .enumerate()
                    .flat_map(|(ib, &b)| (0..d).map(move |cb| (ib * d + cb, b * d + cb)))
                    .map(|(j, g)| row[j] * u_local[g])
                    .sum::<f64>();
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn facet_normals_are_unit() {
        let n = facet_normal(&[&[0.0, 0.0], &[2.0, 0.0]]);
        assert_eq!(n, vec![0.0, -1.0]);
        let n = facet_normal(&[&[0.0, 0.0, 0.0], &[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0]]);
        assert_eq!(n, vec![0.0, 0.0, 1.0]);
    }
}
