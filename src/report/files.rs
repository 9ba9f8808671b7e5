//! The output files: the contact CSV, the JSON report and the plots
//! (rank 0), and the ParaView files: `-vtk FILE.vtu` gathers the mesh on
//! rank 0 into one file, `-vtk PATH.pvtu` has every rank write its piece.
//! Every file is written atomically; a failure on any rank fails the run.

use super::vtk::{self, Field, Piece};
use super::{json, plot, ContactRow, Results};
use crate::contact::hertz;
use crate::error::Error;
use crate::mesh::distribute::LocalMesh;
use crate::options::{Friction, Settings};
use crate::solver::stopping::StopRule;
use mpi::collective::SystemOperation;
use mpi::traits::*;
use std::path::Path;

/// Rank 0's files: the plots, the contact CSV, the report.
pub fn write_root_files(m: &Results) -> Result<(), Error> {
    let s = m.settings;
    let mut first_error = None;
    let mut keep = |r: Result<(), Error>| {
        if let Err(e) = r {
            first_error.get_or_insert(e);
        }
    };
    if let Some(path) = &s.plot_contact {
        keep(plot_contact(path, m));
    }
    if let Some(path) = &s.plot_history {
        keep(plot_history(path, m));
    }
    if let Some(path) = &s.contact_output {
        keep(
            super::write_atomic(Path::new(path), super::csv(m.rows).as_bytes())
                .map_err(|e| Error::output("-contact_output", path, e)),
        );
    }
    if let Some(path) = &s.report {
        let text = json::Report::new(m).to_json();
        keep(
            super::write_atomic(Path::new(path), text.as_bytes())
                .map_err(|e| Error::output("-report", path, e)),
        );
    }
    first_error.map_or(Ok(()), Err)
}

/// Makes a write failure on any rank the failure of all: every rank
/// returns the error of the lowest rank that failed (its message sent to
/// the others, so that rank 0 prints the file and the reason), or its own.
pub fn collective<C: Communicator>(world: &C, outcome: Result<(), Error>) -> Result<(), Error> {
    let size = world.size();
    let mine = if outcome.is_err() { world.rank() } else { size };
    let mut first = size;
    world.all_reduce_into(&mine, &mut first, SystemOperation::min());
    if first == size {
        return outcome;
    }
    let mut text = match &outcome {
        Err(e) if world.rank() == first => e.to_string().into_bytes(),
        _ => Vec::new(),
    };
    let root = world.process_at_rank(first);
    let mut len = text.len() as u64;
    root.broadcast_into(&mut len);
    text.resize(len as usize, 0);
    root.broadcast_into(&mut text[..]);
    match outcome {
        Err(e) => Err(e),
        Ok(()) => {
            let text = String::from_utf8_lossy(&text);
            let message = text.strip_prefix("error: ").unwrap_or(&text);
            Err(Error::BadInput(format!("{message} (on rank {first})")))
        }
    }
}

/// `-plot_history`: per iteration, the paper's change (4.16)/(5.6) where
/// it was computed (not in a condensed run under the accuracy stop), the
/// constraint residual, and under the accuracy stop the error estimate of
/// lambda with the target that stops the run ([`plot::history_curves`]).
fn plot_history(path: &str, m: &Results) -> Result<(), Error> {
    use plot::{plot_lines, Series, Style};
    let h = &m.state.history;
    let its: Vec<f64> = (0..h.len()).map(|k| k as f64).collect();
    let accuracy = (m.settings.ubr.stop == StopRule::Accuracy && !m.solved.is_comparator())
        .then_some(m.settings.ubr.lambda_rtol);
    let coulomb = m.solved.fixed_point_iterations > 0;
    let curves = plot::history_curves(h, Some(m.solved.last.criterion), accuracy, coulomb);
    let series: Vec<Series> = curves
        .iter()
        .map(|c| Series {
            label: &c.label,
            x: &its,
            y: &c.y,
            style: if c.dashed {
                Style::DashedLine
            } else {
                Style::Line
            },
        })
        .collect();
    let note = match curves
        .iter()
        .find(|c| c.label.starts_with("relative change"))
    {
        Some(c) if !c.label.contains("end only") => "",
        _ if m.problem.lin.condensed_unknowns() > 0 => {
            " (condensed solves: no change (4.16) per iteration)"
        }
        _ => " (no change (4.16) per iteration)",
    };
    let x_label = if coulomb {
        "Tresca iteration (those of every fixed-point iteration, in a row)"
    } else {
        "iteration"
    };
    plot_lines(
        Path::new(path),
        &format!("{}: convergence history{note}", m.solved.name),
        x_label,
        "value (log scale)",
        &series,
        true,
    )
    .map_err(|e| Error::output("-plot_history", path, e))
}

