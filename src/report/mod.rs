//! What the user sees: the summary on rank 0, the JSON report, the contact
//! CSV, and the comparison with the analytic Hertz pressure.
//!
//! Contact data are gathered on rank 0 (candidates are a surface: few), sorted
//! by the node's tag in the input mesh. Files are written atomically
//! (temporary file in the same directory, then rename).

pub mod files;
pub mod history;
pub mod json;
pub mod plot;
pub mod summary;
pub mod vtk;

use crate::checks::{Deformation, Diagnostics, Forces};
use crate::contact::hertz;
use crate::mesh::distribute::LocalMesh;
use crate::options::{Friction, HertzReference, MeshSource, Settings};
use crate::solver::outcome::Solved;
use crate::solver::surface::UbrState;
use crate::solver::{penalty, Problem};
use mpi::traits::*;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// One contact candidate, as written to the CSV (an MPI datatype of its
/// own, to gather and broadcast the rows).
#[derive(Clone, Debug, Default, Equivalence)]
pub struct ContactRow {
    pub node: u64,
    pub x: [f64; 3],
    pub weight: f64,
    pub gap: f64,
    pub un: f64,
    pub ut: [f64; 3],
    pub lambda_n: f64,
    pub lambda_t: [f64; 3],
    /// 0 open, 1 contact, 2 stick, 3 slip.
    pub status: u8,
    /// The friction bound s (0 without friction; not in the CSV).
    pub bound: f64,
    /// The contact surface: the index of its group in `-contact_surface`
    /// (not in the CSV).
    pub group: usize,
    /// The candidate's unit normal n_i (0 beyond the mesh's dimension).
    pub normal: [f64; 3],
}

impl ContactRow {
    pub fn status_name(&self) -> &'static str {
        ["open", "contact", "stick", "slip"][self.status as usize]
    }
}

/// The owned candidates as rows; `bound` is the friction bound s per
/// candidate (empty without friction).
pub fn contact_rows(
    local: &LocalMesh,
    problem: &Problem,
    state: &UbrState,
    bound: &[f64],
) -> Vec<ContactRow> {
    let d = local.dim;
    let cs = &problem.contact;
    let sf = &state.surface;
    let friction = problem.tangential;
    (0..cs.len())
        .map(|i| {
            let v = cs.node[i];
            let mut x = [0.0; 3];
            x[..d].copy_from_slice(local.x(v));
            let mut ut = [0.0; 3];
            ut[..d].copy_from_slice(&sf.ut[i * d..(i + 1) * d]);
            let mut normal = [0.0; 3];
            normal[..d].copy_from_slice(cs.n(i));
            let mut lt = [0.0; 3];
            if friction {
                lt[..d].copy_from_slice(&sf.stress_t[i * d..(i + 1) * d]);
            }
            let status = match (sf.in_contact[i], friction, sf.slip[i]) {
                (false, _, _) => 0,
                (true, false, _) => 1,
                (true, true, false) => 2,
                (true, true, true) => 3,
            };
            ContactRow {
                node: local.node_tag[v],
                x,
                weight: cs.w[i],
                gap: cs.g[i],
                un: sf.un[i],
                ut,
                // + 0.0 turns -0 into 0 in the CSV
                lambda_n: sf.stress_n[i] + 0.0,
                lambda_t: lt.map(|v| v + 0.0),
                status,
                bound: bound.get(i).copied().unwrap_or(0.0),
                group: cs.group[i],
                normal: normal.map(|v| v + 0.0),
            }
        })
        .collect()
}

/// Wall-clock seconds of each phase (rank 0's).
#[derive(Clone, Debug, Default)]
pub struct Times {
    pub mesh: f64,
    pub partition: f64,
    pub assembly: f64,
    pub factorization: f64,
    pub r_choice: f64,
    pub iterations: f64,
    pub total: f64,
}

