//! Several obstacles (`-obstacles NAME1,NAME2,...`): each NAME described by
//! its own options, `-obstacle_NAME KIND` and `-obstacle_NAME_point`,
//! `_center`, `_radius`, `_axis`, `_direction`, `_mesh`, `_mesh_group`,
//! `_search_distance`, read as the single obstacle's are.

use super::declared::{nonempty, real_of, vector_of, CONTACT_DIRECTION, CONTACT_NORMAL};
use super::declared::{
    OBSTACLE, OBSTACLE_AXIS, OBSTACLE_CENTER, OBSTACLE_MESH, OBSTACLE_MESH_GROUP, OBSTACLE_POINT,
    OBSTACLE_RADIUS, OBSTACLE_SEARCH_DISTANCE,
};
use super::{positive, unit, ContactSettings, NamedObstacle, NormalMode, Obstacle};
use crate::error::{bad, Error};
use crate::petsc::options;

/// The kinds an obstacle may be.
const KINDS: [&str; 5] = ["plane", "ball", "halfball", "cylinder", "mesh"];

/// The contact settings of `-obstacles names` on `surfaces`.
pub fn read(
    surfaces: Vec<String>,
    names: Vec<String>,
    notes: &mut Vec<String>,
) -> Result<ContactSettings, Error> {
    // The single obstacle's options do not mix with the named ones.
    for opt in [
        OBSTACLE.name,
        OBSTACLE_POINT.name,
        OBSTACLE_CENTER.name,
        OBSTACLE_RADIUS.name,
        OBSTACLE_AXIS.name,
        OBSTACLE_MESH.name,
        OBSTACLE_MESH_GROUP.name,
        OBSTACLE_SEARCH_DISTANCE.name,
    ] {
        if options::has_name(opt)? {
            return bad(format!(
                "option {opt}: with -obstacles each obstacle has its own options (-obstacle_NAME, -obstacle_NAME_point, ...)"
            ));
        }
    }
    let mut seen = std::collections::HashSet::new();
    for n in &names {
        if !seen.insert(n) {
            return bad(format!("option -obstacles: '{n}' is named twice"));
        }
        if n.contains(['-', ' ']) || n.is_empty() {
            return bad(format!(
                "option -obstacles: '{n}' is not a name (letters, digits, _)"
            ));
        }
    }
    let direction = match CONTACT_DIRECTION.vector()? {
        Some(v) => unit(CONTACT_DIRECTION.name, v, notes)?,
        None => Vec::new(),
    };
    let mode = CONTACT_NORMAL.get()?;
    let mut obstacles = Vec::with_capacity(names.len());
    for name in names {
        obstacles.push(one(&name, mode, &direction, notes)?);
    }
    let first = obstacles[0].clone();
    Ok(ContactSettings {
        surfaces,
        direction,
        normal: first.normal,
        obstacle: first.obstacle,
        obstacles,
        named: true,
        pairs: Vec::new(),
        pair_node_to_segment: false,
    })
}

/// `-obstacle_NAME ...`: one obstacle.
fn one(
    name: &str,
    mode: &str,
    default_direction: &[f64],
    notes: &mut Vec<String>,
) -> Result<NamedObstacle, Error> {
    let opt = |key: &str| format!("-obstacle_{name}{key}");
    let head = opt("");
    let Some(kind) = nonempty(&head)? else {
        return bad(format!(
            "option {head} (plane, ball, halfball, cylinder or mesh) is required: -obstacles names '{name}'"
        ));
    };
    if !KINDS.contains(&kind.as_str()) {
        return bad(format!(
            "option {head}: unknown value '{kind}' ({})",
            KINDS.join(", ")
        ));
    }
    let normal = match (mode, kind.as_str()) {
        ("fixed", "mesh") => {
            return bad(format!(
            "option -contact_normal fixed: {head} mesh measures gaps to each node's closest point"
        ))
        }
        ("fixed", _) | ("auto", "plane") => NormalMode::Fixed,
        _ => NormalMode::Closest,
    };
    let direction = match vector_of(&opt("_direction"))? {
        Some(v) => unit(&opt("_direction"), v, notes)?,
        None => default_direction.to_vec(),
    };
    if direction.is_empty() && (normal == NormalMode::Fixed || kind == "halfball") {
        return bad(format!(
            "option {} is required: {head} {kind} with -contact_normal {} (or give -contact_direction for every obstacle)",
            opt("_direction"),
            normal.as_str()
        ));
    }
    let positive = |key: &str| -> Result<Option<f64>, Error> {
        match real_of(&opt(key))? {
            Some(v) => positive(&opt(key), v).map(Some),
            None => Ok(None),
        }
    };
    let required = |key: &str, v: Option<Vec<f64>>| -> Result<Vec<f64>, Error> {
        v.map_or_else(
            || {
                bad(format!(
                    "option {} is required with {head} {kind}",
                    opt(key)
                ))
            },
            Ok,
        )
    };
    let obstacle = match kind.as_str() {
        "plane" => Obstacle::Plane {
            point: required("_point", vector_of(&opt("_point"))?)?,
        },
        "mesh" => Obstacle::Mesh {
            file: nonempty(&opt("_mesh"))?.map_or_else(
                || {
                    bad(format!(
                        "option {} is required with {head} mesh",
                        opt("_mesh")
                    ))
                },
                Ok,
            )?,
            group: nonempty(&opt("_mesh_group"))?,
            search: positive("_search_distance")?,
        },
        _ => {
            let center = required("_center", vector_of(&opt("_center"))?)?;
            let radius = positive("_radius")?.map_or_else(
                || {
                    bad(format!(
                        "option {} is required with {head} {kind}",
                        opt("_radius")
                    ))
                },
                Ok,
            )?;
            match kind.as_str() {
                "ball" => Obstacle::Ball { center, radius },
                "halfball" => Obstacle::HalfBall { center, radius },
                _ => {
                    let axis = match vector_of(&opt("_axis"))? {
                        Some(a) if center.len() == 3 => unit(&opt("_axis"), a, notes)?,
                        Some(_) => {
                            return bad(format!(
                                "option {}: a 2D cylinder is the disc, it has no axis",
                                opt("_axis")
                            ))
                        }
                        None if center.len() == 3 => {
                            return bad(format!(
                                "option {} is required with a 3D {head} cylinder",
                                opt("_axis")
                            ))
                        }
                        None => Vec::new(),
                    };
                    Obstacle::Cylinder {
                        center,
                        axis,
                        radius,
                    }
                }
            }
        }
    };
    Ok(NamedObstacle {
        name: name.to_string(),
        obstacle,
        direction,
        normal,
    })
}
