//! The contact set: candidate nodes of Gamma_c owned by this rank, their
//! nodal weights `w_i`, unit normals `n_i` (the fixed direction n, or from
//! the closest point on the obstacle) and gaps `g_i` along them, and the
//! pointwise projections of the paper, (4.15) and (5.5).

use crate::comm::allreduce_max;
use crate::error::{bad, Error};
use crate::fem::element::facet_weights;
use crate::mesh::distribute::LocalMesh;
use crate::options::{ContactSettings, NamedObstacle, NormalMode};
pub use obstacle::{closest, gap, Obstacle};

pub mod hertz;
pub mod interior;
pub mod mesh_obstacle;
pub mod mortar;
pub mod mortar3d;
pub mod obstacle;
pub mod prescribed;
pub mod search;
pub mod surface;

/// Candidates owned by this rank.
#[derive(Clone, Debug, Default)]
pub struct ContactSet {
    pub dim: usize,
    /// The fixed contact direction n (`-contact_direction`; empty when not
    /// given, with closest normals).
    pub direction: Vec<f64>,
    /// Whether every candidate's normal is `direction` (fixed normals, or
    /// closest normals on a plane): the same on every rank.
    pub uniform: bool,
    /// Unit normal n_i of each candidate, `dim` components each.
    pub normal: Vec<f64>,
    /// Local node index (an owned node) of each candidate.
    pub node: Vec<usize>,
    /// Nodal weight w_i (trapezoidal quadrature on Gamma_c).
    pub w: Vec<f64>,
    /// Gap g_i along n_i (negative: initial penetration).
    pub g: Vec<f64>,
    /// Each candidate's contact surface: its index in
    /// `ContactSettings::surfaces`, the first group with a facet at the node
    /// (a node where two groups meet counts in the first).
    pub group: Vec<usize>,
    /// A surface node on a ball's centre or a cylinder's axis (closest
    /// normals: no normal there), by its tag; the caller reports it.
    pub on_center: Option<u64>,
    /// Each candidate's obstacle: its index in
    /// `ContactSettings::obstacles` (the one of smallest gap); for the
    /// slave node of a contact pair p, `obstacles.len() + p`.
    pub obstacle: Vec<usize>,
    /// Each candidate's contact pair (`ContactSettings::pairs`), or
    /// `usize::MAX` against a rigid obstacle.
    pub pair: Vec<usize>,
    /// A pair's slave node: its mortar row `P_kj` by master node (global
    /// number, increasing); empty against a rigid obstacle.
    pub mortar: Vec<Vec<(usize, f64)>>,
    /// A pair's slave node: its image on the master (`dim` values per
    /// candidate, zero against a rigid obstacle).
    pub image: Vec<f64>,
    /// Warnings of [`Self::build`]: an obstacle surface read reversed, a
    /// ball or a cylinder read as the cavity it bounds.
    pub reoriented: Vec<String>,
}

/// The largest part of a facet-made normal along prescribed displacement
/// components that [`ContactSet::align_normals`] takes for a tilt (an
/// averaged normal on a symmetry plane is tilted by about h / 2R).
pub const TILT: f64 = 0.5;

impl ContactSet {
    pub fn len(&self) -> usize {
        self.node.len()
    }
    pub fn is_empty(&self) -> bool {
        self.node.is_empty()
    }

    /// The unit normal n_i of candidate i.
    #[inline]
    pub fn n(&self, i: usize) -> &[f64] {
        &self.normal[i * self.dim..(i + 1) * self.dim]
    }

    /// The one normal of every candidate, when they share it.
    pub fn common_normal(&self) -> Option<&[f64]> {
        self.uniform.then_some(&self.direction[..])
    }