/// Sums over the gathered rows (rank 0).
#[derive(Clone, Debug, Default)]
pub struct Totals {
    /// `sum w lambda_n`, `sum w lambda_t`.
    pub force: f64,
    pub tangential_force: Vec<f64>,
    pub in_contact: usize,
    pub stick: usize,
    pub slip: usize,
    pub peak_pressure: f64,
    /// `sum w lambda_n` over the candidates of each contact surface, by
    /// its index in `-contact_surface` (up to the last with a candidate:
    /// see [`Results::group_forces`]); they add up to `force`.
    pub group_force: Vec<f64>,
}

impl Totals {
    pub fn of(rows: &[ContactRow], dim: usize) -> Totals {
        let mut t = Totals {
            tangential_force: vec![0.0; dim],
            ..Default::default()
        };
        for r in rows {
            t.force += r.weight * r.lambda_n;
            if r.group >= t.group_force.len() {
                t.group_force.resize(r.group + 1, 0.0);
            }
            t.group_force[r.group] += r.weight * r.lambda_n;
            for (c, f) in t.tangential_force.iter_mut().enumerate() {
                *f += r.weight * r.lambda_t[c];
            }
            t.in_contact += usize::from(r.status != 0);
            t.stick += usize::from(r.status == 2);
            t.slip += usize::from(r.status == 3);
            t.peak_pressure = t.peak_pressure.max(r.lambda_n);
        }
        t
    }
}

/// Everything the summary and the report show (on rank 0).
pub struct Results<'a> {
    pub settings: &'a Settings,
    pub local: &'a LocalMesh,
    pub ranks: usize,
    pub candidates: usize,
    pub problem: &'a Problem,
    pub choice: Option<&'a penalty::Choice>,
    pub solved: &'a Solved,
    pub state: &'a UbrState,
    pub diag: &'a Diagnostics,
    pub forces: &'a Forces,
    pub shape: &'a Deformation,
    /// Every candidate, gathered, sorted by node tag.
    pub rows: &'a [ContactRow],
    pub totals: Totals,
    pub hertz: Option<HertzComparison>,
    pub times: Times,
    /// Peak memory (MiB): rank 0, the largest rank, all ranks.
    pub memory: [f64; 3],
    /// The warnings of the run (also printed on stderr).
    pub warnings: &'a [String],
    /// The message the run ends with when it fails (exit status 3 or 4).
    pub failure: Option<String>,
}

impl Results<'_> {
    /// The friction law's name in the summary.
    pub fn friction_name(&self) -> &'static str {
        match self.settings.friction {
            Friction::None => "frictionless",
            Friction::Tresca => "Tresca friction",
            Friction::Coulomb => "Coulomb friction",
        }
    }

    /// The contact force `sum w lambda_n` of each group of
    /// `-contact_surface`, in its order (a group named twice counts once),
    /// then of each contact pair's slave surface.
    pub fn group_forces(&self) -> Vec<(String, f64)> {
        let names: Vec<&String> = self
            .settings
            .contact
            .as_ref()
            .map(|c| {
                c.surfaces
                    .iter()
                    .chain(c.pairs.iter().map(|p| &p.0))
                    .collect()
            })
            .unwrap_or_default();
        let mut out: Vec<(String, f64)> = Vec::with_capacity(names.len());
        for (k, name) in names.iter().enumerate() {
            let f = self.totals.group_force.get(k).copied().unwrap_or(0.0);
            match out.iter_mut().find(|(n, _)| n == *name) {
                Some((_, g)) => *g += f,
                None => out.push(((*name).clone(), f)),
            }
        }
        out
    }
}

/// This process's peak resident memory in MiB (VmHWM from /proc/self/status; 0 if unknown).
pub fn peak_memory_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
        })
        .map(|kb| kb / 1024.0)
        .unwrap_or(0.0)
}

