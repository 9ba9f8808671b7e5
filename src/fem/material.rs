//! The material of each cell: the global `-E`, `-nu`, `-density`, or those
//! of the body group it is in (`-E_NAME`, `-nu_NAME`, `-density_NAME`;
//! [`crate::options::materials`]).
//!
//! Resolved on every rank from its local mesh once it is distributed: the
//! groups and the table of sets of body groups are the whole mesh's on
//! every rank, so every check here gives every rank the same answer (its
//! errors are collective) without communication. The contact's Hertz E*,
//! from the cells under its surfaces ([`contact_e_star`]), takes one
//! all-reduce.

use std::collections::HashMap;

use mpi::traits::Communicator;

use crate::comm::allreduce_max_vec;
use crate::error::{bad, Error};
use crate::mesh::distribute::LocalMesh;
use crate::mesh::CellMaterials;
use crate::options::materials::Material;
use crate::options::Settings;

/// "E 10, nu 0.3" (and the density where it weighs): a material in words.
fn words(m: &Material, gravity: bool) -> String {
    if gravity {
        format!("E {}, nu {}, density {}", m.young, m.nu, m.density)
    } else {
        format!("E {}, nu {}", m.young, m.nu)
    }
}

/// The names of the mesh's body groups (its dimension), for messages.
fn body_names(mesh: &LocalMesh) -> String {
    let names: Vec<&str> = mesh
        .groups
        .iter()
        .filter(|g| g.dim == mesh.dim)
        .map(|g| g.name.as_str())
        .collect();
    if names.is_empty() {
        let kind = if mesh.dim == 2 {
            "Physical Surface"
        } else {
            "Physical Volume"
        };
        format!("it has none: in Gmsh, a {kind} holds the cells of a body")
    } else {
        format!("it has: {}", names.join(", "))
    }
}

/// Sets `mesh.materials` from the options: the index of each option's
/// group, the material of each set of body groups, then of each cell. Bad
/// input: an option naming no group of the mesh's dimension, a cell in two
/// body groups of different materials.
pub fn resolve(mesh: &mut LocalMesh, settings: &Settings) -> Result<(), Error> {
    let m = &settings.materials;
    let global = Material {
        young: settings.young,
        nu: settings.nu,
        density: m.global.density,
    };
    let gravity = m.gravity.is_some();
    // The material of each group an option names, and that option.
    let mut of_group: Vec<Option<(Material, String)>> = vec![None; mesh.groups.len()];
    for b in &m.bodies {
        let option = b.option();
        let Some(g) = crate::mesh::find_group(&mesh.groups, &b.group) else {
            return bad(format!(
                "option {option}: the mesh has no body group '{}' (a physical group of its dimension, {}D; {})",
                b.group,
                mesh.dim,
                body_names(mesh)
            ));
        };
        if mesh.groups[g].dim != mesh.dim {
            return bad(format!(
                "option {option}: group '{}' has dimension {}; a material needs a body group, of dimension {} ({})",
                b.group,
                mesh.groups[g].dim,
                mesh.dim,
                body_names(mesh)
            ));
        }
        of_group[g] = Some((b.over(global), option));
    }
    let mut list = vec![global];
    let mut set_material = Vec::with_capacity(mesh.bodies.sets.len());
    for set in &mesh.bodies.sets {
        let material = |g: u32| of_group[g as usize].as_ref().map_or(global, |(m, _)| *m);
        let first = set.first().map_or(global, |&g| material(g));
        if let Some(&other) = set.iter().find(|&&g| material(g) != first) {
            let g0 = set[0];
            let option = of_group[g0 as usize]
                .as_ref()
                .or(of_group[other as usize].as_ref())
                .map_or(String::new(), |(_, o)| o.clone());
            return bad(format!(
                "option {option}: cells of the mesh are in both body groups '{}' and '{}', of different materials ({} against {}); a cell takes one material: give both groups the same, or put each cell in one",
                mesh.groups[g0 as usize].name,
                mesh.groups[other as usize].name,
                words(&first, gravity),
                words(&material(other), gravity)
            ));
        }
        let k = match list.iter().position(|x| *x == first) {
            Some(k) => k,
            None => {
                list.push(first);
                list.len() - 1
            }
        };
        set_material.push(k as u32);
    }
    let of_cell = if list.len() == 1 {
        Vec::new()
    } else {
        let sets = &mesh.bodies.cell_set;
        sets.iter().map(|&k| set_material[k as usize]).collect()
    };
    mesh.materials = CellMaterials { list, of_cell };
    Ok(())
}