    /// Normals made of facets in the directions the node may move: a pair's
    /// slave normal (averaged from the slave facets) and a closest normal
    /// on an obstacle given as a mesh (`-obstacle mesh`, from its facets).
    /// At such a candidate with prescribed displacement components
    /// (`dirichlet`, owned dofs), the normal's part along them is removed
    /// when it is a tilt (at most [`TILT`] in norm), and the gap measured
    /// along the new normal. A node on a symmetry plane (a quarter model,
    /// `ux = 0` on its cut) has a normal averaged from the facets on one
    /// side of the plane, or the normal of an obstacle facet that does not
    /// respect the plane, tilted out of it by about h / 2R; its tangential
    /// relative displacement then took a part of the normal approach that
    /// no tangential force could change, and Coulomb friction drifted
    /// there towards slip (the ball on a block of
    /// `tests/pairs/ball_block3d.geo` at hc 0.04, nu_f 0.8: CF-FP failed,
    /// its Tresca solve stalled with two nodes' tangential multipliers
    /// moving by r u_t each iteration; a quarter block on a faceted rigid
    /// sphere, nu_f 0.3, the same; and the set-up warned of a Dirichlet
    /// condition along n there). A larger part is a Dirichlet condition on
    /// the contact direction itself, kept as given (the set-up warns of
    /// it); fixed directions and analytic obstacles' normals are exact.
    pub fn align_normals(
        &mut self,
        mesh: &LocalMesh,
        dirichlet: &[(usize, f64)],
        settings: &ContactSettings,
    ) {
        let d = self.dim;
        let fixed: std::collections::HashSet<usize> = dirichlet.iter().map(|&(k, _)| k).collect();
        for i in 0..self.len() {
            let pair = self.pair[i] != usize::MAX;
            let faceted = settings.obstacles.get(self.obstacle[i]).is_some_and(|o| {
                matches!(o.obstacle, Obstacle::Mesh { .. }) && o.normal == NormalMode::Closest
            });
            if !pair && !faceted {
                continue;
            }
            let v = self.node[i];
            let comps: Vec<usize> = (0..d).filter(|&c| fixed.contains(&(v * d + c))).collect();
            let n = &mut self.normal[i * d..(i + 1) * d];
            let along: f64 = comps.iter().map(|&c| n[c] * n[c]).sum();
            if comps.is_empty() || along == 0.0 || along > TILT * TILT {
                continue;
            }
            let old = n.to_vec();
            comps.iter().for_each(|&c| n[c] = 0.0);
            let norm = n.iter().map(|x| x * x).sum::<f64>().sqrt();
            n.iter_mut().for_each(|x| *x /= norm);
            self.g[i] = if pair {
                let x = &mesh.coords[v * d..(v + 1) * d];
                (0..d).map(|c| n[c] * (self.image[i * d + c] - x[c])).sum()
            } else {
                // The closest point lies at g along the old normal.
                self.g[i] * (0..d).map(|c| n[c] * old[c]).sum::<f64>()
            };
        }
    }

    /// The checks and the choice that need every rank, after [`Self::build`]:
    /// a surface node on the obstacle's centre (or axis) is bad input; with
    /// closest normals and no `-contact_direction`, `direction` (the axis
    /// of the Hertz comparison and of the plots) becomes the normal of the
    /// candidate with the smallest gap.
    pub fn settle<C: mpi::traits::Communicator>(&mut self, world: &C) -> Result<(), Error> {
        let at = allreduce_max(world, self.on_center.map_or(-1.0, |t| t as f64));
        if at >= 0.0 {
            return bad(format!(
                "option -contact_normal: surface node {} lies on the obstacle's centre (or axis), where no normal is the closest; use -contact_normal fixed or move the obstacle",
                at as u64
            ));
        }
        if self.direction.is_empty() {
            let d = self.dim;
            let mut mine = [f64::INFINITY, 0.0, 0.0, 0.0];
            for i in 0..self.len() {
                if self.g[i] < mine[0] {
                    mine[0] = self.g[i];
                    mine[1..1 + d].copy_from_slice(self.n(i));
                }
            }
            let all = crate::comm::Layout::new(world, 4).all_gather(world, &mine[..]);
            let best = all
                .chunks(4)
                .min_by(|a, b| a[0].total_cmp(&b[0]))
                .map(|c| c[1..1 + d].to_vec());
            self.direction = best.unwrap_or_else(|| vec![0.0; d]);
        }
        Ok(())
    }