/// The centre `-plot_contact` measures from: `-reference_center`, else the
/// candidate with the smallest gap when one has it alone, else (a flat
/// contact) the centre of the contact pressure.
fn plot_center(given: Option<&[f64]>, rows: &[ContactRow], d: usize) -> Vec<f64> {
    let gmin = rows.iter().map(|r| r.gap).fold(f64::INFINITY, f64::min);
    let scale = rows
        .iter()
        .fold(0.0f64, |a, r| a.max(r.gap.abs()))
        .max(1e-300);
    let at_min = rows.iter().filter(|r| r.gap - gmin <= 1e-9 * scale).count();
    let force: f64 = rows.iter().map(|r| r.weight * r.lambda_n).sum();
    if given.is_some() || at_min <= 1 || force <= 0.0 {
        return hertz::center(given, d, rows.iter().map(|r| (r.gap, &r.x[..])));
    }
    (0..d)
        .map(|k| {
            rows.iter()
                .map(|r| r.weight * r.lambda_n * r.x[k])
                .sum::<f64>()
                / force
        })
        .collect()
}

/// The Hertz pressure of `-reference hertz` at 401 points across the zoom
/// (else across the candidates at `x`, sorted); empty without a reference.
fn hertz_curve(
    s: &Settings,
    d: usize,
    x: &[f64],
    zoom: Option<&std::ops::Range<f64>>,
) -> (Vec<f64>, Vec<f64>) {
    let Some(r) = &s.reference else {
        return (Vec::new(), Vec::new());
    };
    let (lo, hi) = match zoom {
        Some(z) => (z.start, z.end),
        None => (
            x.first().copied().unwrap_or(0.0),
            x.last().copied().unwrap_or(0.0),
        ),
    };
    (0..=400)
        .map(|k| {
            let xi = lo + (hi - lo) * k as f64 / 400.0;
            let p = r.pressure(d, s.e_star(d), xi.abs()).0;
            (xi, p)
        })
        .unzip()
}

/// The candidates of the contact's side of the body: those no farther from
/// the tangent plane at `center` (along `n`) than the zone of the nodes in
/// contact spreads along it and across it. The far side of a whole disc
/// or ball has the near side's coordinates: its open candidates fell among
/// those in contact, and the 2D bound's line zigzagged to them.
fn near_side(
    rows: &[ContactRow],
    center: &[f64],
    n: &[f64],
    coordinate: impl Fn(&ContactRow) -> f64,
) -> Vec<usize> {
    let off = |r: &ContactRow| hertz::normal_offset(&r.x, center, n).abs();
    let touching = rows.iter().filter(|r| r.status != 0);
    let (along, across) = touching.fold((0.0f64, 0.0f64), |(a, c), r| {
        (a.max(coordinate(r).abs()), c.max(off(r)))
    });
    let reach = along + across;
    (0..rows.len())
        .filter(|&i| reach == 0.0 || off(&rows[i]) <= reach)
        .collect()
}