/// Poisson's ratio above which the linear elements lock visibly (lambda/mu
/// = 2 nu / (1 - 2 nu) = 49). Measured on the Hertz scene, the L2 error of
/// the contact pressure against Hertz, on 6619 and 1692 nodes: nu 0.3
/// 2.8%, 3.0%; 0.49 2.7%, 3.3% (Q1 4.5% against 3.1%); 0.495 4.4%;
/// 0.499 10.7%, 19.4% (Q1 34%); 0.4999 51%; 0.49999 126%.
pub const LOCKING_NU: f64 = 0.49;

/// The largest Poisson's ratio of the local cells, and the largest of
/// those that take it from `-nu` (no `-nu_NAME` of their body groups):
/// `NEG_INFINITY` where none (after [`resolve`]; their maxima over the
/// ranks go to [`locking_warning`]).
pub fn local_max_nu(mesh: &LocalMesh, settings: &Settings) -> [f64; 2] {
    let bodies = &settings.materials.bodies;
    let own_nu: Vec<bool> = mesh
        .bodies
        .sets
        .iter()
        .map(|set| {
            set.iter().any(|&g| {
                bodies.iter().any(|b| {
                    b.nu.is_some()
                        && crate::mesh::find_group(&mesh.groups, &b.group) == Some(g as usize)
                })
            })
        })
        .collect();
    let mut max = [f64::NEG_INFINITY; 2];
    for c in 0..mesh.cells.len() {
        let nu = of_cell(mesh, settings, c).nu;
        max[0] = max[0].max(nu);
        let set = mesh.bodies.cell_set.get(c).map_or(0, |&k| k as usize);
        if !own_nu.get(set).copied().unwrap_or(false) {
            max[1] = max[1].max(nu);
        }
    }
    max
}

/// The warning for a mesh whose cells take a Poisson's ratio above
/// [`LOCKING_NU`] (`nu`: [`local_max_nu`]'s maxima over the ranks), naming
/// the options that set it; none in plane stress, which does not lock: P1
/// and Q1 elements make a nearly incompressible body too stiff.
pub fn locking_warning(nu: [f64; 2], mesh: &LocalMesh, settings: &Settings) -> Option<String> {
    if (mesh.dim == 2 && settings.plane_stress) || nu[0] <= LOCKING_NU {
        return None;
    }
    // The body groups that have cells: those of the sets (whole mesh).
    let has_cells = |name: &str| {
        let found = crate::mesh::find_group(&mesh.groups, name);
        mesh.bodies
            .sets
            .iter()
            .flatten()
            .any(|&g| Some(g as usize) == found)
    };
    let mut options: Vec<String> = settings
        .materials
        .bodies
        .iter()
        .filter(|b| b.nu.is_some_and(|v| v > LOCKING_NU) && has_cells(&b.group))
        .map(|b| format!("-nu_{} {}", b.group, b.nu.unwrap_or(0.0)))
        .collect();
    if nu[1] > LOCKING_NU {
        options.insert(0, format!("-nu {}", settings.nu));
    }
    Some(format!(
        "{}: nearly incompressible (lambda/mu = {:.0}); linear elements (P1, Q1) lock at such a Poisson's ratio, making the body too stiff: contact pressures come out too high and contact zones too narrow, by more than the mesh's own error, and mesh refinement cures it slowly (Hertz, L2 error of the pressure: 2.7% at nu 0.49, 11% at 0.499, 51% at 0.4999); unless the body is confined, nu 0.49 changes the exact answer little (Hertz: p0 0.65% below that of 0.4999)",
        options.join(", "),
        2.0 * nu[0] / (1.0 - 2.0 * nu[0])
    ))
}