    /// Builds the owned candidates of the surfaces `settings.surfaces` (a
    /// facet in two of them counts once). The caller checks the global
    /// candidate count (a surface with no candidate is bad input).
    pub fn build<C: mpi::traits::Communicator>(
        world: &C,
        mesh: &LocalMesh,
        settings: &ContactSettings,
    ) -> Result<ContactSet, Error> {
        let d = mesh.dim;
        let mut groups = Vec::with_capacity(settings.surfaces.len());
        for name in &settings.surfaces {
            groups.push(mesh.group_for(
                "-contact_surface",
                name,
                d - 1..=d - 1,
                "a contact surface",
            )?);
        }
        if !settings.direction.is_empty() && settings.direction.len() != d {
            return bad(format!(
                "option -contact_direction: {} components given, the mesh is {}D",
                settings.direction.len(),
                d
            ));
        }
        let single = settings.obstacles.len() == 1;
        let (surfaces, reoriented) = obstacle_surfaces(world, mesh, settings)?;
        let n = &settings.direction;
        // Weights of every owned node of the surface.
        let mut weight = vec![0.0; mesh.owned_count];
        let mut on_surface = vec![false; mesh.owned_count];
        let mut group_of = vec![usize::MAX; mesh.owned_count];
        let mut seen = std::collections::HashSet::new();
        // w_i: sum over the facets of the surfaces touching node i of the
        // facet's nodal weight (measure / vertices for a simplex facet;
        // int N_i dA for a quadrilateral, a quarter of a parallelogram;
        // `element::facet_weights`); a facet in two surfaces counts once.
        let mut share = Vec::with_capacity(4);
        for (k, group) in groups.into_iter().enumerate() {
            for e in &group.conn {
                let mut key = e.to_vec();
                key.sort_unstable();
                if !seen.insert(key) {
                    continue;
                }
                let pts: Vec<&[f64]> = e.iter().map(|&v| mesh.x(v)).collect();
                facet_weights(&pts, &mut share);
                for (&v, &w) in e.iter().zip(&share) {
                    if mesh.is_owned(v) {
                        weight[v] += w;
                        on_surface[v] = true;
                        group_of[v] = group_of[v].min(k);
                    }
                }
            }
        }
        let fixed = settings.normal == NormalMode::Fixed;
        let mut set = ContactSet {
            dim: d,
            direction: n.clone(),
            uniform: single && (fixed || matches!(settings.obstacle, Obstacle::Plane { .. })),
            reoriented,
            ..Default::default()
        };
        let cavity = round_cavities(world, mesh, settings, &mut set.reoriented);
        for v in 0..mesh.owned_count {
            if !on_surface[v] {
                continue;
            }
            // The obstacle of smallest gap (the first on a tie).
            let mut best: Option<(f64, Vec<f64>, usize)> = None;
            for (k, (o, surface)) in settings.obstacles.iter().zip(&surfaces).enumerate() {
                let (found, on_center) = gap_at(o, surface.as_ref(), cavity[k], mesh.x(v));
                if on_center && single {
                    set.on_center.get_or_insert(mesh.node_tag[v]);
                }
                if let Some((g, normal)) = found {
                    if best.as_ref().is_none_or(|b| g < b.0) {
                        best = Some((g, normal, k));
                    }
                }
            }
            if let Some((g, normal, k)) = best {
                set.node.push(v);
                set.w.push(weight[v]);
                set.g.push(g);
                set.normal.extend(normal);
                set.group.push(group_of[v]);
                set.obstacle.push(k);
                set.pair.push(usize::MAX);
                set.mortar.push(Vec::new());
                set.image.extend(std::iter::repeat_n(0.0, d));
            }
        }
        Ok(set)
    }

    /// Whether a candidate is a contact pair's slave node.
    pub fn has_pairs(&self) -> bool {
        self.pair.iter().any(|&p| p != usize::MAX)
    }

    /// Adds the slave nodes of the contact pairs (`settings.pairs`) as
    /// candidates, with their mortar rows ([`mortar`] in 2D, [`mortar3d`]).
    pub fn add_pairs<C: mpi::traits::Communicator>(
        &mut self,
        world: &C,
        mesh: &LocalMesh,
        settings: &ContactSettings,
    ) -> Result<(), Error> {
        if settings.pairs.is_empty() {
            return Ok(());
        }
        if mesh.dim == 3 && settings.pair_node_to_segment {
            return bad(
                "option -contact_pair_scheme node_to_segment: 2D only (the 3D pairs are mortar)",
            );
        }
        let lo = mesh.owned_start;
        // Each candidate's pair (None: -contact_surface's).
        let mut taken: std::collections::HashMap<usize, Option<usize>> =
            self.node.iter().map(|&v| (v, None)).collect();
        let (mut slaves, mut masters) = (Vec::new(), Vec::new());
        for (p, (s, m)) in settings.pairs.iter().enumerate() {
            let (mut rows, mut slave_nodes, master_nodes) = pair_rows(world, mesh, settings, s, m)?;
            // Where the two surfaces of one body meet (a crack's tip or
            // front, a slot's end), a node on both is one material point:
            // no candidate (its gap is zero and stays zero).
            let on_master: std::collections::HashSet<usize> =
                master_nodes.iter().copied().collect();
            let shared = slave_nodes.iter().filter(|n| on_master.contains(n)).count();
            if shared > 0 && shared < slave_nodes.len() {
                rows.retain(|r| !on_master.contains(&r.node));
                slave_nodes.retain(|n| !on_master.contains(n));
            }
            // (Decided on every rank: the first such node's tag, and where.)
            let twice = rows
                .iter()
                .find_map(|r| taken.get(&(r.node - lo)).map(|&q| (r.node - lo, q)));
            let mine = twice.map_or(-1.0, |(v, _)| mesh.node_tag[v] as f64);
            let tag = allreduce_max(world, mine);
            // The other side of the node of that tag (its rank's).
            let other = match twice {
                Some((_, q)) if mine == tag => q.map_or(0.0, |q| q as f64 + 1.0),
                _ => -1.0,
            };
            let other = allreduce_max(world, other);
            if tag >= 0.0 {
                let other = match other as usize {
                    0 => "a candidate of -contact_surface".to_string(),
                    q => format!(
                        "a slave node of the pair {},{}",
                        settings.pairs[q - 1].0,
                        settings.pairs[q - 1].1
                    ),
                };
                return bad(format!(
                    "option -contact_pair: node {} of surface '{s}' (the pair {s},{m}) is {other} too; a node meets one obstacle or one pair",
                    tag as u64
                ));
            }
            for r in &rows {
                taken.insert(r.node - lo, Some(p));
            }
            for r in rows {
                let v = r.node - lo;
                self.node.push(v);
                self.w.push(r.w);
                self.g.push(r.gap);
                self.normal.extend(&r.normal[..mesh.dim]);
                self.group.push(settings.surfaces.len() + p);
                self.obstacle.push(settings.obstacles.len() + p);
                self.pair.push(p);
                self.mortar.push(r.row);
                self.image.extend(&r.point[..mesh.dim]);
            }
            slaves.extend(slave_nodes.into_iter().map(|n| (n, s)));
            masters.extend(master_nodes.into_iter().map(|n| (n, m)));
        }
        self.uniform = false;
        let slave_of: std::collections::HashMap<usize, &String> = slaves.into_iter().collect();
        if let Some((n, m)) = masters.iter().find(|(n, _)| slave_of.contains_key(n)) {
            // (The node's tag from the rank that holds it.)
            let v = mesh.node_global.iter().position(|g| g == n);
            let tag = allreduce_max(world, v.map_or(-1.0, |v| mesh.node_tag[v] as f64));
            return bad(format!(
                "option -contact_pair: node {} is on the slave surface '{}' and the master surface '{m}'; a node takes one side",
                tag as u64, slave_of[n]
            ));
        }
        Ok(())
    }
}

