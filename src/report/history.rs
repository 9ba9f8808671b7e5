//! The outputs of a load history: `-history_output FILE.csv` (one row per
//! step), the ParaView series (`-vtk` with a history: one file per step
//! and a `.pvd` index), and `-plot_history_curve FILE.png`.

use super::plot::{plot_lines, Series, Style};
use super::write_atomic;
use crate::error::Error;
use std::fmt::Write;
use std::path::Path;

/// What one load step gave.
#[derive(Clone, Debug, Default)]
pub struct StepRow {
    /// 1-based.
    pub step: usize,
    /// The factor of each group of the history.
    pub factors: Vec<f64>,
    /// The force the obstacle exerts on the body (`dim` components).
    pub contact_force: Vec<f64>,
    /// Measure of the nodes in contact (sum of their weights: a length in
    /// 2D, an area in 3D).
    pub contact_area: f64,
    /// Largest distance of a node in contact from the contact centre
    /// (`-reference_center`, else the candidate with the smallest gap),
    /// orthogonal to the contact direction (`-contact_direction`, else that
    /// candidate's normal): the half-width (2D) or radius (3D) of the
    /// contact zone.
    pub contact_extent: f64,
    pub peak_pressure: f64,
    pub contact_nodes: usize,
    pub stick: usize,
    pub slip: usize,
    /// Each Dirichlet group's reaction (`dim` components).
    pub reactions: Vec<(String, Vec<f64>)>,
    /// Each obstacle's force on the body, with several (`-obstacles`).
    pub obstacles: Vec<(String, Vec<f64>)>,
    /// The curve's point: mean displacement of the group along its
    /// component, and the force on it.
    pub curve: (f64, f64),
    pub iterations: usize,
    pub converged: bool,
    pub time: f64,
}

/// The history table: a header naming every column, one row per step;
/// numbers in Rust's shortest round-trip form.
pub fn csv(groups: &[String], dim: usize, curve: &str, rows: &[StepRow]) -> String {
    let axes = ["x", "y", "z"];
    let mut out = String::from("step");
    for g in groups {
        out.push_str(&format!(",{g}"));
    }
    for a in &axes[..dim] {
        out.push_str(&format!(",contact_force_{a}"));
    }
    if let Some(first) = rows.first() {
        for (name, _) in &first.obstacles {
            for a in &axes[..dim] {
                out.push_str(&format!(",contact_force_{name}_{a}"));
            }
        }
    }
    out.push_str(",contact_area,contact_extent,peak_pressure,contact_nodes,stick,slip");
    if let Some(first) = rows.first() {
        for (name, _) in &first.reactions {
            for a in &axes[..dim] {
                out.push_str(&format!(",reaction_{name}_{a}"));
            }
        }
    }
    out.push_str(&format!(
        ",curve_displacement_{curve},curve_force_{curve},iterations,converged,time\n"
    ));
    for r in rows {
        let _ = write!(out, "{}", r.step);
        for f in &r.factors {
            let _ = write!(out, ",{f:e}");
        }
        for f in r
            .contact_force
            .iter()
            .chain(r.obstacles.iter().flat_map(|o| &o.1))
        {
            let _ = write!(out, ",{f:e}");
        }
        let _ = write!(
            out,
            ",{:e},{:e},{:e},{},{},{}",
            r.contact_area, r.contact_extent, r.peak_pressure, r.contact_nodes, r.stick, r.slip
        );
        for (_, f) in &r.reactions {
            for v in f {
                let _ = write!(out, ",{v:e}");
            }
        }
        let _ = writeln!(
            out,
            ",{:e},{:e},{},{},{:e}",
            r.curve.0, r.curve.1, r.iterations, r.converged, r.time
        );
    }
    out
}

/// The file of step `k` (1-based) of the series of `-vtk PATH`:
/// `{stem}_step{k:04}.{vtu|pvtu}` beside it.
pub fn step_path(vtk: &str, k: usize) -> String {
    let p = Path::new(vtk);
    let stem = p
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = p
        .extension()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "vtu".into());
    let name = format!("{stem}_step{k:04}.{ext}");
    match p.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(d) => d.join(name).display().to_string(),
        None => name,
    }
}

/// The `.pvd` index of the series (`{stem}.pvd` beside `-vtk PATH`).
pub fn pvd_path(vtk: &str) -> String {
    Path::new(vtk).with_extension("pvd").display().to_string()
}

/// The ParaView collection: one dataset per step, its time the step.
pub fn pvd(vtk: &str, steps: usize) -> String {
    let mut out = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
    );
    for k in 1..=steps {
        let file = step_path(vtk, k);
        let name = Path::new(&file)
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or(file);
        let _ = writeln!(
            out,
            "    <DataSet timestep=\"{k}\" group=\"\" part=\"0\" file=\"{name}\"/>"
        );
    }
    out.push_str("  </Collection>\n</VTKFile>\n");
    out
}

/// Writes the table and the plot of a history (rank 0).
pub fn write_files(
    table: Option<&str>,
    plot: Option<&str>,
    groups: &[String],
    dim: usize,
    curve: &str,
    rows: &[StepRow],
) -> Result<(), Error> {
    if let Some(path) = table {
        write_atomic(Path::new(path), csv(groups, dim, curve, rows).as_bytes())
            .map_err(|e| Error::output("-history_output", path, e))?;
    }
    if let Some(path) = plot {
        // The curve from the unloaded state through every step.
        let mut x = vec![0.0];
        let mut y = vec![0.0];
        x.extend(rows.iter().map(|r| r.curve.0));
        y.extend(rows.iter().map(|r| r.curve.1));
        let series = [
            Series {
                label: "",
                x: &x,
                y: &y,
                style: Style::Line,
            },
            Series {
                label: "load steps",
                x: &x[1..],
                y: &y[1..],
                style: Style::Points,
            },
        ];
        plot_lines(
            Path::new(path),
            &format!("force against displacement, {curve}"),
            &format!("mean displacement of {curve}"),
            &format!("force on {curve}"),
            &series,
            false,
        )
        .map_err(|e| Error::output("-plot_history_curve", path, e))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_names_and_table() {
        assert_eq!(step_path("out/a.vtu", 3), "out/a_step0003.vtu");
        assert_eq!(step_path("a.pvtu", 12), "a_step0012.pvtu");
        assert_eq!(pvd_path("out/a.vtu"), "out/a.pvd");
        let p = pvd("out/a.vtu", 2);
        assert!(p.contains("timestep=\"2\" group=\"\" part=\"0\" file=\"a_step0002.vtu\""));
        let row = StepRow {
            step: 1,
            factors: vec![0.5],
            contact_force: vec![0.0, 2.5],
            reactions: vec![("left".into(), vec![-1.0, 0.0])],
            converged: true,
            ..Default::default()
        };
        let t = csv(&["factor".into()], 2, "dirichlet_left_ux", &[row]);
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines[0], "step,factor,contact_force_x,contact_force_y,contact_area,contact_extent,peak_pressure,contact_nodes,stick,slip,reaction_left_x,reaction_left_y,curve_displacement_dirichlet_left_ux,curve_force_dirichlet_left_ux,iterations,converged,time");
        assert_eq!(lines[1].split(',').count(), lines[0].split(',').count());
        assert!(lines[1].starts_with("1,5e-1,0e0,2.5e0,"));
    }
}