/// The material of local cell `c` (the global one before [`resolve`]).
pub fn of_cell(mesh: &LocalMesh, settings: &Settings, c: usize) -> Material {
    match mesh.materials.list.get(mesh.materials.index(c)) {
        Some(m) => *m,
        None => Material {
            young: settings.young,
            nu: settings.nu,
            density: settings.materials.global.density,
        },
    }
}

/// Of each side (a list of surface groups), the largest
/// [`Material::hertz_modulus`] of the local cells that hold one of its facets
/// (-infinity where this rank holds none).
fn side_moduli(mesh: &LocalMesh, settings: &Settings, sides: &[Vec<&str>]) -> Vec<f64> {
    let facets: Vec<Vec<&[usize]>> = sides
        .iter()
        .map(|groups| {
            groups
                .iter()
                .filter_map(|g| mesh.group(g))
                .flat_map(|g| g.conn.iter())
                .filter(|f| !f.is_empty())
                .collect()
        })
        .collect();
    // The cells at each facet's first node.
    let mut at: HashMap<usize, Vec<usize>> = facets
        .iter()
        .flatten()
        .map(|f| (f[0], Vec::new()))
        .collect();
    for (c, cell) in mesh.cells.iter().enumerate() {
        for v in cell {
            if let Some(cells) = at.get_mut(v) {
                cells.push(c);
            }
        }
    }
    let plane_stress = settings.plane_stress;
    facets
        .iter()
        .map(|side| {
            let mut e = f64::NEG_INFINITY;
            for f in side {
                for &c in &at[&f[0]] {
                    let cell = mesh.cells.get(c);
                    if f.iter().all(|v| cell.contains(v)) {
                        let m = of_cell(mesh, settings, c);
                        e = e.max(m.hertz_modulus(mesh.dim, plane_stress));
                    }
                }
            }
            e
        })
        .collect()
}

/// E* of Hertz's formulas for the scene's contact (`-reference hertz`,
/// `-tresca_bound hertz`; Johnson, Contact Mechanics, 4.2-4.3): on a rigid
/// obstacle E/(1 - nu^2) (E in plane stress, 2D) of the cells under the
/// contact surface; for two elastic bodies (`-contact_pair`)
/// `1/E* = 1/E*_1 + 1/E*_2`, each body's from the cells under its surface
/// of the pair. A
/// surface on cells of several materials takes the stiffest; of several
/// contacts (pairs, a pair and an obstacle), the largest E*. None where the
/// mesh holds none of the surfaces' facets. Collective.
pub fn contact_e_star<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    settings: &Settings,
) -> Option<f64> {
    let contact = settings.contact.as_ref()?;
    let rigid: Vec<&str> = contact.surfaces.iter().map(String::as_str).collect();
    let mut sides = vec![rigid];
    for (slave, master) in &contact.pairs {
        sides.push(vec![slave.as_str()]);
        sides.push(vec![master.as_str()]);
    }
    let e = allreduce_max_vec(world, &side_moduli(mesh, settings, &sides));
    let pairs = e[1..].chunks(2).map(|p| 1.0 / (1.0 / p[0] + 1.0 / p[1]));
    let best = pairs.fold(e[0], f64::max);
    (best.is_finite() && best > 0.0).then_some(best)
}

/// The distinct materials of the mesh's cells, the global one first (it
/// alone before [`resolve`]).
pub fn list(mesh: &LocalMesh, settings: &Settings) -> Vec<Material> {
    if mesh.materials.list.is_empty() {
        vec![of_cell(mesh, settings, 0)]
    } else {
        mesh.materials.list.clone()
    }
}