/// The mesh as the summary names it.
pub fn mesh_label(source: &MeshSource) -> String {
    match source {
        MeshSource::File(p) => p.clone(),
        MeshSource::Generate { name, h, q1 } => format!(
            "generated {name}, h = {}{}",
            // Rust writes every digit of 1e300 in plain notation.
            if (1e-4..1e6).contains(h) {
                format!("{h}")
            } else {
                format!("{h:e}")
            },
            match (q1, name.as_str()) {
                (false, _) => "",
                (true, "hertz2d") => ", quadrilaterals",
                (true, _) => ", hexahedra",
            }
        ),
    }
}

/// Gathers every rank's rows on rank 0, sorted by node tag (empty elsewhere).
pub fn gather_rows<C: Communicator>(world: &C, rows: &[ContactRow]) -> Vec<ContactRow> {
    let mut all = files::gather(world, rows);
    all.sort_by_key(|r| r.node);
    all
}

/// Sends rank 0's rows to every rank (for outputs every rank writes).
pub fn broadcast_rows<C: Communicator>(world: &C, rows: &[ContactRow]) -> Vec<ContactRow> {
    let root = world.process_at_rank(0);
    let mut len = [rows.len() as u64];
    root.broadcast_into(&mut len[..]);
    let mut all = if world.rank() == 0 {
        rows.to_vec()
    } else {
        vec![ContactRow::default(); len[0] as usize]
    };
    root.broadcast_into(&mut all[..]);
    all
}

/// The Hertz comparison, computed on rank 0 from the gathered rows.
#[derive(Clone, Debug, Default)]
pub struct HertzComparison {
    pub error_l2: f64,
    pub error_rel: f64,
    pub peak: f64,
    pub peak_hertz: f64,
    pub half_width: f64,
    pub half_width_hertz: f64,
    /// The candidates within Hertz's half-width of the centre, and the
    /// distance from the centre to the nearest other candidate (the mesh's
    /// spacing there).
    pub zone_candidates: usize,
    pub spacing: f64,
    /// The candidates in contact.
    pub touching: usize,
    /// The model's contact force `sum w lambda_n`, `-reference_force`, and
    /// the part of the whole contact the model carries (1/2 for each
    /// symmetry plane that cuts its contact zone at the centre:
    /// [`hertz::symmetric_part`]).
    pub force: f64,
    pub reference_force: f64,
    pub part: f64,
    /// Hertz's E* and R ([`crate::options::Settings::e_star`], the
    /// curvatures of `-reference_radius` added).
    pub e_star: f64,
    pub radius: f64,
    /// Hertz's cylinder formula (2D, or 3D along `-reference_axis`): the
    /// zone has a half-width, `force` is per unit length over `length`
    /// (the candidates' extent along the line, 3D).
    pub line: bool,
    pub length: f64,
    /// 3D with the sphere's formula: the zone's extents along and across
    /// its longest direction, and that direction ([`elongation`]).
    pub elongation: Option<(f64, f64, Vec<f64>)>,
}

impl HertzComparison {
    /// Where nothing touches, the comparison has nothing to compare; where
    /// Hertz's contact zone holds fewer than 3 candidates, it measures the
    /// mesh, not the solve: the warning that says so.
    pub fn resolution_warning(&self) -> Option<String> {
        if self.touching == 0 {
            return Some(
                "no contact candidate touches the obstacle: -reference hertz compares Hertz's pressure with none (the 'peak pressure' is what the iteration leaves on open candidates, within the tolerance)"
                    .to_string(),
            );
        }
        (self.zone_candidates < 3).then(|| {
            let nearest = if self.spacing.is_finite() {
                format!(
                    " (the nearest candidate to the centre is {:.4e} from it)",
                    self.spacing
                )
            } else {
                String::new()
            };
            format!(
                "Hertz's contact half-width {:.4e} holds {} contact candidate{}{nearest}: the mesh cannot resolve Hertz's pressure there, so the comparison measures the mesh, not the solution; refine the contact surface to a spacing of about a fifth of the half-width",
                self.half_width_hertz,
                self.zone_candidates,
                if self.zone_candidates == 1 { "" } else { "s" },
            )
        })
    }