/// A pair's mortar rows (this rank's slave nodes), and the nodes (global
/// numbers) of its slave and master surfaces.
type PairRows = (Vec<mortar::MortarNode>, Vec<usize>, Vec<usize>);

/// The mortar rows of this rank's slave nodes of the pair (`s`, `m`), and
/// the nodes (global numbers) of its two surfaces.
fn pair_rows<C: mpi::traits::Communicator>(
    world: &C,
    mesh: &LocalMesh,
    settings: &ContactSettings,
    s: &str,
    m: &str,
) -> Result<PairRows, Error> {
    let opt = "-contact_pair";
    let (lo, hi) = (mesh.owned_start, mesh.owned_start + mesh.owned_count);
    let mine = |g: usize| (lo..hi).contains(&g);
    let empty = |name: &str, n: usize| -> Result<(), Error> {
        match n {
            0 => bad(format!("option -contact_pair: group '{name}' has no facet")),
            _ => Ok(()),
        }
    };
    if mesh.dim == 3 {
        let mine_s = agreed(world, mortar3d::local_facets(mesh, opt, s))?;
        let mine_m = agreed(world, mortar3d::local_facets(mesh, opt, m))?;
        let slave = mortar3d::gather_facets(world, &mine_s);
        let master = mortar3d::gather_facets(world, &mine_m);
        empty(s, slave.len())?;
        empty(m, master.len())?;
        let rows = mortar3d::mortar_rows(&slave, &master, mine);
        let nodes = |f: &[mortar3d::Facet]| f.iter().flat_map(|x| x.nodes.clone()).collect();
        return Ok((rows, nodes(&slave), nodes(&master)));
    }
    let mine_s = agreed(world, mortar::local_segments(mesh, opt, s))?;
    let mine_m = agreed(world, mortar::local_segments(mesh, opt, m))?;
    let slave = mortar::gather_segments(world, &mine_s);
    let master = mortar::gather_segments(world, &mine_m);
    empty(s, slave.len())?;
    empty(m, master.len())?;
    let rows = if settings.pair_node_to_segment {
        mortar::node_to_segment_rows(&slave, &master, mine)
    } else {
        mortar::mortar_rows(&slave, &master, mine)
    };
    let nodes = |f: &[mortar::Segment]| f.iter().flat_map(|x| x.nodes).collect();
    Ok((rows, nodes(&slave), nodes(&master)))
}

/// `local` on every rank, or the error of the lowest rank that failed on
/// every rank (a facet's fault is seen by the rank that holds it; every
/// rank must stop with the same message, not wait in the gathering).
fn agreed<C: mpi::traits::Communicator, T>(world: &C, local: Result<T, Error>) -> Result<T, Error> {
    use mpi::traits::*;
    let me = world.rank();
    let mut first = 0i32;
    let mine = if local.is_err() { -me } else { i32::MIN };
    world.all_reduce_into(&mine, &mut first, mpi::collective::SystemOperation::max());
    if first == i32::MIN {
        return local;
    }
    let root = world.process_at_rank(-first);
    let mut text = match &local {
        Err(e) => e.to_string().into_bytes(),
        Ok(_) => Vec::new(),
    };
    let mut len = text.len() as u64;
    root.broadcast_into(&mut len);
    text.resize(len as usize, 0);
    root.broadcast_into(&mut text[..]);
    let msg = String::from_utf8_lossy(&text);
    Err(Error::BadInput(
        msg.strip_prefix("error: ").unwrap_or(&msg).to_string(),
    ))
}