/// `-plot_contact`: pressure, and with friction |lambda_t| and the bound s,
/// along the surface (2D: a signed coordinate from the contact centre, so
/// that both sides of an asymmetric contact show; 3D: the distance from
/// it, scattered points), with the Hertz curve under `-reference hertz`;
/// zoomed on the contact zone ([`plot::contact_zoom`]), the stress axis
/// from zero, the 2D bound's line broken between surfaces and at holes.
fn plot_contact(path: &str, m: &Results) -> Result<(), Error> {
    use plot::{plot_with_axes, Axes, Series, Style};
    let (s, rows, d) = (m.settings, m.rows, m.local.dim);
    let n = &m.problem.contact.direction;
    let given = s
        .contact_center
        .as_deref()
        .or(s.reference.as_ref().and_then(|r| r.center.as_deref()));
    let center = plot_center(given, rows, d);
    let coordinate = |r: &ContactRow| match (d, &s.reference) {
        (2, _) => hertz::coordinate_2d(&r.x, &center, n),
        (_, Some(h)) => h.distance(&r.x, &center, n),
        _ => hertz::distance(&r.x, &center, n),
    };
    let mut order = near_side(rows, &center, n, coordinate);
    order.sort_by(|&a, &b| coordinate(&rows[a]).total_cmp(&coordinate(&rows[b])));
    let x: Vec<f64> = order.iter().map(|&i| coordinate(&rows[i])).collect();
    let p: Vec<f64> = order.iter().map(|&i| rows[i].lambda_n).collect();
    let lt: Vec<f64> = order
        .iter()
        .map(|&i| rows[i].lambda_t.iter().map(|v| v * v).sum::<f64>().sqrt())
        .collect();
    let bound: Vec<f64> = order.iter().map(|&i| rows[i].bound).collect();
    let group: Vec<usize> = order.iter().map(|&i| rows[i].group).collect();
    let touching: Vec<bool> = order.iter().map(|&i| rows[i].status != 0).collect();
    let zoom = plot::contact_zoom(&x, &touching);
    let (bx, by) = plot::break_lines(&x, &bound, &group);
    // 3D: the bound at the nodes in contact (elsewhere it is 0, as the
    // pressure shows).
    let touching_bound: Vec<f64> = bound
        .iter()
        .zip(&touching)
        .map(|(&b, &t)| if t { b } else { f64::NAN })
        .collect();
    let mut series = vec![Series {
        label: "contact pressure lambda_n",
        x: &x,
        y: &p,
        style: Style::Points,
    }];
    if s.friction != Friction::None {
        series.push(Series {
            label: "|tangential traction lambda_t|",
            x: &x,
            y: &lt,
            style: Style::Points,
        });
        // In 3D the distance does not order the nodes along a curve: the
        // bound at each node, not a line through them.
        series.push(if d == 2 {
            Series {
                label: "friction bound s",
                x: &bx,
                y: &by,
                style: Style::Line,
            }
        } else {
            Series {
                label: "friction bound s (at each node in contact)",
                x: &x,
                y: &touching_bound,
                style: Style::Rings,
            }
        });
    }
    let (hx, hy) = hertz_curve(s, d, &x, zoom.as_ref());
    if s.reference.is_some() {
        series.push(Series {
            label: "Hertz pressure",
            x: &hx,
            y: &hy,
            style: Style::DashedLine,
        });
    }
    let title = format!(
        "Contact stresses ({}): {} of {} candidates in contact{}",
        m.friction_name(),
        touching.iter().filter(|&&t| t).count(),
        rows.len(),
        if zoom.is_some() {
            ", zoomed on the contact zone"
        } else {
            ""
        }
    );
    let line = s.reference.as_ref().and_then(|h| h.line(n)).is_some();
    let axis = if d == 2 {
        "position along the surface from the contact centre (signed, orthogonal to n)"
    } else if line {
        "distance from the contact line (along -reference_axis), orthogonal to n"
    } else {
        "distance from the contact centre, orthogonal to n"
    };
    let axes = Axes {
        x_range: zoom,
        y_from_zero: true,
    };
    plot_with_axes(
        Path::new(path),
        &title,
        axis,
        "stress",
        &series,
        false,
        &axes,
    )
    .map_err(|e| Error::output("-plot_contact", path, e))
}

/// The fields of one rank's part of the mesh, for the ParaView files.
struct PieceData {
    /// The cells this rank writes (those whose smallest global node it
    /// owns), where each ends in `cells`, and their fields.
    cells: Vec<usize>,
    offsets: Vec<usize>,
    stress: Vec<f64>,
    von_mises: Vec<f64>,
    /// Point fields at the local nodes.
    disp: Vec<f64>,
    pressure: Vec<f64>,
    traction: Vec<f64>,
    gap: Vec<f64>,
    status: Vec<i32>,
    /// With contact pairs: the traction the slaves put on the master
    /// nodes (0 elsewhere).
    master: Option<Vec<f64>>,
}