    /// Hertz's load against the model's: where the model's contact force
    /// is not its part of `-reference_force` (within 5%), the comparison
    /// uses a load the model does not carry (the half model's own force
    /// given for the whole contact's: 83% "error" on the shipped Hertz
    /// scene; a displacement-driven scene whose force was guessed).
    pub fn force_warning(&self) -> Option<String> {
        let (f, r, part) = (self.force, self.reference_force, self.part);
        if self.touching == 0 || ((f - part * r) / (part * r)).abs() <= 0.05 {
            return None;
        }
        let cut = if part == 1.0 {
            "the whole contact (its contact zone spreads on both sides of the centre)".to_string()
        } else if part == 0.5 {
            "half of the contact (its contact zone lies on one side of the centre: a model cut by a symmetry plane)".to_string()
        } else {
            format!("{part} of the contact (its contact zone lies on one side of the centre along two axes: a model cut by two symmetry planes)")
        };
        let force = if self.length > 0.0 {
            format!(
                "contact force per unit length is {f:.4e} ({:.4e} over its length {:.4e} along -reference_axis)",
                f * self.length,
                self.length
            )
        } else {
            format!("contact force is {f:.4e}")
        };
        Some(format!(
            "-reference_force {}: the model's {force}, and the model carries {cut}, so the whole contact's load is {:.4e}, not {}; the Hertz comparison uses a load the model does not carry",
            crate::options::shown(r),
            f / part,
            crate::options::shown(r),
        ))
    }

    /// 3D with the sphere's formula: a contact zone over three times as
    /// long as it is wide (a sphere's is a disc, a half or a quarter of
    /// one in a model cut by symmetry planes: at most twice), a line
    /// contact (a cylinder on its side) that the sphere's formula does not
    /// describe: the warning that names `-reference_axis`.
    pub fn shape_warning(&self) -> Option<String> {
        let (long, across, dir) = self.elongation.as_ref()?;
        if *long <= 3.0 * across {
            return None;
        }
        Some(format!(
            "-reference hertz: the contact zone is {long:.4e} long (along ({:.3}, {:.3}, {:.3})) and {across:.4e} across, a line contact, where Hertz's formula in 3D is a sphere's (a circle of radius {:.4e} here); for a cylinder on its side give its axis, -reference_axis x,y,z (Hertz's line contact, -reference_force per unit length of the whole cylinder)",
            dir[0], dir[1], dir[2], self.half_width_hertz
        ))
    }
}

/// The contact pressure against Hertz's, at the candidates `rows` (rank 0).
pub fn compare_hertz(
    rows: &[ContactRow],
    dim: usize,
    n: &[f64],
    e_star: f64,
    reference: &HertzReference,
) -> HertzComparison {
    let center = hertz::center(
        reference.center.as_deref(),
        dim,
        rows.iter().map(|r| (r.gap, &r.x[..])),
    );
    let line = reference.line(n);
    let mut err2 = 0.0;
    let mut p2 = 0.0;
    let mut out = HertzComparison {
        spacing: f64::INFINITY,
        reference_force: reference.force,
        e_star,
        radius: reference.radius,
        line: reference.formula_dim(dim) == 2,
        ..HertzComparison::default()
    };
    for r in rows {
        let (p, p0, b, x) = reference.pressure_at(dim, e_star, &r.x, &center, n);
        if p > 0.0 {
            out.zone_candidates += 1;
        }
        if x > 0.0 {
            out.spacing = out.spacing.min(x);
        }
        if r.status != 0 {
            out.touching += 1;
        }
        out.force += r.weight * r.lambda_n;
        err2 += r.weight * (r.lambda_n - p).powi(2);
        p2 += r.weight * p * p;
        out.peak = out.peak.max(r.lambda_n);
        out.peak_hertz = p0;
        out.half_width_hertz = b;
        if r.status != 0 && r.lambda_n > 0.0 {
            out.half_width = out.half_width.max(x);
        }
    }
    let offsets: Vec<Vec<f64>> = rows
        .iter()
        .filter(|r| r.status != 0)
        .map(|r| hertz::tangential_offset(&r.x, &center, n))
        .collect();
    out.part = hertz::symmetric_part(&offsets, n, line.as_deref());
    if let Some(l) = &line {
        // The force per unit length: over the candidates' length along
        // the line (the cylinder's, in the model).
        let along = rows
            .iter()
            .map(|r| r.x.iter().zip(l).map(|(a, b)| a * b).sum::<f64>());
        let (lo, hi) = along.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        out.length = hi - lo;
        if out.length > 0.0 {
            out.force /= out.length;
        }
    } else if dim == 3 {
        out.elongation = elongation(&offsets);
    }
    out.error_l2 = err2.sqrt();
    out.error_rel = if p2 > 0.0 { (err2 / p2).sqrt() } else { 0.0 };
    out
}