/// The obstacle's points against the mesh's dimension; `single`: the
/// options are `-obstacle_point`, ..., else `-obstacle_NAME_point`, ...
fn check_dimensions(o: &NamedObstacle, d: usize, single: bool) -> Result<(), Error> {
    let opt = |key: &str| {
        if single {
            format!("-obstacle_{key}")
        } else {
            format!("-obstacle_{}_{key}", o.name)
        }
    };
    if !single && !o.direction.is_empty() && o.direction.len() != d {
        return bad(format!(
            "option {}: {} components given, the mesh is {d}D",
            opt("direction"),
            o.direction.len()
        ));
    }
    match &o.obstacle {
        Obstacle::Plane { point } if point.len() != d => bad(format!(
            "option {}: {} components given, the mesh is {}D",
            opt("point"),
            point.len(),
            d
        )),
        Obstacle::Ball { center, .. }
        | Obstacle::HalfBall { center, .. }
        | Obstacle::Cylinder { center, .. }
            if center.len() != d =>
        {
            bad(format!(
                "option {}: {} components given, the mesh is {}D",
                opt("center"),
                center.len(),
                d
            ))
        }
        Obstacle::Cylinder { axis, .. } if d == 2 && !axis.is_empty() => bad(format!(
            "option {}: a 2D cylinder is the disc, it has no axis",
            opt("axis")
        )),
        _ => Ok(()),
    }
}

/// An error of the surface reader ("option -obstacle_mesh: ...") about
/// obstacle `name` of `-obstacles`, naming the option the user gave
/// (`-obstacle_NAME_mesh`); only the message's head changes, not a path
/// that may hold the same words.
fn of_named(e: Error, name: Option<&str>) -> Error {
    const HEAD: &str = "option -obstacle_mesh";
    match (e, name) {
        (Error::BadInput(m), Some(name)) if m.starts_with(HEAD) => {
            Error::BadInput(format!("option -obstacle_{name}_mesh{}", &m[HEAD.len()..]))
        }
        (e, _) => e,
    }
}

/// The rigid surface of `-obstacle mesh`: read (every rank reads the same
/// file, so an error is the same on every rank), closed, with its search
/// distance.
fn read_surface(
    file: &str,
    group: Option<&str>,
    search: Option<f64>,
    dim: usize,
) -> Result<mesh_obstacle::MeshObstacle, Error> {
    let surface = mesh_obstacle::MeshObstacle::read_group(std::path::Path::new(file), dim, group)?;
    // A signed distance needs an inside: a closed surface (an open one
    // would give nodes beyond its rim a gap of the wrong sign).
    surface.require_closed()?;
    Ok(match search {
        Some(d) => surface.with_search_distance(d),
        None => surface,
    })
}

/// The surface of each `-obstacle mesh` of `settings` (None for the other
/// obstacles), read, checked and oriented to the body
/// ([`orient_to_body`]), with the warnings of those read reversed.
/// Collective.
fn obstacle_surfaces<C: mpi::traits::Communicator>(
    world: &C,
    mesh: &LocalMesh,
    settings: &ContactSettings,
) -> Result<(Vec<Option<mesh_obstacle::MeshObstacle>>, Vec<String>), Error> {
    let d = mesh.dim;
    let mut surfaces = Vec::with_capacity(settings.obstacles.len());
    let mut reoriented = Vec::new();
    for o in &settings.obstacles {
        check_dimensions(o, d, !settings.named)?;
        surfaces.push(match &o.obstacle {
            Obstacle::Mesh {
                file,
                group,
                search,
            } => {
                let named = settings.named.then_some(o.name.as_str());
                let surface = read_surface(file, group.as_deref(), *search, d)
                    .map_err(|e| of_named(e, named))?;
                let option =
                    named.map_or(OPTION_MESH.to_string(), |n| format!("-obstacle_{n}_mesh"));
                let (surface, warning) = orient_to_body(world, mesh, surface, &option)?;
                reoriented.extend(warning);
                Some(surface)
            }
            _ => None,
        });
    }
    Ok((surfaces, reoriented))
}

/// The gap and unit normal of obstacle `o` (its surface for `-obstacle
/// mesh`; a ball or cylinder read as its cavity where `cavity`) at `x`, None
/// where `x` is no candidate of it; and whether `x` lies on a ball's centre
/// or a cylinder's axis with closest normals, where no normal is the
/// closest.
fn gap_at(
    o: &NamedObstacle,
    surface: Option<&mesh_obstacle::MeshObstacle>,
    cavity: bool,
    x: &[f64],
) -> (Option<(f64, Vec<f64>)>, bool) {
    if let Some(s) = surface {
        // Farther than the search distance: no candidate.
        return (s.closest(x).map(|c| (c.gap, c.normal)), false);
    }
    let fixed = o.normal == NormalMode::Fixed;
    let along = |g: Option<f64>| g.map(|g| (g, o.direction.clone()));
    let found = match (fixed, cavity) {
        (true, false) => along(gap(x, &o.direction, &o.obstacle)),
        (true, true) => along(obstacle::cavity_gap(x, &o.direction, &o.obstacle)),
        (false, false) => closest(x, &o.direction, &o.obstacle),
        (false, true) => obstacle::cavity_closest(x, &o.obstacle),
    };
    let on_center = !fixed && found.is_none();
    (found, on_center)
}