/// The cells this rank writes with their stresses, and the point fields at
/// its local nodes (`rows`: every candidate, on every rank).
fn piece_data(
    s: &Settings,
    local: &LocalMesh,
    u_local: &[f64],
    rows: &[ContactRow],
    master: Option<&[(u64, f64)]>,
) -> PieceData {
    let d = local.dim;
    let k = d + 1;
    // Cells this rank writes.
    let mine: Vec<usize> = (0..local.num_cells())
        .filter(|&c| {
            let gmin = local
                .cells
                .get(c)
                .iter()
                .map(|&v| local.node_global[v])
                .min()
                .unwrap_or(0);
            gmin >= local.owned_start && gmin < local.owned_start + local.owned_count
        })
        .collect();
    let mut cells = Vec::with_capacity(mine.len() * k);
    let mut offsets = Vec::with_capacity(mine.len());
    let mut stress = Vec::with_capacity(mine.len() * 9);
    let mut von_mises = Vec::with_capacity(mine.len());
    let mut xs = Vec::with_capacity(8 * d);
    let mut us = Vec::with_capacity(8 * d);
    for &c in &mine {
        let cell = local.cells.get(c);
        xs.clear();
        us.clear();
        for &v in cell {
            xs.extend_from_slice(local.x(v));
            us.extend_from_slice(&u_local[v * d..(v + 1) * d]);
        }
        cells.extend_from_slice(cell);
        offsets.push(cells.len());
        // Each cell's own material (-E_NAME, -nu_NAME on its body group).
        let m = crate::fem::material::of_cell(local, s, c);
        let (sig, vm) = crate::fem::stress::cell_stress(d, &xs, &us, m.young, m.nu, s.plane_stress);
        stress.extend_from_slice(&sig);
        von_mises.push(vm);
    }
    // Contact fields at the nodes (-1 status: not a candidate).
    let by_tag: std::collections::HashMap<u64, &ContactRow> =
        rows.iter().map(|r| (r.node, r)).collect();
    let npts = local.num_local_nodes();
    let mut out = PieceData {
        cells,
        offsets,
        stress,
        von_mises,
        disp: vec![0.0; npts * 3],
        pressure: vec![0.0; npts],
        traction: vec![0.0; npts * 3],
        gap: vec![0.0; npts],
        status: vec![-1i32; npts],
        master: master.map(|m| {
            let by_tag: std::collections::HashMap<u64, f64> = m.iter().copied().collect();
            (0..npts)
                .map(|v| by_tag.get(&local.node_tag[v]).copied().unwrap_or(0.0))
                .collect()
        }),
    };
    for v in 0..npts {
        out.disp[v * 3..v * 3 + d].copy_from_slice(&u_local[v * d..(v + 1) * d]);
        if let Some(r) = by_tag.get(&local.node_tag[v]) {
            out.pressure[v] = r.lambda_n;
            out.traction[v * 3..v * 3 + 3].copy_from_slice(&r.lambda_t);
            out.gap[v] = r.gap;
            out.status[v] = r.status as i32;
        }
    }
    out
}