/// Of a contact zone in 3D (`offsets`: the tangential offsets of the
/// candidates in contact), its extents along and across its longest
/// principal direction, and that direction.
fn elongation(offsets: &[Vec<f64>]) -> Option<(f64, f64, Vec<f64>)> {
    if offsets.len() < 6 {
        return None;
    }
    let k = offsets.len() as f64;
    let mean: Vec<f64> = (0..3)
        .map(|c| offsets.iter().map(|o| o[c]).sum::<f64>() / k)
        .collect();
    let cov = nalgebra::Matrix3::from_fn(|i, j| {
        offsets
            .iter()
            .map(|o| (o[i] - mean[i]) * (o[j] - mean[j]))
            .sum::<f64>()
    });
    let eig = cov.symmetric_eigen();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let extent = |c: usize| {
        let v = eig.eigenvectors.column(c);
        let along = offsets
            .iter()
            .map(|o| o[0] * v[0] + o[1] * v[1] + o[2] * v[2]);
        let (lo, hi) = along.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        });
        hi - lo
    };
    let v = eig.eigenvectors.column(order[0]);
    Some((extent(order[0]), extent(order[1]), vec![v[0], v[1], v[2]]))
}

/// Writes `bytes` to `path` atomically: a temporary file in the same
/// directory, then a rename; on failure the temporary file is removed, so a
/// reader never sees a partial file. The one writer of every output file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let Some(name) = path.file_name() else {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a file path",
        ));
    };
    let tmp = dir.join(format!(
        ".{}.tmp{}-{}",
        name.to_string_lossy(),
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

pub fn csv(rows: &[ContactRow]) -> String {
    let mut s = String::from(
        "node,x,y,z,weight,gap,un,ut_x,ut_y,ut_z,lambda_n,lambda_t_x,lambda_t_y,lambda_t_z,status,n_x,n_y,n_z\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{:e},{:e},{:e}",
            r.node,
            r.x[0],
            r.x[1],
            r.x[2],
            r.weight,
            r.gap,
            r.un,
            r.ut[0],
            r.ut[1],
            r.ut[2],
            r.lambda_n,
            r.lambda_t[0],
            r.lambda_t[1],
            r.lambda_t[2],
            r.status_name(),
            r.normal[0],
            r.normal[1],
            r.normal[2]
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("ubr-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("out.json");
        write_atomic(&p, b"{}").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"{}");
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(names.len(), 1);
        let bad = dir.join("missing/out.json");
        assert!(write_atomic(&bad, b"{}").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn mesh_label_writes_h_briefly() {
        let label = |h: f64| {
            mesh_label(&MeshSource::Generate {
                name: "block3d".into(),
                h,
                q1: false,
            })
        };
        assert_eq!(label(0.0333), "generated block3d, h = 0.0333");
        assert_eq!(label(5.0), "generated block3d, h = 5");
        assert_eq!(label(1e300), "generated block3d, h = 1e300");
        assert_eq!(label(2.5e-5), "generated block3d, h = 2.5e-5");
    }
}