/// Which obstacles of `settings` are read as the cavity they bound: a ball
/// or a cylinder with most of the body's nodes inside it (up to
/// [`ORIENT_SAMPLES`] per rank) is a socket or a bore holding the body,
/// the rigid solid outside it; a warning naming it goes to `warnings`. A
/// body cannot start inside a rigid solid (an interference fit puts a thin
/// layer of it there, never most of it): read as a solid, such a ball
/// crushed the body it was meant to hold. Collective.
fn round_cavities<C: mpi::traits::Communicator>(
    world: &C,
    mesh: &LocalMesh,
    settings: &ContactSettings,
    warnings: &mut Vec<String>,
) -> Vec<bool> {
    let obstacles = &settings.obstacles;
    // Nothing to ask of planes, surfaces or contact pairs alone (the same
    // on every rank).
    if !obstacles.iter().any(|o| obstacle::is_round(&o.obstacle)) {
        return vec![false; obstacles.len()];
    }
    // Per obstacle: nodes inside, nodes outside (none for the others).
    let count = body_sides(world, mesh, obstacles.len(), |x, count| {
        for (k, o) in obstacles.iter().enumerate() {
            if let Some(inside) = obstacle::inside_round(x, &o.obstacle) {
                count[2 * k + usize::from(!inside)] += 1.0;
            }
        }
    });
    let mut cavity = Vec::with_capacity(obstacles.len());
    for (o, c) in obstacles.iter().zip(count.chunks(2)) {
        let inside = c[0] > c[1];
        if inside {
            let kind = if matches!(o.obstacle, Obstacle::Ball { .. }) {
                "ball"
            } else {
                "cylinder"
            };
            let option = if settings.named {
                format!("-obstacle_{}", o.name)
            } else {
                "-obstacle".to_string()
            };
            warnings.push(format!(
                "{option} {kind}: {:.0}% of the body's nodes lie inside it; it is read as the cavity it bounds (a socket, a bore), the rigid solid outside it and the body within (a {kind} the body rests on or wraps lies outside the body)",
                100.0 * c[0] / (c[0] + c[1])
            ));
        }
        cavity.push(inside);
    }
    cavity
}

/// The option that names a single obstacle's surface file.
const OPTION_MESH: &str = "-obstacle_mesh";

/// How many of its owned nodes each rank tests against an obstacle surface
/// in [`orient_to_body`] (evenly spaced in its numbering; all where fewer).
const ORIENT_SAMPLES: usize = 4096;

/// The body's sides of `parts` things (obstacles, parts of a surface):
/// `count` adds each sampled node (up to [`ORIENT_SAMPLES`] of the owned
/// nodes per rank, evenly spaced) to its thing's pair (inside, outside) of
/// the `2 * parts` sums, which are then summed over the ranks.
/// Collective.
fn body_sides<C: mpi::traits::Communicator>(
    world: &C,
    mesh: &LocalMesh,
    parts: usize,
    count: impl Fn(&[f64], &mut [f64]),
) -> Vec<f64> {
    let step = (mesh.owned_count / ORIENT_SAMPLES).max(1);
    let mut sums = vec![0.0; 2 * parts];
    for v in (0..mesh.owned_count).step_by(step) {
        count(mesh.x(v), &mut sums);
    }
    crate::comm::allreduce_sum_vec(world, &sums)
}