/// `-vtk`: `FILE.vtu` (one file, gathered on rank 0) or `PATH.pvtu` (an
/// index and a piece per rank). Both carry the node tag of the mesh file;
/// `master`: the contact pairs' traction on the master nodes, by node tag
/// (the field `master_traction`).
pub fn write_vtk<C: Communicator>(
    world: &C,
    path: &str,
    (s, local): (&Settings, &LocalMesh),
    u_local: &[f64],
    rows: &[ContactRow],
    master: Option<&[(u64, f64)]>,
) -> Result<(), Error> {
    let data = piece_data(s, local, u_local, rows, master);
    let rank = world.rank();
    let ranks = vec![rank; data.von_mises.len()];
    if path.ends_with(".vtu") {
        return write_gathered(world, path, local, &data, &ranks);
    }
    let bad_path = |e: std::io::Error| Error::output("-vtk", path, e);
    let target = Path::new(path);
    let stem_path = target.with_extension("");
    let stem = stem_path
        .file_name()
        .map(|x| x.to_string_lossy().into_owned())
        .unwrap_or_else(|| "ubr".into());
    let dir = stem_path
        .parent()
        .filter(|x| !x.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .to_path_buf();
    let piece = Piece {
        dim: local.dim,
        coords: &local.coords,
        cells: &data.cells,
        offsets: &data.offsets,
        point_data: point_fields(&data, &local.node_tag),
        cell_data: cell_fields(&data, &ranks),
    };
    let name = vtk::piece_file_name(&stem, rank as usize);
    let own = stem_path.with_file_name(&name);
    // (The error names the piece.)
    let written =
        vtk::write_vtu(&own, &piece).map_err(|e| Error::BadInput(format!("option -vtk: {e}")));
    // The index only over pieces that are all there; a piece alone is half
    // an output, and is removed.
    let wrote = written.is_ok();
    if let Err(e) = collective(world, written) {
        if wrote {
            let _ = std::fs::remove_file(&own);
        }
        return Err(e);
    }
    if rank == 0 {
        let names: Vec<String> = (0..world.size() as usize)
            .map(|r| vtk::piece_file_name(&stem, r))
            .collect();
        vtk::write_pvtu(
            &dir.join(format!("{stem}.pvtu")),
            &names,
            &piece.point_fields(),
            &piece.cell_fields(),
        )
        .map_err(bad_path)?;
        remove_stale_pieces(&stem_path, &stem, names.len());
    }
    Ok(())
}

/// Removes the pieces `{stem}_{k}.vtu`, k = `from`, `from + 1`, ..., that
/// an earlier run on more ranks left beside the index (until one is
/// missing, or is not a VTK unstructured grid): the index does not name
/// them, but ParaView offers `{stem}_0..k.vtu` as one time series, in
/// which a stale piece looks like a step of this run.
fn remove_stale_pieces(stem_path: &Path, stem: &str, from: usize) {
    use std::io::Read as _;
    for k in from.. {
        let piece = stem_path.with_file_name(vtk::piece_file_name(stem, k));
        let mut head = [0u8; 256];
        let n = std::fs::File::open(&piece).and_then(|mut f| f.read(&mut head));
        let ours = n.is_ok_and(|n| {
            String::from_utf8_lossy(&head[..n]).contains("<VTKFile type=\"UnstructuredGrid\"")
        });
        if !ours || std::fs::remove_file(&piece).is_err() {
            return;
        }
    }
}

fn point_fields<'a>(p: &'a PieceData, tags: &'a [u64]) -> Vec<Field<'a>> {
    let mut fields = vec![
        Field::Vector("displacement", &p.disp),
        Field::Scalar("contact_pressure", &p.pressure),
        Field::Vector("tangential_traction", &p.traction),
        Field::Scalar("gap", &p.gap),
        Field::Int("contact_status", &p.status),
        Field::Id("node_tag", tags),
    ];
    if let Some(m) = &p.master {
        fields.push(Field::Scalar("master_traction", m));
    }
    fields
}

fn cell_fields<'a>(p: &'a PieceData, ranks: &'a [i32]) -> Vec<Field<'a>> {
    vec![
        Field::Tensor("stress", &p.stress),
        Field::Scalar("von_mises", &p.von_mises),
        Field::Int("rank", ranks),
    ]
}

/// Every rank's `mine` concatenated in rank order on rank 0 (empty elsewhere).
pub(super) fn gather<C: Communicator, T: Equivalence + Clone>(world: &C, mine: &[T]) -> Vec<T> {
    if world.rank() != 0 {
        world.process_at_rank(0).send(mine);
        return Vec::new();
    }
    let mut all = mine.to_vec();
    for p in 1..world.size() {
        let (v, _) = world.process_at_rank(p).receive_vec::<T>();
        all.extend(v);
    }
    all
}

/// `-vtk FILE.vtu`: the owned nodes of every rank (in global order: the
/// ranks own consecutive blocks) and the cells each writes, gathered on
/// rank 0 into one file: each node once, each cell once.
fn write_gathered<C: Communicator>(
    world: &C,
    path: &str,
    local: &LocalMesh,
    data: &PieceData,
    ranks: &[i32],
) -> Result<(), Error> {
    let d = local.dim;
    let own = local.owned_count;
    let cells: Vec<u64> = data
        .cells
        .iter()
        .map(|&v| local.node_global[v] as u64)
        .collect();
    let coords = gather(world, &local.coords[..own * d]);
    let tags = gather(world, &local.node_tag[..own]);
    let disp = gather(world, &data.disp[..own * 3]);
    let traction = gather(world, &data.traction[..own * 3]);
    let pressure = gather(world, &data.pressure[..own]);
    let gap = gather(world, &data.gap[..own]);
    let status = gather(world, &data.status[..own]);
    let master = data.master.as_ref().map(|m| gather(world, &m[..own]));
    let cells = gather(world, &cells);
    let sizes: Vec<u64> = data
        .offsets
        .iter()
        .scan(0, |prev, &end| {
            let size = end - *prev;
            *prev = end;
            Some(size as u64)
        })
        .collect();
    let sizes = gather(world, &sizes);
    let stress = gather(world, &data.stress);
    let von_mises = gather(world, &data.von_mises);
    let ranks = gather(world, ranks);
    if world.rank() != 0 {
        return Ok(());
    }
    let all = PieceData {
        cells: cells.iter().map(|&v| v as usize).collect(),
        offsets: sizes
            .iter()
            .scan(0, |end, &size| {
                *end += size as usize;
                Some(*end)
            })
            .collect(),
        stress,
        von_mises,
        disp,
        pressure,
        traction,
        gap,
        status,
        master,
    };
    let piece = Piece {
        dim: d,
        coords: &coords,
        cells: &all.cells,
        offsets: &all.offsets,
        point_data: point_fields(&all, &tags),
        cell_data: cell_fields(&all, &ranks),
    };
    vtk::write_vtu(Path::new(path), &piece).map_err(|e| Error::output("-vtk", path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(x: f64, gap: f64, lambda_n: f64) -> ContactRow {
        ContactRow {
            x: [x, 0.0, 0.0],
            gap,
            lambda_n,
            weight: 1.0,
            ..Default::default()
        }
    }

    #[test]
    fn the_plot_centre() {
        // A curved contact: the candidate with the smallest gap.
        let curved = [row(0.0, 0.3, 0.0), row(1.0, 0.1, 2.0), row(2.0, 0.2, 1.0)];
        assert_eq!(plot_center(None, &curved, 2), vec![1.0, 0.0]);
        // Given, it wins (with or without a Hertz reference).
        assert_eq!(plot_center(Some(&[5.0, 1.0]), &curved, 2), vec![5.0, 1.0]);
        // A flat contact (equal gaps): the centre of pressure, not the
        // first candidate found.
        let flat = [row(0.0, 0.0, 1.0), row(1.0, 0.0, 1.0), row(2.0, 0.0, 2.0)];
        let c = plot_center(None, &flat, 2);
        assert!((c[0] - 1.25).abs() < 1e-15 && c[1] == 0.0, "{c:?}");
    }

    #[test]
    fn the_far_side_of_a_disc_is_not_plotted() {
        // A disc of radius 1 on the plane y = 0 (n = (0,-1)), 36 candidates
        // round its rim, the 3 lowest in contact.
        let rows: Vec<ContactRow> = (0..36)
            .map(|k| {
                let a = -std::f64::consts::FRAC_PI_2 + k as f64 * std::f64::consts::PI / 18.0;
                let x = [a.cos(), 1.0 + a.sin(), 0.0];
                let touching = !(2..=34).contains(&k);
                ContactRow {
                    x,
                    status: u8::from(touching),
                    ..Default::default()
                }
            })
            .collect();
        let (c, n) = ([0.0, 0.0], [0.0, -1.0]);
        let near = near_side(&rows, &c, &n, |r| hertz::coordinate_2d(&r.x, &c, &n));
        // Kept: the zone and its neighbours up to 0.17 + 0.015 above the
        // plane; the top of the disc, which projects into the zone, is not.
        assert!(near.iter().all(|&i| rows[i].x[1] < 0.2), "{near:?}");
        assert!(near.contains(&0) && near.contains(&2) && near.contains(&34));
        // Nothing in contact: everything.
        let open: Vec<ContactRow> = rows
            .iter()
            .map(|r| ContactRow {
                status: 0,
                ..r.clone()
            })
            .collect();
        assert_eq!(near_side(&open, &c, &n, |r| r.x[0]).len(), 36);
    }
}