/// The obstacle of a closed surface is the side its normals point away
/// from (the module doc of [`mesh_obstacle`]); a connected part of the
/// surface whose orientation puts most of the body's nodes nearest to it
/// inside the obstacle is read reversed, with a warning naming `option`: a
/// body cannot start inside a rigid obstacle (an interference fit puts a
/// thin layer of it there, never most of it), while the orientation of a
/// curve or surface a user draws in Gmsh is easily the other one (a
/// clockwise groove meant as the solid below it). The body's side is
/// measured on its nodes (up to [`ORIENT_SAMPLES`] per rank, beyond the
/// search distance too), each counted for the part its closest point lies
/// on; the same decision on every rank. Collective.
fn orient_to_body<C: mpi::traits::Communicator>(
    world: &C,
    mesh: &LocalMesh,
    surface: mesh_obstacle::MeshObstacle,
    option: &str,
) -> Result<(mesh_obstacle::MeshObstacle, Option<String>), Error> {
    // Every sampled node counts, however far: a search distance below an
    // interference would leave mostly the nodes inside.
    let search = surface.search_distance();
    let surface = surface.with_search_distance(f64::INFINITY);
    let parts = surface.components();
    // Per part: nodes inside, nodes outside.
    let count = body_sides(world, mesh, parts, |x, count| match surface.closest(x) {
        Some(c) if c.gap != 0.0 => count[2 * c.component + usize::from(c.gap > 0.0)] += 1.0,
        _ => {}
    });
    let surface = surface.with_search_distance(search);
    let flip: Vec<bool> = count.chunks(2).map(|c| c[0] > c[1]).collect();
    let flipped = flip.iter().filter(|&&f| f).count();
    if flipped == 0 {
        return Ok((surface, None));
    }
    let (inside, total) = count
        .chunks(2)
        .zip(&flip)
        .filter(|(_, &f)| f)
        .fold((0.0, 0.0), |(i, t), (c, _)| (i + c[0], t + c[0] + c[1]));
    let what = if parts == 1 {
        "the orientation of its elements".to_string()
    } else {
        format!("the orientation of {flipped} of its {parts} connected parts")
    };
    let warning = format!(
        "{option} {}: {what} put {:.0}% of the body's nodes nearest to {} inside the obstacle; {} read reversed, the obstacle on the side away from the body (a solid's boundary is oriented with its normals outward: counter-clockwise in 2D; a cavity's inward)",
        surface.file(),
        100.0 * inside / total,
        if flipped == 1 { "it" } else { "them" },
        if flipped == 1 { "it is" } else { "they are" },
    );
    Ok((surface.reversed(&flip)?, Some(warning)))
}

/// The contact projection (4.15) with the multiplier update (4.4) at one node:
/// returns `(phi, lambda_next, in_contact)` for normal displacement `un`,
/// multiplier `lambda`, gap `g`, augmentation `r` and step `rho`.
#[inline]
pub fn project_normal(un: f64, lambda: f64, g: f64, r: f64, rho: f64) -> (f64, f64, bool) {
    let gamma = (lambda + r * (un - g)).max(0.0); // (4.14)
    let phi = un + (lambda - gamma) / r; // (4.15)
                                         // (4.4): lambda + rho (un - phi) = lambda + (rho / r)(gamma - lambda); the
                                         // second form gives gamma exactly (so lambda >= 0 exactly) when rho = r.
    let lambda_next = lambda + (rho / r) * (gamma - lambda);
    (phi, lambda_next, gamma > 0.0)
}

/// The friction projection (5.5) with the multiplier update at one node, for
/// tangential displacement `ut`, multiplier `lambda` (both `dim` components,
/// tangent to n) and bound `s`: writes `phi` and `lambda_next`; returns
/// whether the node slips (the first branch of (5.5), `|lambda + r ut| > s`).
#[inline]
pub fn project_tangential(
    ut: &[f64],
    lambda: &[f64],
    s: f64,
    r: f64,
    rho: f64,
    phi: &mut [f64],
    lambda_next: &mut [f64],
) -> bool {
    let d = ut.len();
    let mut q = [0.0; 3];
    for c in 0..d {
        q[c] = lambda[c] + r * ut[c];
    }
    let norm = q[..d].iter().map(|v| v * v).sum::<f64>().sqrt();
    let slip = norm > s;
    // lambda + rho (ut - phi) = lambda + (rho / r)(target - lambda), with
    // target = q s/|q| (slip) or q (stick): |lambda_next| <= s when rho = r.
    let (phi_factor, target_factor) = if slip {
        ((norm - s) / (r * norm), s / norm)
    } else {
        (0.0, 1.0)
    };
    for c in 0..d {
        phi[c] = phi_factor * q[c];
        lambda_next[c] = lambda[c] + (rho / r) * (target_factor * q[c] - lambda[c]);
    }
    slip
}

/// The projection (4.14)-(4.15) with the update (4.4) at rho = r, written on
/// `z = lambda + r u_n` (the only combination of lambda and u_n it reads):
/// returns `(phi, lambda_next, in_contact)` with
/// `lambda_next = (z - r g)^+` and `phi = (z - lambda_next) / r`.
#[inline]
pub fn project_normal_z(z: f64, g: f64, r: f64) -> (f64, f64, bool) {
    let gamma = (z - r * g).max(0.0);
    ((z - gamma) / r, gamma, gamma > 0.0)
}

/// The projection (5.5) with the update at rho = r, on
/// `z = lambda_t + r u_t`: `lambda_next` is z projected onto the ball of
/// radius s, `phi = (z - lambda_next) / r`. Returns whether the node slips.
#[inline]
pub fn project_tangential_z(
    z: &[f64],
    s: f64,
    r: f64,
    phi: &mut [f64],
    lambda_next: &mut [f64],
) -> bool {
    let norm = z.iter().map(|v| v * v).sum::<f64>().sqrt();
    let slip = norm > s;
    let factor = if slip { s / norm } else { 1.0 };
    for c in 0..z.len() {
        lambda_next[c] = factor * z[c];
        phi[c] = (z[c] - lambda_next[c]) / r;
    }
    slip
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The z forms agree with the paper's forms at rho = r.
    #[test]
    fn z_forms_match_the_paper_forms() {
        let r = 2.5;
        for &(un, lam, g) in &[
            (0.5, 0.0, 0.2),
            (-1.0, 2.0, 0.0),
            (0.1, 10.0, 0.3),
            (0.3, 0.1, -0.2),
        ] {
            let (p1, l1, c1) = project_normal(un, lam, g, r, r);
            let (p2, l2, c2) = project_normal_z(lam + r * un, g, r);
            assert!((p1 - p2).abs() < 1e-12 && (l1 - l2).abs() < 1e-12 && c1 == c2);
        }
        let (ut, lt) = ([0.3, -0.4], [0.2, 0.1]);
        for s in [0.0, 0.5, 10.0] {
            let (mut p1, mut l1, mut p2, mut l2) = ([0.0; 2], [0.0; 2], [0.0; 2], [0.0; 2]);
            let a = project_tangential(&ut, &lt, s, r, r, &mut p1, &mut l1);
            let z = [lt[0] + r * ut[0], lt[1] + r * ut[1]];
            let b = project_tangential_z(&z, s, r, &mut p2, &mut l2);
            assert_eq!(a, b);
            for c in 0..2 {
                assert!((p1[c] - p2[c]).abs() < 1e-12 && (l1[c] - l2[c]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn projection_is_feasible_and_idempotent() {
        let r = 3.0;
        for &(un, lam, g) in &[
            (0.5, 0.0, 0.2),
            (-1.0, 2.0, 0.0),
            (0.1, 10.0, 0.3),
            (0.0, 0.0, 0.0),
        ] {
            let (phi, lnext, _) = project_normal(un, lam, g, r, r);
            assert!(phi <= g + 1e-15, "phi {phi} > g {g}");
            assert!(lnext >= 0.0);
            // With rho = r the update is lambda+ = (lambda + r(un - g))^+.
            assert!((lnext - (lam + r * (un - g)).max(0.0)).abs() < 1e-12);
            // Projecting phi itself with the next multiplier is a fixed point.
            let (phi2, l2, _) = project_normal(phi, lnext, g, r, r);
            if lnext > 0.0 {
                assert!((phi2 - g).abs() < 1e-12 && (l2 - lnext).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn large_r_limit_is_the_obstacle_projection() {
        let (phi, _, _) = project_normal(0.5, 0.0, 0.2, 1e12, 1e12);
        assert!((phi - 0.2).abs() < 1e-9);
        let (phi, _, c) = project_normal(0.1, 0.0, 0.2, 1e12, 1e12);
        assert!((phi - 0.1).abs() < 1e-9 && !c);
    }

    #[test]
    fn friction_projection_bounds_and_limits() {
        let r = 2.0;
        let mut phi = [0.0; 2];
        let mut lam = [0.0; 2];
        // Slip: |lambda+| = s, phi along q.
        let slip = project_tangential(&[1.0, 0.5], &[0.3, -0.1], 0.7, r, r, &mut phi, &mut lam);
        assert!(slip);
        let nl = (lam[0] * lam[0] + lam[1] * lam[1]).sqrt();
        assert!((nl - 0.7).abs() < 1e-14);
        let q = [0.3 + 2.0, -0.1 + 1.0];
        assert!((phi[0] * q[1] - phi[1] * q[0]).abs() < 1e-14 && phi[0] * q[0] > 0.0);
        // Stick: phi = 0, lambda+ = lambda + r ut.
        let slip = project_tangential(&[0.01, 0.0], &[0.1, 0.0], 5.0, r, r, &mut phi, &mut lam);
        assert!(!slip && phi == [0.0, 0.0] && (lam[0] - 0.12).abs() < 1e-15);
        // s = 0: frictionless, lambda+ = 0, phi = ut + lambda/r.
        project_tangential(&[0.4, -0.2], &[0.2, 0.0], 0.0, r, r, &mut phi, &mut lam);
        assert!(lam.iter().all(|v| v.abs() < 1e-15));
        assert!((phi[0] - 0.5).abs() < 1e-15 && (phi[1] + 0.2).abs() < 1e-15);
        // Idempotence: projecting the fixed point again changes nothing.
        let (ut, l0) = ([0.3, 0.4], [0.6, 0.0]);
        let mut p1 = [0.0; 2];
        let mut l1 = [0.0; 2];
        project_tangential(&ut, &l0, 0.5, r, r, &mut p1, &mut l1);
        let mut p2 = [0.0; 2];
        let mut l2 = [0.0; 2];
        project_tangential(&p1, &l1, 0.5, r, r, &mut p2, &mut l2);
        assert!((p2[0] - p1[0]).abs() < 1e-14 && (l2[1] - l1[1]).abs() < 1e-14);
    }
}
